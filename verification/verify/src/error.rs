//! The error of a verification run or a command: every failure maps to an exit status and a
//! one-line cause.
//!
//! Library crates return their own `thiserror` enums carrying file, line and value; the
//! pipeline and the commands turn them into [`Error`] and `main` prints `<program>: <cause>` on
//! standard error.

use std::fmt;

/// A failure of a run or a command, with the exit status it maps to (2).
#[derive(Debug)]
pub enum Error {
    /// Bad input or usage (exit 2): malformed YAML or CSV, unknown IDs, units, effects, NaN,
    /// non-monotonic time, solver failure. The message is one line and names file and line.
    BadInput(String),
    /// An I/O failure writing outputs (exit 2).
    Io(String),
}

impl Error {
    /// Bad input with a one-line cause.
    pub fn bad(msg: impl Into<String>) -> Self {
        Error::BadInput(msg.into())
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            // keep it one line whatever the source error printed
            Error::BadInput(m) | Error::Io(m) => {
                let one: Vec<&str> = m.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
                write!(f, "{}", one.join(" | "))
            }
        }
    }
}

impl std::error::Error for Error {}

impl From<geodesic_util::output::WriteError> for Error {
    fn from(e: geodesic_util::output::WriteError) -> Self {
        Error::Io(e.to_string())
    }
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::Io(e.to_string())
    }
}

/// Result of a command: the process exit status on success (0, or 1 for a verdict of
/// non-compliance), or a [`Error`] (exit 2).
pub type CmdResult = Result<u8, Error>;
