//! What to measure next (`geodesic_fit::design`) on a synthetic retraction record whose truth
//! is `piezo + voltage_ramp`, against the alternative `piezo + plunger_compliance`. Asserted:
//!
//! * the expected delta BIC of the record as measured (computed without noise, from the fitted
//!   models) agrees with the delta BIC observed on the noisy record within the noise's spread
//!   (`4 sqrt(chi2)` + 5: the observed gap fluctuates by about `2 sqrt(chi2)`);
//! * halving the noise multiplies the chi-square part by exactly 4;
//! * a finer sampling of the same span does not separate them less (more samples of the same
//!   signal), and the options come best first.

use geodesic_dataset::synth::{SynthSpec, generate};
use geodesic_facility::effects::Scenario;
use geodesic_fit::design::advise;
use geodesic_fit::fit::{FitOptions, Prepared, fit};

#[test]
fn expected_separation_matches_the_record_and_scales_as_it_should() {
    let mut spec = SynthSpec::defaults(Scenario::RtRetraction, &["piezo", "voltage_ramp"]);
    spec.post_s = 3e-4;
    spec.seed = 77;
    // a fast ramp (1e10 V/s): close to the ideal step, so that the two candidates are close
    // (observed delta BIC about 17)
    spec.params.insert("voltage_ramp.em".into(), 1e10);
    let prep = Prepared::new(generate(&spec, "design.yaml").expect("synth"));
    let a = fit(&prep, &["piezo", "voltage_ramp"], &FitOptions::default()).expect("fit a");
    let opts = FitOptions {
        sigma: Some(a.sigma),
        ..Default::default()
    };
    let b = fit(&prep, &["piezo", "plunger_compliance"], &opts).expect("fit b");
    let observed = b.bic() - a.bic();
    let adv = advise(
        &prep,
        ("voltage_ramp", &a),
        ("plunger_compliance", &b),
        observed,
        &opts,
    )
    .expect("advice");
    let ln_n = (prep.dataset.t.len() as f64).ln();
    let dk = (b.n_free as f64 - a.n_free as f64) * ln_n;
    let get = |c: &str| adv.options.iter().find(|o| o.change == c).expect(c);
    let measured = get("as measured");
    let chi2 = measured.if_first_true - dk;
    assert!(chi2 >= 0.0, "{measured:?}");
    assert!(
        (observed - measured.if_first_true).abs() < 4.0 * chi2.sqrt() + 5.0,
        "observed {observed} vs expected {}",
        measured.if_first_true
    );
    let halved = get("noise halved");
    assert!(
        ((halved.if_first_true - dk) - 4.0 * chi2).abs() < 1e-9 * chi2.max(1.0),
        "{halved:?}"
    );
    let finer = get("sampling rate x2");
    assert!(finer.samples > measured.samples);
    assert!(
        finer.if_first_true - (b.n_free as f64 - a.n_free as f64) * (finer.samples as f64).ln()
            >= 0.9 * chi2,
        "{finer:?} vs {measured:?}"
    );
    for w in adv.options.windows(2) {
        assert!(w[0].separation >= w[1].separation);
    }
    assert!(adv.best.starts_with(&adv.options[0].change));
}
