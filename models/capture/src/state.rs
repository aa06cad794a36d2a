//! The 12-state TM state right after release (thesis ch. 7, Tab. "TM state requirement";
//! physics.md section 6): offsets, linear velocities, angles and angular rates along/around
//! x, y and z. This module names the states, holds a state vector and reads one from YAML.
//!
//! The state names are the contract shared by the YAML files, the `geodesic capture` flags and
//! the JSON output: `x y z` [m], `vx vy vz` [m/s], `thx thy thz` [rad], `wx wy wz` [rad/s].

use std::collections::HashMap;
use std::fmt;

use serde_saphyr::Spanned;

use crate::error::CaptureError;

/// Number of TM states the capture criterion sums over (thesis ch. 7).
pub const N_STATES: usize = 12;

/// One of the 12 TM states, in the canonical order used by every array in this crate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum StateName {
    /// Offset along x [m].
    X,
    /// Offset along y [m].
    Y,
    /// Offset along z (the GPRM release axis) [m].
    Z,
    /// Linear velocity along x [m/s].
    Vx,
    /// Linear velocity along y [m/s].
    Vy,
    /// Linear velocity along z [m/s].
    Vz,
    /// Angle around x [rad].
    Thx,
    /// Angle around y [rad].
    Thy,
    /// Angle around z [rad].
    Thz,
    /// Angular rate around x [rad/s].
    Wx,
    /// Angular rate around y [rad/s].
    Wy,
    /// Angular rate around z [rad/s].
    Wz,
}

impl StateName {
    /// All states in canonical order (index = position in a [`TmState`]).
    pub const ALL: [StateName; N_STATES] = [
        StateName::X,
        StateName::Y,
        StateName::Z,
        StateName::Vx,
        StateName::Vy,
        StateName::Vz,
        StateName::Thx,
        StateName::Thy,
        StateName::Thz,
        StateName::Wx,
        StateName::Wy,
        StateName::Wz,
    ];

    /// Short name used in YAML, CLI flags and JSON (`x`, `vz`, `thx`, `wz`, ...).
    pub const fn as_str(self) -> &'static str {
        match self {
            StateName::X => "x",
            StateName::Y => "y",
            StateName::Z => "z",
            StateName::Vx => "vx",
            StateName::Vy => "vy",
            StateName::Vz => "vz",
            StateName::Thx => "thx",
            StateName::Thy => "thy",
            StateName::Thz => "thz",
            StateName::Wx => "wx",
            StateName::Wy => "wy",
            StateName::Wz => "wz",
        }
    }

    /// SI unit of the state (`m`, `m/s`, `rad`, `rad/s`).
    pub const fn unit(self) -> &'static str {
        match self {
            StateName::X | StateName::Y | StateName::Z => "m",
            StateName::Vx | StateName::Vy | StateName::Vz => "m/s",
            StateName::Thx | StateName::Thy | StateName::Thz => "rad",
            StateName::Wx | StateName::Wy | StateName::Wz => "rad/s",
        }
    }

    /// Requirement ID of the TM state bound on this state (`TMS-X-POS`, `TMS-Z-VEL`, ...).
    pub const fn requirement_id(self) -> &'static str {
        match self {
            StateName::X => "TMS-X-POS",
            StateName::Y => "TMS-Y-POS",
            StateName::Z => "TMS-Z-POS",
            StateName::Vx => "TMS-X-VEL",
            StateName::Vy => "TMS-Y-VEL",
            StateName::Vz => "TMS-Z-VEL",
            StateName::Thx => "TMS-X-ANG",
            StateName::Thy => "TMS-Y-ANG",
            StateName::Thz => "TMS-Z-ANG",
            StateName::Wx => "TMS-X-RATE",
            StateName::Wy => "TMS-Y-RATE",
            StateName::Wz => "TMS-Z-RATE",
        }
    }

    /// Index of the state in canonical order.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Parses a short name (`"vz"`); `None` when it is not one of the 12.
    pub fn parse(name: &str) -> Option<StateName> {
        StateName::ALL.into_iter().find(|s| s.as_str() == name)
    }

    /// The 12 names joined by spaces, for error messages.
    pub fn list() -> String {
        StateName::ALL.map(StateName::as_str).join(" ")
    }
}

impl fmt::Display for StateName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A TM state: 12 values in SI units in [`StateName::ALL`] order.
///
/// ```
/// use geodesic_capture::{StateName, TmState};
/// let mut s = TmState::zero();
/// s.set(StateName::Vz, -3e-6);
/// assert_eq!(s.get(StateName::Vz), -3e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TmState(pub [f64; N_STATES]);

impl TmState {
    /// All 12 states zero (TM centred and at rest).
    pub const fn zero() -> Self {
        TmState([0.0; N_STATES])
    }

    /// Value of one state [SI unit of that state].
    pub fn get(&self, s: StateName) -> f64 {
        self.0[s.index()]
    }

    /// Sets one state [SI unit of that state].
    pub fn set(&mut self, s: StateName, value: f64) {
        self.0[s.index()] = value;
    }

    /// Reads a state from YAML text: a mapping from state name to value in SI units, e.g.
    /// `vz: -3.0e-6`. Unset states are 0. `file` labels error messages.
    ///
    /// Errors name file and line: YAML syntax, an unknown state name, a non-numeric or
    /// non-finite value.
    pub fn from_yaml_str(text: &str, file: &str) -> Result<TmState, CaptureError> {
        let map = parse_named_map::<f64>(text, file)?;
        let mut state = TmState::zero();
        for (name, value, line) in map {
            if !value.is_finite() {
                return Err(CaptureError::BadValue {
                    file: file.to_owned(),
                    line,
                    name: name.to_string(),
                    value: value.to_string(),
                    cause: "state value must be finite".into(),
                });
            }
            state.set(name, value);
        }
        Ok(state)
    }

    /// Reads a state from a YAML file (see [`TmState::from_yaml_str`]).
    pub fn load(path: &std::path::Path) -> Result<TmState, CaptureError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| CaptureError::Io {
            file: file.clone(),
            cause: e.to_string(),
        })?;
        TmState::from_yaml_str(&text, &file)
    }
}

/// Parses a YAML mapping keyed by state names into `(state, value, line)` triples, rejecting
/// unknown names with their line. Duplicate keys are a YAML error (serde-saphyr default).
pub(crate) fn parse_named_map<T>(
    text: &str,
    file: &str,
) -> Result<Vec<(StateName, T, u64)>, CaptureError>
where
    T: for<'de> serde::Deserialize<'de>,
{
    // An empty document (or only comments) is an empty mapping.
    if text.lines().all(|l| {
        let t = l.trim();
        t.is_empty() || t.starts_with('#') || t == "---"
    }) {
        return Ok(Vec::new());
    }
    let raw: NamedMap<T> =
        serde_saphyr::from_str(text).map_err(|e| CaptureError::yaml(file, &e))?;
    named_entries(raw, file)
}

/// A YAML mapping from state name to a value, with the locations of keys and values.
pub(crate) type NamedMap<T> = HashMap<Spanned<String>, Spanned<T>>;

/// Resolves the keys of a [`NamedMap`] to states, sorted in canonical order; an unknown key
/// is an error naming its line.
pub(crate) fn named_entries<T>(
    raw: NamedMap<T>,
    file: &str,
) -> Result<Vec<(StateName, T, u64)>, CaptureError> {
    let mut out = Vec::with_capacity(raw.len());
    for (k, v) in raw {
        let line = k.referenced.line();
        let name = StateName::parse(&k.value).ok_or_else(|| CaptureError::UnknownState {
            file: file.to_owned(),
            line,
            name: k.value.clone(),
        })?;
        out.push((name, v.value, line));
    }
    out.sort_by_key(|(n, _, _)| *n);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_in_order() {
        for (i, s) in StateName::ALL.iter().enumerate() {
            assert_eq!(s.index(), i);
            assert_eq!(StateName::parse(s.as_str()), Some(*s));
        }
        assert_eq!(StateName::parse("vq"), None);
    }

    #[test]
    fn reads_state_yaml() {
        let s = TmState::from_yaml_str("vz: -3.0e-6\nx: 1.0e-5\n", "s.yaml").unwrap();
        assert_eq!(s.get(StateName::Vz), -3e-6);
        assert_eq!(s.get(StateName::X), 1e-5);
        assert_eq!(s.get(StateName::Y), 0.0);
    }

    #[test]
    fn empty_state_yaml_is_zero() {
        let s = TmState::from_yaml_str("# nothing\n", "s.yaml").unwrap();
        assert_eq!(s, TmState::zero());
    }

    #[test]
    fn unknown_state_names_file_and_line() {
        let e = TmState::from_yaml_str("vz: 1.0e-6\nvq: 2.0\n", "s.yaml").unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("s.yaml:2:"), "{msg}");
        assert!(msg.contains("vq"), "{msg}");
    }

    #[test]
    fn non_numeric_value_names_file_and_line() {
        let e = TmState::from_yaml_str("x: 0.0\nvz: fast\n", "s.yaml").unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("s.yaml:2"), "{msg}");
    }

    #[test]
    fn duplicate_key_is_an_error() {
        let e = TmState::from_yaml_str("vz: 1.0\nvz: 2.0\n", "s.yaml").unwrap_err();
        assert!(e.to_string().starts_with("s.yaml:"), "{e}");
    }

    #[test]
    fn non_finite_value_is_an_error() {
        let e = TmState::from_yaml_str("vz: .nan\n", "s.yaml").unwrap_err();
        assert!(e.to_string().starts_with("s.yaml:1:"), "{e}");
    }
}
