//! `geodesic schema`: the schema of each command's `--json` document, against real output.
//! verify (a partial run; a gated run of the CubeSat mission), requirements, fit, diagnose and discover run on small inputs (the public examples
//! with the effects of the project's snapshot of outputs), and their documents are checked
//! against `geodesic schema COMMAND` by the small validator below: types, `required`, `const`,
//! `enum`, `$ref` into `$defs`, `allOf`/`anyOf`/`oneOf`, items, and, stricter than JSON Schema
//! itself, every property the output has must be declared by the schema (what a renamed or
//! added field would break). The full draft 2020-12 validation of every output CI records is
//! `.ci/clients.sh`'s (Python `jsonschema`).

mod common;
use common::{geodesic, scratch, workspace};

use serde_json::Value;
use std::collections::BTreeSet;

/// `geodesic schema COMMAND`, parsed.
fn schema_of(command: &str) -> Value {
    let out = geodesic(&["schema", command], &workspace());
    assert_eq!(
        out.status.code(),
        Some(0),
        "schema {command}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("a schema is JSON")
}

/// Runs `geodesic ARGS` in a scratch folder and parses its standard output.
fn json_of(name: &str, args: &[&str], codes: &[i32]) -> Value {
    let d = scratch(name);
    let out = geodesic(args, &d);
    assert!(
        out.status.code().is_some_and(|c| codes.contains(&c)),
        "{args:?}: exit {:?}: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON document")
}

/// The schema a `$ref` (`#/$defs/NAME`, or `#` for the root) points to.
fn resolve<'a>(root: &'a Value, r: &str) -> &'a Value {
    let pointer = r.strip_prefix('#').expect("a local $ref");
    let pointer = pointer.replace("~1", "/").replace("~0", "~");
    root.pointer(&pointer)
        .unwrap_or_else(|| panic!("$ref {r} resolves to nothing"))
}

fn type_matches(t: &str, v: &Value) -> bool {
    match t {
        "null" => v.is_null(),
        "boolean" => v.is_boolean(),
        "string" => v.is_string(),
        "array" => v.is_array(),
        "object" => v.is_object(),
        "number" => v.is_number(),
        "integer" => v.is_i64() || v.is_u64(),
        other => panic!("unknown type {other}"),
    }
}

/// Validates `v` at `path` against schema `s`; pushes each violation into `errs`. Returns the
/// property names `s` declares for `v` (its own `properties`, those of its `$ref`, its `allOf`
/// and of the `anyOf`/`oneOf` branches `v` matches), or `None` when any name is allowed (a map:
/// `additionalProperties` is a schema; a schema that says nothing of the keys). With `strict`, a property of `v` declared nowhere is a
/// violation (the instance's outermost schema; a branch is not strict on its own).
fn check(
    s: &Value,
    v: &Value,
    root: &Value,
    path: &str,
    strict: bool,
    errs: &mut Vec<String>,
) -> Option<BTreeSet<String>> {
    if let Some(b) = s.as_bool() {
        if !b {
            errs.push(format!("{path}: the schema allows nothing here"));
        }
        return None;
    }
    let s = s.as_object().expect("a schema is an object or a boolean");
    // a schema that says nothing of an object's keys (a `serde_json::Value` field) allows any
    let says_keys = [
        "properties",
        "additionalProperties",
        "patternProperties",
        "$ref",
        "allOf",
        "anyOf",
        "oneOf",
    ]
    .iter()
    .any(|k| s.contains_key(*k));
    let mut declared: Option<BTreeSet<String>> = says_keys.then(BTreeSet::new);
    let merge = |d: &mut Option<BTreeSet<String>>, more: Option<BTreeSet<String>>| match more {
        None => *d = None,
        Some(m) => {
            if let Some(d) = d {
                d.extend(m)
            }
        }
    };
    if let Some(r) = s.get("$ref").and_then(Value::as_str) {
        let more = check(resolve(root, r), v, root, path, false, errs);
        merge(&mut declared, more);
    }
    if let Some(t) = s.get("type") {
        let ok = match t {
            Value::String(t) => type_matches(t, v),
            Value::Array(ts) => ts.iter().any(|t| type_matches(t.as_str().unwrap(), v)),
            _ => panic!("{path}: type is a string or an array"),
        };
        if !ok {
            errs.push(format!("{path}: {v} is not of type {t}"));
        }
    }
    if let Some(c) = s.get("const")
        && c != v
    {
        errs.push(format!("{path}: {v} is not the constant {c}"));
    }
    if let Some(e) = s.get("enum").and_then(Value::as_array)
        && !e.contains(v)
    {
        errs.push(format!("{path}: {v} is not one of {e:?}"));
    }
    if let Some(min) = s.get("minimum").and_then(Value::as_f64)
        && v.as_f64().is_some_and(|x| x < min)
    {
        errs.push(format!("{path}: {v} is below the minimum {min}"));
    }
    for a in s
        .get("allOf")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        let more = check(a, v, root, path, false, errs);
        merge(&mut declared, more);
    }
    for key in ["anyOf", "oneOf"] {
        if let Some(branches) = s.get(key).and_then(Value::as_array) {
            let mut passing = Vec::new();
            for b in branches {
                let mut e = Vec::new();
                let d = check(b, v, root, path, false, &mut e);
                if e.is_empty() {
                    passing.push(d);
                }
            }
            if passing.is_empty() || (key == "oneOf" && passing.len() > 1) {
                errs.push(format!(
                    "{path}: {} of the {} branches of {key} match",
                    passing.len(),
                    branches.len()
                ));
            }
            for d in passing {
                merge(&mut declared, d);
            }
        }
    }
    if let Some(obj) = v.as_object() {
        let props = s.get("properties").and_then(Value::as_object);
        for r in s
            .get("required")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            let r = r.as_str().unwrap();
            if !obj.contains_key(r) {
                errs.push(format!("{path}: required property {r:?} missing"));
            }
        }
        for (k, val) in obj {
            let p = format!("{path}/{k}");
            if let Some(ps) = props.and_then(|ps| ps.get(k)) {
                check(ps, val, root, &p, true, errs);
                if let Some(d) = &mut declared {
                    d.insert(k.clone());
                }
            } else if let Some(extra) = s.get("additionalProperties")
                && extra != &Value::Bool(false)
            {
                check(extra, val, root, &p, true, errs);
                declared = None;
            }
        }
        if strict && let Some(d) = &declared {
            for k in obj.keys().filter(|k| !d.contains(*k)) {
                errs.push(format!("{path}/{k}: not declared by the schema"));
            }
        }
    }
    if let Some(arr) = v.as_array() {
        check_items(s, arr, root, path, errs);
    }
    declared
}

/// The items of an array `arr` at `path` against schema `s`: `prefixItems` (a tuple), then
/// `items`, `minItems`, `maxItems`.
fn check_items(
    s: &serde_json::Map<String, Value>,
    arr: &[Value],
    root: &Value,
    path: &str,
    errs: &mut Vec<String>,
) {
    let prefix = s.get("prefixItems").and_then(Value::as_array);
    for (i, item) in arr.iter().enumerate() {
        let p = format!("{path}/{i}");
        match prefix.and_then(|pi| pi.get(i)) {
            Some(ps) => {
                check(ps, item, root, &p, true, errs);
            }
            None => {
                if let Some(items) = s.get("items") {
                    check(items, item, root, &p, true, errs);
                }
            }
        }
    }
    if let Some(n) = s.get("minItems").and_then(Value::as_u64)
        && (arr.len() as u64) < n
    {
        errs.push(format!("{path}: fewer than {n} items"));
    }
    if let Some(n) = s.get("maxItems").and_then(Value::as_u64)
        && (arr.len() as u64) > n
    {
        errs.push(format!("{path}: more than {n} items"));
    }
}

/// Every violation of `doc` against `schema`.
fn violations(schema: &Value, doc: &Value) -> Vec<String> {
    let mut errs = Vec::new();
    check(schema, doc, schema, "", true, &mut errs);
    errs
}

fn assert_valid(command: &str, doc: &Value) {
    let schema = schema_of(command);
    assert_eq!(
        schema["$schema"], "https://json-schema.org/draft/2020-12/schema",
        "{command}"
    );
    assert_eq!(schema["$id"], format!("urn:geodesic:schema:{command}"));
    assert_eq!(schema["title"], format!("geodesic {command} --json"));
    assert!(
        schema["description"]
            .as_str()
            .is_some_and(|d| !d.is_empty()),
        "{command}: the output type's doc comment is the schema's description"
    );
    let errs = violations(&schema, doc);
    assert!(
        errs.is_empty(),
        "{command} --json against its schema:\n{}",
        errs.join("\n")
    );
}

fn example(name: &str) -> String {
    workspace()
        .join("data/examples")
        .join(name)
        .display()
        .to_string()
}

#[test]
fn verify_output_matches_its_schema() {
    // a partial run: two rows and what they depend on, with a small Monte Carlo
    let doc = json_of(
        "verify",
        &[
            "verify",
            "--only",
            "CHG-V,TMS-X-POS",
            "--mc-n",
            "2000",
            "--reports",
            "r",
            "--json",
            "-q",
        ],
        &[0, 1],
    );
    assert!(doc["run"]["partial"].is_object());
    assert!(
        doc["requirements"]
            .as_array()
            .is_some_and(|r| !r.is_empty())
    );
    assert_valid("verify", &doc);
}

#[test]
fn verify_with_a_baseline_matches_its_schema() {
    // the CubeSat mission (a second of work), run twice: the second gated against the first's
    // compliance.json adds `baseline_diff`
    let d = scratch("gate");
    let run = |reports: &str, extra: &[&str]| {
        let mut args = vec![
            "verify",
            "--mission",
            "drag-free-cubesat",
            "--reports",
            reports,
            "--json",
            "-q",
        ];
        args.extend_from_slice(extra);
        let out = geodesic(&args, &d);
        assert!(
            matches!(out.status.code(), Some(0 | 1)),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice::<Value>(&out.stdout).unwrap()
    };
    let first = run("a", &[]);
    assert_valid("verify", &first);
    let base = d.join("a/compliance.json");
    let second = run("b", &["--baseline", base.to_str().unwrap()]);
    assert!(second["baseline_diff"].is_object(), "{second}");
    assert_valid("verify", &second);
}

#[test]
fn requirements_outputs_match_their_schema() {
    // check, list and show (without a last run, then with the partial run of `verify --only`)
    let reqs = workspace().join("requirements");
    let reqs = reqs.to_str().unwrap();
    let d = scratch("requirements");
    let out = geodesic(
        &[
            "verify",
            "--requirements",
            reqs,
            "--only",
            "CHG-V",
            "--reports",
            "r",
            "-q",
        ],
        &d,
    );
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for args in [
        vec!["requirements", "check", "--requirements", reqs, "--json"],
        vec!["requirements", "list", "--requirements", reqs, "--json"],
        vec![
            "requirements",
            "list",
            "--requirements",
            reqs,
            "--reports",
            "r",
            "--json",
        ],
        vec![
            "requirements",
            "show",
            "CHG-V",
            "--requirements",
            reqs,
            "--json",
        ],
        vec![
            "requirements",
            "show",
            "CHG-V",
            "--requirements",
            reqs,
            "--reports",
            "r",
            "--json",
        ],
    ] {
        let out = geodesic(&args, &d);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_valid("requirements", &doc);
    }
}

#[test]
fn fit_output_matches_its_schema() {
    let doc = json_of(
        "fit",
        &[
            "fit",
            &example("tmmf-adhesion.yaml"),
            "--effects",
            "needle_contact,tip_contact,tip_adhesion",
            "--reports",
            "r",
            "--json",
            "-q",
        ],
        &[0],
    );
    assert_valid("fit", &doc);
}

#[test]
fn diagnose_output_matches_its_schema() {
    let doc = json_of(
        "diagnose",
        &[
            "diagnose",
            &example("rt-plunger.yaml"),
            "--effects",
            "piezo",
            "--reports",
            "r",
            "--json",
            "-q",
        ],
        &[0],
    );
    assert_valid("diagnose", &doc);
}

#[test]
fn discover_output_matches_its_schema() {
    let doc = json_of(
        "discover",
        &[
            "discover",
            &example("rt-plunger.yaml"),
            "--effects",
            "piezo",
            "--reports",
            "r",
            "--json",
            "-q",
        ],
        &[0],
    );
    assert_valid("discover", &doc);
}

#[test]
fn a_renamed_or_retyped_field_is_a_violation() {
    // the validator can fail: the fit document with one field renamed, then one retyped
    let doc = json_of(
        "renamed",
        &[
            "fit",
            &example("rt-plunger.yaml"),
            "--effects",
            "piezo,plunger_compliance",
            "--reports",
            "r",
            "--json",
            "-q",
        ],
        &[0],
    );
    let schema = schema_of("fit");
    assert_eq!(violations(&schema, &doc), Vec::<String>::new());
    let mut renamed = doc.clone();
    let obj = renamed.as_object_mut().unwrap();
    let v = obj.remove("chi2_red").expect("fit --json has chi2_red");
    obj.insert("chi2_reduced".into(), v);
    let errs = violations(&schema, &renamed);
    assert!(
        errs.iter().any(|e| e.contains("\"chi2_red\" missing"))
            && errs
                .iter()
                .any(|e| e == "/chi2_reduced: not declared by the schema"),
        "{errs:?}"
    );
    let mut retyped = doc;
    retyped["params"] = Value::String("none".into());
    let errs = violations(&schema, &retyped);
    assert!(errs.iter().any(|e| e.starts_with("/params: ")), "{errs:?}");
}

#[test]
fn schema_lists_writes_every_command_and_refuses_an_unknown_one() {
    let out = geodesic(&["schema", "--json"], &workspace());
    assert_eq!(out.status.code(), Some(0));
    let list: Value = serde_json::from_slice(&out.stdout).unwrap();
    let commands: Vec<&str> = list["commands"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap())
        .collect();
    for c in [
        "verify",
        "requirements",
        "fit",
        "diagnose",
        "discover",
        "synth",
        "history",
        "effects",
        "campaign",
        "asd",
        "tiptrack",
        "surfaces",
        "montecarlo",
        "charge",
        "capture",
        "plunger",
        "tip-radius",
        "sensitivity",
    ] {
        assert!(commands.contains(&c), "{c} has no schema: {commands:?}");
    }
    // the text list names each of them
    let out = geodesic(&["schema"], &workspace());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        commands
            .iter()
            .all(|c| text.lines().any(|l| l.trim() == *c)),
        "{text}"
    );
    // --all --out DIR: one file a command, each the schema `schema COMMAND` prints
    let d = scratch("all");
    let out = geodesic(&["schema", "--all", "--out", "schemas"], &d);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut files: Vec<String> = std::fs::read_dir(d.join("schemas"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    files.sort();
    let mut expected: Vec<String> = commands
        .iter()
        .map(|c| format!("{c}.schema.json"))
        .collect();
    expected.sort();
    assert_eq!(files, expected);
    let written: Value =
        serde_json::from_slice(&std::fs::read(d.join("schemas/charge.schema.json")).unwrap())
            .unwrap();
    assert_eq!(written, schema_of("charge"));
    // an unknown command: exit 2, one line with the list
    let out = geodesic(&["schema", "frobnicate"], &workspace());
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("frobnicate") && err.contains("verify, fit, diagnose"),
        "{err}"
    );
}

#[test]
fn descriptions_carry_the_units_of_the_doc_comments() {
    // the doc comment of a field with a unit is its description in the schema
    let s = schema_of("charge");
    let d = s["properties"]["c_rt_pf"]["description"].as_str().unwrap();
    assert!(d.contains("[pF]"), "{d}");
}
