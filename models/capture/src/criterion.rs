//! The quartic capture criterion (thesis ch. 7, eq. after "a full set of TM initial states can
//! be controlled if"; physics.md section 6):
//!
//! `sum_{i=1}^{12} (x0_i / x_LIM,i)^4 < 1`
//!
//! and the quantities derived from a limit set: the consistency constraint
//! `sum_i (1.4 req_i / x_LIM,i)^4 = 1`, the single-state limits and the largest scale of the
//! requirement box that stays capturable.

use crate::limits::Xlim;
use crate::state::{N_STATES, StateName, TmState};

/// Per-state terms `(x0_i / x_LIM,i)^4` [-], canonical order.
pub fn terms(xlim: &Xlim, state: &TmState) -> [f64; N_STATES] {
    std::array::from_fn(|i| (state.0[i] / xlim.xlim[i]).powi(4))
}

/// Quartic sum `sum_i (x0_i / x_LIM,i)^4` [-] (thesis ch. 7).
///
/// ```
/// use geodesic_capture::{quartic_sum, StateName, TmState, Xlim};
/// let x = Xlim::default_set();
/// let mut s = TmState::zero();
/// s.set(StateName::Vz, 6e-6); // half the 12 um/s single-state limit
/// assert!((quartic_sum(&x, &s) - 0.0625).abs() < 1e-12);
/// ```
pub fn quartic_sum(xlim: &Xlim, state: &TmState) -> f64 {
    terms(xlim, state).iter().sum()
}

/// Verdict of the criterion: captured when the quartic sum is strictly below 1.
pub fn is_captured(xlim: &Xlim, state: &TmState) -> bool {
    quartic_sum(xlim, state) < 1.0
}

/// One state's contribution to the quartic sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Term {
    /// The state.
    pub state: StateName,
    /// Its value [SI unit of the state].
    pub value: f64,
    /// Its limit `x_LIM` [SI unit of the state].
    pub xlim: f64,
    /// `(value / xlim)^4` [-].
    pub term: f64,
    /// `term / quartic_sum` [-] (0 when the sum is 0).
    pub share: f64,
}

/// Full evaluation of one TM state.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Quartic sum [-].
    pub quartic_sum: f64,
    /// `quartic_sum < 1`.
    pub captured: bool,
    /// All 12 terms, canonical order.
    pub terms: Vec<Term>,
    /// Non-zero terms sorted largest first (ties in canonical order).
    pub dominant: Vec<Term>,
}

/// Evaluates a state: sum, verdict, per-state terms and the dominant states.
///
/// Overflow rule: a term or sum that overflows (e.g. `vz = 1e308`) saturates at `f64::MAX`, so
/// that every reported figure stays finite; such a state is far outside the box and is
/// reported as not captured. A NaN term (NaN state) also counts as `f64::MAX`: never captured.
pub fn evaluate(xlim: &Xlim, state: &TmState) -> Evaluation {
    let mut t = terms(xlim, state);
    for v in t.iter_mut() {
        if !v.is_finite() {
            *v = f64::MAX;
        }
    }
    let sum: f64 = t.iter().fold(0.0f64, |a, b| {
        let s = a + b;
        if s.is_finite() { s } else { f64::MAX }
    });
    let terms: Vec<Term> = StateName::ALL
        .iter()
        .map(|&s| Term {
            state: s,
            value: state.get(s),
            xlim: xlim.limit(s),
            term: t[s.index()],
            share: if sum > 0.0 { t[s.index()] / sum } else { 0.0 },
        })
        .collect();
    let mut dominant: Vec<Term> = terms.iter().copied().filter(|t| t.term > 0.0).collect();
    dominant.sort_by(|a, b| b.term.total_cmp(&a.term).then(a.state.cmp(&b.state)));
    Evaluation {
        quartic_sum: sum,
        captured: sum < 1.0,
        terms,
        dominant,
    }
}

/// Consistency sum `sum_i (box_scale req_i / x_LIM,i)^4` [-]; the thesis requires it to be 1.
pub fn consistency_sum(xlim: &Xlim) -> f64 {
    (0..N_STATES)
        .map(|i| (xlim.box_scale * xlim.req[i] / xlim.xlim[i]).powi(4))
        .sum()
}

/// Consistency residual `|sum_i (box_scale req_i / x_LIM,i)^4 - 1|` [-]
/// (value of requirement CAP-XLIM-CONSISTENCY).
pub fn consistency_residual(xlim: &Xlim) -> f64 {
    (consistency_sum(xlim) - 1.0).abs()
}

/// Single-state limits: the supremum of `|x0_i|` that is captured when every other state is
/// zero. For the quartic criterion that is `x_LIM,i` itself (the sum equals 1 there, so the
/// limit is not included). [SI unit of each state]
pub fn single_state_limits(xlim: &Xlim) -> [f64; N_STATES] {
    xlim.xlim
}

/// Largest scale `s` of the requirement box (all 12 states at `s req_i`) that stays
/// capturable, as a supremum: `s = (sum_i (req_i / x_LIM,i)^4)^(-1/4)` [-]. Equals
/// `box_scale` exactly when the consistency constraint holds.
pub fn max_box_scale(xlim: &Xlim) -> f64 {
    let s: f64 = (0..N_STATES)
        .map(|i| (xlim.req[i] / xlim.xlim[i]).powi(4))
        .sum();
    s.powf(-0.25)
}

/// Corner of the requirement box scaled by `scale`: every state at `scale * req_i` [SI].
pub fn box_corner(xlim: &Xlim, scale: f64) -> TmState {
    TmState(xlim.req.map(|r| scale * r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn an_overflowing_state_is_not_captured_and_every_figure_is_finite() {
        let x = Xlim::default_set();
        let mut st = TmState::zero();
        st.set(StateName::Vz, 1e308);
        st.set(StateName::Vx, -1e308);
        let e = evaluate(&x, &st);
        assert!(!e.captured);
        assert_eq!(e.quartic_sum, f64::MAX);
        assert!(
            e.terms
                .iter()
                .all(|t| t.term.is_finite() && t.share.is_finite())
        );
    }

    #[test]
    fn default_set_is_consistent_and_scales_by_1_4() {
        let x = Xlim::default_set();
        // 7 significant digits in the YAML -> residual of order 1e-7.
        assert!(
            consistency_residual(&x) < 1e-6,
            "{}",
            consistency_residual(&x)
        );
        assert_relative_eq!(max_box_scale(&x), 1.4, max_relative = 1e-6);
    }

    #[test]
    fn requirement_corner_sum_is_1_over_1_4_to_the_4th() {
        let x = Xlim::default_set();
        let s = quartic_sum(&x, &box_corner(&x, 1.0));
        assert_relative_eq!(s, 1.0 / 1.4f64.powi(4), max_relative = 1e-6);
        assert!(is_captured(&x, &box_corner(&x, 1.0)));
        assert!(!is_captured(&x, &box_corner(&x, 1.41)));
    }

    #[test]
    fn vz_alone_single_state_limit() {
        let x = Xlim::default_set();
        let mut s = TmState::zero();
        s.set(StateName::Vz, 11.99e-6);
        assert!(is_captured(&x, &s));
        s.set(StateName::Vz, 12.0e-6);
        assert_relative_eq!(quartic_sum(&x, &s), 1.0, max_relative = 1e-12);
        assert!(!is_captured(&x, &s), "the criterion is strict");
        assert_eq!(single_state_limits(&x)[StateName::Vz.index()], 12e-6);
    }

    #[test]
    fn evaluation_orders_dominant_states() {
        let x = Xlim::default_set();
        let mut s = TmState::zero();
        s.set(StateName::Vz, -6e-6);
        s.set(StateName::X, 100e-6);
        let e = evaluate(&x, &s);
        assert_eq!(e.dominant.len(), 2);
        assert_eq!(e.dominant[0].state, StateName::Vz);
        assert_eq!(e.dominant[1].state, StateName::X);
        assert_relative_eq!(e.dominant[0].term, 0.0625, max_relative = 1e-12);
        let shares: f64 = e.terms.iter().map(|t| t.share).sum();
        assert_relative_eq!(shares, 1.0, max_relative = 1e-12);
        assert!(e.captured);
    }

    #[test]
    fn inconsistent_set_shows_in_residual_and_scale() {
        let mut x = Xlim::default_set();
        x.xlim = x.xlim.map(|v| 2.0 * v);
        assert_relative_eq!(consistency_residual(&x), 15.0 / 16.0, max_relative = 1e-5);
        assert_relative_eq!(max_box_scale(&x), 2.8, max_relative = 1e-6);
    }
}
