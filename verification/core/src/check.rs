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

/// What a check is given to run.
#[derive(Clone, Debug)]
pub struct CheckContext {
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

/// Evidence for one requirement.
#[derive(Clone, Debug, Serialize)]
pub struct Evidence {
    /// Requirement ID the evidence is for.
    pub requirement: String,
    /// Value or reason.
    pub outcome: Outcome,
    /// One sentence: what produced the value.
    pub activity: String,
    /// Inputs that produced it (N, seed, case, dataset, ...).
    pub inputs: BTreeMap<String, serde_json::Value>,
    /// Files written (relative to the reports directory).
    pub artifacts: Vec<String>,
}

impl Evidence {
    /// Evidence with a measured value.
    pub fn measured(requirement: &str, value: Quantity, activity: impl Into<String>) -> Self {
        Evidence {
            requirement: requirement.to_string(),
            outcome: Outcome::Measured(value),
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
