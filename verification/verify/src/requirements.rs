//! `requirements check | list | show ID`: a mission's requirement set without running a
//! verification (`geodesic requirements`, and a project's harness). `check` validates the requirement files with verify's loader
//! and errors; `list` lists every requirement with its status from the last run; `show` prints
//! one requirement with its source, limit, method, flow-down (parent and children), traced tests
//! and its evidence from the last run.

use crate::error::{CmdResult, Error as CliError};
use crate::ids::unknown_id;
use crate::mission::Mission;
use geodesic_core::Requirements;
use geodesic_core::matrix::{Matrix, Row};
use schemars::JsonSchema;
use serde::Serialize;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Flags of `geodesic requirements`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub action: Action,
}

/// `check`, `list` or `show ID`.
#[derive(clap::Subcommand, Debug)]
pub enum Action {
    /// Validate the requirement files only (verify's loader and errors): exit 0 with a count,
    /// 2 with file:line:column and the cause.
    #[command(after_help = "Examples:
  geodesic requirements check
  geodesic requirements check --requirements missions/NAME/requirements --json")]
    Check(Common),
    /// List every requirement (ID, title, level, method, limit) with its status from the last
    /// run (the compliance.json under --reports).
    #[command(after_help = "Examples:
  geodesic requirements list
  geodesic requirements list --reports out/ --json | jq '.requirements[] | select(.status == \"non-compliant\")'")]
    List(ListArgs),
    /// One requirement: source, limit, method, parent and children, traced tests, its evidence
    /// from the last run.
    #[command(after_help = "Examples:
  geodesic requirements show REL-GPRM-VEL
  geodesic requirements show CHG-Q --json | jq .last_run.row.evidence
An unknown ID is exit 2 with the nearest IDs.")]
    Show(ShowArgs),
}

/// Flags every action has.
#[derive(clap::Args, Debug)]
pub struct Common {
    /// Directory of requirement YAML files [default: ./requirements if present, else the
    /// built-in set; as verify].
    #[arg(long, value_name = "DIR")]
    pub requirements: Option<PathBuf>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Flags of `requirements list`.
#[derive(clap::Args, Debug)]
pub struct ListArgs {
    /// The flags every `requirements` subcommand takes.
    #[command(flatten)]
    pub common: Common,
    /// Directory of the last run's reports (its compliance.json gives the statuses).
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
}

/// Flags of `requirements show`.
#[derive(clap::Args, Debug)]
pub struct ShowArgs {
    /// Requirement ID.
    pub id: String,
    /// The flags every `requirements` subcommand takes.
    #[command(flatten)]
    pub common: Common,
    /// Directory of the last run's reports (its compliance.json gives the evidence).
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Recorded test run read for the traced tests [default: ./target/geodesic/test-run.json
    /// if present].
    #[arg(long, value_name = "FILE.json")]
    pub tests: Option<PathBuf>,
}

impl Args {
    /// The requirement folder the action names, if any.
    pub fn requirements_dir(&self) -> Option<&Path> {
        match &self.action {
            Action::Check(c) => c.requirements.as_deref(),
            Action::List(a) => a.common.requirements.as_deref(),
            Action::Show(a) => a.common.requirements.as_deref(),
        }
    }
}

/// Runs the command for `mission`.
pub fn run(mission: &Mission, args: Args) -> CmdResult {
    run_for(mission, args, geodesic_core::testrun::RECORD_COMMAND)
}

/// [`run`], naming `test_command` as the command that records the traced tests (a project's
/// own `cargo run -- test`).
pub fn run_for(mission: &Mission, args: Args, test_command: &str) -> CmdResult {
    match args.action {
        Action::Check(c) => check(mission, c),
        Action::List(a) => list(mission, a),
        Action::Show(a) => show(mission, a, test_command),
    }
}

/// Loads and validates the requirement set as `verify` does: the same loader, the same
/// `check:` names. Returns the set, its source and its SHA-256.
fn load(
    mission: &Mission,
    dir: Option<&PathBuf>,
) -> Result<(Requirements, String, String), CliError> {
    let (reqs, source, hash) = crate::pipeline::load_requirements(mission, dir)?;
    reqs.validate_checks(&mission.check_names())?;
    Ok((reqs, source, hash))
}

fn check(mission: &Mission, c: Common) -> CmdResult {
    let (reqs, source, hash) = load(mission, c.requirements.as_ref())?;
    let files: std::collections::BTreeSet<String> = reqs
        .items
        .iter()
        .map(|r| r.origin.file.display().to_string())
        .collect();
    if c.json {
        let doc = CheckDoc {
            valid: true,
            source: &source,
            requirements_hash: &hash,
            requirements: reqs.items.len(),
            families: reqs.families.len(),
            files: &files,
        };
        println!("{}", to_value(&doc)?);
    } else {
        println!(
            "{} requirements in {} files, {} families ({source}): valid (sha256 {hash})",
            reqs.items.len(),
            files.len(),
            reqs.families.len()
        );
    }
    Ok(0)
}

/// The last run's compliance.json under `reports`, if there is one.
struct LastRun {
    file: PathBuf,
    doc: Value,
}

impl LastRun {
    fn find(reports: &Path) -> Result<Option<LastRun>, CliError> {
        let file = reports.join("compliance.json");
        if !file.is_file() {
            return Ok(None);
        }
        let text = geodesic_util::fsio::read_text(&file, 1 << 30).map_err(|e| {
            CliError::unreadable(format!("{}: {}", file.display(), e.cause()))
                .in_file(&file, e.line())
        })?;
        let doc: Value = serde_json::from_str(&text).map_err(|e| {
            CliError::malformed(format!(
                "{}:{}:{}: not a compliance matrix: {e}",
                file.display(),
                e.line(),
                e.column()
            ))
            .in_file(&file, e.line())
        })?;
        if !doc["requirements"].is_array() {
            return Err(CliError::malformed(format!(
                "{}: not a compliance matrix (no `requirements` list)",
                file.display()
            )));
        }
        Ok(Some(LastRun { file, doc }))
    }

    fn row(&self, id: &str) -> Option<&Value> {
        self.doc["requirements"]
            .as_array()
            .and_then(|rows| rows.iter().find(|r| r["id"] == id))
    }

    fn partial(&self) -> bool {
        !self.doc["run"]["partial"].is_null()
    }

    /// What the last run is, with whether it ran on the same requirement files (`row`: the
    /// row of the requirement `show` shows).
    fn info(&self, hash: &str, row: Option<Value>) -> LastRunDoc {
        let run = &self.doc["run"];
        LastRunDoc {
            file: self.file.display().to_string(),
            date: run["date"].clone(),
            commit: run["commit"].clone(),
            partial: self.partial(),
            same_requirements: run["requirements_hash"] == hash,
            row,
        }
    }

    /// One line saying which run the statuses come from, and whether they may not apply.
    fn line(&self, hash: &str) -> String {
        let run = &self.doc["run"];
        let mut l = format!(
            "status from the last run: {} ({}, commit {})",
            self.file.display(),
            run["date"].as_str().unwrap_or("?"),
            run["commit"]
                .as_str()
                .map_or("?", |c| &c[..c.len().min(12)])
        );
        if self.partial() {
            l.push_str(&format!(
                "; a partial run (--only {}): the other rows did not run",
                run["partial"]["only"]
                    .as_array()
                    .map(|a| a
                        .iter()
                        .filter_map(Value::as_str)
                        .collect::<Vec<_>>()
                        .join(","))
                    .unwrap_or_default()
            ));
        }
        if run["requirements_hash"] != hash {
            l.push_str(
                "; the requirement files changed since (another sha256): run `verify` again",
            );
        }
        l
    }

    /// The status of a row: its verdict, or why it has none.
    fn status(&self, id: &str) -> (Option<String>, String) {
        match self.row(id) {
            Some(r) => (
                r["status"].as_str().map(str::to_string),
                r["verdict"]
                    .as_str()
                    .or(r["status"].as_str())
                    .unwrap_or("?")
                    .to_string(),
            ),
            None if self.partial() => (None, "not in the last run (partial)".into()),
            None => (None, "not in the last run".into()),
        }
    }
}

/// Rows of the set without evidence: the limit, method, level, children as every report
/// writes them.
fn bare_rows(
    reqs: &Requirements,
    tests: Option<geodesic_core::matrix::TestEvidence<'_>>,
) -> Matrix {
    Matrix::build_with(reqs, &[], tests, &[])
}

fn list(mission: &Mission, a: ListArgs) -> CmdResult {
    let (reqs, source, hash) = load(mission, a.common.requirements.as_ref())?;
    let last = LastRun::find(&a.reports)?;
    let m = bare_rows(&reqs, None);
    let rows: Vec<(&Row, Option<String>, String)> = m
        .requirements
        .iter()
        .map(|r| {
            let (status, verdict) = match &last {
                Some(l) => l.status(&r.id),
                None => (None, "no last run".into()),
            };
            (r, status, verdict)
        })
        .collect();
    if a.common.json {
        let doc = ListDoc {
            source: &source,
            requirements_hash: &hash,
            last_run: last.as_ref().map(|l| l.info(&hash, None)),
            requirements: rows
                .iter()
                .map(|(r, status, verdict)| ListRow {
                    id: &r.id,
                    title: &r.title,
                    family: &r.family,
                    level: &r.level,
                    method: &r.method,
                    limit: geodesic_report::fmt_limit(r),
                    probability: r.probability.as_deref(),
                    status: status.as_deref(),
                    verdict,
                })
                .collect(),
        };
        println!("{}", pretty(&doc)?);
        return Ok(0);
    }
    let table: Vec<[String; 6]> = rows
        .iter()
        .map(|(r, _, verdict)| {
            [
                r.id.clone(),
                r.title.clone(),
                r.level.clone(),
                r.method.clone(),
                geodesic_report::fmt_limit(r),
                verdict.clone(),
            ]
        })
        .collect();
    let head = ["ID", "title", "level", "method", "limit", "status"];
    let mut w = head.map(|h| h.chars().count());
    for r in &table {
        for (i, c) in r.iter().enumerate() {
            w[i] = w[i].max(c.chars().count());
        }
    }
    let pad = |s: &str, n: usize| format!("{s}{}", " ".repeat(n.saturating_sub(s.chars().count())));
    let line = |cells: Vec<String>| {
        println!(
            "{}",
            cells
                .iter()
                .enumerate()
                .map(|(i, c)| pad(c, w[i]))
                .collect::<Vec<_>>()
                .join("  ")
                .trim_end()
        )
    };
    line(head.iter().map(|s| s.to_string()).collect());
    for r in table {
        line(r.to_vec());
    }
    println!("{} requirements from {source}", reqs.items.len());
    match &last {
        Some(l) => println!("{}", l.line(&hash)),
        None => println!(
            "no last run: no {} (run `verify`, or give --reports DIR)",
            a.reports.join("compliance.json").display()
        ),
    }
    Ok(0)
}

fn show(mission: &Mission, a: ShowArgs, test_command: &str) -> CmdResult {
    let (reqs, source, hash) = load(mission, a.common.requirements.as_ref())?;
    let Some(req) = reqs.get(a.id.trim()) else {
        return Err(unknown_id("", a.id.trim(), &reqs));
    };
    let last = LastRun::find(&a.reports)?;
    let tests_path = a.tests.clone().or_else(|| {
        let p = PathBuf::from("target/geodesic/test-run.json");
        p.is_file().then_some(p)
    });
    let test_run = match &tests_path {
        Some(p) => Some(
            geodesic_core::testrun::TestRun::load(p)
                .map_err(|e| CliError::evidence(e).in_file(p, 0))?,
        ),
        None => None,
    };
    let freshness = test_run.as_ref().map(|t| {
        t.freshness_for(
            &geodesic_core::testrun::tree_state_any(Path::new(".")),
            test_command,
        )
    });
    let tests_label = tests_path.as_ref().map(|p| p.display().to_string());
    let m = bare_rows(
        &reqs,
        match (&tests_label, &test_run, &freshness) {
            (Some(file), Some(run), Some(freshness)) => Some(geodesic_core::matrix::TestEvidence {
                file,
                run,
                freshness,
            }),
            _ => None,
        },
    );
    let Some(row) = m.requirements.iter().find(|r| r.id == req.id.as_str()) else {
        return Err(CliError::evidence(format!("{}: not in the matrix", req.id)));
    };
    let children: Vec<String> = reqs
        .children(req.id.as_str())
        .iter()
        .map(|c| c.to_string())
        .collect();
    let parent = req.parent.as_ref().map(|(p, margin)| ParentDoc {
        id: p.to_string(),
        margin: *margin,
    });
    let fresh = freshness.as_ref().is_some_and(|f| f.is_fresh());
    let last_row = last.as_ref().and_then(|l| l.row(req.id.as_str()));
    let doc = ShowDoc {
        id: req.id.to_string(),
        title: &req.title,
        text: &req.text,
        family: &req.family,
        source: &req.source,
        quantity: &req.quantity,
        limit: geodesic_report::fmt_limit(row),
        probability: req.probability.as_deref(),
        method: &row.method,
        level: &row.level,
        stage: &row.stage,
        activity: &req.activity,
        check: req.check.as_deref(),
        note: req.note.as_deref(),
        defined_at: &row.defined_at,
        parent,
        children: &children,
        tests: &row.tests,
        test_run: tests_label.as_ref().map(|f| TestRunDoc { file: f, fresh }),
        requirements: &source,
        requirements_hash: &hash,
        last_run: last
            .as_ref()
            .map(|l| l.info(&hash, Some(last_row.cloned().unwrap_or(Value::Null)))),
    };
    if a.common.json {
        println!("{}", pretty(&doc)?);
        return Ok(0);
    }
    println!("{}  {}", req.id, req.title);
    println!("  {}", req.text);
    println!("  defined at   {}", row.defined_at);
    println!("  source       {}", req.source);
    if !req.quantity.is_empty() {
        println!("  quantity     {}", req.quantity);
    }
    println!(
        "  limit        {}{}",
        geodesic_report::fmt_limit(row),
        req.probability
            .as_ref()
            .map_or(String::new(), |p| format!(" at {p}"))
    );
    println!(
        "  method       {} ({} level, {} stage); activity: {}",
        row.method, row.level, row.stage, req.activity
    );
    if let Some(c) = &req.check {
        println!("  check        {c}");
    }
    match &req.parent {
        Some((p, margin)) => println!("  parent       {p} (margin factor {margin})"),
        None => println!("  parent       none"),
    }
    println!(
        "  children     {}",
        if children.is_empty() {
            "none".to_string()
        } else {
            children.join(", ")
        }
    );
    if let Some(n) = &req.note {
        println!("  note         {n}");
    }
    print_tests(tests_label.as_deref(), &row.tests, fresh, test_command);
    print_last_run(last.as_ref(), last_row, &a.reports, &hash);
    Ok(0)
}

/// Prints the traced tests of a requirement from the recorded test run `tests_label`.
fn print_tests(
    tests_label: Option<&str>,
    tests: &[geodesic_core::matrix::TestRef],
    fresh: bool,
    test_command: &str,
) {
    match (tests_label, tests.is_empty()) {
        (None, _) => println!(
            "  traced tests no recorded test run (`{test_command}` writes target/geodesic/test-run.json)"
        ),
        (Some(f), true) => println!(
            "  traced tests none in {f}{}",
            if fresh { "" } else { " (stale)" }
        ),
        (Some(f), false) => {
            println!(
                "  traced tests from {f}{}:",
                if fresh {
                    ""
                } else {
                    " (stale: results of another tree)"
                }
            );
            for t in tests {
                println!(
                    "    {} {} ({}, {})",
                    t.result.as_str(),
                    t.test,
                    t.kind,
                    t.location
                );
            }
        }
    }
}

/// Prints a requirement's row of the last run (`compliance.json` under `reports`).
fn print_last_run(last: Option<&LastRun>, last_row: Option<&Value>, reports: &Path, hash: &str) {
    match (last, last_row) {
        (None, _) => println!(
            "  last run     none: no {} (run `verify`, or give --reports DIR)",
            reports.join("compliance.json").display()
        ),
        (Some(l), None) => println!("  last run     {}: not in it", l.file.display()),
        (Some(l), Some(r)) => {
            println!("  {}", l.line(hash));
            println!(
                "  verdict      {}",
                r["verdict"]
                    .as_str()
                    .or(r["status"].as_str())
                    .unwrap_or("?")
            );
            let num = |v: &Value| v.as_f64().map(geodesic_core::units::fmt_num);
            if let Some(v) = num(&r["value"]) {
                println!(
                    "  value        {v} {}{}",
                    r["unit"].as_str().unwrap_or(""),
                    match r["margin"].as_f64() {
                        Some(m) => format!(" (margin {})", geodesic_report::fmt_margin(Some(m))),
                        None => String::new(),
                    }
                );
            }
            if let Some(reason) = r["reason"].as_str() {
                println!("  reason       {reason}");
            }
            for f in r["findings"].as_array().into_iter().flatten() {
                println!("  finding      {}", f.as_str().unwrap_or(""));
            }
            for e in r["evidence"].as_array().into_iter().flatten() {
                println!(
                    "  evidence     {}: {}{}",
                    e["check"].as_str().unwrap_or("?"),
                    e["activity"].as_str().unwrap_or(""),
                    num(&e["value"]).map_or(String::new(), |v| format!(
                        " = {v} {}",
                        r["unit"].as_str().unwrap_or("")
                    ))
                );
            }
        }
    }
}

/// A document through `serde_json::Value`: its keys in alphabetical order, as these documents
/// have always printed.
fn to_value<T: Serialize>(doc: &T) -> Result<Value, CliError> {
    serde_json::to_value(doc).map_err(CliError::io)
}

/// [`to_value`], pretty-printed.
fn pretty<T: Serialize>(doc: &T) -> Result<String, CliError> {
    serde_json::to_string_pretty(&to_value(doc)?).map_err(CliError::io)
}

/// The documents of `requirements check | list | show ID --json`, one for each action (for the
/// schema: `geodesic schema requirements`).
#[derive(JsonSchema)]
#[serde(untagged)]
pub enum RequirementsDoc {
    /// `requirements check --json`.
    Check(CheckDoc<'static>),
    /// `requirements list --json`.
    List(ListDoc<'static>),
    /// `requirements show ID --json`.
    Show(Box<ShowDoc<'static>>),
}

/// What `requirements check --json` prints: the set is valid (an invalid one is exit 2).
#[derive(Serialize, JsonSchema)]
pub struct CheckDoc<'a> {
    /// Always `true` (an invalid set is refused with exit 2 and its `file:line:column`).
    pub valid: bool,
    /// Where the set was read from (a folder, or the copy built into the binary).
    pub source: &'a str,
    /// SHA-256 of the requirement files (hex), as `verify` records it.
    pub requirements_hash: &'a str,
    /// Requirements in the set.
    pub requirements: usize,
    /// Families in the set.
    pub families: usize,
    /// The requirement files read.
    pub files: &'a std::collections::BTreeSet<String>,
}

/// The last run whose statuses `requirements list | show` report (`compliance.json` under
/// `--reports`).
#[derive(Serialize, JsonSchema)]
pub struct LastRunDoc {
    /// Its `compliance.json`.
    pub file: String,
    /// Its `run.date`, as the file has it.
    pub date: Value,
    /// Its `run.commit`, as the file has it.
    pub commit: Value,
    /// Whether it was a partial run (`verify --only`): other rows did not run.
    pub partial: bool,
    /// Whether it ran on the same requirement files (the same SHA-256).
    pub same_requirements: bool,
    /// `show` only: the requirement's row in it, as the file has it (`geodesic schema verify`,
    /// `requirements[]`), `null` when the run has none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub row: Option<Value>,
}

/// What `requirements list --json` prints.
#[derive(Serialize, JsonSchema)]
pub struct ListDoc<'a> {
    /// Where the set was read from.
    pub source: &'a str,
    /// SHA-256 of the requirement files (hex).
    pub requirements_hash: &'a str,
    /// The last run the statuses come from, `null` when there is none.
    pub last_run: Option<LastRunDoc>,
    /// One row a requirement.
    pub requirements: Vec<ListRow<'a>>,
}

/// A requirement of `requirements list --json`.
#[derive(Serialize, JsonSchema)]
pub struct ListRow<'a> {
    /// Requirement ID.
    pub id: &'a str,
    /// Title.
    pub title: &'a str,
    /// Family.
    pub family: &'a str,
    /// Level (as every report writes it).
    pub level: &'a str,
    /// ECSS verification method.
    pub method: &'a str,
    /// The limit as written, with its unit (`<= 7.5 um/s`).
    pub limit: String,
    /// Probability the limit holds with (`99.73 %`), `null` when none.
    pub probability: Option<&'a str>,
    /// Its status in the last run, `null` without one or when the run has no row for it.
    pub status: Option<&'a str>,
    /// Its verdict in the last run, or why there is none.
    pub verdict: &'a str,
}

/// What `requirements show ID --json` prints.
#[derive(Serialize, JsonSchema)]
pub struct ShowDoc<'a> {
    /// Requirement ID.
    pub id: String,
    /// Title.
    pub title: &'a str,
    /// Text.
    pub text: &'a str,
    /// Family.
    pub family: &'a str,
    /// Source (document, section).
    pub source: &'a str,
    /// The quantity the limit bounds.
    pub quantity: &'a str,
    /// The limit as written, with its unit.
    pub limit: String,
    /// Probability the limit holds with, `null` when none.
    pub probability: Option<&'a str>,
    /// ECSS verification method.
    pub method: &'a str,
    /// Level.
    pub level: &'a str,
    /// Verification stage.
    pub stage: &'a str,
    /// Verification activity.
    pub activity: &'a str,
    /// The check that provides its evidence, `null` when none.
    pub check: Option<&'a str>,
    /// Note, `null` when none.
    pub note: Option<&'a str>,
    /// `file:line` where it is defined.
    pub defined_at: &'a str,
    /// Its parent with the derivation margin, `null` for a top-level requirement.
    pub parent: Option<ParentDoc>,
    /// Requirements derived from it.
    pub children: &'a [String],
    /// Traced tests (`verifies!`) with their recorded results.
    pub tests: &'a [geodesic_core::matrix::TestRef],
    /// The recorded test run read, `null` when none.
    pub test_run: Option<TestRunDoc<'a>>,
    /// Where the set was read from.
    pub requirements: &'a str,
    /// SHA-256 of the requirement files (hex).
    pub requirements_hash: &'a str,
    /// The last run, with the requirement's row in it; `null` when there is none.
    pub last_run: Option<LastRunDoc>,
}

/// A requirement's parent.
#[derive(Serialize, JsonSchema)]
pub struct ParentDoc {
    /// Parent requirement ID.
    pub id: String,
    /// Derivation margin as the requirement file states it: this limit = margin x the
    /// parent's limit [-].
    pub margin: f64,
}

/// The recorded test run `requirements show` read.
#[derive(Serialize, JsonSchema)]
pub struct TestRunDoc<'a> {
    /// Its file.
    pub file: &'a str,
    /// Whether it is a run of this work tree.
    pub fresh: bool,
}

#[cfg(test)]
mod tests {
    use crate::ids::nearest_ids;

    #[test]
    fn nearest_ids_of_a_typo_and_of_a_fragment() {
        let ids = ["TMS-X-POS", "TMS-Y-POS", "TMS-X-VEL", "CHG-Q", "CHG-V"];
        assert_eq!(nearest_ids("tms-x-pso", &ids)[0], "TMS-X-POS");
        assert_eq!(nearest_ids("CHG-W", &ids), vec!["CHG-Q", "CHG-V"]);
        assert!(nearest_ids("ZZZZZZZZZZZZ", &ids).is_empty());
    }
}
