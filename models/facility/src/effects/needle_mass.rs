//! `needle_mass`: the needles as a body with mass (physics.md section 4, examples README).

use super::{
    Effect, FitHints, ForceEffect, ForceLaw, GuessContext, LawState, ParamSpec, ReleaseCheck, Role,
    Scenario, TmState,
};

/// The needles are a body of mass `m_nd` on a spring `k_nd` and damper `c_nd` to ground,
/// preloaded to push with `F_pre` at rest; the TM touches it through the unilateral
/// spring-damper `k_tm, c_tm` with initial compression `F_pre/k_tm` (thesis Tab. "Parameters of
/// the TMmu supporting system": k_tm 2.03e6 N/m, k_nd 1.12e6 N/m, m_nd 1.74 kg). Replaces the
/// fixed needle spring: `needle_contact` then contributes only `F_pre`.
///
/// States: body displacement `u` [m] (0 at rest) and velocity `u'` [m/s]. Contact compression
/// `delta = F_pre/k_tm + u - x`; contact force on the TM `max(0, k_tm*delta + c_tm*(u' - x'))`
/// while `delta > 0`; body `m_nd*u'' = F_pre - k_nd*u - c_nd*u' - F_contact`.
#[derive(Debug, Clone, Copy)]
pub struct NeedleMass;

static PARAMS: [ParamSpec; 5] = [
    ParamSpec::log("m_nd", "kg", 1.74, 1e-4, 100.0),
    ParamSpec::log("k_nd", "N/m", 1.12e6, 1e5, 1e9),
    ParamSpec::log("k_tm", "N/m", 2.03e6, 3e5, 1e9),
    ParamSpec::log("c_nd", "N s/m", 1.0, 1e-4, 1e5),
    ParamSpec::log("c_tm", "N s/m", 1.0, 1e-4, 1e5),
];

impl Effect for NeedleMass {
    fn name(&self) -> &'static str {
        "needle_mass"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn summary(&self) -> &'static str {
        "needle body m_nd on k_nd,c_nd, touching the TM through k_tm,c_tm (physics.md s.4)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        &PARAMS
    }
    fn supersedes(&self) -> &'static [&'static str] {
        &["needle_contact.k_nd"]
    }
    fn role(&self) -> Role<'_> {
        Role::Force(self)
    }
    fn hints(&self) -> &dyn FitHints {
        self
    }
}

impl ForceEffect for NeedleMass {
    fn n_states(&self) -> usize {
        2
    }
    fn law(&self, p: &[f64]) -> Option<ForceLaw> {
        Some(ForceLaw::NeedleBody {
            m_nd: p[0],
            k_nd: p[1],
            k_tm: p[2],
            c_nd: p[3],
            c_tm: p[4],
        })
    }
    fn force(&self, p: &[f64], s: &TmState, ds: &mut [f64]) -> f64 {
        // the law is the one place the body's dynamics are written
        let law = self.law(p).expect("needle_mass has a law");
        let mut d = [0.0; 2];
        let fc = law.force(&LawState::of(s), &mut d);
        ds.copy_from_slice(&d);
        fc
    }
    fn released(&self, p: &[f64], s: &TmState, _r: &ReleaseCheck) -> bool {
        // Out of contact, the body oscillates about u_eq = F_pre/k_nd with an energy that damping
        // only lowers: u never exceeds u_eq + A, A = sqrt((u - u_eq)^2 + m_nd du^2/k_nd). With
        // the TM moving away (v >= 0) the contact overlap F_pre/k_tm + u - x stays negative
        // once it is negative for u = u_eq + A.
        let (m_nd, k_nd, k_tm) = (p[0], p[1], p[2]);
        let (u, du) = (s.own[0], s.own[1]);
        let u_eq = s.f_pre / k_nd;
        let amp = ((u - u_eq).powi(2) + m_nd * du * du / k_nd).sqrt();
        s.v >= 0.0 && s.f_pre / k_tm + u_eq + amp - s.x < 0.0
    }
    fn own_states_slow(&self, p: &[f64], h_tail: f64) -> bool {
        // out of contact the body is an oscillator of its own (k_nd, c_nd on m_nd): a quarter
        // radian of it per tail step, and a quarter of its damping time, as the adhesions ask
        // of their wells (`adhesion_smooth`)
        let (m_nd, k_nd, c_nd) = (p[0], p[1], p[3]);
        h_tail * h_tail * k_nd <= 0.0625 * m_nd && h_tail * c_nd <= 0.25 * m_nd
    }
}

impl FitHints for NeedleMass {
    /// Body masses from 0.1 to 3 times the TM's, with spring pairs whose series stiffness is
    /// the rigid-needle stiffness fitted by the baseline (when known), and the thesis pair.
    fn starts(&self, g: &GuessContext) -> Vec<Vec<f64>> {
        let m = if g.m_kg > 0.0 { g.m_kg } else { 0.089 };
        let mut pairs = vec![(1.12e6, 2.03e6)];
        if g.k_needle_n_m > 0.0 {
            let k = g.k_needle_n_m;
            pairs.push((2.0 * k, 2.0 * k));
            pairs.push((1.25 * k, 5.0 * k));
        }
        let mut v = Vec::new();
        for f in [0.1, 0.3, 1.0, 3.0] {
            for &(knd, ktm) in &pairs {
                let clamp = |x: f64, i: usize| x.clamp(PARAMS[i].lower, PARAMS[i].upper);
                v.push(vec![
                    clamp(f * m, 0),
                    clamp(knd, 1),
                    clamp(ktm, 2),
                    1.0,
                    1.0,
                ]);
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_rest_the_body_is_in_equilibrium_and_pushes_with_the_preload() {
        let p = [1.74, 1.12e6, 2.03e6, 1.0, 1.0];
        let s = TmState {
            t: 0.0,
            x: 0.0,
            v: 0.0,
            y: 0.0,
            e_tip: 0.0,
            needle_gap: 0.0,
            f_pre: 0.3,
            needle_body: true,
            m_kg: 0.089,
            own: &[0.0, 0.0],
        };
        let mut ds = [9.0, 9.0];
        let f = NeedleMass.force(&p, &s, &mut ds);
        assert!((f - 0.3).abs() < 1e-12);
        assert!(ds[1].abs() < 1e-9);
    }
}
