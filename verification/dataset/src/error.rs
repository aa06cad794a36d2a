//! Errors of dataset loading, fitting and report writing, each naming file and line.

use geodesic_util::text::one_line;

/// A failure of the fit crate, with the data a user needs to fix the input.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// Bad input at a known place: `file:line: cause` (line 0: the whole file).
    #[error("{}", fmt_at(.file, *.line, .cause))]
    Input {
        /// The file.
        file: String,
        /// 1-based line, 0 when unknown.
        line: usize,
        /// What is wrong.
        cause: String,
    },
    /// Writing an output failed.
    #[error("{}: cannot write: {}", one_line(.path), one_line(.cause))]
    Write {
        /// The output path.
        path: String,
        /// The I/O error.
        cause: String,
    },
}

fn fmt_at(file: &str, line: usize, cause: &str) -> String {
    // a file name or a quoted input may hold a line break: the message stays on one line
    let (file, cause) = (one_line(file), one_line(cause));
    if line > 0 {
        format!("{file}:{line}: {cause}")
    } else {
        format!("{file}: {cause}")
    }
}

impl FitError {
    /// Bad input at `file:line`.
    pub fn input(file: impl Into<String>, line: usize, cause: impl Into<String>) -> Self {
        FitError::Input {
            file: file.into(),
            line,
            cause: cause.into(),
        }
    }
}

/// Writes `bytes` to `path` whole or not at all, creating the folder if needed
/// ([`geodesic_util::output::write_whole`]: a temporary file beside it, then a rename; the
/// temporary file is removed on failure or interruption).
pub fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> Result<(), FitError> {
    geodesic_util::output::write_whole(path, bytes)
        .map(|_| ())
        .map_err(|e| FitError::Write {
            path: path.display().to_string(),
            cause: e.cause,
        })
}
