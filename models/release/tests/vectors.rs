//! The eight reference releases of `testdata/release-vectors.json` (copied from the project
//! spec; an independent DOP853 implementation at rtol 1e-12): the fast and the reference
//! integrators must each match every case within 0.5 % or 0.001 um/s.

use geodesic_mechanism::PiezoParams;
use geodesic_release::expgauss::ExpGauss;
use geodesic_release::inputs::ReleaseInputs;
use geodesic_release::integrator::{DormandPrince, Integrator, Rk4Fixed};
use serde_json::Value;

fn mech(v: &Value) -> PiezoParams {
    let g = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("mech.{k}"));
    PiezoParams {
        r_ohm: g("R"),
        m_kg: g("m"),
        ca_f: g("Ca"),
        k_n_m: g("k"),
        kg_n_m: g("Kg"),
        b_ns_m: g("b"),
        mg_kg: g("Mg"),
        t_c_m: g("T"),
    }
}

/// Reads the cases: (label, inputs, v_um_s, t_end_us).
pub fn cases() -> Vec<(String, ReleaseInputs, f64, f64)> {
    let text = include_str!("../testdata/release-vectors.json");
    let doc: Value = serde_json::from_str(text).unwrap();
    doc["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let mut r = ReleaseInputs::nominal();
            let inp = c["inputs"].as_object().unwrap();
            for (k, v) in inp {
                match k.as_str() {
                    "mech1" => r.mech[0] = mech(v),
                    "mech2" => r.mech[1] = mech(v),
                    "A1_1" => r.a1_n_m[0] = v.as_f64().unwrap(),
                    "A1_2" => r.a1_n_m[1] = v.as_f64().unwrap(),
                    "lam_1" => r.lambda_m[0] = v.as_f64().unwrap(),
                    "lam_2" => r.lambda_m[1] = v.as_f64().unwrap(),
                    "em1" => r.em_v_s[0] = v.as_f64().unwrap(),
                    "em2" => r.em_v_s[1] = v.as_f64().unwrap(),
                    "Rt1" => r.tip_radius_m[0] = v.as_f64().unwrap(),
                    "Rt2" => r.tip_radius_m[1] = v.as_f64().unwrap(),
                    "F0" => r.preload_n = v.as_f64().unwrap(),
                    other => panic!("unknown input {other}"),
                }
            }
            (
                c["label"].as_str().unwrap().to_string(),
                r,
                c["v_um_s"].as_f64().unwrap(),
                c["t_end_us"].as_f64().unwrap(),
            )
        })
        .collect()
}

fn check<I: Integrator>(integ: &I) {
    let mut failures = Vec::new();
    for (label, r, v_ref, t_ref) in cases() {
        let out = r.simulate(integ).unwrap();
        let v = out.v_tm_m_s * 1e6;
        let tol = (0.005 * v_ref.abs()).max(0.001);
        eprintln!(
            "{:<55} v = {v:+.6} um/s (ref {v_ref:+.6}), t_end = {:.2} us (ref {t_ref:.2}), {:?}",
            label,
            out.t_end_s * 1e6,
            out.stats
        );
        assert!(!out.fallback_stop, "{label}: fallback stop");
        if (v - v_ref).abs() > tol {
            failures.push(format!("{label}: {v} vs {v_ref}"));
        }
    }
    assert!(
        failures.is_empty(),
        "{} with {}: {failures:#?}",
        "vectors",
        integ.name()
    );
}

#[test]
fn exponential_collocation_matches_reference_vectors() {
    let mut failures = Vec::new();
    for (label, r, v_ref, t_ref) in cases() {
        let out = r
            .model()
            .simulate_expgauss(&ExpGauss::fast())
            .expect("the piezo mechanism gives its modes")
            .unwrap();
        let v = out.v_tm_m_s * 1e6;
        let tol = (0.005 * v_ref.abs()).max(0.001);
        eprintln!(
            "{:<55} v = {v:+.6} um/s (ref {v_ref:+.6}), t_end = {:.2} us (ref {t_ref:.2}), {:?}",
            label,
            out.t_end_s * 1e6,
            out.stats
        );
        assert!(!out.fallback_stop, "{label}: fallback stop");
        if (v - v_ref).abs() > tol {
            failures.push(format!("{label}: {v} vs {v_ref}"));
        }
    }
    assert!(failures.is_empty(), "expgauss: {failures:#?}");
}

#[test]
fn fast_integrator_matches_reference_vectors() {
    check(&DormandPrince::fast());
}

#[test]
fn reference_integrator_matches_reference_vectors() {
    check(&DormandPrince::reference());
}

#[test]
fn fixed_step_rk4_matches_reference_vectors() {
    check(&Rk4Fixed { h: 2e-9 });
}
