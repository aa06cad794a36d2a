//! Traced tests of the framework family.
