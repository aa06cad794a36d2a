//! Criterion benchmark of the issue-35 fit: the public `rt-plunger` record resampled to
//! 1 000 000 samples (linear interpolation, [`geodesic_benches::resample_rt_plunger`]) fitted
//! with `piezo` alone (its missing effects left out, as a user's first fit would), with the
//! profile likelihood that `geodesic fit` runs: the same work as
//! `geodesic fit rt-plunger-1000000.yaml --effects piezo` without its plot and history.
//! `cargo bench -p geodesic-benches --bench fit_long`; the README's performance section
//! compares the two.

use std::hint::black_box;
use std::time::Duration;

use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use geodesic_dataset::{Dataset, dataset::LoadOptions};
use geodesic_fit::fit::{FitOptions, Prepared, fit};

fn long_retraction(c: &mut Criterion) {
    let n = 1_000_000;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fit_long");
    let path = geodesic_benches::resample_rt_plunger(n, &dir).expect("resampled record");
    let prep = Prepared::new(Dataset::load_with(&path, LoadOptions::default()).expect("load"));
    let opts = FitOptions {
        profile: true,
        ..FitOptions::default()
    };
    let mut g = c.benchmark_group("fit_wrong_model");
    // ten fits of about 30 s of CPU each: flat sampling (one fit per sample; the linear mode's
    // 1 + 2 + ... + 10 fits would take half an hour), a warm-up of one fit
    g.sample_size(10);
    g.sampling_mode(SamplingMode::Flat);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(60));
    g.throughput(Throughput::Elements(n as u64));
    g.bench_with_input(BenchmarkId::new("rt-plunger-piezo", n), &prep, |b, prep| {
        b.iter(|| fit(black_box(prep), &["piezo"], &opts).expect("fit"))
    });
    g.finish();
}

/// Four parameter vectors of the retraction model (a Jacobian's columns) on the same
/// million-sample record: one evaluation after the other, and side by side
/// (`Model::predict_many`, the same bits: `RtConfig::retraction_many`).
fn retraction_lanes(c: &mut Criterion) {
    let n = 1_000_000;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fit_long");
    let path = geodesic_benches::resample_rt_plunger(n, &dir).expect("resampled record");
    let prep = Prepared::new(Dataset::load_with(&path, LoadOptions::default()).expect("load"));
    let model = geodesic_facility::Model::new(
        geodesic_facility::Scenario::RtRetraction,
        &["piezo", "plunger_compliance"],
    )
    .expect("model");
    // the example's truth (data/examples/rt-plunger.truth.json), each of the first four
    // parameters moved by 0.1 %
    let truth = [371.2, 9e-4, 2.3e-7, 4.91e7, 9.77, 5.73, 0.019, 2.15e6];
    let ps: Vec<Vec<f64>> = (0..4)
        .map(|k| {
            let mut p = truth.to_vec();
            p[k] *= 1.001;
            p
        })
        .collect();
    let mut g = c.benchmark_group("retraction_4_vectors");
    g.sample_size(20);
    g.throughput(Throughput::Elements(4 * n as u64));
    g.bench_function(BenchmarkId::new("one_by_one", n), |b| {
        b.iter(|| {
            ps.iter()
                .map(|p| model.predict(black_box(p), &prep.dataset.t, &prep.inputs))
                .collect::<Vec<_>>()
        })
    });
    g.bench_function(BenchmarkId::new("side_by_side", n), |b| {
        b.iter(|| model.predict_many(black_box(&ps), &prep.dataset.t, &prep.inputs))
    });
    g.finish();
}

criterion_group!(benches, long_retraction, retraction_lanes);
criterion_main!(benches);
