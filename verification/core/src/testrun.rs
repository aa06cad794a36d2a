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
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, schemars::JsonSchema,
)]
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
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, schemars::JsonSchema,
)]
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
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RecordedTest {
    /// Crate of the test binary (`geodesic_checks`, `verification`, ...).
    pub krate: String,
    /// Test name as the test harness prints it (`structure::tests::deflection_evidence`).
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
    /// Why the record does not count for a requirement, by requirement ID, found by
    /// [`check_records`] against the tree (its location is not in the fingerprinted tree, holds
    /// no `verifies!` of that requirement, or the call never ran): never read from a file.
    #[serde(skip)]
    pub rejected: BTreeMap<String, String>,
    /// The requirement IDs whose limit the test's source asserts after its `verifies!` call
    /// (`assert_limit("ID", ...)`), read from the tree by [`check_records`]: what a failed or
    /// ignored test would have asserted. Never read from a file.
    #[serde(skip)]
    pub source_asserts_limit: std::collections::BTreeSet<String>,
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
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TraceCall {
    /// `file:line` of the call.
    pub location: String,
    /// Requirement IDs it names.
    pub requirements: Vec<String>,
    /// How many times it executed.
    pub count: u64,
}

/// One assertion recorded by a test.
#[derive(
    Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, schemars::JsonSchema,
)]
pub struct TraceAssertion {
    /// Requirement ID.
    pub requirement: String,
    /// What was asserted.
    pub assertion: Assertion,
}

/// A recorded test run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TestRun {
    /// Git commit the tests ran on (`unknown` outside a repository).
    pub commit: String,
    /// Whether the work tree had uncommitted changes.
    pub dirty: bool,
    /// Fingerprint of the work tree the tests ran on ([`tree_state`]: every file git tracks or
    /// would track, as it was on disk); `None` when the tree changed while the tests ran, or
    /// in a run recorded before this field existed. [`TestRun::freshness`] compares it with
    /// the tree a verdict is computed on.
    #[serde(default)]
    pub tree_sha256: Option<String>,
    /// The proptest RNG seed every property test ran with (`PROPTEST_RNG_SEED`), when fixed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub proptest_rng_seed: Option<String>,
    /// UTC date and time the run finished (RFC 3339).
    pub date: String,
    /// The command that ran the tests.
    pub command: String,
    /// Every test the run saw that traces to a requirement (or was declared to).
    pub tests: Vec<RecordedTest>,
}

/// The state of a git work tree: its commit and a fingerprint of its content.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TreeState {
    /// `git rev-parse HEAD`.
    pub commit: String,
    /// SHA-256 over every file git tracks, as it is on disk, and every untracked file git
    /// would track (not ignored) in a directory that holds tracked files, each framed by its
    /// path and length, in path order; a tracked file deleted from disk counts as deleted.
    /// Ignored files (`target/`, `reports/`) are left out, and so are untracked files in
    /// directories of their own (a `verify --reports DIR` written inside the repository does
    /// not make the tests stale): what tests read is tracked, or sits beside tracked files (a
    /// new requirement file in `requirements/`, which the build embeds). Uncommitted edits
    /// change it; a run of the tests and a verdict on the same fingerprint saw the same
    /// sources and inputs.
    pub tree_sha256: String,
    /// Whether the tree differs from the commit (tracked files changed or untracked files).
    pub dirty: bool,
    /// The work tree's top folder.
    pub top: std::path::PathBuf,
    /// The paths the fingerprint covers, relative to [`TreeState::top`] (`/`-separated).
    pub files: std::collections::BTreeSet<String>,
}

fn git(dir: &Path, args: &[&str]) -> Result<Vec<u8>, String> {
    let out = std::process::Command::new("git")
        .arg("-C")
        .arg(dir)
        .args(args)
        .stderr(std::process::Stdio::null())
        .output()
        .map_err(|e| format!("git: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "`git {}` failed in {}",
            args.join(" "),
            dir.display()
        ));
    }
    Ok(out.stdout)
}

/// The file kinds a folder outside git is fingerprinted by ([`tree_state_any`]): the sources,
/// the manifests and the YAML data (requirements, inputs, descriptor), not the reports.
pub const WALKED_EXTENSIONS: &[&str] = &["rs", "toml", "lock", "yaml", "yml"];

/// [`tree_state`] in a git work tree; in a folder outside git (a project just generated by
/// `geodesic new mission`: its root holds a `Cargo.toml`), a fingerprint of the files of [`WALKED_EXTENSIONS`] under `dir`,
/// skipping hidden folders, `target` and the top-level names the folder's `.gitignore` lists
/// (`/reports`), with commit `unknown`. Put the project in git for the full fingerprint.
pub fn tree_state_any(dir: &Path) -> Result<TreeState, String> {
    if git(dir, &["rev-parse", "--show-toplevel"]).is_ok() || !dir.join("Cargo.toml").is_file() {
        return tree_state(dir);
    }
    let top = dir.to_path_buf();
    let ignored: Vec<String> = std::fs::read_to_string(top.join(".gitignore"))
        .unwrap_or_default()
        .lines()
        .map(|l| {
            l.trim()
                .trim_start_matches('/')
                .trim_end_matches('/')
                .to_string()
        })
        .filter(|l| !l.is_empty() && !l.starts_with('#') && !l.contains(['*', '?', '[', '/', '!']))
        .collect();
    let mut files = std::collections::BTreeSet::new();
    let mut stack = vec![(top.clone(), String::new())];
    while let Some((d, rel)) = stack.pop() {
        let rd = std::fs::read_dir(&d).map_err(|e| format!("{}: {e}", d.display()))?;
        for e in rd.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let r = if rel.is_empty() {
                name.clone()
            } else {
                format!("{rel}/{name}")
            };
            if name.starts_with('.') || (rel.is_empty() && ignored.contains(&name)) {
                continue;
            }
            let t = e.file_type().map_err(|e| format!("{}: {e}", d.display()))?;
            if t.is_dir() {
                if name != "target" {
                    stack.push((e.path(), r));
                }
            } else if Path::new(&name)
                .extension()
                .is_some_and(|x| WALKED_EXTENSIONS.iter().any(|w| x == *w))
            {
                files.insert(r);
            }
        }
    }
    let mut parts = Vec::with_capacity(files.len());
    for f in &files {
        let full = top.join(f);
        parts.push((
            f.clone(),
            std::fs::read(&full).map_err(|e| format!("{}: {e}", full.display()))?,
        ));
    }
    let tree_sha256 =
        geodesic_util::hash::sha256_parts(parts.iter().map(|(n, b)| (n.as_str(), b.as_slice())));
    Ok(TreeState {
        commit: "unknown".into(),
        tree_sha256,
        dirty: false,
        top,
        files,
    })
}

/// The command that records this repository's test run (`geodesic_testrun`); a project
/// verified with geodesic has its own (`cargo run -- test`).
pub const RECORD_COMMAND: &str = "cargo xtask test";

/// The commit and content fingerprint of the git work tree holding `dir`; `Err` outside a
/// work tree (or without git), with why.
pub fn tree_state(dir: &Path) -> Result<TreeState, String> {
    let top = git(dir, &["rev-parse", "--show-toplevel"])
        .map_err(|_| format!("{} is not in a git work tree", dir.display()))?;
    let top = std::path::PathBuf::from(String::from_utf8_lossy(&top).trim().to_string());
    let commit = String::from_utf8_lossy(&git(&top, &["rev-parse", "HEAD"])?)
        .trim()
        .to_string();
    let tracked = git(&top, &["ls-files", "-z", "--cached"])?;
    let untracked = git(&top, &["ls-files", "-z", "--others", "--exclude-standard"])?;
    let split = |l: &[u8]| -> Vec<Vec<u8>> {
        l.split(|b| *b == 0)
            .filter(|p| !p.is_empty())
            .map(<[u8]>::to_vec)
            .collect()
    };
    let parent = |p: &[u8]| -> Vec<u8> {
        p.iter()
            .rposition(|b| *b == b'/')
            .map_or_else(Vec::new, |i| p[..i].to_vec())
    };
    let mut paths = split(&tracked);
    let dirs: std::collections::BTreeSet<Vec<u8>> = paths.iter().map(|p| parent(p)).collect();
    paths.extend(
        split(&untracked)
            .into_iter()
            .filter(|p| dirs.contains(&parent(p))),
    );
    paths.sort_unstable();
    paths.dedup();
    let mut parts: Vec<(String, Vec<u8>)> = Vec::with_capacity(paths.len());
    for p in &paths {
        let rel = String::from_utf8_lossy(p).into_owned();
        let full = top.join(&rel);
        let bytes = match std::fs::symlink_metadata(&full) {
            Ok(m) if m.file_type().is_symlink() => {
                let mut b = b"symlink:".to_vec();
                b.extend(
                    std::fs::read_link(&full)
                        .map(|t| t.display().to_string().into_bytes())
                        .unwrap_or_default(),
                );
                b
            }
            Ok(m) if m.is_file() => {
                std::fs::read(&full).map_err(|e| format!("{}: {e}", full.display()))?
            }
            Ok(_) => b"not-a-file".to_vec(),
            Err(_) => b"deleted".to_vec(),
        };
        parts.push((rel, bytes));
    }
    let tree_sha256 =
        geodesic_util::hash::sha256_parts(parts.iter().map(|(n, b)| (n.as_str(), b.as_slice())));
    let dirty = !git(&top, &["status", "--porcelain"])?.is_empty();
    let files = parts.into_iter().map(|(n, _)| n).collect();
    Ok(TreeState {
        commit,
        tree_sha256,
        dirty,
        top,
        files,
    })
}

/// Whether a recorded test run is evidence for the tree a verdict is computed on.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(tag = "state", rename_all = "kebab-case")]
pub enum Freshness {
    /// Same commit and the same content fingerprint: the tests ran on these sources.
    Fresh,
    /// The run does not match the tree (another commit, edits since, no fingerprint, ...).
    Stale {
        /// Why, one line.
        reason: String,
    },
}

impl Freshness {
    /// Whether fresh.
    pub fn is_fresh(&self) -> bool {
        matches!(self, Freshness::Fresh)
    }

    /// The reason when stale.
    pub fn reason(&self) -> Option<&str> {
        match self {
            Freshness::Fresh => None,
            Freshness::Stale { reason } => Some(reason),
        }
    }
}

impl TestRun {
    /// Reads a recorded run; the error names the file.
    pub fn load(path: &Path) -> Result<TestRun, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| {
            // serde quotes the offending input, which may hold a line break: keep one line
            format!(
                "{}:{}:{}: not a recorded test run: {}",
                geodesic_util::text::one_line(&path.display().to_string()),
                e.line(),
                e.column(),
                geodesic_util::text::clip(&e.to_string(), 300)
            )
        })
    }

    /// Whether this run is evidence for the tree `now` (`Err`: the tree cannot be read, with
    /// why): fresh only on the same commit with the same content fingerprint, so that a run
    /// on another commit, a run before uncommitted edits, a run whose tree changed while it
    /// ran, or a run without a fingerprint (older or foreign) is stale. A dirty tree is fine
    /// as long as it is the tree the tests ran on.
    pub fn freshness(&self, now: &Result<TreeState, String>) -> Freshness {
        self.freshness_for(now, RECORD_COMMAND)
    }

    /// [`TestRun::freshness`], the stale reasons naming `command` as the one that records a
    /// run again (a project's own `cargo run -- test`).
    pub fn freshness_for(&self, now: &Result<TreeState, String>, command: &str) -> Freshness {
        let stale = |reason: String| Freshness::Stale { reason };
        let short = |c: &str| c.chars().take(12).collect::<String>();
        let now = match now {
            Ok(t) => t,
            Err(why) => {
                return stale(format!(
                    "cannot be matched with the sources: {why} (run verify in the repository the tests ran in)"
                ));
            }
        };
        if self.commit != now.commit {
            return stale(format!(
                "recorded on commit {}, the work tree is at {}",
                short(&self.commit),
                short(&now.commit)
            ));
        }
        match &self.tree_sha256 {
            None => stale(format!(
                "the run has no tree fingerprint (recorded by an older `{command}`, or its tree changed while the tests ran): run `{command}` again"
            )),
            Some(h) if *h != now.tree_sha256 => stale(format!(
                "the work tree changed since the tests ran on commit {} (uncommitted edits): run `{command}` again",
                short(&self.commit)
            )),
            Some(_) => Freshness::Fresh,
        }
    }

    /// The recorded tests that executed a `verifies!` call naming `id`.
    pub fn for_requirement<'a>(&'a self, id: &'a str) -> impl Iterator<Item = &'a RecordedTest> {
        self.tests
            .iter()
            .filter(move |t| t.requirements.iter().any(|r| r == id))
    }
}

/// `text` with the contents of comments and of string and character literals blanked (newlines
/// kept), so that a brace or a `verifies!` inside them is not read as code; string literals
/// keep their quotes and their text is kept in `strings` (byte offset of the opening quote ->
/// the literal's content).
fn code_and_strings(text: &str) -> (Vec<u8>, BTreeMap<usize, String>) {
    let b = text.as_bytes();
    let mut code = b.to_vec();
    let mut strings = BTreeMap::new();
    let mut i = 0;
    while i < b.len() {
        if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                code[i] = b' ';
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            while i < b.len() && !b[i..].starts_with(b"*/") {
                if b[i] != b'\n' {
                    code[i] = b' ';
                }
                i += 1;
            }
            for c in code.iter_mut().take((i + 2).min(b.len())).skip(i) {
                *c = b' ';
            }
            i += 2;
        } else if b[i] == b'"' {
            let open = i;
            i += 1;
            let start = i;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    code[i] = b' ';
                    i += 1;
                }
                if i < b.len() && b[i] != b'\n' {
                    code[i] = b' ';
                }
                i += 1;
            }
            strings.insert(open, text[start..i.min(b.len())].to_string());
            i += 1;
        } else if b[i] == b'r'
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'))
            && b.get(i + 1 + b[i + 1..].iter().take_while(|c| **c == b'#').count()) == Some(&b'"')
        {
            // a raw string r"..." / r#"..."#
            let hashes = b[i + 1..].iter().take_while(|c| **c == b'#').count();
            let open = i + 1 + hashes;
            let mut close_seq = vec![b'"'];
            close_seq.extend(std::iter::repeat_n(b'#', hashes));
            let end = find(&b[open + 1..], &close_seq).map_or(b.len(), |k| open + 1 + k);
            for c in code.iter_mut().take(end).skip(open + 1) {
                if *c != b'\n' {
                    *c = b' ';
                }
            }
            strings.insert(open, text[open + 1..end].to_string());
            i = end + close_seq.len();
        } else if b[i] == b'\'' && i + 2 < b.len() && b[i + 1] != b'\\' && b[i + 2] == b'\'' {
            code[i + 1] = b' ';
            i += 3;
        } else if b[i] == b'\'' && i + 3 < b.len() && b[i + 1] == b'\\' {
            let end = (i + 3..b.len())
                .find(|&k| b[k] == b'\'')
                .unwrap_or(b.len() - 1);
            for c in code.iter_mut().take(end).skip(i + 1) {
                *c = b' ';
            }
            i = end + 1;
        } else {
            i += 1;
        }
    }
    (code, strings)
}

/// What the source says at a recorded `file:line`: the requirement IDs of the `verifies!` call
/// that starts on that line (`None`: no call there), and the IDs whose limit the code after
/// the call asserts, up to the end of the block holding it (`assert_limit("ID", ...)`).
pub fn source_trace(text: &str, line: usize) -> Option<(Vec<String>, Vec<String>)> {
    let (code, strings) = code_and_strings(text);
    let start = text
        .split_inclusive('\n')
        .take(line.checked_sub(1)?)
        .map(str::len)
        .sum::<usize>();
    if start >= text.len() && line > 1 {
        return None;
    }
    let end_of_line = code[start..]
        .iter()
        .position(|c| *c == b'\n')
        .map_or(code.len(), |k| start + k);
    let on_line = &code[start..end_of_line];
    let at = start + find(on_line, b"verifies!")?;
    let open = at + code[at..].iter().position(|c| *c == b'(')?;
    let close = open + code[open..].iter().position(|c| *c == b')')?;
    let ids: Vec<String> = strings.range(open..close).map(|(_, s)| s.clone()).collect();
    // the rest of the enclosing block
    let mut depth = 0i64;
    let mut end = code.len();
    for (k, c) in code.iter().enumerate().skip(close) {
        match c {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth < 0 {
                    end = k;
                    break;
                }
            }
            _ => {}
        }
    }
    let mut limits = Vec::new();
    let mut k = close;
    while let Some(p) = find(&code[k..end], b"assert_limit") {
        let p = k + p;
        let after = p + b"assert_limit".len();
        let rest = &code[after..end];
        let ws = rest.iter().take_while(|c| c.is_ascii_whitespace()).count();
        if rest.get(ws) == Some(&b'(') {
            let q = after + ws + 1;
            let ws2 = code[q..end]
                .iter()
                .take_while(|c| c.is_ascii_whitespace())
                .count();
            if let Some(id) = strings.get(&(q + ws2))
                && !limits.contains(id)
            {
                limits.push(id.clone());
            }
        }
        k = after;
    }
    Some((ids, limits))
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Checks every record of `run` against the tree it claims to be a run of: each recorded
/// location (`file:line`, several joined by `, `) must be a file the fingerprint covers whose
/// line holds a `verifies!` call, the calls must name every requirement the record claims, and
/// a passed test must have run its call (cases > 0). What does not hold is kept, per
/// requirement, in [`RecordedTest::rejected`]; what the source asserts after the call in
/// [`RecordedTest::source_asserts_limit`].
pub fn check_records(run: &mut TestRun, tree: &TreeState) {
    let mut cache: BTreeMap<String, Option<String>> = BTreeMap::new();
    for t in &mut run.tests {
        let mut named: Vec<String> = Vec::new();
        let mut problems: Vec<String> = Vec::new();
        let locations: Vec<&str> = t
            .location
            .split(", ")
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect();
        if locations.is_empty() {
            problems.push("the record names no location of its verifies! call".into());
        }
        for loc in locations {
            let Some((file, line)) = loc
                .rsplit_once(':')
                .and_then(|(f, l)| Some((f, l.parse::<usize>().ok()?)))
            else {
                problems.push(format!("its location `{loc}` is not file:line"));
                continue;
            };
            let file = file.trim_start_matches("./");
            if !tree.files.contains(file) {
                problems.push(format!(
                    "its location {loc} is not a file of the fingerprinted tree"
                ));
                continue;
            }
            let text = cache
                .entry(file.to_string())
                .or_insert_with(|| std::fs::read_to_string(tree.top.join(file)).ok());
            match text.as_deref().and_then(|x| source_trace(x, line)) {
                Some((ids, limits)) => {
                    named.extend(ids);
                    t.source_asserts_limit.extend(limits);
                }
                None => problems.push(format!("line {line} of {file} holds no verifies! call")),
            }
        }
        if t.result == TestResult::Passed && t.cases == 0 {
            problems.push("its verifies! call never ran (cases 0)".into());
        }
        for id in &t.requirements {
            let mut why = problems.clone();
            if problems.is_empty() && !named.contains(id) {
                why.push(format!("no verifies! at {} names {id}", t.location));
            }
            if !why.is_empty() {
                t.rejected.insert(id.clone(), why.join("; "));
            }
        }
    }
}

/// The files `verify` read (paths as given) that the fingerprint of `tree` does not cover: a
/// file git ignores or does not see (hidden through `.git/info/exclude`, in an untracked
/// folder of its own) or outside the work tree. A run of the tests is not evidence about them.
pub fn uncovered(tree: &TreeState, read: &[std::path::PathBuf]) -> Vec<String> {
    let top = std::fs::canonicalize(&tree.top).unwrap_or_else(|_| tree.top.clone());
    read.iter()
        .filter(|p| {
            let Ok(abs) = std::fs::canonicalize(p) else {
                return true;
            };
            match abs.strip_prefix(&top) {
                Ok(rel) => {
                    let rel = rel
                        .components()
                        .map(|c| c.as_os_str().to_string_lossy().into_owned())
                        .collect::<Vec<_>>()
                        .join("/");
                    !tree.files.contains(&rel)
                }
                Err(_) => true,
            }
        })
        .map(|p| p.display().to_string())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn git_in(d: &Path, args: &[&str]) {
        let ok = std::process::Command::new("git")
            .args(["-c", "user.name=t", "-c", "user.email=t@t"])
            .args(args)
            .current_dir(d)
            .output()
            .unwrap()
            .status
            .success();
        assert!(ok, "git {args:?}");
    }

    fn run_of(t: &TreeState) -> TestRun {
        TestRun {
            commit: t.commit.clone(),
            dirty: t.dirty,
            tree_sha256: Some(t.tree_sha256.clone()),
            proptest_rng_seed: None,
            date: "2026-01-01T00:00:00Z".into(),
            command: "cargo xtask test".into(),
            tests: vec![],
        }
    }

    const SRC: &str = r##"// verifies!("NOT-HERE")
#[test]
fn gprm() {
    geodesic_core::verifies!("REL-GPRM-VEL", "TMS-Z-VEL");
    let s = "}"; let c = '}';
    let j = r#"{"a": "}"}"#;
    geodesic_core::trace::assert_limit("REL-GPRM-VEL", 1e-6);
}

#[test]
fn snap() {
    geodesic_core::verifies!(
        "CHG-V"
    );
}
fn after() { assert_limit("CHG-V", 1.0); }
"##;

    #[test]
    fn the_source_at_a_recorded_line_says_what_it_verifies_and_asserts() {
        assert_eq!(super::source_trace(SRC, 1), None, "a comment is no call");
        assert_eq!(
            super::source_trace(SRC, 4),
            Some((
                vec!["REL-GPRM-VEL".to_string(), "TMS-Z-VEL".to_string()],
                vec!["REL-GPRM-VEL".to_string()]
            ))
        );
        assert_eq!(super::source_trace(SRC, 5), None);
        // a call over several lines; the assertion of another function is not its own
        assert_eq!(
            super::source_trace(SRC, 12),
            Some((vec!["CHG-V".to_string()], vec![]))
        );
        assert_eq!(super::source_trace(SRC, 99), None);
    }

    fn recorded(location: &str, result: TestResult, cases: u64, reqs: &[&str]) -> RecordedTest {
        RecordedTest {
            krate: "verification".into(),
            test: "t".into(),
            result,
            location: location.into(),
            requirements: reqs.iter().map(|r| r.to_string()).collect(),
            cases,
            assertions: vec![Assertion::Limit],
            kind: "unit".into(),
            asserted: BTreeMap::new(),
            rejected: BTreeMap::new(),
            source_asserts_limit: Default::default(),
        }
    }

    /// A record counts only where the tree holds its call: a location outside the tree, a line
    /// with no `verifies!`, a call that does not name the requirement, a passed test whose call
    /// never ran, are each rejected with why; a file hidden from git is not in the tree.
    #[test]
    fn test_records_are_checked_against_the_tree() {
        let tmp = tempfile::tempdir().unwrap();
        let d = tmp.path();
        std::fs::create_dir_all(d.join("tests")).unwrap();
        std::fs::write(d.join("tests/v.rs"), SRC).unwrap();
        git_in(d, &["init", "-q"]);
        git_in(d, &["add", "-A"]);
        git_in(d, &["commit", "-q", "-m", "one"]);
        // hidden from git: not in the fingerprint, so not a place a test can be
        std::fs::write(d.join(".git/info/exclude"), "hidden.rs\n").unwrap();
        std::fs::write(d.join("tests/hidden.rs"), SRC).unwrap();
        let tree = tree_state(d).unwrap();
        assert!(tree.files.contains("tests/v.rs"));
        assert!(!tree.files.contains("tests/hidden.rs"));
        let mut run = run_of(&tree);
        run.tests = vec![
            recorded("tests/v.rs:4", TestResult::Passed, 1, &["REL-GPRM-VEL"]),
            recorded("tests/nowhere.rs:1", TestResult::Passed, 1, &["CHG-V"]),
            recorded("tests/v.rs:5", TestResult::Passed, 1, &["CHG-V"]),
            recorded(
                "tests/v.rs:4",
                TestResult::Passed,
                1,
                &["CHG-V", "TMS-Z-VEL"],
            ),
            recorded("tests/v.rs:12", TestResult::Passed, 0, &["CHG-V"]),
            recorded(
                "tests/hidden.rs:4",
                TestResult::Passed,
                1,
                &["REL-GPRM-VEL"],
            ),
            recorded("tests/v.rs:12", TestResult::Ignored, 0, &["CHG-V"]),
        ];
        check_records(&mut run, &tree);
        let why = |i: usize, id: &str| run.tests[i].rejected.get(id).cloned();
        assert_eq!(why(0, "REL-GPRM-VEL"), None);
        assert!(
            run.tests[0].source_asserts_limit.contains("REL-GPRM-VEL"),
            "{:?}",
            run.tests[0].source_asserts_limit
        );
        assert!(
            why(1, "CHG-V")
                .unwrap()
                .contains("not a file of the fingerprinted tree")
        );
        assert!(why(2, "CHG-V").unwrap().contains("holds no verifies! call"));
        assert!(
            why(3, "CHG-V").unwrap().contains("names CHG-V"),
            "{:?}",
            why(3, "CHG-V")
        );
        assert_eq!(why(3, "TMS-Z-VEL"), None);
        assert!(why(4, "CHG-V").unwrap().contains("never ran (cases 0)"));
        assert!(why(5, "REL-GPRM-VEL").is_some());
        assert_eq!(
            why(6, "CHG-V"),
            None,
            "an ignored test ran nothing, as it says"
        );
        // what verify reads: a hidden requirement file is not covered, a tracked one is
        let read = [d.join("tests/v.rs"), d.join("tests/hidden.rs")];
        let out = uncovered(&tree, &read);
        assert_eq!(out.len(), 1, "{out:?}");
        assert!(out[0].ends_with("hidden.rs"));
    }

    /// The fingerprint follows what the tests read: tracked files and new files beside them;
    /// not ignored files, nor untracked output folders of their own.
    #[test]
    fn the_tree_fingerprint_follows_the_sources_not_the_outputs() {
        let tmp = tempfile::tempdir().unwrap();
        let d = tmp.path();
        std::fs::create_dir_all(d.join("src")).unwrap();
        std::fs::write(d.join("src/a.rs"), "fn a() {}\n").unwrap();
        std::fs::write(d.join(".gitignore"), "/target\n").unwrap();
        git_in(d, &["init", "-q"]);
        git_in(d, &["add", "-A"]);
        git_in(d, &["commit", "-q", "-m", "one"]);
        let t0 = tree_state(d).unwrap();
        assert!(!t0.dirty);
        let run = run_of(&t0);
        assert!(run.freshness(&tree_state(d)).is_fresh());
        // outputs: an ignored folder, an untracked folder of its own
        std::fs::create_dir_all(d.join("target/x")).unwrap();
        std::fs::write(d.join("target/x/run.json"), "{}").unwrap();
        std::fs::create_dir_all(d.join("my-reports")).unwrap();
        std::fs::write(d.join("my-reports/compliance.json"), "{}").unwrap();
        assert!(run.freshness(&tree_state(d)).is_fresh());
        // an uncommitted edit, then a new file beside the sources: stale
        std::fs::write(d.join("src/a.rs"), "fn a() { }\n").unwrap();
        let why = run.freshness(&tree_state(d));
        assert!(
            why.reason()
                .unwrap()
                .contains("changed since the tests ran"),
            "{why:?}"
        );
        std::fs::write(d.join("src/a.rs"), "fn a() {}\n").unwrap();
        assert!(run.freshness(&tree_state(d)).is_fresh());
        std::fs::write(d.join("src/b.rs"), "fn b() {}\n").unwrap();
        assert!(!run.freshness(&tree_state(d)).is_fresh());
        // a dirty tree is fresh for a run of that same dirty tree
        let dirty = tree_state(d).unwrap();
        assert!(dirty.dirty);
        assert!(run_of(&dirty).freshness(&tree_state(d)).is_fresh());
        // another commit; no fingerprint; not a work tree
        git_in(d, &["add", "-A"]);
        git_in(d, &["commit", "-q", "-m", "two"]);
        assert!(
            run.freshness(&tree_state(d))
                .reason()
                .unwrap()
                .starts_with("recorded on commit")
        );
        let mut old = run_of(&tree_state(d).unwrap());
        old.tree_sha256 = None;
        assert!(!old.freshness(&tree_state(d)).is_fresh());
        let outside = tempfile::tempdir().unwrap();
        assert!(
            run.freshness(&tree_state(outside.path()))
                .reason()
                .unwrap()
                .contains("not in a git work tree")
        );
    }

    /// A folder outside git (a generated project before `git init`): its sources and YAML data
    /// fingerprint it, its reports and ignored folders do not.
    #[test]
    fn a_folder_outside_git_is_fingerprinted_by_its_sources_and_data() {
        let tmp = tempfile::tempdir().unwrap();
        let d = tmp.path();
        if tree_state(d).is_ok() {
            return; // the temporary folder is inside a git work tree: nothing to test here
        }
        std::fs::create_dir_all(d.join("src")).unwrap();
        std::fs::write(d.join("src/a.rs"), "fn a() {}\n").unwrap();
        std::fs::write(d.join("design.yaml"), "x_m: 1\n").unwrap();
        assert!(tree_state_any(d).is_err(), "no Cargo.toml: not a project");
        std::fs::write(d.join("Cargo.toml"), "[package]\n").unwrap();
        std::fs::write(d.join(".gitignore"), "/target\n/reports\n").unwrap();
        let t0 = tree_state_any(d).unwrap();
        assert_eq!(t0.commit, "unknown");
        assert!(t0.files.contains("src/a.rs") && t0.files.contains("design.yaml"));
        let run = run_of(&t0);
        assert!(run.freshness(&tree_state_any(d)).is_fresh());
        for (f, text) in [
            ("reports/m.yaml", "a: 1"),
            ("target/x.rs", ""),
            ("r1.json", "{}"),
        ] {
            std::fs::create_dir_all(d.join(f).parent().unwrap()).unwrap();
            std::fs::write(d.join(f), text).unwrap();
        }
        assert!(run.freshness(&tree_state_any(d)).is_fresh());
        std::fs::write(d.join("design.yaml"), "x_m: 2\n").unwrap();
        assert!(!run.freshness(&tree_state_any(d)).is_fresh());
    }
}
