//! Errors of the capture model: every variant carries the file and line a user needs to fix
//! the input, and displays as one line starting with `file:line:`.

/// Error reading or checking capture inputs (TM states, xlim, state distributions).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CaptureError {
    /// The file could not be read.
    #[error("{file}: {cause}")]
    Io {
        /// File path.
        file: String,
        /// Operating-system cause.
        cause: String,
    },
    /// YAML syntax or type error.
    #[error("{file}:{line}:{column}: {cause}")]
    Yaml {
        /// File path (or label).
        file: String,
        /// 1-based line (0 when unknown).
        line: u64,
        /// 1-based column (0 when unknown).
        column: u64,
        /// Parser message, first line only.
        cause: String,
    },
    /// A key that is not one of the 12 state names.
    #[error("{file}:{line}: unknown state `{name}` (expected one of: {expected})", expected = crate::StateName::list())]
    UnknownState {
        /// File path.
        file: String,
        /// 1-based line of the key.
        line: u64,
        /// The offending key.
        name: String,
    },
    /// A value that parses but is not acceptable (non-finite, not positive, ...).
    #[error("{file}:{line}: {name} = {value}: {cause}")]
    BadValue {
        /// File path.
        file: String,
        /// 1-based line.
        line: u64,
        /// Field or state name.
        name: String,
        /// Offending value as written.
        value: String,
        /// Why it is rejected.
        cause: String,
    },
    /// A required state is absent from a table that must list all 12.
    #[error("{file}:{line}: `{section}` lacks state `{name}` (all of {expected} are required)", expected = crate::StateName::list())]
    Missing {
        /// File path.
        file: String,
        /// 1-based line of the table (its first entry when the position of the key is unknown).
        line: u64,
        /// Section of the file (`xlim`, `requirement`).
        section: String,
        /// Missing state.
        name: String,
    },
}

impl CaptureError {
    /// Wraps a serde-saphyr error with the file name and its location.
    pub(crate) fn yaml(file: &str, e: &serde_saphyr::Error) -> Self {
        let y = geodesic_util::yaml_error(e);
        CaptureError::Yaml {
            file: file.to_owned(),
            line: y.line.unwrap_or(0),
            column: y.column.unwrap_or(0),
            cause: y.cause,
        }
    }
}
