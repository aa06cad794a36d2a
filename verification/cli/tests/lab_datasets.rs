//! Lab-style variants of the public retraction example (`data/examples/lab/`, written by its
//! `make.py` from `data/examples/rt-plunger.*`): time in us, the tip in um under the lab's
//! column name, comment lines; one with an empty cell, one with a wild sample, one with a typo
//! in a key. Each gives the plain record's answer or a one-line refusal naming file, line and
//! the fix; the wild sample is named by its line and the residual is never reported white.

mod common;
use common::{geodesic, scratch, workspace};

use serde_json::Value;

/// `geodesic fit DATASET --effects piezo,plunger_compliance --json ARGS`: (exit, JSON, stderr).
fn fit(dataset: &str, args: &[&str]) -> (Option<i32>, Option<Value>, String) {
    let d = scratch("fit");
    let yaml = workspace().join(dataset);
    let mut a = vec![
        "fit",
        yaml.to_str().unwrap(),
        "--effects",
        "piezo,plunger_compliance",
        "--json",
        "--reports",
        "r",
    ];
    a.extend_from_slice(args);
    let out = geodesic(&a, &d);
    (
        out.status.code(),
        serde_json::from_slice(&out.stdout).ok(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

/// Every parameter of `b` within `k` of the larger reported sigma of `a`'s and `b`'s.
fn same_answer(a: &Value, b: &Value, k: f64) {
    let (pa, pb) = (
        a["params"].as_object().unwrap(),
        b["params"].as_object().unwrap(),
    );
    assert_eq!(pa.len(), pb.len());
    for (name, x) in pa {
        let y = &pb[name];
        let (vx, vy) = (x["value"].as_f64().unwrap(), y["value"].as_f64().unwrap());
        let s = x["sigma"]
            .as_f64()
            .unwrap()
            .max(y["sigma"].as_f64().unwrap());
        assert!(
            (vx - vy).abs() <= k * s,
            "{name}: {vx} against {vy} (sigma {s})"
        );
    }
    let (ca, cb) = (
        a["chi2_red"].as_f64().unwrap(),
        b["chi2_red"].as_f64().unwrap(),
    );
    assert!((ca - cb).abs() < 0.01, "chi2_red {ca} against {cb}");
}

#[test]
fn lab_variants_give_the_plain_records_answer_or_a_refusal_with_line_and_fix() {
    let (code, plain, err) = fit("data/examples/rt-plunger.yaml", &[]);
    assert_eq!(code, Some(0), "{err}");
    let plain = plain.unwrap();
    assert_eq!(plain["residual_white"], true);
    assert!(plain.get("outliers").is_none() && plain.get("warnings").is_none());

    // us, um, a named column, comments: the same bits, so the same fit to the last digit
    let (code, lab, err) = fit("data/examples/lab/rt-plunger-lab.yaml", &[]);
    assert_eq!(code, Some(0), "{err}");
    let lab = lab.unwrap();
    assert!(err.is_empty(), "no warning: {err}");
    for key in [
        "params",
        "chi2_red",
        "rms",
        "noise",
        "residual_white",
        "n_samples",
    ] {
        assert_eq!(lab[key], plain[key], "{key}");
    }

    // one empty cell: that row skipped, counted and named; the same answer
    let (code, missing, err) = fit("data/examples/lab/rt-plunger-missing.yaml", &[]);
    assert_eq!(code, Some(0), "{err}");
    let missing = missing.unwrap();
    assert_eq!(
        missing["n_samples"].as_u64().unwrap() + 1,
        plain["n_samples"].as_u64().unwrap()
    );
    assert!(
        err.contains("rt-plunger-missing.csv:402:") && err.contains("1 row skipped"),
        "{err}"
    );
    same_answer(&plain, &missing, 0.5);
    // refused under --strict, at its line, saying what to do
    let (code, _, err) = fit("data/examples/lab/rt-plunger-missing.yaml", &["--strict"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("rt-plunger-missing.csv:402:") && err.contains("fill it in"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");

    // one wild sample (1e18 m): excluded and named by its line, never a white residual
    let (code, wild, err) = fit("data/examples/lab/rt-plunger-wild.yaml", &[]);
    assert_eq!(code, Some(0), "{err}");
    let wild = wild.unwrap();
    assert!(
        err.contains("rt-plunger-wild.csv:302:") && err.contains("wild sample"),
        "{err}"
    );
    assert_eq!(wild["residual_white"], false);
    let o = &wild["outliers"][0];
    assert_eq!(
        (o["line"].as_u64(), o["excluded"].as_bool()),
        (Some(302), Some(true))
    );
    assert!(o["robust_sigma"].as_f64().unwrap() > 1e20);
    same_answer(&plain, &wild, 0.5);
    let (code, _, err) = fit("data/examples/lab/rt-plunger-wild.yaml", &["--strict"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("rt-plunger-wild.csv:302:"), "{err}");

    // a typo in a key: refused at its line with the nearest key
    let (code, _, err) = fit("data/examples/lab/rt-plunger-typo.yaml", &[]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("rt-plunger-typo.yaml:13:") && err.contains("did you mean `noise`"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

#[test]
fn diagnose_of_the_wild_record_names_the_missing_effect_and_flags_the_sample() {
    let d = scratch("diagnose");
    let yaml = workspace().join("data/examples/lab/rt-plunger-wild.yaml");
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
    assert_eq!(out.status.code(), Some(0));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["missing"], "plunger_compliance");
    assert_eq!(doc["fit"]["residual_white"], false);
    assert_eq!(doc["fit"]["outliers"][0]["line"], 302);
    // one history row per model version: a second diagnose adds none
    geodesic(
        &[
            "diagnose",
            yaml.to_str().unwrap(),
            "--effects",
            "piezo",
            "--reports",
            "r",
        ],
        &d,
    );
    let h = std::fs::read_to_string(d.join("r/fits/rt-plunger-wild.history.jsonl")).unwrap();
    assert_eq!(h.lines().count(), 1, "{h}");
}
