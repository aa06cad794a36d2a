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
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct InputFile {
    /// Path as given (or `<built-in>/...` for the copy embedded in the binary).
    pub label: String,
    /// The file's text.
    #[serde(skip)]
    pub text: String,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
    /// Where a model input was resolved from: the file given with its flag, the repository's
    /// copy in the current directory, or the copy built into the binary (`None` for a file
    /// read otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub origin: Option<InputOrigin>,
    /// Every parameter of a model input by path, its value as written in flow style (issue
    /// 49): what the gate compares with the baseline's ("input changed, needs review"). Empty
    /// until [`InputFile::with_parameters`] fills it (the verify pipeline does for each
    /// declared input).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub parameters: BTreeMap<String, String>,
    /// The pedigree each parameter states (`measured`, `calibrated`, `cited`, `design`,
    /// `assumed`), by path ([`crate::pedigree`]); what the credibility assessment's input
    /// pedigree factor reads.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub pedigree: BTreeMap<String, crate::pedigree::Kind>,
}

/// Where a model input file came from (`geodesic` resolves every model input the same way:
/// the file given with its flag, else the repository's copy when run from the repository's
/// root, else the copy built into the binary).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum InputOrigin {
    /// Given with its flag (`--design FILE.yaml`, ...).
    Given,
    /// The mission's copy (the path its descriptor declares) in the current directory.
    Repository,
    /// The copy built into the binary.
    BuiltIn,
}

impl InputOrigin {
    /// In words: `given`, `the repository's copy`, `the built-in copy`.
    pub fn words(self) -> &'static str {
        match self {
            InputOrigin::Given => "given",
            InputOrigin::Repository => "the repository's copy",
            InputOrigin::BuiltIn => "the built-in copy",
        }
    }
}

impl InputFile {
    /// An input file from its label and text (hashes the text).
    pub fn new(label: impl Into<String>, text: impl Into<String>) -> Self {
        let text = text.into();
        InputFile {
            label: label.into(),
            sha256: geodesic_util::hash::sha256_hex(text.as_bytes()),
            text,
            origin: None,
            parameters: BTreeMap::new(),
            pedigree: BTreeMap::new(),
        }
    }

    /// The same file with its parameters and their pedigree read from its YAML
    /// ([`crate::pedigree::parameters`], [`crate::pedigree::kinds`]); nothing for a file that
    /// is no YAML.
    pub fn with_parameters(mut self) -> Self {
        self.parameters = crate::pedigree::parameters(&self.text);
        self.pedigree = crate::pedigree::kinds(&self.text);
        self
    }

    /// The same file, stating where it was resolved from.
    pub fn with_origin(mut self, origin: InputOrigin) -> Self {
        self.origin = Some(origin);
        self
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

/// The input files of a run, by the name its mission declares them under (e.g. `design`), each
/// with its text, where it came from and its SHA-256, and the time series a spectral check
/// judges. The framework knows no input by name: a mission declares its inputs (name, words,
/// default path, built-in copy) and its checks read them with [`Inputs::file`].
#[derive(Clone, Debug, Default, Serialize, schemars::JsonSchema)]
pub struct Inputs {
    /// The declared input files by name (in JSON, one key per input).
    #[serde(flatten)]
    pub files: BTreeMap<String, InputFile>,
    /// The declared inputs in declaration order: (name, words for a reader).
    #[serde(skip)]
    pub declared: Vec<(String, String)>,
    /// Time series judged by the spectral check, by requirement ID (the series YAML; its CSV's
    /// hash is in the evidence).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub series: BTreeMap<String, InputFile>,
}

impl Inputs {
    /// Adds (or replaces) the input `name`, described in `words` (`design inputs`).
    pub fn insert(&mut self, name: &str, words: &str, file: InputFile) {
        if !self.declared.iter().any(|(n, _)| n == name) {
            self.declared.push((name.to_string(), words.to_string()));
        }
        self.files.insert(name.to_string(), file);
    }

    /// The input `name`, if the run has it.
    pub fn get(&self, name: &str) -> Option<&InputFile> {
        self.files.get(name)
    }

    /// The input `name`; an error naming it when the run's mission declares no such input.
    pub fn file(&self, name: &str) -> Result<&InputFile, CheckError> {
        self.files.get(name).ok_or_else(|| {
            CheckError::config(format!(
                "no input `{name}` in this run (the mission declares: {})",
                if self.files.is_empty() {
                    "none".to_string()
                } else {
                    self.files.keys().cloned().collect::<Vec<_>>().join(", ")
                }
            ))
        })
    }

    /// The inputs in declaration order: (name, words, file).
    pub fn iter(&self) -> impl Iterator<Item = (&str, &str, &InputFile)> {
        self.declared
            .iter()
            .filter_map(|(n, w)| self.files.get(n).map(|f| (n.as_str(), w.as_str(), f)))
    }
}

/// One run option a mission declares, with its value for a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunOption {
    /// Its key: in `run` of `compliance.json` and for [`CheckContext::option`] (`mc_n`).
    pub key: String,
    /// Its value for the run.
    pub value: u64,
    /// How the reports name it (`N`).
    pub words: String,
    /// The reports' line it is printed on with the other options of the same group
    /// (`Monte Carlo`); empty: a line of its own, named by `words`.
    pub group: String,
}

/// The run options a mission declares (`mission.yaml` `options:`), in declaration order, with
/// their values for a run. `compliance.json` writes each as `"KEY": VALUE` in `run`; the
/// reports print them by group (`Monte Carlo: N = 100000, seed = 1`). A mission that declares
/// none has none, and its reports print no line for them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RunOptions(Vec<RunOption>);

impl RunOptions {
    /// Adds an option (or sets the value of one already there).
    pub fn push(&mut self, option: RunOption) {
        match self.0.iter_mut().find(|o| o.key == option.key) {
            Some(o) => *o = option,
            None => self.0.push(option),
        }
    }

    /// The value of the option `key`.
    pub fn get(&self, key: &str) -> Option<u64> {
        self.0.iter().find(|o| o.key == key).map(|o| o.value)
    }

    /// The options in declaration order.
    pub fn iter(&self) -> impl Iterator<Item = &RunOption> {
        self.0.iter()
    }

    /// Whether the mission declares none.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The keys, comma separated (`none` when there are none).
    pub fn keys(&self) -> String {
        if self.0.is_empty() {
            return "none".into();
        }
        self.0
            .iter()
            .map(|o| o.key.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The reports' lines: `(label, text)` per group in order of first appearance
    /// (`("Monte Carlo", "N = 100000, seed = 1")`), an option without a group on its own
    /// line (`(words, value)`).
    pub fn lines(&self) -> Vec<(&str, String)> {
        let mut out: Vec<(&str, String)> = Vec::new();
        for o in &self.0 {
            if o.group.is_empty() {
                out.push((o.words.as_str(), o.value.to_string()));
            } else if let Some((_, text)) = out.iter_mut().find(|(g, _)| *g == o.group) {
                text.push_str(&format!(", {} = {}", o.words, o.value));
            } else {
                out.push((o.group.as_str(), format!("{} = {}", o.words, o.value)));
            }
        }
        out
    }
}

impl Serialize for RunOptions {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for o in &self.0 {
            m.serialize_entry(&o.key, &o.value)?;
        }
        m.end()
    }
}

impl schemars::JsonSchema for RunOptions {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "RunOptions".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "description": "The run options the mission declares, by key (e.g. `mc_n`, `seed`): whole numbers",
            "type": "object",
            "additionalProperties": {"type": "integer", "minimum": 0}
        })
    }
}

/// What a check is given to run.
#[derive(Clone, Debug)]
pub struct CheckContext {
    /// The loaded requirement set: checks read limits from it (a flow-down is computed from
    /// these, never from constants).
    pub requirements: std::sync::Arc<crate::Requirements>,
    /// The input files.
    pub inputs: std::sync::Arc<Inputs>,
    /// Directory where the check may write artifacts (plots); paths in [`Evidence::artifacts`]
    /// are relative to it.
    pub reports_dir: PathBuf,
    /// The run options the mission declares (its `mission.yaml` `options:`, e.g. a Monte
    /// Carlo sample count and seed), with their values for this run: read them with
    /// [`CheckContext::option`].
    pub options: RunOptions,
    /// Confidence of the bounds a sampled verdict is decided by [-] (0.95 by default).
    pub confidence: f64,
    /// No progress output.
    pub quiet: bool,
}

impl CheckContext {
    /// The value of the run option `key` (its key in the mission's `options:`, e.g. `mc_n`),
    /// as the type the check reads it in; an error when the mission declares no such option or
    /// the value does not fit `T`.
    pub fn option<T: TryFrom<u64>>(&self, key: &str) -> Result<T, CheckError> {
        let v = self.options.get(key).ok_or_else(|| {
            CheckError::config(format!(
                "the run option `{key}` is not declared by the mission (its options: {})",
                self.options.keys()
            ))
        })?;
        T::try_from(v).map_err(|_| {
            CheckError::config(format!(
                "the run option `{key}` = {v} does not fit the type its check reads"
            ))
        })
    }

    /// The probability a requirement states, as a fraction (`None` when it states none or is
    /// not loaded).
    pub fn probability(&self, id: &str) -> Option<f64> {
        self.requirements.get(id).and_then(|r| r.probability_value)
    }
}

/// The result a check gives for one requirement.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
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
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, schemars::JsonSchema,
)]
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
    /// A result taken from a cited external source (e.g. a published end-to-end simulation).
    Accepted,
    /// The accuracy of an analysis method (an image analysis, the fit's uncertainty) shown on
    /// synthetic inputs of known truth: evidence about the tool, not about the product.
    MethodValidation,
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
            Basis::MethodValidation => "method-validation",
            Basis::Illustration => "illustration",
        }
    }

    /// Whether evidence on this basis may decide a verdict.
    pub fn decides(self) -> bool {
        self != Basis::Illustration
    }

    /// The basis as a reader takes it in a verdict (`flow-down`, `method validation`).
    pub fn label(self) -> &'static str {
        match self {
            Basis::MethodValidation => "method validation",
            b => b.as_str(),
        }
    }
}

impl std::fmt::Display for Basis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Evidence for one requirement.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
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
    /// When the value is a statistic of a sample (a Monte Carlo quantile, a probability from
    /// successes): the sample and its exact confidence bounds, by which the matrix decides.
    pub sampling: Option<Sampling>,
    /// Requirement IDs whose limits this value takes as met (a flow-down assumes them): when
    /// one of them is not verified, the verdict says so.
    pub assumes: Vec<String>,
    /// The model input files the value was computed from (the names of [`Inputs`]): a row that judges one of them (see
    /// [`Evidence::judges_input`]) and is non-compliant marks this verdict.
    pub model_inputs: Vec<String>,
    /// The model input file this evidence judges (a calibration check judges the input's
    /// adhesion against a campaign it was not calibrated on).
    pub judges_input: Option<String>,
    /// What the value shows by construction, if it does (a quantity derived from the limit it
    /// is compared with): stated in the verdict.
    pub by_construction: Option<String>,
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
            sampling: None,
            assumes: Vec::new(),
            model_inputs: Vec::new(),
            judges_input: None,
            by_construction: None,
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
            sampling: None,
            assumes: Vec::new(),
            model_inputs: Vec::new(),
            judges_input: None,
            by_construction: None,
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

    /// The sample statistic the value is (see [`Evidence::sampling`]).
    pub fn with_sampling(mut self, s: Sampling) -> Self {
        self.sampling = Some(s);
        self
    }

    /// Requirement IDs whose limits the value takes as met.
    pub fn assuming<I: IntoIterator<Item = S>, S: Into<String>>(mut self, ids: I) -> Self {
        for id in ids {
            let id = id.into();
            if !self.assumes.contains(&id) {
                self.assumes.push(id);
            }
        }
        self
    }

    /// Model input files (names of [`Inputs`]) the value was computed from.
    pub fn from_inputs(mut self, names: &[&str]) -> Self {
        for n in names {
            if !self.model_inputs.iter().any(|m| m == n) {
                self.model_inputs.push(n.to_string());
            }
        }
        self
    }

    /// The model input file this evidence judges.
    pub fn judging_input(mut self, name: &str) -> Self {
        self.judges_input = Some(name.to_string());
        self
    }

    /// What the value shows by construction.
    pub fn by_construction(mut self, why: impl Into<String>) -> Self {
        self.by_construction = Some(why.into());
        self
    }
}

/// What a sampled value is a statistic of.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum SampleStatistic {
    /// The `probability` quantile of a sample (order statistics bound it).
    Quantile,
    /// A probability estimated from successes (Clopper-Pearson bounds it).
    Proportion,
}

/// A value computed from a sample, with its exact confidence bounds (see [`geodesic_util::stats`]).
/// The compliance matrix decides with the bounds, never with the estimate: an upper limit is
/// met when the upper bound meets it, violated when the lower bound violates it, and otherwise
/// (the interval straddles the limit, or the sample cannot give the bound) not verified.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct Sampling {
    /// Quantile or proportion.
    pub statistic: SampleStatistic,
    /// The quantile's level, or the probability a proportion must show [-] (from the
    /// requirement: its `probability`, or its limit for a proportion).
    pub probability: f64,
    /// Confidence of each one-sided bound [-].
    pub confidence: f64,
    /// Sample size.
    pub n: u64,
    /// Successes, for a proportion.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub successes: Option<u64>,
    /// The point estimate (the nearest-rank quantile, or successes / n), in SI in the
    /// evidence and in the requirement's unit in a matrix row.
    pub estimate: f64,
    /// Lower confidence bound (`None`: the sample cannot give one).
    pub lower: Option<f64>,
    /// Upper confidence bound (`None`: the sample cannot give one).
    pub upper: Option<f64>,
    /// Ranks (1-based) of the order statistics that give the bounds, for a quantile.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub lower_rank: Option<u64>,
    /// See `lower_rank`.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub upper_rank: Option<u64>,
    /// The smallest sample that can show the probability at this confidence.
    pub n_required: u64,
    /// How the bounds were computed, in a few words.
    pub method: String,
}

impl Sampling {
    /// The `probability` quantile of `sorted` (ascending; at least one value) with its
    /// order-statistic bounds at `confidence`. `scale` multiplies every value (a quantity
    /// derived monotonically from the sample, e.g. a drift over 15 s).
    pub fn quantile(sorted: &[f64], probability: f64, confidence: f64) -> Sampling {
        use geodesic_util::stats;
        let n = sorted.len() as u64;
        let at = |k: Option<u64>| k.map(|k| sorted[(k - 1) as usize]);
        let lower_rank = stats::quantile_lower_rank(n, probability, confidence);
        let upper_rank = stats::quantile_upper_rank(n, probability, confidence);
        Sampling {
            statistic: SampleStatistic::Quantile,
            probability,
            confidence,
            n,
            successes: None,
            estimate: stats::quantile_sorted(sorted, probability),
            lower: at(lower_rank),
            upper: at(upper_rank),
            lower_rank,
            upper_rank,
            n_required: stats::min_n(probability, confidence),
            method: "distribution-free order-statistic bounds (exact binomial)".into(),
        }
    }

    /// A probability from `successes` of `n` with its Clopper-Pearson bounds at `confidence`;
    /// `probability` is what the requirement asks it to show.
    pub fn proportion(successes: u64, n: u64, probability: f64, confidence: f64) -> Sampling {
        use geodesic_util::stats;
        Sampling {
            statistic: SampleStatistic::Proportion,
            probability,
            confidence,
            n,
            successes: Some(successes),
            estimate: if n == 0 {
                f64::NAN
            } else {
                successes as f64 / n as f64
            },
            lower: (n > 0).then(|| stats::clopper_pearson_lower(successes, n, confidence)),
            upper: (n > 0).then(|| stats::clopper_pearson_upper(successes, n, confidence)),
            lower_rank: None,
            upper_rank: None,
            n_required: stats::min_n(probability, confidence),
            method: "Clopper-Pearson (exact binomial)".into(),
        }
    }

    /// Every value multiplied by `k > 0` (a quantity that grows with the sampled one).
    pub fn scaled(mut self, k: f64) -> Sampling {
        self.estimate *= k;
        self.lower = self.lower.map(|v| v * k);
        self.upper = self.upper.map(|v| v * k);
        self
    }

    /// One line: `99.73 % quantile: upper 95 % bound 1.334 (estimate 1.329; N = 100 000,
    /// order statistic 99 758)`, values formatted by `fmt`.
    pub fn describe(&self, fmt: &dyn Fn(f64) -> String) -> String {
        let pct = |p: f64| crate::units::fmt_pct(p);
        match self.statistic {
            SampleStatistic::Quantile => format!(
                "{} quantile of N = {}: estimate {}, {} % bounds [{}, {}]{}",
                pct(self.probability),
                self.n,
                fmt(self.estimate),
                crate::units::fmt_num(100.0 * self.confidence),
                self.lower.map_or("none".into(), fmt),
                self.upper.map_or("none".into(), fmt),
                if self.upper.is_none() {
                    format!(
                        " (N = {} cannot bound the {} quantile at {} % confidence: need N >= {})",
                        self.n,
                        pct(self.probability),
                        crate::units::fmt_num(100.0 * self.confidence),
                        self.n_required
                    )
                } else {
                    String::new()
                }
            ),
            SampleStatistic::Proportion => format!(
                "{} of {}: estimate {}, {} % Clopper-Pearson bounds [{}, {}]",
                self.successes.unwrap_or(0),
                self.n,
                fmt(self.estimate),
                crate::units::fmt_num(100.0 * self.confidence),
                self.lower.map_or("none".into(), fmt),
                self.upper.map_or("none".into(), fmt),
            ),
        }
    }
}

/// A check failed to run, by kind of failure; `Display` is the one-line cause.
///
/// A caller matches on the variant (and the file and line of [`CheckError::Input`]); the text
/// is the message as printed, naming file and line itself where they are known. Build one with
/// [`CheckError::input`], [`CheckError::model`], [`CheckError::evidence`] or
/// [`CheckError::config`].
#[derive(Clone, Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CheckError {
    /// An input of the check is wrong (malformed, missing a field, out of range).
    #[error("{message}")]
    Input {
        /// The input file (its label), when known.
        file: Option<String>,
        /// The 1-based line in `file`, when known (`None`: the whole file).
        line: Option<usize>,
        /// The one-line message.
        message: String,
    },
    /// A model, solver or simulation the check runs failed.
    #[error("{message}")]
    Model {
        /// What failed (`release Monte Carlo`, `adhesion identification`).
        model: String,
        /// The one-line message.
        message: String,
    },
    /// The evidence cannot be produced or drawn (a plot, a limit the requirement lacks).
    #[error("{0}")]
    Evidence(String),
    /// The run does not give the check what it needs (an input the mission does not declare,
    /// a thread that panicked).
    #[error("{0}")]
    Config(String),
}

impl CheckError {
    /// An input of the check is wrong; add its file and line with [`CheckError::in_file`].
    pub fn input(msg: impl Into<String>) -> Self {
        CheckError::Input {
            file: None,
            line: None,
            message: msg.into(),
        }
    }

    /// The model (solver, simulation) `model` failed.
    pub fn model(model: &str, msg: impl Into<String>) -> Self {
        CheckError::Model {
            model: model.to_string(),
            message: msg.into(),
        }
    }

    /// The evidence cannot be produced or drawn.
    pub fn evidence(msg: impl Into<String>) -> Self {
        CheckError::Evidence(msg.into())
    }

    /// The run does not give the check what it needs.
    pub fn config(msg: impl Into<String>) -> Self {
        CheckError::Config(msg.into())
    }

    /// The same error, stating the input file (and 1-based line, 0 for the whole file) it is
    /// in; the message is unchanged. No effect on kinds other than [`CheckError::Input`].
    pub fn in_file(mut self, at: &str, at_line: usize) -> Self {
        if let CheckError::Input { file, line, .. } = &mut self {
            *file = Some(at.to_string());
            *line = (at_line > 0).then_some(at_line);
        }
        self
    }

    /// The input file, for [`CheckError::Input`] when known.
    pub fn file(&self) -> Option<&str> {
        match self {
            CheckError::Input { file, .. } => file.as_deref(),
            _ => None,
        }
    }

    /// The 1-based line, for [`CheckError::Input`] when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            CheckError::Input { line, .. } => *line,
            _ => None,
        }
    }

    /// The one-line message (as `Display` prints it).
    pub fn message(&self) -> &str {
        match self {
            CheckError::Input { message, .. } | CheckError::Model { message, .. } => message,
            CheckError::Evidence(m) | CheckError::Config(m) => m,
        }
    }
}

/// Whether `check` has work in a requirement set: one of the IDs it declares is loaded, or a
/// loaded requirement names it in `check:` (a generic check such as `spectral-asd`).
pub fn is_wanted(check: &dyn Check, reqs: &crate::Requirements) -> bool {
    check.verifies().iter().any(|id| reqs.get(id).is_some())
        || reqs
            .items
            .iter()
            .any(|r| r.check.as_deref() == Some(check.name()))
}

/// A verification activity.
pub trait Check: Send + Sync {
    /// Stable name of the activity (`release-montecarlo`), referenced by `check:` in YAML.
    fn name(&self) -> &'static str;
    /// Requirement IDs this check provides evidence for.
    fn verifies(&self) -> &'static [&'static str];
    /// Model input files (names of [`Inputs`]) whose validity this check judges
    /// (its evidence carries [`Evidence::judges_input`]): a row computed from such an input
    /// depends on this check's verdict (`verify --only` runs it too). None by default.
    fn judges(&self) -> &'static [&'static str] {
        &[]
    }
    /// Runs the activity.
    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError>;
}

/// One row of a comparison with a reference (e.g. a reference document's figures): stated in the reports next to
/// the compliance matrix, with the assumptions that produced it.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
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

impl ReferenceRow {
    /// A row: the figure compared, geodesic's value, the reference, their difference and the
    /// note (the assumptions, or why it differs).
    pub fn new(
        figure: &str,
        value: String,
        reference: String,
        difference: String,
        note: &str,
    ) -> ReferenceRow {
        ReferenceRow {
            figure: figure.into(),
            value,
            reference,
            difference,
            note: note.into(),
        }
    }

    /// The relative difference of `value` from `reference` (same unit), as the table writes it:
    /// `+12 %`, `-3 %`.
    pub fn percent(value: f64, reference: f64) -> String {
        format!("{:+.0} %", 100.0 * (value - reference) / reference)
    }
}
