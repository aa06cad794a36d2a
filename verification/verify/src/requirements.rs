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
use serde_json::{Value, json};
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
    reqs.validate_checks(&mission.check_names())
        .map_err(|e| CliError::bad(e.to_string()))?;
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
        println!(
            "{}",
            json!({
                "valid": true,
                "source": source,
                "requirements_hash": hash,
                "requirements": reqs.items.len(),
                "families": reqs.families.len(),
                "files": files,
            })
        );
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
        let text = geodesic_core::fsio::read_text(&file, 1 << 30)
            .map_err(|e| CliError::bad(format!("{}: {}", file.display(), e.cause())))?;
        let doc: Value = serde_json::from_str(&text).map_err(|e| {
            CliError::bad(format!(
                "{}:{}:{}: not a compliance matrix: {e}",
                file.display(),
                e.line(),
                e.column()
            ))
        })?;
        if !doc["requirements"].is_array() {
            return Err(CliError::bad(format!(
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

    /// What the last run is, in JSON, with whether it ran on the same requirement files.
    fn info(&self, hash: &str) -> Value {
        let run = &self.doc["run"];
        json!({
            "file": self.file.display().to_string(),
            "date": run["date"],
            "commit": run["commit"],
            "partial": self.partial(),
            "same_requirements": run["requirements_hash"] == hash,
        })
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
        let doc = json!({
            "source": source,
            "requirements_hash": hash,
            "last_run": last.as_ref().map(|l| l.info(&hash)),
            "requirements": rows.iter().map(|(r, status, verdict)| json!({
                "id": r.id,
                "title": r.title,
                "family": r.family,
                "level": r.level,
                "method": r.method,
                "limit": geodesic_report::fmt_limit(r),
                "probability": r.probability,
                "status": status,
                "verdict": verdict,
            })).collect::<Vec<_>>(),
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).map_err(|e| CliError::Io(e.to_string()))?
        );
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
        Some(p) => Some(geodesic_core::testrun::TestRun::load(p).map_err(CliError::bad)?),
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
        return Err(CliError::bad(format!("{}: not in the matrix", req.id)));
    };
    let children: Vec<String> = reqs
        .children(req.id.as_str())
        .iter()
        .map(|c| c.to_string())
        .collect();
    let parent = req
        .parent
        .as_ref()
        .map(|(p, margin)| json!({"id": p.to_string(), "margin": margin}));
    let fresh = freshness.as_ref().is_some_and(|f| f.is_fresh());
    let last_row = last.as_ref().and_then(|l| l.row(req.id.as_str()));
    let doc = json!({
        "id": req.id.to_string(),
        "title": req.title,
        "text": req.text,
        "family": req.family,
        "source": req.source,
        "quantity": req.quantity,
        "limit": geodesic_report::fmt_limit(row),
        "probability": req.probability,
        "method": row.method,
        "level": row.level,
        "stage": row.stage,
        "activity": req.activity,
        "check": req.check,
        "note": req.note,
        "defined_at": row.defined_at,
        "parent": parent,
        "children": children,
        "tests": row.tests,
        "test_run": tests_label.as_ref().map(|f| json!({"file": f, "fresh": fresh})),
        "requirements": source,
        "requirements_hash": hash,
        "last_run": last.as_ref().map(|l| {
            let mut v = l.info(&hash);
            v["row"] = last_row.cloned().unwrap_or(Value::Null);
            v
        }),
    });
    if a.common.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).map_err(|e| CliError::Io(e.to_string()))?
        );
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
