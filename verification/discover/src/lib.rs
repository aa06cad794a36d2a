//! geodesic-discover: model identification, which model explains a record, on top of
//! `geodesic-fit`, which fits one given model to one record. Named for its main job: `discover`
//! (the loop that `diagnose` is one round of) finds the effects a model misses, catalogue
//! effects or kinds of term outside the catalogue.
//!
//! - [`diagnose`]: candidate effects ranked by delta BIC (one round);
//! - [`kinds`]: the kinds of term outside the catalogue (position, velocity, delay, creep,
//!   slip, impulse, vibration) fitted to what a model leaves;
//! - [`discover`]: the discovery loop, its text, and `--scaffold`'s orchestration (a new
//!   effect's code is written by `geodesic-codegen`);
//! - [`session`]: the identification session a front end calls: a dataset, a model and options
//!   in, `fit`, `diagnose` or `discover` run with their outputs, typed results out, progress
//!   through the caller's observer.
//!
//! The modules use each other without a cycle (`.ci/framework.py` checks every crate's module graph in CI).
//! The engine names no scenario: what differs between scenarios is asked of the scenario's
//! implementation in the facility crate (`geodesic_facility::scenario`).

#![warn(missing_docs)]
pub mod diagnose;
pub mod discover;
pub mod kinds;
pub mod session;

pub use diagnose::{DiagnoseReport, diagnose};
pub use discover::{DiscoverOptions, DiscoverReport, discover};
pub use session::{Discovered, FitRequest, PosteriorRequest, Session};

// The engine this crate builds on, imported (privately) at the root so that the modules name
// its parts as `crate::estimate`, `crate::dataset`, ... as they did inside `geodesic-fit`.
#[cfg(test)]
use geodesic_dataset::synth;
use geodesic_dataset::{FitError, coords, dataset, error};
use geodesic_fit::{design, estimate, outliers, prepare, record, report, screen, summary};
use geodesic_fit::{history, plot};
use geodesic_numeric as numeric;
