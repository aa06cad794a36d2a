//! The fit's coordinates of a parameter (`ln p` for a parameter fitted in log space, `p / scale`
//! otherwise) and the checks of user-given values and bounds against its spec.

use geodesic_facility::ParamSpec;

/// `p` [SI] in the fit's coordinate of `s`.
pub fn to_u(s: &ParamSpec, p: f64) -> f64 {
    if s.log {
        p.max(1e-300).ln()
    } else {
        p / s.scale
    }
}

/// The value [SI] of the fit's coordinate `u` of `s`.
pub fn from_u(s: &ParamSpec, u: f64) -> f64 {
    if s.log { u.exp() } else { u * s.scale }
}

/// Why `v` is not an acceptable value of the parameter `spec` (named `name`): not finite, or
/// of the wrong sign for a parameter whose physical range is non-negative (masses, stiffnesses,
/// resistances), or not positive for one fitted in log space.
pub fn check_value(spec: &ParamSpec, name: &str, v: f64) -> Result<(), String> {
    if !v.is_finite() {
        return Err(format!("{name} must be a finite number"));
    }
    if spec.log && v <= 0.0 {
        return Err(format!("{name} must be positive ({})", spec.unit));
    }
    if spec.lower >= 0.0 && v < 0.0 {
        return Err(format!("{name} cannot be negative ({})", spec.unit));
    }
    Ok(())
}

/// Why `lo:hi` is not an acceptable bound of the parameter `spec`: both finite, `lo < hi`, and
/// `lo > 0` for a parameter fitted in log space (it replaces the built-in range).
pub fn check_bound(spec: &ParamSpec, lo: f64, hi: f64) -> Result<(), String> {
    if !(lo.is_finite() && hi.is_finite()) {
        return Err("bounds must be finite numbers".into());
    }
    if lo >= hi {
        return Err("lower bound not below upper bound".into());
    }
    if spec.log && lo <= 0.0 {
        return Err(format!(
            "the parameter is strictly positive: the lower bound must be above 0 ({})",
            spec.unit
        ));
    }
    if spec.lower >= 0.0 && lo < 0.0 {
        return Err(format!("the parameter cannot be negative ({})", spec.unit));
    }
    Ok(())
}
