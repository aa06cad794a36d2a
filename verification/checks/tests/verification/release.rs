//! Traced tests of the release family.
