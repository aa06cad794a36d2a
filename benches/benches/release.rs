//! Criterion benchmarks of the in-flight release: one release (no adhesion, adhesion at the
//! experimental bounds, a random draw of the default budget) with the fast and the reference
//! integrators, and the Monte Carlo throughput (releases per second, all cores).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use geodesic_release::budget::Budget;
use geodesic_release::inputs::ReleaseInputs;
use geodesic_release::integrator::DormandPrince;
use geodesic_release::montecarlo::{self, Case, draw_inputs};
use std::hint::black_box;

fn one_release(c: &mut Criterion) {
    let mut g = c.benchmark_group("one_release");
    let nominal = ReleaseInputs::nominal();
    let mut bound = ReleaseInputs::nominal();
    bound.a1_n_m[1] = 1.5e5;
    bound.lambda_m[1] = 8e-7;
    let random = draw_inputs(&Budget::default_budget(), Case::All, 1, 0);
    let fast = DormandPrince::fast();
    g.bench_function("no_adhesion/fast", |b| {
        b.iter(|| black_box(&nominal).simulate(&fast).unwrap())
    });
    g.bench_function("adhesion_bound/fast", |b| {
        b.iter(|| black_box(&bound).simulate(&fast).unwrap())
    });
    g.bench_function("random_draw/fast", |b| {
        b.iter(|| black_box(&random).simulate(&fast).unwrap())
    });
    g.bench_function("adhesion_bound/reference", |b| {
        b.iter(|| {
            black_box(&bound)
                .simulate(&DormandPrince::reference())
                .unwrap()
        })
    });
    g.finish();
}

fn throughput(c: &mut Criterion) {
    let mut g = c.benchmark_group("montecarlo");
    g.sample_size(10);
    let budget = Budget::default_budget();
    let n = 2000;
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("case_all_2000_draws", |b| {
        b.iter(|| montecarlo::run(&budget, Case::All, n, black_box(1), None, &|_| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, one_release, throughput);
criterion_main!(benches);
