//! The compliance matrix: every requirement with its status, value, limit, margin, evidence and
//! the tests that cover it.
//!
//! A requirement is `compliant` when a check measured a value that satisfies its limit,
//! `non-compliant` when a measured value does not, and `not-verified` when no check gave a value
//! (no check at all, or a check that states why it cannot). It is never silently compliant.
//! When several checks measure the same requirement, the one with the smallest margin decides.

use crate::check::{Basis, Evidence, Outcome};
use crate::disposition::Disposition;
use crate::requirement::{Requirement, Requirements};
use crate::testrun::{Assertion, TestResult, TestRun};
use serde::Serialize;
use std::collections::BTreeMap;

/// Compliance status of a requirement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, PartialOrd, Ord)]
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
#[derive(Clone, Debug, Serialize)]
pub struct EvidenceEntry {
    /// Name of the check that produced it.
    pub check: String,
    /// What the value rests on (`None` when no value).
    pub basis: Option<Basis>,
    /// What produced the value.
    pub activity: String,
    /// Value in the requirement's unit (absent when not verified).
    pub value: Option<f64>,
    /// Why no value, if so.
    pub reason: Option<String>,
    /// Inputs (N, seed, dataset, ...).
    pub inputs: BTreeMap<String, serde_json::Value>,
    /// Files written (relative to the reports directory).
    pub artifacts: Vec<String>,
}

/// A test that traces to a requirement, with its recorded result.
#[derive(Clone, Debug, Serialize)]
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
}

impl TestRef {
    /// Whether this test is evidence for its requirement: it passed and asserted the limit or an
    /// independent reference (a snapshot alone is change detection).
    pub fn is_evidence(&self) -> bool {
        self.result == TestResult::Passed
            && self
                .assertions
                .iter()
                .any(|a| matches!(a, Assertion::Limit | Assertion::Reference))
    }
}

/// The state of a requirement's traced tests in the recorded run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
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
}

impl TestsStatus {
    /// As written in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            TestsStatus::Passed => "passed",
            TestsStatus::Failed => "failed",
            TestsStatus::Incomplete => "incomplete",
            TestsStatus::None => "none",
        }
    }
}

/// One row of the matrix.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Requirement ID.
    pub id: String,
    /// Status.
    pub status: Status,
    /// What the deciding value rests on: `model`, `flow-down` or `accepted` (`None` when not
    /// verified; illustrations never decide).
    pub basis: Option<Basis>,
    /// Known non-compliance: NCR, waiver or RFD.
    pub disposition: Option<Disposition>,
    /// Deciding value, in `unit`.
    pub value: Option<f64>,
    /// Limit, in `unit` (`None`, JSON `null`, for a qualitative requirement: no limit).
    pub limit: Option<f64>,
    /// Margin `(limit - value) / limit` (sign-adjusted for lower bounds).
    pub margin: Option<f64>,
    /// Unit of `value` and `limit`, as written in the requirement (empty when qualitative).
    pub unit: String,
    /// Comparison (`<=`, `<`, `>=`, `>`; empty when qualitative).
    pub op: String,
    /// Limit as written ([`QUALITATIVE_LIMIT_TEXT`] when the requirement has no limit).
    pub limit_text: String,
    /// Probability level, if any.
    pub probability: Option<String>,
    /// Title.
    pub title: String,
    /// Shall statement.
    pub text: String,
    /// What is measured or computed.
    pub quantity: String,
    /// Family.
    pub family: String,
    /// Thesis source.
    pub source: String,
    /// Verification method.
    pub method: String,
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
}

/// A check whose evidence names a requirement that is not loaded.
#[derive(Clone, Debug, Serialize)]
pub struct Orphan {
    /// Check name.
    pub check: String,
    /// The unknown requirement ID.
    pub requirement: String,
}

/// Counts by status.
#[derive(Clone, Debug, Default, Serialize, PartialEq, Eq)]
pub struct Summary {
    /// Number of requirements.
    pub total: usize,
    /// Compliant.
    pub compliant: usize,
    /// Non-compliant.
    pub non_compliant: usize,
    /// Not verified.
    pub not_verified: usize,
}

/// The compliance matrix.
#[derive(Clone, Debug, Serialize)]
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
#[derive(Clone, Debug, Serialize)]
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
}

impl Matrix {
    /// Builds the matrix from requirements, the evidence of each check (by check name), the
    /// recorded test run (`run`: the file it came from and its content) and the dispositions.
    pub fn build(
        reqs: &Requirements,
        evidence: &[(String, Vec<Evidence>)],
        run: Option<(&str, &TestRun)>,
        dispositions: &[Disposition],
    ) -> Matrix {
        let mut orphans = Vec::new();
        let mut by_req: BTreeMap<&str, Vec<(&str, &Evidence)>> = BTreeMap::new();
        for (check, evs) in evidence {
            for e in evs {
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
        let rows: Vec<Row> = reqs
            .items
            .iter()
            .map(|r| {
                row(
                    r,
                    reqs,
                    by_req.get(r.id.as_str()).map(Vec::as_slice).unwrap_or(&[]),
                    run.map(|(_, t)| t),
                    dispositions.iter().find(|d| d.requirement == r.id.as_str()),
                )
            })
            .collect();
        let mut s = Summary {
            total: rows.len(),
            ..Default::default()
        };
        for r in &rows {
            match r.status {
                Status::Compliant => s.compliant += 1,
                Status::NonCompliant => s.non_compliant += 1,
                Status::NotVerified => s.not_verified += 1,
            }
        }
        Matrix {
            requirements: rows,
            summary: s,
            orphan_checks: orphans,
            test_run: run.map(|(file, t)| TestRunInfo {
                file: file.to_string(),
                commit: t.commit.clone(),
                dirty: t.dirty,
                date: t.date.clone(),
                command: t.command.clone(),
            }),
        }
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

    /// IDs of the requirements whose traced tests failed, were ignored or did not run.
    pub fn with_test_problems(&self) -> Vec<&str> {
        self.requirements
            .iter()
            .filter(|r| {
                matches!(
                    r.tests_status,
                    TestsStatus::Failed | TestsStatus::Incomplete
                )
            })
            .map(|r| r.id.as_str())
            .collect()
    }

    /// Exit status of `verify`: 1 if any requirement is non-compliant, else 0.
    pub fn exit_code(&self) -> u8 {
        u8::from(self.summary.non_compliant > 0)
    }
}

fn row(
    r: &Requirement,
    reqs: &Requirements,
    evs: &[(&str, &Evidence)],
    run: Option<&TestRun>,
    disposition: Option<&Disposition>,
) -> Row {
    let Some(lim) = &r.limit else {
        // qualitative: no value can decide; evidence that names it anyway is shown, not used
        let entries = evs
            .iter()
            .map(|(check, e)| EvidenceEntry {
                check: check.to_string(),
                basis: None,
                activity: e.activity.clone(),
                value: None,
                reason: Some(format!(
                    "check {check} gave evidence for a qualitative requirement (no limit to compare with)"
                )),
                inputs: e.inputs.clone(),
                artifacts: e.artifacts.clone(),
            })
            .collect();
        return finish_row(
            r,
            reqs,
            run,
            disposition,
            Verdict {
                status: Status::NotVerified,
                basis: None,
                value: None,
                margin: None,
                reason: Some(qualitative_reason(r.method)),
                entries,
            },
        );
    };
    let scale = lim.unit.scale;
    let limit = lim.value.value / scale;
    let mut entries = Vec::new();
    let mut best: Option<(f64, f64, Basis)> = None; // (value in unit, margin, basis)
    let mut reasons = Vec::new();
    let mut illustrations = Vec::new();
    for (check, e) in evs {
        let (value, reason) = match &e.outcome {
            Outcome::Measured(q) if q.dim == lim.dim && !q.value.is_nan() => {
                let v = q.value / scale;
                let m = lim.op.margin(v, limit);
                let basis = e.basis.unwrap_or(Basis::Illustration);
                if basis.decides() {
                    if best.is_none_or(|(_, bm, _)| m < bm) {
                        best = Some((v, m, basis));
                    }
                } else {
                    illustrations.push(format!(
                        "illustration only (not a verdict): {} gives {} {}",
                        check,
                        crate::units::fmt_num(v),
                        lim.unit.symbol
                    ));
                }
                (Some(v), None)
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
                reasons.push(why.clone());
                (None, Some(why))
            }
            Outcome::NotVerified(why) => {
                reasons.push(why.clone());
                (None, Some(why.clone()))
            }
        };
        entries.push(EvidenceEntry {
            check: check.to_string(),
            basis: if value.is_some() { e.basis } else { None },
            activity: e.activity.clone(),
            value,
            reason,
            inputs: e.inputs.clone(),
            artifacts: e.artifacts.clone(),
        });
    }
    let (status, value, margin, reason, basis) = match best {
        Some((v, m, basis)) => {
            let ok = lim.op.holds(v, limit);
            (
                if ok {
                    Status::Compliant
                } else {
                    Status::NonCompliant
                },
                Some(v),
                Some(m),
                None,
                Some(basis),
            )
        }
        None => {
            reasons.extend(illustrations);
            let why = if reasons.is_empty() {
                "no check provides evidence for this requirement".to_string()
            } else {
                reasons.join("; ")
            };
            (Status::NotVerified, None, None, Some(why), None)
        }
    };
    finish_row(
        r,
        reqs,
        run,
        disposition,
        Verdict {
            status,
            basis,
            value,
            margin,
            reason,
            entries,
        },
    )
}

/// What the evidence decided for one requirement.
struct Verdict {
    status: Status,
    basis: Option<Basis>,
    value: Option<f64>,
    margin: Option<f64>,
    reason: Option<String>,
    entries: Vec<EvidenceEntry>,
}

/// The row of `r` with its verdict, tests and links.
fn finish_row(
    r: &Requirement,
    reqs: &Requirements,
    run: Option<&TestRun>,
    disposition: Option<&Disposition>,
    v: Verdict,
) -> Row {
    let Verdict {
        status,
        basis,
        value,
        margin,
        reason,
        entries,
    } = v;
    let tests: Vec<TestRef> = run
        .map(|run| {
            run.for_requirement(r.id.as_str())
                .map(|t| TestRef {
                    test: format!("{}::{}", t.krate, t.test),
                    kind: t.kind.clone(),
                    location: t.location.clone(),
                    result: t.result,
                    assertions: t.assertions_for(r.id.as_str()),
                    cases: t.cases,
                })
                .collect()
        })
        .unwrap_or_default();
    let tests_status = if tests.iter().any(|t| t.result == TestResult::Failed) {
        TestsStatus::Failed
    } else if tests
        .iter()
        .any(|t| matches!(t.result, TestResult::Ignored | TestResult::NotRun))
    {
        TestsStatus::Incomplete
    } else if tests.iter().any(TestRef::is_evidence) {
        TestsStatus::Passed
    } else {
        TestsStatus::None
    };
    Row {
        id: r.id.to_string(),
        status,
        basis,
        disposition: disposition.cloned(),
        value,
        limit: r.limit.as_ref().map(|l| l.in_unit()),
        margin,
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
        tests,
        tests_status,
        defined_at: format!("{}:{}", r.origin.file.display(), r.origin.line),
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
