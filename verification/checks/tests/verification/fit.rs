//! Traced tests of the fit family: the fit of TMMF releases is the ground evidence behind the
//! adhesion statistics of the release Monte Carlo (FAC-ADH-CAL). Synthetic releases with the
//! Monte Carlo budget's adhesion are diagnosed and fitted like campaign data: the tool must name
//! the adhesion and recover the peak pull-off `A1*lambda/e` within its reported uncertainty.

use geodesic_checks::facility::{peak_pull_off, synthetic_release};
use geodesic_facility::Scenario;
use geodesic_fit::diagnose::diagnose;
use geodesic_fit::fit::{FitOptions, Prepared, fit};
use geodesic_fit::synth::{SynthSpec, generate};
use geodesic_release::budget::Budget;

#[test]
fn campaign_fits_recover_the_peak_pull_off_of_the_monte_carlo_adhesion() {
    geodesic_core::verifies!("FAC-ADH-CAL", "FAC-FIT-QUAL");
    let budget = Budget::default_budget();
    // the budget's mean adhesion, and a strong bond near the experimental bounds (thesis:
    // A1 <= 1.5e5 N/m, lambda <= 8e-7 m)
    let cases = [
        (
            budget.adhesion.A1_n_m.mean(),
            budget.adhesion.lambda_m.mean(),
            51,
        ),
        (1.35e5, 7.5e-7, 52),
    ];
    for (a1, lambda, seed) in cases {
        let prep = synthetic_release(a1, lambda, seed).expect("synth");
        let (d, _) = diagnose(
            &prep,
            &["needle_contact", "tip_contact"],
            &FitOptions::default(),
        )
        .expect("diagnose");
        assert_eq!(
            d.missing.as_deref(),
            Some("tip_adhesion"),
            "A1 {a1}, lambda {lambda}"
        );
        let o = fit(
            &prep,
            &["needle_contact", "tip_contact", "tip_adhesion"],
            &FitOptions::default(),
        )
        .expect("fit");
        assert!(
            (o.chi2_red() - 1.0).abs() < 0.2,
            "chi2_red {}",
            o.chi2_red()
        );
        let (peak, sigma) = peak_pull_off(&o).expect("tip_adhesion fitted");
        let truth = a1 * lambda / std::f64::consts::E;
        assert!(sigma > 0.0 && sigma < 0.1 * truth, "peak {peak} +- {sigma}");
        assert!(
            (peak - truth).abs() <= 3.0 * sigma,
            "peak pull-off {peak:.4e} +- {sigma:.2e} N, truth {truth:.4e} N"
        );
    }
}

#[test]
fn diagnose_summary_snapshot() {
    // a fixed synthetic retraction with a hidden finite voltage slope: the ranking, the verdict
    // and the rounded figures are a regression snapshot of the whole pipeline
    let mut spec = SynthSpec::defaults(Scenario::RtRetraction, &["piezo", "voltage_ramp"]);
    spec.post_s = 3e-4;
    spec.seed = 61;
    let prep = Prepared::new(generate(&spec, "snap.yaml").expect("synth"));
    let (d, _) = diagnose(&prep, &["piezo"], &FitOptions::default()).expect("diagnose");
    let round = |v: f64| format!("{v:.2e}");
    let summary = serde_json::json!({
        "missing": d.missing,
        "ranking": d.candidates.iter().map(|c| c.effect.clone()).collect::<Vec<_>>(),
        "baseline_chi2_red": round(d.fit.chi2_red),
        "candidate_chi2_red": d.candidates.iter().map(|c| round(c.chi2_red)).collect::<Vec<_>>(),
        "em": d.candidates[0].params.get("voltage_ramp.em").map(|p| round(p.value)),
    });
    insta::assert_json_snapshot!(summary);
}
