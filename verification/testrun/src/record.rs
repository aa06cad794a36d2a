//! The recorded run: `cargo test` run and joined with what the tests recorded, written whole.

use geodesic_core::testrun::{TestResult, TestRun, TraceRecord};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The proptest RNG seed of the recorded test run (`PROPTEST_RNG_SEED`), unless the caller
/// sets one.
pub const PROPTEST_RNG_SEED: u64 = 20_261_127;

/// What to run and how to name it.
#[derive(Clone, Debug)]
pub struct Recording {
    /// The project's root: where `cargo test` runs, whose sources are scanned for `verifies!`
    /// and whose tree is fingerprinted.
    pub root: PathBuf,
    /// The folder the run is written to (`test-run.json`) and the tests' records gathered in
    /// (`<target>/geodesic`: [`target_dir`]; a project's harness: `<root>/target/geodesic`,
    /// where its `verify` reads it, whatever `CARGO_TARGET_DIR` says).
    pub out_dir: PathBuf,
    /// `cargo test`'s own arguments before the caller's (`["--workspace", "--release"]`).
    pub cargo_args: Vec<String>,
    /// The caller's extra arguments, passed through (`-p geodesic-core`, `-- NAME`).
    pub extra: Vec<String>,
    /// The command recorded in the run, the caller's arguments included (`cargo xtask test --
    /// -p geodesic-core`).
    pub command: String,
    /// The program's name on every line it prints (`xtask test`).
    pub prefix: String,
    /// How long a fresh clone's first build takes, said before it starts (`6 minutes`).
    pub fresh_build: Option<String>,
}

/// The target directory: `CARGO_TARGET_DIR` (or `CARGO_BUILD_TARGET_DIR`) if set (relative to
/// `root`), else `<root>/target`.
pub fn target_dir(root: &Path) -> PathBuf {
    ["CARGO_TARGET_DIR", "CARGO_BUILD_TARGET_DIR"]
        .iter()
        .find_map(|v| std::env::var_os(v).filter(|s| !s.is_empty()))
        .map(|d| root.join(d))
        .unwrap_or_else(|| root.join("target"))
}

/// `git rev-parse HEAD` (`unknown` outside a repository) and whether the tree is dirty.
fn git_state(root: &Path) -> (String, bool) {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .current_dir(root)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "HEAD"]) {
        Some(commit) if !commit.is_empty() => {
            let dirty = git(&["status", "--porcelain"]).is_none_or(|s| !s.is_empty());
            (commit, dirty)
        }
        _ => ("unknown".into(), false),
    }
}

/// UTC date and time of `secs` since the Unix epoch, RFC 3339 (`2026-11-23T18:23:14Z`).
pub fn rfc3339(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let s = secs % 86_400;
    format!(
        "{}T{:02}:{:02}:{:02}Z",
        geodesic_core::disposition::civil_from_days(days),
        s / 3600,
        s / 60 % 60,
        s % 60
    )
}

/// Reads every record the tests wrote in `dir`.
fn read_records(dir: &Path, prefix: &str) -> Vec<TraceRecord> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| rd.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    files.sort();
    files
        .iter()
        .filter_map(|f| {
            let text = std::fs::read_to_string(f).ok()?;
            match serde_json::from_str(&text) {
                Ok(r) => Some(r),
                Err(e) => {
                    eprintln!("{prefix}: {}: {e}", f.display());
                    None
                }
            }
        })
        .collect()
}

/// Runs `cargo test` as `r` says, writes `<target>/geodesic/test-run.json` and returns cargo's
/// exit status (0, or cargo's non-zero status, 1 when it does not fit a byte; 101 when cargo
/// was killed). `Err` is a run that
/// could not start or a record that could not be written (the caller exits 2).
pub fn record(r: &Recording) -> Result<u8, String> {
    let root = &r.root;
    let prefix = r.prefix.as_str();
    let out_dir = &r.out_dir;
    let trace_dir = out_dir.join(format!("trace-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&trace_dir);
    std::fs::create_dir_all(&trace_dir).map_err(|e| format!("{}: {e}", trace_dir.display()))?;
    let (commit, dirty) = git_state(root);
    // the tree the tests run on, fingerprinted before and after: `verify` counts the run only
    // for that tree (geodesic_core::testrun::TestRun::freshness)
    let tree_before = geodesic_core::testrun::tree_state_any(root).ok();
    // every property test of the recorded run draws its cases from one fixed seed: a traced
    // test's result is a fact about the commit, not one draw of a hundred (plain `cargo test`
    // keeps exploring new cases); the user's own PROPTEST_RNG_SEED wins
    let proptest_seed = std::env::var("PROPTEST_RNG_SEED")
        .ok()
        .filter(|s| !s.trim().is_empty())
        .unwrap_or_else(|| PROPTEST_RNG_SEED.to_string());

    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    // the release profile: the tests share every compiled crate with `cargo build --release`
    // (README, "Tests and build profiles")
    cmd.current_dir(root)
        .arg("test")
        .args(&r.cargo_args)
        .args(&r.extra)
        .env(geodesic_core::trace::TRACE_DIR_ENV, &trace_dir)
        .env("PROPTEST_RNG_SEED", &proptest_seed);
    if std::io::stdout().is_terminal() && std::env::var_os("CARGO_TERM_COLOR").is_none() {
        cmd.env("CARGO_TERM_COLOR", "always");
    }
    let mut line: Vec<&str> = vec!["cargo", "test"];
    line.extend(r.cargo_args.iter().map(String::as_str));
    line.extend(r.extra.iter().map(String::as_str));
    match &r.fresh_build {
        Some(t) => println!(
            "{prefix}: {} (a fresh clone builds for about {t} on 2 cores first; the status says what runs)",
            line.join(" ")
        ),
        None => println!("{prefix}: {} (the status says what runs)", line.join(" ")),
    }
    let (text, status) = crate::progress::run_streamed(cmd, prefix)
        .map_err(|e| format!("running cargo test: {e}"))?;

    let listed = crate::output::parse(&text);
    let records = read_records(&trace_dir, prefix);
    let declared = crate::scan::scan(root);
    let (tests, mut warnings) = crate::join::join(&listed, &records, &declared);
    for d in &declared {
        for id in &d.requirements {
            if !geodesic_core::trace::is_known(id) {
                warnings.push(format!(
                    "{}: verifies!(\"{id}\") names an unknown requirement",
                    d.location
                ));
            }
        }
    }
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let tree_after = geodesic_core::testrun::tree_state_any(root).ok();
    let tree_sha256 = match (&tree_before, &tree_after) {
        (Some(a), Some(b)) if a == b => Some(a.tree_sha256.clone()),
        (Some(_), Some(_)) => {
            warnings.push(
                "the work tree changed while the tests ran: the run is recorded without a tree fingerprint (stale for geodesic verify)".into(),
            );
            None
        }
        _ => None,
    };
    let run = TestRun {
        commit,
        dirty,
        tree_sha256,
        proptest_rng_seed: Some(proptest_seed),
        date: rfc3339(secs),
        command: r.command.clone(),
        tests,
    };
    let path = out_dir.join("test-run.json");
    let json = serde_json::to_string_pretty(&run).map_err(|e| e.to_string())?;
    geodesic_util::output::write_atomic(&path, (json + "\n").as_bytes())
        .map_err(|e| e.to_string())?;
    let _ = std::fs::remove_dir_all(&trace_dir);

    for w in &warnings {
        eprintln!("{prefix}: warning: {w}");
    }
    eprintln!("{}", summary(&run, &path));
    Ok(match status.code() {
        Some(0) => 0,
        Some(c) => u8::try_from(c).unwrap_or(1).max(1),
        None => 101,
    })
}

/// One paragraph: where the run is, how many traced tests by result and kind, and the tests
/// that are not evidence.
fn summary(run: &TestRun, path: &Path) -> String {
    let mut by_result: BTreeMap<&str, usize> = BTreeMap::new();
    let mut by_kind: BTreeMap<&str, usize> = BTreeMap::new();
    for t in &run.tests {
        *by_result.entry(t.result.as_str()).or_default() += 1;
        *by_kind.entry(t.kind.as_str()).or_default() += 1;
    }
    let list = |m: &BTreeMap<&str, usize>| {
        m.iter()
            .map(|(k, n)| format!("{n} {k}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut s = format!(
        "recorded {} traced tests in {}: {}; kinds: {}",
        run.tests.len(),
        path.display(),
        list(&by_result),
        list(&by_kind)
    );
    for t in &run.tests {
        if t.result != TestResult::Passed {
            s.push_str(&format!(
                "\n  {} {}::{} ({})",
                t.result.as_str(),
                t.krate,
                t.test,
                t.requirements.join(", ")
            ));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::rfc3339;

    #[test]
    fn dates_are_rfc3339_utc() {
        assert_eq!(rfc3339(0), "1970-01-01T00:00:00Z");
        assert_eq!(rfc3339(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(rfc3339(1_798_054_994), "2026-12-23T19:43:14Z");
        assert_eq!(rfc3339(4_107_542_399), "2100-02-28T23:59:59Z");
    }
}
