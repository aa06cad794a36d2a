//! Fail fast and quiet unless asked (issue 35, items 2 and 3): every input file, output folder
//! and flag is checked before any computation, so a bad one is one line on standard error
//! (naming the flag or file), exit 2, with no check run and nothing written; and standard error
//! carries no per-check timing unless `--progress` is given (the timings go into the report's
//! run information).
//!
//! "Before any computation" is asserted on the output, never on time: each bad-input run is
//! given `--progress`, which prints a line as soon as a check or a fit starts, and its standard
//! error must still be the one line of the cause.

mod common;
use common::{geodesic, scratch, workspace};

use std::path::Path;

/// Asserts exit 2 with exactly one line on standard error containing every one of `names`,
/// and nothing on standard output.
fn one_line(out: &std::process::Output, names: &[&str]) -> String {
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(2), "exit status; stderr: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "one line on stderr, got: {err}");
    for n in names {
        assert!(lines[0].contains(n), "`{n}` not named in: {}", lines[0]);
    }
    assert!(out.stdout.is_empty(), "nothing on stdout");
    err
}

fn verify(d: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["--progress", "verify", "--mc-n", "1000"];
    args.extend_from_slice(extra);
    geodesic(&args, d)
}

#[test]
fn verify_refuses_a_bad_input_before_any_check_runs_and_writes_nothing() {
    let d = scratch("verify-inputs");
    std::fs::write(d.join("bad.json"), "{\n  \"requirements\": [\n  oops\n}\n").unwrap();
    std::fs::write(d.join("bad.yaml"), "a: [unclosed\n").unwrap();
    std::fs::write(d.join("a-file"), "x").unwrap();
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            vec!["--baseline", "nope.json"],
            vec!["--baseline", "nope.json"],
        ),
        // malformed: the file and its line
        (vec!["--baseline", "bad.json"], vec!["bad.json:3:"]),
        (vec!["--tests", "nope.json"], vec!["--tests", "nope.json"]),
        (
            vec!["--dispositions", "nope.yaml"],
            vec!["--dispositions", "nope.yaml"],
        ),
        (vec!["--budget", "nope.yaml"], vec!["--budget", "nope.yaml"]),
        (
            vec!["--capture", "nope.yaml"],
            vec!["--capture", "nope.yaml"],
        ),
        (vec!["--charge", "nope.yaml"], vec!["--charge", "nope.yaml"]),
        (vec!["--budget", "bad.yaml"], vec!["bad.yaml"]),
        (
            vec!["--series", "LPF-DA-ASD=nope.yaml"],
            vec!["--series", "nope.yaml"],
        ),
        (vec!["--reports", "a-file"], vec!["--reports", "a-file"]),
        (
            vec!["--reports", "a-file/reports"],
            vec!["--reports", "a-file"],
        ),
        (
            vec!["--junit", "no-such-folder/junit.xml"],
            vec!["--junit", "no-such-folder"],
        ),
        (vec!["--confidence", "1.5"], vec!["--confidence"]),
    ];
    for (args, names) in cases {
        let out = verify(&d, &args);
        let err = one_line(&out, &names);
        assert!(!err.contains("check "), "{args:?}: a check ran: {err}");
        assert!(!d.join("reports").exists(), "{args:?}: reports written");
        assert!(
            !d.join("a-file").is_dir(),
            "{args:?}: the file was replaced"
        );
    }
}

#[test]
fn fit_diagnose_discover_refuse_an_unwritable_reports_folder_before_the_fit() {
    let d = scratch("fit-reports");
    std::fs::write(d.join("a-file"), "x").unwrap();
    let ds = workspace().join("data/examples/rt-plunger.yaml");
    let ds = ds.to_str().unwrap();
    for cmd in ["fit", "diagnose", "discover"] {
        let out = geodesic(
            &[
                "--progress",
                cmd,
                ds,
                "--effects",
                "piezo",
                "--reports",
                "a-file",
            ],
            &d,
        );
        let err = one_line(&out, &["--reports", "a-file"]);
        assert!(!err.contains("samples"), "{cmd}: the fit started: {err}");
        // a missing dataset: its path
        let out = geodesic(&["--progress", cmd, "nope.yaml", "--effects", "piezo"], &d);
        one_line(&out, &["nope.yaml"]);
        assert!(!d.join("reports").exists(), "{cmd}: reports written");
    }
}

#[test]
fn outputs_of_montecarlo_import_export_and_merge_parts_are_checked_first() {
    let d = scratch("outputs");
    std::fs::write(d.join("a-file"), "x").unwrap();
    // a million releases would take a while: the refusal comes before the first
    let out = geodesic(
        &[
            "--progress",
            "montecarlo",
            "--n",
            "1000000",
            "--shard",
            "1/2",
            "--out",
            "no-such-folder/part.json",
        ],
        &d,
    );
    let err = one_line(&out, &["--out", "no-such-folder"]);
    assert!(!err.contains("releases"), "the Monte Carlo started: {err}");
    let out = geodesic(&["merge", "nope-1.json", "nope-2.json"], &d);
    one_line(&out, &["nope-1.json"]);
    let out = geodesic(&["export", "reqif", "--out", "a-file/x.reqif"], &d);
    one_line(&out, &["--out", "a-file"]);
    let out = geodesic(&["import", "reqif", "nope.reqif", "--out", "a-file"], &d);
    one_line(&out, &["--out", "a-file"]);
    let out = geodesic(&["import", "reqif", "nope.reqif", "--out", "imported"], &d);
    one_line(&out, &["nope.reqif"]);
    assert!(!d.join("imported").exists());
}

/// A short verify: the charge requirements only, no fidelity table.
fn short_verify(d: &Path, progress: bool) -> std::process::Output {
    let req = d.join("requirements");
    std::fs::create_dir_all(&req).unwrap();
    std::fs::copy(
        workspace().join("requirements/charge.yaml"),
        req.join("charge.yaml"),
    )
    .unwrap();
    let mut args = vec![
        "verify",
        "--json",
        "--no-fidelity",
        "--requirements",
        "requirements",
    ];
    if progress {
        args.insert(0, "--progress");
    }
    geodesic(&args, d)
}

#[test]
fn verify_is_quiet_unless_asked_and_its_timings_are_in_the_run_information() {
    let d = scratch("quiet");
    let out = short_verify(&d, false);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        matches!(out.status.code(), Some(0 | 1)),
        "exit {:?}: {err}",
        out.status.code()
    );
    // standard error is not a terminal here: nothing but errors and warnings
    assert!(
        err.lines()
            .all(|l| l.contains("error") || l.contains("warning")),
        "unasked output on stderr: {err}"
    );
    assert!(!err.contains("took"), "{err}");
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let t = &doc["run"]["timings"];
    let checks = t["checks"].as_array().expect("run.timings.checks");
    assert!(!checks.is_empty());
    for c in checks {
        assert!(c["check"].is_string());
        let s = c["wall_s"].as_f64().expect("wall_s a number");
        assert!(s.is_finite() && s >= 0.0);
    }
    assert!(t["total_s"].as_f64().is_some_and(|s| s.is_finite()));
    let md = std::fs::read_to_string(d.join("reports/compliance.md")).unwrap();
    assert!(md.contains("wall time (differs run to run; not compared): total"));
    // with --progress: the check's wall time on stderr as it ran
    let d = scratch("progress");
    let out = short_verify(&d, true);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("took"), "--progress: {err}");
}
