//! Checks of the `capture` family (being written; the registry reads `checks()`).

use geodesic_core::Check;

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    Vec::new()
}
