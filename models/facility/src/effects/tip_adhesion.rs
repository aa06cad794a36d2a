//! `tip_adhesion`: adhesion between the release tip and the TM (thesis eq. adh, physics.md s.2).

use super::{
    Effect, FitHints, ForceEffect, ForceLaw, GuessContext, ParamSpec, ReleaseCheck, Role, Scenario,
    TmState, adhesion_force, adhesion_released, adhesion_smooth,
};

/// Adds `F = A1*e*exp(-e/lambda)` for `e > 0` at the tip (pulls the TM towards the retracting
/// tip, +x); `e` is the tip elongation of `tip_contact`. Experimental bounds (thesis):
/// `A1` in [0, 1.5e5] N/m, `lambda` in [0, 8e-7] m; the fit allows a wider range.
#[derive(Debug, Clone, Copy)]
pub struct TipAdhesion;

static PARAMS: [ParamSpec; 2] = [
    ParamSpec::log("A1", "N/m", 1e5, 10.0, 1e7),
    ParamSpec::log("lambda", "m", 4e-7, 1e-9, 1e-5),
];

/// Starting grid shared by the two adhesion effects, spanning the thesis bounds.
pub(super) fn adhesion_starts() -> Vec<Vec<f64>> {
    let mut v = Vec::new();
    for a1 in [3e4, 1.2e5] {
        for l in [1e-7, 3e-7, 8e-7] {
            v.push(vec![a1, l]);
        }
    }
    v
}

impl Effect for TipAdhesion {
    fn name(&self) -> &'static str {
        "tip_adhesion"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn summary(&self) -> &'static str {
        "tip adhesion: F = A1*e*exp(-e/lambda) for e > 0 (thesis eq. adh, physics.md s.2)"
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

impl ForceEffect for TipAdhesion {
    fn law(&self, p: &[f64]) -> Option<ForceLaw> {
        Some(ForceLaw::TipAdhesion {
            a1: p[0],
            lambda: p[1],
        })
    }
    fn force(&self, p: &[f64], s: &TmState, _ds: &mut [f64]) -> f64 {
        adhesion_force(p[0], p[1], s.e_tip)
    }
    fn released(&self, p: &[f64], s: &TmState, r: &ReleaseCheck) -> bool {
        // the elongation grows at least at the present rate (tip speed never decreases)
        adhesion_released(p[0], p[1], s.e_tip, r.tip_speed_m_s - s.v, r)
    }
    fn smooth(&self, p: &[f64], s: &TmState, r: &ReleaseCheck, h_tail: f64) -> bool {
        adhesion_smooth(p[0], p[1], s.e_tip, r.tip_speed_m_s - s.v, h_tail, r.m_kg)
    }
}

impl FitHints for TipAdhesion {
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
    fn pulls_towards_the_tip() {
        let s = TmState {
            t: 0.0,
            x: 0.0,
            v: 0.0,
            y: 0.0,
            e_tip: 6e-7,
            needle_gap: 1e-6,
            f_pre: 6e-3,
            needle_body: false,
            m_kg: 0.089,
            own: &[],
        };
        let f = TipAdhesion.force(&[1.3e5, 6e-7], &s, &mut []);
        assert!((f - 1.3e5 * 6e-7 / std::f64::consts::E).abs() < 1e-12);
    }
}
