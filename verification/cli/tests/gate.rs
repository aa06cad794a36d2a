//! End-to-end tests of the CI gate and of the verdicts' inputs: `verify --baseline` exits 0 on
//! an unchanged run and 1 on a regression (each requirement named once), a TM state limit
//! edited in a copy of `requirements/` moves every row that depends on it, dispositions and the
//! recorded test run show in the rows; the holes of issue 32 stay closed (a sample too small,
//! a stale or forged test run, an edited requirement, a non-compliance without disposition, a
//! seed change that must pass). Each test works in its own scratch directory.
//!
//! The facility family is left out of the requirement copies (its identification check fits
//! synthetic releases and is slow in the test profile); it is covered by the framework tests.

mod common;
use common::{geodesic, scratch, workspace};

use serde_json::Value;
use std::path::{Path, PathBuf};

/// Copies the requirement families except `facility` into `d/requirements`, applying `edit` to
/// each file's text, and the repository's dispositions (found from `d` as from a clone's root).
fn requirements(d: &Path, edit: impl Fn(&str, &str) -> String) -> PathBuf {
    let req = d.join("requirements");
    std::fs::create_dir_all(&req).unwrap();
    std::fs::create_dir_all(d.join("verification")).unwrap();
    std::fs::copy(
        workspace().join("verification/dispositions.yaml"),
        d.join("verification/dispositions.yaml"),
    )
    .unwrap();
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

/// The traced tests of the scratch trees: what a recorded run's locations point at.
/// `tests/traced.rs:3` verifies TMS-Z-POS, `:8` REL-GPRM-VEL and TMS-Z-POS, `:13` CHG-V, each
/// asserting its limit.
const TRACED: &str = "#[test]
fn z_offset() {
    geodesic_core::verifies!(\"TMS-Z-POS\");
    geodesic_core::trace::assert_limit(\"TMS-Z-POS\", 1e-6);
}
#[test]
fn gprm() {
    geodesic_core::verifies!(\"REL-GPRM-VEL\", \"TMS-Z-POS\");
    geodesic_core::trace::assert_limit(\"REL-GPRM-VEL\", 1e-6);
}
#[test]
fn chg_v() {
    geodesic_core::verifies!(\"CHG-V\");
    geodesic_core::trace::assert_limit(\"CHG-V\", 1.0);
}
";

/// Makes `d` a git work tree that tracks only `requirements/`, `verification/` (the
/// dispositions verify reads) and `tests/traced.rs` ([`TRACED`]; everything else a test writes
/// there, reports, runs, inputs, is ignored), with one commit; returns the fingerprint a fresh
/// test run of it records.
fn git_repo(d: &Path) -> geodesic_core::testrun::TreeState {
    std::fs::write(
        d.join(".gitignore"),
        "/*\n!/.gitignore\n!/requirements/\n!/verification/\n!/tests/\n",
    )
    .unwrap();
    std::fs::create_dir_all(d.join("tests")).unwrap();
    std::fs::write(d.join("tests/traced.rs"), TRACED).unwrap();
    for args in [
        &["init", "-q"][..],
        &["add", "-A"],
        &[
            "-c",
            "user.name=t",
            "-c",
            "user.email=t@t",
            "commit",
            "-q",
            "-m",
            "requirements",
        ],
    ] {
        let ok = std::process::Command::new("git")
            .args(args)
            .current_dir(d)
            .status()
            .unwrap()
            .success();
        assert!(ok, "git {args:?}");
    }
    geodesic_core::testrun::tree_state(d).unwrap()
}

/// A recorded test run of `tree` (fresh for it) with the given tests (JSON array text).
fn run_json(tree: &geodesic_core::testrun::TreeState, tests: &str) -> String {
    format!(
        r#"{{"commit": "{}", "dirty": false, "tree_sha256": "{}", "date": "2026-01-01T00:00:00Z",
            "command": "cargo xtask test", "tests": {tests}}}"#,
        tree.commit, tree.tree_sha256
    )
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
                [
                    "model",
                    "flow-down",
                    "accepted",
                    "method-validation",
                    "measurement"
                ]
                .contains(&basis.as_str().unwrap()),
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
    for input in ["budget", "capture", "charge"] {
        assert_eq!(
            run["inputs"][input]["sha256"].as_str().unwrap().len(),
            64,
            "{input}"
        );
    }
    assert_eq!(run["confidence"], 0.95);
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
    // (its pedigree widens the TM mass's plausible range with a reason: issue 49)
    let lighter = budget
        .replace("tm_mass_kg: {fixed: 1.96}", "tm_mass_kg: {fixed: 0.49}")
        .replace(
            "tm_mass_kg: {kind: cited,",
            "tm_mass_kg: {range: {min: 0.4, max: 2.0, reason: \"this test's what-if: a lighter TM\"}, kind: cited,",
        );
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
    let tree = git_repo(&d);
    let run = |z_pos: &str| {
        run_json(
            &tree,
            &format!(
                r#"[
              {{"krate": "verification", "test": "capture::z_offset", "result": "{z_pos}",
                "location": "tests/traced.rs:3", "requirements": ["TMS-Z-POS"], "cases": 1,
                "assertions": ["limit"], "kind": "unit"}},
              {{"krate": "verification", "test": "release::gprm", "result": "passed",
                "location": "tests/traced.rs:8", "requirements": ["REL-GPRM-VEL"], "cases": 256,
                "assertions": ["limit"], "kind": "proptest"}}]"#
            ),
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
    assert_eq!(doc["test_run"]["fresh"], true, "{}", doc["test_run"]);
    assert_eq!(row(&doc, "TMS-Z-POS")["tests_status"], "passed");
    assert_eq!(row(&doc, "TMS-Z-POS")["tests"][0]["result"], "passed");
    // JUnit: one test case per traced test naming its requirements
    let junit = std::fs::read_to_string(d.join("junit.xml")).unwrap();
    assert!(
        junit.contains("<testsuite name=\"geodesic traced tests\" tests=\"2\""),
        "{junit}"
    );
    assert!(junit.contains("name=\"z_offset\""), "{junit}");
    assert!(junit.contains("requirement: TMS-Z-POS\n"), "{junit}");
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
    // not compliant: its ignored test asserts its limit (issue 49)
    let r = row(&doc, "TMS-Z-POS");
    assert_eq!(r["status"], "not-verified", "{r}");
    assert!(
        r["reason"].as_str().unwrap().starts_with(
            "traced test verification::capture::z_offset asserts its limit and was ignored"
        ),
        "{r}"
    );
    assert_eq!(code, 1, "a passing test lost is a regression: {err}");
    let line = err
        .lines()
        .find(|l| l.contains("REGRESSION TMS-Z-POS: "))
        .unwrap_or_else(|| panic!("{err}"));
    assert!(
        line.contains("lost its evidence")
            && line.contains(
                "test verification::capture::z_offset passed in the baseline, now ignored"
            ),
        "{line}"
    );
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

/// The recorded run is checked against the tree: a forged run (commit 000..., dated 2001, every
/// test passed) or a run of an earlier state of the tree shows as stale on every row and in the
/// summary, and `--require-tests` fails on it naming the rows; the same run recorded for this
/// tree passes.
#[test]
fn a_forged_or_stale_test_run_is_stale_on_every_row_and_fails_require_tests() {
    let d = scratch("stale");
    let req = requirements(&d, |_, t| t.to_string());
    let tree = git_repo(&d);
    let tests = r#"[{"krate": "verification", "test": "release::gprm", "result": "passed",
        "location": "tests/traced.rs:8", "requirements": ["REL-GPRM-VEL", "TMS-Z-POS"], "cases": 1,
        "assertions": ["limit"], "kind": "unit"}]"#;
    let forged = format!(
        r#"{{"commit": "{}", "dirty": false, "date": "2001-01-01T00:00:00Z",
            "command": "cargo xtask test", "tests": {tests}}}"#,
        "0".repeat(40)
    );
    std::fs::write(d.join("forged.json"), forged).unwrap();
    let (_, doc, err) = verify(
        &d,
        &req,
        "f",
        &["--tests", "forged.json", "--require-tests"],
    );
    assert_eq!(doc["test_run"]["fresh"], false);
    assert!(
        doc["test_run"]["stale_reason"]
            .as_str()
            .unwrap()
            .contains("recorded on commit 000000000000"),
        "{}",
        doc["test_run"]
    );
    assert_eq!(doc["summary"]["tests"], "stale");
    for r in doc["requirements"].as_array().unwrap() {
        assert_eq!(r["tests_status"], "stale", "{}", r["id"]);
        if r["status"] != "not-verified" {
            assert!(
                r["verdict"].as_str().unwrap().contains("tests stale"),
                "{r}"
            );
        }
    }
    assert!(
        err.contains("--require-tests: the recorded test run forged.json is STALE"),
        "{err}"
    );
    assert!(err.contains("--require-tests: REL-GPRM-VEL: its traced test results are stale"));
    // the same tests recorded for this tree: fresh
    std::fs::write(d.join("fresh.json"), run_json(&tree, tests)).unwrap();
    let (_, doc, _) = verify(&d, &req, "g", &["--tests", "fresh.json"]);
    assert_eq!(doc["test_run"]["fresh"], true);
    assert_eq!(row(&doc, "TMS-Z-POS")["tests_status"], "passed");
    // a run of this commit whose tree then changed (an uncommitted edit): stale
    let f = req.join("charge.yaml");
    let text = std::fs::read_to_string(&f).unwrap();
    std::fs::write(&f, format!("{text}\n# an edit\n")).unwrap();
    let out = geodesic(
        &[
            "verify",
            "--mc-n",
            "2000",
            "--no-fidelity",
            "--requirements",
            req.to_str().unwrap(),
            "--reports",
            "h",
            "--tests",
            "fresh.json",
            "--require-tests",
        ],
        &d,
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("the work tree changed since the tests ran"),
        "{err}"
    );
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("STALE"), "{table}");
    // the terminal says the confidence the sampled verdicts are decided at
    assert!(
        table.contains("sampled verdicts: decided by their 95 % confidence bounds"),
        "{table}"
    );
}

/// A Monte Carlo too small to bound the requirement's quantile leaves its rows not verified
/// (never compliant on the point estimate), and against a baseline of a larger sample it fails
/// the gate naming each row.
#[test]
fn a_monte_carlo_too_small_for_its_probability_is_not_verified_and_fails_the_gate() {
    let d = scratch("small");
    let req = requirements(&d, |_, t| t.to_string());
    verify(&d, &req, "base", &[]);
    for n in ["10", "200"] {
        let out = geodesic(
            &[
                "verify",
                "--json",
                "--mc-n",
                n,
                "--no-fidelity",
                "--requirements",
                req.to_str().unwrap(),
                "--reports",
                "now",
                "--baseline",
                "base/compliance.json",
            ],
            &d,
        );
        assert_eq!(out.status.code(), Some(1), "N = {n}");
        let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        for id in [
            "REL-GPRM-VEL",
            "REL-DFACS-VEL",
            "TMS-Z-VEL",
            "TMS-Z-POS",
            "CAP-RELEASE-PROB",
            "PLG-EXTRA-VEL",
        ] {
            let r = row(&doc, id);
            assert_eq!(r["status"], "not-verified", "N = {n}: {id}: {r}");
            assert!(
                err.lines()
                    .any(|l| l.starts_with(&format!("geodesic: REGRESSION {id}: "))),
                "N = {n}: {id} not named: {err}"
            );
        }
        let why = row(&doc, "REL-GPRM-VEL")["reason"]
            .as_str()
            .unwrap()
            .to_string();
        assert!(
            why.contains(&format!(
                "N = {n} cannot show the 99.73 % quantile at 95 % confidence; need N >= 1109"
            )),
            "{why}"
        );
        assert_eq!(
            row(&doc, "REL-GPRM-VEL")["sampling"]["n"],
            n.parse::<u64>().unwrap()
        );
    }
}

/// The requirement's `probability` is the quantile judged: at 50 % the row is the median's.
#[test]
fn the_requirements_probability_is_the_quantile_judged() {
    let d = scratch("prob");
    let req = requirements(&d, |name, t| {
        if name == "release.yaml" {
            t.replacen("probability: \"99.73 %\"", "probability: \"50 %\"", 1)
        } else {
            t.to_string()
        }
    });
    let (_, doc, _) = verify(&d, &req, "r", &[]);
    let gprm = row(&doc, "REL-GPRM-VEL");
    let dfacs = row(&doc, "REL-DFACS-VEL");
    assert_eq!(gprm["sampling"]["probability"], 0.5);
    assert!(
        gprm["value"].as_f64().unwrap() < 0.8 * dfacs["value"].as_f64().unwrap(),
        "{gprm} {dfacs}"
    );
}

/// A requirement edit is reviewed whichever way it goes: CHG-Q's limit loosened to close its
/// NCR, or tightened, fails the gate naming CHG-Q; so does a non-compliance whose disposition
/// is dropped, and a new non-compliant requirement without one.
#[test]
fn requirement_edits_and_missing_dispositions_fail_the_gate() {
    let d = scratch("edits");
    let req = requirements(&d, |_, t| t.to_string());
    let ncr = "dispositions:\n  - requirement: CHG-Q\n    kind: NCR\n    reference: NCR-T-1\n    \
               reason: known\n    owner: tests\n    date: 2020-01-01\n";
    std::fs::write(d.join("ncr.yaml"), ncr).unwrap();
    std::fs::write(d.join("none.yaml"), "dispositions: []\n").unwrap();
    let (code, _, err) = verify(&d, &req, "base", &["--dispositions", "ncr.yaml"]);
    assert_eq!(code, 1, "{err}");
    let (code, _, err) = verify(
        &d,
        &req,
        "same",
        &[
            "--dispositions",
            "ncr.yaml",
            "--baseline",
            "base/compliance.json",
        ],
    );
    assert_eq!(code, 0, "an unchanged run with its NCR passes: {err}");
    for (limit, name) in [("3.2e8 e", "loose"), ("2.8e8 e", "tight")] {
        let dir = scratch(name);
        let edited = requirements(&dir, |f, t| {
            if f == "charge.yaml" {
                t.replace("limit: \"<= 3e8 e\"", &format!("limit: \"<= {limit}\""))
            } else {
                t.to_string()
            }
        });
        let (code, _, err) = verify(
            &d,
            &edited,
            name,
            &[
                "--dispositions",
                "ncr.yaml",
                "--baseline",
                "base/compliance.json",
            ],
        );
        assert_eq!(code, 1, "{limit}: {err}");
        assert!(
            err.contains(&format!(
                "REGRESSION CHG-Q: requirement changed, needs review: limit `<= 3e8 e` -> `<= {limit}`"
            )),
            "{err}"
        );
    }
    // the disposition dropped
    let (code, _, err) = verify(
        &d,
        &req,
        "dropped",
        &[
            "--dispositions",
            "none.yaml",
            "--baseline",
            "base/compliance.json",
        ],
    );
    assert_eq!(code, 1);
    assert!(
        err.contains("REGRESSION CHG-Q: its disposition NCR-T-1 was withdrawn"),
        "{err}"
    );
    // a baseline without CHG-Q: it is new now, and non-compliant without a disposition
    let dir = scratch("without");
    let without = requirements(&dir, |f, t| {
        if f == "charge.yaml" {
            let (head, rest) = t.split_once("  - id: CHG-Q\n").unwrap();
            let (_, tail) = rest.split_once("  - id: CHG-V\n").unwrap();
            format!("{head}  - id: CHG-V\n{tail}")
        } else {
            t.to_string()
        }
    });
    verify(&d, &without, "base2", &["--dispositions", "none.yaml"]);
    let (code, doc, err) = verify(
        &d,
        &req,
        "added",
        &[
            "--dispositions",
            "none.yaml",
            "--baseline",
            "base2/compliance.json",
        ],
    );
    assert_eq!(code, 1);
    assert_eq!(doc["baseline_diff"]["added"][0], "CHG-Q");
    assert!(
        err.contains("REGRESSION CHG-Q: new requirement, non-compliant with no disposition"),
        "{err}"
    );
    assert_eq!(
        row(&doc, "CHG-Q")["verdict"],
        "non-compliant (no disposition)"
    );
    // the gate's own output names what was added, with its status
    assert!(
        err.contains("added since base2/compliance.json: CHG-Q (non-compliant)"),
        "{err}"
    );
}

/// A requirement added on an existing check is judged by it (not left "no check provides
/// evidence"): a new velocity requirement on the release Monte Carlo with a limit below the
/// computed quantile is non-compliant, and the gate fails naming it.
#[test]
fn a_new_requirement_on_the_release_monte_carlo_is_judged_and_can_fail_the_gate() {
    let d = scratch("new-on-mc");
    let req = requirements(&d, |_, t| t.to_string());
    verify(&d, &req, "base", &[]);
    let added = requirements(&d, |f, t| {
        if f == "release.yaml" {
            let i = t.find("  - id: REL-DFACS-VEL\n").unwrap();
            let j = i + t[i..].find("    parent:").unwrap();
            let block = t[i..j]
                .replace("id: REL-DFACS-VEL", "id: REL-NEW-VEL")
                .replace("<= 7.5 um/s", "<= 1 um/s");
            format!("{}{block}{}", &t[..i], &t[i..])
        } else if f == "charge.yaml" {
            // and one on a check that evaluates fixed quantities: not verified, saying why
            let i = t.find("  - id: CHG-V\n").unwrap();
            let block = t[i..].replace("id: CHG-V", "id: CHG-V2");
            format!("{t}{block}")
        } else {
            t.to_string()
        }
    });
    let (code, doc, err) = verify(&d, &added, "now", &["--baseline", "base/compliance.json"]);
    let new = row(&doc, "REL-NEW-VEL");
    assert_eq!(new["status"], "non-compliant", "{new}");
    // the same quantile of the same Monte Carlo as REL-DFACS-VEL, judged at its own limit: a
    // non-compliance is shown by the lower confidence bound, above the limit
    let dfacs = row(&doc, "REL-DFACS-VEL");
    assert_eq!(new["sampling"]["estimate"], dfacs["sampling"]["estimate"]);
    assert_eq!(new["value"], new["sampling"]["lower"]);
    assert!(new["value"].as_f64().unwrap() > 1.0, "{new}");
    assert_eq!(code, 1);
    // the only regression: the repository's known non-compliances keep their dispositions
    assert_eq!(doc["baseline_diff"]["regressions"], 1, "{err}");
    assert!(
        err.contains("REGRESSION REL-NEW-VEL: new requirement, non-compliant with no disposition"),
        "{err}"
    );
    let v2 = row(&doc, "CHG-V2");
    assert_eq!(v2["status"], "not-verified");
    assert!(
        v2["reason"]
            .as_str()
            .unwrap()
            .contains("its check `charge-analysis` ran and gave no evidence for CHG-V2"),
        "{v2}"
    );
    assert!(
        err.contains("REL-NEW-VEL (non-compliant), CHG-V2 (not-verified)")
            || err.contains("CHG-V2 (not-verified), REL-NEW-VEL (non-compliant)"),
        "{err}"
    );
}

/// A change of seed moves the sampled values within their sampling uncertainty: the gate
/// passes (the image and fit validations do not move with the seed at all).
#[test]
fn a_seed_change_alone_passes_the_gate() {
    let d = scratch("seed");
    let req = requirements(&d, |_, t| t.to_string());
    verify(&d, &req, "base", &[]);
    for seed in ["2", "3"] {
        let (code, doc, err) = verify(
            &d,
            &req,
            &format!("s{seed}"),
            &["--seed", seed, "--baseline", "base/compliance.json"],
        );
        assert_eq!(code, 0, "--seed {seed}: {err}");
        assert_eq!(doc["baseline_diff"]["regressions"], 0);
    }
}

/// Model rows move with their model inputs: an edited capacitance in the charge inputs moves
/// CHG-Q (and the run names the file with its hash); a TM of half the budget's mass moves
/// PLG-EXTRA-VEL.
#[test]
fn charge_and_budget_inputs_move_their_rows() {
    let d = scratch("inputs");
    let req = requirements(&d, |_, t| t.to_string());
    let (_, base, _) = verify(&d, &req, "base", &[]);
    let charge = std::fs::read_to_string(workspace().join("models/charge/charge.yaml")).unwrap();
    std::fs::write(
        d.join("charge.yaml"),
        charge.replace("c_eh_f: 34.4e-12", "c_eh_f: 30.0e-12"),
    )
    .unwrap();
    let budget = std::fs::read_to_string(workspace().join("models/release/budget.yaml")).unwrap();
    std::fs::write(
        d.join("half.yaml"),
        budget
            .replace("tm_mass_kg: {fixed: 1.96}", "tm_mass_kg: {fixed: 0.98}")
            .replace(
                "tm_mass_kg: {kind: cited,",
                "tm_mass_kg: {range: {min: 0.4, max: 2.0, reason: \"this test's what-if: a lighter TM\"}, kind: cited,",
            ),
    )
    .unwrap();
    let (_, doc, _) = verify(
        &d,
        &req,
        "now",
        &["--charge", "charge.yaml", "--budget", "half.yaml"],
    );
    let v = |doc: &Value, id: &str| row(doc, id)["value"].as_f64().unwrap();
    assert!(v(&doc, "CHG-Q") < 0.97 * v(&base, "CHG-Q"));
    assert_eq!(doc["run"]["inputs"]["charge"]["label"], "charge.yaml");
    assert!(v(&doc, "PLG-EXTRA-VEL") > 1.5 * v(&base, "PLG-EXTRA-VEL"));
    // a bad charge file is bad input with its line
    std::fs::write(
        d.join("bad.yaml"),
        charge.replace("gap_m: 100.0e-9", "gap_m: -1"),
    )
    .unwrap();
    let out = geodesic(
        &[
            "verify",
            "--requirements",
            req.to_str().unwrap(),
            "--charge",
            "bad.yaml",
        ],
        &d,
    );
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("bad.yaml:") && e.contains("gap_m"), "{e}");
}

/// One record of a recorded run (JSON text), asserting its requirements' limits.
fn rec(test: &str, result: &str, location: &str, reqs: &str, cases: u64) -> String {
    format!(
        r#"{{"krate": "verification", "test": "{test}", "result": "{result}",
            "location": "{location}", "requirements": [{reqs}], "cases": {cases},
            "assertions": ["limit"], "kind": "unit"}}"#
    )
}

/// A scratch tree ([`git_repo`]) with a baseline written from a fresh run of two passing traced
/// tests (CHG-V, REL-GPRM-VEL: [`good_records`]) in `base/`.
fn traced_tree(name: &str) -> (PathBuf, PathBuf, geodesic_core::testrun::TreeState, Value) {
    let d = scratch(name);
    let req = requirements(&d, |_, t| t.to_string());
    let tree = git_repo(&d);
    std::fs::write(
        d.join("good.json"),
        run_json(&tree, &format!("[{}]", good_records().join(","))),
    )
    .unwrap();
    let (_, base, err) = verify(&d, &req, "base", &["--tests", "good.json"]);
    assert_eq!(base["test_run"]["fresh"], true, "{err}");
    (d, req, tree, base)
}

/// The records of the passing traced tests of CHG-V and REL-GPRM-VEL in [`TRACED`].
fn good_records() -> [String; 2] {
    [
        rec(
            "charge::chg_v",
            "passed",
            "tests/traced.rs:13",
            r#""CHG-V""#,
            1,
        ),
        rec(
            "release::gprm",
            "passed",
            "tests/traced.rs:8",
            r#""REL-GPRM-VEL""#,
            1,
        ),
    ]
}

/// Issue 49: a recorded test counts only where the fingerprinted tree holds its `verifies!` of
/// that requirement and its call ran. A record at a file that does not exist, at a line whose
/// call names another requirement, or whose call never ran (cases 0) is rejected: the row is
/// not plainly compliant, `--require-tests` fails and the gate exits 1, each naming the row.
#[test]
fn forged_test_records_are_refused_and_fail_the_gate() {
    let (d, req, tree, base) = traced_tree("forged-records");
    let good = good_records();
    assert_eq!(row(&base, "CHG-V")["verdict"], "compliant");
    // the binary says which commit it was built from, and that it is not this tree's
    assert_eq!(base["run"]["build_commit"].as_str().unwrap().len(), 40);
    assert!(
        base["run"]["build_note"]
            .as_str()
            .unwrap()
            .starts_with("this binary was built from commit"),
        "{}",
        base["run"]
    );
    let forgeries = [
        (
            "nowhere",
            rec(
                "charge::this_test_does_not_exist",
                "passed",
                "verification/checks/tests/verification/nowhere.rs:1",
                r#""CHG-V""#,
                1,
            ),
            "is not a file of the fingerprinted tree",
        ),
        (
            "never-ran",
            rec(
                "charge::chg_v",
                "passed",
                "tests/traced.rs:13",
                r#""CHG-V""#,
                0,
            ),
            "never ran (cases 0)",
        ),
        (
            "other-call",
            rec(
                "charge::chg_v",
                "passed",
                "tests/traced.rs:3",
                r#""CHG-V""#,
                1,
            ),
            "names CHG-V",
        ),
    ];
    for (name, forged, why) in forgeries {
        let file = format!("{name}.json");
        std::fs::write(
            d.join(&file),
            run_json(&tree, &format!("[{forged},{}]", good[1])),
        )
        .unwrap();
        let (code, doc, err) = verify(
            &d,
            &req,
            name,
            &[
                "--tests",
                &file,
                "--require-tests",
                "--baseline",
                "base/compliance.json",
            ],
        );
        assert_eq!(code, 1, "{name}: {err}");
        let r = row(&doc, "CHG-V");
        assert_eq!(r["tests_status"], "rejected", "{name}: {r}");
        assert_eq!(r["verdict"], "compliant (test record rejected)", "{name}");
        assert!(
            r["tests"][0]["rejected"].as_str().unwrap().contains(why),
            "{name}: {r}"
        );
        assert!(
            err.contains("--require-tests: CHG-V: traced test record rejected against the tree"),
            "{name}: {err}"
        );
        let line = err
            .lines()
            .find(|l| l.contains("REGRESSION CHG-V: "))
            .unwrap_or_else(|| panic!("{name}: {err}"));
        assert!(
            line.contains("traced test record rejected against the tree"),
            "{name}: {line}"
        );
    }
}

/// Issue 49: a failed traced test that asserts its row's limit leaves the row not compliant,
/// and the gate exits 1 naming it.
#[test]
fn a_failed_traced_test_that_asserts_the_limit_leaves_its_row_not_compliant() {
    let (d, req, tree, _) = traced_tree("failed-test");
    let good = good_records();
    std::fs::write(
        d.join("failed.json"),
        run_json(
            &tree,
            &format!(
                "[{},{}]",
                good[0],
                rec(
                    "release::gprm",
                    "failed",
                    "tests/traced.rs:8",
                    r#""REL-GPRM-VEL""#,
                    1
                )
            ),
        ),
    )
    .unwrap();
    let (code, doc, err) = verify(
        &d,
        &req,
        "failed",
        &[
            "--tests",
            "failed.json",
            "--baseline",
            "base/compliance.json",
        ],
    );
    assert_eq!(code, 1, "{err}");
    let r = row(&doc, "REL-GPRM-VEL");
    assert_eq!(r["status"], "not-verified", "{r}");
    assert!(
        r["reason"]
            .as_str()
            .unwrap()
            .starts_with("traced test verification::release::gprm asserts its limit and failed"),
        "{r}"
    );
    assert!(err.contains("REGRESSION REL-GPRM-VEL: "), "{err}");
}

/// Issue 49: what verify reads is what the fingerprint covers. A requirement file hidden from
/// git through `.git/info/exclude` makes the recorded run stale, naming the file.
#[test]
fn a_requirement_file_hidden_from_git_makes_the_test_run_stale() {
    let d = scratch("hidden");
    let req = requirements(&d, |_, t| t.to_string());
    let tree = git_repo(&d);
    std::fs::write(d.join("run.json"), run_json(&tree, "[]")).unwrap();
    let (_, doc, _) = verify(&d, &req, "a", &["--tests", "run.json"]);
    assert_eq!(doc["test_run"]["fresh"], true, "{}", doc["test_run"]);
    std::fs::write(d.join(".git/info/exclude"), "extra.yaml\n").unwrap();
    std::fs::write(
        req.join("extra.yaml"),
        "family: extra\nlevel: system\nstage: qualification\nrequirements:\n  - id: EXT-ONE\n    title: t\n    text: \"The TM shall be grounded.\"\n    source: s\n    method: inspection\n    activity: a\n",
    )
    .unwrap();
    assert_eq!(
        geodesic_core::testrun::tree_state(&d).unwrap().tree_sha256,
        tree.tree_sha256,
        "git does not see the hidden file"
    );
    let (code, doc, err) = verify(&d, &req, "b", &["--tests", "run.json", "--require-tests"]);
    assert_eq!(code, 1, "{err}");
    assert_eq!(doc["test_run"]["fresh"], false);
    let why = doc["test_run"]["stale_reason"].as_str().unwrap();
    assert!(
        why.contains("extra.yaml") && why.contains("does not cover"),
        "{why}"
    );
    assert!(row(&doc, "EXT-ONE")["id"].is_string());
}

/// Issue 49: the ECSS method decides which evidence closes a requirement. PLG-EXTRA-VEL made
/// `method: test` is not closed by its model (not verified, "not verified" in the VCD), and
/// the gate exits 1 naming it; so does an edit of a requirement's `check:`.
#[test]
fn a_test_method_is_not_closed_by_a_model_and_method_or_check_edits_fail_the_gate() {
    let d = scratch("method");
    let req = requirements(&d, |_, t| t.to_string());
    verify(&d, &req, "base", &[]);
    let dir = scratch("method-copy");
    let edited = requirements(&dir, |f, t| {
        if f == "plunger.yaml" {
            t.replacen("    method: analysis", "    method: test", 1)
        } else if f == "charge.yaml" {
            let i = t.find("  - id: CHG-V\n").unwrap();
            let (head, tail) = t.split_at(i);
            format!(
                "{head}{}",
                tail.replacen("check: charge-analysis", "check: plunger-attraction", 1)
            )
        } else {
            t.to_string()
        }
    });
    let (code, doc, err) = verify(&d, &edited, "now", &["--baseline", "base/compliance.json"]);
    assert_eq!(code, 1, "{err}");
    let r = row(&doc, "PLG-EXTRA-VEL");
    assert_eq!(r["method"], "test");
    assert_eq!(r["status"], "not-verified", "{r}");
    assert!(
        r["reason"]
            .as_str()
            .unwrap()
            .starts_with("its method is test (ECSS-E-ST-10-02C): model evidence"),
        "{r}"
    );
    assert!(
        err.contains(
            "REGRESSION PLG-EXTRA-VEL: requirement changed, needs review: method `analysis` -> `test`"
        ),
        "{err}"
    );
    assert!(
        err.contains("REGRESSION CHG-V: requirement changed, needs review: check `charge-analysis` -> `plunger-attraction`"),
        "{err}"
    );
    let vcd = std::fs::read_to_string(d.join("now/vcd.csv")).unwrap();
    let line = vcd
        .lines()
        .find(|l| l.starts_with("PLG-EXTRA-VEL,"))
        .unwrap();
    assert!(line.contains("not verified"), "{line}");
}

/// Issue 49: `--confidence` outside [0.5, 1) is refused (exit 2); an open NCR on a compliant
/// row leaves it not plainly compliant; a disposition whose requirement was renamed is said,
/// and the rows computed from the input its renamed judge rejects are not plainly compliant.
#[test]
fn smaller_holes_confidence_open_ncr_renamed_judge() {
    let d = scratch("holes");
    let req = requirements(&d, |_, t| t.to_string());
    for c in ["0.001", "0.4", "1", "1.5"] {
        let out = geodesic(
            &[
                "verify",
                "--requirements",
                req.to_str().unwrap(),
                "--confidence",
                c,
            ],
            &d,
        );
        assert_eq!(out.status.code(), Some(2), "--confidence {c}");
        let e = String::from_utf8_lossy(&out.stderr);
        assert!(
            e.contains(&format!("--confidence {c}: must be at least 0.5")),
            "{e}"
        );
    }
    let ncr = "dispositions:\n  - requirement: CHG-V\n    kind: NCR\n    reference: NCR-T-9\n    \
               reason: seen on the bench\n    owner: tests\n    date: 2099-01-01\n";
    std::fs::write(d.join("ncr.yaml"), ncr).unwrap();
    // the facility family with FAC-ADH-CAL alone, renamed
    let fac = std::fs::read_to_string(workspace().join("requirements/facility.yaml")).unwrap();
    let i = fac.find("  - id: FAC-ADH-CAL\n").unwrap();
    let j = i + 4 + fac[i + 4..].find("  - id: ").unwrap();
    let head = &fac[..fac.find("requirements:\n").unwrap() + "requirements:\n".len()];
    std::fs::write(
        req.join("facility.yaml"),
        format!(
            "{head}{}",
            fac[i..j].replace("id: FAC-ADH-CAL", "id: FAC-ADH-CAL-2")
        ),
    )
    .unwrap();
    let (_, doc, err) = verify(&d, &req, "r", &["--dispositions", "ncr.yaml"]);
    assert_eq!(
        row(&doc, "CHG-V")["verdict"],
        "compliant (NCR NCR-T-9 open)"
    );
    let v = row(&doc, "REL-GPRM-VEL")["verdict"].as_str().unwrap();
    assert!(v.contains("budget judge FAC-ADH-CAL not loaded"), "{v}");
    assert_eq!(doc["summary"]["plainly_compliant"], 0);
    // the mission's own dispositions file names FAC-ADH-CAL: said
    let (_, _, err2) = verify(&d, &req, "s", &[]);
    assert!(
        err2.contains("NCR NCR-GEO-002") && err2.contains("names FAC-ADH-CAL, which is not loaded"),
        "{err2} / {err}"
    );
}

/// Issue 49: a model input edit is reviewed like a requirement edit, whichever way it moves
/// the rows. `contact_voltage_2sigma_v: 1.0 -> 0.95` closes CHG-Q's known non-compliance
/// (NCR-GEO-001 would simply drop): the gate exits 1 naming CHG-Q, the parameter, its old and
/// new value; a comment edit moves nothing and passes.
#[test]
fn a_model_input_edit_that_closes_a_non_compliance_fails_the_gate_naming_the_row() {
    let d = scratch("input-edit");
    let req = requirements(&d, |_, t| t.to_string());
    let (_, base, _) = verify(&d, &req, "base", &[]);
    assert_eq!(row(&base, "CHG-Q")["status"], "non-compliant");
    assert_eq!(
        base["run"]["inputs"]["charge"]["parameters"]["contact_voltage_2sigma_v"],
        "1.0"
    );
    let charge = std::fs::read_to_string(workspace().join("models/charge/charge.yaml")).unwrap();
    let edited = charge.replace(
        "contact_voltage_2sigma_v: 1.0",
        "contact_voltage_2sigma_v: 0.95",
    );
    assert_ne!(edited, charge);
    std::fs::write(d.join("charge.yaml"), edited).unwrap();
    let (code, doc, err) = verify(
        &d,
        &req,
        "now",
        &[
            "--baseline",
            "base/compliance.json",
            "--charge",
            "charge.yaml",
        ],
    );
    assert_eq!(
        row(&doc, "CHG-Q")["status"],
        "compliant",
        "the edit closes it"
    );
    assert_eq!(code, 1, "{err}");
    let line = err
        .lines()
        .find(|l| l.contains("REGRESSION CHG-Q:"))
        .unwrap_or_else(|| panic!("{err}"));
    assert!(
        line.contains(
            "input changed, needs review: charge contact_voltage_2sigma_v 1.0 -> 0.95 (charge.yaml)"
        ) && line.contains("status non-compliant -> compliant"),
        "{line}"
    );
    let changes = doc["baseline_diff"]["inputs_changed"].as_array().unwrap();
    assert_eq!(changes.len(), 1, "{changes:?}");
    assert_eq!(changes[0]["parameter"], "contact_voltage_2sigma_v");
    let rows = changes[0]["rows"].as_array().unwrap();
    assert!(
        rows.iter()
            .any(|r| r.as_str().unwrap().starts_with("CHG-Q (")),
        "{rows:?}"
    );
    assert!(
        rows.iter()
            .any(|r| r.as_str().unwrap().starts_with("CHG-V (")),
        "{rows:?}"
    );

    // a comment edit changes the file's hash, no parameter: nothing to review
    std::fs::write(d.join("comment.yaml"), format!("{charge}\n# a note\n")).unwrap();
    let (code, doc, err) = verify(
        &d,
        &req,
        "now2",
        &[
            "--baseline",
            "base/compliance.json",
            "--charge",
            "comment.yaml",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        doc["baseline_diff"]["inputs_changed"]
            .as_array()
            .unwrap()
            .is_empty()
    );
}

/// Issue 49: every judged row carries a credibility assessment, and a requirement may state the
/// level its verdict needs. REL-GPRM-VEL with `credibility: 4` is not compliant, whatever its
/// margin: its budget is rejected by FAC-ADH-CAL (validation 0). The gate calls a row demoted
/// so a regression, naming it.
#[test]
fn a_requirement_needing_more_credibility_than_its_evidence_has_is_not_compliant() {
    let d = scratch("credibility");
    let need4 = |name: &str, t: &str| {
        if name == "release.yaml" {
            t.replacen(
                "    check: release-montecarlo\n    parent: {id: TMS-Z-VEL, margin: 1.0}",
                "    check: release-montecarlo\n    parent: {id: TMS-Z-VEL, margin: 1.0}\n    credibility: 4",
                1,
            )
        } else {
            t.to_string()
        }
    };
    // every family, FAC-ADH-CAL's too; `--only` runs REL-GPRM-VEL and the row that judges its
    // budget
    let all = d.join("all");
    std::fs::create_dir_all(&all).unwrap();
    for e in std::fs::read_dir(workspace().join("requirements"))
        .unwrap()
        .flatten()
    {
        let name = e.file_name().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(e.path()).unwrap();
        std::fs::write(all.join(&name), need4(&name, &text)).unwrap();
    }
    assert!(
        std::fs::read_to_string(all.join("release.yaml"))
            .unwrap()
            .contains("credibility: 4")
    );
    let (code, doc, err) = verify(&d, &all, "only", &["--only", "REL-GPRM-VEL"]);
    assert_eq!(code, 1, "FAC-ADH-CAL is non-compliant: {err}");
    let r = row(&doc, "REL-GPRM-VEL");
    let c = &r["credibility"];
    assert_eq!(r["status"], "not-verified", "{r}");
    assert_eq!(c["required"], 4, "{c}");
    assert_eq!(c["validation"]["level"], 0, "{c}");
    assert!(
        c["validation"]["why"]
            .as_str()
            .unwrap()
            .contains("rejected by FAC-ADH-CAL"),
        "{c}"
    );
    assert!(
        r["reason"]
            .as_str()
            .unwrap()
            .contains("below the 4 its requirement needs"),
        "{r}"
    );
    for f in [
        "verification",
        "validation",
        "input_pedigree",
        "results_uncertainty",
        "results_robustness",
    ] {
        let l = c[f]["level"].as_u64().unwrap();
        assert!(
            l <= 4 && c[f]["why"].as_str().is_some_and(|w| !w.is_empty()),
            "{f}: {c}"
        );
    }
    assert_eq!(c["results_uncertainty"]["level"], 4, "{c}");
    assert_eq!(c["results_robustness"]["level"], 3, "{c}");

    // the gate: a baseline without the need, then the need
    let req = requirements(&d, |_, t| t.to_string());
    let (_, base, _) = verify(&d, &req, "base", &[]);
    assert_eq!(row(&base, "REL-GPRM-VEL")["status"], "compliant");
    for r in base["requirements"].as_array().unwrap() {
        assert_eq!(
            r["status"] != "not-verified",
            r.get("credibility").is_some(),
            "every judged row, only those: {}",
            r["id"]
        );
    }
    let req4 = requirements(&d, need4);
    let (code, doc, err) = verify(&d, &req4, "now", &["--baseline", "base/compliance.json"]);
    assert_eq!(row(&doc, "REL-GPRM-VEL")["status"], "not-verified");
    assert_eq!(code, 1, "{err}");
    assert!(
        err.lines().any(|l| l.contains("REGRESSION REL-GPRM-VEL:")
            && l.contains(
                "no longer compliant: credibility 0 is below the 4 its requirement needs"
            )),
        "{err}"
    );
    // a level that is not 0-4 is bad input with its file and line
    let bad = requirements(&d, |name, t| {
        if name == "release.yaml" {
            t.replacen(
                "    check: release-montecarlo\n",
                "    check: release-montecarlo\n    credibility: 5\n",
                1,
            )
        } else {
            t.to_string()
        }
    });
    let out = geodesic(
        &[
            "requirements",
            "check",
            "--requirements",
            bad.to_str().unwrap(),
        ],
        &d,
    );
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{e}");
    assert!(
        e.contains("release.yaml:") && e.contains("credibility 5 is not a level of 0 to 4"),
        "{e}"
    );
}
