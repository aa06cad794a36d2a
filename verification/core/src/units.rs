//! Physical units as engineers write them: `5 um/s`, `200 µm`, `2 mrad`, `100 urad/s`, `3e8 e`,
//! `1.1 V`, `4.91e7 N/m`.
//!
//! Why hand-written rather than `uom`: `uom` parses `"200 µm"` only with U+00B5 and a space, and
//! rejects `um`, `200µm` or the Greek mu, which the requirements and datasets use. What this
//! project needs is small and exact: a dimension vector ([`Dim`]), SI prefixes (with `u`, `µ`
//! and `μ` for micro), the handful of symbols physics texts use, products, quotients and integer
//! powers. A [`Unit`] is a scale to SI and a dimension; a [`Quantity`] is a value in SI with
//! its dimension. The radian is kept as its own base dimension so that `2 mrad` cannot be
//! compared with `2 mm`.

use geodesic_util::text::one_line;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Elementary charge [C] (exact, SI 2019).
pub const ELEMENTARY_CHARGE_C: f64 = 1.602_176_634e-19;

/// Exponents of the base dimensions: metre, kilogram, second, ampere, kelvin, radian.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
pub struct Dim(pub [i8; 6]);

impl Dim {
    /// Pure number.
    pub const DIMENSIONLESS: Dim = Dim([0, 0, 0, 0, 0, 0]);
    /// Length [m].
    pub const LENGTH: Dim = Dim([1, 0, 0, 0, 0, 0]);
    /// Mass [kg].
    pub const MASS: Dim = Dim([0, 1, 0, 0, 0, 0]);
    /// Time [s].
    pub const TIME: Dim = Dim([0, 0, 1, 0, 0, 0]);
    /// Velocity [m/s].
    pub const VELOCITY: Dim = Dim([1, 0, -1, 0, 0, 0]);
    /// Acceleration [m/s^2].
    pub const ACCELERATION: Dim = Dim([1, 0, -2, 0, 0, 0]);
    /// Angle [rad].
    pub const ANGLE: Dim = Dim([0, 0, 0, 0, 0, 1]);
    /// Angular rate [rad/s].
    pub const ANGULAR_RATE: Dim = Dim([0, 0, -1, 0, 0, 1]);
    /// Electric charge [C].
    pub const CHARGE: Dim = Dim([0, 0, 1, 1, 0, 0]);
    /// Electric potential [V].
    pub const VOLTAGE: Dim = Dim([2, 1, -3, -1, 0, 0]);
    /// Capacitance [F].
    pub const CAPACITANCE: Dim = Dim([-2, -1, 4, 2, 0, 0]);
    /// Force [N].
    pub const FORCE: Dim = Dim([1, 1, -2, 0, 0, 0]);
    /// Energy [J].
    pub const ENERGY: Dim = Dim([2, 1, -2, 0, 0, 0]);
    /// Momentum [N s].
    pub const MOMENTUM: Dim = Dim([1, 1, -1, 0, 0, 0]);
    /// Stiffness [N/m].
    pub const STIFFNESS: Dim = Dim([0, 1, -2, 0, 0, 0]);
    /// Frequency [Hz].
    pub const FREQUENCY: Dim = Dim([0, 0, -1, 0, 0, 0]);
    /// Temperature [K].
    pub const TEMPERATURE: Dim = Dim([0, 0, 0, 0, 1, 0]);

    /// The named dimensions a requirement may declare, with their names.
    pub const NAMED: &'static [(&'static str, Dim)] = &[
        ("dimensionless", Dim::DIMENSIONLESS),
        ("length", Dim::LENGTH),
        ("mass", Dim::MASS),
        ("time", Dim::TIME),
        ("velocity", Dim::VELOCITY),
        ("acceleration", Dim::ACCELERATION),
        ("angle", Dim::ANGLE),
        ("angular_rate", Dim::ANGULAR_RATE),
        ("charge", Dim::CHARGE),
        ("voltage", Dim::VOLTAGE),
        ("capacitance", Dim::CAPACITANCE),
        ("force", Dim::FORCE),
        ("energy", Dim::ENERGY),
        ("momentum", Dim::MOMENTUM),
        ("stiffness", Dim::STIFFNESS),
        ("frequency", Dim::FREQUENCY),
        ("temperature", Dim::TEMPERATURE),
    ];

    /// Looks up a named dimension (`velocity`, `angle`, ...).
    pub fn from_name(name: &str) -> Option<Dim> {
        Dim::NAMED.iter().find(|(n, _)| *n == name).map(|(_, d)| *d)
    }

    /// The name of this dimension if it is one of [`Dim::NAMED`].
    pub fn name(self) -> Option<&'static str> {
        Dim::NAMED.iter().find(|(_, d)| *d == self).map(|(n, _)| *n)
    }

    /// The product's dimension (`None`: an exponent beyond the range of `i8`).
    fn mul(self, o: Dim) -> Option<Dim> {
        let mut r = self.0;
        for (a, b) in r.iter_mut().zip(o.0) {
            *a = a.checked_add(b)?;
        }
        Some(Dim(r))
    }

    /// The power's dimension (`None`: an exponent beyond the range of `i8`).
    fn pow(self, p: i8) -> Option<Dim> {
        let mut r = self.0;
        for a in r.iter_mut() {
            *a = a.checked_mul(p)?;
        }
        Some(Dim(r))
    }
}

impl fmt::Display for Dim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(n) = self.name() {
            return write!(f, "{n}");
        }
        let syms = ["m", "kg", "s", "A", "K", "rad"];
        let parts: Vec<String> = syms
            .iter()
            .zip(self.0)
            .filter(|(_, e)| *e != 0)
            .map(|(s, e)| {
                if e == 1 {
                    s.to_string()
                } else {
                    format!("{s}^{e}")
                }
            })
            .collect();
        if parts.is_empty() {
            write!(f, "1")
        } else {
            write!(f, "{}", parts.join(" "))
        }
    }
}

/// A unit: the factor that converts a value in this unit to SI, and its dimension.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Unit {
    /// Multiply a value in this unit by `scale` to get SI.
    pub scale: f64,
    /// Dimension.
    pub dim: Dim,
    /// The text as written (normalised: `µ` for micro).
    pub symbol: String,
}

/// Why a unit or quantity string was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum UnitError {
    /// The unit text has a symbol that is not known.
    #[error("unknown unit `{}` (symbol `{}`{})", one_line(.unit), one_line(.symbol), suggestion(.symbol))]
    UnknownSymbol {
        /// The whole unit text.
        unit: String,
        /// The part that was not recognised.
        symbol: String,
    },
    /// The quantity has no leading number.
    #[error("`{}` is not a number followed by a unit (e.g. `5 um/s`)", one_line(.0))]
    NotAQuantity(String),
    /// The number is NaN or infinite.
    #[error("`{}` is not a finite number", one_line(.0))]
    NotFinite(String),
    /// A power of a dimension beyond +-127, or a scale beyond the range of f64.
    #[error("unit `{}`: a power or a scale out of range", one_line(.0))]
    PowerOutOfRange(String),
    /// Empty unit text.
    #[error("empty unit")]
    Empty,
}

const PREFIXES: &[(&str, f64)] = &[
    ("Y", 1e24),
    ("Z", 1e21),
    ("E", 1e18),
    ("P", 1e15),
    ("T", 1e12),
    ("G", 1e9),
    ("M", 1e6),
    ("k", 1e3),
    ("h", 1e2),
    ("da", 1e1),
    ("d", 1e-1),
    ("c", 1e-2),
    ("m", 1e-3),
    ("u", 1e-6),
    ("µ", 1e-6),
    ("n", 1e-9),
    ("p", 1e-12),
    ("f", 1e-15),
    ("a", 1e-18),
];

/// Base and derived symbols: (symbol, scale to SI, dimension, takes prefixes).
fn symbol(s: &str) -> Option<(f64, Dim, bool)> {
    let v = match s {
        "m" => (1.0, Dim::LENGTH, true),
        "g" => (1e-3, Dim::MASS, true),
        "s" => (1.0, Dim::TIME, true),
        "A" => (1.0, Dim([0, 0, 0, 1, 0, 0]), true),
        "K" => (1.0, Dim::TEMPERATURE, true),
        "rad" => (1.0, Dim::ANGLE, true),
        "deg" | "degree" | "degrees" => (std::f64::consts::PI / 180.0, Dim::ANGLE, false),
        // revolutions per minute and per second, as motor and turntable data sheets write them
        "rpm" => (std::f64::consts::PI / 30.0, Dim::ANGULAR_RATE, false),
        "rps" => (2.0 * std::f64::consts::PI, Dim::ANGULAR_RATE, false),
        "micron" | "microns" => (1e-6, Dim::LENGTH, false),
        "sec" | "secs" => (1.0, Dim::TIME, true),
        "gram" | "grams" => (1e-3, Dim::MASS, false),
        "V" => (1.0, Dim::VOLTAGE, true),
        "C" => (1.0, Dim::CHARGE, true),
        "e" => (ELEMENTARY_CHARGE_C, Dim::CHARGE, false),
        "F" => (1.0, Dim::CAPACITANCE, true),
        "N" => (1.0, Dim::FORCE, true),
        "J" => (1.0, Dim::ENERGY, true),
        "W" => (1.0, Dim([2, 1, -3, 0, 0, 0]), true),
        "Pa" => (1.0, Dim([-1, 1, -2, 0, 0, 0]), true),
        "Hz" => (1.0, Dim::FREQUENCY, true),
        "Ohm" | "ohm" | "Ω" => (1.0, Dim([2, 1, -3, -2, 0, 0]), true),
        "min" => (60.0, Dim::TIME, false),
        "h" => (3600.0, Dim::TIME, false),
        "day" | "days" | "d" => (86400.0, Dim::TIME, false),
        "1" => (1.0, Dim::DIMENSIONLESS, false),
        "%" => (1e-2, Dim::DIMENSIONLESS, false),
        "ppm" => (1e-6, Dim::DIMENSIONLESS, false),
        _ => return None,
    };
    Some(v)
}

/// Unit names written out, with the symbol to write instead (for suggestions only).
const SPELLED: &[(&str, &str)] = &[
    ("second", "s"),
    ("millisecond", "ms"),
    ("microsecond", "us"),
    ("nanosecond", "ns"),
    ("meter", "m"),
    ("metre", "m"),
    ("millimeter", "mm"),
    ("millimetre", "mm"),
    ("micrometer", "um"),
    ("micrometre", "um"),
    ("nanometer", "nm"),
    ("nanometre", "nm"),
    ("kilogram", "kg"),
    ("volt", "V"),
    ("millivolt", "mV"),
    ("radian", "rad"),
    ("microradian", "urad"),
    ("hertz", "Hz"),
    ("newton", "N"),
    ("coulomb", "C"),
    ("farad", "F"),
    ("minute", "min"),
    ("hour", "h"),
    ("percent", "%"),
];

/// Symbols an unknown symbol is compared with for a suggestion (with common prefixes).
fn suggestion_candidates() -> Vec<String> {
    let bases = [
        "m", "g", "s", "A", "K", "rad", "V", "C", "e", "F", "N", "J", "W", "Pa", "Hz", "deg",
        "rpm", "micron", "min", "h", "day", "ppm",
    ];
    let mut out: Vec<String> = bases.iter().map(|b| b.to_string()).collect();
    for p in ["k", "m", "u", "n", "p"] {
        for b in ["m", "g", "s", "rad", "V", "N", "Hz", "F", "C"] {
            out.push(format!("{p}{b}"));
        }
    }
    out
}

/// Case-insensitive edit distance between two short words: insertions, deletions,
/// substitutions and transpositions of adjacent characters (optimal string alignment).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.to_lowercase().chars().collect();
    let b: Vec<char> = b.to_lowercase().chars().collect();
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// `; did you mean `X`?` for an unknown unit symbol: a unit name written out (`meters`), the
/// same symbol in another case (`MS`), or one edit away from a known symbol (`rmp`); else
/// empty.
fn suggestion(symbol: &str) -> String {
    let s = symbol.trim();
    let lower = s.to_lowercase();
    let singular = lower.strip_suffix('s').unwrap_or(&lower);
    let found = SPELLED
        .iter()
        .find(|(w, _)| *w == lower || *w == singular)
        .map(|(_, sym)| sym.to_string())
        .or_else(|| {
            let cands = suggestion_candidates();
            let same_case = cands.iter().find(|c| c.to_lowercase() == lower).cloned();
            same_case.or_else(|| {
                if s.chars().count() < 3 {
                    return None;
                }
                cands
                    .into_iter()
                    .filter(|c| c.chars().count() >= 2)
                    .map(|c| (edit_distance(s, &c), c))
                    .filter(|(d, _)| *d == 1)
                    .min_by(|a, b| a.0.cmp(&b.0).then_with(|| a.1.cmp(&b.1)))
                    .map(|(_, c)| c)
            })
        });
    match found {
        Some(f) => format!("; did you mean `{f}`?"),
        None => String::new(),
    }
}

/// One factor: a symbol with an optional prefix (a whole symbol wins over prefix + symbol, so
/// `m` is the metre, `mm` the millimetre, `ms` the millisecond, `Pa` the pascal).
fn factor(s: &str) -> Option<(f64, Dim)> {
    if let Some((sc, d, _)) = symbol(s) {
        return Some((sc, d));
    }
    for (p, ps) in PREFIXES {
        if let Some(rest) = s.strip_prefix(p)
            && let Some((sc, d, true)) = symbol(rest)
        {
            return Some((sc * ps, d));
        }
    }
    None
}

/// Normalises micro signs (Greek mu U+03BC and micro sign U+00B5 both become `µ`) and trims.
fn normalise(s: &str) -> String {
    s.trim().replace('\u{03BC}', "µ")
}

/// Parses a unit expression: factors separated by `*`, `·`, `.` or spaces, at most one `/`
/// (everything after it is in the denominator), integer powers with `^` (`m/s^2`, `N m`).
///
/// ```
/// use geodesic_core::units::{parse_unit, Dim};
/// let u = parse_unit("um/s").unwrap();
/// assert_eq!(u.dim, Dim::VELOCITY);
/// assert!((u.scale - 1e-6).abs() < 1e-20);
/// assert_eq!(parse_unit("µrad/s").unwrap().dim, Dim::ANGULAR_RATE);
/// assert!(parse_unit("furlong").is_err());
/// ```
pub fn parse_unit(text: &str) -> Result<Unit, UnitError> {
    let norm = normalise(text);
    if norm.is_empty() {
        return Err(UnitError::Empty);
    }
    let mut scale = 1.0;
    let mut dim = Dim::DIMENSIONLESS;
    let (num, den) = match norm.split_once('/') {
        Some((a, b)) => (a.to_string(), Some(b.to_string())),
        None => (norm.clone(), None),
    };
    let mut apply = |part: &str, sign: i8| -> Result<(), UnitError> {
        for tok in part.split(['*', '·', ' ']).filter(|t| !t.is_empty()) {
            let (base, pow) = match tok.split_once('^') {
                Some((b, p)) => {
                    let p: i8 = p.parse().map_err(|_| UnitError::UnknownSymbol {
                        unit: text.to_string(),
                        symbol: tok.to_string(),
                    })?;
                    (b, p)
                }
                None => {
                    // `m2`, `s2` style powers
                    let digits = tok.trim_start_matches(|c: char| !c.is_ascii_digit());
                    if !digits.is_empty()
                        && tok.len() > digits.len()
                        && digits.parse::<i8>().is_ok()
                    {
                        (
                            &tok[..tok.len() - digits.len()],
                            digits.parse::<i8>().unwrap_or(1),
                        )
                    } else {
                        (tok, 1)
                    }
                }
            };
            if base == "1" && sign == 1 {
                continue;
            }
            let (sc, d) = factor(base).ok_or_else(|| UnitError::UnknownSymbol {
                unit: text.to_string(),
                symbol: base.to_string(),
            })?;
            let too_large = || UnitError::PowerOutOfRange(text.to_string());
            let p = pow.checked_mul(sign).ok_or_else(too_large)?;
            scale *= sc.powi(p as i32);
            dim = d.pow(p).and_then(|d| dim.mul(d)).ok_or_else(too_large)?;
            if !(scale.is_finite() && scale > 0.0) {
                return Err(too_large());
            }
        }
        Ok(())
    };
    apply(&num, 1)?;
    if let Some(d) = den {
        if d.contains('/') {
            return Err(UnitError::UnknownSymbol {
                unit: text.to_string(),
                symbol: d,
            });
        }
        apply(&d, -1)?;
    }
    Ok(Unit {
        scale,
        dim,
        symbol: norm,
    })
}

/// A value in SI units with its dimension.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Quantity {
    /// Value in SI units.
    pub value: f64,
    /// Dimension.
    pub dim: Dim,
}

impl Quantity {
    /// A value already in SI units.
    pub fn new(value_si: f64, dim: Dim) -> Self {
        Quantity {
            value: value_si,
            dim,
        }
    }

    /// The value expressed in `unit` (which must have the same dimension).
    pub fn in_unit(&self, unit: &Unit) -> f64 {
        self.value / unit.scale
    }
}

/// Parses `"<number> <unit>"` (the space is optional: `200µm`, `5 um/s`, `3e8 e`, `1.1 V`,
/// `0.26` for a pure number). Returns the quantity in SI and the unit as written.
///
/// ```
/// use geodesic_core::units::{parse_quantity, Dim};
/// let (q, u) = parse_quantity("3e8 e").unwrap();
/// assert_eq!(q.dim, Dim::CHARGE);
/// assert!((q.value - 3e8 * 1.602176634e-19).abs() < 1e-20);
/// assert_eq!(u.symbol, "e");
/// let (q, _) = parse_quantity("200µm").unwrap();
/// assert!((q.value - 2e-4).abs() < 1e-15);
/// ```
pub fn parse_quantity(text: &str) -> Result<(Quantity, Unit), UnitError> {
    let norm = normalise(text);
    // longest prefix that parses as a number
    let bytes: Vec<(usize, char)> = norm.char_indices().collect();
    let mut split = 0;
    for (i, c) in &bytes {
        let end = i + c.len_utf8();
        let cand = &norm[..end];
        if cand.trim().parse::<f64>().is_ok() && !cand.ends_with(' ') {
            split = end;
        }
    }
    // "3e8 e": "3e" is not a number but "3e8" is; "1e" alone would not be taken.
    if split == 0 {
        return Err(UnitError::NotAQuantity(text.to_string()));
    }
    let num_text = norm[..split].trim();
    if num_text.eq_ignore_ascii_case("nan") || num_text.to_ascii_lowercase().contains("inf") {
        return Err(UnitError::NotFinite(text.to_string()));
    }
    let value: f64 = num_text
        .parse()
        .map_err(|_| UnitError::NotAQuantity(text.to_string()))?;
    if !value.is_finite() {
        return Err(UnitError::NotFinite(text.to_string()));
    }
    let rest = norm[split..].trim();
    let unit = if rest.is_empty() {
        Unit {
            scale: 1.0,
            dim: Dim::DIMENSIONLESS,
            symbol: String::new(),
        }
    } else {
        parse_unit(rest)?
    };
    let si = value * unit.scale;
    if !si.is_finite() {
        // e.g. `1e308 km`: finite as written, beyond f64 in SI
        return Err(UnitError::NotFinite(text.to_string()));
    }
    Ok((Quantity::new(si, unit.dim), unit))
}

/// Parses a value of dimension `dim` as given on a command line or in a file: a bare number is
/// taken in SI units (`3e-6` for 3 um/s), a number with a unit is converted (`3um/s`,
/// `3 um/s`, `200 µm`). Refuses a unit of another dimension and non-finite values; the error is
/// one line naming the expected dimension.
///
/// ```
/// use geodesic_core::units::{parse_si, Dim};
/// assert_eq!(parse_si("3e-6", Dim::VELOCITY).unwrap(), 3e-6);
/// assert!((parse_si("3um/s", Dim::VELOCITY).unwrap() - 3e-6).abs() < 1e-18);
/// assert!(parse_si("3 um", Dim::VELOCITY).is_err());
/// assert!(parse_si("NaN", Dim::VELOCITY).is_err());
/// ```
pub fn parse_si(text: &str, dim: Dim) -> Result<f64, String> {
    let want = || {
        dim.name()
            .map(|n| format!("of dimension {n}"))
            .unwrap_or_else(|| "a value".into())
    };
    let (q, unit) = parse_quantity(text).map_err(|e| e.to_string())?;
    if unit.symbol.is_empty() {
        // a bare number: SI units of the expected dimension
        return Ok(q.value);
    }
    if q.dim != dim {
        return Err(format!(
            "`{}`: unit `{}` is not {} (give SI units or a unit of that dimension)",
            one_line(text),
            one_line(&unit.symbol),
            want()
        ));
    }
    if !q.value.is_finite() {
        return Err(format!("`{}`: not a finite number", one_line(text)));
    }
    Ok(q.value)
}

/// Formats a number compactly with at most 4 significant digits, trailing zeros dropped (`5`,
/// `1.503`, `3.13e8`, `3e8`): the same number is written the same way in every report.
pub fn fmt_num(v: f64) -> String {
    fmt_num_digits(v, 4)
}

/// [`fmt_num`] with as many more significant digits (up to 8) as it takes for the written
/// number to be closer to `v` than a hundredth of its distance to `limit`: a value 0.27 % from
/// its limit is not written as the round number beside it (`0.99997`, not `1`, against
/// `>= 0.9973`).
pub fn fmt_num_near(v: f64, limit: f64) -> String {
    let gap = (v - limit).abs();
    let mut d = 4;
    loop {
        let s = fmt_num_digits(v, d);
        let back: f64 = s.parse().unwrap_or(v);
        if d >= 8 || !v.is_finite() || (back - v).abs() <= 0.01 * gap {
            return s;
        }
        d += 1;
    }
}

/// A fraction as a percentage with up to 6 significant digits (`99.73 %`, `99.997 %`, `95 %`).
pub fn fmt_pct(p: f64) -> String {
    format!("{} %", fmt_num_digits(100.0 * p, 6))
}

/// [`fmt_num`] with `digits` significant digits (1 to 17).
pub fn fmt_num_digits(v: f64, digits: usize) -> String {
    let digits = digits.clamp(1, 17) as i32;
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!(
            "{:.*}",
            (digits - 1 - a.log10().floor() as i32).max(0) as usize,
            v
        );
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.*e}", (digits - 1) as usize);
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn common_spellings_are_units_and_unknown_ones_get_a_suggestion() {
        let rpm = parse_unit("rpm").unwrap();
        assert_eq!(rpm.dim, Dim::ANGULAR_RATE);
        // 30 rpm is pi rad/s
        let (q, _) = parse_quantity("30 rpm").unwrap();
        assert!((q.value - std::f64::consts::PI).abs() < 1e-15);
        let (q, _) = parse_quantity("5 micron").unwrap();
        // as `5 um`: the number times the scale
        assert!((q.value - 5e-6).abs() < 1e-20 && q.dim == Dim::LENGTH);
        assert_eq!(q.value, parse_quantity("5 um").unwrap().0.value);
        assert_eq!(parse_unit("microns").unwrap().scale, 1e-6);
        assert_eq!(parse_unit("msec").unwrap().dim, Dim::TIME);
        assert_eq!(parse_unit("msec").unwrap().scale, 1e-3);
        assert_eq!(parse_unit("grams").unwrap().dim, Dim::MASS);
        assert_eq!(parse_unit("degrees").unwrap().dim, Dim::ANGLE);
        for (bad, hint) in [
            ("meters", "`m`"),
            ("micrometre", "`um`"),
            ("MS", "`ms`"),
            ("rmp", "`rpm`"),
            ("mircon", "`micron`"),
            ("Volts", "`V`"),
        ] {
            let e = parse_unit(bad).unwrap_err().to_string();
            assert!(e.contains(&format!("did you mean {hint}")), "{bad}: {e}");
        }
        let e = parse_unit("furlong").unwrap_err().to_string();
        assert!(!e.contains("did you mean"), "{e}");
    }

    #[test]
    fn numbers_near_their_limit_keep_the_digits_that_tell_them_apart() {
        assert_eq!(fmt_num_near(0.999_970_043, 0.9973), "0.99997");
        assert_eq!(fmt_num_near(1.3429, 5.0), "1.343");
        assert_eq!(fmt_num_near(3.13e8, 3e8), "3.13e8");
        assert_eq!(fmt_pct(0.9973), "99.73 %");
        assert_eq!(fmt_pct(0.95), "95 %");
        assert_eq!(fmt_num_digits(0.999_970_043, 6), "0.99997");
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-30)
    }

    #[test]
    fn engineering_spellings() {
        for (t, v, d) in [
            ("5 um/s", 5e-6, Dim::VELOCITY),
            ("5 µm/s", 5e-6, Dim::VELOCITY),
            ("5 μm/s", 5e-6, Dim::VELOCITY),
            ("200 µm", 2e-4, Dim::LENGTH),
            ("200µm", 2e-4, Dim::LENGTH),
            ("2 mrad", 2e-3, Dim::ANGLE),
            ("100 urad/s", 1e-4, Dim::ANGULAR_RATE),
            ("1.1 V", 1.1, Dim::VOLTAGE),
            ("2.5 pF", 2.5e-12, Dim::CAPACITANCE),
            ("4.91e7 N/m", 4.91e7, Dim::STIFFNESS),
            ("9.81 m/s^2", 9.81, Dim::ACCELERATION),
            ("11 uN s", 11e-6, Dim::MOMENTUM),
            ("20 mN", 0.02, Dim::FORCE),
            ("1.96 kg", 1.96, Dim::MASS),
            ("0.26", 0.26, Dim::DIMENSIONLESS),
            ("50 days", 50.0 * 86400.0, Dim::TIME),
            ("371.2 Ohm", 371.2, Dim([2, 1, -3, -2, 0, 0])),
        ] {
            let (q, _) = parse_quantity(t).unwrap_or_else(|e| panic!("{t}: {e}"));
            assert!(close(q.value, v), "{t}: {} vs {v}", q.value);
            assert_eq!(q.dim, d, "{t}");
        }
        let (q, _) = parse_quantity("3e8 e").unwrap();
        assert!(close(q.value, 3e8 * ELEMENTARY_CHARGE_C));
    }

    #[test]
    fn refusals() {
        assert!(matches!(
            parse_unit("furlong"),
            Err(UnitError::UnknownSymbol { .. })
        ));
        assert!(parse_quantity("um/s").is_err());
        assert!(parse_quantity("NaN m").is_err());
        assert!(parse_quantity("inf m").is_err());
        assert!(parse_unit("").is_err());
        assert!(parse_unit("m/s/s").is_err());
    }

    #[test]
    fn radian_is_not_metre() {
        assert_ne!(
            parse_unit("mrad").unwrap().dim,
            parse_unit("mm").unwrap().dim
        );
    }

    #[test]
    fn formatting() {
        assert_eq!(fmt_num(5.0), "5");
        assert_eq!(fmt_num(1.5034), "1.503");
        assert_eq!(fmt_num(0.0), "0");
        assert_eq!(fmt_num(3.1e8), "3.1e8");
        assert_eq!(fmt_num(3e8), "3e8");
        assert_eq!(fmt_num(3.13e8), "3.13e8");
        assert_eq!(fmt_num(-2.5e-9), "-2.5e-9");
    }

    proptest::proptest! {
        /// Any finite value with any prefix parses back to value x prefix, in any micro spelling.
        #[test]
        fn prefixed_values_round_trip(v in -1e6f64..1e6, p in 0usize..6, micro in 0usize..3) {
            let (pre, scale) = [("", 1.0), ("k", 1e3), ("m", 1e-3), ("u", 1e-6), ("n", 1e-9), ("p", 1e-12)][p];
            let pre = if pre == "u" { ["u", "µ", "\u{03BC}"][micro] } else { pre };
            let (q, _) = parse_quantity(&format!("{v:e} {pre}m/s")).unwrap();
            proptest::prop_assert_eq!(q.dim, Dim::VELOCITY);
            proptest::prop_assert!((q.value - v * scale).abs() <= 1e-12 * (v * scale).abs().max(1e-300));
        }

        /// Arbitrary text never panics the parser.
        #[test]
        fn never_panics(t in "\\PC{0,12}") {
            let _ = parse_quantity(&t);
            let _ = parse_unit(&t);
        }
    }
}
