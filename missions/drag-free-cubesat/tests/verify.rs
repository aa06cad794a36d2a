//! The mission end to end through the verify pipeline (`geodesic_verify::pipeline::run`, what
//! `geodesic verify --mission drag-free-cubesat` and this crate's program call): its own matrix
//! and document, verdicts that move with its design file, and a bad design file refused before
//! anything is written (issue 16, item 4; issue 49).

use geodesic_mission_drag_free_cubesat::{DEFAULT_DESIGN_YAML, mission, ranges};
use geodesic_verify::pipeline::{Options, run};
use serde_json::Value;
use std::path::Path;

/// The mission on its folder's files (this crate's folder).
fn here() -> geodesic_verify::Mission {
    mission().at(env!("CARGO_MANIFEST_DIR"))
}

fn options(reports: &Path, design: Option<&Path>) -> Options {
    let mut o = Options {
        reports: reports.to_path_buf(),
        json: true,
        ..Options::default()
    };
    if let Some(d) = design {
        o.inputs.insert("design".into(), d.to_path_buf());
    }
    o
}

/// The run's error (a run that succeeds fails the test).
fn refused(opts: &Options) -> String {
    match run(&here(), opts) {
        Ok(o) => panic!("accepted, exit {}", o.code),
        Err(e) => e.to_string(),
    }
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
fn the_mission_has_its_own_matrix_and_document() {
    let d = tempfile::tempdir().unwrap();
    let out = run(&here(), &options(&d.path().join("r"), None)).unwrap();
    assert_eq!(out.code, 0);
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    assert_eq!(doc["run"]["document"]["id"], "GEO-DFC-HSG-VCD-001");
    let s = &doc["summary"];
    assert_eq!(
        (s["total"].as_u64(), s["compliant"].as_u64()),
        (Some(7), Some(4))
    );
    assert_eq!(row(&doc, "DFC-MAG-SHIELD")["basis"], "model");
    assert_eq!(row(&doc, "DFC-MODE-1")["basis"], "accepted");
    assert_eq!(row(&doc, "DFC-ACC-ASD")["status"], "not-verified");
    // its own fidelity rows, no other mission's
    let fid = doc["run"]["fidelity"].as_array().unwrap();
    assert!(
        fid.iter()
            .any(|r| r["figure"].as_str().unwrap().contains("Al6061"))
    );
    assert!(
        !fid.iter()
            .any(|r| r["figure"].as_str().unwrap().contains("99.73"))
    );
    assert!(d.path().join("r/index.html").is_file() && d.path().join("r/vcd.xlsx").is_file());
}

#[test]
fn the_shield_verdict_moves_with_the_design_file() {
    let d = tempfile::tempdir().unwrap();
    let thin = d.path().join("thin.yaml");
    std::fs::write(
        &thin,
        DEFAULT_DESIGN_YAML.replace("thickness_mm: 0.1", "thickness_mm: 0.02"),
    )
    .unwrap();
    let out = run(&here(), &options(&d.path().join("r"), Some(&thin))).unwrap();
    assert_eq!(out.code, 1);
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    let r = row(&doc, "DFC-MAG-SHIELD");
    assert_eq!(r["status"], "non-compliant");
    assert!(r["value"].as_f64().unwrap() > 0.01);
    // a broken design file is refused with its name, nothing written
    let bad = d.path().join("bad.yaml");
    std::fs::write(&bad, "caging_load_n: [\n").unwrap();
    let e = refused(&options(&d.path().join("r2"), Some(&bad)));
    assert!(e.to_string().contains("bad.yaml"), "{e}");
    assert!(!d.path().join("r2").exists());
}

/// Issue 49: a design value outside the plausible range the mission states is refused before
/// anything runs, in one line naming the file and line, the range and the unit; the same value
/// with its range overridden for a reason is accepted.
#[test]
fn unit_slips_in_the_design_are_refused_with_file_line_range_and_unit() {
    let d = tempfile::tempdir().unwrap();
    for (from, to, key, want) in [
        (
            "mu_r: 200000.0",
            "mu_r: 2e12",
            "shield.mu_r",
            "shield.mu_r = 2e12 is outside its plausible range [1, 1e6] -",
        ),
        (
            "fe_von_mises_mpa: 27.5",
            "fe_von_mises_mpa: 0.0275",
            "fe_von_mises_mpa",
            "fe_von_mises_mpa = 0.0275 is outside its plausible range [0.4, 2000] MPa",
        ),
    ] {
        let line = DEFAULT_DESIGN_YAML
            .lines()
            .position(|l| l.contains(from))
            .unwrap()
            + 1;
        let edited = DEFAULT_DESIGN_YAML.replacen(from, to, 1);
        assert_ne!(edited, DEFAULT_DESIGN_YAML, "{from}");
        let f = d.path().join("in.yaml");
        std::fs::write(&f, &edited).unwrap();
        let e = refused(&options(&d.path().join("reports"), Some(&f)));
        assert_eq!(e.lines().count(), 1, "one line: {e}");
        assert!(e.contains(&format!("in.yaml:{line}: ")), "{e}");
        assert!(e.contains(want), "{e}");
        assert!(
            !d.path().join("reports").exists(),
            "nothing written on bad input"
        );
        let why = edited.replacen(
            &format!("  {key}: {{kind:"),
            &format!(
                "  {key}: {{range: {{min: 0, max: 1e13, reason: \"this test's what-if\"}}, kind:"
            ),
            1,
        );
        assert_ne!(why, edited, "the pedigree entry of {key}");
        assert!(ranges::question(&why, "in.yaml").is_ok());
    }
}

/// The reviewed baseline the descriptor names (`baseline:`, as a generated project's
/// `verify --baseline` gate reads one): the unchanged folder gates against it with exit 0; a
/// thinner shield foil is a regression (exit 1, the row named). The mission's dispositions
/// file (`dispositions:`) is read and named in the run.
#[test]
fn the_gate_against_the_reviewed_baseline_passes_unchanged_and_fails_on_a_thinner_foil() {
    let d = tempfile::tempdir().unwrap();
    let m = here();
    let baseline = m.path(
        m.spec
            .baseline
            .as_deref()
            .expect("a baseline in mission.yaml"),
    );
    let mut o = options(&d.path().join("r"), None);
    o.baseline = Some(baseline.clone());
    let out = run(&m, &o).unwrap();
    assert_eq!(out.code, 0, "{:?}", out.messages);
    assert!(out.diff.is_some());
    let doc: Value = serde_json::from_str(&out.json).unwrap();
    let disp = doc["run"]["dispositions"]["label"].as_str().unwrap();
    assert!(disp.ends_with("dispositions.yaml"), "{disp}");

    let thin = d.path().join("thin.yaml");
    std::fs::write(
        &thin,
        DEFAULT_DESIGN_YAML.replace("thickness_mm: 0.1", "thickness_mm: 0.02"),
    )
    .unwrap();
    let mut o = options(&d.path().join("r2"), Some(&thin));
    o.baseline = Some(baseline);
    let out = run(&m, &o).unwrap();
    assert_eq!(out.code, 1);
    assert!(
        out.messages.iter().any(|l| l.contains("DFC-MAG-SHIELD")),
        "{:?}",
        out.messages
    );
}
