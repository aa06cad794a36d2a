//! The capture limits `x_LIM,i` tied to a requirement box `req_i` (thesis ch. 7, "DFACS
//! worst-case initial conditions"; physics.md section 6), and the derivation of the default
//! limits. The limits are read from the capture inputs file (the `inputs` module); the box from
//! the loaded requirements.
//!
//! The thesis does not print `x_LIM`; it gives (a) the z velocity alone is captured up to
//! 12 um/s, (b) the requirement box scales by 1.4 and (c) the consistency constraint
//! `sum_i (1.4 req_i / x_LIM,i)^4 = 1`. [`derive_xlim`] builds the default set from these:
//! `x_LIM,vz = 12 um/s` and every other `x_LIM,i = c req_i` with `c` solving (c) exactly. The
//! inputs file `models/capture/capture.yaml` holds the result; a unit test re-derives it.

use crate::state::{N_STATES, StateName, TmState};

/// Requirement box of the thesis (Tab. "TM state requirement", ch. 2) [SI]: for this crate's
/// examples and tests only. `geodesic verify` and `geodesic capture` read the box from the loaded
/// requirement set (rows TMS-*), never from this constant.
pub const THESIS_BOX: [f64; N_STATES] = [
    200e-6, 200e-6, 200e-6, 5e-6, 5e-6, 5e-6, 2e-3, 2e-3, 2e-3, 100e-6, 100e-6, 100e-6,
];

/// Capture limits and the requirement box they are tied to.
#[derive(Clone, Debug, PartialEq)]
pub struct Xlim {
    /// Requirement box `req_i` (thesis Tab. "TM state requirement") [SI unit of each state].
    pub req: [f64; N_STATES],
    /// Capture limits `x_LIM,i` of the quartic criterion [SI unit of each state].
    pub xlim: [f64; N_STATES],
    /// Box scale factor of the consistency constraint (thesis: 1.4) [-].
    pub box_scale: f64,
    /// Where the values came from (file path or the embedded-default label).
    pub source: String,
}

impl Xlim {
    /// Requirement box as a state (each state at `+req_i`).
    pub fn requirement_state(&self) -> TmState {
        TmState(self.req)
    }

    /// Capture limit of one state [SI unit of the state].
    pub fn limit(&self, s: StateName) -> f64 {
        self.xlim[s.index()]
    }

    /// Requirement bound of one state [SI unit of the state].
    pub fn requirement(&self, s: StateName) -> f64 {
        self.req[s.index()]
    }
}

/// Error of [`derive_xlim`]: the anchor limit leaves no room for the other 11 states.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "anchor {anchor} = {limit} cannot satisfy the constraint: (box_scale*req/xlim)^4 = {ratio4} must be < 1"
)]
pub struct DeriveError {
    /// Anchored state.
    pub anchor: StateName,
    /// Anchor limit [SI].
    pub limit: f64,
    /// `(box_scale req_anchor / limit)^4` [-].
    pub ratio4: f64,
}

/// Derives a limit set satisfying the consistency constraint exactly (thesis ch. 7):
///
/// `x_LIM,anchor = anchor_limit`, and `x_LIM,i = c req_i` for the other 11 states with
/// `sum_i (box_scale req_i / x_LIM,i)^4 = 1`, that is
/// `c = box_scale * (11 / (1 - (box_scale req_anchor / anchor_limit)^4))^(1/4)`.
///
/// Default inputs: anchor `vz`, `anchor_limit = 12e-6` m/s (thesis: "the control system is able
/// to control the TM even if its after-release velocity along z is equal to 12 um/s"),
/// `box_scale = 1.4`.
///
/// ```
/// use geodesic_capture::{derive_xlim, StateName, Xlim};
/// let req = Xlim::default_set().req;
/// let x = derive_xlim(&req, 1.4, StateName::Vz, 12e-6).unwrap();
/// assert_eq!(x[StateName::Vz.index()], 12e-6);
/// let s: f64 = (0..12).map(|i| (1.4 * req[i] / x[i]).powi(4)).sum();
/// assert!((s - 1.0).abs() < 1e-12);
/// ```
pub fn derive_xlim(
    req: &[f64; N_STATES],
    box_scale: f64,
    anchor: StateName,
    anchor_limit: f64,
) -> Result<[f64; N_STATES], DeriveError> {
    let ratio4 = (box_scale * req[anchor.index()] / anchor_limit).powi(4);
    if ratio4.is_nan() || ratio4 >= 1.0 {
        return Err(DeriveError {
            anchor,
            limit: anchor_limit,
            ratio4,
        });
    }
    let others = (N_STATES - 1) as f64;
    let c = box_scale * (others / (1.0 - ratio4)).powf(0.25);
    let mut out = req.map(|r| c * r);
    out[anchor.index()] = anchor_limit;
    Ok(out)
}

/// The factor `c = x_LIM,i / req_i` of the non-anchored states in [`derive_xlim`] [-].
pub fn derived_factor(req_anchor: f64, box_scale: f64, anchor_limit: f64) -> f64 {
    let ratio4 = (box_scale * req_anchor / anchor_limit).powi(4);
    box_scale * (((N_STATES - 1) as f64) / (1.0 - ratio4)).powf(0.25)
}

#[cfg(test)]
mod tests {
    use super::*;

    const REQ: [f64; N_STATES] = THESIS_BOX;

    #[test]
    fn embedded_default_loads_with_thesis_requirement_box() {
        let x = Xlim::default_set();
        for (s, (got, want)) in StateName::ALL.iter().zip(x.req.iter().zip(REQ)) {
            assert_eq!(*got, want, "req of {s}");
        }
        assert_eq!(x.box_scale, 1.4);
    }

    #[test]
    fn embedded_default_is_the_documented_derivation() {
        // The YAML stores the derived values to 7 significant digits.
        let x = Xlim::default_set();
        let d = derive_xlim(&x.req, 1.4, StateName::Vz, 12e-6).unwrap();
        for (s, (got, want)) in StateName::ALL.iter().zip(x.xlim.iter().zip(d)) {
            let rel = (got - want).abs() / want;
            assert!(rel < 1e-6, "{s}: {got} vs {want}");
        }
    }

    #[test]
    fn derived_factor_value() {
        // c = 1.4 * (11 / (1 - (7/12)^4))^(1/4) = 2.62929...
        let c = derived_factor(5e-6, 1.4, 12e-6);
        assert!((c - 2.629_29).abs() < 1e-5, "{c}");
    }

    #[test]
    fn derive_rejects_an_anchor_that_fills_the_budget() {
        let e = derive_xlim(&REQ, 1.4, StateName::Vz, 7e-6).unwrap_err();
        assert_eq!(e.anchor, StateName::Vz);
    }
}
