//! Tests that trace to requirements.
//!
//! A test that verifies a requirement says so in its first statement, and asserts the
//! requirement's limit ([`assert_limit`]) or an independent reference ([`assert_reference`]):
//!
//! ```no_run
//! # fn main() {
//! geodesic_core::verifies!("REL-GPRM-VEL", "REL-DFACS-VEL");
//! let v_m_s = 1.3e-6;
//! geodesic_core::trace::assert_limit("REL-GPRM-VEL", v_m_s);
//! # }
//! ```
//!
//! An ID that is not in `requirements/` fails the build (the IDs are embedded at build time and
//! checked in a constant), and the test at run time:
//!
//! ```compile_fail,E0080
//! geodesic_core::verifies!("NOT-A-REQ");
//! ```
//!
//! While `cargo xtask test` records a run it sets `GEODESIC_TRACE_DIR`: each executing
//! `verifies!` call and each assertion made through this module is then recorded, for the test
//! running on the current thread (libtest names a test's thread after the test), in one file per
//! test in that directory ([`crate::testrun::TraceRecord`]). The recorder joins these records
//! with the test results into `target/geodesic/test-run.json`, which the compliance matrix reads.
//! Without the variable nothing is recorded.

use crate::testrun::{Assertion, TraceAssertion, TraceCall, TraceRecord};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Mutex, OnceLock};

/// Requirement IDs found in `requirements/*.yaml` when this crate was built.
pub const KNOWN_REQUIREMENT_IDS: &[&str] =
    include!(concat!(env!("OUT_DIR"), "/requirement_ids.rs"));

/// The repository's requirement files as `(path, text)`, embedded when this crate was built,
/// so that a traced test can assert a requirement's own limit ([`assert_limit`]).
pub const REQUIREMENT_SOURCES: &[(&str, &str)] =
    include!(concat!(env!("OUT_DIR"), "/requirement_sources.rs"));

/// The other missions' requirement files, `(mission, [(path, text)])`, from
/// `missions/<mission>/requirements/*.yaml` (e.g. the Drag-Free CubeSat).
pub const MISSION_SOURCES: &[(&str, &[(&str, &str)])] =
    include!(concat!(env!("OUT_DIR"), "/mission_sources.rs"));

/// The embedded requirement set of `mission` (parsed once per call site's need), or `None`.
pub fn mission_requirements(mission: &str) -> Option<crate::Requirements> {
    let (_, files) = MISSION_SOURCES.iter().find(|(m, _)| *m == mission)?;
    let src: Vec<(std::path::PathBuf, String)> = files
        .iter()
        .map(|(p, t)| (std::path::PathBuf::from(p), t.to_string()))
        .collect();
    Some(
        crate::Requirements::from_sources(&src)
            .unwrap_or_else(|e| panic!("embedded requirements of {mission}: {e}")),
    )
}

/// A requirement of the built-in set or of any mission's set.
fn any_requirement(id: &str) -> Option<crate::requirement::Requirement> {
    if let Some(r) = requirements().get(id) {
        return Some(r.clone());
    }
    MISSION_SOURCES
        .iter()
        .filter_map(|(m, _)| mission_requirements(m))
        .find_map(|reqs| reqs.get(id).cloned())
}

/// The embedded requirement set (parsed once).
pub fn requirements() -> &'static crate::Requirements {
    static REQS: std::sync::OnceLock<crate::Requirements> = std::sync::OnceLock::new();
    REQS.get_or_init(|| {
        let src: Vec<(std::path::PathBuf, String)> = REQUIREMENT_SOURCES
            .iter()
            .map(|(p, t)| (std::path::PathBuf::from(p), t.to_string()))
            .collect();
        crate::Requirements::from_sources(&src)
            .unwrap_or_else(|e| panic!("embedded requirements: {e}"))
    })
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

/// Asserts that `value` agrees with an independent `reference` (named, e.g. "thesis Tab. 6.2" or
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

/// Whether `id` is a known requirement ID (usable in constants: [`verifies!`] checks its IDs at
/// build time with it).
pub const fn is_known(id: &str) -> bool {
    let mut i = 0;
    while i < KNOWN_REQUIREMENT_IDS.len() {
        let k = KNOWN_REQUIREMENT_IDS[i].as_bytes();
        let b = id.as_bytes();
        if k.len() == b.len() {
            let mut j = 0;
            while j < k.len() && k[j] == b[j] {
                j += 1;
            }
            if j == k.len() {
                return true;
            }
        }
        i += 1;
    }
    false
}

/// Panics (failing the test) if an ID is not a known requirement. Used by [`verifies!`].
pub fn assert_known(ids: &[&str], location: &str) {
    for id in ids {
        assert!(
            KNOWN_REQUIREMENT_IDS.contains(id),
            "{location}: verifies!(\"{id}\") names an unknown requirement (not in requirements/*.yaml)"
        );
    }
}

/// Declares the requirement IDs a test verifies. An unknown ID fails the build (and the test);
/// while a run is recorded (`cargo xtask test`), the call is recorded for the running test.
#[macro_export]
macro_rules! verifies {
    ($($id:literal),+ $(,)?) => {{
        $(
            const _: () = ::core::assert!(
                $crate::trace::is_known($id),
                ::core::concat!(
                    "verifies!(\"", $id, "\") names an unknown requirement (not in requirements/*.yaml)"
                )
            );
        )+
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
    fn known_ids_are_embedded() {
        assert!(super::KNOWN_REQUIREMENT_IDS.len() >= 12);
    }

    #[test]
    #[should_panic(expected = "unknown requirement")]
    fn unknown_id_fails() {
        super::assert_known(&["NOT-A-REQ"], "here");
    }

    #[test]
    fn known_ids_in_constants() {
        const { assert!(super::is_known("REL-GPRM-VEL")) };
        assert!(!super::is_known("REL-GPRM-VE"));
        assert!(!super::is_known("REL-GPRM-VELX"));
        assert!(!super::is_known(""));
    }

    #[test]
    fn record_file_names_are_distinct_and_plain() {
        let a = super::record_file_name("verification-0a1b", "capture::a_b");
        let b = super::record_file_name("verification-0a1b", "capture_a::b");
        assert_eq!(a, "verification~2d0a1b-capture.a_b.json");
        assert_ne!(a, b);
        let c = super::record_file_name("x", "src/a.rs - f (line 3)");
        assert!(
            c.chars()
                .all(|c| c.is_ascii_alphanumeric() || "_.~-".contains(c)),
            "{c}"
        );
    }
}
