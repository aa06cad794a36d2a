//! Verification activities: a [`Check`] declares the requirement IDs it verifies and, when run,
//! returns [`Evidence`]: a value with its dimension (or the reason it cannot give one) and the
//! inputs that produced it (Monte Carlo N and seed, dataset, test names, ...).
//!
//! Checks live in `geodesic-checks`, one module per family, all listed in one registry that
//! `geodesic verify`, the reports and the tests read.

pub use crate::units::{Dim, Quantity};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A model input file read at run time: what it is, where it came from, its text and hash.
///
/// Model crates parse [`InputFile::text`] themselves (core depends on no model crate); the
/// reports name [`InputFile::label`] and [`InputFile::sha256`] so that an auditor can tell which
/// inputs produced a verdict.
#[derive(Clone, Debug, Serialize)]
pub struct InputFile {
    /// Path as given (or `<built-in>/...` for the copy embedded in the binary).
    pub label: String,
    /// The file's text.
    #[serde(skip)]
    pub text: String,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
}

impl InputFile {
    /// An input file from its label and text (hashes the text).
    pub fn new(label: impl Into<String>, text: impl Into<String>) -> Self {
        let text = text.into();
        InputFile {
            label: label.into(),
            sha256: crate::hash::sha256_hex(text.as_bytes()),
            text,
        }
    }

    /// Reads a file whole; the error names the file.
    pub fn read(path: &std::path::Path) -> Result<Self, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let b = e.as_bytes();
            let line = b[..at].iter().filter(|c| **c == b'\n').count() + 1;
            format!("{}:{line}: not UTF-8 text", path.display())
        })?;
        Ok(InputFile::new(path.display().to_string(), text))
    }
}

/// The model input files of a run (release budget, capture limits and state distribution).
#[derive(Clone, Debug, Serialize)]
pub struct ModelInputs {
    /// The release Monte Carlo uncertainty budget (`models/release/budget.yaml` format).
    pub budget: InputFile,
    /// The capture inputs: xlim and the state sources (`models/capture/capture.yaml` format).
    pub capture: InputFile,
    /// A mission's design inputs read by its checks (e.g. the Drag-Free CubeSat housing:
    /// `missions/drag-free-cubesat/design.yaml`); `None`: the checks use their built-in copy.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub design: Option<InputFile>,
    /// Time series judged by the spectral check, by requirement ID (the series YAML; its CSV's
    /// hash is in the evidence).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub series: BTreeMap<String, InputFile>,
}

/// What a check is given to run.
#[derive(Clone, Debug)]
pub struct CheckContext {
    /// The loaded requirement set: checks read limits from it (a flow-down is computed from
    /// these, never from constants).
    pub requirements: std::sync::Arc<crate::Requirements>,
    /// The model input files.
    pub inputs: std::sync::Arc<ModelInputs>,
    /// Directory where the check may write artifacts (plots); paths in [`Evidence::artifacts`]
    /// are relative to it.
    pub reports_dir: PathBuf,
    /// Monte Carlo sample count [-].
    pub mc_n: usize,
    /// Monte Carlo seed.
    pub seed: u64,
    /// No progress output.
    pub quiet: bool,
}

/// The result a check gives for one requirement.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Outcome {
    /// A value, in SI with its dimension, to compare with the requirement's limit.
    Measured(Quantity),
    /// The activity cannot provide a value; the reason is shown in the matrix.
    NotVerified(String),
}

/// What a measured value rests on: the first thing an auditor asks of a verdict.
///
/// Only [`Basis::Model`], [`Basis::FlowDown`] and [`Basis::Measurement`] evidence can make a
/// requirement plainly compliant; [`Basis::Accepted`] gives a verdict that reads "accepted" everywhere, and
/// [`Basis::Illustration`] is shown beside the row but never decides it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Basis {
    /// Computed by a model from inputs that a model change can move.
    Model,
    /// Computed at run time from the loaded requirements and other rows' evidence (never from
    /// constants).
    FlowDown,
    /// Computed from measured data supplied at run time (a test record, e.g. a time series
    /// whose spectrum a check judges).
    Measurement,
    /// A result taken from a cited external source (e.g. the thesis's E2E simulation).
    Accepted,
    /// A what-if, shown beside the row, never a verdict.
    Illustration,
}

impl Basis {
    /// The basis as written in JSON (`model`, `flow-down`, `measurement`, `accepted`,
    /// `illustration`).
    pub fn as_str(self) -> &'static str {
        match self {
            Basis::Model => "model",
            Basis::FlowDown => "flow-down",
            Basis::Measurement => "measurement",
            Basis::Accepted => "accepted",
            Basis::Illustration => "illustration",
        }
    }

    /// Whether evidence on this basis may decide a verdict.
    pub fn decides(self) -> bool {
        self != Basis::Illustration
    }
}

impl std::fmt::Display for Basis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Evidence for one requirement.
#[derive(Clone, Debug, Serialize)]
pub struct Evidence {
    /// Requirement ID the evidence is for.
    pub requirement: String,
    /// Value or reason.
    pub outcome: Outcome,
    /// What a measured value rests on (`None` for [`Outcome::NotVerified`]).
    pub basis: Option<Basis>,
    /// One sentence: what produced the value.
    pub activity: String,
    /// Inputs that produced it (N, seed, case, dataset, ...).
    pub inputs: BTreeMap<String, serde_json::Value>,
    /// Files written (relative to the reports directory).
    pub artifacts: Vec<String>,
}

impl Evidence {
    /// Evidence with a measured value on a stated `basis`.
    pub fn measured(
        requirement: &str,
        value: Quantity,
        basis: Basis,
        activity: impl Into<String>,
    ) -> Self {
        Evidence {
            requirement: requirement.to_string(),
            outcome: Outcome::Measured(value),
            basis: Some(basis),
            activity: activity.into(),
            inputs: BTreeMap::new(),
            artifacts: Vec::new(),
        }
    }

    /// Evidence that the requirement is not verified, with the reason.
    pub fn not_verified(
        requirement: &str,
        reason: impl Into<String>,
        activity: impl Into<String>,
    ) -> Self {
        Evidence {
            requirement: requirement.to_string(),
            outcome: Outcome::NotVerified(reason.into()),
            basis: None,
            activity: activity.into(),
            inputs: BTreeMap::new(),
            artifacts: Vec::new(),
        }
    }

    /// Adds an input.
    pub fn with_input(mut self, key: &str, value: impl Into<serde_json::Value>) -> Self {
        self.inputs.insert(key.to_string(), value.into());
        self
    }

    /// Adds an artifact path (relative to the reports directory).
    pub fn with_artifact(mut self, path: impl Into<String>) -> Self {
        self.artifacts.push(path.into());
        self
    }
}

/// A check failed to run (a solver failure, a bad configuration): a one-line cause.
#[derive(Clone, Debug, thiserror::Error)]
#[error("{0}")]
pub struct CheckError(pub String);

/// A verification activity.
pub trait Check: Send + Sync {
    /// Stable name of the activity (`release-montecarlo`), referenced by `check:` in YAML.
    fn name(&self) -> &'static str;
    /// Requirement IDs this check provides evidence for.
    fn verifies(&self) -> &'static [&'static str];
    /// Runs the activity.
    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError>;
}

/// One row of a comparison with a reference (the thesis's figures): stated in the reports next to
/// the compliance matrix, with the assumptions that produced it.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceRow {
    /// What is compared (with its definition).
    pub figure: String,
    /// geodesic's value, with unit.
    pub value: String,
    /// The reference value, with unit and source.
    pub reference: String,
    /// Relative difference (`-11 %`), or `-` where it does not apply.
    pub difference: String,
    /// Assumptions or why it differs.
    pub note: String,
}
