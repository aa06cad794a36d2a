//! The binary's error type: every failure maps to an exit status and a one-line cause.
//!
//! Library crates return their own `thiserror` enums carrying file, line and value; the CLI
//! turns them into [`CliError`] and `main` prints `geodesic: <cause>` on standard error.

use std::fmt;

/// A failure of a `geodesic` command, with the exit status it maps to.
#[derive(Debug)]
pub enum CliError {
    /// Bad input or usage (exit 2): malformed YAML or CSV, unknown IDs, units, effects, NaN,
    /// non-monotonic time, solver failure. The message is one line and names file and line.
    BadInput(String),
    /// An I/O failure writing outputs (exit 2).
    Io(String),
}

impl CliError {
    /// Bad input with a one-line cause.
    pub fn bad(msg: impl Into<String>) -> Self {
        CliError::BadInput(msg.into())
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            // keep it one line whatever the source error printed
            CliError::BadInput(m) | CliError::Io(m) => {
                let one: Vec<&str> = m.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
                write!(f, "{}", one.join(" | "))
            }
        }
    }
}

impl std::error::Error for CliError {}

impl From<geodesic_util::output::WriteError> for CliError {
    fn from(e: geodesic_util::output::WriteError) -> Self {
        CliError::Io(e.to_string())
    }
}

impl From<std::io::Error> for CliError {
    fn from(e: std::io::Error) -> Self {
        CliError::Io(e.to_string())
    }
}

/// Result of a command: the process exit status on success (0, or 1 for a verdict of
/// non-compliance), or a [`CliError`] (exit 2).
pub type CmdResult = Result<u8, CliError>;
