//! `needle_contact`: the fixed blocking needles of the TMMF (physics.md section 4).

use super::{
    Effect, FitHints, ForceEffect, ForceLaw, GuessContext, ParamSpec, ReleaseCheck, Role, Scenario,
    TmState,
};

/// Unilateral needle spring `F = k_nd*(x_n0 - x)` while `x < x_n0`, else 0, with
/// `x_n0 = F_pre/k_nd`, so the needles push with `F_pre` before release (catapult effect,
/// `I = F_pre*sqrt(m/k_nd)`, `dt = (pi/2)*sqrt(m/k_nd)`, thesis ch. 5 table of catapult
/// contributions). With `needle_mass` present it contributes only `F_pre`.
///
/// Bounds: `k_nd` in [3e5, 1e8] N/m. The thesis gives 5e5-8e5 N/m (stiff blades) and 1.12e6 N/m
/// (high-load campaign); ASSUMPTION: the lower bound keeps out the soft-needle fits that mimic
/// adhesion from `x` alone (examples README pitfall). Override with `--bound`.
#[derive(Debug, Clone, Copy)]
pub struct NeedleContact;

static PARAMS: [ParamSpec; 2] = [
    ParamSpec::log("k_nd", "N/m", 6.5e5, 3e5, 1e8),
    ParamSpec::log("F_pre", "N", 7e-3, 1e-5, 5.0),
];

impl Effect for NeedleContact {
    fn name(&self) -> &'static str {
        "needle_contact"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn summary(&self) -> &'static str {
        "fixed needles: F = k_nd*(F_pre/k_nd - x) while touching (physics.md s.4)"
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

impl ForceEffect for NeedleContact {
    fn law(&self, p: &[f64]) -> Option<ForceLaw> {
        Some(ForceLaw::NeedleSpring { k: p[0] })
    }
    fn force(&self, p: &[f64], s: &TmState, _ds: &mut [f64]) -> f64 {
        if s.needle_body || s.needle_gap >= 0.0 {
            0.0
        } else {
            -p[0] * s.needle_gap
        }
    }
    /// A grid over the thesis range of needle stiffness and over preloads from 2 mN to 300 mN
    /// (stiff blades to high load), plus the stiffness from the catapult duration
    /// `dt = (pi/2) sqrt(m/k_nd)` measured on the data.
    fn released(&self, _p: &[f64], s: &TmState, _r: &ReleaseCheck) -> bool {
        // replaced by a needle body, or apart with the TM moving away
        s.needle_body || (s.needle_gap > 0.0 && s.v >= 0.0)
    }
}

impl FitHints for NeedleContact {
    fn starts(&self, g: &GuessContext) -> Vec<Vec<f64>> {
        let mut ks = vec![3e5, 6.5e5, 1.5e6, 4e6];
        if g.catapult_s > 0.0 && g.m_kg > 0.0 {
            let k = g.m_kg * (std::f64::consts::FRAC_PI_2 / g.catapult_s).powi(2);
            ks.push(k.clamp(PARAMS[0].lower, PARAMS[0].upper));
        }
        let mut out = Vec::new();
        for k in ks {
            for f in [2e-3, 6e-3, 2e-2, 0.1, 0.3] {
                out.push(vec![k, f]);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pushes_only_while_touching() {
        let s = TmState {
            t: 0.0,
            x: 0.0,
            v: 0.0,
            y: 0.0,
            e_tip: 0.0,
            needle_gap: -1e-8,
            f_pre: 6.5e-3,
            needle_body: false,
            m_kg: 0.089,
            own: &[],
        };
        let f = NeedleContact.force(&[6.5e5, 6.5e-3], &s, &mut []);
        assert!((f - 6.5e-3).abs() < 1e-12);
        let s2 = TmState {
            needle_gap: 1e-9,
            ..s
        };
        assert_eq!(NeedleContact.force(&[6.5e5, 6.5e-3], &s2, &mut []), 0.0);
    }
}
