//! The framework end to end: every registered check run on the built-in requirements, the
//! compliance matrix snapshotted with rounded floats (a change of any value or status shows in
//! review), and the invariants the matrix must keep. The traced tests are not in this matrix:
//! they come from a recorded test run (`cargo xtask test`).

use geodesic_core::Requirements;
use geodesic_core::matrix::{Matrix, Status};
use std::path::Path;

fn requirements() -> Requirements {
    Requirements::load_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../requirements"))
        .unwrap()
}

/// The matrix of the built-in requirements with a small, fixed-seed Monte Carlo (computed once
/// for the tests of this module).
fn matrix() -> &'static Matrix {
    static M: std::sync::OnceLock<Matrix> = std::sync::OnceLock::new();
    M.get_or_init(compute_matrix)
}

fn compute_matrix() -> Matrix {
    let reqs = requirements();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    let ctx = geodesic_checks::builtin_context(dir.clone(), 2000, 7);
    let mut evidence = Vec::new();
    for c in geodesic_checks::registry() {
        if geodesic_core::check::is_wanted(c.as_ref(), &reqs) {
            evidence.push((c.name().to_string(), c.run(&ctx).unwrap()));
        }
    }
    Matrix::build(&reqs, &evidence, None, &[])
}

/// 4 significant digits, so that the snapshot pins values without floating-point noise.
fn round(v: Option<f64>) -> String {
    v.map_or("—".into(), |v| format!("{v:.3e}"))
}

#[test]
fn compliance_matrix_snapshot() {
    let m = matrix();
    let rows: Vec<String> = m
        .requirements
        .iter()
        .map(|r| {
            format!(
                "{:<22} {:<14} {:<10} value {:>10} {:<7} margin {:>10} checks [{}]",
                r.id,
                r.status.as_str(),
                r.basis.map_or("—", |b| b.as_str()),
                round(r.value),
                r.unit,
                round(r.margin),
                r.evidence
                    .iter()
                    .map(|e| format!("{}:{}", e.check, e.basis.map_or("—", |b| b.as_str())))
                    .collect::<Vec<_>>()
                    .join(",")
            )
        })
        .collect();
    insta::assert_snapshot!(rows.join("\n"));
}

#[test]
fn every_requirement_has_a_check_and_no_check_is_orphan() {
    let reqs = requirements();
    let names = geodesic_checks::check_names();
    reqs.validate_checks(&names).unwrap();
    for r in &reqs.items {
        assert!(r.check.is_some(), "{} names no check", r.id);
    }
    // the other missions' checks and requirements are their own crates' (missions/*/)
    let loaded: Vec<&str> = reqs.items.iter().map(|r| r.id.as_str()).collect();
    for c in geodesic_checks::registry() {
        for id in c.verifies() {
            assert!(
                loaded.contains(id),
                "check {} names {id}, which is not a requirement",
                c.name()
            );
        }
    }
}

#[test]
fn not_verified_rows_state_a_reason_and_compliant_rows_a_value() {
    for r in &matrix().requirements {
        match r.status {
            Status::NotVerified => {
                assert!(r.reason.as_ref().is_some_and(|s| !s.is_empty()), "{}", r.id)
            }
            _ => assert!(r.value.is_some() && r.margin.is_some(), "{}", r.id),
        }
    }
}

/// No row is compliant on an illustration, and every verdict names its basis: a compliant or
/// non-compliant row rests on a model, a flow-down or an accepted result; a not-verified row
/// on nothing.
#[test]
fn every_verdict_states_its_basis() {
    use geodesic_core::Basis;
    for r in &matrix().requirements {
        match r.status {
            Status::NotVerified => assert_eq!(r.basis, None, "{}", r.id),
            _ => assert!(
                matches!(
                    r.basis,
                    Some(
                        Basis::Model
                            | Basis::FlowDown
                            | Basis::Accepted
                            | Basis::MethodValidation
                            | Basis::Measurement
                    )
                ),
                "{}: {:?}",
                r.id,
                r.basis
            ),
        }
    }
}

/// A verdict that is not a model's reads as what it rests on, in the status itself: a flow-down,
/// an accepted value, a method validation; what holds by construction says so; a flow-down from
/// a row that is not verified names it; a row computed from the budget FAC-ADH-CAL rejects
/// carries that finding. Only a model verdict with no finding is plainly `compliant`.
#[test]
fn non_model_verdicts_read_as_such() {
    use geodesic_core::Basis;
    let m = matrix();
    let row = |id: &str| m.requirements.iter().find(|r| r.id == id).unwrap();
    for r in &m.requirements {
        assert!(r.verdict.starts_with(r.status.as_str()), "{}", r.id);
        if let Some(b) = r.basis
            && b != Basis::Model
            && r.status != Status::NotVerified
        {
            assert!(r.verdict.contains(b.label()), "{}: {}", r.id, r.verdict);
        }
        if r.verdict == "compliant" {
            assert!(r.plainly_compliant(), "{}", r.id);
        }
    }
    assert_eq!(
        row("TMS-X-POS").verdict,
        "compliant (flow-down; assumes not-verified TMS-X-VEL)"
    );
    assert_eq!(
        row("TMS-Z-ANG").verdict,
        "compliant (flow-down; assumes not-verified TMS-Z-RATE)"
    );
    assert!(row("CAP-QUARTIC").verdict.contains("by construction"));
    assert!(
        row("CAP-XLIM-CONSISTENCY")
            .verdict
            .contains("by construction")
    );
    assert_eq!(
        row("CAP-VZ-SINGLE").verdict,
        "compliant (accepted; by construction)"
    );
    assert!(
        row("CAP-RELEASE-PROB")
            .verdict
            .contains("assumes 5 rows not verified")
    );
    for id in [
        "REL-GPRM-VEL",
        "REL-DFACS-VEL",
        "TMS-Z-VEL",
        "TMS-Z-POS",
        "PLG-EXTRA-VEL",
    ] {
        assert!(
            row(id).verdict.contains("budget rejected by FAC-ADH-CAL"),
            "{id}: {}",
            row(id).verdict
        );
    }
    assert_eq!(row("FAC-SURF-REG").verdict, "compliant (method validation)");
    assert_eq!(row("CHG-V").verdict, "compliant");
    assert_eq!(m.summary.plainly_compliant, 1);
}
