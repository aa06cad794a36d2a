//! Traced tests of the fit family.
