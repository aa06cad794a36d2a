//! Requirements in YAML: loaded in two steps, raw (serde, with source spans) then checked
//! (units parsed, dimensions matched, IDs unique, parents resolved and their margins consistent).
//!
//! One file per family under `requirements/`. Every entry has an `id`, `title`, `text` (a
//! "shall" statement), `source` (a specification's table or section), `quantity` and its `dimension`, a
//! `limit` written as engineers write it (`<= 5 um/s`), the verification `method` (ECSS-E-ST-10-02C:
//! test, analysis, review-of-design, inspection), the `activity` that provides the evidence, an
//! optional `check` naming the registered check that runs it, and an optional `parent` with the
//! `margin` that links them (child limit = margin x parent limit). Every error names
//! `file:line:column` and its cause in one line.
//!
//! A *qualitative* requirement ("The TM shall be grounded by ...", as most requirements
//! imported from DOORS or Polarion are) has no `limit`, and then none of what is tied to a limit:
//! no `dimension`, `probability`, `check` nor `parent` (a margin links two limits); `quantity` is
//! optional. It is closed by its `method` (review of design, inspection, ...) outside geodesic:
//! `verify` reports it not verified. In [`Requirement`] its [`Requirement::limit`] is `None`.

use crate::units::{Dim, Quantity, Unit, parse_quantity};
use serde::{Deserialize, Serialize};
use serde_saphyr::Spanned;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// A checked requirement identifier: upper-case words and digits joined by `-` (`REL-GPRM-VEL`).
#[derive(
    Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(transparent)]
pub struct ReqId(String);

impl ReqId {
    /// Checks the form of an identifier.
    ///
    /// ```
    /// use geodesic_core::requirement::ReqId;
    /// assert!(ReqId::parse("REL-GPRM-VEL").is_ok());
    /// assert!(ReqId::parse("rel gprm").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<ReqId, String> {
        let ok = !s.is_empty()
            && s.split('-').all(|w| {
                !w.is_empty()
                    && w.chars()
                        .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit())
            })
            && s.starts_with(|c: char| c.is_ascii_uppercase());
        if ok {
            Ok(ReqId(s.to_string()))
        } else {
            Err(format!(
                "`{s}` is not a requirement ID (upper-case words and digits joined by '-', e.g. REL-GPRM-VEL)"
            ))
        }
    }

    /// The identifier text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for ReqId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Verification method (ECSS-E-ST-10-02C section 5.2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Verification by test.
    Test,
    /// Verification by analysis (including similarity and simulation).
    Analysis,
    /// Verification by review of design.
    ReviewOfDesign,
    /// Verification by inspection.
    Inspection,
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Method::Test => "test",
            Method::Analysis => "analysis",
            Method::ReviewOfDesign => "review-of-design",
            Method::Inspection => "inspection",
        })
    }
}

/// How a value is compared with the limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub enum Op {
    /// value <= limit
    #[serde(rename = "<=")]
    Le,
    /// value < limit
    #[serde(rename = "<")]
    Lt,
    /// value >= limit
    #[serde(rename = ">=")]
    Ge,
    /// value > limit
    #[serde(rename = ">")]
    Gt,
}

impl Op {
    /// Whether `value` satisfies `value <op> limit`.
    pub fn holds(self, value: f64, limit: f64) -> bool {
        match self {
            Op::Le => value <= limit,
            Op::Lt => value < limit,
            Op::Ge => value >= limit,
            Op::Gt => value > limit,
        }
    }

    /// Margin as a fraction of the limit: `(limit - value) / limit` for an upper bound,
    /// `(value - limit) / limit` for a lower bound; positive when the requirement is met.
    pub fn margin(self, value: f64, limit: f64) -> f64 {
        match self {
            Op::Le | Op::Lt => (limit - value) / limit.abs(),
            Op::Ge | Op::Gt => (value - limit) / limit.abs(),
        }
    }

    /// The symbol as written in YAML.
    pub fn symbol(self) -> &'static str {
        match self {
            Op::Le => "<=",
            Op::Lt => "<",
            Op::Ge => ">=",
            Op::Gt => ">",
        }
    }
}

/// Verification level (ECSS-E-ST-10-02C section 4.2.3: the level of decomposition at which a
/// requirement is verified).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Level {
    /// Equipment (a unit: the release mechanism, a facility's instrument).
    Equipment,
    /// Subsystem (a sensor with its mechanisms, a power or thermal subsystem).
    Subsystem,
    /// Element (a payload or an instrument package).
    Element,
    /// System (the spacecraft with its attitude and orbit control).
    System,
}

impl Level {
    /// Every level, as written in YAML.
    pub const NAMES: [&'static str; 4] = ["equipment", "subsystem", "element", "system"];

    /// The level as written in YAML.
    pub fn as_str(self) -> &'static str {
        match self {
            Level::Equipment => "equipment",
            Level::Subsystem => "subsystem",
            Level::Element => "element",
            Level::System => "system",
        }
    }

    fn parse(s: &str) -> Option<Level> {
        Some(match s {
            "equipment" => Level::Equipment,
            "subsystem" => Level::Subsystem,
            "element" => Level::Element,
            "system" => Level::System,
            _ => return None,
        })
    }
}

/// Verification stage (ECSS-E-ST-10-02C section 4.2.4: when in the programme the requirement is
/// verified).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Stage {
    /// Qualification: the design meets the requirement with margin (analysis, qualification tests).
    Qualification,
    /// Acceptance: the flight item is free of workmanship defects.
    Acceptance,
    /// Pre-launch, at the launch site.
    PreLaunch,
    /// In orbit (commissioning).
    InOrbit,
    /// Post-landing.
    PostLanding,
}

impl Stage {
    /// Every stage, as written in YAML.
    pub const NAMES: [&'static str; 5] = [
        "qualification",
        "acceptance",
        "pre-launch",
        "in-orbit",
        "post-landing",
    ];

    /// The stage as written in YAML.
    pub fn as_str(self) -> &'static str {
        match self {
            Stage::Qualification => "qualification",
            Stage::Acceptance => "acceptance",
            Stage::PreLaunch => "pre-launch",
            Stage::InOrbit => "in-orbit",
            Stage::PostLanding => "post-landing",
        }
    }

    fn parse(s: &str) -> Option<Stage> {
        Some(match s {
            "qualification" => Stage::Qualification,
            "acceptance" => Stage::Acceptance,
            "pre-launch" => Stage::PreLaunch,
            "in-orbit" => Stage::InOrbit,
            "post-landing" => Stage::PostLanding,
            _ => return None,
        })
    }
}

/// The level and stage a requirement takes when neither it nor its file states them: system,
/// qualification (a mission's requirement files state their own `level:` and `stage:`).
pub fn default_level_stage(_family: &str) -> (Level, Stage) {
    (Level::System, Stage::Qualification)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    family: String,
    #[serde(default)]
    description: Option<String>,
    /// Level of every requirement of the file that does not state its own.
    #[serde(default)]
    level: Option<Spanned<String>>,
    /// Stage of every requirement of the file that does not state its own.
    #[serde(default)]
    stage: Option<Spanned<String>>,
    requirements: Vec<RawRequirement>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRequirement {
    id: Spanned<String>,
    title: String,
    text: String,
    source: String,
    #[serde(default)]
    quantity: Option<Spanned<String>>,
    #[serde(default)]
    dimension: Option<Spanned<String>>,
    #[serde(default)]
    limit: Option<Spanned<String>>,
    #[serde(default)]
    spectrum: Option<RawSpectrum>,
    #[serde(default)]
    probability: Option<Spanned<String>>,
    method: Spanned<String>,
    activity: String,
    #[serde(default)]
    check: Option<Spanned<String>>,
    #[serde(default)]
    parent: Option<RawParent>,
    #[serde(default)]
    note: Option<String>,
    #[serde(default)]
    level: Option<Spanned<String>>,
    #[serde(default)]
    stage: Option<Spanned<String>>,
    #[serde(default)]
    credibility: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpectrum {
    band: Spanned<String>,
    shape: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawParent {
    id: Spanned<String>,
    margin: f64,
}

/// Where something was written: file, line and column (1-based).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, schemars::JsonSchema)]
pub struct Origin {
    /// File path.
    pub file: PathBuf,
    /// Line (1-based).
    pub line: u64,
    /// Column (1-based).
    pub column: u64,
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let file = geodesic_util::text::one_line(&self.file.display().to_string());
        write!(f, "{file}:{}:{}", self.line, self.column)
    }
}

/// The quantitative limit of a requirement: `value <op> limit` in a dimension.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Limit {
    /// Dimension of the quantity (that of the limit).
    pub dim: Dim,
    /// Comparison.
    pub op: Op,
    /// Limit in SI.
    pub value: Quantity,
    /// The unit the limit was written in (values are reported in it).
    pub unit: Unit,
    /// The limit as written (`<= 5 um/s`).
    pub text: String,
}

impl Limit {
    /// The limit's number in its written unit (`7.5` for `<= 7.5 um/s`).
    pub fn in_unit(&self) -> f64 {
        self.value.value / self.unit.scale
    }
}

/// A requirement's `probability` as a fraction in (0, 1): `99.73 %`, `0.9973`, or a
/// percentage with its sigma level, `95.45 % (2 sigma)`, which means the exact two-sided
/// coverage `erf(k / sqrt 2)` of `k` standard deviations (0.954 499 7 for 2) and must agree
/// with the percentage to its written digits.
pub fn parse_probability(text: &str) -> Result<(f64, Option<f64>), String> {
    let t = text.trim();
    let (head, sigma) = match t.split_once('(') {
        Some((h, rest)) => {
            let inner = rest.strip_suffix(')').ok_or_else(|| {
                format!("probability `{t}`: write `99.73 %`, `0.9973` or `95.45 % (2 sigma)`")
            })?;
            let k = inner
                .trim()
                .strip_suffix("sigma")
                .map(str::trim)
                .and_then(|k| k.parse::<f64>().ok())
                .filter(|k| k.is_finite() && *k > 0.0 && *k <= 8.0)
                .ok_or_else(|| {
                    format!(
                        "probability `{t}`: `({inner})` is not a sigma level such as `(2 sigma)`"
                    )
                })?;
            (h.trim(), Some(k))
        }
        None => (t, None),
    };
    let (num, pct) = match head.strip_suffix('%') {
        Some(n) => (n.trim(), true),
        None => (head, false),
    };
    let v: f64 = num.parse().map_err(|_| {
        format!("probability `{t}`: write `99.73 %`, `0.9973` or `95.45 % (2 sigma)`")
    })?;
    // a percentage divided by 100 in binary (99.73 / 100 = 0.9973000000000001): rounded to 15
    // significant digits, the fraction is the number the percentage writes
    let p = if pct {
        format!("{:.14e}", v / 100.0).parse().unwrap_or(v / 100.0)
    } else {
        v
    };
    if !(p.is_finite() && p > 0.0 && p < 1.0) {
        return Err(format!(
            "probability `{t}` is not between 0 and 100 % (exclusive)"
        ));
    }
    match sigma {
        None => Ok((p, None)),
        Some(k) => {
            let exact = 1.0 - geodesic_util::normal::erfc(k / std::f64::consts::SQRT_2);
            // the percentage as written carries its own digits: 95.45 % is good to 0.005 %
            let decimals = num.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
            let half_ulp = 0.5 * 10f64.powi(-decimals) * if pct { 0.01 } else { 1.0 };
            if (exact - p).abs() > half_ulp + 2e-7 {
                return Err(format!(
                    "probability `{t}`: {k} sigma is {:.4} %, not {num}{}",
                    100.0 * exact,
                    if pct { " %" } else { "" }
                ));
            }
            Ok((exact, Some(k)))
        }
    }
}

/// A requirement loaded and checked.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Requirement {
    /// Identifier.
    pub id: ReqId,
    /// Family (the file's `family`).
    pub family: String,
    /// Short title.
    pub title: String,
    /// The "shall" statement.
    pub text: String,
    /// Source (a specification's table or section).
    pub source: String,
    /// What is measured or computed (empty for a qualitative requirement that names none).
    pub quantity: String,
    /// The quantitative limit; `None` for a qualitative requirement (no limit: closed by its
    /// method, never by a check).
    pub limit: Option<Limit>,
    /// For a limit that is a curve over frequency (an amplitude spectral density bound): its band
    /// and shape; the limit is then `limit x shape(f)` over the band (see [`crate::spectrum`]).
    pub spectrum: Option<crate::spectrum::Spectrum>,
    /// Probability level the limit applies at (`99.73 %`), if any, as written.
    pub probability: Option<String>,
    /// The probability as a fraction (`0.9973`; `erf(k / sqrt 2)` for a written `(k sigma)`),
    /// what a check that samples judges with (see [`parse_probability`]).
    pub probability_value: Option<f64>,
    /// The sigma level `k` when the probability was written with one (`(2 sigma)`): a model
    /// with a normal output takes its `k`-sigma point exactly.
    pub probability_sigma: Option<f64>,
    /// Verification method.
    pub method: Method,
    /// Verification level (`level:` of the entry, else of the file, else the family default of
    /// [`default_level_stage`]).
    pub level: Level,
    /// Verification stage (`stage:` of the entry, else of the file, else the family default).
    pub stage: Stage,
    /// The verification activity that provides the evidence.
    pub activity: String,
    /// Name of the registered check that runs the activity, if any.
    pub check: Option<String>,
    /// Parent requirement and the margin that links them.
    pub parent: Option<(ReqId, f64)>,
    /// Free note.
    pub note: Option<String>,
    /// The credibility level (0-4, [`crate::credibility`]) its verdict needs (`credibility: 3`
    /// in the YAML): below it the row is not compliant, whatever its margin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub credibility: Option<u8>,
    /// Where the entry starts.
    pub origin: Origin,
    /// Where the `check` field is (to report unknown checks).
    #[serde(skip)]
    pub check_origin: Option<Origin>,
}

/// Why a requirements directory was refused. Display is one line: `file:line:column: cause`.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{origin}: {}", geodesic_util::text::one_line(.cause))]
pub struct LoadError {
    /// Where.
    pub origin: Origin,
    /// What kind of failure (a caller matches on it rather than on the text).
    pub kind: LoadKind,
    /// One-line cause.
    pub cause: String,
}

/// The kind of a [`LoadError`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LoadKind {
    /// The file or folder cannot be read (missing, too large, not UTF-8).
    Unreadable,
    /// Malformed YAML, or a field of the wrong shape.
    Syntax,
    /// A requirement ID that no loaded requirement has.
    UnknownId,
    /// A unit that is not known, or a quantity that is not a number with a unit.
    UnknownUnit,
    /// A check name that no registered check has.
    UnknownCheck,
    /// A NaN or infinite number.
    NotFinite,
    /// Any other value that is refused (out of range, duplicate, empty, a cycle).
    Invalid,
}

impl LoadError {
    /// The same error with the kind `kind`.
    pub fn with_kind(mut self, kind: LoadKind) -> Self {
        self.kind = kind;
        self
    }
}

pub(crate) fn origin_of<T>(file: &Path, s: &Spanned<T>) -> Origin {
    Origin {
        file: file.to_path_buf(),
        line: s.referenced.line(),
        column: s.referenced.column(),
    }
}

/// All requirements of a directory, in file then entry order.
#[derive(Clone, Debug, Default, Serialize, schemars::JsonSchema)]
pub struct Requirements {
    /// The requirements.
    pub items: Vec<Requirement>,
    /// Family descriptions by family name.
    pub families: BTreeMap<String, String>,
}

impl Requirements {
    /// Loads every `*.yaml` / `*.yml` file of `dir` (sorted by name).
    pub fn load_dir(dir: &Path) -> Result<Requirements, LoadError> {
        let top = |cause: String| LoadError {
            origin: Origin {
                file: dir.to_path_buf(),
                line: 1,
                column: 1,
            },
            kind: LoadKind::Unreadable,
            cause,
        };
        let rd = std::fs::read_dir(dir)
            .map_err(|e| top(format!("cannot read requirements directory: {e}")))?;
        let mut files: Vec<PathBuf> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "yml")))
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(top("no *.yaml requirement files in this directory".into()));
        }
        let mut sources = Vec::new();
        for f in files {
            let text = geodesic_util::fsio::read_text(&f, geodesic_util::fsio::MAX_YAML_BYTES)
                .map_err(|e| LoadError {
                    origin: Origin {
                        file: f.clone(),
                        line: e.line().max(1) as u64,
                        column: 1,
                    },
                    kind: LoadKind::Unreadable,
                    cause: e.cause(),
                })?;
            sources.push((f, text));
        }
        let reqs = Requirements::from_sources(&sources)?;
        if reqs.items.is_empty() {
            return Err(top(
                "no requirements in this directory (every file lists none)".into(),
            ));
        }
        Ok(reqs)
    }

    /// Loads requirements from `(path, text)` pairs (the path is used in messages only).
    pub fn from_sources(sources: &[(PathBuf, String)]) -> Result<Requirements, LoadError> {
        let mut out = Requirements::default();
        let mut seen: BTreeMap<String, Origin> = BTreeMap::new();
        let mut parents: Vec<PendingParent> = Vec::new();
        for (file, text) in sources {
            out.load_file(file, text, &mut seen, &mut parents)?;
        }
        let origins = out.link_parents(parents)?;
        out.check_derivation_chains(&origins)?;
        Ok(out)
    }

    /// Appends the requirements of one file (`seen`: the IDs so far, where each is defined;
    /// `parents`: the derivations to link once every file is read).
    fn load_file(
        &mut self,
        file: &Path,
        text: &str,
        seen: &mut BTreeMap<String, Origin>,
        parents: &mut Vec<PendingParent>,
    ) -> Result<(), LoadError> {
        let raw: RawFile = serde_saphyr::from_str(text).map_err(|e| yaml_error(file, &e))?;
        self.families.insert(
            raw.family.clone(),
            raw.description.clone().unwrap_or_default(),
        );
        let (def_level, def_stage) = default_level_stage(&raw.family);
        let file_level = raw
            .level
            .as_ref()
            .map(|s| parse_level(file, s))
            .transpose()?;
        let file_stage = raw
            .stage
            .as_ref()
            .map(|s| parse_stage(file, s))
            .transpose()?;
        let defaults = (
            file_level.unwrap_or(def_level),
            file_stage.unwrap_or(def_stage),
        );
        for r in raw.requirements {
            let idx = self.items.len();
            let (req, parent) = requirement(file, &raw.family, r, defaults, seen)?;
            if let Some((pid, margin)) = parent {
                parents.push((idx, pid, margin, file.to_path_buf()));
            }
            self.items.push(req);
        }
        Ok(())
    }

    /// Links each child to its parent, once every requirement is loaded: the parent exists, is
    /// another requirement, has a limit of the same dimension, and the child's limit is the
    /// margin times the parent's. Returns where each derivation is written.
    fn link_parents(
        &mut self,
        parents: Vec<PendingParent>,
    ) -> Result<Vec<(usize, Origin)>, LoadError> {
        let mut origins: Vec<(usize, Origin)> = Vec::new();
        for (idx, pid, margin, file) in parents {
            let origin = origin_of(&file, &pid);
            let perr = |cause: String| LoadError {
                origin: origin.clone(),
                kind: LoadKind::Invalid,
                cause,
            };
            let parent_id = ReqId::parse(&pid.value).map_err(perr)?;
            let parent = self
                .items
                .iter()
                .find(|p| p.id == parent_id)
                .ok_or_else(|| {
                    perr(format!("parent {parent_id} does not exist"))
                        .with_kind(LoadKind::UnknownId)
                })?
                .clone();
            let child = &self.items[idx];
            if parent.id == child.id {
                return Err(perr(format!("{} names itself as its parent", child.id)));
            }
            let (Some(pl), Some(cl)) = (&parent.limit, &child.limit) else {
                return Err(perr(format!(
                    "parent {} is a qualitative requirement (no limit): a margin links two limits",
                    parent.id
                )));
            };
            if pl.dim != cl.dim {
                return Err(perr(format!(
                    "parent {} is a {} but {} is a {}",
                    parent.id, pl.dim, child.id, cl.dim
                )));
            }
            let expect = pl.value.value * margin;
            if (cl.value.value - expect).abs() > 1e-9 * expect.abs() {
                return Err(perr(format!(
                    "{} limit {} is not margin {} x parent {} limit {}",
                    child.id, cl.text, margin, parent.id, pl.text
                )));
            }
            self.items[idx].parent = Some((parent_id, margin));
            origins.push((idx, origin));
        }
        Ok(origins)
    }

    /// A derivation chain must end: following parents from any requirement of `origins` (a
    /// child, with where its derivation is written) may not return to it.
    fn check_derivation_chains(&self, origins: &[(usize, Origin)]) -> Result<(), LoadError> {
        for (idx, origin) in origins {
            let mut chain = vec![self.items[*idx].id.clone()];
            let mut at = *idx;
            while let Some((p, _)) = &self.items[at].parent {
                let Some(next) = self.items.iter().position(|r| &r.id == p) else {
                    break;
                };
                if next == *idx {
                    chain.push(p.clone());
                    let names: Vec<&str> = chain.iter().map(ReqId::as_str).collect();
                    return Err(LoadError {
                        origin: origin.clone(),
                        kind: LoadKind::Invalid,
                        cause: format!("derivation cycle: {}", names.join(" -> parent ")),
                    });
                }
                if chain.len() > self.items.len() {
                    break;
                }
                chain.push(p.clone());
                at = next;
            }
        }
        Ok(())
    }

    /// Finds a requirement by ID.
    pub fn get(&self, id: &str) -> Option<&Requirement> {
        self.items.iter().find(|r| r.id.as_str() == id)
    }

    /// IDs of the requirements whose parent is `id`.
    pub fn children(&self, id: &str) -> Vec<&ReqId> {
        self.items
            .iter()
            .filter(|r| r.parent.as_ref().is_some_and(|(p, _)| p.as_str() == id))
            .map(|r| &r.id)
            .collect()
    }

    /// Checks that every `check:` field names one of `known` checks.
    pub fn validate_checks(&self, known: &[&str]) -> Result<(), LoadError> {
        for r in &self.items {
            if let (Some(c), Some(o)) = (&r.check, &r.check_origin)
                && !known.contains(&c.as_str())
            {
                return Err(LoadError {
                    origin: o.clone(),
                    kind: LoadKind::UnknownCheck,
                    cause: format!(
                        "{} names unknown check `{c}` (known: {})",
                        r.id,
                        known.join(", ")
                    ),
                });
            }
        }
        Ok(())
    }
}

/// A derivation read and not linked yet: the child's index, the parent's ID as written, the
/// margin, and the child's file.
type PendingParent = (usize, Spanned<String>, f64, PathBuf);

/// A parent as an entry names it: its ID as written and the margin.
type WrittenParent = (Spanned<String>, f64);

fn parse_level(file: &Path, s: &Spanned<String>) -> Result<Level, LoadError> {
    Level::parse(s.value.trim()).ok_or_else(|| LoadError {
        origin: origin_of(file, s),
        kind: LoadKind::Invalid,
        cause: format!(
            "unknown verification level `{}` ({})",
            s.value,
            Level::NAMES.join(", ")
        ),
    })
}

fn parse_stage(file: &Path, s: &Spanned<String>) -> Result<Stage, LoadError> {
    Stage::parse(s.value.trim()).ok_or_else(|| LoadError {
        origin: origin_of(file, s),
        kind: LoadKind::Invalid,
        cause: format!(
            "unknown verification stage `{}` ({})",
            s.value,
            Stage::NAMES.join(", ")
        ),
    })
}

/// One entry of `file` (of `family`) checked: its ID is new (`seen` records it), its limit,
/// method, level (`defaults`: the file's level and stage, else the family's), stage,
/// spectrum and probability read. Returns the requirement, without its parent, and the
/// parent's ID and margin to link once every file is read.
fn requirement(
    file: &Path,
    family: &str,
    r: RawRequirement,
    defaults: (Level, Stage),
    seen: &mut BTreeMap<String, Origin>,
) -> Result<(Requirement, Option<WrittenParent>), LoadError> {
    let at = |s: &Spanned<String>| origin_of(file, s);
    let err = |s: &Spanned<String>, cause: String| LoadError {
        origin: at(s),
        kind: LoadKind::Invalid,
        cause,
    };
    let id = ReqId::parse(&r.id.value).map_err(|c| err(&r.id, c))?;
    if let Some(prev) = seen.get(id.as_str()) {
        return Err(err(
            &r.id,
            format!("duplicate requirement ID {id} (first defined at {prev})"),
        ));
    }
    seen.insert(id.to_string(), at(&r.id));
    let limit = entry_limit(&id, &r, &err)?;
    let method = parse_method(&r.method, &err)?;
    texts_stated(&id, &r, &err)?;
    let level = match &r.level {
        Some(l) => parse_level(file, l)?,
        None => defaults.0,
    };
    let stage = match &r.stage {
        Some(l) => parse_stage(file, l)?,
        None => defaults.1,
    };
    let spectrum = match &r.spectrum {
        Some(sp) => Some(
            crate::spectrum::Spectrum::parse(&sp.band.value, &sp.shape.value)
                .map_err(|c| err(&sp.band, format!("requirement {id}: {c}")))?,
        ),
        None => None,
    };
    let (probability_value, probability_sigma) = entry_probability(&id, &r, &err)?;
    let parent = match r.parent {
        Some(p) if !(p.margin.is_finite() && p.margin > 0.0) => {
            return Err(err(
                &p.id,
                format!("parent margin {} must be a positive number", p.margin),
            ));
        }
        Some(p) => Some((p.id, p.margin)),
        None => None,
    };
    let credibility = match &r.credibility {
        Some(c) if !(c.value.fract() == 0.0 && (0.0..=4.0).contains(&c.value)) => {
            return Err(LoadError {
                origin: origin_of(file, c),
                kind: LoadKind::Invalid,
                cause: format!(
                    "requirement {id}: credibility {} is not a level of 0 to 4 (docs/credibility.md)",
                    c.value
                ),
            });
        }
        Some(c) => Some(c.value as u8),
        None => None,
    };
    let req = Requirement {
        id,
        family: family.to_string(),
        title: r.title,
        text: r.text,
        source: r.source,
        quantity: r.quantity.map(|q| q.value).unwrap_or_default(),
        limit,
        spectrum,
        probability: r.probability.map(|p| p.value),
        probability_value,
        probability_sigma,
        method,
        level,
        stage,
        activity: r.activity,
        check: r.check.as_ref().map(|c| c.value.clone()),
        check_origin: r.check.as_ref().map(&at),
        parent: None,
        note: r.note,
        credibility,
        origin: at(&r.id),
    };
    Ok((req, parent))
}

/// Title, text, source and activity must not be empty.
fn texts_stated(
    id: &ReqId,
    r: &RawRequirement,
    err: &dyn Fn(&Spanned<String>, String) -> LoadError,
) -> Result<(), LoadError> {
    for (name, v) in [
        ("title", &r.title),
        ("text", &r.text),
        ("source", &r.source),
        ("activity", &r.activity),
    ] {
        if v.trim().is_empty() {
            return Err(err(&r.id, format!("requirement {id}: `{name}` is empty")));
        }
    }
    Ok(())
}

/// An entry's probability as a fraction, and its sigma level when written with one (both
/// `None` without a probability).
fn entry_probability(
    id: &ReqId,
    r: &RawRequirement,
    err: &dyn Fn(&Spanned<String>, String) -> LoadError,
) -> Result<(Option<f64>, Option<f64>), LoadError> {
    match &r.probability {
        Some(p) => {
            let (v, k) = parse_probability(&p.value)
                .map_err(|c| err(p, format!("requirement {id}: {c}")))?;
            Ok((Some(v), k))
        }
        None => Ok((None, None)),
    }
}

/// An entry's limit: with a limit, its dimension and quantity must be stated; without one
/// (a qualitative requirement), nothing tied to a limit may be (spectrum, dimension,
/// probability, check, parent).
fn entry_limit(
    id: &ReqId,
    r: &RawRequirement,
    err: &dyn Fn(&Spanned<String>, String) -> LoadError,
) -> Result<Option<Limit>, LoadError> {
    let Some(l) = &r.limit else {
        if let Some(sp) = &r.spectrum {
            return Err(err(
                &sp.band,
                format!(
                    "requirement {id} has a `spectrum` but no `limit` (the limit is the curve's level)"
                ),
            ));
        }
        let tied = [
            ("dimension", r.dimension.as_ref()),
            ("probability", r.probability.as_ref()),
            ("check", r.check.as_ref()),
        ];
        if let Some((name, s)) = tied.iter().find_map(|(n, s)| s.map(|s| (n, s))) {
            return Err(err(
                s,
                format!(
                    "requirement {id} has a `{name}` but no `limit` (a qualitative requirement has no dimension, probability or check)"
                ),
            ));
        }
        if let Some(p) = &r.parent {
            return Err(err(
                &p.id,
                format!(
                    "requirement {id} has a `parent` but no `limit` (a parent margin links two limits)"
                ),
            ));
        }
        return Ok(None);
    };
    let Some(dimension) = &r.dimension else {
        return Err(err(
            l,
            format!("requirement {id} has a limit but no `dimension`"),
        ));
    };
    if r.quantity.is_none() {
        return Err(err(
            l,
            format!("requirement {id} has a limit but no `quantity`"),
        ));
    }
    Ok(Some(parse_limit(dimension, l, r.spectrum.is_some(), err)?))
}

/// The verification method as written (`test`, `analysis`, `review-of-design`,
/// `inspection`).
fn parse_method(
    m: &Spanned<String>,
    err: &dyn Fn(&Spanned<String>, String) -> LoadError,
) -> Result<Method, LoadError> {
    match m.value.as_str() {
        "test" => Ok(Method::Test),
        "analysis" => Ok(Method::Analysis),
        "review-of-design" => Ok(Method::ReviewOfDesign),
        "inspection" => Ok(Method::Inspection),
        other => Err(err(
            m,
            format!(
                "unknown verification method `{other}` (test, analysis, review-of-design, inspection)"
            ),
        )),
    }
}

/// Parses `dimension` and `limit` of a quantitative requirement.
fn parse_limit(
    dimension: &Spanned<String>,
    l: &Spanned<String>,
    spectral: bool,
    err: &dyn Fn(&Spanned<String>, String) -> LoadError,
) -> Result<Limit, LoadError> {
    let dim = Dim::from_name(&dimension.value).ok_or_else(|| {
        let names: Vec<&str> = Dim::NAMED.iter().map(|(n, _)| *n).collect();
        err(
            dimension,
            format!(
                "unknown dimension `{}` (known: {})",
                dimension.value,
                names.join(", ")
            ),
        )
    })?;
    let (op, rest) = parse_op(&l.value).map_err(|c| err(l, c))?;
    // an ASD limit: the unit ends in a per-root-hertz marker, stripped here; the dimension is
    // that of the quantity whose spectral density is bounded
    let stripped;
    let rest = match (spectral, crate::spectrum::strip_asd_unit(rest)) {
        (true, Some(s)) => {
            stripped = s;
            stripped.as_str()
        }
        (true, None) => {
            return Err(err(
                l,
                format!(
                    "limit `{}` has a `spectrum`: write its unit as an amplitude spectral density, ending in Hz^-1/2 (e.g. `<= 3e-14 m s^-2 Hz^-1/2`)",
                    l.value.trim()
                ),
            ));
        }
        (false, Some(_)) => {
            return Err(err(
                l,
                format!(
                    "limit `{}` is a spectral density: state its band and shape under `spectrum`",
                    l.value.trim()
                ),
            ));
        }
        (false, None) => rest,
    };
    let (value, mut unit) = parse_quantity(rest).map_err(|e| {
        let kind = match e {
            crate::units::UnitError::NotFinite(_) => LoadKind::NotFinite,
            _ => LoadKind::UnknownUnit,
        };
        err(l, format!("limit `{}`: {e}", l.value)).with_kind(kind)
    })?;
    if spectral {
        unit.symbol = format!("{} Hz^-1/2", unit.symbol);
    }
    if value.dim != dim {
        return Err(err(
            l,
            format!(
                "limit `{}` is a {} but the requirement's dimension is {}",
                l.value, value.dim, dim
            ),
        ));
    }
    if !value.value.is_finite() {
        return Err(err(
            l,
            format!("limit `{}` is not a finite number", l.value.trim()),
        ));
    }
    if value.value != 0.0 && !value.value.is_normal() {
        return Err(err(
            l,
            format!(
                "limit `{}` is subnormal (below {:e} in SI); the relative margin divides by it",
                l.value.trim(),
                f64::MIN_POSITIVE
            ),
        ));
    }
    if value.value == 0.0 {
        return Err(err(
            l,
            "a limit of zero leaves no relative margin; state a non-zero bound".into(),
        ));
    }
    Ok(Limit {
        dim,
        op,
        value,
        unit,
        text: l.value.trim().to_string(),
    })
}

fn parse_op(s: &str) -> Result<(Op, &str), String> {
    let t = s.trim();
    for (sym, op) in [
        ("<=", Op::Le),
        ("≤", Op::Le),
        (">=", Op::Ge),
        ("≥", Op::Ge),
        ("<", Op::Lt),
        (">", Op::Gt),
    ] {
        if let Some(rest) = t.strip_prefix(sym) {
            return Ok((op, rest.trim()));
        }
    }
    Err(format!(
        "limit `{t}` must start with <=, <, >= or > (e.g. `<= 5 um/s`)"
    ))
}

/// A YAML error of `file` as a [`LoadError`] with the parser's line and column.
pub(crate) fn yaml_error(file: &Path, e: &serde_saphyr::Error) -> LoadError {
    let y = geodesic_util::yaml_error(e);
    LoadError {
        origin: Origin {
            file: file.to_path_buf(),
            line: y.line.unwrap_or(1),
            column: y.column.unwrap_or(1),
        },
        kind: LoadKind::Syntax,
        cause: y.cause,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probabilities_as_written() {
        assert_eq!(parse_probability("99.73 %").unwrap(), (0.9973, None));
        assert_eq!(parse_probability("0.9973").unwrap(), (0.9973, None));
        let (p, k) = parse_probability("95.45 % (2 sigma)").unwrap();
        assert!((p - 0.954_499_736).abs() < 1e-7 && k == Some(2.0), "{p}");
        for bad in [
            "95.45 % (3 sigma)",
            "150 %",
            "0 %",
            "often",
            "99.73 % (two sigma)",
        ] {
            let e = parse_probability(bad).unwrap_err();
            assert!(e.contains(bad.split(' ').next().unwrap()), "{bad}: {e}");
        }
    }

    const GOOD: &str = "family: release
requirements:
  - id: REL-A
    title: A
    text: The thing shall be slow.
    source: Spec Tab. 1
    quantity: velocity
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: Monte Carlo
  - id: REL-B
    title: B
    text: The design shall allow 7.5 um/s.
    source: Spec ch. 7
    quantity: velocity
    dimension: velocity
    limit: <= 7.5 um/s
    method: analysis
    activity: Monte Carlo
    parent: {id: REL-A, margin: 1.5}
";

    fn load(t: &str) -> Result<Requirements, LoadError> {
        Requirements::from_sources(&[(PathBuf::from("r.yaml"), t.to_string())])
    }

    #[test]
    fn level_and_stage_come_from_the_entry_the_file_or_the_default() {
        let r = load(GOOD).unwrap();
        // neither the entry nor the file states them: system, qualification whatever the
        // family (the framework knows no mission's families)
        assert_eq!(r.items[0].level, Level::System, "the default");
        assert_eq!(r.items[0].stage, Stage::Qualification);
        let t = GOOD
            .replace("requirements:", "level: element\nrequirements:")
            .replacen(
                "    activity: Monte Carlo\n",
                "    activity: Monte Carlo\n    level: equipment\n    stage: in-orbit\n",
                1,
            );
        let r = load(&t).unwrap();
        assert_eq!(
            (r.items[0].level, r.items[0].stage),
            (Level::Equipment, Stage::InOrbit)
        );
        assert_eq!(
            (r.items[1].level, r.items[1].stage),
            (Level::Element, Stage::Qualification)
        );
        let bad = GOOD.replacen(
            "    activity: Monte Carlo\n",
            "    activity: Monte Carlo\n    stage: flight\n",
            1,
        );
        let e = load(&bad).unwrap_err().to_string();
        assert!(
            e.starts_with("r.yaml:12:") && e.contains("unknown verification stage `flight`"),
            "{e}"
        );
    }

    #[test]
    fn loads_and_links_parent() {
        let r = load(GOOD).unwrap();
        assert_eq!(r.items.len(), 2);
        assert_eq!(r.items[1].parent.as_ref().unwrap().0.as_str(), "REL-A");
        assert!((r.items[0].limit.as_ref().unwrap().value.value - 5e-6).abs() < 1e-18);
        assert_eq!(r.children("REL-A").len(), 1);
    }

    fn err_of(t: &str) -> String {
        load(t).unwrap_err().to_string()
    }

    #[test]
    fn errors_name_file_line_and_cause() {
        let e = err_of(&GOOD.replace("id: REL-B", "id: REL-A"));
        assert!(
            e.starts_with("r.yaml:12:") && e.contains("duplicate"),
            "{e}"
        );
        let e = err_of(&GOOD.replace("<= 7.5 um/s", "<= 7.5 furlong"));
        assert!(e.starts_with("r.yaml:18:") && e.contains("furlong"), "{e}");
        let e = err_of(&GOOD.replace("<= 7.5 um/s", "<= 7.5 mrad"));
        assert!(e.contains("dimension"), "{e}");
        let e = err_of(&GOOD.replace("margin: 1.5", "margin: 2"));
        assert!(e.contains("margin"), "{e}");
        let e = err_of(&GOOD.replace("id: REL-A, margin", "id: REL-Z, margin"));
        assert!(
            e.contains("does not exist") && e.starts_with("r.yaml:21:"),
            "{e}"
        );
        let e = err_of(&GOOD.replace(
            "    activity: Monte Carlo\n  - id",
            "    activity: Monte Carlo\n    colour: red\n  - id",
        ));
        assert!(
            e.starts_with("r.yaml:12:") && e.contains("unknown field"),
            "{e}"
        );
        let e = err_of(&GOOD.replace("requirements:\n", "requirements: [\n"));
        assert!(e.starts_with("r.yaml:"), "{e}");
        let e = err_of(&GOOD.replace(
            "method: analysis\n    activity: Monte Carlo\n  - id",
            "method: guess\n    activity: Monte Carlo\n  - id",
        ));
        assert!(e.contains("method"), "{e}");
        assert!(!e.contains('\n'));
    }

    #[test]
    fn refuses_cycles_subnormal_limits_empty_dirs_and_bad_bytes() {
        // A parent of B parent of A (margins 1 keep the limits consistent)
        let cyc = GOOD
            .replace("<= 7.5 um/s", "<= 5 um/s")
            .replace("margin: 1.5", "margin: 1")
            .replace(
                "    activity: Monte Carlo\n  - id",
                "    activity: Monte Carlo\n    parent: {id: REL-B, margin: 1}\n  - id",
            );
        let e = err_of(&cyc);
        assert!(
            e.starts_with("r.yaml:") && e.contains("derivation cycle"),
            "{e}"
        );
        let e = err_of(&GOOD.replace("<= 5 um/s", "\">= 1e-320 m/s\""));
        assert!(e.starts_with("r.yaml:9:") && e.contains("subnormal"), "{e}");
        let e = err_of(&GOOD.replace("<= 5 um/s", "<= 1e400 m/s"));
        assert!(e.starts_with("r.yaml:9:"), "{e}");
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().to_path_buf();
        std::fs::write(dir.join("a.yaml"), "family: x\nrequirements: []\n").unwrap();
        let e = Requirements::load_dir(&dir).unwrap_err().to_string();
        assert!(e.contains("no requirements"), "{e}");
        let mut bytes = GOOD.as_bytes().to_vec();
        let at = GOOD.find("Spec ch. 7").unwrap();
        bytes[at] = 0xff;
        std::fs::write(dir.join("a.yaml"), &bytes).unwrap();
        let e = Requirements::load_dir(&dir).unwrap_err().to_string();
        assert!(e.contains("a.yaml:15:") && e.contains("UTF-8"), "{e}");
    }

    const QUAL: &str = "  - id: REL-G
    title: Grounding
    text: The TM shall be grounded by a wire until release.
    source: Spec ch. 2
    method: review-of-design
    activity: design review
";

    #[test]
    fn qualitative_requirements_load_without_a_limit() {
        let r = load(&format!("{GOOD}{QUAL}")).unwrap();
        assert_eq!(r.items.len(), 3);
        let g = r.get("REL-G").unwrap();
        assert!(g.limit.is_none());
        assert_eq!(g.quantity, "");
        assert_eq!(g.method, Method::ReviewOfDesign);
        assert!(g.check.is_none() && g.parent.is_none() && g.probability.is_none());
        // the quantitative ones are unchanged
        let a = r.items[0].limit.as_ref().unwrap();
        assert_eq!(
            (a.op, a.text.as_str(), a.in_unit()),
            (Op::Le, "<= 5 um/s", 5.0)
        );
        // a quantity may name what the prose is about
        let q = load(&format!(
            "{GOOD}{}",
            QUAL.replace("    method:", "    quantity: grounding\n    method:")
        ))
        .unwrap();
        assert_eq!(q.get("REL-G").unwrap().quantity, "grounding");
    }

    #[test]
    fn qualitative_requirements_state_nothing_tied_to_a_limit() {
        let with = |extra: &str| err_of(&format!("{GOOD}{QUAL}{extra}"));
        // the qualitative entry starts at line 22; added fields are at line 28
        for (extra, word) in [
            ("    dimension: velocity\n", "`dimension` but no `limit`"),
            ("    probability: 99.73 %\n", "`probability` but no `limit`"),
            ("    check: release-velocity\n", "`check` but no `limit`"),
            (
                "    parent: {id: REL-A, margin: 1}\n",
                "`parent` but no `limit`",
            ),
        ] {
            let e = with(extra);
            assert!(e.starts_with("r.yaml:28:") && e.contains(word), "{e}");
            assert!(!e.contains('\n'));
        }
        // a quantitative child cannot hang from a qualitative parent by a margin
        let e = err_of(&format!(
            "{GOOD}{QUAL}  - id: REL-H
    title: H
    text: The thing shall be slower.
    source: Spec ch. 7
    quantity: velocity
    dimension: velocity
    limit: <= 4 um/s
    method: analysis
    activity: Monte Carlo
    parent: {{id: REL-G, margin: 2}}
"
        ));
        assert!(
            e.starts_with("r.yaml:37:") && e.contains("REL-G is a qualitative requirement"),
            "{e}"
        );
        // a limit still needs its dimension, its quantity and a method
        let e = err_of(&GOOD.replace(
            "    dimension: velocity\n    limit: <= 5",
            "    limit: <= 5",
        ));
        assert!(
            e.starts_with("r.yaml:8:") && e.contains("no `dimension`"),
            "{e}"
        );
        let e = err_of(&GOOD.replace(
            "    quantity: velocity\n    dimension: velocity\n    limit: <= 5",
            "    dimension: velocity\n    limit: <= 5",
        ));
        assert!(
            e.starts_with("r.yaml:8:") && e.contains("no `quantity`"),
            "{e}"
        );
        let e = err_of(&format!(
            "{GOOD}{}",
            QUAL.replace("    method: review-of-design\n", "")
        ));
        assert!(e.contains("method"), "{e}");
    }

    #[test]
    fn margins() {
        assert!((Op::Le.margin(1.5, 5.0) - 0.7).abs() < 1e-12);
        assert!((Op::Ge.margin(0.999, 0.9973) - 0.0017046).abs() < 1e-6);
        assert!(Op::Le.margin(6.0, 5.0) < 0.0);
    }
}
