//! End-to-end tests of the `geodesic` binary: exit statuses, one-line causes with file:line,
//! and the JSON contract of `verify` (interface.md).

mod common;
use common::{geodesic, scratch, workspace};

use std::path::PathBuf;
use std::process::Output;

/// A copy of the built-in requirements with one file's text replaced.
fn broken_requirements(name: &str, file: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    let d = scratch(name);
    let req = d.join("requirements");
    std::fs::create_dir_all(&req).unwrap();
    for e in std::fs::read_dir(workspace().join("requirements"))
        .unwrap()
        .flatten()
    {
        let text = std::fs::read_to_string(e.path()).unwrap();
        let text = if e.file_name() == file {
            edit(&text)
        } else {
            text
        };
        std::fs::write(req.join(e.file_name()), text).unwrap();
    }
    d
}

fn assert_bad(out: &Output, file_line: &str, cause: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert!(out.stdout.is_empty(), "nothing on stdout on bad input");
    assert_eq!(err.trim().lines().count(), 1, "one-line cause: {err}");
    assert!(err.contains(file_line), "expected {file_line} in: {err}");
    assert!(
        err.to_lowercase().contains(cause),
        "expected `{cause}` in: {err}"
    );
}

#[test]
fn malformed_yaml_names_file_and_line() {
    let d = broken_requirements("malformed", "charge.yaml", |t| {
        t.replacen("requirements:", "requirements: [", 1)
    });
    let out = geodesic(
        &["verify", "--json", "--mc-n", "200", "--reports", "out"],
        &d,
    );
    assert_bad(&out, "charge.yaml:", "");
    assert!(
        !d.join("out/compliance.json").exists(),
        "no partial report on bad input"
    );
}

/// A broken-requirements case: name, file edited, the edit, expected `file:` and cause.
type BrokenCase = (
    &'static str,
    &'static str,
    Box<dyn Fn(&str) -> String>,
    &'static str,
    &'static str,
);

#[test]
fn duplicate_id_unknown_unit_unknown_field_missing_parent() {
    let cases: [BrokenCase; 5] = [
        (
            "dup",
            "charge.yaml",
            Box::new(|t: &str| t.replace("id: CHG-V", "id: CHG-Q")),
            "charge.yaml:",
            "duplicate",
        ),
        (
            "unit",
            "charge.yaml",
            Box::new(|t: &str| t.replace("<= 1.1 V", "<= 1.1 furlong")),
            "charge.yaml:",
            "furlong",
        ),
        (
            "dim",
            "charge.yaml",
            Box::new(|t: &str| t.replace("<= 1.1 V", "<= 1.1 mrad")),
            "charge.yaml:",
            "dimension",
        ),
        (
            "field",
            "charge.yaml",
            Box::new(|t: &str| {
                t.replacen(
                    "    method: analysis\n",
                    "    method: analysis\n    colour: red\n",
                    1,
                )
            }),
            "charge.yaml:",
            "unknown field",
        ),
        (
            "parent",
            "release.yaml",
            Box::new(|t: &str| {
                t.replace(
                    "{id: REL-GPRM-VEL, margin: 1.5}",
                    "{id: REL-NOPE, margin: 1.5}",
                )
            }),
            "release.yaml:",
            "does not exist",
        ),
    ];
    for (name, file, edit, at, cause) in cases {
        let d = broken_requirements(name, file, edit);
        let out = geodesic(&["verify", "--json", "--mc-n", "200"], &d);
        assert_bad(&out, at, cause);
    }
}

#[test]
fn unknown_check_name_is_refused_with_its_line() {
    let d = broken_requirements("check", "charge.yaml", |t| {
        t.replacen("check: charge-analysis", "check: crystal-ball", 1)
    });
    let out = geodesic(&["verify", "--json", "--mc-n", "200"], &d);
    assert_bad(&out, "charge.yaml:", "unknown check");
}

#[test]
fn missing_requirements_dir_is_bad_input() {
    let d = scratch("nodir");
    let out = geodesic(&["verify", "--requirements", "nowhere", "--json"], &d);
    assert_bad(&out, "nowhere", "cannot read");
}

#[test]
fn verify_json_lists_every_requirement_with_a_status() {
    let d = scratch("json");
    let req = workspace().join("requirements");
    let out = geodesic(
        &[
            "verify",
            "--json",
            "--mc-n",
            "2000",
            "--requirements",
            req.to_str().unwrap(),
        ],
        &d,
    );
    let code = out.status.code().unwrap();
    assert!(
        code == 0 || code == 1,
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("one JSON document on stdout");
    let rows = doc["requirements"].as_array().unwrap();
    let n_yaml: usize = std::fs::read_dir(&req)
        .unwrap()
        .flatten()
        .map(|e| {
            std::fs::read_to_string(e.path())
                .unwrap()
                .matches("\n  - id: ")
                .count()
        })
        .sum();
    assert_eq!(rows.len(), n_yaml);
    let mut non_compliant = false;
    for r in rows {
        let s = r["status"].as_str().unwrap();
        assert!(["compliant", "non-compliant", "not-verified"].contains(&s));
        non_compliant |= s == "non-compliant";
        for k in ["id", "value", "limit", "margin", "evidence"] {
            assert!(r.get(k).is_some(), "row lacks {k}");
        }
        if s == "not-verified" {
            assert!(
                r["reason"].as_str().is_some_and(|x| !x.is_empty()),
                "not-verified without a reason: {r}"
            );
        }
    }
    assert_eq!(code == 1, non_compliant, "exit status matches the verdict");
    assert!(d.join("reports/compliance.json").exists() && d.join("reports/compliance.md").exists());
}

#[test]
fn effects_lists_the_catalogue_with_units_and_ranges() {
    let d = scratch("effects");
    let out = geodesic(&["effects", "--json"], &d);
    assert_eq!(out.status.code(), Some(0));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let effects = doc["effects"].as_array().unwrap();
    // the ten effects of the interface contract
    assert_eq!(effects.len(), 10);
    let tip = effects
        .iter()
        .find(|e| e["effect"] == "tip_adhesion")
        .unwrap();
    assert_eq!(tip["scenario"], "tmmf-release");
    let a1 = &tip["parameters"][0];
    assert_eq!(a1["name"], "tip_adhesion.A1");
    assert_eq!(a1["unit"], "N/m");
    assert!(a1["min"].as_f64().unwrap() < a1["max"].as_f64().unwrap());
    let out = geodesic(&["effects", "--scenario", "rt-retraction", "--json"], &d);
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<&str> = doc["effects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["effect"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["piezo", "plunger_compliance", "voltage_ramp"]);
    let out = geodesic(&["effects", "--scenario", "moon"], &d);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--scenario moon"));
}
