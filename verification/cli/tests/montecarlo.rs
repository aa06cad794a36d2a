//! End-to-end tests of `geodesic montecarlo` and `geodesic merge` (interface.md): one JSON
//! document, the same numbers for a seed whatever the thread count, shards merged into exactly
//! the single run, and exit 2 with a one-line cause on bad input.

use serde_json::Value;
use std::process::Command;

fn geodesic(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_geodesic"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn without_seconds(json: &str) -> Value {
    let mut v: Value = serde_json::from_str(json).unwrap();
    v.as_object_mut().unwrap().remove("seconds");
    v
}

#[test]
fn same_numbers_twice_with_any_thread_count_and_merged_shards() {
    let base = ["montecarlo", "--n", "600", "--seed", "4", "--json"];
    let (c1, a, _) = geodesic(&base);
    assert_eq!(c1, 0);
    let a = without_seconds(&a);
    for k in ["n", "seed", "case", "p9973_um_s", "mean_um_s", "max_um_s"] {
        assert!(a.get(k).is_some(), "missing {k}");
    }
    let mut one = base.to_vec();
    one.extend(["--threads", "1"]);
    let (_, b, _) = geodesic(&one);
    assert_eq!(a, without_seconds(&b));

    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut parts = Vec::new();
    for i in 1..=3 {
        let p = dir.join(format!("part{i}.json")).display().to_string();
        let shard = format!("{i}/3");
        let (c, _, e) = geodesic(&[
            "montecarlo",
            "--n",
            "600",
            "--seed",
            "4",
            "--shard",
            &shard,
            "--out",
            &p,
            "--json",
        ]);
        assert_eq!(c, 0, "{e}");
        parts.push(p);
    }
    let mut merge = vec!["merge", "--json"];
    merge.extend(parts.iter().rev().map(String::as_str));
    let (c, m, e) = geodesic(&merge);
    assert_eq!(c, 0, "{e}");
    assert_eq!(a, without_seconds(&m));

    let (c, _, e) = geodesic(&["merge", &parts[0], &parts[2]]);
    assert_eq!(c, 2);
    assert!(
        e.contains("missing shard(s) 2/3") && e.lines().count() == 1,
        "{e}"
    );
}

#[test]
fn bad_input_exits_2_with_one_line() {
    for args in [
        vec!["montecarlo", "--case", "both", "--n", "10"],
        vec![
            "montecarlo",
            "--n",
            "10",
            "--shard",
            "0/2",
            "--out",
            "x.json",
        ],
        vec![
            "montecarlo",
            "--n",
            "10",
            "--budget",
            "/nonexistent/budget.yaml",
        ],
        vec!["merge", "/nonexistent/part.json"],
    ] {
        let (c, out, e) = geodesic(&args);
        assert_eq!(c, 2, "{args:?}");
        assert!(
            out.is_empty() && e.trim().lines().count() == 1,
            "{args:?}: {e}"
        );
    }
}

#[test]
fn sensitivity_prints_the_contract_groups() {
    let (code, out, err) = geodesic(&["sensitivity", "--n", "200", "--seed", "3", "--json"]);
    assert_eq!(code, 0, "{err}");
    let doc: Value = serde_json::from_str(&out).unwrap();
    let groups = doc["groups"].as_array().unwrap();
    assert_eq!(groups.len(), 7);
    for g in groups {
        for key in [
            "group",
            "first",
            "first_ci",
            "total",
            "total_ci",
            "p9973_shift_um_s",
        ] {
            assert!(g.get(key).is_some(), "{key}");
        }
    }
    let (code, _, err) = geodesic(&["sensitivity", "--n", "5"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn montecarlo_reports_the_interval_of_its_9973_point_and_the_probability_met() {
    let (code, out, err) = geodesic(&["montecarlo", "--n", "2000", "--seed", "2", "--json"]);
    assert_eq!(code, 0, "{err}");
    let doc: Value = serde_json::from_str(&out).unwrap();
    let p = doc["p9973_um_s"].as_f64().unwrap();
    let iv = doc["p9973_interval_um_s"].as_array().unwrap();
    let (lo, hi) = (iv[0].as_f64().unwrap(), iv[1].as_f64().unwrap());
    assert!(lo <= p && p <= hi && lo < hi, "{lo} {p} {hi}");
    // no draw of the built-in budget comes near 5 um/s: P(Poisson(2000 * 0.0027) >= 1)
    let pm = doc["probability_met"].as_f64().unwrap();
    assert!((pm - (1.0 - (-5.4f64).exp())).abs() < 1e-9, "{pm}");
}
