//! geodesic-testrun: a recorded test run, for this repository (`cargo xtask test`) and for any
//! project verified with geodesic (its harness's `test` command, `cargo run -- test`).
//!
//! [`record`] runs `cargo test` with the given arguments (its output and exit status unchanged,
//! with a status line after each minute of silence: [`progress`]), records which traced tests
//! ran, with what result and what they asserted ([`output`] reads libtest's lines, [`scan`] the
//! declared `verifies!` calls, [`join`] puts them together with the records the tests wrote),
//! and writes `target/geodesic/test-run.json` (a [`geodesic_core::testrun::TestRun`], read by
//! the compliance matrix). The run records the commit and a fingerprint of the work tree it ran
//! on (`verify` counts it only for that tree), and runs every property test from one fixed
//! proptest seed ([`PROPTEST_RNG_SEED`]).
//!
//! The crate names no mission.

#![warn(missing_docs)]
pub mod join;
pub mod output;
pub mod progress;
mod record;
pub mod scan;

pub use record::{PROPTEST_RNG_SEED, Recording, record, rfc3339, target_dir};
