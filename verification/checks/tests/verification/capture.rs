//! Traced tests of the capture family.
