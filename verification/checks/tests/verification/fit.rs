//! Traced tests of the fit family: the fit of TMMF releases is the ground evidence behind the
//! adhesion statistics of the release Monte Carlo. Synthetic releases with the Monte Carlo
//! budget's adhesion, simulated by a truth model that is not the fitted one, are diagnosed and
//! fitted like campaign data: the tool must name the adhesion, and its reported uncertainty of
//! the peak pull-off `A1*lambda/e` must cover the truth as often as FAC-FIT-QUAL requires.

use geodesic_checks::facility::{
    FULL, TruthModel, coverage, coverages, peak_pull_off, synthetic_release_with,
};
use geodesic_dataset::synth::{SynthSpec, generate};
use geodesic_discover::diagnose::diagnose;
use geodesic_facility::Scenario;
use geodesic_fit::fit::{FitOptions, Prepared, fit};
use geodesic_release::budget::Budget;

/// Releases of the test's coverage study (the check uses 32).
const TEST_RELEASES: usize = 12;

/// FAC-FIT-QUAL on a smaller study than the check's: diagnose names `tip_adhesion` on a strong
/// bond near the thesis's bounds (truth oversampled, with an unmodelled drift), the completed fit
/// is at chi2_red 1 within 0.2 and recovers the peak pull-off within 3 sigma; then the 2-sigma
/// coverage of the peak pull-off over 12 releases drawn from the budget (seed 21) meets the
/// requirement's own limit. With a true coverage of 95.4 % the chance that fewer than 10 of 12
/// are covered is 1.6 %; the seed is fixed, so the outcome is deterministic.
#[test]
fn adhesion_identification_names_the_adhesion_and_covers_the_truth() {
    geodesic_core::verifies!("FAC-FIT-QUAL");
    let (a1, lambda) = (1.35e5, 7.5e-7);
    let prep = synthetic_release_with(a1, lambda, 52, TruthModel::DIFFERENT).expect("synth");
    let (d, _) = diagnose(
        &prep,
        &["needle_contact", "tip_contact"],
        &FitOptions::default(),
    )
    .expect("diagnose");
    assert_eq!(d.missing.as_deref(), Some("tip_adhesion"));
    let o = fit(&prep, &FULL, &FitOptions::default()).expect("fit");
    assert!(
        (o.chi2_red() - 1.0).abs() < 0.2,
        "chi2_red {}",
        o.chi2_red()
    );
    let (peak, sigma) = peak_pull_off(&o).expect("tip_adhesion fitted");
    let truth = a1 * lambda / std::f64::consts::E;
    assert!(
        (peak - truth).abs() <= 3.0 * sigma,
        "peak pull-off {peak:.4e} +- {sigma:.2e} N, truth {truth:.4e} N"
    );

    let started = std::time::Instant::now();
    let opts = FitOptions {
        profile: true,
        ..FitOptions::default()
    };
    let rel = coverage(
        &Budget::default_budget().adhesion,
        TEST_RELEASES,
        21,
        TruthModel::DIFFERENT,
        &opts,
    );
    let z: Vec<f64> = rel.iter().map(|r| r.z_peak).collect();
    let c = coverages(&z);
    eprintln!(
        "coverage of {} releases in {:.1} s: 1/2/3 sigma {c:?}, z {z:.2?}",
        rel.len(),
        started.elapsed().as_secs_f64()
    );
    geodesic_core::trace::assert_limit("FAC-FIT-QUAL", c[1]);
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
