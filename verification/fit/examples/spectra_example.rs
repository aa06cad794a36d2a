//! Writes `data/spectra/lpf-da-example.{yaml,csv}`: a SYNTHETIC differential-acceleration series
//! with a known spectrum, for demonstrating `geodesic asd` and `geodesic verify --series`
//! (docs/spectra.md). It is not a LISA Pathfinder measurement.
//!
//! Spectrum: white acceleration noise of ASD 1.5e-14 m s^-2 Hz^-1/2 plus a random walk of ASD
//! 2.5e-17 / f m s^-2 Hz^-1/2 (at low frequency), sampled at 0.1 Hz for 4096 samples (11.4 h);
//! ChaCha8 seed 1. Run: `cargo run -p geodesic-fit --example spectra_example`.

use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::fmt::Write;

fn main() {
    let fs: f64 = 0.1;
    let n = 4096;
    let white_asd = 1.5e-14;
    let red_coef = 2.5e-17; // ASD = red_coef / f
    let sd_white = white_asd / (2.0 / fs).sqrt();
    let sd_step = red_coef * 2.0 * std::f64::consts::PI / (2.0 * fs).sqrt();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let (w, r) = (
        Normal::new(0.0, sd_white).unwrap(),
        Normal::new(0.0, sd_step).unwrap(),
    );
    let mut walk = 0.0;
    let mut csv = String::from("t,da\n");
    for i in 0..n {
        walk += r.sample(&mut rng);
        let v = w.sample(&mut rng) + walk;
        // fm/s^2 with 6 significant digits
        let _ = writeln!(csv, "{},{:.6e}", i as f64 / fs, v * 1e15);
    }
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/spectra");
    std::fs::create_dir_all(root).unwrap();
    std::fs::write(format!("{root}/lpf-da-example.csv"), csv).unwrap();
    std::fs::write(
        format!("{root}/lpf-da-example.yaml"),
        "description: >-\n  SYNTHETIC differential acceleration (not a measurement): white 1.5e-14 m s^-2 Hz^-1/2\n  plus a random walk of ASD 2.5e-17/f, 0.1 Hz, 4096 samples, seed 1\n  (verification/fit/examples/spectra_example.rs).\norigin: synthetic\ndata: lpf-da-example.csv\ntime_column: t\nchannel: da\nunit: fm/s^2\n",
    )
    .unwrap();
    println!("wrote {root}/lpf-da-example.{{yaml,csv}}");
}
