//! The error of a verification run or a command: every failure maps to an exit status (2) and a
//! one-line cause.
//!
//! [`Error`] is an enum a caller matches on by kind of failure: [`Error::Usage`] (a bad flag or
//! option combination), [`Error::Input`] (a bad input file or value, with its [`InputKind`], the
//! file and the line when known), [`Error::Model`] (a model or solver failed),
//! [`Error::Check`] (a check failed to run, with the check's name and its typed
//! [`CheckError`]) and [`Error::Io`] (writing an output failed). Library errors keep their
//! structure: `From` impls fill the file and line from the library's own fields and keep the
//! library error as the [`std::error::Error::source`] of the run's error (downcast it to match
//! on it).
//!
//! `main` prints `<program>: <cause>` on standard error: `Display` is the one-line message
//! (`message` fields hold it whole, naming file and line themselves where they are known).
//!
//! ```
//! use geodesic_verify::error::{Error, InputKind};
//! let e = Error::input(InputKind::UnknownId, "reqs.yaml:3: unknown requirement `R-9`")
//!     .in_file("reqs.yaml", 3);
//! match &e {
//!     Error::Input { kind: InputKind::UnknownId, file: Some(f), line: Some(3), .. } => {
//!         assert_eq!(f.to_str(), Some("reqs.yaml"))
//!     }
//!     other => panic!("{other:?}"),
//! }
//! assert_eq!(e.to_string(), "reqs.yaml:3: unknown requirement `R-9`");
//! ```

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use geodesic_core::check::CheckError;
use geodesic_core::requirement::LoadKind;

/// The library error a run's error came from, kept whole (see [`std::error::Error::source`]).
pub type Source = Arc<dyn std::error::Error + Send + Sync + 'static>;

/// What is wrong with an input ([`Error::Input`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum InputKind {
    /// The file cannot be read (missing, not a regular file, too large, not UTF-8).
    Unreadable,
    /// Malformed YAML, CSV or JSON, or a field of the wrong shape.
    Malformed,
    /// An unknown requirement ID.
    UnknownId,
    /// An unknown unit, or a quantity that is not a number with a unit.
    UnknownUnit,
    /// An unknown effect, term or model name.
    UnknownEffect,
    /// An unknown name of something else: a check, an input, a format, a mission, a family.
    UnknownName,
    /// A value is NaN or infinite.
    NotFinite,
    /// A value outside its allowed range or otherwise invalid.
    Invalid,
    /// Two inputs or options that contradict each other (given twice, both given).
    Conflict,
    /// Evidence that is stale, missing or unusable (a recorded test run, a baseline).
    Evidence,
}

/// A failure of a run or a command; every kind maps to exit status 2.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum Error {
    /// A bad flag or option combination; the message names the flag.
    Usage(String),
    /// A bad input file or value.
    Input {
        /// The file, when the failure is in one.
        file: Option<PathBuf>,
        /// The 1-based line in `file`, when known (`None`: the whole file).
        line: Option<usize>,
        /// What is wrong.
        kind: InputKind,
        /// The one-line message (it names file and line itself).
        message: String,
        /// The library error it came from, if any.
        source: Option<Source>,
    },
    /// A model or solver failed.
    Model {
        /// The model, solver or computation that failed, when named.
        model: Option<String>,
        /// The one-line message.
        message: String,
        /// The library error it came from, if any.
        source: Option<Source>,
    },
    /// A check failed to run (printed `check NAME: CAUSE`).
    Check {
        /// The check's name (`release-montecarlo`).
        check: String,
        /// Why.
        source: CheckError,
    },
    /// Writing an output (or another I/O operation) failed.
    Io {
        /// The path, when known.
        path: Option<PathBuf>,
        /// The one-line message.
        message: String,
    },
}

impl Error {
    /// A bad flag or option combination.
    pub fn usage(msg: impl Into<String>) -> Self {
        Error::Usage(msg.into())
    }

    /// A bad input of kind `kind`; add the file and line with [`Error::in_file`].
    pub fn input(kind: InputKind, msg: impl Into<String>) -> Self {
        Error::Input {
            file: None,
            line: None,
            kind,
            message: msg.into(),
            source: None,
        }
    }

    /// A file that cannot be read ([`InputKind::Unreadable`]).
    pub fn unreadable(msg: impl Into<String>) -> Self {
        Error::input(InputKind::Unreadable, msg)
    }

    /// Malformed YAML, CSV or JSON ([`InputKind::Malformed`]).
    pub fn malformed(msg: impl Into<String>) -> Self {
        Error::input(InputKind::Malformed, msg)
    }

    /// An unknown requirement ID ([`InputKind::UnknownId`]).
    pub fn unknown_id(msg: impl Into<String>) -> Self {
        Error::input(InputKind::UnknownId, msg)
    }

    /// An unknown unit ([`InputKind::UnknownUnit`]).
    pub fn unknown_unit(msg: impl Into<String>) -> Self {
        Error::input(InputKind::UnknownUnit, msg)
    }

    /// An unknown effect, term or model ([`InputKind::UnknownEffect`]).
    pub fn unknown_effect(msg: impl Into<String>) -> Self {
        Error::input(InputKind::UnknownEffect, msg)
    }

    /// An unknown name (check, input, format, mission) ([`InputKind::UnknownName`]).
    pub fn unknown_name(msg: impl Into<String>) -> Self {
        Error::input(InputKind::UnknownName, msg)
    }

    /// A NaN or infinite value ([`InputKind::NotFinite`]).
    pub fn not_finite(msg: impl Into<String>) -> Self {
        Error::input(InputKind::NotFinite, msg)
    }

    /// A value out of range or otherwise invalid ([`InputKind::Invalid`]).
    pub fn invalid(msg: impl Into<String>) -> Self {
        Error::input(InputKind::Invalid, msg)
    }

    /// Inputs or options that contradict each other ([`InputKind::Conflict`]).
    pub fn conflict(msg: impl Into<String>) -> Self {
        Error::input(InputKind::Conflict, msg)
    }

    /// Stale, missing or unusable evidence ([`InputKind::Evidence`]).
    pub fn evidence(msg: impl Into<String>) -> Self {
        Error::input(InputKind::Evidence, msg)
    }

    /// A bad input of kind `kind` whose cause is the library error `e` (kept as the source).
    pub fn input_from(kind: InputKind, e: impl std::error::Error + Send + Sync + 'static) -> Self {
        Error::Input {
            file: None,
            line: None,
            kind,
            message: e.to_string(),
            source: Some(Arc::new(e)),
        }
    }

    /// A model or solver failure (`model`: what failed, when named).
    pub fn model(model: Option<&str>, msg: impl Into<String>) -> Self {
        Error::Model {
            model: model.map(str::to_string),
            message: msg.into(),
            source: None,
        }
    }

    /// The model (or computation) `model` failed with the library error `e`, printed
    /// `MODEL: CAUSE` (`e` is kept as the source).
    pub fn model_from(model: &str, e: impl std::error::Error + Send + Sync + 'static) -> Self {
        Error::Model {
            model: Some(model.to_string()),
            message: format!("{model}: {e}"),
            source: Some(Arc::new(e)),
        }
    }

    /// A check named `check` failed to run.
    pub fn check(check: &str, source: CheckError) -> Self {
        Error::Check {
            check: check.to_string(),
            source,
        }
    }

    /// An I/O failure with no path named.
    pub fn io(msg: impl fmt::Display) -> Self {
        Error::Io {
            path: None,
            message: msg.to_string(),
        }
    }

    /// An I/O failure on `path`, printed `PATH: CAUSE`.
    pub fn io_at(path: &Path, cause: impl fmt::Display) -> Self {
        Error::Io {
            path: Some(path.to_path_buf()),
            message: format!("{}: {cause}", path.display()),
        }
    }

    /// The same error, stating the file (and the 1-based line, 0 for the whole file) it is in;
    /// the message is unchanged. No effect on kinds that carry no file.
    pub fn in_file(mut self, at: impl AsRef<Path>, at_line: usize) -> Self {
        match &mut self {
            Error::Input { file, line, .. } => {
                *file = Some(at.as_ref().to_path_buf());
                *line = (at_line > 0).then_some(at_line);
            }
            Error::Io { path, .. } => *path = Some(at.as_ref().to_path_buf()),
            _ => {}
        }
        self
    }

    /// The same error with the input kind `k` (for [`Error::Input`]; no effect on others).
    pub fn with_kind(mut self, k: InputKind) -> Self {
        if let Error::Input { kind, .. } = &mut self {
            *kind = k;
        }
        self
    }

    /// The input kind, for [`Error::Input`].
    pub fn kind(&self) -> Option<InputKind> {
        match self {
            Error::Input { kind, .. } => Some(*kind),
            _ => None,
        }
    }

    /// The file the failure is in, when known.
    pub fn file(&self) -> Option<&Path> {
        match self {
            Error::Input { file, .. } => file.as_deref(),
            Error::Io { path, .. } => path.as_deref(),
            Error::Check { source, .. } => source.file().map(Path::new),
            _ => None,
        }
    }

    /// The 1-based line the failure is at, when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            Error::Input { line, .. } => *line,
            Error::Check { source, .. } => source.line(),
            _ => None,
        }
    }

    /// The exit status of the process for this error: 2 for every kind.
    pub fn exit_status(&self) -> u8 {
        2
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let whole = match self {
            Error::Usage(m) => m.clone(),
            Error::Input { message, .. }
            | Error::Model { message, .. }
            | Error::Io { message, .. } => message.clone(),
            Error::Check { check, source } => format!("check {check}: {source}"),
        };
        // keep it one line whatever the source error printed
        let one: Vec<&str> = whole
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect();
        write!(f, "{}", one.join(" | "))
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Input { source, .. } | Error::Model { source, .. } => source
                .as_deref()
                .map(|s| s as &(dyn std::error::Error + 'static)),
            Error::Check { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<geodesic_util::output::WriteError> for Error {
    fn from(e: geodesic_util::output::WriteError) -> Self {
        Error::io(e)
    }
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::io(e)
    }
}

/// A check's error outside a run of the check (a command that calls a check's helper): an
/// input error stays an [`Error::Input`] ([`InputKind::Invalid`], with its file and line), a
/// model failure an [`Error::Model`], an unusable evidence an [`Error::Input`] of kind
/// [`InputKind::Evidence`], a missing requirement or input an [`Error::Usage`]; the message is
/// the check's.
impl From<CheckError> for Error {
    fn from(e: CheckError) -> Self {
        let message = e.to_string();
        match &e {
            CheckError::Input { file, line, .. } => Error::Input {
                file: file.as_ref().map(PathBuf::from),
                line: *line,
                kind: InputKind::Invalid,
                message,
                source: Some(Arc::new(e)),
            },
            CheckError::Model { model, .. } => Error::Model {
                model: Some(model.clone()),
                message,
                source: Some(Arc::new(e)),
            },
            CheckError::Evidence(_) => Error::Input {
                file: None,
                line: None,
                kind: InputKind::Evidence,
                message,
                source: Some(Arc::new(e)),
            },
            _ => Error::Usage(message),
        }
    }
}

/// A requirements, dispositions or document file refused, at its file and line, of the kind
/// its [`LoadKind`] says (a YAML error is [`InputKind::Malformed`], an unknown check
/// [`InputKind::UnknownName`]).
impl From<geodesic_core::requirement::LoadError> for Error {
    fn from(e: geodesic_core::requirement::LoadError) -> Self {
        let kind = match e.kind {
            LoadKind::Unreadable => InputKind::Unreadable,
            LoadKind::Syntax => InputKind::Malformed,
            LoadKind::UnknownId => InputKind::UnknownId,
            LoadKind::UnknownUnit => InputKind::UnknownUnit,
            LoadKind::UnknownCheck => InputKind::UnknownName,
            LoadKind::NotFinite => InputKind::NotFinite,
            _ => InputKind::Invalid,
        };
        let (file, line) = (e.origin.file.clone(), e.origin.line as usize);
        Error::input_from(kind, e).in_file(file, line)
    }
}

/// A unit or quantity refused: [`InputKind::NotFinite`] for a NaN or infinite number,
/// [`InputKind::UnknownUnit`] otherwise.
impl From<geodesic_core::units::UnitError> for Error {
    fn from(e: geodesic_core::units::UnitError) -> Self {
        let kind = match e {
            geodesic_core::units::UnitError::NotFinite(..) => InputKind::NotFinite,
            _ => InputKind::UnknownUnit,
        };
        Error::input_from(kind, e)
    }
}

/// A file that cannot be read: [`InputKind::Unreadable`].
impl From<geodesic_util::fsio::ReadError> for Error {
    fn from(e: geodesic_util::fsio::ReadError) -> Self {
        Error::input_from(InputKind::Unreadable, e)
    }
}

/// Result of a command: the process exit status on success (0, or 1 for a verdict of
/// non-compliance), or a [`Error`] (exit 2).
pub type CmdResult = Result<u8, Error>;
