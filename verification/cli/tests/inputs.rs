//! One input resolution for every command (issue 37, item 3): `verify`, `montecarlo`,
//! `sensitivity` and `tip-radius` read the same budget file (the repository's copy when run from
//! the repository's root, the built-in copy elsewhere, the file given with `--budget`), say
//! which, and print the same SHA-256 of its bytes; editing the budget moves them all.
//!
//! Run on a copy of the repository's models in a scratch directory, never on the real files.

mod common;

use common::{geodesic, scratch, workspace};
use serde_json::Value;
use std::path::Path;

fn json_of(args: &[&str], cwd: &Path) -> Value {
    let out = geodesic(args, cwd);
    assert!(
        out.status.code() == Some(0) || out.status.code() == Some(1),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}"))
}

/// A scratch "repository" holding a copy of the models the commands read.
fn copy_models(name: &str) -> std::path::PathBuf {
    let root = scratch(name);
    for rel in [
        "models/release/budget.yaml",
        "models/capture/capture.yaml",
        "models/charge/charge.yaml",
    ] {
        let to = root.join(rel);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(workspace().join(rel), &to).unwrap();
    }
    root
}

/// What each command read (`{label, sha256, origin}`) and a figure that depends on the budget.
struct Seen {
    input: Value,
    figure: f64,
}

fn run_all(dir: &Path) -> Vec<(&'static str, Seen)> {
    let reports = dir.join("reports-out");
    let reports = reports.to_str().unwrap();
    let v = json_of(
        &[
            "verify",
            "--only",
            "REL-GPRM-VEL",
            "--mc-n",
            "3000",
            "--no-fidelity",
            "--reports",
            reports,
            "--json",
        ],
        dir,
    );
    let row = v["requirements"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["id"] == "REL-GPRM-VEL")
        .unwrap()
        .clone();
    let verify = Seen {
        input: v["run"]["inputs"]["budget"].clone(),
        figure: row["sampling"]["estimate"].as_f64().unwrap(),
    };
    let mc = json_of(&["montecarlo", "--n", "3000", "--json"], dir);
    assert_eq!(mc["budget_hash"], mc["inputs"]["budget"]["sha256"]);
    let montecarlo = Seen {
        input: mc["inputs"]["budget"].clone(),
        figure: mc["p9973_um_s"].as_f64().unwrap(),
    };
    let s = json_of(&["sensitivity", "--n", "200", "--json"], dir);
    let sensitivity = Seen {
        input: s["inputs"]["budget"].clone(),
        figure: s["p9973_um_s"].as_f64().unwrap(),
    };
    let t = json_of(
        &["tip-radius", "--radii", "10", "--mc-n", "2000", "--json"],
        dir,
    );
    let tip = Seen {
        input: t["inputs"]["budget"].clone(),
        figure: t["monte_carlo"][0]["p9973_um_s"].as_f64().unwrap(),
    };
    assert!(t["mass_kg"].is_number());
    vec![
        ("verify", verify),
        ("montecarlo", montecarlo),
        ("sensitivity", sensitivity),
        ("tip-radius", tip),
    ]
}

#[test]
fn every_command_reads_hashes_and_moves_with_the_repository_budget() {
    let dir = copy_models("repo");
    let budget = dir.join("models/release/budget.yaml");
    let bytes = std::fs::read(&budget).unwrap();
    let sha = geodesic_util::hash::sha256_hex(&bytes);
    let before = run_all(&dir);
    for (cmd, s) in &before {
        assert_eq!(s.input["sha256"], sha.as_str(), "{cmd}");
        assert_eq!(s.input["origin"], "repository", "{cmd}");
        assert_eq!(s.input["label"], "models/release/budget.yaml", "{cmd}");
        assert!(s.figure.is_finite() && s.figure > 0.0, "{cmd}");
    }

    // a lighter TM: every release velocity grows (the same momentum on less mass)
    let text = String::from_utf8(bytes).unwrap();
    // (its pedigree widens the TM mass's plausible range with a reason: issue 49)
    let edited = text
        .replacen("tm_mass_kg: {fixed: 1.96}", "tm_mass_kg: {fixed: 1.5}", 1)
        .replace(
            "tm_mass_kg: {kind: cited,",
            "tm_mass_kg: {range: {min: 0.4, max: 2.0, reason: \"this test's what-if: a lighter TM\"}, kind: cited,",
        );
    assert_ne!(edited, text, "the budget's TM mass line moved");
    std::fs::write(&budget, &edited).unwrap();
    let sha_edited = geodesic_util::hash::sha256_hex(edited.as_bytes());
    let after = run_all(&dir);
    for ((cmd, b), (_, a)) in before.iter().zip(&after) {
        assert_eq!(a.input["sha256"], sha_edited.as_str(), "{cmd}");
        assert_eq!(a.input["origin"], "repository", "{cmd}");
        assert!(
            a.figure > b.figure * 1.1,
            "{cmd}: {} um/s with 1.96 kg, {} um/s with 1.5 kg",
            b.figure,
            a.figure
        );
    }
    let t = json_of(&["tip-radius", "--mc-n", "0", "--json"], &dir);
    assert_eq!(t["mass_kg"], 1.5);
}

#[test]
fn outside_the_repository_the_built_in_copy_and_a_given_file() {
    let empty = scratch("elsewhere");
    let original = std::fs::read(workspace().join("models/release/budget.yaml")).unwrap();
    let sha = geodesic_util::hash::sha256_hex(&original);
    let mc = json_of(&["montecarlo", "--n", "2000", "--json"], &empty);
    assert_eq!(mc["inputs"]["budget"]["origin"], "built-in");
    assert_eq!(mc["inputs"]["budget"]["sha256"], sha.as_str());
    assert_eq!(mc["budget_hash"], sha.as_str());
    let s = json_of(&["sensitivity", "--n", "200", "--json"], &empty);
    assert_eq!(s["inputs"]["budget"]["origin"], "built-in");
    assert_eq!(s["inputs"]["budget"]["sha256"], sha.as_str());

    let given = empty.join("mine.yaml");
    std::fs::write(&given, &original).unwrap();
    let t = json_of(
        &[
            "tip-radius",
            "--mc-n",
            "0",
            "--budget",
            given.to_str().unwrap(),
            "--json",
        ],
        &empty,
    );
    assert_eq!(t["inputs"]["budget"]["origin"], "given");
    assert_eq!(t["inputs"]["budget"]["sha256"], sha.as_str());

    // the human output says which file and its hash
    let out = geodesic(&["montecarlo", "--n", "2000"], &empty);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains(&format!(
            "release budget: <built-in>/models/release/budget.yaml (the built-in copy), sha256 {sha}: "
        )),
        "{text}"
    );
}

#[test]
fn capture_and_charge_say_which_file_they_read() {
    let dir = copy_models("repo-cc");
    let cap = json_of(&["capture", "--vz", "3um/s", "--json"], &dir);
    let cap_sha = geodesic_util::hash::sha256_hex(
        &std::fs::read(dir.join("models/capture/capture.yaml")).unwrap(),
    );
    assert_eq!(cap["inputs"]["capture"]["sha256"], cap_sha.as_str());
    assert_eq!(cap["inputs"]["capture"]["origin"], "repository");

    // charge reads its defaults from the charge file: a wider contact voltage spread moves Q
    let q = |dir: &Path| json_of(&["charge", "--n", "2000", "--json"], dir);
    let before = q(&dir);
    assert_eq!(before["inputs"]["charge"]["origin"], "repository");
    let f = dir.join("models/charge/charge.yaml");
    let text = std::fs::read_to_string(&f).unwrap();
    let edited = text.replacen(
        "contact_voltage_2sigma_v: 1.0",
        "contact_voltage_2sigma_v: 2.0",
        1,
    );
    assert_ne!(edited, text);
    std::fs::write(&f, &edited).unwrap();
    let after = q(&dir);
    assert_eq!(
        after["inputs"]["charge"]["sha256"],
        geodesic_util::hash::sha256_hex(edited.as_bytes()).as_str()
    );
    let (b, a) = (
        before["q_2sigma_e"].as_f64().unwrap(),
        after["q_2sigma_e"].as_f64().unwrap(),
    );
    assert!((a / b - 2.0).abs() < 1e-9, "Q 2-sigma {b} -> {a} e");
}

/// Issue 49: a model input whose value lies outside the plausible range its mission states is
/// refused before anything runs: exit 2, one line naming the file and line, the range and the
/// unit expected. The audit's slips: a tenfold TM mass, a capacitance in F for pF, a
/// permeability no material has, a stress in GPa under an MPa key.
#[test]
fn unit_slips_in_model_inputs_are_refused_with_file_line_range_and_unit() {
    let d = scratch("slips");
    for (rel, from, to, args, want) in [
        (
            "models/release/budget.yaml",
            "tm_mass_kg: {fixed: 1.96}",
            "tm_mass_kg: {fixed: 19.6}",
            &["verify", "--budget", "in.yaml"][..],
            "tm_mass_kg = 19.6 is outside its plausible range [1.9, 2] kg",
        ),
        (
            "models/release/budget.yaml",
            "tm_mass_kg: {fixed: 1.96}",
            "tm_mass_kg: {fixed: 19.6}",
            &["montecarlo", "--n", "10", "--budget", "in.yaml"][..],
            "tm_mass_kg = 19.6 is outside its plausible range [1.9, 2] kg",
        ),
        (
            "models/charge/charge.yaml",
            "c_eh_f: 34.4e-12",
            "c_eh_f: 34.4",
            &["verify", "--charge", "in.yaml"][..],
            "capacitances.c_eh_f = 34.4 is outside its plausible range [1e-13, 1e-9] F",
        ),
    ] {
        let text = std::fs::read_to_string(workspace().join(rel)).unwrap();
        let line = text.lines().position(|l| l.contains(from)).unwrap() + 1;
        let edited = text.replacen(from, to, 1);
        assert_ne!(edited, text, "{rel}: {from}");
        std::fs::write(d.join("in.yaml"), &edited).unwrap();
        let out = geodesic(args, &d);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
        assert!(err.contains(&format!("in.yaml:{line}: ")), "{err}");
        assert!(err.contains(want), "{err}");
        assert!(!d.join("reports").exists(), "nothing written on bad input");
        // the same value with a range overridden for a reason is accepted
        let key = to.split(':').next().unwrap().trim();
        let why = edited.replacen(
            &format!("  {}: {{kind:", pedigree_key(rel, key)),
            &format!(
                "  {}: {{range: {{min: 0, max: 1e13, reason: \"this test's what-if\"}}, kind:",
                pedigree_key(rel, key)
            ),
            1,
        );
        assert_ne!(why, edited, "{rel}: the pedigree entry of {key}");
        let pedigree = geodesic_missions::ranges::question(&why, "in.yaml", ranges_of(rel));
        assert!(pedigree.is_ok(), "{pedigree:?}");
    }
}

fn pedigree_key(rel: &str, key: &str) -> String {
    if rel.contains("charge") {
        format!("capacitances.{key}")
    } else {
        key.into()
    }
}

fn ranges_of(rel: &str) -> &'static [geodesic_core::pedigree::Range] {
    use geodesic_missions::ranges::{BUDGET, CHARGE};
    if rel.contains("budget") {
        BUDGET
    } else {
        CHARGE
    }
}
