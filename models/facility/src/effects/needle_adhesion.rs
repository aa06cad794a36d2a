//! `needle_adhesion`: adhesion between the blocking needles and the TM (physics.md section 4).

use super::tip_adhesion::adhesion_starts;
use super::{
    Effect, FitHints, ForceEffect, ForceLaw, GuessContext, ParamSpec, ReleaseCheck, Role, Scenario,
    TmState, adhesion_force, adhesion_released, adhesion_smooth,
};

/// The adhesion law of thesis eq. (adh) at the needles: for `x > x_n0` it pulls the TM back
/// towards the needles (-x) with `A1*e*exp(-e/lambda)`, `e = x - x_n0` (thesis: negligible).
#[derive(Debug, Clone, Copy)]
pub struct NeedleAdhesion;

static PARAMS: [ParamSpec; 2] = [
    ParamSpec::log("A1", "N/m", 1e5, 10.0, 1e7),
    ParamSpec::log("lambda", "m", 4e-7, 1e-9, 1e-5),
];

impl Effect for NeedleAdhesion {
    fn name(&self) -> &'static str {
        "needle_adhesion"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn summary(&self) -> &'static str {
        "needle adhesion: F = -A1*e*exp(-e/lambda), e = x - x_n0 > 0 (physics.md s.4)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        &PARAMS
    }
    fn role(&self) -> Role<'_> {
        Role::Force(self)
    }
    fn hints(&self) -> &dyn FitHints {
        self
    }
}

impl ForceEffect for NeedleAdhesion {
    fn law(&self, p: &[f64]) -> Option<ForceLaw> {
        Some(ForceLaw::NeedleAdhesion {
            a1: p[0],
            lambda: p[1],
        })
    }
    fn force(&self, p: &[f64], s: &TmState, _ds: &mut [f64]) -> f64 {
        -adhesion_force(p[0], p[1], s.needle_gap)
    }
    fn released(&self, p: &[f64], s: &TmState, r: &ReleaseCheck) -> bool {
        // in free flight the gap grows at the TM's velocity
        adhesion_released(p[0], p[1], s.needle_gap, s.v, r)
    }
    fn smooth(&self, p: &[f64], s: &TmState, r: &ReleaseCheck, h_tail: f64) -> bool {
        adhesion_smooth(p[0], p[1], s.needle_gap, s.v, h_tail, r.m_kg)
    }
}

impl FitHints for NeedleAdhesion {
    fn null_params(&self) -> Option<Vec<f64>> {
        Some(vec![PARAMS[0].lower, PARAMS[1].lower])
    }
    fn starts(&self, _g: &GuessContext) -> Vec<Vec<f64>> {
        adhesion_starts()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pulls_back_towards_the_needles() {
        let s = TmState {
            t: 0.0,
            x: 0.0,
            v: 0.0,
            y: 0.0,
            e_tip: 0.0,
            needle_gap: 3e-7,
            f_pre: 6e-3,
            needle_body: false,
            m_kg: 0.089,
            own: &[],
        };
        assert!(NeedleAdhesion.force(&[1e5, 3e-7], &s, &mut []) < 0.0);
    }
}
