//! Reports are committed as a whole set or not at all: killed runs (SIGKILL at spread-out
//! moments, SIGTERM) never leave a mixture of two runs' files, an interrupted run leaves nothing
//! behind, and a bad `--junit` target fails before anything is replaced.

mod common;
use common::{geodesic, scratch, workspace};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

const CONTROLLED: [&str; 5] = [
    "compliance.json",
    "compliance.md",
    "vcd.md",
    "vcd.html",
    "index.html",
];

/// A project folder with only the charge requirements (a quick verify).
fn project(name: &str) -> std::path::PathBuf {
    let d = scratch(name);
    std::fs::create_dir_all(d.join("req")).unwrap();
    std::fs::copy(
        workspace().join("requirements/charge.yaml"),
        d.join("req/charge.yaml"),
    )
    .unwrap();
    d
}

fn args(seed: u32) -> Vec<String> {
    args_to(seed, "r")
}

fn args_to(seed: u32, reports: &str) -> Vec<String> {
    [
        "verify",
        "--requirements",
        "req",
        "--no-fidelity",
        "--mc-n",
        "1000",
        "--seed",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([seed.to_string(), "--reports".into(), reports.into()])
    .collect()
}

/// The `--seed N` each controlled report was written with: one value, or a mixed set.
fn seeds_of_set(r: &Path) -> Vec<String> {
    let mut seeds: Vec<String> = CONTROLLED
        .iter()
        .filter_map(|f| std::fs::read_to_string(r.join(f)).ok())
        .map(|text| {
            let i = text
                .find("--seed ")
                .expect("the command line is in every report")
                + 7;
            text[i..].chars().take_while(char::is_ascii_digit).collect()
        })
        .collect();
    seeds.sort();
    seeds.dedup();
    seeds
}

fn leftovers(dir: &Path, out: &mut Vec<String>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.contains("tmp-geodesic") || name.contains("link-geodesic") {
            out.push(e.path().display().to_string());
        }
        if e.file_type().unwrap().is_dir() {
            leftovers(&e.path(), out);
        }
    }
}

fn set_folders(r: &Path) -> usize {
    std::fs::read_dir(r.join(".geodesic/sets")).unwrap().count()
}

#[test]
fn killed_runs_never_leave_a_mixed_report_set() {
    let d = project("kill");
    let first = geodesic(&args(1).iter().map(String::as_str).collect::<Vec<_>>(), &d);
    assert!(first.status.code().unwrap() <= 1, "{first:?}");
    assert_eq!(seeds_of_set(&d.join("r")), vec!["1"]);
    let mut seen_new = 0;
    for k in 0..20u32 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_geodesic"))
            .args(args(k + 2))
            .current_dir(&d)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // kill points spread over the run, commit included (whatever the machine's speed, every
        // moment must leave one whole set)
        std::thread::sleep(Duration::from_millis(u64::from(k) * 5));
        let _ = child.kill();
        let _ = child.wait();
        let seeds = seeds_of_set(&d.join("r"));
        assert_eq!(seeds.len(), 1, "kill {k}: a mixed report set {seeds:?}");
        if seeds[0] == (k + 2).to_string() {
            seen_new += 1;
        }
        for f in CONTROLLED {
            assert!(d.join("r").join(f).is_file(), "kill {k}: {f} is missing");
        }
    }
    // the next run removes what the killed runs left and keeps one set
    let last = geodesic(&args(99).iter().map(String::as_str).collect::<Vec<_>>(), &d);
    assert!(last.status.code().unwrap() <= 1, "{last:?}");
    assert_eq!(seeds_of_set(&d.join("r")), vec!["99"]);
    assert_eq!(set_folders(&d.join("r")), 1);
    let mut left = Vec::new();
    leftovers(&d, &mut left);
    assert!(left.is_empty(), "left behind: {left:?}");
    eprintln!("{seen_new} of 20 killed runs had committed their set");
}

#[test]
fn an_interrupted_run_leaves_nothing_behind() {
    let d = project("term");
    let first = geodesic(&args(1).iter().map(String::as_str).collect::<Vec<_>>(), &d);
    assert!(first.status.code().unwrap() <= 1, "{first:?}");
    for (k, sig) in ["TERM", "INT", "HUP"].iter().enumerate() {
        let child = Command::new(env!("CARGO_BIN_EXE_geodesic"))
            .args(args(k as u32 + 2))
            .current_dir(&d)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(150));
        let status = Command::new("kill")
            .args([format!("-{sig}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let out = child.wait_with_output().unwrap();
        // interrupted (128 + signal) or finished before the signal arrived (0 or 1)
        let code = out.status.code().unwrap();
        assert!(code <= 1 || code > 128, "{sig}: exit {code}");
        assert_eq!(seeds_of_set(&d.join("r")).len(), 1);
        assert_eq!(set_folders(&d.join("r")), 1, "{sig}: a staged set was left");
        let mut left = Vec::new();
        leftovers(&d, &mut left);
        assert!(left.is_empty(), "{sig}: left behind: {left:?}");
    }
}

#[test]
fn a_bad_junit_target_fails_before_the_reports_are_replaced() {
    let d = project("junit");
    let first = geodesic(&args(1).iter().map(String::as_str).collect::<Vec<_>>(), &d);
    assert!(first.status.code().unwrap() <= 1, "{first:?}");
    std::fs::create_dir_all(d.join("a-dir")).unwrap();
    for target in ["missing/junit.xml", "a-dir"] {
        let mut a = args(7);
        a.extend(["--junit".to_string(), target.to_string()]);
        let out = geodesic(&a.iter().map(String::as_str).collect::<Vec<_>>(), &d);
        assert_eq!(out.status.code(), Some(2), "{target}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("--junit") && err.contains(target), "{err}");
        assert_eq!(seeds_of_set(&d.join("r")), vec!["1"], "{target}");
        let mut left = Vec::new();
        leftovers(&d, &mut left);
        assert!(left.is_empty(), "{target}: left behind: {left:?}");
    }
    // a file where the reports folder should be
    std::fs::write(d.join("not-a-dir"), b"x").unwrap();
    let a = args_to(7, "not-a-dir");
    let out = geodesic(&a.iter().map(String::as_str).collect::<Vec<_>>(), &d);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("not-a-dir") && err.contains("not a directory"),
        "{err}"
    );
}
