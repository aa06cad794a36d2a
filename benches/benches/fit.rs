//! Criterion benchmarks of the identification fits: the forward model of each scenario (and four
//! TMMF parameter vectors one by one and in lockstep; a five-parameter Jacobian by differences
//! and by the tangents), and
//! `fit` with the right model at 2 000, 20 000 and 400 000 samples (tmmf-release: 200 kHz, the
//! facility's rate, for 10 ms, 100 ms and 2 s; rt-retraction: 1 MHz for 2 ms, 20 ms, 0.4 s and
//! 1 s), and
//! `diagnose` of the 400 000-sample TMMF release, and `discover` (issue 33, item 6) from the
//! baseline `needle_contact,tip_contact` of a TMMF release that hides its tip adhesion, at
//! 2 000 samples (10 ms at 200 kHz) and 400 000 samples (2 s). The
//! throughput is in samples, so criterion prints the cost per sample; the datasets are
//! synthesized in memory with `synth`'s code (fixed seeds). `sampling_twins`: a 20 000-sample
//! rt-retraction record and a 2 000-sample TMMF release on their regular grid, jittered and
//! gapped, forward model and `fit` (issue 50, item 5).

use std::hint::black_box;
use std::time::Duration;

use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use geodesic_dataset::synth::{SynthSpec, generate};
use geodesic_discover::diagnose::diagnose;
use geodesic_discover::discover::{DiscoverOptions, discover};
use geodesic_facility::{Model, Scenario, TipProfile};
use geodesic_fit::fit::{FitOptions, Prepared, fit};

const TMMF: [&str; 3] = ["needle_contact", "tip_contact", "tip_adhesion"];
const TMMF_BASE: [&str; 2] = ["needle_contact", "tip_contact"];
const RT: [&str; 3] = ["piezo", "plunger_compliance", "voltage_ramp"];

/// A synthetic record of `scenario` with about `n` samples (1 ms, 20 us before the trigger).
fn record(scenario: Scenario, n: usize) -> Prepared {
    let tm = scenario == Scenario::TmmfRelease;
    let effects: &[&str] = if tm { &TMMF } else { &RT };
    let mut spec = SynthSpec::defaults(scenario, effects);
    if tm {
        spec.params.insert("tip_adhesion.A1".into(), 1.3e5);
        spec.params.insert("tip_adhesion.lambda".into(), 6e-7);
        spec.profile = TipProfile {
            jerk_m_s3: 6000.0,
            v_m_s: 3e-3,
        };
    }
    spec.post_s = (n as f64 - 1.0) / spec.fs_hz - spec.pre_s;
    spec.seed = 3;
    Prepared::new(generate(&spec, "bench.yaml").expect("synth"))
}

fn forward(c: &mut Criterion) {
    let mut g = c.benchmark_group("forward_model");
    for (scenario, effects, p) in [
        (
            Scenario::TmmfRelease,
            &TMMF[..],
            vec![6.5e5, 7e-3, 1e6, 1.3e5, 6e-7],
        ),
        (Scenario::RtRetraction, &RT[..], Vec::new()),
    ] {
        let model = Model::new(scenario, effects).unwrap();
        let p = if p.is_empty() { model.nominal() } else { p };
        for n in [2_000usize, 400_000] {
            let prep = record(scenario, n);
            g.throughput(Throughput::Elements(n as u64));
            g.bench_with_input(BenchmarkId::new(scenario.name(), n), &prep, |b, prep| {
                b.iter(|| model.predict(black_box(&p), &prep.dataset.t, &prep.inputs))
            });
        }
    }
    g.finish();
}

/// Four parameter vectors of the TMMF model (a Jacobian's columns) on a 2 000-sample record:
/// one evaluation after the other, and in lockstep (`Model::predict_many`, the same bits).
fn lockstep(c: &mut Criterion) {
    let mut g = c.benchmark_group("forward_model_4_vectors");
    let model = Model::new(Scenario::TmmfRelease, &TMMF).unwrap();
    let n = 2_000;
    let prep = record(Scenario::TmmfRelease, n);
    let ps: Vec<Vec<f64>> = (0..4)
        .map(|k| {
            let mut p = vec![6.5e5, 7e-3, 1e6, 1.3e5, 6e-7];
            p[k] *= 1.001;
            p
        })
        .collect();
    g.throughput(Throughput::Elements(4 * n as u64));
    g.bench_function(BenchmarkId::new("one_by_one", n), |b| {
        b.iter(|| {
            ps.iter()
                .map(|p| model.predict(black_box(p), &prep.dataset.t, &prep.inputs))
                .collect::<Vec<_>>()
        })
    });
    g.bench_function(BenchmarkId::new("lockstep", n), |b| {
        b.iter(|| model.predict_many(black_box(&ps), &prep.dataset.t, &prep.inputs))
    });
    g.finish();
    // the exact Jacobian of the five parameters (one integration carrying the tangents)
    // against its five forward-difference columns in lockstep
    let mut g = c.benchmark_group("jacobian_5_parameters");
    let p = vec![6.5e5, 7e-3, 1e6, 1.3e5, 6e-7];
    let dirs: Vec<usize> = (0..5).collect();
    let cols: Vec<Vec<f64>> = (0..5)
        .map(|k| {
            let mut q = p.clone();
            q[k] *= 1.001;
            q
        })
        .collect();
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function(BenchmarkId::new("one_reading", n), |b| {
        b.iter(|| model.predict(black_box(&p), &prep.dataset.t, &prep.inputs))
    });
    g.bench_function(BenchmarkId::new("differences_lockstep", n), |b| {
        b.iter(|| model.predict_many(black_box(&cols), &prep.dataset.t, &prep.inputs))
    });
    g.bench_function(BenchmarkId::new("tangents", n), |b| {
        b.iter(|| model.predict_with_tangents(black_box(&p), &dirs, &prep.dataset.t, &prep.inputs))
    });
    g.finish();
}

fn fits(c: &mut Criterion) {
    let mut g = c.benchmark_group("fit");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(30));
    for (scenario, effects, sizes) in [
        (
            Scenario::TmmfRelease,
            &TMMF[..],
            &[2_000usize, 20_000, 400_000][..],
        ),
        (
            Scenario::RtRetraction,
            &RT[..],
            // 1 MHz: 2 ms, 20 ms, 0.4 s and 1 s (the mechanism tests' rate)
            &[2_000usize, 20_000, 400_000, 1_000_000][..],
        ),
    ] {
        for &n in sizes {
            let prep = record(scenario, n);
            g.throughput(Throughput::Elements(n as u64));
            g.bench_with_input(BenchmarkId::new(scenario.name(), n), &prep, |b, prep| {
                b.iter(|| fit(prep, effects, &FitOptions::default()).expect("fit"))
            });
        }
    }
    g.finish();
}

fn diagnoses(c: &mut Criterion) {
    let mut g = c.benchmark_group("diagnose");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(60));
    let n = 400_000;
    let prep = record(Scenario::TmmfRelease, n);
    g.throughput(Throughput::Elements(n as u64));
    g.bench_with_input(BenchmarkId::new("tmmf-release", n), &prep, |b, prep| {
        b.iter(|| diagnose(prep, &TMMF_BASE, &FitOptions::default()).expect("diagnose"))
    });
    g.finish();
}

fn discoveries(c: &mut Criterion) {
    let mut g = c.benchmark_group("discover");
    // one iteration a sample: a discover of the 400 000-sample record takes about 40 s, so
    // its ten samples take seven minutes (criterion's least sample size)
    g.sample_size(10);
    g.sampling_mode(SamplingMode::Flat);
    for (n, secs) in [(2_000usize, 60u64), (400_000, 300)] {
        g.measurement_time(Duration::from_secs(secs));
        let prep = record(Scenario::TmmfRelease, n);
        g.throughput(Throughput::Elements(n as u64));
        let opts = DiscoverOptions {
            fit: FitOptions::default(),
            max_rounds: 4,
        };
        g.bench_with_input(BenchmarkId::new("tmmf-release", n), &prep, |b, prep| {
            b.iter(|| discover(prep, &TMMF_BASE, &opts, |_| {}).expect("discover"))
        });
    }
    g.finish();
}

/// The time stamps of `t` after the trigger moved by a normal jitter of sd 10 % of the step
/// (a fixed seed; issue 50, item 5), or with one sample of every 7 left out.
fn irregular(t: &[f64], jitter: bool) -> Vec<f64> {
    let h = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let mut s = 50u64;
    let mut uniform = || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    t.iter()
        .enumerate()
        .filter(|&(i, &ti)| jitter || ti <= 0.0 || i % 7 != 3)
        .map(|(_, &ti)| {
            let g = (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos();
            if jitter && ti > 0.0 {
                ti + 0.1 * h * g
            } else {
                ti
            }
        })
        .collect()
}

/// The twin of `prep` at the time stamps `irregular(t, jitter)` keeps (jittered, or one sample
/// in 7 left out): each channel's reading moved by what `model` at `p` (the record's truth)
/// reads at the new time stamp instead of the old one, so that the twin is the same physics
/// and noise at other time stamps.
fn twin(prep: &Prepared, model: &Model, p: &[f64], jitter: bool) -> Prepared {
    let t = &prep.dataset.t;
    let moved = irregular(t, jitter);
    let kept: Vec<usize> = if jitter {
        (0..t.len()).collect()
    } else {
        (0..t.len())
            .filter(|&i| t[i] <= 0.0 || i % 7 != 3)
            .collect()
    };
    let before = model.predict(p, t, &prep.inputs);
    let after = model.predict(p, &moved, &prep.inputs);
    let mut ds = prep.dataset.clone();
    for (name, y) in ds.channels.iter_mut() {
        let fitted = name.as_str() == prep.channel;
        *y = kept
            .iter()
            .zip(&after)
            .map(|(&k, a)| if fitted { y[k] - before[k] + a } else { y[k] })
            .collect();
    }
    if ds.rows.lines.len() == t.len() {
        ds.rows.lines = kept.iter().map(|&k| ds.rows.lines[k]).collect();
    }
    ds.t = moved;
    Prepared::new(ds)
}

/// Regular, jittered and gapped twins (issue 50, item 5: the irregular ones no more than twice
/// the regular one) of a 20 000-sample rt-retraction record (1 MHz, 20 ms): the forward model
/// of each at nominal parameters, and `fit` of each with `piezo,plunger_compliance`; and of a
/// 2 000-sample TMMF release (200 kHz, 10 ms): the forward model and `fit` with the right
/// model; and `discover` from the piezo on 5 000-sample retraction twins.
fn sampling_twins(c: &mut Criterion) {
    let n = 20_000;
    let prep = record(Scenario::RtRetraction, n);
    let truth = Model::new(Scenario::RtRetraction, &RT).unwrap();
    let p_truth = truth.nominal();
    let effects = ["piezo", "plunger_compliance"];
    let model = Model::new(Scenario::RtRetraction, &effects).unwrap();
    let p = model.nominal();
    let rt = [
        ("regular", twin_regular(&prep)),
        ("jittered", twin(&prep, &truth, &p_truth, true)),
        ("gapped", twin(&prep, &truth, &p_truth, false)),
    ];
    let tm = record(Scenario::TmmfRelease, 2_000);
    let tm_model = Model::new(Scenario::TmmfRelease, &TMMF).unwrap();
    let tm_p = vec![6.5e5, 7e-3, 1e6, 1.3e5, 6e-7];
    let tmmf = [
        ("regular", twin_regular(&tm)),
        ("jittered", twin(&tm, &tm_model, &tm_p, true)),
        ("gapped", twin(&tm, &tm_model, &tm_p, false)),
    ];
    let mut g = c.benchmark_group("sampling_twins_forward");
    for (name, twin) in &rt {
        g.throughput(Throughput::Elements(twin.dataset.t.len() as u64));
        g.bench_with_input(BenchmarkId::new(format!("rt-{name}"), n), twin, |b, tw| {
            b.iter(|| model.predict(black_box(&p), &tw.dataset.t, &tw.inputs))
        });
    }
    for (name, twin) in &tmmf {
        g.throughput(Throughput::Elements(twin.dataset.t.len() as u64));
        g.bench_with_input(
            BenchmarkId::new(format!("tmmf-{name}"), 2_000),
            twin,
            |b, tw| b.iter(|| tm_model.predict(black_box(&tm_p), &tw.dataset.t, &tw.inputs)),
        );
    }
    g.finish();
    let mut g = c.benchmark_group("sampling_twins_fit");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(30));
    for (name, twin) in &rt {
        g.throughput(Throughput::Elements(twin.dataset.t.len() as u64));
        g.bench_with_input(BenchmarkId::new(format!("rt-{name}"), n), twin, |b, tw| {
            b.iter(|| fit(tw, &effects, &FitOptions::default()).expect("fit"))
        });
    }
    for (name, twin) in &tmmf {
        g.throughput(Throughput::Elements(twin.dataset.t.len() as u64));
        g.bench_with_input(
            BenchmarkId::new(format!("tmmf-{name}"), 2_000),
            twin,
            |b, tw| b.iter(|| fit(tw, &TMMF, &FitOptions::default()).expect("fit")),
        );
    }
    g.finish();
    // discover from the piezo alone (the plunger hidden) on 5 000-sample retraction twins:
    // the candidates' searches, the stiff starts of the multi-start and a voltage ramp
    // included (issue 50, item 5: `discover` on a jittered record was 3.3 times its regular
    // twin before the balanced bins)
    let n_d = 5_000;
    let prep_d = record(Scenario::RtRetraction, n_d);
    let rt_d = [
        ("regular", twin_regular(&prep_d)),
        ("jittered", twin(&prep_d, &truth, &p_truth, true)),
        ("gapped", twin(&prep_d, &truth, &p_truth, false)),
    ];
    let opts = DiscoverOptions {
        fit: FitOptions::default(),
        max_rounds: 4,
    };
    let mut g = c.benchmark_group("sampling_twins_discover");
    g.sample_size(10);
    g.sampling_mode(SamplingMode::Flat);
    g.measurement_time(Duration::from_secs(60));
    for (name, twin) in &rt_d {
        g.throughput(Throughput::Elements(twin.dataset.t.len() as u64));
        g.bench_with_input(
            BenchmarkId::new(format!("rt-{name}"), n_d),
            twin,
            |b, tw| b.iter(|| discover(tw, &["piezo"], &opts, |_| {}).expect("discover")),
        );
    }
    g.finish();
}

/// The regular twin: the record itself.
fn twin_regular(prep: &Prepared) -> Prepared {
    Prepared::new(prep.dataset.clone())
}

criterion_group!(
    benches,
    forward,
    lockstep,
    fits,
    diagnoses,
    discoveries,
    sampling_twins
);
criterion_main!(benches);
