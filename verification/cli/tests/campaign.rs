//! `geodesic synth --campaign` and `geodesic campaign` end to end on a synthetic campaign of 8
//! short TMMF releases drawn from a known adhesion population (issue 14). Asserted: the
//! contract's keys; no release skipped; each release's A1 and lambda within 4 sigma of its truth;
//! the population mean of A1 and lambda within 3 `mean_sigma` of the mean of the drawn values;
//! P_x from the model and from the data agree within their spread; the correlation's interval
//! holds its estimate; the page (Markdown table, JSON, histograms, adhesion scatter) is written
//! under reports/campaign; a bad release is reported with its file and exit 2.

mod common;
use common::{geodesic, scratch};

use serde_json::Value;

/// Traced to REL-GPRM-VEL (issue 14, item 5): the flight prediction made from a campaign of
/// measured releases meets the requirement's limit over its whole identification interval, and
/// that interval holds the independent reference (the Monte Carlo of the population the campaign
/// sampled, from the truth file).
#[test]
fn a_synthetic_campaign_recovers_its_population() {
    geodesic_core::verifies!("REL-GPRM-VEL");
    let d = scratch("campaign");
    succeeds(
        &[
            "synth",
            "--campaign",
            "8",
            "--out",
            "camp",
            "--seed",
            "4",
            "-q",
        ],
        &d,
    );
    let out = succeeds(
        &[
            "campaign",
            "camp/campaign.yaml",
            "--effects",
            "needle_contact,tip_contact,tip_adhesion",
            "--json",
        ],
        &d,
    );
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    let truth: Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("camp/truth.json")).unwrap()).unwrap();
    assert_eq!(doc["releases"].as_array().unwrap().len(), 8);
    assert!(doc["failed"].as_array().unwrap().is_empty());
    table_is_whole(&doc);
    population_recovered(&doc, &truth);
    page_written(&d, &out.stdout);
    // closing the loop (issue 14 item 3)
    std::fs::write(d.join("campaign.json"), &out.stdout).unwrap();
    monte_carlo_holds_the_sampled_population(&d, &truth);
    a_damaged_release_is_reported(&d);
}

/// Runs geodesic in `d` and asserts exit 0 (stderr shown otherwise).
fn succeeds(args: &[&str], d: &std::path::Path) -> std::process::Output {
    let out = geodesic(args, d);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The table's statistics of P_x, F_peak and dt, and P_x from the model and from the data in
/// agreement within their spread.
fn table_is_whole(doc: &Value) {
    for key in ["P_x_kg_m_s", "F_peak_N", "dt_s"] {
        for stat in ["mean", "sd", "sd_mean", "min", "max"] {
            assert!(
                doc["table"][key]["model"][stat].as_f64().is_some(),
                "{key}.{stat}"
            );
        }
    }
    let px = &doc["table"]["P_x_kg_m_s"];
    let (pm, pd) = (
        px["model"]["mean"].as_f64().unwrap(),
        px["data"]["mean"].as_f64().unwrap(),
    );
    assert!(
        (pm - pd).abs() < px["model"]["sd"].as_f64().unwrap(),
        "P_x model {pm} data {pd}"
    );
}

/// Each release's A1 and lambda within 4 sigma of its truth; the population mean within 3
/// `mean_sigma` of the mean of the drawn values; the correlation's bootstrap interval holds
/// the estimate.
fn population_recovered(doc: &Value, truth: &Value) {
    let releases = doc["releases"].as_array().unwrap();
    for name in ["tip_adhesion.A1", "tip_adhesion.lambda"] {
        let mut drawn = Vec::new();
        for r in releases {
            let file = r["file"].as_str().unwrap();
            let t = truth["releases"]
                .as_array()
                .unwrap()
                .iter()
                .find(|t| file.ends_with(t["file"].as_str().unwrap()))
                .unwrap();
            let want = t[name].as_f64().unwrap();
            let got = r["params"][name]["value"].as_f64().unwrap();
            let sigma = r["params"][name]["sigma"].as_f64().unwrap();
            assert!(
                (got - want).abs() < 4.0 * sigma,
                "{file} {name}: {got} +- {sigma} vs {want}"
            );
            drawn.push(want);
        }
        let p = &doc["population"][name];
        for key in ["mean", "mean_sigma", "sd", "sd_sigma"] {
            assert!(p[key].as_f64().is_some(), "population.{name}.{key}");
        }
        let mean_drawn = drawn.iter().sum::<f64>() / drawn.len() as f64;
        let (m, s) = (
            p["mean"].as_f64().unwrap(),
            p["mean_sigma"].as_f64().unwrap(),
        );
        assert!(
            (m - mean_drawn).abs() < 3.0 * s,
            "{name}: {m} +- {s} vs drawn mean {mean_drawn}"
        );
    }
    assert!(doc["population"]["correlation"].is_object());
    // the correlation's bootstrap interval holds the estimate
    let key = "tip_adhesion.A1~tip_adhesion.lambda";
    if let Some(r) = doc["population"]["correlation"][key].as_f64() {
        let ci = &doc["correlation_ci95"][key];
        let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
        assert!(
            lo <= r && r <= hi && -1.0 <= lo && hi <= 1.0,
            "{r} in [{lo}, {hi}]"
        );
    }
}

/// The page: written whole under reports/campaign, the JSON identical to `stdout`, the table
/// in the thesis's form, every release listed, both plots with their legends.
fn page_written(d: &std::path::Path, stdout: &[u8]) {
    let page = d.join("reports/campaign");
    let json = std::fs::read(page.join("campaign.json")).unwrap();
    assert_eq!(
        String::from_utf8_lossy(&json).trim(),
        String::from_utf8_lossy(stdout).trim()
    );
    let md = std::fs::read_to_string(page.join("campaign.md")).unwrap();
    for want in [
        "| quantity | unit | source | mean | sd | sd of the mean | min | max |",
        "| P_x_kg_m_s | kg m/s | model |",
        "| tip_adhesion.A1 | N/m |",
        "A1-lambda correlation",
        "![adhesion.svg](adhesion.svg)",
    ] {
        assert!(md.contains(want), "campaign.md lacks {want}");
    }
    assert_eq!(md.matches("| camp/release-").count(), 8);
    let svg = std::fs::read_to_string(page.join("adhesion.svg")).unwrap();
    assert!(svg.contains("population 1-sigma") && svg.contains("error ellipse"));
    let svg = std::fs::read_to_string(page.join("histograms.svg")).unwrap();
    assert!(svg.contains("from the fitted model") && svg.contains("from the data"));
}

/// `geodesic montecarlo --n 4000 --seed 3 --json` in `d` with `args`, exit 0, its JSON.
fn montecarlo(d: &std::path::Path, args: &[&str]) -> Value {
    let mut a = vec!["montecarlo", "--n", "4000", "--seed", "3", "--json", "-q"];
    a.extend_from_slice(args);
    serde_json::from_slice(&succeeds(&a, d).stdout).unwrap()
}

/// The Monte Carlo takes its adhesion from the campaign (`d/campaign.json`); its 99.73 %
/// interval, which carries the identification uncertainty, holds the 99.73 % point of the
/// population the campaign actually sampled (the drawn values' mean and spread, from `truth`)
/// and meets REL-GPRM-VEL's limit; the budget key `adhesion_from` does the same as the flag.
fn monte_carlo_holds_the_sampled_population(d: &std::path::Path, truth: &Value) {
    let est = montecarlo(
        d,
        &[
            "--adhesion-from",
            "campaign.json",
            "--population-draws",
            "12",
        ],
    );
    let iv: Vec<f64> = est["p9973_interval_um_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        est["uncertainty"]
            .as_str()
            .unwrap()
            .contains("identification")
    );
    assert!((0.0..=1.0).contains(&est["probability_met"].as_f64().unwrap()));
    let moments = |name: &str| {
        let v: Vec<f64> = truth["releases"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t[name].as_f64().unwrap())
            .collect();
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let sd = (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt();
        serde_json::json!({"mean": m, "mean_sigma": 0.0, "sd": sd, "sd_sigma": 0.0})
    };
    let sample = serde_json::json!({"population": {
        "tip_adhesion.A1": moments("tip_adhesion.A1"),
        "tip_adhesion.lambda": moments("tip_adhesion.lambda")}});
    std::fs::write(d.join("sample.json"), sample.to_string()).unwrap();
    let p = montecarlo(
        d,
        &["--adhesion-from", "sample.json", "--population-draws", "1"],
    )["p9973_um_s"]
        .as_f64()
        .unwrap();
    // p inside [lo, hi]: |midpoint - p| <= half-width
    geodesic_core::trace::assert_reference_abs(
        "REL-GPRM-VEL",
        "the sampled population's 99.73 % point [um/s] inside the identification interval",
        0.5 * (iv[0] + iv[1]),
        p,
        0.5 * (iv[1] - iv[0]),
    );
    geodesic_core::trace::assert_limit("REL-GPRM-VEL", iv[1] * 1e-6);
    // the budget key does the same as the flag
    let budget = format!(
        "{}\nadhesion_from: campaign.json\n",
        geodesic_release::budget::DEFAULT_BUDGET_YAML.trim_end()
    );
    std::fs::write(d.join("b.yaml"), budget).unwrap();
    let via_key = montecarlo(d, &["--budget", "b.yaml", "--population-draws", "12"]);
    assert_eq!(via_key["p9973_um_s"], est["p9973_um_s"]);
    assert_eq!(via_key["p9973_interval_um_s"], est["p9973_interval_um_s"]);
}

/// A damaged release: reported with its file, the others still fitted, exit 2.
fn a_damaged_release_is_reported(d: &std::path::Path) {
    std::fs::write(d.join("camp/release-003.csv"), "t,x,y\n0,1\n").unwrap();
    let out = geodesic(
        &[
            "campaign",
            "camp",
            "--effects",
            "needle_contact,tip_contact,tip_adhesion",
            "--json",
        ],
        d,
    );
    assert_eq!(out.status.code(), Some(2));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["releases"].as_array().unwrap().len(), 7);
    let failed = doc["failed"].as_array().unwrap();
    assert_eq!(failed.len(), 1);
    assert!(
        failed[0]["file"]
            .as_str()
            .unwrap()
            .ends_with("release-003.yaml")
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("release-003"));
}

#[test]
fn verify_takes_the_adhesion_of_a_budgets_campaign() {
    // a budget naming a campaign result: every check sees the campaign's adhesion (here a
    // population far weaker than the built-in budget's), and a missing campaign file is exit 2
    // with nothing written
    let d = scratch("verify-campaign");
    let ws = common::workspace();
    std::fs::create_dir_all(d.join("reqs")).unwrap();
    for f in ["release.yaml", "tm-state.yaml"] {
        std::fs::copy(ws.join("requirements").join(f), d.join("reqs").join(f)).unwrap();
    }
    let pop = serde_json::json!({"population": {
        "tip_adhesion.A1": {"mean": 2.0e4, "mean_sigma": 2.0e3, "sd": 5.0e3, "sd_sigma": 1.0e3},
        "tip_adhesion.lambda": {"mean": 3.0e-7, "mean_sigma": 2.0e-8, "sd": 5.0e-8, "sd_sigma": 1.0e-8}}});
    std::fs::write(d.join("weak.json"), pop.to_string()).unwrap();
    let budget = |camp: &str| {
        format!(
            "{}\nadhesion_from: {camp}\n",
            geodesic_release::budget::DEFAULT_BUDGET_YAML.trim_end()
        )
    };
    std::fs::write(d.join("b.yaml"), budget("weak.json")).unwrap();
    std::fs::write(d.join("missing.yaml"), budget("nowhere.json")).unwrap();
    let run = |b: Option<&str>, reports: &str| {
        let mut a = vec![
            "verify",
            "--requirements",
            "reqs",
            "--mc-n",
            "2000",
            "--no-fidelity",
            "--json",
            "--reports",
            reports,
        ];
        if let Some(b) = b {
            a.extend_from_slice(&["--budget", b]);
        }
        geodesic(&a, &d)
    };
    let value = |o: &std::process::Output| -> f64 {
        let doc: Value = serde_json::from_slice(&o.stdout).unwrap();
        doc["requirements"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["id"] == "REL-GPRM-VEL")
            .unwrap()["value"]
            .as_f64()
            .unwrap()
    };
    let base = run(None, "r1");
    let weak = run(Some("b.yaml"), "r2");
    assert_eq!(
        weak.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&weak.stderr)
    );
    assert!(
        value(&weak) < 0.5 * value(&base),
        "{} vs {}",
        value(&weak),
        value(&base)
    );
    // REL-GPRM-VEL states its uncertainty: sampling only with the budget's own adhesion, the
    // campaign's identification too with adhesion_from
    let inputs = |o: &std::process::Output| -> Value {
        let doc: Value = serde_json::from_slice(&o.stdout).unwrap();
        let row = doc["requirements"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["id"] == "REL-GPRM-VEL")
            .unwrap()
            .clone();
        row["evidence"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["check"] == "release-montecarlo")
            .unwrap()["inputs"]
            .clone()
    };
    let (bi, wi) = (inputs(&base), inputs(&weak));
    assert!(
        bi["uncertainty"]
            .as_str()
            .unwrap()
            .contains("sampling only"),
        "{bi}"
    );
    assert!(
        wi["uncertainty"]
            .as_str()
            .unwrap()
            .contains("identification"),
        "{wi}"
    );
    let iv = wi["p9973_interval_um_s"].as_array().unwrap();
    let (lo, hi) = (iv[0].as_f64().unwrap(), iv[1].as_f64().unwrap());
    assert!(lo < hi && (0.0..=1.0).contains(&wi["probability_met"].as_f64().unwrap()));
    let bad = run(Some("missing.yaml"), "r3");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("nowhere.json"));
    assert!(!d.join("r3").exists());
}
