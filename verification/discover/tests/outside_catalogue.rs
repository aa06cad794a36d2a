//! Physics outside the catalogue (issue 13): records whose missing physics no effect of the
//! catalogue holds. A synthetic truth from the catalogue gets one extra term added to its
//! fitted channel to first order (the response of a small force, a delay, a creep, a slip or a
//! vibration), then the same seeded noise as the plain record. Each test asserts:
//!
//! * `explained` is false and no round names a catalogue effect as added;
//! * the description's leading term is the right kind, acting on the right state variable, with
//!   its parameter (frequency, damping rate, delay, time constant, time of the jump) near the
//!   injected one.

use geodesic_dataset::Dataset;
use geodesic_dataset::synth::{SynthSpec, generate};
use geodesic_discover::discover::{DiscoverOptions, DiscoverReport, describe, discover};
use geodesic_facility::Model;
use geodesic_facility::effects::Scenario;
use geodesic_fit::fit::{FitOptions, FitReport, MAX_STARTS, Prepared, default_starts, fit_model};

const TMMF: [&str; 3] = ["needle_contact", "tip_contact", "tip_adhesion"];
const RT: [&str; 2] = ["piezo", "plunger_compliance"];

fn spec(s: Scenario, truth: &[&str], seed: u64) -> SynthSpec {
    let mut spec = SynthSpec::defaults(s, truth);
    spec.seed = seed;
    if s == Scenario::RtRetraction {
        spec.post_s = 5e-4;
    } else {
        // the public example's span (1 ms before the trigger, 8 ms after) at 50 kHz: 451
        // samples, so that each test runs in seconds
        spec.fs_hz = 5e4;
    }
    spec
}

/// The noisy record, its noiseless truth of the fitted channel and the channel's name.
fn pair(spec: &SynthSpec) -> (Dataset, Vec<f64>, &'static str) {
    let ds = generate(spec, "outside.yaml").expect("synth");
    let mut quiet = spec.clone();
    for v in quiet.noise.values_mut() {
        *v = 1e-30;
    }
    let truth = generate(&quiet, "quiet.yaml").expect("synth");
    let ch = if ds.scenario == Scenario::TmmfRelease {
        "x"
    } else {
        "y"
    };
    let x = truth.channels[ch].clone();
    (ds, x, ch)
}

/// Cumulative integral from the trigger (trapezoids).
fn integ(t: &[f64], v: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; v.len()];
    for i in 1..v.len() {
        if t[i - 1] >= 0.0 {
            out[i] = out[i - 1] + 0.5 * (v[i] + v[i - 1]) * (t[i] - t[i - 1]);
        }
    }
    out
}

/// Adds `extra(t, truth)` to the fitted channel.
fn inject(
    spec: &SynthSpec,
    extra: impl Fn(&[f64], &[f64]) -> Vec<f64>,
) -> (Prepared, Vec<f64>, f64) {
    let (mut ds, x, ch) = pair(spec);
    let e = extra(&ds.t, &x);
    let peak = e.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let c = ds.channels.get_mut(ch).expect("channel");
    for (v, d) in c.iter_mut().zip(&e) {
        *v += d;
    }
    (Prepared::new(ds), e, peak)
}

fn run(prep: &Prepared, baseline: &[&str]) -> DiscoverReport {
    let opts = DiscoverOptions {
        fit: FitOptions::default(),
        max_rounds: 3,
    };
    discover(prep, baseline, &opts, |_| {}).expect("discover").0
}

/// The common assertions; returns the leading term's kind and parameter value.
fn assert_outside(r: &DiscoverReport, kind: &str, state: &str) -> f64 {
    eprintln!("reason: {}", r.reason);
    eprintln!("leading: {:?}", r.residual.leading);
    for t in &r.residual.terms {
        eprintln!("  {} [{}] delta BIC {:.1}", t.term, t.state, t.delta_bic);
    }
    for c in &r.residual.correlations {
        eprintln!("  r({}) = {:+.3}", c.state, c.r);
    }
    assert!(!r.explained, "explained: {}: {:?}", r.reason, r.rounds);
    assert!(
        r.rounds.iter().all(|x| x.added.is_none()),
        "a catalogue effect named: {:?}",
        r.rounds
    );
    let lead = r.residual.terms.first().expect("a leading term");
    assert_eq!(lead.kind, kind, "{:?}", r.residual.terms);
    assert!(lead.state.contains(state), "{}", lead.state);
    lead.parameter.as_ref().expect("a parameter").value
}

fn derivative(t: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            (x[b] - x[a]) / (t[b] - t[a])
        })
        .collect()
}

#[test]
fn a_pendulum_mode_is_a_restoring_force_on_the_position_at_its_frequency() {
    let f0 = 30.0;
    let w2 = (std::f64::consts::TAU * f0).powi(2);
    let (prep, _, peak) = inject(&spec(Scenario::TmmfRelease, &TMMF, 41), |t, x| {
        integ(t, &integ(t, x)).iter().map(|v| -w2 * v).collect()
    });
    eprintln!("injected peak {peak:.3e} m");
    let r = run(&prep, &TMMF);
    let f = assert_outside(&r, "position", "position");
    assert!((f / f0 - 1.0).abs() < 0.05, "f0 {f} Hz against {f0}");
}

/// At the public example's sampling (200 kHz, 1800 samples): on the 50 kHz records of the other
/// tests the catalogue model absorbs a damping force to the noise (docs/fitting.md).
#[test]
fn a_damping_force_is_a_force_on_the_velocity_with_its_rate() {
    let gamma = 100.0;
    let mut sp = spec(Scenario::TmmfRelease, &TMMF, 10);
    sp.fs_hz = 2e5;
    let (prep, _, peak) = inject(&sp, |t, x| {
        let x0 = x[t.iter().position(|&t| t >= 0.0).expect("a trigger")];
        let xr: Vec<f64> = x.iter().map(|v| v - x0).collect();
        integ(t, &xr).iter().map(|v| -gamma * v).collect()
    });
    eprintln!("injected peak {peak:.3e} m");
    let r = run(&prep, &TMMF);
    let g = assert_outside(&r, "velocity", "velocity");
    assert!(
        (g / gamma - 1.0).abs() < 0.05,
        "gamma {g} 1/s against {gamma}"
    );
}

#[test]
fn a_slip_of_the_contact_point_is_a_jump_at_its_time() {
    let (a, t0) = (2e-8, 1.5e-3);
    let (prep, _, _) = inject(&spec(Scenario::TmmfRelease, &TMMF, 44), |t, _| {
        t.iter().map(|&t| if t >= t0 { a } else { 0.0 }).collect()
    });
    let r = run(&prep, &TMMF);
    let got = assert_outside(&r, "slip", "time");
    assert!((got - t0).abs() < 3e-5, "t0 {got} s against {t0}");
}

fn vibration(f: f64, seed: u64) -> DiscoverReport {
    let a = 2e-8;
    let (prep, _, _) = inject(&spec(Scenario::TmmfRelease, &TMMF, seed), |t, _| {
        t.iter()
            .map(|&t| a * (std::f64::consts::TAU * f * t + 0.4).sin())
            .collect()
    });
    run(&prep, &TMMF)
}

/// 12 cycles in the record: the frequency within 2 %, and a spectral peak there.
#[test]
fn a_floor_vibration_is_a_sinusoid_at_its_frequency() {
    let f = 1370.0;
    let r = vibration(f, 45);
    let got = assert_outside(&r, "vibration", "periodic");
    assert!((got / f - 1.0).abs() < 0.02, "f {got} Hz against {f}");
    let p = r.residual.peaks.first().expect("a peak");
    assert!((p.hz / f - 1.0).abs() < 0.02, "peak at {} Hz", p.hz);
}

/// 1.2 cycles in the record (the 137 Hz floor vibration): the periodogram cannot
/// resolve it, the sinusoid fit does once the model is refitted with it (the baseline absorbs
/// part of the cycle: the score test alone gave 128.1 Hz); frequency within 2 % (136.6 Hz at
/// seed 48), reported as the first spectral peak, and `interferometer_cyclic` (which with
/// `drift` brings this record to chi2_red 1.06) is not named.
#[test]
fn a_vibration_of_about_one_cycle_in_the_record_is_still_a_sinusoid() {
    let f = 137.0;
    let r = vibration(f, 48);
    let got = assert_outside(&r, "vibration", "periodic");
    assert!((got / f - 1.0).abs() < 0.02, "f {got} Hz against {f}");
    let p = r.residual.peaks.first().expect("a peak");
    assert!((p.hz - got).abs() < 1e-9, "peak at {} Hz", p.hz);
}

#[test]
fn piezo_creep_is_a_logarithm_of_time() {
    let (c, tau) = (-2e-8, 2e-5);
    let (prep, _, _) = inject(&spec(Scenario::RtRetraction, &RT, 46), |t, _| {
        t.iter()
            .map(|&t| if t > 0.0 { c * (t / tau).ln_1p() } else { 0.0 })
            .collect()
    });
    let r = run(&prep, &RT);
    let got = assert_outside(&r, "creep", "time");
    assert!((got / tau - 1.0).abs() < 0.5, "tau {got} s against {tau}");
}

#[test]
fn a_trigger_delay_of_the_tip_is_a_shift_of_the_time_axis() {
    let d = 2e-6;
    let (prep, _, peak) = inject(&spec(Scenario::RtRetraction, &RT, 47), |t, x| {
        derivative(t, x).iter().map(|v| -d * v).collect()
    });
    eprintln!("injected peak {peak:.3e} m");
    let r = run(&prep, &RT);
    let got = assert_outside(&r, "delay", "time");
    assert!((got / d - 1.0).abs() < 0.1, "delay {got} s against {d}");
}

/// `x` at `at` by linear interpolation (held at the ends).
fn interp(t: &[f64], x: &[f64], at: f64) -> f64 {
    let j = t.partition_point(|&v| v <= at);
    if j == 0 {
        x[0]
    } else if j >= t.len() {
        x[t.len() - 1]
    } else {
        let a = (at - t[j - 1]) / (t[j] - t[j - 1]);
        x[j - 1] + a * (x[j] - x[j - 1])
    }
}

/// A true shift of 5 us (five samples, as long as the tip's first rise: far from the first-order
/// `-d dx/dt` of the test above): the record is the truth at `t - d`.
#[test]
fn a_trigger_delay_of_five_samples_is_still_a_shift_of_the_time_axis() {
    let d = 5e-6;
    let (prep, _, _) = inject(&spec(Scenario::RtRetraction, &RT, 49), |t, x| {
        t.iter()
            .zip(x)
            .map(|(&ti, &xi)| interp(t, x, ti - d) - xi)
            .collect()
    });
    let r = run(&prep, &RT);
    let got = assert_outside(&r, "delay", "time");
    assert!((got / d - 1.0).abs() < 0.05, "delay {got} s against {d}");
}

/// Two terms outside the catalogue at once (issue 50, item 4): a damping force (gamma 100 1/s,
/// the public example's sampling, the TM moving at nearly constant speed) and a 10 nm pickup
/// at 150 Hz (1.2 cycles in the record), described on the catalogue model's fit (what
/// `discover` describes when no catalogue effect explains the record). Taking the leading
/// single term out and searching the rest after it picked an anti-restoring force with an
/// offset (its constant-force column stands in for the damping's) and a vibration pulled off
/// its frequency. Every pair of the leading kinds fitted jointly: `separate_terms` holds the
/// damping and the vibration, gamma within 10 % and f within 3 %, each resolved (a finite
/// sigma) and strongly supported beside the other.
#[test]
fn a_damping_and_a_pickup_are_reported_as_the_two_terms() {
    let (gamma, f, a) = (100.0, 150.0, 1e-8);
    let mut sp = spec(Scenario::TmmfRelease, &TMMF, 50);
    sp.fs_hz = 2e5;
    let (prep, _, _) = inject(&sp, |t, x| {
        let x0 = x[t.iter().position(|&t| t >= 0.0).expect("a trigger")];
        let xr: Vec<f64> = x.iter().map(|v| v - x0).collect();
        integ(t, &xr)
            .iter()
            .zip(t)
            .map(|(v, &t)| -gamma * v + a * (std::f64::consts::TAU * f * t + 0.7).sin())
            .collect()
    });
    let opts = FitOptions::default();
    let model = Model::with_effects(
        Scenario::TmmfRelease,
        &TMMF.map(|n| geodesic_facility::effects::by_name(n).expect("catalogue effect")),
    )
    .expect("model");
    let starts = default_starts(&model, &prep.guess, MAX_STARTS);
    let o = fit_model(&prep, &model, &opts, &starts).expect("fit");
    let r = FitReport::new(&prep, &o);
    let d = describe(&prep, &o, &r, &opts).expect("describe");
    eprintln!("leading: {:?}", d.leading);
    let terms = &d.separate_terms;
    for t in terms {
        eprintln!(
            "  separate: {} ({:.3e} +- {:.2e}, delta BIC {:.1})",
            t.term, t.coefficient, t.sigma, t.delta_bic
        );
    }
    eprintln!("  alike: {:?}", d.separate_indistinguishable);
    assert_eq!(terms.len(), 2, "{}", serde_json::json!(d));
    let value = |kind: &str| {
        let t = terms
            .iter()
            .find(|t| t.kind == kind)
            .unwrap_or_else(|| panic!("no {kind} term: {}", serde_json::json!(terms)));
        assert!(t.sigma.is_finite() && t.sigma > 0.0, "{}", t.term);
        assert!(t.delta_bic < -10.0, "{}: delta BIC {}", t.term, t.delta_bic);
        t.parameter.as_ref().expect("a parameter").value
    };
    let g = value("velocity");
    assert!(
        (g / gamma - 1.0).abs() < 0.1,
        "gamma {g} 1/s against {gamma}"
    );
    let got = value("vibration");
    assert!((got / f - 1.0).abs() < 0.03, "f {got} Hz against {f}");
}
