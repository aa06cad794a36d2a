//! Tests that trace to requirements.
//!
//! A test that verifies a requirement says so in its first statement, and asserts the
//! requirement's limit ([`assert_limit`]) or an independent reference ([`assert_reference`]):
//!
//! ```no_run
//! # fn main() {
//! geodesic_core::verifies!("REL-GPRM-VEL", "REL-SYS-VEL");
//! let v_m_s = 1.3e-6;
//! geodesic_core::trace::assert_limit("REL-GPRM-VEL", v_m_s);
//! # }
//! ```
//!
//! An ID that is not a requirement of the mission fails the test. The requirements are read at
//! run time from the mission the tests run in: the outermost folder at or above the working
//! directory holding a `mission.yaml` (cargo runs a test in its package's folder), its
//! requirement folder and those of `missions/*/mission.yaml` under it; the framework embeds no
//! mission's data.
//!
//! While `cargo xtask test` records a run it sets `GEODESIC_TRACE_DIR`: each executing
//! `verifies!` call and each assertion made through this module is then recorded, for the test
//! running on the current thread (libtest names a test's thread after the test), in one file per
//! test in that directory ([`crate::testrun::TraceRecord`]). The recorder joins these records
//! with the test results into `target/geodesic/test-run.json`, which the compliance matrix reads.
//! Without the variable nothing is recorded.

use crate::testrun::{Assertion, TraceAssertion, TraceCall, TraceRecord};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

/// The environment variable naming the folder of the `mission.yaml` whose requirements the
/// traced tests are checked against (default: the nearest folder at or above the working
/// directory that holds one: cargo runs a test in its package's folder).
pub const MISSION_ROOT_ENV: &str = "GEODESIC_MISSION_ROOT";

/// The folder of the mission the running tests belong to: [`MISSION_ROOT_ENV`], else the
/// nearest folder at or above the working directory holding a `mission.yaml` whose folder is
/// not itself under `missions/` (a repository's root mission), else the nearest holding one.
pub fn mission_root() -> Option<&'static Path> {
    static ROOT: OnceLock<Option<PathBuf>> = OnceLock::new();
    ROOT.get_or_init(|| {
        if let Some(d) = std::env::var_os(MISSION_ROOT_ENV).filter(|d| !d.is_empty()) {
            return Some(PathBuf::from(d));
        }
        let cwd = std::env::current_dir().ok()?;
        let found: Vec<&Path> = cwd
            .ancestors()
            .filter(|d| d.join("mission.yaml").is_file())
            .collect();
        // the outermost one: a mission's own crate inside a repository verifies against the
        // repository's missions, all of which are loaded below
        found.last().map(|p| p.to_path_buf())
    })
    .as_deref()
}

#[derive(serde::Deserialize)]
struct Descriptor {
    name: String,
    requirements: String,
}

fn read_descriptor(dir: &Path) -> Option<Descriptor> {
    let text = std::fs::read_to_string(dir.join("mission.yaml")).ok()?;
    serde_saphyr::from_str(&text).ok()
}

/// Every mission's requirement set, `(name, requirements)`: the root mission's first, then
/// each `missions/<name>/mission.yaml` under the root (read once, at run time: the framework
/// embeds no mission's data).
pub fn missions() -> &'static [(String, crate::Requirements)] {
    static ALL: OnceLock<Vec<(String, crate::Requirements)>> = OnceLock::new();
    ALL.get_or_init(|| {
        let Some(root) = mission_root() else {
            return Vec::new();
        };
        let mut dirs = vec![root.to_path_buf()];
        let mut others: Vec<PathBuf> = std::fs::read_dir(root.join("missions"))
            .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        others.retain(|d| d.join("mission.yaml").is_file());
        others.sort();
        dirs.extend(others);
        let mut out = Vec::new();
        for d in dirs {
            let Some(desc) = read_descriptor(&d) else {
                panic!(
                    "{}: not a readable mission descriptor",
                    d.join("mission.yaml").display()
                );
            };
            let reqs = crate::Requirements::load_dir(&d.join(&desc.requirements))
                .unwrap_or_else(|e| panic!("requirements of mission {}: {e}", desc.name));
            out.push((desc.name, reqs));
        }
        out
    })
}

/// The requirement set of mission `name` (see [`missions`]), or `None`.
pub fn mission_requirements(mission: &str) -> Option<crate::Requirements> {
    missions()
        .iter()
        .find(|(m, _)| m == mission)
        .map(|(_, r)| r.clone())
}

/// A requirement of any mission's set.
fn any_requirement(id: &str) -> Option<crate::requirement::Requirement> {
    missions()
        .iter()
        .find_map(|(_, reqs)| reqs.get(id).cloned())
}

/// The root mission's requirement set (see [`missions`]); panics when the tests run outside
/// a mission's folder.
pub fn requirements() -> &'static crate::Requirements {
    &missions()
        .first()
        .unwrap_or_else(|| {
            panic!("no mission.yaml at or above the working directory (set {MISSION_ROOT_ENV})")
        })
        .1
}

/// Asserts that `value_si` (SI units, the requirement's dimension) meets requirement `id`'s own
/// limit as written in `requirements/` (e.g. `<= 5 um/s`), and returns the margin. The
/// assertion names the requirement, the value and the limit in the requirement's unit.
#[track_caller]
pub fn assert_limit(id: &str, value_si: f64) -> f64 {
    let r = any_requirement(id).unwrap_or_else(|| panic!("assert_limit: unknown requirement {id}"));
    let lim = r.limit.as_ref().unwrap_or_else(|| {
        panic!("assert_limit: {id} is a qualitative requirement (no limit to assert)")
    });
    let (v, l) = (value_si / lim.unit.scale, lim.in_unit());
    assert!(
        value_si.is_finite() && lim.op.holds(v, l),
        "{id}: {v} {} does not meet its limit {}",
        lim.unit.symbol,
        lim.text
    );
    record_assertion(id, crate::testrun::Assertion::Limit);
    lim.op.margin(v, l)
}

/// Asserts that `value` agrees with an independent `reference` (named, e.g. "spec Tab. 6.2" or
/// "release-vectors.json #3") within the relative tolerance `rel_tol`, for requirement `id`.
#[track_caller]
pub fn assert_reference(id: &str, what: &str, value: f64, reference: f64, rel_tol: f64) {
    let ok = value.is_finite()
        && reference.is_finite()
        && (value - reference).abs() <= rel_tol * reference.abs();
    assert!(
        ok,
        "{id}: {value} differs from the reference {reference} ({what}) by more than {rel_tol} relative"
    );
    record_assertion(id, crate::testrun::Assertion::Reference);
}

/// The environment variable naming the directory where a recorded run's traces go.
pub const TRACE_DIR_ENV: &str = "GEODESIC_TRACE_DIR";

/// The trace directory of the run being recorded (`None`: not recording).
fn trace_dir() -> Option<&'static PathBuf> {
    static DIR: OnceLock<Option<PathBuf>> = OnceLock::new();
    DIR.get_or_init(|| {
        std::env::var_os(TRACE_DIR_ENV)
            .filter(|d| !d.is_empty())
            .map(PathBuf::from)
    })
    .as_ref()
}

/// The records of this process, by test (thread) name.
fn records() -> &'static Mutex<HashMap<String, TraceRecord>> {
    static RECORDS: OnceLock<Mutex<HashMap<String, TraceRecord>>> = OnceLock::new();
    RECORDS.get_or_init(Default::default)
}

/// File name of a test's record: the test binary and the test name, with every character other
/// than ASCII letters, digits and `_` encoded (`::` as `.`, others as `~xx`), so that distinct
/// tests never share a file.
pub fn record_file_name(binary: &str, test: &str) -> String {
    let mut out = String::new();
    for part in [binary, test] {
        if !out.is_empty() {
            out.push('-');
        }
        let mut chars = part.chars().peekable();
        while let Some(c) = chars.next() {
            if c.is_ascii_alphanumeric() || c == '_' {
                out.push(c);
            } else if c == ':' && chars.peek() == Some(&':') {
                chars.next();
                out.push('.');
            } else {
                let mut buf = [0u8; 4];
                for b in c.encode_utf8(&mut buf).bytes() {
                    out.push_str(&format!("~{b:02x}"));
                }
            }
        }
    }
    out.push_str(".json");
    out
}

/// Updates the record of the test running on this thread and writes it to its own file (only
/// while a run is recorded, and only on a named thread: libtest names each test's thread).
fn update_record(f: impl FnOnce(&mut TraceRecord)) {
    let Some(dir) = trace_dir() else { return };
    let Some(test) = std::thread::current().name().map(str::to_string) else {
        return;
    };
    let mut map = records().lock().unwrap_or_else(|e| e.into_inner());
    let rec = map.entry(test.clone()).or_insert_with(|| TraceRecord {
        test,
        binary: std::env::current_exe()
            .ok()
            .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
            .unwrap_or_default(),
        ..Default::default()
    });
    f(rec);
    // The test's own file, rewritten whole after every update: nothing is lost if the test
    // panics later, and no two tests share a path.
    let path = dir.join(record_file_name(&rec.binary, &rec.test));
    let write = || -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        std::fs::write(&path, serde_json::to_vec(&*rec)?)
    };
    if let Err(e) = write() {
        eprintln!("geodesic trace: cannot write {}: {e}", path.display());
    }
}

/// Like [`assert_reference`] with an absolute tolerance `abs_tol` (in the unit of `value`): for a
/// reference of zero, or a tolerance stated in the value's unit.
#[track_caller]
pub fn assert_reference_abs(id: &str, what: &str, value: f64, reference: f64, abs_tol: f64) {
    let ok = value.is_finite() && reference.is_finite() && (value - reference).abs() <= abs_tol;
    assert!(
        ok,
        "{id}: {value} differs from the reference {reference} ({what}) by more than {abs_tol}"
    );
    record_assertion(id, crate::testrun::Assertion::Reference);
}

/// Records, for the test running on this thread, that it asserted `kind` for `id` (used by the
/// test-run recorder; a no-op when no run is being recorded).
pub fn record_assertion(id: &str, kind: Assertion) {
    update_record(|r| {
        let a = TraceAssertion {
            requirement: id.to_string(),
            assertion: kind,
        };
        if !r.asserted.contains(&a) {
            r.asserted.push(a);
        }
    });
}

/// What [`verifies!`] does at run time: fails the test if an ID is unknown, then records the
/// call for the test running on this thread when a run is recorded.
pub fn verifies_at(ids: &[&str], krate: &str, location: &str) {
    assert_known(ids, location);
    update_record(|r| {
        if r.krate.is_empty() {
            r.krate = krate.to_string();
        }
        match r.calls.iter_mut().find(|c| c.location == location) {
            Some(c) => c.count += 1,
            None => r.calls.push(TraceCall {
                location: location.to_string(),
                requirements: ids.iter().map(|s| s.to_string()).collect(),
                count: 1,
            }),
        }
    });
}

/// Whether `id` is a requirement of one of the missions (see [`missions`]).
pub fn is_known(id: &str) -> bool {
    any_requirement(id).is_some()
}

/// Panics (failing the test) if an ID is not a known requirement. Used by [`verifies!`].
pub fn assert_known(ids: &[&str], location: &str) {
    for id in ids {
        assert!(
            is_known(id),
            "{location}: verifies!(\"{id}\") names an unknown requirement (not in the requirements of {})",
            mission_root().map_or("any mission found".to_string(), |r| r
                .join("mission.yaml")
                .display()
                .to_string())
        );
    }
}

/// Declares the requirement IDs a test verifies. An unknown ID fails the test; while a run is
/// recorded (`cargo xtask test`), the call is recorded for the running test.
#[macro_export]
macro_rules! verifies {
    ($($id:literal),+ $(,)?) => {{
        $crate::trace::verifies_at(
            &[$($id),+],
            match ::core::option_env!("CARGO_CRATE_NAME") {
                ::core::option::Option::Some(c) => c,
                ::core::option::Option::None => "",
            },
            ::core::concat!(::core::file!(), ":", ::core::line!()),
        )
    }};
}

#[cfg(test)]
mod tests {

    #[test]
    #[should_panic(expected = "unknown requirement")]
    fn unknown_id_fails() {
        super::assert_known(&["NOT-A-REQ"], "here");
    }

    #[test]
    fn the_ids_are_those_of_the_mission_the_tests_run_under() {
        // the core's own tests run in verification/core, under the repository's mission.yaml:
        // every ID of its requirement folder is known, an altered one is not
        let (_, reqs) = super::missions()
            .first()
            .expect("a mission.yaml above the crate");
        assert!(!reqs.items.is_empty());
        for r in &reqs.items {
            assert!(super::is_known(r.id.as_str()), "{}", r.id);
            assert!(!super::is_known(&format!("{}-X", r.id)), "{}-X", r.id);
        }
        assert!(!super::is_known(""));
    }

    #[test]
    fn record_file_names_are_distinct_and_plain() {
        let a = super::record_file_name("verification-0a1b", "family::a_b");
        let b = super::record_file_name("verification-0a1b", "family_a::b");
        assert_eq!(a, "verification~2d0a1b-family.a_b.json");
        assert_ne!(a, b);
        let c = super::record_file_name("x", "src/a.rs - f (line 3)");
        assert!(
            c.chars()
                .all(|c| c.is_ascii_alphanumeric() || "_.~-".contains(c)),
            "{c}"
        );
    }
}
