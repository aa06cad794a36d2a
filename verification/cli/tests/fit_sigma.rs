//! Issue 48: a needle-body fit reported every free parameter with sigma 0 (a symmetry check
//! that took a parameter on its bound for nine directions of the others). The command,
//! end to end: `synth` of a heavy TM at high preload with a damped needle body, then `fit` with
//! the right model. Every free parameter has a positive sigma with its truth within 3 sigma, or
//! is reported unresolved (no sigma); `symmetries` lists each direction once. The truth is the
//! `synth` command's own parameters (its `.truth.json`), not the fit's.

mod common;
use common::{geodesic, scratch};
use serde_json::Value;

#[test]
fn a_needle_body_fit_has_no_zero_sigma_and_covers_its_truth() {
    let dir = scratch("needle-body-sigma");
    let synth = geodesic(
        &[
            "synth",
            "--scenario",
            "tmmf-release",
            "--effects",
            "needle_contact,tip_contact,tip_adhesion,needle_mass",
            "--param",
            "needle_contact.F_pre=0.3",
            "--param",
            "tip_contact.k_c=4e6",
            "--param",
            "tip_adhesion.A1=7e4",
            "--param",
            "tip_adhesion.lambda=3.5e-7",
            "--param",
            "needle_mass.m_nd=0.5",
            "--param",
            "needle_mass.k_nd=1.12e6",
            "--param",
            "needle_mass.k_tm=2.03e6",
            "--param",
            "needle_mass.c_nd=20",
            "--param",
            "needle_mass.c_tm=5",
            "--known",
            "m=0.844",
            "--fs",
            "2e5",
            "--pre",
            "0.001",
            "--post",
            "0.009",
            "--seed",
            "5",
            "--out",
            "nm/nm.yaml",
        ],
        &dir,
    );
    assert!(
        synth.status.success(),
        "{}",
        String::from_utf8_lossy(&synth.stderr)
    );
    let fit = geodesic(
        &[
            "fit",
            "nm/nm.yaml",
            "--effects",
            "needle_contact,tip_contact,tip_adhesion,needle_mass",
            "--json",
        ],
        &dir,
    );
    assert!(
        fit.status.success(),
        "{}",
        String::from_utf8_lossy(&fit.stderr)
    );
    let v: Value = serde_json::from_slice(&fit.stdout).unwrap();
    let truth: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("nm/nm.truth.json")).unwrap())
            .unwrap();
    let mut bad = Vec::new();
    let mut resolved = 0;
    for (name, p) in v["params"].as_object().unwrap() {
        if p["fixed"] == true {
            continue;
        }
        let value = p["value"].as_f64().unwrap();
        match p["sigma"].as_f64() {
            Some(s) if s > 0.0 && s.is_finite() => {
                resolved += 1;
                let t = truth["params"][name].as_f64().unwrap();
                if (value - t).abs() > 3.0 * s {
                    bad.push(format!(
                        "{name}: {value:e} +- {s:e}, truth {t:e} ({:.1} sigma)",
                        (value - t).abs() / s
                    ));
                }
            }
            Some(s) => bad.push(format!("{name}: sigma {s:e}")),
            None => assert_eq!(p["resolved"], false, "{name}: no sigma, yet resolved"),
        }
    }
    // each unresolved direction once (unit vectors: two along one direction have |dot| ~ 1)
    let dirs: Vec<&serde_json::Map<String, Value>> = v["symmetries"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|s| s["direction"].as_object())
        .collect();
    for (i, a) in dirs.iter().enumerate() {
        for b in &dirs[..i] {
            let dot: f64 = a
                .iter()
                .map(|(k, x)| x.as_f64().unwrap() * b.get(k).and_then(Value::as_f64).unwrap_or(0.0))
                .sum();
            assert!(
                dot.abs() < 0.999,
                "two symmetries along one direction: {a:?}"
            );
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
    // the record resolves the preload, the tip's stiffness and the body's stiffnesses at least
    assert!(resolved >= 4, "only {resolved} resolved: {}", v["params"]);
}
