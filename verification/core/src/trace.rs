//! Tests that trace to requirements.
//!
//! A test that verifies a requirement says so in its first statement:
//!
//! ```
//! # fn main() {
//! geodesic_core::verifies!("REL-GPRM-VEL", "REL-DFACS-VEL");
//! # }
//! ```
//!
//! At run time the macro fails the test if an ID is not in `requirements/` (the IDs are
//! embedded at build time). At build time, `geodesic-checks`' build script collects every
//! `verifies!` call of the workspace into a table ([`TestTrace`]) that the compliance matrix
//! uses to list, per requirement, the tests that cover it; an unknown ID there fails the build.

use serde::Serialize;

/// Requirement IDs found in `requirements/*.yaml` when this crate was built.
pub const KNOWN_REQUIREMENT_IDS: &[&str] =
    include!(concat!(env!("OUT_DIR"), "/requirement_ids.rs"));

/// The repository's requirement files as `(path, text)`, embedded when this crate was built,
/// so that a traced test can assert a requirement's own limit ([`assert_limit`]).
pub const REQUIREMENT_SOURCES: &[(&str, &str)] =
    include!(concat!(env!("OUT_DIR"), "/requirement_sources.rs"));

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
    let r = requirements()
        .get(id)
        .unwrap_or_else(|| panic!("assert_limit: unknown requirement {id}"));
    let (v, l) = (value_si / r.unit.scale, r.limit.value / r.unit.scale);
    assert!(
        value_si.is_finite() && r.op.holds(v, l),
        "{id}: {v} {} does not meet its limit {}",
        r.unit.symbol,
        r.limit_text
    );
    record_assertion(id, crate::testrun::Assertion::Limit);
    r.op.margin(v, l)
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

/// Records, for the test running on this thread, that it asserted `kind` for `id` (used by the
/// test-run recorder; a no-op when no run is being recorded).
pub fn record_assertion(_id: &str, _kind: crate::testrun::Assertion) {}

/// One test that declares the requirements it verifies.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct TestTrace {
    /// Test name (`module::function`).
    pub test: &'static str,
    /// Source file, relative to the workspace root.
    pub file: &'static str,
    /// Line of the `verifies!` call.
    pub line: u32,
    /// Kind: `proptest`, `snapshot` (insta) or `unit`.
    pub kind: &'static str,
    /// Requirement IDs.
    pub requirements: &'static [&'static str],
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

/// Declares the requirement IDs a test verifies; fails the test if one is unknown.
#[macro_export]
macro_rules! verifies {
    ($($id:literal),+ $(,)?) => {
        $crate::trace::assert_known(&[$($id),+], concat!(file!(), ":", line!()))
    };
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
        crate::verifies!("NOT-A-REQ");
    }
}
