//! geodesic-core: the verification framework's foundation.
//!
//! - [`units`]: units as engineers write them (`5 um/s`, `200 µm`, `3e8 e`) and dimensions.
//! - [`requirement`]: requirements in YAML, loaded raw then checked, errors with `file:line:column`.
//! - [`check`]: the [`check::Check`] trait, the [`check::Evidence`] a check returns and the
//!   [`CheckError`] it fails with, an enum matched by kind (`Input` with file and line, `Model`,
//!   `Evidence`, `Config`); a requirement file's [`requirement::LoadError`] says its
//!   [`requirement::LoadKind`].
//! - [`matrix`]: the compliance matrix: evidence compared with limits, margins, statuses.
//! - [`trace`]: the `verifies!` macro that traces tests to requirement IDs.
//!
//! This crate depends on no model crate: models <- framework <- CLI.

#![warn(missing_docs)]
mod cas;
pub mod check;
pub mod credibility;
pub mod disposition;
pub mod document;
pub mod matrix;
pub mod pedigree;
pub mod requirement;
pub mod spectrum;
pub mod testrun;
pub mod trace;
pub mod units;

pub use check::{Basis, Check, CheckContext, CheckError, Evidence, Outcome};
pub use requirement::{ReqId, Requirement, Requirements};
pub use units::{Dim, Quantity};
