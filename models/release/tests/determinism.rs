//! The Monte Carlo gives bit-identical values for a seed whatever the thread count.

use geodesic_release::budget::Budget;
use geodesic_release::montecarlo::{Case, run};

#[test]
fn same_values_with_one_and_three_threads() {
    let b = Budget::default_budget();
    let go = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run(&b, Case::Adhesion, 700, 9, None, &|_| {}).unwrap())
    };
    let (a, c) = (go(1), go(3));
    assert_eq!(a.v_m_s, c.v_m_s);
    assert_eq!(a.summary(), c.summary());
}
