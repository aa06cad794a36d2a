//! End-to-end tests of `geodesic capture` and `geodesic charge`: the JSON contract of
//! interface.md, negative flag values, and exit 2 with `file:line` on bad input.

mod common;
use common::test_dir;

use std::path::PathBuf;
use std::process::Output;

/// Runs `geodesic ARGS` in this test's own temporary directory.
fn geodesic(args: &[&str]) -> Output {
    common::geodesic(args, &test_dir())
}

fn json(out: &Output) -> serde_json::Value {
    json_with(out, 0)
}

/// The JSON document of a run that exited with `code` (capture: 1 = not captured).
fn json_with(out: &Output, code: i32) -> serde_json::Value {
    assert_eq!(
        out.status.code(),
        Some(code),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("exactly one JSON document on stdout")
}

fn scratch_file(name: &str, text: &str) -> PathBuf {
    let p = test_dir().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn assert_bad(out: &Output, file_line: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert!(out.stdout.is_empty());
    assert_eq!(err.trim().lines().count(), 1, "one-line cause: {err}");
    assert!(err.contains(file_line), "expected {file_line} in: {err}");
}

#[test]
fn capture_json_with_negative_velocity() {
    let d = json(&geodesic(&["capture", "--vz", "-3e-6", "--json"]));
    // (3/12)^4
    assert!((d["quartic_sum"].as_f64().unwrap() - 0.003_906_25).abs() < 1e-12);
    assert_eq!(d["captured"], true);
    assert_eq!(d["dominant"][0]["state"], "vz");
    assert!((d["max_box_scale"].as_f64().unwrap() - 1.4).abs() < 1e-6);
    assert_eq!(d["xlim"]["vz"].as_f64().unwrap(), 12e-6);
}

#[test]
fn capture_at_the_single_state_limit_is_not_captured() {
    // exit 1: the verdict of a command that judges
    let d = json_with(&geodesic(&["capture", "--vz", "12e-6", "--json"]), 1);
    assert_eq!(d["captured"], false);
}

#[test]
fn capture_state_file_and_flag_override() {
    let s = scratch_file("state.yaml", "vz: 6.0e-6\nx: 1.0e-4\n");
    let d = json(&geodesic(&[
        "capture",
        "--state",
        s.to_str().unwrap(),
        "--x",
        "0",
        "--json",
    ]));
    assert!((d["quartic_sum"].as_f64().unwrap() - 0.0625).abs() < 1e-12);
    assert_eq!(d["state"]["x"].as_f64().unwrap(), 0.0);
}

#[test]
fn capture_unknown_state_exits_2_with_file_line() {
    let s = scratch_file("bad-state.yaml", "vz: 1.0e-6\nvq: 2.0\n");
    let f = s.to_str().unwrap();
    assert_bad(
        &geodesic(&["capture", "--state", f, "--json"]),
        &format!("{f}:2"),
    );
}

#[test]
fn capture_bad_xlim_exits_2_with_file_line() {
    let text = geodesic_capture::DEFAULT_CAPTURE_YAML;
    let line = text
        .lines()
        .position(|l| l.starts_with("    vz: 12.0e-6"))
        .unwrap()
        + 1;
    let s = scratch_file(
        "bad-xlim.yaml",
        &text.replacen("    vz: 12.0e-6", "    vz: -12.0e-6", 1),
    );
    let f = s.to_str().unwrap();
    assert_bad(
        &geodesic(&["capture", "--capture", f, "--json"]),
        &format!("{f}:{line}:"),
    );
}

#[test]
fn capture_incomplete_xlim_exits_2_with_file_line() {
    let text = geodesic_capture::DEFAULT_CAPTURE_YAML.replacen("    wz: 262.9282e-6\n", "", 1);
    let s = scratch_file("short-xlim.yaml", &text);
    let f = s.to_str().unwrap();
    let out = geodesic(&["capture", "--capture", f, "--json"]);
    assert_bad(&out, &format!("{f}:"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("lacks state"));
}

#[test]
fn capture_probability_from_samples() {
    let s = scratch_file("vz.txt", "# z velocities\n1e-6\n-2e-6\n13e-6\n");
    let d = json(&geodesic(&[
        "capture",
        "--vz-samples",
        s.to_str().unwrap(),
        "--json",
    ]));
    let p = &d["capture_probability"];
    assert_eq!(p["n"], 3);
    assert_eq!(p["captured"], 2);
}

#[test]
fn charge_json_contract_and_values() {
    let d = json(&geodesic(&["charge", "--n", "20000", "--json"]));
    let c = d["c_rt_pf"].as_f64().unwrap();
    assert!((c - 2.4441).abs() < 1e-3, "{c}");
    let q = d["q_2sigma_e"].as_f64().unwrap();
    assert!((q - 3.1297e8).abs() < 1e5, "{q}");
    let v = d["v_2sigma_v"].as_f64().unwrap();
    assert!((v - 1.0605).abs() < 1e-3, "{v}");
    assert!((d["neutralise"]["days"].as_f64().unwrap() - 50.0).abs() < 1e-9);
    assert_eq!(d["monte_carlo"]["n"], 20000);
    assert_eq!(d["inputs"]["d_m"].as_f64().unwrap(), 100e-9);
}

#[test]
fn charge_rejects_a_non_positive_gap() {
    let out = geodesic(&["charge", "--d-m", "-1e-7", "--json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--d-m"));
}
