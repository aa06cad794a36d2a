//! geodesic-verify: the verify pipeline as a library, for the `geodesic` command line and for
//! any project that verifies its own system with geodesic.
//!
//! - [`mission`]: a mission is a descriptor (`mission.yaml`: its requirement sets, input files,
//!   document, dispositions, baseline, reference table) plus its checks;
//! - [`pipeline`]: resolve inputs -> run checks -> matrix -> compare with a baseline -> write
//!   every report format ([`geodesic_report::formats`]), whole or not at all;
//! - [`harness`]: a project's own `main` in one line (`geodesic_verify::harness::main(mission)`),
//!   the pattern of criterion's or libtest-mimic's harness;
//! - [`error`]: the run's [`Error`], an enum matched by kind of failure ([`Error::Usage`],
//!   [`Error::Input`] with its [`InputKind`], file and line, [`Error::Model`], [`Error::Check`],
//!   [`Error::Io`]); every kind exits with status 2 and prints one line.
//!
//! The crate names no mission.

#![warn(missing_docs)]
pub mod error;
pub mod harness;
mod ids;
pub mod mission;
mod only;
pub mod pipeline;
pub mod plugin;
pub mod preflight;
pub mod progress;
pub mod quantity;
pub mod requirements;
pub mod scaffold;
pub mod schema;
pub mod usage;

pub use error::{Error, InputKind};
pub use mission::{InputSpec, Mission, MissionSpec, Session};
pub use pipeline::{Options, Outcome};
