//! Physical quantities on the command line, as the YAML files accept them: a bare number is in SI
//! units (`--vz 3e-6`), a number with a unit is converted (`--vz 3um/s`, `--vz "3 um/s"`,
//! `--fix tip_adhesion.lambda=400nm`). A unit of the wrong dimension, NaN and infinities are
//! refused with one line naming the flag.

use crate::error::Error as CliError;
use geodesic_core::units::{Dim, parse_si};

fn parser(dim: Dim) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| parse_si(s, dim)
}

/// `value_parser` for a flag whose name states its unit (`--c-eh-pf`, `--rate-e-s`): a bare
/// number is in that unit (`scale` SI units per flag unit), a number with a unit is converted
/// into it (`--c-eh-pf 34.4pF`, `--c-eh-pf 3.44e-11F`).
pub fn in_unit(
    dim: Dim,
    scale: f64,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let si = parse_si(s, dim)?;
        let bare = geodesic_core::units::parse_quantity(s)
            .map(|(_, u)| u.symbol.is_empty())
            .unwrap_or(true);
        Ok(if bare { si } else { si / scale })
    }
}

/// `value_parser` for a length [m].
pub fn length() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim::LENGTH)
}
/// `value_parser` for a velocity [m/s].
pub fn velocity() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim::VELOCITY)
}
/// `value_parser` for an angle [rad].
pub fn angle() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim::ANGLE)
}
/// `value_parser` for an angular rate [rad/s].
pub fn angular_rate() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim::ANGULAR_RATE)
}
/// `value_parser` for a time [s].
pub fn time() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim::TIME)
}
/// `value_parser` for a frequency [Hz].
pub fn frequency() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim::FREQUENCY)
}
/// `value_parser` for a voltage [V].
pub fn voltage() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim::VOLTAGE)
}
/// `value_parser` for a jerk [m/s^3].
pub fn jerk() -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    parser(Dim([1, 0, -3, 0, 0, 0]))
}

/// `value_parser` `p` whose value must be > 0: `what` names it in the refusal
/// (`--fs -100`: "a sampling frequency must be > 0, not -100 (SI)").
pub fn positive(
    p: impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static,
    what: &'static str,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let v = p(s)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{what} must be > 0, not {v} (SI)"))
        }
    }
}

/// `value_parser` `p` whose value must be >= 0: `what` names it in the refusal.
pub fn non_negative(
    p: impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static,
    what: &'static str,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let v = p(s)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(format!("{what} cannot be negative, not {v} (SI)"))
        }
    }
}

/// Parses `NAME=VALUE` where VALUE may carry a unit of the dimension `dim_of(NAME)`; a name of
/// unknown dimension takes a bare number only (the command then names the unknown parameter).
pub fn pair(
    text: &str,
    flag: &str,
    dim_of: impl Fn(&str) -> Option<Dim>,
) -> Result<(String, f64), CliError> {
    let (k, v) = text
        .split_once('=')
        .ok_or_else(|| CliError::usage(format!("--{flag} `{text}`: expected NAME=VALUE")))?;
    let k = k.trim();
    let value =
        value_of(v.trim(), dim_of(k)).map_err(|e| CliError::usage(format!("--{flag} {k}: {e}")))?;
    Ok((k.to_string(), value))
}

/// Parses `NAME=LO:HI` (`--bound`), each end with a unit of the dimension `dim_of(NAME)` (a
/// bare number when it is unknown); the lower end must be below the upper.
pub fn bound(
    text: &str,
    dim_of: impl Fn(&str) -> Option<Dim>,
) -> Result<(String, (f64, f64)), CliError> {
    let (k, r) = text
        .split_once('=')
        .ok_or_else(|| CliError::usage(format!("--bound `{text}`: expected NAME=LO:HI")))?;
    let k = k.trim();
    let (lo, hi) = r
        .split_once(':')
        .ok_or_else(|| CliError::usage(format!("--bound `{text}`: expected LO:HI")))?;
    let dim = dim_of(k);
    let lo = value_of(lo.trim(), dim)
        .map_err(|e| CliError::usage(format!("--bound {k}: lower bound {e}")))?;
    let hi = value_of(hi.trim(), dim)
        .map_err(|e| CliError::usage(format!("--bound {k}: upper bound {e}")))?;
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return Err(CliError::usage(format!(
            "--bound `{text}`: lower bound not below upper bound"
        )));
    }
    Ok((k.to_string(), (lo, hi)))
}

/// A value for a quantity of dimension `dim` (or a bare number when `dim` is unknown).
pub fn value_of(text: &str, dim: Option<Dim>) -> Result<f64, String> {
    match dim {
        Some(d) => parse_si(text, d),
        None => {
            let v: f64 = text
                .parse()
                .map_err(|_| format!("`{text}` is not a number"))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(format!("`{text}`: not a finite number"))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_convert_and_wrong_dimensions_are_refused() {
        assert_eq!(velocity()("3e-6").unwrap(), 3e-6);
        assert!((velocity()("3um/s").unwrap() - 3e-6).abs() < 1e-18);
        assert!((velocity()("3 um/s").unwrap() - 3e-6).abs() < 1e-18);
        assert!(velocity()("3 um").unwrap_err().contains("velocity"));
        assert!(velocity()("inf").is_err());
        assert!(velocity()("NaN").is_err());
        assert!((angle()("1.5 mrad").unwrap() - 1.5e-3).abs() < 1e-15);
        // NAME=VALUE with the dimension the name has (a length here), a bare number otherwise
        let dim = |n: &str| (n == "a.len").then_some(Dim::LENGTH);
        let (k, v) = pair("a.len=400 nm", "fix", dim).unwrap();
        assert_eq!(k, "a.len");
        assert!((v - 4e-7).abs() < 1e-20);
        assert!(pair("a.len=400 V", "fix", dim).is_err());
        let (_, v) = pair("b=1e5", "fix", dim).unwrap();
        assert_eq!(v, 1e5);
        assert!(pair("nosuch.p=nan", "fix", dim).is_err());
        assert!(pair("novalue", "fix", dim).is_err());
        let (k, (lo, hi)) = bound("a.len=1 nm:2 um", dim).unwrap();
        assert_eq!(k, "a.len");
        assert!((lo - 1e-9).abs() < 1e-21 && (hi - 2e-6).abs() < 1e-18);
        assert!(
            bound("a.len=2:1", dim)
                .unwrap_err()
                .to_string()
                .contains("not below")
        );
        assert!(
            bound("a.len=1 V:2", dim)
                .unwrap_err()
                .to_string()
                .contains("lower bound")
        );
        assert!(
            bound("a.len", dim)
                .unwrap_err()
                .to_string()
                .contains("NAME=LO:HI")
        );
        assert!(
            bound("a.len=1", dim)
                .unwrap_err()
                .to_string()
                .contains("LO:HI")
        );
        let fs = positive(frequency(), "a sampling frequency");
        assert_eq!(fs("1kHz").unwrap(), 1e3);
        assert!(
            fs("-100")
                .unwrap_err()
                .contains("a sampling frequency must be > 0")
        );
        assert!(fs("0").is_err());
        let pre = non_negative(time(), "the record before the trigger");
        assert_eq!(pre("0").unwrap(), 0.0);
        assert!(pre("-1ms").unwrap_err().contains("cannot be negative"));
    }
}
