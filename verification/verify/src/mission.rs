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
//! options:                    # run options its checks read (optional; whole numbers)
//!   - name: mc-n              # the flag (`--mc-n N`)
//!     key: mc_n               # `run.mc_n` in compliance.json; `ctx.option::<usize>("mc_n")`
//!     words: N                # how the reports name it
//!     group: Monte Carlo      # the reports' line it is printed on (`Monte Carlo: N = 100000`)
//!     default: 100000
//!     min: 1                  # optional, 0 by default
//!     max: 10000000           # optional
//!     about: Monte Carlo sample count used by the checks that run one
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
    /// The run options its checks read (a Monte Carlo sample count, a seed, ...): each is a
    /// `verify` flag, a key of `run` in `compliance.json` and a value of the check context.
    #[serde(default)]
    pub options: Vec<OptionSpec>,
}

/// One run option a mission declares: a whole number its checks read
/// ([`geodesic_core::CheckContext::option`]).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptionSpec {
    /// Its flag without the dashes (`mc-n`: `--mc-n N`).
    pub name: String,
    /// Its key in `run` of `compliance.json` and in the check context [default: `name` with
    /// `-` as `_`].
    #[serde(default)]
    pub key: Option<String>,
    /// How the reports name it (`N`).
    pub words: String,
    /// The reports' line it is printed on with the other options of the same group (`Monte
    /// Carlo`); none: a line of its own.
    #[serde(default)]
    pub group: Option<String>,
    /// Its value when the flag is not given.
    pub default: u64,
    /// The smallest value accepted [default: 0].
    #[serde(default)]
    pub min: u64,
    /// The largest value accepted [default: none].
    #[serde(default)]
    pub max: Option<u64>,
    /// What it is, for `--help`.
    #[serde(default)]
    pub about: String,
}

impl OptionSpec {
    /// Its key in `run` and in the check context.
    pub fn key(&self) -> String {
        self.key
            .clone()
            .unwrap_or_else(|| self.name.replace('-', "_"))
    }

    /// Its value for a run: `given`, else its default; an error (the flag, the value and the
    /// range) when outside `min..=max`.
    pub fn value(&self, given: Option<u64>) -> Result<u64, String> {
        let v = given.unwrap_or(self.default);
        let max = self.max.unwrap_or(u64::MAX);
        if v < self.min || v > max {
            return Err(format!(
                "--{} {v}: must be between {} and {max}",
                self.name, self.min
            ));
        }
        Ok(v)
    }
}

impl MissionSpec {
    /// The run options for a run: each declared option with the value `given` by name (its
    /// flag's name) or its default; an error for a value out of range or an option the mission
    /// does not declare.
    pub fn run_options(
        &self,
        given: &BTreeMap<String, u64>,
    ) -> Result<geodesic_core::check::RunOptions, String> {
        if let Some(name) = given
            .keys()
            .find(|n| !self.options.iter().any(|o| &o.name == *n))
        {
            let declared: Vec<&str> = self.options.iter().map(|o| o.name.as_str()).collect();
            return Err(format!(
                "--{name}: mission {} declares no option `{name}` (its options: {})",
                self.name,
                if declared.is_empty() {
                    "none".to_string()
                } else {
                    declared.join(", ")
                }
            ));
        }
        let mut out = geodesic_core::check::RunOptions::default();
        for o in &self.options {
            out.push(geodesic_core::check::RunOption {
                key: o.key(),
                value: o.value(given.get(&o.name).copied())?,
                words: o.words.clone(),
                group: o.group.clone().unwrap_or_default(),
            });
        }
        Ok(out)
    }
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
        let mut keys = Vec::new();
        for o in &spec.options {
            if !ok(&o.name) || seen.contains(&o.name) || RESERVED.contains(&o.name.as_str()) {
                return Err(Error::invalid(format!(
                    "{label}: option `{}`: a name of lower-case letters, digits, `-` and `_`, not an input's nor one of verify's own flags",
                    o.name
                )));
            }
            seen.push(o.name.clone());
            if keys.contains(&o.key()) {
                return Err(Error::conflict(format!(
                    "{label}: option `{}`: key `{}` declared twice",
                    o.name,
                    o.key()
                )));
            }
            keys.push(o.key());
            if o.value(None).is_err() {
                return Err(Error::invalid(format!(
                    "{label}: option `{}`: default {} outside min {} .. max {}",
                    o.name,
                    o.default,
                    o.min,
                    o.max.map_or("none".to_string(), |m| m.to_string())
                )));
            }
        }
        Ok(spec)
    }
}

/// `verify`'s own flags, which no option may take.
const RESERVED: &[&str] = &[
    "requirements",
    "dispositions",
    "document",
    "tests",
    "require-tests",
    "reports",
    "confidence",
    "junit",
    "baseline",
    "margin-tolerance",
    "no-fidelity",
    "series",
    "only",
    "json",
    "mission",
    "help",
];

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

#[cfg(test)]
mod tests {
    use super::*;

    const BASE: &str = "name: m\ntitle: t\nrequirements: requirements\n";

    fn spec(options: &str) -> Result<MissionSpec, Error> {
        MissionSpec::from_yaml(&format!("{BASE}options:\n{options}"), "mission.yaml")
    }

    #[test]
    fn declared_options_give_their_defaults_values_and_report_lines() {
        let s = spec(
            "  - {name: mc-n, words: N, group: Monte Carlo, default: 100, min: 1, max: 1000, about: draws}\n  - {name: seed, words: seed, group: Monte Carlo, default: 1}\n  - {name: order, key: k, words: order, default: 3}\n",
        )
        .unwrap();
        let o = s.run_options(&BTreeMap::new()).unwrap();
        assert_eq!(
            (o.get("mc_n"), o.get("seed"), o.get("k")),
            (Some(100), Some(1), Some(3))
        );
        assert_eq!(
            o.lines(),
            vec![
                ("Monte Carlo", "N = 100, seed = 1".to_string()),
                ("order", "3".to_string())
            ]
        );
        let json = serde_json::to_string(&o).unwrap();
        assert_eq!(json, r#"{"mc_n":100,"seed":1,"k":3}"#);
        let given: BTreeMap<String, u64> = [("seed".to_string(), 7)].into_iter().collect();
        assert_eq!(s.run_options(&given).unwrap().get("seed"), Some(7));
        for (v, want) in [
            (0, "--mc-n 0: must be between 1 and 1000"),
            (1001, "--mc-n 1001: must be between 1 and 1000"),
        ] {
            let given: BTreeMap<String, u64> = [("mc-n".to_string(), v)].into_iter().collect();
            assert_eq!(s.run_options(&given).unwrap_err(), want);
        }
        let given: BTreeMap<String, u64> = [("runs".to_string(), 2)].into_iter().collect();
        assert_eq!(
            s.run_options(&given).unwrap_err(),
            "--runs: mission m declares no option `runs` (its options: mc-n, seed, order)"
        );
    }

    #[test]
    fn a_mission_without_options_has_none_and_refuses_one() {
        let s = MissionSpec::from_yaml(BASE, "mission.yaml").unwrap();
        let o = s.run_options(&BTreeMap::new()).unwrap();
        assert!(o.is_empty() && o.lines().is_empty());
        assert_eq!(serde_json::to_string(&o).unwrap(), "{}");
        let given: BTreeMap<String, u64> = [("seed".to_string(), 2)].into_iter().collect();
        assert!(
            s.run_options(&given)
                .unwrap_err()
                .contains("(its options: none)")
        );
    }

    #[test]
    fn bad_option_declarations_are_refused() {
        for (decl, why) in [
            (
                "  - {name: reports, words: r, default: 1}\n",
                "option `reports`",
            ),
            (
                "  - {name: n, words: N, default: 0, min: 1}\n",
                "default 0 outside min 1",
            ),
            (
                "  - {name: a, key: k, words: a, default: 1}\n  - {name: b, key: k, words: b, default: 1}\n",
                "key `k` declared twice",
            ),
            (
                "  - {name: n, words: N, default: 1, typo: 2}\n",
                "unknown field",
            ),
        ] {
            let e = spec(decl).unwrap_err().to_string();
            assert!(e.contains("mission.yaml") && e.contains(why), "{decl}: {e}");
        }
    }
}
