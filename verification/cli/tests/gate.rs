//! End-to-end tests of the CI gate and of the verdicts' inputs: `verify --baseline` exits 0 on
//! an unchanged run and 1 on a regression (each requirement named once), a TM state limit
//! edited in a copy of `requirements/` moves every row that depends on it, dispositions and the
//! recorded test run show in the rows. Each test works in its own scratch directory.
//!
//! The facility family is left out of the requirement copies (its identification check fits
//! synthetic releases and is slow in the test profile); it is covered by the framework tests.

mod common;
use common::{geodesic, scratch, workspace};

use serde_json::Value;
use std::path::{Path, PathBuf};

/// Copies the requirement families except `facility` into `d/requirements`, applying `edit` to
/// each file's text.
fn requirements(d: &Path, edit: impl Fn(&str, &str) -> String) -> PathBuf {
    let req = d.join("requirements");
    std::fs::create_dir_all(&req).unwrap();
    for e in std::fs::read_dir(workspace().join("requirements"))
        .unwrap()
        .flatten()
    {
        let name = e.file_name().to_string_lossy().into_owned();
        if name == "facility.yaml" {
            continue;
        }
        let text = std::fs::read_to_string(e.path()).unwrap();
        std::fs::write(req.join(&name), edit(&name, &text)).unwrap();
    }
    req
}

/// `verify --json` in `d` with a small Monte Carlo and the given extra flags.
fn verify(d: &Path, req: &Path, reports: &str, extra: &[&str]) -> (i32, Value, String) {
    let mut args = vec![
        "verify",
        "--json",
        "--mc-n",
        "2000",
        "--no-fidelity",
        "--requirements",
        req.to_str().unwrap(),
        "--reports",
        reports,
    ];
    args.extend_from_slice(extra);
    let out = geodesic(&args, d);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let code = out.status.code().unwrap();
    assert!(code == 0 || code == 1, "exit {code}: {err}");
    let doc = serde_json::from_slice(&out.stdout).expect("one JSON document");
    (code, doc, err)
}

fn row<'a>(doc: &'a Value, id: &str) -> &'a Value {
    doc["requirements"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["id"] == id)
        .unwrap_or_else(|| panic!("no row {id}"))
}

#[test]
fn every_row_has_a_basis_and_the_run_names_its_inputs() {
    let d = scratch("basis");
    let req = requirements(&d, |_, t| t.to_string());
    let (_, doc, _) = verify(&d, &req, "reports", &[]);
    for r in doc["requirements"].as_array().unwrap() {
        let basis = r.get("basis").expect("row has a basis field");
        match r["status"].as_str().unwrap() {
            "not-verified" => assert!(basis.is_null() && r["reason"].is_string(), "{r}"),
            _ => assert!(
                ["model", "flow-down", "accepted"].contains(&basis.as_str().unwrap()),
                "{r}"
            ),
        }
    }
    let run = &doc["run"];
    for k in [
        "commit",
        "dirty",
        "date",
        "requirements_hash",
        "tool_version",
    ] {
        assert!(run.get(k).is_some(), "run lacks {k}");
    }
    assert_eq!(
        run["inputs"]["budget"]["sha256"].as_str().unwrap().len(),
        64
    );
    assert_eq!(row(&doc, "CAP-VZ-SINGLE")["basis"], "accepted");
    assert_eq!(row(&doc, "TMS-X-RATE")["status"], "not-verified");
}

#[test]
fn unchanged_run_against_its_baseline_exits_0() {
    let d = scratch("unchanged");
    let req = requirements(&d, |_, t| t.to_string());
    let (code, _, _) = verify(&d, &req, "base", &[]);
    assert_eq!(code, 1, "CHG-Q is non-compliant without a baseline");
    let (code, doc, err) = verify(&d, &req, "now", &["--baseline", "base/compliance.json"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(doc["baseline_diff"]["regressions"], 0);
    assert!(
        doc["baseline_diff"]["changes"]
            .as_array()
            .unwrap()
            .is_empty()
    );
}

#[test]
fn a_budget_change_that_eats_a_margin_exits_1_naming_each_requirement_once() {
    let d = scratch("budget");
    let req = requirements(&d, |_, t| t.to_string());
    verify(&d, &req, "base", &[]);
    let budget = std::fs::read_to_string(workspace().join("models/release/budget.yaml")).unwrap();
    // a lighter TM: the same momentum gives 4 times the velocity
    let lighter = budget.replace("tm_mass_kg: {fixed: 1.96}", "tm_mass_kg: {fixed: 0.49}");
    assert_ne!(lighter, budget);
    std::fs::write(d.join("lighter.yaml"), lighter).unwrap();
    let (code, doc, err) = verify(
        &d,
        &req,
        "now",
        &[
            "--baseline",
            "base/compliance.json",
            "--budget",
            "lighter.yaml",
        ],
    );
    assert_eq!(code, 1, "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("REGRESSION")).collect();
    let ids: Vec<&str> = lines
        .iter()
        .map(|l| {
            l.split("REGRESSION ")
                .nth(1)
                .unwrap()
                .split(':')
                .next()
                .unwrap()
        })
        .collect();
    let mut unique = ids.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), ids.len(), "each requirement once: {lines:?}");
    assert!(ids.contains(&"REL-GPRM-VEL"), "{lines:?}");
    assert_eq!(
        doc["baseline_diff"]["regressions"].as_u64().unwrap() as usize,
        ids.len()
    );
    for l in &lines {
        assert!(!l.contains("Some("), "plain words: {l}");
    }
    assert_eq!(doc["run"]["inputs"]["budget"]["label"], "lighter.yaml");
}

#[test]
fn a_looser_tm_state_limit_moves_every_row_that_depends_on_it() {
    let d = scratch("loose");
    let base = requirements(&d, |_, t| t.to_string());
    let (_, before, _) = verify(&d, &base, "base", &[]);
    let loose_dir = scratch("loose-copy");
    let loose = requirements(&loose_dir, |name, t| {
        if name == "tm-state.yaml" {
            // TMS-X-VEL only: the first velocity limit in the file
            t.replacen("limit: \"<= 5 um/s\"", "limit: \"<= 20 um/s\"", 1)
        } else {
            t.to_string()
        }
    });
    let (_, after, _) = verify(&d, &loose, "now", &[]);
    assert_eq!(row(&after, "TMS-X-VEL")["limit"], 20.0);
    // 20 um/s for 15 s: 300 um > 200 um
    let x = row(&after, "TMS-X-POS");
    assert_eq!(x["status"], "non-compliant", "{x}");
    assert!((x["value"].as_f64().unwrap() - 300.0).abs() < 1e-9, "{x}");
    for id in ["CAP-QUARTIC", "CAP-XLIM-CONSISTENCY", "CAP-RELEASE-PROB"] {
        assert_ne!(
            row(&before, id)["value"],
            row(&after, id)["value"],
            "{id} did not move"
        );
    }
    assert_eq!(row(&after, "CAP-QUARTIC")["status"], "non-compliant");
}

#[test]
fn dispositions_show_and_an_expired_one_is_a_regression() {
    let d = scratch("disp");
    let req = requirements(&d, |_, t| t.to_string());
    let ok = "dispositions:\n  - requirement: CHG-Q\n    kind: NCR\n    reference: NCR-T-1\n    \
              reason: known\n    owner: tests\n    date: 2020-01-01\n";
    std::fs::write(d.join("ok.yaml"), ok).unwrap();
    let (_, doc, _) = verify(&d, &req, "base", &["--dispositions", "ok.yaml"]);
    assert_eq!(row(&doc, "CHG-Q")["disposition"]["reference"], "NCR-T-1");
    let expired = format!("{ok}    expires: 2020-06-30\n");
    std::fs::write(d.join("expired.yaml"), expired).unwrap();
    let (code, doc, err) = verify(
        &d,
        &req,
        "now",
        &[
            "--dispositions",
            "expired.yaml",
            "--baseline",
            "base/compliance.json",
        ],
    );
    assert_eq!(code, 1, "{err}");
    assert_eq!(row(&doc, "CHG-Q")["disposition"]["expired"], true);
    assert!(
        err.contains("REGRESSION CHG-Q: its NCR NCR-T-1 expired"),
        "{err}"
    );
    // an unknown requirement is bad input naming the file and line
    std::fs::write(d.join("bad.yaml"), ok.replace("CHG-Q", "CHG-NOPE")).unwrap();
    let out = geodesic(
        &[
            "verify",
            "--requirements",
            req.to_str().unwrap(),
            "--dispositions",
            "bad.yaml",
        ],
        &d,
    );
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("bad.yaml:2:") && e.contains("CHG-NOPE"), "{e}");
    // the repository's default file (found from the working directory) applies to a subset of
    // the requirements: its entries for requirements not loaded are skipped
    std::fs::create_dir_all(d.join("verification")).unwrap();
    std::fs::write(d.join("verification/dispositions.yaml"), ok).unwrap();
    std::fs::remove_file(req.join("charge.yaml")).unwrap();
    let (_, doc, _) = verify(&d, &req, "subset", &[]);
    assert!(
        doc["requirements"]
            .as_array()
            .unwrap()
            .iter()
            .all(|r| r["id"] != "CHG-Q")
    );
    assert!(doc["run"]["dispositions"]["label"].is_string());
}

#[test]
fn an_ignored_or_failed_traced_test_shows_in_its_row_and_can_fail_verify() {
    let d = scratch("tests");
    let req = requirements(&d, |_, t| t.to_string());
    let run = |z_pos: &str| {
        format!(
            r#"{{"commit": "abc", "dirty": false, "date": "2026-01-01T00:00:00Z",
              "command": "cargo xtask test", "tests": [
              {{"krate": "verification", "test": "capture::z_offset", "result": "{z_pos}",
                "location": "x.rs:1", "requirements": ["TMS-Z-POS"], "cases": 1,
                "assertions": ["limit"], "kind": "unit"}},
              {{"krate": "verification", "test": "release::gprm", "result": "passed",
                "location": "y.rs:1", "requirements": ["REL-GPRM-VEL"], "cases": 256,
                "assertions": ["limit"], "kind": "proptest"}}]}}"#
        )
    };
    std::fs::write(d.join("pass.json"), run("passed")).unwrap();
    std::fs::write(d.join("ignored.json"), run("ignored")).unwrap();
    let (_, doc, _) = verify(
        &d,
        &req,
        "base",
        &["--tests", "pass.json", "--junit", "junit.xml"],
    );
    assert_eq!(row(&doc, "TMS-Z-POS")["tests_status"], "passed");
    assert_eq!(row(&doc, "TMS-Z-POS")["tests"][0]["result"], "passed");
    // JUnit: one test case per traced test naming its requirements
    let junit = std::fs::read_to_string(d.join("junit.xml")).unwrap();
    assert!(
        junit.contains("<testsuite name=\"geodesic traced tests\" tests=\"2\""),
        "{junit}"
    );
    assert!(junit.contains("name=\"z_offset\""), "{junit}");
    assert!(junit.contains("<property name=\"requirement\" value=\"TMS-Z-POS\"/>"));
    let (code, doc, err) = verify(
        &d,
        &req,
        "now",
        &[
            "--tests",
            "ignored.json",
            "--baseline",
            "base/compliance.json",
        ],
    );
    assert_eq!(row(&doc, "TMS-Z-POS")["tests_status"], "incomplete");
    assert_eq!(code, 1, "a passing test lost is a regression: {err}");
    assert!(err.contains("REGRESSION TMS-Z-POS: test verification::capture::z_offset passed in the baseline, now ignored"), "{err}");
    // without a baseline, --require-tests fails on it
    let (code, _, err) = verify(
        &d,
        &req,
        "again",
        &["--tests", "ignored.json", "--require-tests"],
    );
    assert_eq!(code, 1);
    assert!(err.contains("TMS-Z-POS"), "{err}");
}
