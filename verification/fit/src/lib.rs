//! geodesic-fit: confront the facility models with measurements.
//!
//! - [`dataset`]: YAML + CSV datasets (interface.md), bad input refused with file and line.
//! - [`lm`]: bounded Levenberg-Marquardt with finite-difference Jacobians.
//! - [`prepare`]: noise per channel, the smooth tip profile, data-driven guesses.
//! - [`fit`]: data-driven multi-start fits, covariance, profile likelihood.
//! - [`report`]: the fit object of interface.md.
//! - [`outliers`]: outliers and stuck parameters, said out loud.
//! - [`residual`]: reduced chi-square, whiteness test, failure windows.
//! - [`diagnose`]: fits every candidate effect a model lacks and ranks them by delta BIC.
//! - [`synth`]: synthetic datasets from a truth model built from the same effect code.
//! - [`history`]: per-dataset fit history (JSON lines) and its table.
//! - [`plot`]: SVGs of data, model and residual, and of the history.

pub mod campaign;
pub mod campaign_page;
pub mod dataset;
pub mod design;
pub mod diagnose;
pub mod discover;
pub mod ensemble;
pub mod error;
pub mod fit;
pub mod history;
pub mod identify;
pub mod kinds;
pub mod linalg;
pub mod lm;
pub mod noise;
pub mod outliers;
pub mod plot;
pub mod posterior;
pub mod prepare;
pub mod progress;
pub mod report;
pub mod residual;
pub mod scaffold;
pub mod spectral;
pub mod synth;

pub use dataset::Dataset;
pub use error::FitError;
pub use fit::{FitOptions, FitOutcome, FitReport, Prepared, fit};
