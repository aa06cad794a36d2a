//! `geodesic discover` and the `explained` field of `diagnose` on the public retraction example
//! (`data/examples/rt-plunger.yaml`: the truth is piezo + plunger_compliance): the contract's
//! keys, the missing effect added in round 1 with the residual explained, every round's fit in
//! the history that `geodesic history` reads.

mod common;
use common::{geodesic, scratch, workspace};

use serde_json::Value;

#[test]
fn discover_adds_the_plunger_and_explains_the_retraction_example() {
    let d = scratch("discover");
    let yaml = workspace().join("data/examples/rt-plunger.yaml");
    let out = geodesic(
        &[
            "discover",
            yaml.to_str().unwrap(),
            "--effects",
            "piezo",
            "--json",
            "--reports",
            "r",
        ],
        &d,
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "dataset",
        "rounds",
        "final",
        "explained",
        "reason",
        "residual",
        "thresholds",
    ] {
        assert!(doc.get(key).is_some(), "{key}");
    }
    for key in ["windows", "peaks", "correlations", "terms"] {
        assert!(doc["residual"][key].is_array(), "residual.{key}");
    }
    // the noise figure is the YAML's in every round, and the final fit says so (it said
    // `given` once: the figure discover holds for every round lost its source)
    assert_eq!(
        doc["final"]["noise_source"]["y"], "yaml",
        "{}",
        doc["final"]["noise_source"]
    );
    let rounds = doc["rounds"].as_array().unwrap();
    assert_eq!(rounds.len(), 2, "{rounds:?}");
    assert_eq!(rounds[0]["added"], Value::Null);
    assert_eq!(rounds[1]["added"], "plunger_compliance");
    for key in [
        "effects",
        "removed",
        "chi2_red",
        "rms",
        "delta_bic",
        "margin",
    ] {
        assert!(rounds[1].get(key).is_some(), "rounds[].{key}");
    }
    assert!(rounds[1]["delta_bic"].as_f64().unwrap() < -10.0);
    assert_eq!(doc["explained"], Value::Bool(true), "{}", doc["reason"]);
    assert!(doc["final"]["chi2_red"].as_f64().unwrap() < 1.2);
    // the ledger is in the fit history
    let hist = geodesic(
        &[
            "history",
            yaml.to_str().unwrap(),
            "--reports",
            "r",
            "--json",
        ],
        &d,
    );
    let h = String::from_utf8_lossy(&hist.stdout);
    assert!(h.contains("plunger_compliance"), "{h}");
    // diagnose keeps its fields and adds `explained`
    let out = geodesic(
        &[
            "diagnose",
            yaml.to_str().unwrap(),
            "--effects",
            "piezo",
            "--json",
            "--reports",
            "r",
        ],
        &d,
    );
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["missing"], "plunger_compliance");
    assert_eq!(doc["explained"], Value::Bool(true));
}

#[test]
fn fit_posterior_holds_the_truth_of_the_example() {
    // interface.md: `fit ... --posterior --json` adds posterior.PARAM.{median, lo68, hi68,
    // lo95, hi95}; on the public example every true parameter lies inside its 95 % interval and
    // the intervals are ordered
    let d = common::scratch("posterior");
    let ws = common::workspace();
    let yaml = ws.join("data/examples/tmmf-adhesion.yaml");
    let out = common::geodesic(
        &[
            "fit",
            yaml.to_str().unwrap(),
            "--effects",
            "needle_contact,tip_contact,tip_adhesion",
            "--posterior",
            "--json",
            "--reports",
            "r",
        ],
        &d,
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let truth: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(ws.join("data/examples/tmmf-adhesion.truth.json")).unwrap(),
    )
    .unwrap();
    let post = doc["posterior"].as_object().unwrap();
    assert_eq!(post.len(), 5);
    for (name, p) in post {
        let g = |k: &str| p[k].as_f64().unwrap();
        assert!(g("lo95") <= g("lo68") && g("lo68") <= g("median"));
        assert!(g("median") <= g("hi68") && g("hi68") <= g("hi95"));
        let t = truth["params"][name].as_f64().unwrap();
        assert!(g("lo95") <= t && t <= g("hi95"), "{name}: {t} outside 95 %");
    }
}

#[test]
fn fit_posterior_ensemble_writes_flags_and_a_corner_plot() {
    // `--posterior-method ensemble`: the contract's keys plus the sampler's flags, the method
    // with its walkers and acceptance, a corner plot naming every free parameter; a bad method
    // or step count is exit 2 (the sampler's accuracy is tested in geodesic-fit)
    let d = common::scratch("posterior-ensemble");
    let ws = common::workspace();
    let yaml = ws.join("data/examples/rt-plunger.yaml");
    let run = |extra: &[&str]| {
        let mut a = vec![
            "fit",
            yaml.to_str().unwrap(),
            "--effects",
            "piezo,plunger_compliance",
            "--posterior",
            "--json",
            "--reports",
            "r",
            "--fix",
            "piezo.m=9e-4",
        ];
        a.extend_from_slice(extra);
        common::geodesic(&a, &d)
    };
    let out = run(&["--posterior-method", "ensemble", "--posterior-steps", "150"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let post = doc["posterior"].as_object().unwrap();
    assert!(!post.is_empty());
    for (name, p) in post {
        for k in ["median", "lo68", "hi68", "lo95", "hi95"] {
            assert!(p[k].as_f64().is_some(), "{name}.{k}");
        }
        assert!(p["prior_limited"].is_boolean() && p["multimodal"].is_boolean());
        assert!(p["autocorr_steps"].as_f64().unwrap() >= 1.0, "{name}: {p}");
        assert!(p["converged"].is_boolean(), "{name}: {p}");
    }
    let m = &doc["posterior_method"];
    assert_eq!(m["method"], "ensemble");
    assert!(m["acceptance"].as_f64().unwrap() > 0.0);
    // 150 steps, a third burnt: 100 kept; the run converged only if every parameter did
    assert_eq!(m["kept_steps_per_walker"], 100);
    let all = post.values().all(|p| p["converged"] == true);
    assert_eq!(m["converged"], all);
    let svg = std::fs::read_to_string(d.join(m["corner_svg"].as_str().unwrap())).unwrap();
    for name in post.keys() {
        assert!(svg.contains(name.as_str()), "corner plot lacks {name}");
    }
    assert_eq!(run(&["--posterior-method", "mcmc"]).status.code(), Some(2));
    assert_eq!(
        run(&["--posterior-method", "ensemble", "--posterior-steps", "5"])
            .status
            .code(),
        Some(2)
    );
}
