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
use geodesic_fit::fit::{FitOptions, Prepared, fit};
use geodesic_fit::{Dataset, dataset::LoadOptions};

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

criterion_group!(benches, long_retraction);
criterion_main!(benches);
