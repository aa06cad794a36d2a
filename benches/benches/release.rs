//! Criterion benchmarks of the in-flight release: one release (no adhesion, adhesion at the
//! experimental bounds, a random draw of the default budget) with the Monte Carlo's exponential
//! Gauss collocation and, for comparison, the Dormand-Prince integrators; the per-release setup
//! (modal decomposition); and the Monte Carlo throughput (10^4 releases, all cores).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use geodesic_mechanism::{Mechanism, PiezoMechanism};
use geodesic_release::budget::Budget;
use geodesic_release::expgauss::ExpGauss;
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
    let budget = Budget::default_budget();
    let random = draw_inputs(&budget, Case::All, 1, 0);
    let fast = DormandPrince::fast();
    let eg = ExpGauss::fast();
    for (name, r) in [
        ("no_adhesion", &nominal),
        ("adhesion_bound", &bound),
        ("random_draw", &random),
    ] {
        g.bench_function(format!("{name}/expgauss"), |b| {
            b.iter(|| black_box(r).simulate_fast(&eg).unwrap())
        });
        g.bench_function(format!("{name}/dopri_fast"), |b| {
            b.iter(|| black_box(r).simulate(&fast).unwrap())
        });
    }
    g.bench_function("adhesion_bound/dopri_reference", |b| {
        b.iter(|| {
            black_box(&bound)
                .simulate(&DormandPrince::reference())
                .unwrap()
        })
    });
    // the mean cost of a draw: 64 draws of case all (draw, model, simulate), per release
    let draws: Vec<ReleaseInputs> = (0..64)
        .map(|i| draw_inputs(&budget, Case::All, 1, i))
        .collect();
    g.throughput(Throughput::Elements(draws.len() as u64));
    g.bench_function("case_all_64_draws/expgauss", |b| {
        b.iter(|| {
            for r in &draws {
                black_box(r.simulate_fast(&eg).unwrap());
            }
        })
    });
    g.finish();
    let mut g = c.benchmark_group("setup");
    let mech = PiezoMechanism::new(
        random.mech[0],
        geodesic_mechanism::VoltageCommand::nominal(),
    );
    g.bench_function("piezo_modes", |b| {
        b.iter(|| black_box(&mech).modes().unwrap())
    });
    g.bench_function("draw_inputs", |b| {
        b.iter(|| draw_inputs(&budget, Case::All, 1, black_box(17)))
    });
    g.finish();
}

fn throughput(c: &mut Criterion) {
    let mut g = c.benchmark_group("montecarlo");
    g.sample_size(10);
    let budget = Budget::default_budget();
    let n = 10_000;
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("case_all_10k_draws", |b| {
        b.iter(|| montecarlo::run(&budget, Case::All, n, black_box(1), None, &|_| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, one_release, throughput);
criterion_main!(benches);
