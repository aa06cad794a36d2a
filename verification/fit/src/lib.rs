//! geodesic-fit: fit one model of the facility to one measurement record.
//!
//! Estimation on top of the numeric core, the crate `geodesic-numeric` (Levenberg-Marquardt,
//! linear algebra, noise, sampling and posteriors; it knows no dataset, model, effect or
//! scenario), re-exported as [`numeric`] because its types are part of this crate's results
//! ([`numeric::noise::ArNoise`], [`numeric::posterior::Posterior`], ...). The records (datasets,
//! synthetic records, a parameter's fit coordinates, the error type [`FitError`]) are the crate
//! `geodesic-dataset`. Which model explains a record (`diagnose`, the kinds of term outside the
//! catalogue, `discover`) and the identification session that runs fit, diagnose and discover
//! are the crate `geodesic-discover`, on top of this one. The modules use each other without a
//! cycle (`.ci/framework.py` checks every crate's module graph in CI):
//! - [`prepare`]: noise per channel, the smooth tip profile, data-driven guesses;
//! - [`identify`]: symmetries, held values, identifiable combinations;
//! - [`estimate`]: data-driven multi-start fits, covariance, profile likelihood;
//! - [`report`]: the fit object of interface.md, with [`outliers`] (outliers and stuck
//!   parameters, said out loud); [`summary`]: a fit's text summary;
//! - [`record`], [`screen`]: the record as the fit sees it, its screening for bad samples;
//! - [`fit`]: the public face of the three above (re-exports only);
//! - [`history`], [`plot`] (the plain data of the plots `geodesic-plot` draws), [`design`];
//! - [`spectral`]: a series' amplitude spectral density judged against a spectral requirement.
//!
//! The engine names no scenario: what differs between scenarios is asked of the scenario's
//! implementation in the facility crate (`geodesic_facility::scenario`).

#![warn(missing_docs)]
pub mod design;
pub mod estimate;
pub mod fit;
pub mod history;
pub mod identify;
pub mod plot;
pub mod prepare;
pub mod record;
pub mod report;
pub mod screen;
pub mod spectral;
pub mod summary;

pub use fit::{FitOptions, FitOutcome, FitReport, Prepared, fit};
pub use geodesic_dataset::FitError;
/// The numeric core (the crate `geodesic-numeric`), whose types appear in this crate's results;
/// the modules here name it `crate::numeric`.
pub use geodesic_numeric as numeric;
pub use report::outliers;

// The records, from geodesic-dataset, imported (privately) at the root so that the modules name
// them `crate::dataset`, `crate::error`, ... Callers import `geodesic_dataset` themselves.
#[cfg(test)]
use geodesic_dataset::synth;
use geodesic_dataset::{coords, dataset, error};
