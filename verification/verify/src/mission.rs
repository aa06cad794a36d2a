//! A mission: the data (a `mission.yaml` descriptor, its requirement files, its input files,
//! its document and dispositions) plus the code that verifies it (its checks, the validation
//! of its input files, its reference tables).
//!
//! The framework names no mission: a crate builds a [`Mission`] from its descriptor and hands
//! it to the pipeline ([`crate::pipeline::run`]), to the test-oracle harness
//! ([`crate::harness::main`]) or to the `geodesic` command line.
//!
//! ```yaml
//! # mission.yaml
//! name: my-mission            # what `verify --mission NAME` selects
//! title: My mission's widget  # in words
//! requirements: requirements  # the folder of requirement YAML files, relative to this file
//! inputs:                     # the input files its checks read, by name
//!   - name: design
//!     words: design inputs    # how the reports name it
//!     path: design.yaml       # its default path, relative to this file
//!     about: the widget's dimensions and materials
//! document: document.yaml     # the reports' identification (id, issue, title, project)
//! dispositions: dispositions.yaml   # known non-compliances (optional)
//! baseline: baseline/compliance.json  # the gate's reference (optional)
//! reference:                  # the comparison table beside the matrix (optional)
//!   title: Fidelity against the reference design
//!   column: Reference
//! ```

use crate::error::Error;
use geodesic_core::check::{Check, CheckContext, CheckError, InputFile, ReferenceRow};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A mission's descriptor (`mission.yaml`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MissionSpec {
    /// The mission's name (`verify --mission NAME`): lower case, digits and `-`.
    pub name: String,
    /// The system verified, in words.
    pub title: String,
    /// The folder of requirement YAML files, relative to the descriptor.
    pub requirements: String,
    /// The input files its checks read.
    #[serde(default)]
    pub inputs: Vec<InputSpec>,
    /// The reports' identification (id, issue, title, project), relative to the descriptor.
    #[serde(default)]
    pub document: Option<String>,
    /// Dispositions of known non-compliances, relative to the descriptor.
    #[serde(default)]
    pub dispositions: Option<String>,
    /// The compliance.json the gate compares with, relative to the descriptor.
    #[serde(default)]
    pub baseline: Option<String>,
    /// The comparison with a reference (e.g. a design report) shown beside the
    /// matrix.
    #[serde(default)]
    pub reference: Option<ReferenceSpec>,
}

/// One input file a mission's checks read.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputSpec {
    /// Its name: the key in `run.inputs`, the name checks read it by, and its flag
    /// (`--NAME FILE`).
    pub name: String,
    /// How the reports name it (`design inputs`).
    pub words: String,
    /// Its default path, relative to the descriptor.
    pub path: String,
    /// What it holds, for `--help` and the docs.
    #[serde(default)]
    pub about: String,
}

/// The heading and column of a mission's reference table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSpec {
    /// The table's heading (`Fidelity against the design report`).
    pub title: String,
    /// The reference column's heading (`Design report`).
    pub column: String,
}

impl MissionSpec {
    /// Parses a descriptor; errors are one line with the file and line.
    pub fn from_yaml(text: &str, label: &str) -> Result<MissionSpec, Error> {
        let spec: MissionSpec = serde_saphyr::from_str(text).map_err(|e| {
            let line = yaml_line(&e.to_string());
            Error::malformed(format!("{label}:{line}: {}", first_line(&e.to_string())))
                .in_file(label, line)
        })?;
        let ok = |s: &str| {
            !s.is_empty()
                && s.chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_')
        };
        if !ok(&spec.name) {
            return Err(Error::invalid(format!(
                "{label}: name `{}`: use lower-case letters, digits, `-` and `_`",
                spec.name
            )));
        }
        let mut seen = Vec::new();
        for i in &spec.inputs {
            if !ok(&i.name) || i.name == "series" {
                return Err(Error::invalid(format!(
                    "{label}: input `{}`: a name of lower-case letters, digits, `-` and `_` (not `series`)",
                    i.name
                )));
            }
            if seen.contains(&i.name) {
                return Err(Error::conflict(format!(
                    "{label}: input `{}` declared twice",
                    i.name
                )));
            }
            seen.push(i.name.clone());
        }
        Ok(spec)
    }
}

fn first_line(s: &str) -> String {
    s.lines().next().unwrap_or("").to_string()
}

fn yaml_line(s: &str) -> usize {
    // serde-saphyr says "... at line L column C"
    s.split("line ")
        .nth(1)
        .and_then(|t| t.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(1)
}

/// What a run of a mission's checks shares: the checks, and the reference table computed
/// from the same state (e.g. one Monte Carlo the checks and the table both read).
pub struct Session {
    /// The registered checks, in a stable order.
    pub checks: Vec<Box<dyn Check>>,
    /// The reference table (`None`: the mission has none), computed after the checks.
    pub reference: Option<ReferenceTable>,
}

/// A reference table: rows computed from the run's context.
pub type ReferenceTable =
    Box<dyn Fn(&CheckContext) -> Result<Vec<ReferenceRow>, CheckError> + Send + Sync>;

type SessionFn = Arc<dyn Fn() -> Session + Send + Sync>;
type Validator = Arc<dyn Fn(&InputFile) -> Result<(), String> + Send + Sync>;
type SeriesValidator = Arc<dyn Fn(&Path) -> Result<(), String> + Send + Sync>;

/// A mission: its descriptor, where it lies, the copies of its files built into the program,
/// and its code (checks, input validation, reference tables).
#[derive(Clone)]
pub struct Mission {
    /// The descriptor.
    pub spec: MissionSpec,
    /// The folder of the descriptor, relative to the working directory (`.` for the root
    /// mission of a repository): the descriptor's paths resolve from it.
    pub root: PathBuf,
    /// Copies of the mission's files built into the program, by path relative to the
    /// descriptor (`requirements/release.yaml`, `design.yaml`, ...): used when the file is not
    /// found on disk, so that the program verifies from any directory.
    pub builtin: BTreeMap<String, &'static str>,
    /// The largest Monte Carlo sample count its checks accept.
    pub max_mc_n: usize,
    session: SessionFn,
    validators: BTreeMap<String, Validator>,
    series: Option<SeriesValidator>,
}

impl std::fmt::Debug for Mission {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mission")
            .field("name", &self.spec.name)
            .field("root", &self.root)
            .finish()
    }
}

impl Mission {
    /// A mission from its descriptor's text (`label` names it in errors) and the folder it
    /// lies in; its checks come from `session`, called once per run.
    pub fn new(
        descriptor: &str,
        label: &str,
        root: impl Into<PathBuf>,
        session: impl Fn() -> Session + Send + Sync + 'static,
    ) -> Result<Mission, Error> {
        Ok(Mission {
            spec: MissionSpec::from_yaml(descriptor, label)?,
            root: root.into(),
            builtin: BTreeMap::new(),
            max_mc_n: usize::MAX,
            session: Arc::new(session),
            validators: BTreeMap::new(),
            series: None,
        })
    }

    /// A mission whose checks need no shared state: `checks` builds its registry.
    pub fn with_checks(
        descriptor: &str,
        label: &str,
        root: impl Into<PathBuf>,
        checks: impl Fn() -> Vec<Box<dyn Check>> + Send + Sync + 'static,
    ) -> Result<Mission, Error> {
        Mission::new(descriptor, label, root, move || Session {
            checks: checks(),
            reference: None,
        })
    }

    /// Adds a copy of one of its files (path relative to the descriptor) built into the
    /// program.
    pub fn builtin(mut self, path: &str, text: &'static str) -> Mission {
        self.builtin.insert(path.to_string(), text);
        self
    }

    /// Checks an input file before any check runs (exit 2 with the cause, nothing written).
    pub fn validate(
        mut self,
        input: &str,
        f: impl Fn(&InputFile) -> Result<(), String> + Send + Sync + 'static,
    ) -> Mission {
        self.validators.insert(input.to_string(), Arc::new(f));
        self
    }

    /// Accepts time series (`verify --series ID=FILE.yaml`), checked by `f` before any check
    /// runs.
    pub fn series(
        mut self,
        f: impl Fn(&Path) -> Result<(), String> + Send + Sync + 'static,
    ) -> Mission {
        self.series = Some(Arc::new(f));
        self
    }

    /// Caps the Monte Carlo sample count.
    pub fn max_mc_n(mut self, n: usize) -> Mission {
        self.max_mc_n = n;
        self
    }

    /// The same mission found in another folder.
    pub fn at(mut self, root: impl Into<PathBuf>) -> Mission {
        self.root = root.into();
        self
    }

    /// A fresh session: its checks and reference table.
    pub fn session(&self) -> Session {
        (self.session)()
    }

    /// The names of its checks.
    pub fn check_names(&self) -> Vec<&'static str> {
        self.session().checks.iter().map(|c| c.name()).collect()
    }

    /// Validates an input file with the mission's validator for it, if any.
    pub fn validate_input(&self, name: &str, f: &InputFile) -> Result<(), String> {
        match self.validators.get(name) {
            Some(v) => v(f),
            None => Ok(()),
        }
    }

    /// Validates a time series file; an error when the mission judges none.
    pub fn validate_series(&self, p: &Path) -> Result<(), String> {
        match &self.series {
            Some(v) => v(p),
            None => Err(format!(
                "mission {} judges no time series (--series)",
                self.spec.name
            )),
        }
    }

    /// A path of the descriptor, relative to the working directory.
    pub fn path(&self, rel: &str) -> PathBuf {
        if self.root.as_os_str().is_empty() || self.root == Path::new(".") {
            PathBuf::from(rel)
        } else {
            self.root.join(rel)
        }
    }

    /// The built-in requirement files: `(file name, text)`, sorted by name.
    pub fn builtin_requirements(&self) -> Vec<(&str, &'static str)> {
        let dir = format!("{}/", self.spec.requirements.trim_end_matches('/'));
        self.builtin
            .iter()
            .filter_map(|(p, t)| p.strip_prefix(&dir).map(|n| (n, *t)))
            .filter(|(n, _)| !n.contains('/'))
            .collect()
    }
}
