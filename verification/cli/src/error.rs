//! The binary's error type: [`geodesic_verify::Error`] (every failure maps to an exit status
//! and a one-line cause; `main` prints `geodesic: <cause>` on standard error).

pub use geodesic_verify::error::{CmdResult, Error as CliError};
