//! Deterministic noise: the seeded Gaussian the tests of the identification crates draw from.

/// `n` draws of Gaussian noise of unit sigma, deterministic (ChaCha8 seeded with `seed`): the
/// test noise of the identification crates.
pub fn gauss(n: usize, seed: u64) -> Vec<f64> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let d = Normal::new(0.0, 1.0).unwrap();
    (0..n).map(|_| d.sample(&mut r)).collect()
}
