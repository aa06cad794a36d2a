//! geodesic-dataset: the measurement records the identification engine reads and writes.
//!
//! - [`dataset`]: YAML + CSV datasets (interface.md): loading, units, lab files (DAQ exports,
//!   counts with a calibration, channels mapped by name), bad input refused with file and line;
//! - [`synth`]: synthetic datasets from a truth model built from the facility's effect code, and
//!   a synthetic campaign's truth;
//! - [`coords`]: the fit's coordinates of a parameter and the checks of user-given values and
//!   bounds against its spec;
//! - [`noise`]: deterministic Gaussian noise (the tests' noise);
//! - [`error`]: the error of loading, fitting and writing ([`FitError`]), naming file and line.
//!
//! It names no scenario: what differs between scenarios is asked of the facility crate
//! (`geodesic_facility::scenario`).

#![warn(missing_docs)]
pub mod coords;
pub mod dataset;
pub mod error;
pub mod noise;
pub mod synth;

pub use dataset::Dataset;
pub use error::FitError;
