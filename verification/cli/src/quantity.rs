//! Physical quantities on the command line: the framework's value parsers
//! ([`geodesic_verify::quantity`]) and the dimensions of the fit's parameters and channels.

use geodesic_core::units::{Dim, parse_unit};
use geodesic_facility::effects::catalogue;
pub use geodesic_verify::quantity::*;

/// The dimension of an effect parameter (`tip_adhesion.A1`) from the catalogue's unit, if the
/// parameter is known and its unit parses.
pub fn param_dim(name: &str) -> Option<Dim> {
    let (effect, param) = name.split_once('.')?;
    let e = catalogue().iter().find(|e| e.name() == effect)?;
    let p = e.params().iter().find(|p| p.name == param)?;
    parse_unit(p.unit).ok().map(|u| u.dim)
}

/// The dimension of a dataset channel (`x`, `y`: m; `E`: V) or `known` constant (`m`: kg;
/// `E0`: V).
pub fn channel_dim(name: &str) -> Option<Dim> {
    match name {
        "x" | "y" => Some(Dim::LENGTH),
        "E" | "E0" => Some(Dim::VOLTAGE),
        "m" => Some(Dim::MASS),
        _ => None,
    }
}
