//! A recorded test run: the results of the tests that trace to requirements, read by the
//! compliance matrix instead of the source text.
//!
//! `cargo xtask test` runs the workspace's tests (the README's test command) and writes
//! `target/geodesic/test-run.json`: when, on which commit (and whether the tree was dirty), the
//! command, and for every test that executed a [`crate::verifies!`] call: its name, result,
//! the requirement IDs whose call executed, how many times (a property test runs its body once
//! per case) and what it asserted (the requirement's limit, an independent reference, or only a
//! snapshot). Declared traces whose test did not run are reported as `ignored` or `not-run`.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// Result of one test in a recorded run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TestResult {
    /// Ran and passed.
    Passed,
    /// Ran and failed.
    Failed,
    /// Marked `#[ignore]`: did not run.
    Ignored,
    /// Not in the recorded run (no run recorded, a dead function, a comment, a filtered run).
    NotRun,
}

impl TestResult {
    /// As written in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            TestResult::Passed => "passed",
            TestResult::Failed => "failed",
            TestResult::Ignored => "ignored",
            TestResult::NotRun => "not-run",
        }
    }
}

/// What a traced test asserted about the requirement (recorded at run time).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Assertion {
    /// The requirement's own limit, read from the requirement set (`trace::assert_limit`).
    Limit,
    /// An independent reference value (`trace::assert_reference`).
    Reference,
    /// Only a snapshot or other change detection: not evidence of compliance.
    ChangeDetection,
}

impl Assertion {
    /// As written in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Assertion::Limit => "limit",
            Assertion::Reference => "reference",
            Assertion::ChangeDetection => "change-detection",
        }
    }
}

/// One test of a recorded run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RecordedTest {
    /// Crate of the test binary (`geodesic_checks`, `verification`, ...).
    pub krate: String,
    /// Test name as the test harness prints it (`capture::tests::criterion_evidence`).
    pub test: String,
    /// Result.
    pub result: TestResult,
    /// `file:line` of the `verifies!` call that executed (empty when none did).
    #[serde(default)]
    pub location: String,
    /// Requirement IDs whose `verifies!` call executed.
    #[serde(default)]
    pub requirements: Vec<String>,
    /// How many times the call executed (cases of a property test).
    #[serde(default)]
    pub cases: u64,
    /// What the test asserted, strongest first.
    #[serde(default)]
    pub assertions: Vec<Assertion>,
    /// Test kind: `proptest` (more than one case), `snapshot` (an insta assertion), `unit`.
    #[serde(default)]
    pub kind: String,
    /// What the test asserted, per requirement ID (strongest first); empty in runs recorded
    /// before this field existed, see [`RecordedTest::assertions_for`].
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub asserted: BTreeMap<String, Vec<Assertion>>,
}

impl RecordedTest {
    /// What the test asserted about requirement `id`: its own assertions for that ID when the
    /// run recorded them per requirement (`[change-detection]` when it asserted nothing for
    /// `id`), else [`RecordedTest::assertions`].
    pub fn assertions_for(&self, id: &str) -> Vec<Assertion> {
        if self.asserted.is_empty() {
            return self.assertions.clone();
        }
        match self.asserted.get(id) {
            Some(a) if !a.is_empty() => a.clone(),
            _ => vec![Assertion::ChangeDetection],
        }
    }
}

/// What one test recorded at run time (one file per test in the trace directory, written by
/// [`crate::trace`] while `GEODESIC_TRACE_DIR` is set and read by `cargo xtask test`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TraceRecord {
    /// Crate of the `verifies!` call (`CARGO_CRATE_NAME` at the call site; empty if none ran).
    pub krate: String,
    /// Test name: the name libtest gave the test's thread.
    pub test: String,
    /// File stem of the test binary (`verification-0123abcd`).
    pub binary: String,
    /// The `verifies!` calls that executed, in first-execution order.
    pub calls: Vec<TraceCall>,
    /// The assertions made through `trace::assert_limit` / `trace::assert_reference`.
    pub asserted: Vec<TraceAssertion>,
}

/// One `verifies!` call site as executed by a test.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TraceCall {
    /// `file:line` of the call.
    pub location: String,
    /// Requirement IDs it names.
    pub requirements: Vec<String>,
    /// How many times it executed.
    pub count: u64,
}

/// One assertion recorded by a test.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct TraceAssertion {
    /// Requirement ID.
    pub requirement: String,
    /// What was asserted.
    pub assertion: Assertion,
}

/// A recorded test run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TestRun {
    /// Git commit the tests ran on (`unknown` outside a repository).
    pub commit: String,
    /// Whether the work tree had uncommitted changes.
    pub dirty: bool,
    /// UTC date and time the run finished (RFC 3339).
    pub date: String,
    /// The command that ran the tests.
    pub command: String,
    /// Every test the run saw that traces to a requirement (or was declared to).
    pub tests: Vec<RecordedTest>,
}

impl TestRun {
    /// Reads a recorded run; the error names the file.
    pub fn load(path: &Path) -> Result<TestRun, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| {
            // serde quotes the offending input, which may hold a line break: keep one line
            format!(
                "{}:{}:{}: not a recorded test run: {}",
                crate::text::one_line(&path.display().to_string()),
                e.line(),
                e.column(),
                crate::text::clip(&e.to_string(), 300)
            )
        })
    }

    /// The recorded tests that executed a `verifies!` call naming `id`.
    pub fn for_requirement<'a>(&'a self, id: &'a str) -> impl Iterator<Item = &'a RecordedTest> {
        self.tests
            .iter()
            .filter(move |t| t.requirements.iter().any(|r| r == id))
    }
}
