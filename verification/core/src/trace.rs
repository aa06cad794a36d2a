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
