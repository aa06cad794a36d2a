//! `tip_contact`: the compressive branch of the release-tip contact (physics.md section 4).

use super::{
    Effect, FitHints, ForceEffect, ForceLaw, GuessContext, ParamSpec, ReleaseCheck, Role, Scenario,
    TmState,
};

/// Linear compressive contact `F = k_c*e` for `e <= 0`, 0 for `e > 0`, with
/// `e = (y - x) - F_pre/k_c`, so `F = -F_pre` before release (physics.md section 4).
///
/// Bounds: `k_c` in [2e5, 1e8] N/m. ASSUMPTION: the Hertz stiffness `2*Es*a` of the 10 mm tip
/// (physics.md section 2, Es = 59 GPa) is 7e5 N/m at 2 mN preload and 4e6 N/m at 300 mN; the
/// bounds leave a factor 3 below and 25 above. Override with `--bound`.
#[derive(Debug, Clone, Copy)]
pub struct TipContact;

static PARAMS: [ParamSpec; 1] = [ParamSpec::log("k_c", "N/m", 1e6, 2e5, 1e8)];

impl Effect for TipContact {
    fn name(&self) -> &'static str {
        "tip_contact"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn summary(&self) -> &'static str {
        "tip contact: F = k_c*e for e <= 0, e = (y - x) - F_pre/k_c (physics.md s.4)"
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

impl ForceEffect for TipContact {
    fn law(&self, p: &[f64]) -> Option<ForceLaw> {
        Some(ForceLaw::TipSpring { k: p[0] })
    }
    fn force(&self, p: &[f64], s: &TmState, _ds: &mut [f64]) -> f64 {
        if s.e_tip <= 0.0 { p[0] * s.e_tip } else { 0.0 }
    }
    fn released(&self, _p: &[f64], s: &TmState, r: &ReleaseCheck) -> bool {
        // out of contact and the tip moving away at least as fast as the TM
        s.e_tip > 0.0 && r.tip_speed_m_s >= s.v
    }
}

impl FitHints for TipContact {
    fn starts(&self, _g: &GuessContext) -> Vec<Vec<f64>> {
        vec![vec![4e5], vec![1e6], vec![3e6]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compressive_only() {
        let s = TmState {
            t: 0.0,
            x: 0.0,
            v: 0.0,
            y: 0.0,
            e_tip: -6e-9,
            needle_gap: 0.0,
            f_pre: 6e-3,
            needle_body: false,
            m_kg: 0.089,
            own: &[],
        };
        assert!((TipContact.force(&[1e6], &s, &mut []) + 6e-3).abs() < 1e-12);
        let s2 = TmState { e_tip: 1e-9, ..s };
        assert_eq!(TipContact.force(&[1e6], &s2, &mut []), 0.0);
    }
}
