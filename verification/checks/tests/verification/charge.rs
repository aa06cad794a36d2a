//! Traced tests of the charge family.
