//! geodesic-report: writes what `geodesic verify` produces.
//!
//! - [`markdown`]: the compliance report `compliance.md` (matrix, one section per requirement,
//!   trace views).
//! - [`terminal`]: the short table printed on a terminal.
//! - [`vcd`]: the Verification Control Document with the ECSS-E-ST-10-02C Annex B fields
//!   (Markdown, CSV; also inside the HTML page).
//! - [`xlsx`]: the same VCD as an XLSX workbook with a metadata sheet.
//! - [`html`]: `index.html`, self-contained, with the plots inlined.
//! - [`junit`]: JUnit XML for CI dashboards.
//! - [`baseline`]: change impact against a baseline `compliance.json`.
//! - [`write`]: writing a set of report files whole or not at all (staged, then renamed).
//!
//! The JSON form is the [`geodesic_core::matrix::Matrix`] itself, wrapped in [`Report`].

#![warn(missing_docs)]
pub mod baseline;
pub mod formats;
pub mod html;
pub mod junit;
pub mod markdown;
pub mod terminal;
pub mod vcd;
pub mod write;
pub mod xlsx;

use geodesic_core::matrix::Matrix;
use serde::Serialize;

/// How the verification was run (stated in every report). Everything here is controlled
/// content: two runs of the same commit and inputs give the same values apart from `date` and
/// `timings` (the wall time of each check, which differs run to run: no comparison, baseline
/// diff or determinism check reads it).
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct RunInfo {
    /// The document's identifier, issue, title and project (`verification/document.yaml`).
    pub document: geodesic_core::document::Document,
    /// The file the document identification was read from, with its SHA-256.
    pub document_file: geodesic_core::check::InputFile,
    /// geodesic version.
    pub geodesic_version: String,
    /// geodesic version (the contract's name for it).
    pub tool_version: String,
    /// Git commit of the working directory (`unknown` outside a repository).
    pub commit: String,
    /// Whether the work tree had uncommitted changes to tracked files.
    pub dirty: bool,
    /// UTC date and time of the run (RFC 3339).
    pub date: String,
    /// The command line.
    pub command: String,
    /// Requirements directory (or `built-in`).
    pub requirements: String,
    /// SHA-256 over the requirement files (names and bytes, sorted by name).
    pub requirements_hash: String,
    /// The input files the mission declares, with their SHA-256.
    pub inputs: geodesic_core::check::Inputs,
    /// The dispositions file and its SHA-256 (`None`: no dispositions).
    pub dispositions: Option<geodesic_core::check::InputFile>,
    /// The run options the mission declares (e.g. a Monte Carlo sample count `mc_n` [-] and
    /// its `seed`), each written as its own key of `run`.
    #[serde(flatten)]
    pub options: geodesic_core::check::RunOptions,
    /// Confidence of the bounds a sampled verdict is decided by [-].
    pub confidence: f64,
    /// Checks that ran, with the requirements they verify.
    pub checks: Vec<CheckRun>,
    /// geodesic's figures against the mission's reference (the fidelity table).
    pub fidelity: Vec<geodesic_core::check::ReferenceRow>,
    /// The heading and reference column of the fidelity table (the mission's descriptor
    /// names them); not part of the JSON.
    #[serde(skip)]
    pub reference: ReferenceHeading,
    /// A partial run (`verify --only`): which rows were chosen and which came as their
    /// dependencies; absent in a whole run. A gate never compares a partial run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub partial: Option<Partial>,
    /// Wall time of the run and of each check [s]: differs run to run (machine, load), so it
    /// is information only: the baseline diff and the determinism checks ignore it.
    pub timings: Timings,
    /// The commit the binary was built from (`git rev-parse HEAD` at build time), when known.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub build_commit: Option<String>,
    /// Said when the binary's build commit is not the commit of the tree it judges: the checks
    /// that ran are those of the build, not of the tree.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub build_note: Option<String>,
    /// Dispositions that name a requirement not loaded (renamed or removed), one line each:
    /// said, never silently dropped.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub unmatched_dispositions: Vec<String>,
}

/// How the reports title the fidelity table and its reference column.
#[derive(Clone, Debug)]
pub struct ReferenceHeading {
    /// The table's heading (`Fidelity against the reference`).
    pub title: String,
    /// The reference column (`Reference`).
    pub column: String,
}

impl Default for ReferenceHeading {
    fn default() -> Self {
        ReferenceHeading {
            title: "Fidelity against the reference".into(),
            column: "Reference".into(),
        }
    }
}

/// What a partial run (`verify --only ID,...`) ran.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Partial {
    /// The requirement IDs given to `--only`.
    pub only: Vec<String>,
    /// The requirements run because a chosen one depends on them (its parents, the rows a
    /// flow-down assumes, the rows that judge a model input it is computed from), with why.
    pub dependencies: Vec<PartialDependency>,
    /// Requirements loaded but not run.
    pub not_run: usize,
    /// In words.
    pub note: String,
}

/// A dependency of a partial run.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct PartialDependency {
    /// Requirement ID.
    pub id: String,
    /// Why it is needed.
    pub why: String,
}

/// Wall times of a run [s] (not controlled content: they differ run to run).
#[derive(Clone, Debug, Default, Serialize, schemars::JsonSchema)]
pub struct Timings {
    /// Wall time of every check and of the fidelity table together [s].
    pub total_s: f64,
    /// Per check (and `fidelity table`), in the order they ran.
    pub checks: Vec<CheckTiming>,
}

/// The wall time of one check [s].
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct CheckTiming {
    /// Check name (or `fidelity table`).
    pub check: String,
    /// Wall time [s].
    pub wall_s: f64,
}

/// Label of the wall-time line of [`run_lines`] (a comparison of two reports masks that line).
pub const TIMINGS_LABEL: &str = "wall time (differs run to run; not compared)";

/// The timings in one line: `total 12.3 s; check a 1.2 s, check b 3.4 s`.
pub fn timings_line(t: &Timings) -> String {
    if t.checks.is_empty() {
        return "none recorded".into();
    }
    let each: Vec<String> = t
        .checks
        .iter()
        .map(|c| format!("{} {:.1} s", c.check, c.wall_s))
        .collect();
    format!("total {:.1} s; {}", t.total_s, each.join(", "))
}

/// One check that ran.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct CheckRun {
    /// Check name.
    pub name: String,
    /// Requirement IDs it declares.
    pub verifies: Vec<String>,
}

/// The compliance report: the matrix and how it was produced. Serialises to the JSON of
/// `geodesic verify --json` (`{"requirements": [...], "summary": ..., "run": ...}`).
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Report {
    /// Matrix rows, summary and orphan checks (flattened).
    #[serde(flatten)]
    pub matrix: Matrix,
    /// Run information.
    pub run: RunInfo,
    /// Requirements a baseline comparison (`--baseline`) asks to re-verify, with why (the VCD's
    /// re-verification flag); empty without a baseline.
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub reverify: std::collections::BTreeMap<String, String>,
}

/// The run's identification as `(label, value)` pairs, for the header of every report: tool
/// version, commit (and whether the tree was dirty), date, command, requirement set and model
/// input files with their SHA-256, the test run.
pub fn run_lines(rep: &Report) -> Vec<(&str, String)> {
    let r = &rep.run;
    let short = |h: &str| h.chars().take(16).collect::<String>();
    let d = &r.document;
    let mut v = vec![
        (
            "document",
            format!("{} issue {}: {}", d.id, d.issue, d.title),
        ),
        ("project", d.project.clone()),
        ("geodesic", r.tool_version.clone()),
        (
            "commit",
            format!("{}{}", r.commit, if r.dirty { " (dirty tree)" } else { "" }),
        ),
        ("date (UTC)", r.date.clone()),
        ("command", r.command.clone()),
    ];
    if let Some(p) = &r.partial {
        v.push(("partial run", p.note.clone()));
    }
    v.extend([(
        "requirements",
        format!(
            "{} (sha256 {})",
            r.requirements,
            short(&r.requirements_hash)
        ),
    )]);
    for (_, words, f) in r.inputs.iter() {
        v.push((words, format!("{} (sha256 {})", f.label, short(&f.sha256))));
    }
    v.extend([
        (
            "time series (spectral checks)",
            if r.inputs.series.is_empty() {
                "none".into()
            } else {
                r.inputs
                    .series
                    .iter()
                    .map(|(id, f)| format!("{id}: {} (sha256 {})", f.label, short(&f.sha256)))
                    .collect::<Vec<_>>()
                    .join("; ")
            },
        ),
        (
            "dispositions",
            r.dispositions.as_ref().map_or("none".into(), |d| {
                format!("{} (sha256 {})", d.label, short(&d.sha256))
            }),
        ),
    ]);
    v.extend(r.options.lines());
    v.extend([
        (
            "sampled verdicts",
            format!(
                "decided by exact one-sided {} confidence bounds (order statistics for a quantile, Clopper-Pearson for a probability), at the probability each requirement states",
                geodesic_core::units::fmt_pct(r.confidence)
            ),
        ),
    ]);
    v.push(("test results", test_run_line(&rep.matrix)));
    v.push((TIMINGS_LABEL, timings_line(&r.timings)));
    v
}

/// The recorded test run in one line: file, commit, date, and `STALE: why` when it is not a
/// run of this tree.
pub fn test_run_line(m: &geodesic_core::matrix::Matrix) -> String {
    m.test_run.as_ref().map_or(
        "none recorded (cargo xtask test records them)".into(),
        |t| {
            format!(
                "{} (commit {}{}, {}){}",
                t.file,
                t.commit.chars().take(12).collect::<String>(),
                if t.dirty { ", dirty" } else { "" },
                t.date,
                match &t.stale_reason {
                    Some(why) if !t.fresh => format!(" STALE: {why}; not evidence for this run"),
                    _ => " fresh: a run of this work tree".into(),
                }
            )
        },
    )
}

/// A row's sample in a few words (`99.73 % quantile of N = 100 000: estimate 1.329 um/s,
/// 95 % bounds [1.323, 1.334] um/s`), or `None` when its value is not sampled.
pub fn sampling_text(r: &geodesic_core::matrix::Row) -> Option<String> {
    let s = r.sampling.as_ref()?;
    let limit = r.limit.unwrap_or(f64::NAN);
    let unit = r.unit.clone();
    Some(s.describe(&|v| {
        format!("{} {unit}", geodesic_core::units::fmt_num_near(v, limit))
            .trim_end()
            .to_string()
    }))
}

/// A row's sample in the fewest words for a table cell (`99.73 % quantile, N = 100000, 95 %
/// bound`); empty when its value is not sampled.
pub fn sampling_short(r: &geodesic_core::matrix::Row) -> String {
    use geodesic_core::check::SampleStatistic;
    use geodesic_core::units::fmt_pct;
    let Some(s) = &r.sampling else {
        return String::new();
    };
    format!(
        "{}, N = {}, {} bound",
        match s.statistic {
            SampleStatistic::Quantile => format!("{} quantile", fmt_pct(s.probability)),
            SampleStatistic::Proportion => format!("probability {}", fmt_pct(s.probability)),
        },
        s.n,
        fmt_pct(s.confidence)
    )
}

/// [`geodesic_core::units::fmt_num_near`], shorter to call from the writers.
/// What a traced test asserts, for the reports' test lines: its recorded assertions joined by
/// commas, or "nothing recorded".
pub(crate) fn assertions_text(t: &geodesic_core::matrix::TestRef) -> String {
    if t.assertions.is_empty() {
        "nothing recorded".to_string()
    } else {
        let asserted: Vec<&str> = t.assertions.iter().map(|a| a.as_str()).collect();
        asserted.join(", ")
    }
}

pub(crate) fn units_near(v: f64, limit: f64) -> String {
    geodesic_core::units::fmt_num_near(v, limit)
}

/// Formats a value for a table: 4 significant digits, `—` when absent.
pub fn fmt_opt(v: Option<f64>) -> String {
    v.map_or_else(|| "—".to_string(), geodesic_core::units::fmt_num)
}

/// The limit of a row as every report writes it: comparison, number (at most 4 significant
/// digits, [`geodesic_core::units::fmt_num`]) and unit, `<= 3e8 e`, `>= 0.9973`.
pub fn fmt_limit(r: &geodesic_core::matrix::Row) -> String {
    match r.limit {
        Some(l) => format!("{} {} {}", r.op, geodesic_core::units::fmt_num(l), r.unit)
            .trim_end()
            .to_string(),
        // a qualitative requirement: no quantitative limit
        None => r.limit_text.clone(),
    }
}

/// The deciding value of a row with its unit (`1.329 um/s`), `—` when absent; with the
/// digits it takes not to read as its limit's neighbour (`0.99997`, not `1`).
pub fn fmt_value(r: &geodesic_core::matrix::Row) -> String {
    match r.value {
        Some(v) => format!(
            "{} {}",
            match r.limit {
                Some(l) => geodesic_core::units::fmt_num_near(v, l),
                None => geodesic_core::units::fmt_num(v),
            },
            r.unit
        )
        .trim_end()
        .to_string(),
        None => "—".into(),
    }
}

/// A list of IDs for a trace view: `None.` when empty.
pub fn id_list(ids: &[&str]) -> String {
    if ids.is_empty() {
        "None.".to_string()
    } else {
        ids.join(", ")
    }
}

/// The verdict as a reader should take it, the same words in every report ([`Row::verdict`]):
/// `compliant`, `compliant (flow-down; assumes not-verified TMS-X-VEL)`, `compliant
/// (accepted, by construction)`, `non-compliant (NCR NCR-GEO-001)`, `not-verified`.
///
/// [`Row::verdict`]: geodesic_core::matrix::Row::verdict
pub fn verdict(r: &geodesic_core::matrix::Row) -> String {
    r.verdict.clone()
}

/// The basis of a row as a word (`model`, `flow-down`, `accepted`, `—`).
pub fn basis_word(r: &geodesic_core::matrix::Row) -> &'static str {
    r.basis.map_or("—", |b| b.as_str())
}

/// A row's traced tests in a few words: `2 passed`, `1 failed, 1 passed`, `1 ignored`,
/// `none` (with `no run` when no test run is recorded).
pub fn tests_word(r: &geodesic_core::matrix::Row, run_recorded: bool) -> String {
    use geodesic_core::testrun::TestResult;
    if !run_recorded {
        return "no run".into();
    }
    let mut parts = Vec::new();
    if r.tests_status == geodesic_core::matrix::TestsStatus::Stale {
        parts.push("STALE".to_string());
    }
    for res in [
        TestResult::Failed,
        TestResult::Ignored,
        TestResult::NotRun,
        TestResult::Passed,
    ] {
        let n = r.tests.iter().filter(|t| t.result == res).count();
        if n > 0 {
            parts.push(format!("{n} {}", res.as_str()));
        }
    }
    let change_only = r
        .tests
        .iter()
        .filter(|t| t.result == TestResult::Passed && !t.is_evidence())
        .count();
    if change_only > 0 {
        parts.push(format!("({change_only} change detection only)"));
    }
    if parts.is_empty() || parts == ["STALE"] {
        parts.push("none".into());
    }
    if parts[0] == "STALE" {
        format!("STALE: {}", parts[1..].join(", "))
    } else {
        parts.join(", ")
    }
}

/// A row's credibility in a cell: `0 (validation)`, `2 (verification; needs 4)`, `—` when the
/// row is not judged.
pub fn credibility_word(r: &geodesic_core::matrix::Row) -> String {
    r.credibility
        .as_ref()
        .map_or_else(|| "—".to_string(), |c| c.short())
}

/// A row's credibility factor by factor, one line each (`verification 3: ...`), with the row's
/// level and its weakest factor first; empty for a row not judged.
pub fn credibility_lines(r: &geodesic_core::matrix::Row) -> Vec<String> {
    let Some(c) = &r.credibility else {
        return Vec::new();
    };
    let mut v = vec![format!(
        "level {} (weakest: {}){}",
        c.level,
        c.weakest,
        c.required
            .map_or(String::new(), |n| format!("; its requirement needs {n}"))
    )];
    v.extend(
        c.factors()
            .iter()
            .map(|(n, f)| format!("{n} {}: {}", f.level, f.why)),
    );
    v
}

/// Formats a margin as a percentage (`70.0 %`), `—` when absent.
pub fn fmt_margin(m: Option<f64>) -> String {
    m.map_or_else(|| "—".to_string(), |m| format!("{:.1} %", 100.0 * m))
}

#[cfg(test)]
pub(crate) mod testutil {
    //! A two-requirement report for the writers' tests.
    use crate::{Report, RunInfo};
    use geodesic_core::matrix::Matrix;
    use geodesic_core::{Dim, Evidence, Quantity, Requirements};
    use std::path::PathBuf;

    const REQS: &str = "family: f
requirements:
  - id: F-A
    title: a
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: mc
  - id: F-B
    title: b
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: mc
";

    pub(crate) fn report(a_um_s: f64, b_um_s: f64) -> Report {
        let reqs = Requirements::from_sources(&[(PathBuf::from("f.yaml"), REQS.into())]).unwrap();
        let ev = vec![(
            "mc".to_string(),
            vec![
                Evidence::measured(
                    "F-A",
                    Quantity::new(a_um_s * 1e-6, Dim::VELOCITY),
                    geodesic_core::Basis::Model,
                    "mc",
                )
                .with_input("seed", 1),
                Evidence::measured(
                    "F-B",
                    Quantity::new(b_um_s * 1e-6, Dim::VELOCITY),
                    geodesic_core::Basis::Model,
                    "mc",
                )
                .with_input("seed", 1),
            ],
        )];
        Report {
            matrix: Matrix::build(&reqs, &ev, None, &[]),
            run: RunInfo {
                document: geodesic_core::document::Document {
                    id: "DOC-1".into(),
                    issue: "2".into(),
                    title: "T".into(),
                    project: "P".into(),
                },
                document_file: geodesic_core::check::InputFile::new("d.yaml", "d"),
                geodesic_version: "t".into(),
                tool_version: "t".into(),
                commit: "c".into(),
                dirty: false,
                date: "2026-01-01T00:00:00Z".into(),
                command: "geodesic verify".into(),
                requirements: "f".into(),
                requirements_hash: "h".into(),
                inputs: {
                    let mut i = geodesic_core::check::Inputs::default();
                    i.insert(
                        "a",
                        "input a",
                        geodesic_core::check::InputFile::new("a.yaml", "a"),
                    );
                    i.insert(
                        "b",
                        "input b",
                        geodesic_core::check::InputFile::new("b.yaml", "b"),
                    );
                    i
                },
                dispositions: None,
                options: {
                    let mut o = geodesic_core::check::RunOptions::default();
                    for (key, words) in [("mc_n", "N"), ("seed", "seed")] {
                        o.push(geodesic_core::check::RunOption {
                            key: key.into(),
                            value: 1,
                            words: words.into(),
                            group: "Monte Carlo".into(),
                        });
                    }
                    o
                },
                confidence: 0.95,
                checks: vec![],
                fidelity: vec![],
                reference: Default::default(),
                partial: None,
                timings: Default::default(),
                build_commit: None,
                build_note: None,
                unmatched_dispositions: Vec::new(),
            },
            reverify: Default::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::testutil::report;

    #[test]
    fn every_writer_lists_every_requirement() {
        let r = report(1.3, 6.0); // F-A compliant, F-B non-compliant
        let junit = crate::junit::render(&r);
        assert_eq!(junit.matches("<testcase ").count(), 2);
        assert_eq!(junit.matches("<failure ").count(), 1);
        assert!(junit.starts_with("<?xml") && junit.trim_end().ends_with("</testsuites>"));
        let csv = crate::vcd::csv(&r);
        assert_eq!(csv.lines().count(), 3);
        assert!(csv.contains("F-B") && csv.contains(",no,open,"));
        assert!(junit.contains("<property name=\"document\" value=\"DOC-1\"/>"));
        let html = crate::html::render(&r, &[]);
        assert!(
            html.contains("id=\"F-A\"")
                && html.contains("id=\"F-B\"")
                && html.contains("non-compliant")
        );
        assert!(
            !html.contains("http://") && !html.contains("https://"),
            "self-contained: no external resource"
        );
        let md = crate::markdown::render(&r);
        assert!(md.contains("### F-A") && md.contains("### F-B"));
        let table = crate::terminal::table(&r.matrix, false);
        assert!(
            table.contains(
                "2 requirements: 1 compliant (1 model; 1 plainly, 0 with findings), 1 non-compliant (1 without disposition), 0 not verified"
            ),
            "{table}"
        );
    }

    /// The verdict as it must be read, the sample (N, the probability, the confidence) and the
    /// summary by basis, in every writer.
    #[test]
    fn every_writer_states_the_verdict_the_sample_and_the_counts() {
        let mut r = report(1.3, 6.0);
        let row = &mut r.matrix.requirements[0];
        row.basis = Some(geodesic_core::Basis::FlowDown);
        row.verdict = "compliant (flow-down; assumes not-verified F-B)".into();
        row.findings = vec!["takes F-B as met".into()];
        row.sampling = Some(geodesic_core::check::Sampling::quantile(
            &(1..=2000).map(|k| k as f64 * 1e-3).collect::<Vec<f64>>(),
            0.9973,
            0.95,
        ));
        r.matrix.summary.compliant_by_basis = [("flow-down".to_string(), 1)].into();
        r.matrix.summary.compliant_with_findings = 1;
        let line = r.matrix.summary.line();
        assert!(line.contains("1 flow-down"), "{line}");
        let junit = crate::junit::render(&r);
        let html = crate::html::render(&r, &[]);
        let vcd_html = crate::html::render_vcd(&r);
        let md = crate::markdown::render(&r);
        let vcd_md = crate::vcd::markdown(&r);
        let csv = crate::vcd::csv(&r);
        let table = crate::terminal::table(&r.matrix, false);
        for (name, text) in [
            ("junit", &junit),
            ("html", &html),
            ("vcd.html", &vcd_html),
            ("md", &md),
            ("vcd.md", &vcd_md),
            ("csv", &csv),
            ("terminal", &table),
        ] {
            assert!(
                text.contains("flow-down; assumes not-verified F-B"),
                "{name}: no verdict"
            );
            if name != "terminal" {
                assert!(text.contains("N = 2000"), "{name}: no N");
                assert!(text.contains("95 %"), "{name}: no confidence");
                assert!(text.contains("99.73 %"), "{name}: no probability");
            }
        }
        // a qualified compliant is a JUnit pass that says so, never skipped like a not verified
        assert!(junit.contains(
            "<system-out>compliant with findings: compliant (flow-down; assumes not-verified F-B) (takes F-B as met)"
        ));
        assert!(!junit.contains("<skipped"), "{junit}");
        assert!(junit.contains("sample_n: 2000\n"));
        assert!(junit.contains("<property name=\"compliant_flow_down\" value=\"1\"/>"));
        let xlsx = crate::xlsx::render(&r).unwrap();
        assert!(!xlsx.is_empty());
    }

    #[test]
    fn html_escapes_requirement_text() {
        let mut r = report(1.0, 1.0);
        r.matrix.requirements[0].title = "<script>alert(1)</script>".into();
        let html = crate::html::render(&r, &[]);
        assert!(!html.contains("<script>alert(1)"));
    }
}
