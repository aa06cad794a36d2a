//! Requirements whose limit is a curve over frequency: an amplitude spectral density (ASD) bound
//! `L(f) = level x shape(f)` over a band (e.g. a mission's
//! `3e-14 (1 + (f / 3 mHz)^2) m s^-2 Hz^-1/2` over 1-30 mHz, or a temperature stability
//! `1e-3 (1 mHz / f)^(1/3) K Hz^-1/2`).
//!
//! In YAML the `limit` states the level with its ASD unit and `spectrum` the band and shape:
//!
//! ```yaml
//! dimension: acceleration          # of the quantity whose ASD is bounded
//! limit: "<= 3e-14 m s^-2 Hz^-1/2"
//! spectrum:
//!   band: "1 mHz .. 30 mHz"
//!   shape: "1 + (f / 3 mHz)^2"
//! ```
//!
//! A check reports the worst ratio `r = max over the band of ASD(f) / L(f)` as the value
//! `r x level` (the ASD referred to the level), so the matrix's margin `1 - r` is the margin at
//! the worst frequency, which the evidence names.
//!
//! Shapes are sums of terms, each a number or `[c *] (f / F)^p` or `[c *] (F / f)^p` with `F`
//! a frequency with its unit and `p` a number or a fraction `(1/3)`.

use crate::units::{Dim, parse_quantity};
use serde::Serialize;

/// One term of a shape: `coef x (f / f_ref)^exponent` (`f_ref = 0`: the constant `coef`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Term {
    /// Coefficient [-].
    pub coef: f64,
    /// Reference frequency [Hz] (0 for a constant term).
    pub f_ref_hz: f64,
    /// Exponent of `f / f_ref` [-].
    pub exponent: f64,
}

/// The band and shape of a spectral limit.
#[derive(Clone, Debug, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Spectrum {
    /// Band `[f_min, f_max]` [Hz] over which the limit applies.
    pub band_hz: [f64; 2],
    /// The band as written.
    pub band_text: String,
    /// The shape's terms.
    pub terms: Vec<Term>,
    /// The shape as written.
    pub shape_text: String,
}

impl Spectrum {
    /// Parses `band` (`1 mHz .. 30 mHz`, `1e-4 Hz .. 1 Hz`) and `shape`.
    pub fn parse(band: &str, shape: &str) -> Result<Spectrum, String> {
        let band_hz = parse_band(band)?;
        let terms = parse_shape(shape)?;
        let s = Spectrum {
            band_hz,
            band_text: band.trim().to_string(),
            terms,
            shape_text: shape.trim().to_string(),
        };
        // the shape must be positive and finite over the band (checked on a log grid)
        for i in 0..=200 {
            let f = band_hz[0] * (band_hz[1] / band_hz[0]).powf(i as f64 / 200.0);
            let v = s.shape(f);
            if !(v.is_finite() && v > 0.0) {
                return Err(format!(
                    "shape `{}` is {v} at {f:.3e} Hz: it must be positive over the band",
                    s.shape_text
                ));
            }
        }
        Ok(s)
    }

    /// The shape at `f_hz` [Hz] (the limit is `level x shape(f)`).
    pub fn shape(&self, f_hz: f64) -> f64 {
        self.terms
            .iter()
            .map(|t| {
                if t.f_ref_hz == 0.0 {
                    t.coef
                } else {
                    t.coef * (f_hz / t.f_ref_hz).powf(t.exponent)
                }
            })
            .sum()
    }

    /// Whether `f_hz` is inside the band (ends included).
    pub fn in_band(&self, f_hz: f64) -> bool {
        f_hz >= self.band_hz[0] && f_hz <= self.band_hz[1]
    }
}

/// Strips the ASD marker (`Hz^-1/2`, `Hz^(-1/2)`, `Hz^-0.5`, `/sqrt(Hz)`, `/√Hz`, `/rtHz`)
/// from the end of a quantity text; `None` if it has none.
pub fn strip_asd_unit(text: &str) -> Option<String> {
    let t = text.trim();
    for suffix in ["Hz^-1/2", "Hz^(-1/2)", "Hz^-0.5", "Hz^(-0.5)"] {
        if let Some(rest) = t.strip_suffix(suffix) {
            let rest = rest.trim_end();
            // `m/s^2 Hz^-1/2` or `m s^-2 Hz^-1/2`; a trailing `*` or `·` joins them
            let rest = rest.trim_end_matches(['*', '·']).trim_end();
            return Some(rest.to_string());
        }
    }
    for suffix in ["/sqrt(Hz)", "/√Hz", "/rtHz", "/ sqrt(Hz)"] {
        if let Some(rest) = t.strip_suffix(suffix) {
            return Some(rest.trim_end().to_string());
        }
    }
    None
}

fn frequency(text: &str, what: &str) -> Result<f64, String> {
    let (q, _) = parse_quantity(text).map_err(|e| format!("{what} `{}`: {e}", text.trim()))?;
    if q.dim != Dim::FREQUENCY {
        return Err(format!(
            "{what} `{}` is a {}, not a frequency",
            text.trim(),
            q.dim
        ));
    }
    if !(q.value.is_finite() && q.value > 0.0) {
        return Err(format!(
            "{what} `{}` must be a positive frequency",
            text.trim()
        ));
    }
    Ok(q.value)
}

/// Parses `F1 .. F2` (also `F1 - F2` is refused: `-` is ambiguous with exponents).
pub fn parse_band(text: &str) -> Result<[f64; 2], String> {
    let Some((a, b)) = text.split_once("..") else {
        return Err(format!(
            "band `{}` must be written `F1 .. F2` (e.g. `1 mHz .. 30 mHz`)",
            text.trim()
        ));
    };
    let lo = frequency(a, "band start")?;
    let hi = frequency(b, "band end")?;
    if lo >= hi {
        return Err(format!(
            "band `{}`: the start must be below the end",
            text.trim()
        ));
    }
    Ok([lo, hi])
}

fn number(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let t = t
        .strip_prefix('(')
        .and_then(|x| x.strip_suffix(')'))
        .unwrap_or(t);
    let v = if let Some((a, b)) = t.split_once('/') {
        let a: f64 = a
            .trim()
            .parse()
            .map_err(|_| format!("`{t}` is not a number"))?;
        let b: f64 = b
            .trim()
            .parse()
            .map_err(|_| format!("`{t}` is not a number"))?;
        a / b
    } else {
        t.parse::<f64>()
            .map_err(|_| format!("`{t}` is not a number"))?
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("`{t}` is not a finite number"))
    }
}

/// Parses a shape: terms separated by ` + `.
pub fn parse_shape(text: &str) -> Result<Vec<Term>, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("empty shape (write `1` for a flat limit)".into());
    }
    let mut terms = Vec::new();
    for part in split_terms(t) {
        terms.push(parse_term(part.trim()).map_err(|e| format!("shape `{t}`: {e}"))?);
    }
    Ok(terms)
}

/// Splits at `+` signs outside parentheses and not in an exponent (`1e+3`).
fn split_terms(t: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut depth, mut start) = (0i32, 0usize);
    let b = t.as_bytes();
    for (i, &c) in b.iter().enumerate() {
        match c {
            b'(' => depth += 1,
            b')' => depth -= 1,
            b'+' if depth == 0 && !(i > 0 && matches!(b[i - 1], b'e' | b'E')) => {
                out.push(&t[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&t[start..]);
    out
}

fn parse_term(t: &str) -> Result<Term, String> {
    if t.is_empty() {
        return Err("an empty term".into());
    }
    let (coef, rest) = match t.find('(') {
        None => {
            return Ok(Term {
                coef: number(t)?,
                f_ref_hz: 0.0,
                exponent: 0.0,
            });
        }
        Some(0) => (1.0, t),
        Some(i) => {
            let c = t[..i].trim().trim_end_matches(['*', '·', 'x']).trim();
            (number(c)?, &t[i..])
        }
    };
    // rest = "(f / F)^p" or "(F / f)^p" or "(f / F)"
    let close = rest
        .find(')')
        .ok_or_else(|| format!("`{t}`: unbalanced parenthesis"))?;
    let inner = &rest[1..close];
    let after = rest[close + 1..].trim();
    let p = match after.strip_prefix('^') {
        Some(p) => number(p)?,
        None if after.is_empty() => 1.0,
        None => return Err(format!("`{t}`: expected `^` after `)`")),
    };
    let (num, den) = inner
        .split_once('/')
        .ok_or_else(|| format!("`{t}`: write `(f / F)` or `(F / f)`"))?;
    let (num, den) = (num.trim(), den.trim());
    let (f_ref, exponent) = if num == "f" {
        (frequency(den, "reference frequency")?, p)
    } else if den == "f" {
        (frequency(num, "reference frequency")?, -p)
    } else {
        return Err(format!("`{t}`: one side of the ratio must be `f`"));
    };
    Ok(Term {
        coef,
        f_ref_hz: f_ref,
        exponent,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lpf_and_cubesat_shapes() {
        let s = Spectrum::parse("1 mHz .. 30 mHz", "1 + (f / 3 mHz)^2").unwrap();
        assert_eq!(s.band_hz, [1e-3, 30e-3]);
        assert!((s.shape(3e-3) - 2.0).abs() < 1e-12);
        assert!((s.shape(30e-3) - 101.0).abs() < 1e-9);
        let t = Spectrum::parse("0.1 mHz .. 1 Hz", "(1 mHz / f)^(1/3)").unwrap();
        assert!((t.shape(1e-3) - 1.0).abs() < 1e-12);
        assert!((t.shape(8e-3) - 0.5).abs() < 1e-12);
        let c = Spectrum::parse("1e-4 Hz .. 1 Hz", "1").unwrap();
        assert_eq!(c.shape(0.3), 1.0);
        let k = Spectrum::parse("1 mHz .. 1 Hz", "2 * (f / 1 Hz)^0.5 + 1e+0").unwrap();
        assert!((k.shape(1.0) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn asd_units_are_stripped() {
        assert_eq!(
            strip_asd_unit("3e-14 m s^-2 Hz^-1/2").unwrap(),
            "3e-14 m s^-2"
        );
        assert_eq!(
            strip_asd_unit("1e-12 m/s^2/sqrt(Hz)").unwrap(),
            "1e-12 m/s^2"
        );
        assert_eq!(strip_asd_unit("1e-3 K Hz^(-1/2)").unwrap(), "1e-3 K");
        assert!(strip_asd_unit("5 um/s").is_none());
    }

    #[test]
    fn bad_shapes_and_bands_say_why() {
        assert!(
            parse_band("1 mHz - 30 mHz")
                .unwrap_err()
                .contains("F1 .. F2")
        );
        assert!(parse_band("30 mHz .. 1 mHz").unwrap_err().contains("below"));
        assert!(
            parse_band("1 m .. 2 m")
                .unwrap_err()
                .contains("not a frequency")
        );
        assert!(
            parse_shape("1 + (g / 3 mHz)^2")
                .unwrap_err()
                .contains("`f`")
        );
        assert!(parse_shape("1 + (f / 3 mHz)^x").is_err());
        assert!(
            Spectrum::parse("1 mHz .. 1 Hz", "-1")
                .unwrap_err()
                .contains("positive")
        );
    }
}
