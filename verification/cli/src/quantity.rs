//! Physical quantities on the command line: the framework's value parsers
//! ([`geodesic_verify::quantity`]) and the dimensions of the fit's parameters and channels.

use geodesic_core::units::Dim;
pub use geodesic_verify::quantity::*;

pub use geodesic_discover::session::param_dim;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effect_parameters_take_their_catalogue_units() {
        let (k, v) = pair("tip_adhesion.lambda=400 nm", "fix", param_dim).unwrap();
        assert_eq!(k, "tip_adhesion.lambda");
        assert!((v - 4e-7).abs() < 1e-20);
        assert!(pair("tip_adhesion.lambda=400 V", "fix", param_dim).is_err());
        let (_, v) = pair("tip_adhesion.A1=1e5", "fix", param_dim).unwrap();
        assert_eq!(v, 1e5);
        assert!(pair("nosuch.p=nan", "fix", param_dim).is_err());
        assert!(pair("novalue", "fix", param_dim).is_err());
    }
}
