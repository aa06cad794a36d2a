//! The compliance matrix: every requirement with its status, value, limit, margin, evidence and
//! the tests that cover it.
//!
//! A requirement is `compliant` when a check measured a value that satisfies its limit,
//! `non-compliant` when a measured value does not, and `not-verified` when no check gave a value
//! (no check at all, or a check that states why it cannot). It is never silently compliant.
//! When several checks measure the same requirement, the one with the smallest margin decides.
//!
//! A value computed from a sample (a Monte Carlo quantile, a probability from successes) carries
//! its exact confidence bounds ([`crate::check::Sampling`]) and is decided by them, never by the
//! point estimate: an upper limit is met when the upper bound meets it, violated when the lower
//! bound violates it; otherwise (the interval straddles the limit, or the sample is too small to
//! give the bound) the evidence gives no verdict and says how large a sample would.
//!
//! Every verdict also reads as what it rests on ([`Row::verdict`]): its basis when not a model
//! (`compliant (flow-down)`), what it shows by construction, the not-verified rows a flow-down
//! assumes, a model input another row rejects, and traced tests that failed, did not run, are
//! stale or are missing. The summary counts the compliant rows by basis and those with findings.

use crate::check::{Basis, Evidence, Outcome, Sampling};
use crate::disposition::Disposition;
use crate::requirement::{Limit, Op, Requirement, Requirements};
use crate::testrun::{Assertion, Freshness, TestResult, TestRun};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};

/// Compliance status of a requirement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, PartialOrd, Ord, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Verified and met.
    Compliant,
    /// Verified and not met.
    NonCompliant,
    /// No evidence gives a value.
    NotVerified,
}

impl Status {
    /// The status as written in JSON (`compliant`, `non-compliant`, `not-verified`).
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Compliant => "compliant",
            Status::NonCompliant => "non-compliant",
            Status::NotVerified => "not-verified",
        }
    }
}

/// The `limit_text` of a qualitative requirement's row (it has no limit).
pub const QUALITATIVE_LIMIT_TEXT: &str = "none (qualitative)";

/// The reason a qualitative requirement is not verified: geodesic has no value to compare, the
/// requirement is closed by its method (review of design, inspection, ...).
pub fn qualitative_reason(method: crate::requirement::Method) -> String {
    format!(
        "qualitative requirement: no quantitative limit; close by {method} (no registered check)"
    )
}

/// One piece of evidence as shown in the matrix.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct EvidenceEntry {
    /// Name of the check that produced it.
    pub check: String,
    /// What the value rests on (`None` when no value).
    pub basis: Option<Basis>,
    /// What produced the value.
    pub activity: String,
    /// Value in the requirement's unit (absent when not verified): for a sampled value, the
    /// confidence bound that decides.
    pub value: Option<f64>,
    /// Why no value, if so.
    pub reason: Option<String>,
    /// Inputs (N, seed, dataset, ...).
    pub inputs: BTreeMap<String, serde_json::Value>,
    /// Files written (relative to the reports directory).
    pub artifacts: Vec<String>,
    /// The sample and its bounds, in the requirement's unit, for a sampled value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampling: Option<Sampling>,
    /// Requirements whose limits the value takes as met (a flow-down).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub assumes: Vec<String>,
    /// Model input files the value was computed from (the names the mission declares).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub model_inputs: Vec<String>,
    /// The model input file this evidence judges.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub judges_input: Option<String>,
    /// What the value shows by construction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub by_construction: Option<String>,
}

/// A test that traces to a requirement, with its recorded result.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct TestRef {
    /// Test name (`crate::module::function`).
    pub test: String,
    /// Kind (`proptest`, `snapshot`, `unit`).
    pub kind: String,
    /// `file:line` of its `verifies!` call.
    pub location: String,
    /// Recorded result: `passed`, `failed`, `ignored` or `not-run`.
    pub result: TestResult,
    /// What it asserted: the requirement's `limit`, a `reference`, or `change-detection` only.
    pub assertions: Vec<Assertion>,
    /// Cases run (a property test runs many).
    pub cases: u64,
    /// Why the record does not count, when it does not check against the tree (its location is
    /// not in the fingerprinted tree or holds no `verifies!` of this requirement, or its call
    /// never ran).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rejected: Option<String>,
    /// Whether its source asserts this requirement's limit after its `verifies!` call (read
    /// from the tree: what a failed or ignored test would have asserted).
    #[serde(skip)]
    pub source_asserts_limit: bool,
}

impl TestRef {
    /// Whether this test asserts the requirement's own limit: recorded at run time, or in its
    /// source.
    pub fn asserts_limit(&self) -> bool {
        self.source_asserts_limit || self.assertions.contains(&Assertion::Limit)
    }

    /// Whether this test is evidence for its requirement: its record checks against the tree,
    /// its call ran, it passed and asserted the limit or an independent reference (a snapshot
    /// alone is change detection).
    pub fn is_evidence(&self) -> bool {
        self.result == TestResult::Passed
            && self.rejected.is_none()
            && self.cases > 0
            && self
                .assertions
                .iter()
                .any(|a| matches!(a, Assertion::Limit | Assertion::Reference))
    }
}

/// The state of a requirement's traced tests in the recorded run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum TestsStatus {
    /// At least one traced test passed asserting the limit or a reference, and none failed,
    /// was ignored or did not run.
    Passed,
    /// A traced test failed.
    Failed,
    /// Some traced tests were ignored or did not run (none failed).
    Incomplete,
    /// No traced test gives evidence (none, or only change detection).
    None,
    /// The recorded run is not a run of this tree (another commit, edits since, no
    /// fingerprint): its results are not evidence for this verdict.
    Stale,
    /// A record of a traced test does not check against the tree (its location is not in the
    /// fingerprinted tree, holds no `verifies!` of this requirement, or its call never ran).
    Rejected,
}

impl TestsStatus {
    /// As written in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            TestsStatus::Passed => "passed",
            TestsStatus::Failed => "failed",
            TestsStatus::Incomplete => "incomplete",
            TestsStatus::None => "none",
            TestsStatus::Stale => "stale",
            TestsStatus::Rejected => "rejected",
        }
    }
}

/// One row of the matrix.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Row {
    /// Requirement ID.
    pub id: String,
    /// Status.
    pub status: Status,
    /// The status as a reader must take it, the same words in every report:
    /// `compliant`, `compliant (flow-down; assumes not-verified TMS-X-VEL)`,
    /// `compliant (design rejected by WID-CAL)`, `non-compliant (NCR NCR-GEO-001)`,
    /// `not-verified`. Plain `compliant` only for a model (or measurement) verdict with no
    /// finding.
    pub verdict: String,
    /// What the deciding value rests on: `model`, `flow-down`, `measurement`,
    /// `method-validation` or `accepted` (`None` when not verified; illustrations never
    /// decide).
    pub basis: Option<Basis>,
    /// The findings behind the verdict's qualifiers, in plain words (an assumed requirement
    /// that is not verified, a model input another row rejects, traced tests that failed, did
    /// not run, are stale or are missing, what holds by construction).
    pub findings: Vec<String>,
    /// Known non-compliance: NCR, waiver or RFD.
    pub disposition: Option<Disposition>,
    /// Deciding value, in `unit` (for a sampled value: the confidence bound that decides).
    pub value: Option<f64>,
    /// Limit, in `unit` (`None`, JSON `null`, for a qualitative requirement: no limit).
    pub limit: Option<f64>,
    /// Margin `(limit - value) / limit` (sign-adjusted for lower bounds).
    pub margin: Option<f64>,
    /// The sample behind the deciding value (or behind the inconclusive one of a row that is
    /// not verified), with its bounds in `unit`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampling: Option<Sampling>,
    /// Requirements the deciding value takes as met (a flow-down).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub assumes: Vec<String>,
    /// Model input files the deciding value was computed from.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub model_inputs: Vec<String>,
    /// What the deciding value shows by construction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub by_construction: Option<String>,
    /// Unit of `value` and `limit`, as written in the requirement (empty when qualitative).
    pub unit: String,
    /// Comparison (`<=`, `<`, `>=`, `>`; empty when qualitative).
    pub op: String,
    /// Limit as written ([`QUALITATIVE_LIMIT_TEXT`] when the requirement has no limit).
    pub limit_text: String,
    /// Probability level, if any, as written.
    pub probability: Option<String>,
    /// Title.
    pub title: String,
    /// Shall statement.
    pub text: String,
    /// What is measured or computed.
    pub quantity: String,
    /// Family.
    pub family: String,
    /// Where the requirement comes from (a specification's table or section).
    pub source: String,
    /// Verification method.
    pub method: String,
    /// The registered check the requirement names for its evidence (`check:`; empty when
    /// none): an edit of it is an edit of the requirement.
    pub check: String,
    /// Verification level (ECSS-E-ST-10-02C: equipment, subsystem, element, system).
    pub level: String,
    /// Verification stage (qualification, acceptance, pre-launch, in-orbit, post-landing).
    pub stage: String,
    /// Verification activity.
    pub activity: String,
    /// The requirement's free note (a remark of the VCD), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// Parent ID and margin.
    pub parent: Option<String>,
    /// Parent margin factor.
    pub parent_margin: Option<f64>,
    /// Children IDs.
    pub children: Vec<String>,
    /// Why it is not verified (when so).
    pub reason: Option<String>,
    /// Evidence.
    pub evidence: Vec<EvidenceEntry>,
    /// Tests that trace to this requirement, with their recorded results.
    pub tests: Vec<TestRef>,
    /// Summary of [`Row::tests`].
    pub tests_status: TestsStatus,
    /// `file:line` of the requirement.
    pub defined_at: String,
    /// In a partial run (`verify --only`): whether the row was chosen or is run because a
    /// chosen row depends on it, and why; absent in a whole run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selection: Option<Selection>,
    /// The credibility of its verdict (levels 0-4 per factor, the weakest named); absent for
    /// a row not verified, and until the credibility assessment of the matrix has run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub credibility: Option<crate::cas::Credibility>,
}

/// Why a row is in a partial run (`verify --only`).
#[derive(Clone, Debug, Serialize, PartialEq, Eq, schemars::JsonSchema)]
pub struct Selection {
    /// `chosen` (named by `--only`) or `dependency` (a chosen row depends on it).
    pub role: String,
    /// Why, in words: `chosen`, `parent of TMS-X-POS`, `assumed by CAP-RELEASE-PROB`, `judges
    /// the input A-ROW is computed from`.
    pub why: String,
}

impl Row {
    /// Whether the verdict is plain: compliant on a model or measurement with no finding.
    pub fn plainly_compliant(&self) -> bool {
        self.status == Status::Compliant
            && matches!(self.basis, Some(Basis::Model | Basis::Measurement))
            && self.findings.is_empty()
    }
}

/// A check whose evidence names a requirement that is not loaded.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Orphan {
    /// Check name.
    pub check: String,
    /// The unknown requirement ID.
    pub requirement: String,
}

/// The summary of `rows`; `tests` is `fresh`, `stale` or `none`.
fn summarise(rows: &[Row], tests: String) -> Summary {
    let mut s = Summary {
        total: rows.len(),
        tests,
        ..Default::default()
    };
    for r in rows {
        match r.status {
            Status::Compliant => {
                s.compliant += 1;
                let b = r.basis.map_or("none", Basis::as_str).to_string();
                *s.compliant_by_basis.entry(b).or_default() += 1;
                if r.plainly_compliant() {
                    s.plainly_compliant += 1;
                }
                if !r.findings.is_empty() {
                    s.compliant_with_findings += 1;
                }
            }
            Status::NonCompliant => {
                s.non_compliant += 1;
                if r.disposition.is_none() {
                    s.non_compliant_without_disposition += 1;
                }
            }
            Status::NotVerified => s.not_verified += 1,
        }
    }
    s
}

/// Counts by status, and the compliant rows by what they rest on.
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq, schemars::JsonSchema)]
pub struct Summary {
    /// Number of requirements.
    pub total: usize,
    /// Compliant.
    pub compliant: usize,
    /// Non-compliant.
    pub non_compliant: usize,
    /// Not verified.
    pub not_verified: usize,
    /// Compliant rows by the basis of their verdict (`model`, `flow-down`, `accepted`,
    /// `method-validation`, `measurement`).
    pub compliant_by_basis: BTreeMap<String, usize>,
    /// Compliant rows on a model or measurement with no finding ([`Row::plainly_compliant`]).
    pub plainly_compliant: usize,
    /// Compliant rows whose verdict carries a finding.
    pub compliant_with_findings: usize,
    /// Non-compliant rows without a disposition (NCR, waiver, RFD).
    pub non_compliant_without_disposition: usize,
    /// The recorded test results: `fresh`, `stale` or `none` (no run recorded).
    pub tests: String,
}

impl Summary {
    /// The summary sentence every report prints: `28 requirements: 19 compliant (6 model,
    /// 8 flow-down, ...; 1 plainly, 18 with findings), 2 non-compliant, 7 not verified`.
    pub fn line(&self) -> String {
        let mut c = format!("{} compliant", self.compliant);
        if self.compliant > 0 {
            let order = [
                "model",
                "measurement",
                "flow-down",
                "method-validation",
                "accepted",
            ];
            let mut parts: Vec<String> = order
                .iter()
                .filter_map(|b| {
                    self.compliant_by_basis
                        .get(*b)
                        .filter(|n| **n > 0)
                        .map(|n| {
                            format!(
                                "{n} {}",
                                if *b == "method-validation" {
                                    "method validation"
                                } else {
                                    b
                                }
                            )
                        })
                })
                .collect();
            parts.extend(
                self.compliant_by_basis
                    .iter()
                    .filter(|(b, n)| !order.contains(&b.as_str()) && **n > 0)
                    .map(|(b, n)| format!("{n} {b}")),
            );
            c.push_str(&format!(
                " ({}; {} plainly, {} with findings)",
                parts.join(", "),
                self.plainly_compliant,
                self.compliant_with_findings
            ));
        }
        let nc = if self.non_compliant_without_disposition > 0 {
            format!(
                "{} non-compliant ({} without disposition)",
                self.non_compliant, self.non_compliant_without_disposition
            )
        } else {
            format!("{} non-compliant", self.non_compliant)
        };
        format!(
            "{} requirements: {c}, {nc}, {} not verified",
            self.total, self.not_verified
        )
    }
}

/// The compliance matrix.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Matrix {
    /// Rows, in requirement order.
    pub requirements: Vec<Row>,
    /// Counts.
    pub summary: Summary,
    /// Evidence naming unknown requirements.
    pub orphan_checks: Vec<Orphan>,
    /// The recorded test run the test results come from (`None`: no run recorded).
    pub test_run: Option<TestRunInfo>,
}

/// Where the test results come from.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct TestRunInfo {
    /// File read.
    pub file: String,
    /// Commit the tests ran on.
    pub commit: String,
    /// Whether that tree was dirty.
    pub dirty: bool,
    /// When the run finished.
    pub date: String,
    /// The command.
    pub command: String,
    /// Whether the run is a run of the tree this matrix was computed on (same commit and
    /// content fingerprint, [`TestRun::freshness`]); its results count only then.
    pub fresh: bool,
    /// Why not, when stale.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stale_reason: Option<String>,
    /// The run's tree fingerprint.
    pub tree_sha256: Option<String>,
}

/// A recorded test run as the matrix reads it: the file, the run and whether it is a run of
/// the tree the verdicts are computed on.
#[derive(Clone, Copy, Debug)]
pub struct TestEvidence<'a> {
    /// The file it was read from.
    pub file: &'a str,
    /// The run.
    pub run: &'a TestRun,
    /// Whether it is a run of this tree.
    pub freshness: &'a Freshness,
}

/// The freshness [`Matrix::build`] gives a run it was not told about: stale.
static UNCHECKED: std::sync::LazyLock<Freshness> = std::sync::LazyLock::new(|| Freshness::Stale {
    reason: "its freshness was not checked against the work tree".into(),
});

impl Matrix {
    /// Builds the matrix from requirements, the evidence of each check (by check name), the
    /// recorded test run (`run`: the file it came from and its content) and the dispositions.
    /// The run's freshness is not checked here, so it counts as stale: `geodesic verify` uses
    /// [`Matrix::build_with`] with [`TestRun::freshness`].
    pub fn build(
        reqs: &Requirements,
        evidence: &[(String, Vec<Evidence>)],
        run: Option<(&str, &TestRun)>,
        dispositions: &[Disposition],
    ) -> Matrix {
        Matrix::build_with(
            reqs,
            evidence,
            run.map(|(file, run)| TestEvidence {
                file,
                run,
                freshness: &UNCHECKED,
            }),
            dispositions,
        )
    }

    /// Builds the matrix with a test run whose freshness is known.
    pub fn build_with(
        reqs: &Requirements,
        evidence: &[(String, Vec<Evidence>)],
        tests: Option<TestEvidence<'_>>,
        dispositions: &[Disposition],
    ) -> Matrix {
        let mut orphans = Vec::new();
        // a model input judged by evidence whose requirement is not loaded (renamed or
        // removed): input -> that requirement
        let mut unjudged: BTreeMap<String, String> = BTreeMap::new();
        let mut by_req: BTreeMap<&str, Vec<(&str, &Evidence)>> = BTreeMap::new();
        for (check, evs) in evidence {
            for e in evs {
                if reqs.get(&e.requirement).is_none()
                    && let Some(i) = &e.judges_input
                {
                    unjudged
                        .entry(i.clone())
                        .or_insert_with(|| e.requirement.clone());
                }
                if reqs.get(&e.requirement).is_some() {
                    by_req
                        .entry(e.requirement.as_str())
                        .or_default()
                        .push((check.as_str(), e));
                } else {
                    orphans.push(Orphan {
                        check: check.clone(),
                        requirement: e.requirement.clone(),
                    });
                }
            }
        }
        let mut rows: Vec<Row> = reqs
            .items
            .iter()
            .map(|r| {
                row(
                    r,
                    reqs,
                    by_req.get(r.id.as_str()).map(Vec::as_slice).unwrap_or(&[]),
                    tests,
                    dispositions.iter().find(|d| d.requirement == r.id.as_str()),
                )
            })
            .collect();
        closure(&mut rows, tests);
        findings(&mut rows, tests, &unjudged);
        let s = summarise(
            &rows,
            match tests {
                None => "none".into(),
                Some(t) if t.freshness.is_fresh() => "fresh".into(),
                Some(_) => "stale".into(),
            },
        );
        Matrix {
            requirements: rows,
            summary: s,
            orphan_checks: orphans,
            test_run: tests.map(|t| TestRunInfo {
                file: t.file.to_string(),
                commit: t.run.commit.clone(),
                dirty: t.run.dirty,
                date: t.run.date.clone(),
                command: t.run.command.clone(),
                fresh: t.freshness.is_fresh(),
                stale_reason: t.freshness.reason().map(str::to_string),
                tree_sha256: t.run.tree_sha256.clone(),
            }),
        }
    }

    /// Keeps only the rows `keep` accepts (a partial run, `verify --only`) and counts the
    /// summary again over them.
    pub fn retain_rows(&mut self, keep: impl Fn(&Row) -> bool) {
        self.requirements.retain(|r| keep(r));
        let tests = std::mem::take(&mut self.summary.tests);
        self.summary = summarise(&self.requirements, tests);
    }

    /// IDs of the requirements no check gave a value for (trace view).
    pub fn without_value(&self) -> Vec<&str> {
        self.requirements
            .iter()
            .filter(|r| r.value.is_none())
            .map(|r| r.id.as_str())
            .collect()
    }

    /// IDs of the requirements without a passing traced test that asserts their limit or an
    /// independent reference (trace view).
    pub fn without_tests(&self) -> Vec<&str> {
        self.requirements
            .iter()
            .filter(|r| !r.tests.iter().any(TestRef::is_evidence))
            .map(|r| r.id.as_str())
            .collect()
    }

    /// IDs of the requirements whose traced tests failed, were ignored or did not run, or are
    /// stale.
    pub fn with_test_problems(&self) -> Vec<&str> {
        self.requirements
            .iter()
            .filter(|r| {
                matches!(
                    r.tests_status,
                    TestsStatus::Failed | TestsStatus::Incomplete | TestsStatus::Stale
                )
            })
            .map(|r| r.id.as_str())
            .collect()
    }

    /// The rows whose verdict needs test evidence and has none: a verdict (compliant or
    /// non-compliant) computed by a model, from a measurement or as a method validation, with
    /// no passing traced test that asserts its limit or a reference (a flow-down or an
    /// accepted value rests on other rows or a cited source, not on a test of its own).
    pub fn without_test_evidence(&self) -> Vec<&str> {
        self.requirements
            .iter()
            .filter(|r| {
                r.status != Status::NotVerified
                    && matches!(
                        r.basis,
                        Some(Basis::Model | Basis::Measurement | Basis::MethodValidation)
                    )
                    && !r.tests.iter().any(TestRef::is_evidence)
            })
            .map(|r| r.id.as_str())
            .collect()
    }

    /// Exit status of `verify`: 1 if any requirement is non-compliant, else 0.
    pub fn exit_code(&self) -> u8 {
        u8::from(self.summary.non_compliant > 0)
    }
}

/// What one piece of evidence decides, in the requirement's unit.
enum Decision {
    /// A value and its margin.
    Value(f64, f64),
    /// No verdict, with why.
    Undecided(String),
}

/// The decision of a sampled value: by its bounds, never its estimate.
fn decide_sampled(s: &Sampling, op: Op, limit: f64, unit: &str, check: &str) -> Decision {
    let fmt = |v: f64| {
        format!("{} {unit}", crate::units::fmt_num_near(v, limit))
            .trim_end()
            .to_string()
    };
    let (meets, violates) = match op {
        Op::Le | Op::Lt => (s.upper, s.lower),
        Op::Ge | Op::Gt => (s.lower, s.upper),
    };
    if let Some(b) = meets
        && op.holds(b, limit)
    {
        return Decision::Value(b, op.margin(b, limit));
    }
    if let Some(b) = violates
        && !op.holds(b, limit)
    {
        return Decision::Value(b, op.margin(b, limit));
    }
    let conf = crate::units::fmt_pct(s.confidence);
    let what = match s.statistic {
        crate::check::SampleStatistic::Quantile => {
            format!("the {} quantile", crate::units::fmt_pct(s.probability))
        }
        crate::check::SampleStatistic::Proportion => {
            format!("a probability of {}", crate::units::fmt_pct(s.probability))
        }
    };
    let why = if meets.is_none() || s.n < s.n_required {
        format!(
            "N = {} cannot show {what} at {conf} confidence; need N >= {} (check {check}: estimate {})",
            s.n,
            s.n_required,
            fmt(s.estimate)
        )
    } else {
        format!(
            "check {check}: inconclusive at {conf} confidence: the bounds [{}, {}] of {what} (estimate {}, N = {}) straddle the limit {} {}; a larger sample decides",
            s.lower.map_or("none".into(), fmt),
            s.upper.map_or("none".into(), fmt),
            fmt(s.estimate),
            s.n,
            op.symbol(),
            fmt(limit)
        )
    };
    Decision::Undecided(why)
}

fn row(
    r: &Requirement,
    reqs: &Requirements,
    evs: &[(&str, &Evidence)],
    tests: Option<TestEvidence<'_>>,
    disposition: Option<&Disposition>,
) -> Row {
    let verdict = match &r.limit {
        Some(lim) => {
            let mut tally = Tally::default();
            for (check, e) in evs {
                tally.add(lim, check, e);
            }
            tally.verdict(lim)
        }
        None => qualitative_verdict(r, evs),
    };
    finish_row(r, reqs, tests, disposition, verdict)
}

/// The evidence entry of `check` as the matrix shows it: its basis only with a value.
fn evidence_entry(
    check: &str,
    e: &Evidence,
    value: Option<f64>,
    reason: Option<String>,
    sampling: Option<Sampling>,
) -> EvidenceEntry {
    EvidenceEntry {
        check: check.to_string(),
        basis: if value.is_some() { e.basis } else { None },
        activity: e.activity.clone(),
        value,
        reason,
        inputs: e.inputs.clone(),
        artifacts: e.artifacts.clone(),
        sampling,
        assumes: e.assumes.clone(),
        model_inputs: e.model_inputs.clone(),
        judges_input: e.judges_input.clone(),
        by_construction: e.by_construction.clone(),
    }
}

/// The verdict of a qualitative requirement: no value can decide; evidence that names it
/// anyway is shown, not used.
fn qualitative_verdict(r: &Requirement, evs: &[(&str, &Evidence)]) -> Verdict {
    let entries = evs
        .iter()
        .map(|(check, e)| {
            evidence_entry(
                check,
                e,
                None,
                Some(format!(
                    "check {check} gave evidence for a qualitative requirement (no limit to compare with)"
                )),
                None,
            )
        })
        .collect();
    Verdict {
        status: Status::NotVerified,
        deciding: None,
        value: None,
        margin: None,
        reason: Some(qualitative_reason(r.method)),
        entries,
        sampling: None,
    }
}

/// The evidence of a quantitative requirement, read one piece at a time: the deciding value
/// with the smallest margin, and why the others decide nothing.
#[derive(Default)]
struct Tally {
    entries: Vec<EvidenceEntry>,
    /// (entry index, value in the limit's unit, margin)
    best: Option<(usize, f64, f64)>,
    /// The sample of deciding evidence that could not decide.
    undecided_sampling: Option<Sampling>,
    reasons: Vec<String>,
    illustrations: Vec<String>,
}

impl Tally {
    /// Adds the evidence `e` of `check` against limit `lim`.
    fn add(&mut self, lim: &Limit, check: &str, e: &Evidence) {
        let sampling = e.sampling.clone().map(|s| s.scaled(1.0 / lim.unit.scale));
        let (value, reason) = match &e.outcome {
            Outcome::Measured(q) if q.dim == lim.dim && !q.value.is_nan() => {
                self.measured(lim, check, e, q.value, sampling.as_ref())
            }
            Outcome::Measured(q) => {
                let why = if q.value.is_nan() {
                    format!("check {check} gave no number (NaN)")
                } else {
                    format!(
                        "check {check} gave a {} for a {} requirement",
                        q.dim, lim.dim
                    )
                };
                self.reasons.push(why.clone());
                (None, Some(why))
            }
            Outcome::NotVerified(why) => {
                self.reasons.push(why.clone());
                (None, Some(why.clone()))
            }
        };
        self.entries
            .push(evidence_entry(check, e, value, reason, sampling));
    }

    /// A measured value `si` (SI, of the limit's dimension) of `check`: its value in the
    /// limit's unit, or why it decides nothing (a sample whose bounds straddle the limit).
    fn measured(
        &mut self,
        lim: &Limit,
        check: &str,
        e: &Evidence,
        si: f64,
        sampling: Option<&Sampling>,
    ) -> (Option<f64>, Option<String>) {
        let scale = lim.unit.scale;
        let limit = lim.value.value / scale;
        let basis = e.basis.unwrap_or(Basis::Illustration);
        let decision = match sampling {
            Some(s) => decide_sampled(s, lim.op, limit, &lim.unit.symbol, check),
            None => {
                let v = si / scale;
                Decision::Value(v, lim.op.margin(v, limit))
            }
        };
        match decision {
            Decision::Value(v, m) if basis.decides() => {
                if self.best.is_none_or(|(_, _, bm)| m < bm) {
                    self.best = Some((self.entries.len(), v, m));
                }
                (Some(v), None)
            }
            Decision::Value(v, _) => {
                self.illustrations.push(format!(
                    "illustration only (not a verdict): {} gives {} {}",
                    check,
                    crate::units::fmt_num(v),
                    lim.unit.symbol
                ));
                (Some(v), None)
            }
            Decision::Undecided(why) => {
                if basis.decides() {
                    self.reasons.push(why.clone());
                    self.undecided_sampling = self.undecided_sampling.take().or(sampling.cloned());
                }
                (None, Some(why))
            }
        }
    }

    /// The verdict: by the deciding value with the smallest margin, else not verified with
    /// every reason (the illustrations last).
    fn verdict(mut self, lim: &Limit) -> Verdict {
        let limit = lim.value.value / lim.unit.scale;
        match self.best {
            Some((i, v, m)) => Verdict {
                status: if lim.op.holds(v, limit) {
                    Status::Compliant
                } else {
                    Status::NonCompliant
                },
                deciding: Some(i),
                value: Some(v),
                margin: Some(m),
                reason: None,
                sampling: self.entries[i].sampling.clone(),
                entries: self.entries,
            },
            None => {
                self.reasons.extend(self.illustrations);
                let why = if self.reasons.is_empty() {
                    "no check provides evidence for this requirement".to_string()
                } else {
                    self.reasons.join("; ")
                };
                Verdict {
                    status: Status::NotVerified,
                    deciding: None,
                    value: None,
                    margin: None,
                    reason: Some(why),
                    sampling: self.undecided_sampling,
                    entries: self.entries,
                }
            }
        }
    }
}

/// What the evidence decided for one requirement.
struct Verdict {
    status: Status,
    /// Index of the deciding entry.
    deciding: Option<usize>,
    value: Option<f64>,
    margin: Option<f64>,
    reason: Option<String>,
    entries: Vec<EvidenceEntry>,
    sampling: Option<Sampling>,
}

/// The row of `r` with its verdict, tests and links (its findings and verdict text follow in
/// [`findings`], once every row's status is known).
fn finish_row(
    r: &Requirement,
    reqs: &Requirements,
    tests: Option<TestEvidence<'_>>,
    disposition: Option<&Disposition>,
    v: Verdict,
) -> Row {
    let Verdict {
        status,
        deciding,
        value,
        margin,
        reason,
        entries,
        sampling,
    } = v;
    let deciding = deciding.map(|i| &entries[i]);
    let test_refs: Vec<TestRef> = tests
        .map(|t| {
            t.run
                .for_requirement(r.id.as_str())
                .map(|t| TestRef {
                    test: format!("{}::{}", t.krate, t.test),
                    kind: t.kind.clone(),
                    location: t.location.clone(),
                    result: t.result,
                    assertions: t.assertions_for(r.id.as_str()),
                    cases: t.cases,
                    rejected: t.rejected.get(r.id.as_str()).cloned().or_else(|| {
                        (t.result == TestResult::Passed && t.cases == 0)
                            .then(|| "its verifies! call never ran (cases 0)".to_string())
                    }),
                    source_asserts_limit: t.source_asserts_limit.contains(r.id.as_str()),
                })
                .collect()
        })
        .unwrap_or_default();
    let tests_status = if tests.is_some_and(|t| !t.freshness.is_fresh()) {
        TestsStatus::Stale
    } else if test_refs.iter().any(|t| t.rejected.is_some()) {
        TestsStatus::Rejected
    } else if test_refs.iter().any(|t| t.result == TestResult::Failed) {
        TestsStatus::Failed
    } else if test_refs
        .iter()
        .any(|t| matches!(t.result, TestResult::Ignored | TestResult::NotRun))
    {
        TestsStatus::Incomplete
    } else if test_refs.iter().any(TestRef::is_evidence) {
        TestsStatus::Passed
    } else {
        TestsStatus::None
    };
    Row {
        id: r.id.to_string(),
        status,
        verdict: status.as_str().to_string(),
        basis: deciding.and_then(|e| e.basis),
        findings: Vec::new(),
        disposition: disposition.cloned(),
        value,
        limit: r.limit.as_ref().map(|l| l.in_unit()),
        margin,
        sampling,
        assumes: deciding.map_or_else(Vec::new, |e| e.assumes.clone()),
        model_inputs: deciding.map_or_else(Vec::new, |e| e.model_inputs.clone()),
        by_construction: deciding.and_then(|e| e.by_construction.clone()),
        unit: r
            .limit
            .as_ref()
            .map_or_else(String::new, |l| l.unit.symbol.clone()),
        op: r
            .limit
            .as_ref()
            .map_or_else(String::new, |l| l.op.symbol().to_string()),
        limit_text: r
            .limit
            .as_ref()
            .map_or_else(|| QUALITATIVE_LIMIT_TEXT.to_string(), |l| l.text.clone()),
        probability: r.probability.clone(),
        title: r.title.clone(),
        text: r.text.clone(),
        quantity: r.quantity.clone(),
        family: r.family.clone(),
        source: r.source.clone(),
        method: r.method.to_string(),
        check: r.check.clone().unwrap_or_default(),
        level: r.level.as_str().to_string(),
        stage: r.stage.as_str().to_string(),
        note: r.note.clone(),
        activity: r.activity.clone(),
        parent: r.parent.as_ref().map(|(p, _)| p.to_string()),
        parent_margin: r.parent.as_ref().map(|(_, m)| *m),
        children: reqs
            .children(r.id.as_str())
            .into_iter()
            .map(|c| c.to_string())
            .collect(),
        reason,
        evidence: entries,
        tests: test_refs,
        tests_status,
        defined_at: format!("{}:{}", r.origin.file.display(), r.origin.line),
        selection: None,
        credibility: None,
    }
}

/// Turns a compliant row not verified when what closes it does not stand: a traced test that
/// asserts its limit failed, was ignored or did not run (in a run of this tree), or its ECSS
/// method is `test` and neither a measurement nor a passing traced test that asserts its
/// limit closes it (a model, a flow-down or an analysis does not close a test requirement).
fn closure(rows: &mut [Row], tests: Option<TestEvidence<'_>>) {
    let fresh = tests.is_some_and(|t| t.freshness.is_fresh());
    for r in rows.iter_mut() {
        if r.status != Status::Compliant {
            continue;
        }
        let shown = format!(
            "{} {}",
            r.value.map_or("?".into(), crate::units::fmt_num),
            r.unit
        )
        .trim_end()
        .to_string();
        let basis = r.basis.map_or("none", Basis::label);
        let why = if fresh
            && let Some(t) = r.tests.iter().find(|t| {
                t.rejected.is_none()
                    && t.asserts_limit()
                    && matches!(
                        t.result,
                        TestResult::Failed | TestResult::Ignored | TestResult::NotRun
                    )
            }) {
            Some(format!(
                "traced test {} asserts its limit and {}: the {basis} value ({shown}) does not close it while its test does not pass",
                t.test,
                match t.result {
                    TestResult::Failed => "failed",
                    TestResult::Ignored => "was ignored",
                    _ => "did not run",
                }
            ))
        } else if r.method == crate::requirement::Method::Test.to_string()
            && r.basis != Some(Basis::Measurement)
            && !(fresh
                && r.tests
                    .iter()
                    .any(|t| t.is_evidence() && t.assertions.contains(&Assertion::Limit)))
        {
            Some(format!(
                "its method is test (ECSS-E-ST-10-02C): {basis} evidence ({shown}) does not close it; a measurement, or a passing traced test of it that asserts its limit, does"
            ))
        } else {
            None
        };
        if let Some(why) = why {
            r.status = Status::NotVerified;
            r.reason = Some(why);
            r.value = None;
            r.margin = None;
            r.basis = None;
            r.sampling = None;
            r.assumes.clear();
            r.by_construction = None;
        }
    }
}

/// The short name of a model input in a verdict: its declared name, `_` read as a space.
fn input_word(name: &str) -> String {
    name.replace('_', " ")
}

/// Fills every row's findings and verdict text, once every status is known: what a flow-down
/// assumes that is not verified (followed through the assumed rows' own assumptions), a model
/// input a non-compliant row rejects, the traced tests, what holds by construction.
fn findings(
    rows: &mut [Row],
    tests: Option<TestEvidence<'_>>,
    unjudged: &BTreeMap<String, String>,
) {
    let status: BTreeMap<String, Status> = rows.iter().map(|r| (r.id.clone(), r.status)).collect();
    let assumes: BTreeMap<String, Vec<String>> = rows
        .iter()
        .map(|r| (r.id.clone(), r.assumes.clone()))
        .collect();
    let rejected = rejected_inputs(rows);
    let fresh_run = tests.is_some_and(|t| t.freshness.is_fresh());
    for r in rows.iter_mut() {
        let mut qual: Vec<String> = Vec::new();
        let mut found: Vec<String> = Vec::new();
        if r.status == Status::NotVerified {
            r.verdict = r.status.as_str().to_string();
            if r.tests_status == TestsStatus::Stale {
                found.push(format!(
                    "traced test results are stale: {}",
                    tests.and_then(|t| t.freshness.reason()).unwrap_or("")
                ));
            }
            r.findings = found;
            continue;
        }
        basis_findings(r, &mut qual, &mut found);
        assumption_findings(r, &status, &assumes, &mut qual, &mut found);
        for i in &r.model_inputs {
            if let Some((judge, disp)) = rejected.get(i)
                && *judge != r.id
            {
                qual.push(format!("{} rejected by {judge}", input_word(i)));
                found.push(format!(
                    "computed from the {} that {judge} rejects (non-compliant{})",
                    input_word(i),
                    disp.as_ref().map_or(String::new(), |d| format!("; {d}"))
                ));
            }
        }
        for i in &r.model_inputs {
            if let Some(judge) = unjudged.get(i)
                && !rejected.contains_key(i)
            {
                qual.push(format!("{} judge {judge} not loaded", input_word(i)));
                found.push(format!(
                    "computed from the {} that {judge} judges, and {judge} is not in the requirement set (renamed or removed): that judgement, and any disposition of it, is missing",
                    input_word(i)
                ));
            }
        }
        test_findings(r, tests, fresh_run, &mut qual, &mut found);
        r.verdict = if qual.is_empty() {
            r.status.as_str().to_string()
        } else {
            format!("{} ({})", r.status.as_str(), qual.join("; "))
        };
        r.findings = found;
    }
}

/// The model inputs a non-compliant row rejects: input -> (the first such row, its
/// disposition).
fn rejected_inputs(rows: &[Row]) -> BTreeMap<String, (String, Option<String>)> {
    let mut rejected: BTreeMap<String, (String, Option<String>)> = BTreeMap::new();
    for r in rows {
        if r.status != Status::NonCompliant {
            continue;
        }
        for e in r.evidence.iter().filter(|e| e.value.is_some()) {
            if let Some(i) = &e.judges_input {
                rejected.entry(i.clone()).or_insert((
                    r.id.clone(),
                    r.disposition
                        .as_ref()
                        .map(|d| format!("{} {}", d.kind.as_str(), d.reference)),
                ));
            }
        }
    }
    rejected
}

/// The assumed rows of `id` that are not verified or not met, through chains of assumptions
/// (`seen`: the rows already followed).
fn unmet(
    id: &str,
    status: &BTreeMap<String, Status>,
    assumes: &BTreeMap<String, Vec<String>>,
    seen: &mut BTreeSet<String>,
    out: &mut Vec<(String, Status)>,
) {
    for a in assumes.get(id).into_iter().flatten() {
        if !seen.insert(a.clone()) {
            continue;
        }
        let s = status.get(a).copied().unwrap_or(Status::NotVerified);
        if s != Status::Compliant {
            out.push((a.clone(), s));
        }
        unmet(a, status, assumes, seen, out);
    }
}

/// A verified row's qualifiers (`qual`) and findings (`found`) from what it rests on: a
/// non-compliance's disposition (or its absence), a basis other than a model, a proof by
/// construction.
fn basis_findings(r: &Row, qual: &mut Vec<String>, found: &mut Vec<String>) {
    if r.status == Status::NonCompliant {
        match &r.disposition {
            Some(d) => qual.push(format!(
                "{} {}{}",
                d.kind.as_str(),
                d.reference,
                if d.expired { " EXPIRED" } else { "" }
            )),
            None => {
                qual.push("no disposition".into());
                found.push(
                    "non-compliant with no disposition (NCR, waiver or RFD) in the dispositions file"
                        .into(),
                );
            }
        }
    }
    if r.status == Status::Compliant
        && let Some(d) = &r.disposition
    {
        qual.push(format!("{} {} open", d.kind.as_str(), d.reference));
        found.push(format!(
            "a {} ({}, {}) is open against it: {}",
            d.kind.as_str(),
            d.reference,
            d.date,
            d.reason
        ));
    }
    if let Some(b) = r.basis
        && b != Basis::Model
    {
        qual.push(b.label().to_string());
    }
    if r.status == Status::Compliant
        && r.method == crate::requirement::Method::Test.to_string()
        && r.basis != Some(Basis::Measurement)
    {
        qual.push("method test: closed by its traced test".into());
        found.push(format!(
            "its method is test: closed by a passing traced test that asserts its limit (the {} value is shown beside it)",
            r.basis.map_or("none", Basis::label)
        ));
    }
    if let Some(why) = &r.by_construction {
        qual.push("by construction".into());
        found.push(format!("holds by construction: {why}"));
    }
}

/// A verified row's qualifiers and findings from the rows it takes as met that are not
/// verified or not met.
fn assumption_findings(
    r: &Row,
    status: &BTreeMap<String, Status>,
    assumes: &BTreeMap<String, Vec<String>>,
    qual: &mut Vec<String>,
    found: &mut Vec<String>,
) {
    let mut miss = Vec::new();
    unmet(
        &r.id,
        status,
        assumes,
        &mut BTreeSet::from([r.id.clone()]),
        &mut miss,
    );
    match miss.as_slice() {
        [] => {}
        [(id, s)] => qual.push(format!("assumes {} {id}", s.as_str())),
        many => qual.push(format!(
            "assumes {} rows not verified or not met",
            many.len()
        )),
    }
    for (id, s) in &miss {
        found.push(format!(
            "takes {id} as met, which is {}: the verdict holds only if {id} does",
            s.as_str()
        ));
    }
}

/// A verified row's qualifiers and findings from its traced tests: failed, did not run,
/// stale, or (in a fresh run) none that passes and asserts the limit of a verdict that needs
/// one.
fn test_findings(
    r: &Row,
    tests: Option<TestEvidence<'_>>,
    fresh_run: bool,
    qual: &mut Vec<String>,
    found: &mut Vec<String>,
) {
    match r.tests_status {
        TestsStatus::Rejected => {
            qual.push("test record rejected".into());
            let names: Vec<String> = r
                .tests
                .iter()
                .filter_map(|t| t.rejected.as_ref().map(|w| format!("{} ({w})", t.test)))
                .collect();
            found.push(format!(
                "traced test record rejected against the tree: {}",
                names.join(", ")
            ));
        }
        TestsStatus::Failed => {
            qual.push("test failed".into());
            let names: Vec<&str> = r
                .tests
                .iter()
                .filter(|t| t.result == TestResult::Failed)
                .map(|t| t.test.as_str())
                .collect();
            found.push(format!("traced test failed: {}", names.join(", ")));
        }
        TestsStatus::Incomplete => {
            qual.push("tests incomplete".into());
            let names: Vec<String> = r
                .tests
                .iter()
                .filter(|t| matches!(t.result, TestResult::Ignored | TestResult::NotRun))
                .map(|t| format!("{} ({})", t.test, t.result.as_str()))
                .collect();
            found.push(format!("traced test did not run: {}", names.join(", ")));
        }
        TestsStatus::Stale => {
            qual.push("tests stale".into());
            found.push(format!(
                "traced test results are stale: {}",
                tests.and_then(|t| t.freshness.reason()).unwrap_or("")
            ));
        }
        TestsStatus::Passed | TestsStatus::None => {
            let needs = matches!(
                r.basis,
                Some(Basis::Model | Basis::Measurement | Basis::MethodValidation)
            );
            if fresh_run && needs && !r.tests.iter().any(TestRef::is_evidence) {
                qual.push("no traced test".into());
                found.push(
                    "no passing traced test asserts its limit or an independent reference".into(),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::{Dim, Quantity};
    use std::path::PathBuf;

    fn reqs() -> Requirements {
        let t = "family: f
requirements:
  - id: A-ONE
    title: a
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: mc
  - id: A-TWO
    title: b
    text: shall
    source: s
    quantity: q
    dimension: dimensionless
    limit: '>= 0.9973'
    method: analysis
    activity: mc
  - id: A-THREE
    title: c
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: none
";
        Requirements::from_sources(&[(PathBuf::from("f.yaml"), t.into())]).unwrap()
    }

    #[test]
    fn statuses_and_margins() {
        let r = reqs();
        let ev = vec![(
            "mc".to_string(),
            vec![
                Evidence::measured(
                    "A-ONE",
                    Quantity::new(1.5e-6, Dim::VELOCITY),
                    Basis::Model,
                    "mc",
                ),
                Evidence::measured(
                    "A-TWO",
                    Quantity::new(0.99, Dim::DIMENSIONLESS),
                    Basis::Model,
                    "mc",
                ),
                Evidence::measured(
                    "NOPE",
                    Quantity::new(0.99, Dim::DIMENSIONLESS),
                    Basis::Model,
                    "mc",
                ),
            ],
        )];
        let m = Matrix::build(&r, &ev, None, &[]);
        assert_eq!(m.requirements[0].status, Status::Compliant);
        assert!((m.requirements[0].value.unwrap() - 1.5).abs() < 1e-9);
        assert!((m.requirements[0].margin.unwrap() - 0.7).abs() < 1e-9);
        assert_eq!(m.requirements[1].status, Status::NonCompliant);
        assert!(m.requirements[1].margin.unwrap() < 0.0);
        assert_eq!(m.requirements[2].status, Status::NotVerified);
        assert!(
            m.requirements[2]
                .reason
                .as_ref()
                .unwrap()
                .contains("no check")
        );
        assert_eq!(m.orphan_checks.len(), 1);
        assert_eq!(m.exit_code(), 1);
    }

    #[test]
    fn qualitative_requirement_is_not_verified_beside_the_others() {
        let t = "family: f
requirements:
  - id: A-ONE
    title: a
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: mc
  - id: A-GROUND
    title: g
    text: The TM shall be grounded.
    source: s
    method: inspection
    activity: inspection of the harness
";
        let r = Requirements::from_sources(&[(PathBuf::from("f.yaml"), t.into())]).unwrap();
        let ev = vec![(
            "mc".to_string(),
            vec![
                Evidence::measured(
                    "A-ONE",
                    Quantity::new(1.5e-6, Dim::VELOCITY),
                    Basis::Model,
                    "mc",
                ),
                // a check that names it anyway gives no verdict
                Evidence::measured(
                    "A-GROUND",
                    Quantity::new(1.0, Dim::DIMENSIONLESS),
                    Basis::Model,
                    "mc",
                ),
            ],
        )];
        let m = Matrix::build(&r, &ev, None, &[]);
        assert_eq!(m.requirements[0].status, Status::Compliant);
        let g = &m.requirements[1];
        assert_eq!(g.status, Status::NotVerified);
        assert_eq!(
            g.reason.as_deref(),
            Some(
                "qualitative requirement: no quantitative limit; close by inspection (no registered check)"
            )
        );
        assert!(g.basis.is_none() && g.margin.is_none() && g.value.is_none());
        assert!(g.limit.is_none() && g.op.is_empty() && g.unit.is_empty());
        assert_eq!(g.limit_text, QUALITATIVE_LIMIT_TEXT);
        assert_eq!(g.evidence.len(), 1);
        assert!(g.evidence[0].value.is_none() && g.evidence[0].basis.is_none());
        assert_eq!(m.summary.not_verified, 1);
        assert_eq!(m.exit_code(), 0);
        let j = serde_json::to_value(&m).unwrap();
        assert!(j["requirements"][1]["limit"].is_null());
        assert!(j["requirements"][1]["margin"].is_null());
        assert!(j["requirements"][1]["basis"].is_null());
        assert_eq!(j["requirements"][0]["limit"], serde_json::json!(5.0));
    }

    #[test]
    fn wrong_dimension_is_not_verified_not_compliant() {
        let r = reqs();
        let ev = vec![(
            "mc".to_string(),
            vec![Evidence::measured(
                "A-ONE",
                Quantity::new(1e-9, Dim::LENGTH),
                Basis::Model,
                "mc",
            )],
        )];
        let m = Matrix::build(&r, &ev, None, &[]);
        assert_eq!(m.requirements[0].status, Status::NotVerified);
    }

    fn quantile_evidence(id: &str, n: usize, scale: f64) -> Evidence {
        // |X'| = scale x k / n um/s, k = 1..n: the 99.73 % quantile is about 0.9973 scale
        let v: Vec<f64> = (1..=n)
            .map(|k| scale * 1e-6 * k as f64 / n as f64)
            .collect();
        let s = Sampling::quantile(&v, 0.9973, 0.95);
        Evidence::measured(
            id,
            Quantity::new(s.estimate, Dim::VELOCITY),
            Basis::Model,
            "mc",
        )
        .with_sampling(s)
    }

    #[test]
    fn a_sampled_quantile_is_decided_by_its_bound_never_its_estimate() {
        let r = reqs();
        // N = 200: no upper bound exists, the estimate (4.99 um/s) is within the limit
        let m = Matrix::build(
            &r,
            &[("mc".into(), vec![quantile_evidence("A-ONE", 200, 5.0)])],
            None,
            &[],
        );
        let row = &m.requirements[0];
        assert_eq!(row.status, Status::NotVerified);
        let why = row.reason.as_deref().unwrap();
        assert!(
            why.contains(
                "N = 200 cannot show the 99.73 % quantile at 95 % confidence; need N >= 1109"
            ),
            "{why}"
        );
        assert_eq!(row.sampling.as_ref().unwrap().n, 200);
        // N = 100 000: the bound (rank 99 758 of 100 000, 4.9879) decides, with its margin
        let m = Matrix::build(
            &r,
            &[("mc".into(), vec![quantile_evidence("A-ONE", 100_000, 5.0)])],
            None,
            &[],
        );
        let row = &m.requirements[0];
        assert_eq!(row.status, Status::Compliant);
        assert!(
            (row.value.unwrap() - 5.0 * 99_758.0 / 100_000.0).abs() < 1e-9,
            "{:?}",
            row.value
        );
        // an estimate within the limit whose bound is not: not verified (inconclusive)
        let m = Matrix::build(
            &r,
            &[(
                "mc".into(),
                vec![quantile_evidence("A-ONE", 100_000, 5.0 / 0.99745)],
            )],
            None,
            &[],
        );
        let row = &m.requirements[0];
        assert_eq!(row.status, Status::NotVerified, "{:?}", row.value);
        assert!(
            row.reason
                .as_deref()
                .unwrap()
                .contains("straddle the limit")
        );
        // a lower bound beyond the limit: non-compliant
        let m = Matrix::build(
            &r,
            &[("mc".into(), vec![quantile_evidence("A-ONE", 100_000, 5.2)])],
            None,
            &[],
        );
        assert_eq!(m.requirements[0].status, Status::NonCompliant);
        assert_eq!(m.requirements[0].verdict, "non-compliant (no disposition)");
    }

    #[test]
    fn a_probability_is_decided_by_its_lower_bound() {
        let r = reqs();
        let ev = |k: u64, n: u64| {
            Evidence::measured(
                "A-TWO",
                Quantity::new(k as f64 / n as f64, Dim::DIMENSIONLESS),
                Basis::Model,
                "mc",
            )
            .with_sampling(Sampling::proportion(k, n, 0.9973, 0.95))
        };
        // every one of 200 succeeded: 0.05^(1/200) = 0.9851 cannot show 0.9973
        let m = Matrix::build(&r, &[("mc".into(), vec![ev(200, 200)])], None, &[]);
        assert_eq!(m.requirements[1].status, Status::NotVerified);
        assert!(
            m.requirements[1]
                .reason
                .as_deref()
                .unwrap()
                .contains("need N >= 1109")
        );
        let m = Matrix::build(&r, &[("mc".into(), vec![ev(100_000, 100_000)])], None, &[]);
        let row = &m.requirements[1];
        assert_eq!(row.status, Status::Compliant);
        assert!((row.value.unwrap() - 0.05f64.powf(1e-5)).abs() < 1e-15);
    }

    #[test]
    fn verdicts_read_as_what_they_rest_on() {
        let r = reqs();
        let m = Matrix::build(
            &r,
            &[(
                "mc".into(),
                vec![
                    // a flow-down that takes A-THREE (not verified) as met
                    Evidence::measured(
                        "A-ONE",
                        Quantity::new(1e-6, Dim::VELOCITY),
                        Basis::FlowDown,
                        "fd",
                    )
                    .assuming(["A-THREE"]),
                    // a model value from the design inputs, which A-TWO judges and rejects
                    Evidence::measured(
                        "A-TWO",
                        Quantity::new(0.5, Dim::DIMENSIONLESS),
                        Basis::Model,
                        "cal",
                    )
                    .judging_input("design"),
                ],
            )],
            None,
            &[],
        );
        assert_eq!(
            m.requirements[0].verdict,
            "compliant (flow-down; assumes not-verified A-THREE)"
        );
        assert!(m.requirements[0].findings[0].contains("takes A-THREE as met"));
        assert!(!m.requirements[0].plainly_compliant());
        assert_eq!(m.summary.compliant_by_basis["flow-down"], 1);
        assert_eq!(m.summary.plainly_compliant, 0);
        assert_eq!(m.summary.compliant_with_findings, 1);
        let line = m.summary.line();
        assert_eq!(
            line,
            "3 requirements: 1 compliant (1 flow-down; 0 plainly, 1 with findings), 1 non-compliant (1 without disposition), 1 not verified"
        );
        // a model row computed from the rejected design inputs carries the finding
        let m = Matrix::build(
            &r,
            &[(
                "mc".into(),
                vec![
                    Evidence::measured(
                        "A-ONE",
                        Quantity::new(1e-6, Dim::VELOCITY),
                        Basis::Model,
                        "mc",
                    )
                    .from_inputs(&["design"]),
                    Evidence::measured(
                        "A-TWO",
                        Quantity::new(0.5, Dim::DIMENSIONLESS),
                        Basis::Model,
                        "cal",
                    )
                    .judging_input("design"),
                ],
            )],
            None,
            &[],
        );
        assert_eq!(
            m.requirements[0].verdict,
            "compliant (design rejected by A-TWO)"
        );
    }

    #[test]
    fn a_stale_or_failed_run_shows_on_every_row() {
        use crate::testrun::{RecordedTest, TestRun};
        let r = reqs();
        let ev = vec![(
            "mc".to_string(),
            vec![Evidence::measured(
                "A-ONE",
                Quantity::new(1e-6, Dim::VELOCITY),
                Basis::Model,
                "mc",
            )],
        )];
        let mut run = TestRun {
            commit: "0".repeat(40),
            dirty: false,
            tree_sha256: Some("x".into()),
            proptest_rng_seed: None,
            date: "2001-01-01T00:00:00Z".into(),
            command: "forged".into(),
            tests: vec![RecordedTest {
                krate: "c".into(),
                test: "t".into(),
                result: crate::testrun::TestResult::Passed,
                location: "f.rs:1".into(),
                requirements: vec!["A-ONE".into()],
                cases: 1,
                assertions: vec![Assertion::Limit],
                kind: "unit".into(),
                asserted: Default::default(),
                rejected: Default::default(),
                source_asserts_limit: Default::default(),
            }],
        };
        let now = Ok(crate::testrun::TreeState {
            commit: "1".repeat(40),
            tree_sha256: "y".into(),
            dirty: false,
            top: PathBuf::from("."),
            files: Default::default(),
        });
        let fr = run.freshness(&now);
        assert!(!fr.is_fresh());
        let t = TestEvidence {
            file: "run.json",
            run: &run,
            freshness: &fr,
        };
        let m = Matrix::build_with(&r, &ev, Some(t), &[]);
        assert_eq!(m.summary.tests, "stale");
        assert!(!m.test_run.as_ref().unwrap().fresh);
        for row in &m.requirements {
            assert_eq!(row.tests_status, TestsStatus::Stale, "{}", row.id);
        }
        assert_eq!(m.requirements[0].verdict, "compliant (tests stale)");
        // the same run, fresh, with its test failed
        run.tests[0].result = crate::testrun::TestResult::Failed;
        let fresh = Freshness::Fresh;
        let m = Matrix::build_with(
            &r,
            &ev,
            Some(TestEvidence {
                file: "run.json",
                run: &run,
                freshness: &fresh,
            }),
            &[],
        );
        // a failed test that asserts the row's limit: the row is not compliant
        let row = &m.requirements[0];
        assert_eq!(row.status, Status::NotVerified, "{}", row.verdict);
        assert!(
            row.reason
                .as_deref()
                .unwrap()
                .starts_with("traced test c::t asserts its limit and failed"),
            "{:?}",
            row.reason
        );
        assert!(row.value.is_none() && row.basis.is_none());
        // so does an ignored one
        run.tests[0].result = crate::testrun::TestResult::Ignored;
        let built = |run: &TestRun| {
            Matrix::build_with(
                &r,
                &ev,
                Some(TestEvidence {
                    file: "run.json",
                    run,
                    freshness: &fresh,
                }),
                &[],
            )
        };
        assert_eq!(built(&run).requirements[0].status, Status::NotVerified);
        // a failed test that asserted nothing of the limit (a snapshot): named, not deciding
        run.tests[0].result = crate::testrun::TestResult::Failed;
        run.tests[0].assertions = vec![Assertion::ChangeDetection];
        assert_eq!(
            built(&run).requirements[0].verdict,
            "compliant (test failed)"
        );
        // a record whose call never ran, or rejected against the tree: no evidence, named
        run.tests[0].result = crate::testrun::TestResult::Passed;
        run.tests[0].assertions = vec![Assertion::Limit];
        run.tests[0].cases = 0;
        let m = built(&run);
        assert_eq!(m.requirements[0].tests_status, TestsStatus::Rejected);
        assert_eq!(
            m.requirements[0].verdict,
            "compliant (test record rejected)"
        );
        assert!(m.requirements[0].findings[0].contains("never ran (cases 0)"));
        assert_eq!(m.without_test_evidence(), ["A-ONE"]);
        run.tests[0].cases = 1;
        run.tests[0].rejected.insert(
            "A-ONE".into(),
            "its location f.rs:1 is not a file of the fingerprinted tree".into(),
        );
        let m = built(&run);
        assert_eq!(m.requirements[0].tests_status, TestsStatus::Rejected);
        assert!(!m.requirements[0].tests[0].is_evidence());
        run.tests[0].rejected.clear();
        assert_eq!(built(&run).requirements[0].verdict, "compliant");
        // and with no test at all: a model verdict without test evidence
        run.tests.clear();
        let m = Matrix::build_with(
            &r,
            &ev,
            Some(TestEvidence {
                file: "run.json",
                run: &run,
                freshness: &fresh,
            }),
            &[],
        );
        assert_eq!(m.requirements[0].verdict, "compliant (no traced test)");
        assert_eq!(m.without_test_evidence(), ["A-ONE"]);
    }

    /// ECSS method against basis: a `test` requirement is not closed by a model; a measurement
    /// or a passing traced test that asserts its limit closes it.
    #[test]
    fn a_test_requirement_is_not_closed_by_a_model() {
        use crate::testrun::{RecordedTest, TestRun};
        let t = "family: f
requirements:
  - id: A-ONE
    title: a
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: test
    activity: mc
";
        let r = Requirements::from_sources(&[(PathBuf::from("f.yaml"), t.into())]).unwrap();
        let ev = |b: Basis| {
            vec![(
                "mc".to_string(),
                vec![Evidence::measured(
                    "A-ONE",
                    Quantity::new(1e-6, Dim::VELOCITY),
                    b,
                    "mc",
                )],
            )]
        };
        let m = Matrix::build(&r, &ev(Basis::Model), None, &[]);
        let row = &m.requirements[0];
        assert_eq!(row.status, Status::NotVerified);
        assert!(
            row.reason.as_deref().unwrap().starts_with(
                "its method is test (ECSS-E-ST-10-02C): model evidence (1 um/s) does not close it"
            ),
            "{:?}",
            row.reason
        );
        assert_eq!(
            Matrix::build(&r, &ev(Basis::FlowDown), None, &[]).requirements[0].status,
            Status::NotVerified
        );
        // a measurement closes it
        let m = Matrix::build(&r, &ev(Basis::Measurement), None, &[]);
        assert_eq!(m.requirements[0].verdict, "compliant (measurement)");
        // a passing traced test that asserts its limit, in a run of this tree, closes it
        let run = TestRun {
            commit: "c".into(),
            dirty: false,
            tree_sha256: Some("x".into()),
            proptest_rng_seed: None,
            date: "2026-01-01T00:00:00Z".into(),
            command: "cargo xtask test".into(),
            tests: vec![RecordedTest {
                krate: "c".into(),
                test: "t".into(),
                result: crate::testrun::TestResult::Passed,
                location: "f.rs:1".into(),
                requirements: vec!["A-ONE".into()],
                cases: 1,
                assertions: vec![Assertion::Limit],
                kind: "unit".into(),
                asserted: Default::default(),
                rejected: Default::default(),
                source_asserts_limit: Default::default(),
            }],
        };
        let fresh = Freshness::Fresh;
        let tests = Some(TestEvidence {
            file: "run.json",
            run: &run,
            freshness: &fresh,
        });
        let m = Matrix::build_with(&r, &ev(Basis::Model), tests, &[]);
        assert_eq!(
            m.requirements[0].verdict,
            "compliant (method test: closed by its traced test)"
        );
        // the same test, stale: not
        let m = Matrix::build(&r, &ev(Basis::Model), Some(("run.json", &run)), &[]);
        assert_eq!(m.requirements[0].status, Status::NotVerified);
    }

    /// An open NCR on a compliant row, and a model input whose judge is not loaded (renamed),
    /// leave the row not plainly compliant.
    #[test]
    fn an_open_ncr_or_a_missing_judge_is_a_finding() {
        let r = reqs();
        let d = crate::disposition::from_str_with(
            "dispositions:\n  - requirement: A-ONE\n    kind: NCR\n    reference: NCR-X-1\n    reason: seen in test\n    owner: o\n    date: 2099-01-01\n",
            std::path::Path::new("d.yaml"),
            &r,
            20_000,
            true,
        )
        .unwrap();
        let ev = vec![(
            "mc".to_string(),
            vec![
                Evidence::measured(
                    "A-ONE",
                    Quantity::new(1e-6, Dim::VELOCITY),
                    Basis::Model,
                    "mc",
                )
                .from_inputs(&["design"]),
                // the judge of the design inputs, under an ID no longer loaded
                Evidence::measured(
                    "A-CAL",
                    Quantity::new(9.0, Dim::DIMENSIONLESS),
                    Basis::Model,
                    "cal",
                )
                .judging_input("design"),
            ],
        )];
        let m = Matrix::build(&r, &ev, None, &d);
        let row = &m.requirements[0];
        assert_eq!(
            row.verdict,
            "compliant (NCR NCR-X-1 open; design judge A-CAL not loaded)"
        );
        assert!(!row.plainly_compliant());
        assert_eq!(m.summary.plainly_compliant, 0);
    }

    #[test]
    fn worst_evidence_decides() {
        let r = reqs();
        let ev = vec![(
            "mc".to_string(),
            vec![
                Evidence::measured(
                    "A-ONE",
                    Quantity::new(1e-6, Dim::VELOCITY),
                    Basis::Model,
                    "a",
                ),
                Evidence::measured(
                    "A-ONE",
                    Quantity::new(6e-6, Dim::VELOCITY),
                    Basis::Model,
                    "b",
                ),
            ],
        )];
        let m = Matrix::build(&r, &ev, None, &[]);
        assert_eq!(m.requirements[0].status, Status::NonCompliant);
        assert!((m.requirements[0].value.unwrap() - 6.0).abs() < 1e-9);
    }
}
