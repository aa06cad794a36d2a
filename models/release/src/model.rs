//! The two-sided in-flight release (thesis ch. 6, physics.md §3) as a [`SwitchedSystem`].
//!
//! State (12): `[q1, l1, l1', y1, y1', q2, l2, l2', y2, y2', X, X']`. Mechanism `i` sees the
//! contact force `F_c,i = -F_i` with `F_i = F(e_i)` the force of contact `i` on the TM, and
//!
//! ```text
//! M X'' = -F_1 + F_2
//! e_1 =  (X - X0) - (y_1 - y_1(0)) + e0_1
//! e_2 = -(X - X0) - (y_2 - y_2(0)) + e0_2
//! ```
//!
//! Initial state: static equilibrium at the initial voltage with the preload `F0` on both tips;
//! `e0_i < 0` the Hertz indentation of tip `i` under `F0`. Stop (physics.md §3): both contacts
//! opening (`e_i' > 0`) and beyond their release elongation (12 lambda, or 5 nm without adhesion).
//! Fallback, counted in [`ReleaseOutcome::fallback_stop`]: when a weak mechanism's stroke cannot
//! reach 12 lambda, the release also ends once `t > 2 ms` and less than 1 % of each bond's energy
//! remains (the tip has rung down by then; the TM moves nanometres per millisecond).

use crate::integrator::{IntegrateError, Integrator, MAX_SWITCHES, Stats, SwitchedSystem};
use geodesic_contact::ContactLaw;
use geodesic_mechanism::{MECH_STATES, Mechanism};

/// Number of states of the release system.
pub const RELEASE_STATES: usize = 2 * MECH_STATES + 2;
const IX: usize = 2 * MECH_STATES;
const IV: usize = IX + 1;

/// Time limit of one release [s].
pub const T_MAX_S: f64 = 0.02;
/// Earliest time of the fallback stopping rule [s].
pub const FALLBACK_AFTER_S: f64 = 2e-3;
/// Largest remaining bond-energy fraction accepted by the fallback stopping rule.
pub const FALLBACK_FRACTION: f64 = 1e-2;

/// Two mechanisms, two contacts and the TM.
#[derive(Debug, Clone)]
pub struct ReleaseModel<M: Mechanism, C: ContactLaw> {
    /// Mechanism 1 (at -X) and 2 (at +X).
    pub mechanisms: [M; 2],
    /// Contact law at tip 1 and tip 2.
    pub contacts: [C; 2],
    /// TM mass `M` [kg] (1.96 kg).
    pub tm_mass_kg: f64,
    /// Preload `F0` [N] on both tips before release.
    pub preload_n: f64,
    tip0_m: [f64; 2],
    e0_m: [f64; 2],
    open_m: [f64; 2],
    breakpoints: Vec<f64>,
}

/// Result of one release.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReleaseOutcome {
    /// Final TM velocity `X'` [m/s] (+X from mechanism 1 towards 2).
    pub v_tm_m_s: f64,
    /// Time [s] at which both bonds were broken for good.
    pub t_end_s: f64,
    /// Whether the fallback stopping rule ended the release.
    pub fallback_stop: bool,
    /// Integrator statistics.
    pub stats: Stats,
}

impl<M: Mechanism, C: ContactLaw> ReleaseModel<M, C> {
    /// Builds the model and its initial equilibrium.
    pub fn new(mechanisms: [M; 2], contacts: [C; 2], tm_mass_kg: f64, preload_n: f64) -> Self {
        let mut tip0_m = [0.0; 2];
        let mut e0_m = [0.0; 2];
        let mut open_m = [0.0; 2];
        let mut breakpoints = Vec::new();
        for i in 0..2 {
            let s0 = mechanisms[i].initial_state(preload_n);
            tip0_m[i] = mechanisms[i].tip_position_m(&s0);
            e0_m[i] = contacts[i].preload_elongation_m(preload_n);
            open_m[i] = contacts[i].open_elongation_m();
            breakpoints.extend(mechanisms[i].breakpoints_s());
        }
        breakpoints.sort_by(f64::total_cmp);
        breakpoints.dedup();
        Self {
            mechanisms,
            contacts,
            tm_mass_kg,
            preload_n,
            tip0_m,
            e0_m,
            open_m,
            breakpoints,
        }
    }

    /// Initial state (static equilibrium under the preload).
    pub fn initial_state(&self) -> [f64; RELEASE_STATES] {
        let mut y = [0.0; RELEASE_STATES];
        for i in 0..2 {
            let s = self.mechanisms[i].initial_state(self.preload_n);
            y[i * MECH_STATES..(i + 1) * MECH_STATES].copy_from_slice(&s);
        }
        y
    }

    /// Elongations `[e_1, e_2]` [m] of the two contacts in state `y`.
    #[inline]
    pub fn elongations_m(&self, y: &[f64; RELEASE_STATES]) -> [f64; 2] {
        let x = y[IX];
        [
            x - (y[3] - self.tip0_m[0]) + self.e0_m[0],
            -x - (y[MECH_STATES + 3] - self.tip0_m[1]) + self.e0_m[1],
        ]
    }

    /// Rates `[e_1', e_2']` [m/s].
    #[inline]
    fn elongation_rates(&self, y: &[f64; RELEASE_STATES]) -> [f64; 2] {
        let v = y[IV];
        [v - y[4], -v - y[MECH_STATES + 4]]
    }

    /// Contact forces on the TM `[F_1, F_2]` [N] in state `y` (positive: pulling).
    pub fn contact_forces_n(&self, y: &[f64; RELEASE_STATES]) -> [f64; 2] {
        let e = self.elongations_m(y);
        [
            self.contacts[0].force_n(e[0]),
            self.contacts[1].force_n(e[1]),
        ]
    }

    /// Simulates the release with `integrator` until both bonds are broken.
    pub fn simulate<I: Integrator>(
        &self,
        integrator: &I,
    ) -> Result<ReleaseOutcome, IntegrateError> {
        let sol = integrator.solve(self, self.initial_state(), T_MAX_S)?;
        Ok(self.outcome(sol.t, &sol.y, sol.stats))
    }

    /// The outcome of a release stopped at `(t, y)`.
    pub(crate) fn outcome(
        &self,
        t: f64,
        y: &[f64; RELEASE_STATES],
        stats: Stats,
    ) -> ReleaseOutcome {
        self.outcome_at(
            t,
            self.elongations_m(y),
            self.elongation_rates(y),
            y[IV],
            stats,
        )
    }

    /// The outcome of a release stopped at `t` with elongations `e` [m], their rates `de`
    /// [m/s] and TM velocity `v` [m/s].
    pub(crate) fn outcome_at(
        &self,
        t: f64,
        e: [f64; 2],
        de: [f64; 2],
        v: f64,
        stats: Stats,
    ) -> ReleaseOutcome {
        let primary = (0..2).all(|i| e[i] > self.open_m[i] && de[i] > 0.0);
        ReleaseOutcome {
            v_tm_m_s: v,
            t_end_s: t,
            fallback_stop: !primary,
            stats,
        }
    }

    /// The stopping rule (see the module documentation) at time `t` with elongations `e` [m]
    /// and their rates `de` [m/s].
    pub(crate) fn stop_rule(&self, t: f64, e: [f64; 2], de: [f64; 2]) -> bool {
        (0..2).all(|i| {
            (e[i] > self.open_m[i] && de[i] > 0.0)
                || (t > FALLBACK_AFTER_S
                    && self.contacts[i].remaining_bond_fraction(e[i]) < FALLBACK_FRACTION)
        })
    }

    /// Tip positions `y_i(0)` [m] before release.
    pub(crate) fn tip0(&self) -> [f64; 2] {
        self.tip0_m
    }

    /// Release elongations [m] of the stopping rule (12 lambda, or 5 nm without adhesion).
    pub(crate) fn open_m(&self) -> [f64; 2] {
        self.open_m
    }

    /// Elongations `e0_i` [m] before release (Hertz indentation under the preload).
    pub(crate) fn e0(&self) -> [f64; 2] {
        self.e0_m
    }
}

fn split(y: &[f64; RELEASE_STATES], i: usize) -> &[f64; MECH_STATES] {
    y[i * MECH_STATES..(i + 1) * MECH_STATES]
        .try_into()
        .expect("mechanism slice")
}

impl<M: Mechanism, C: ContactLaw> SwitchedSystem<RELEASE_STATES> for ReleaseModel<M, C> {
    #[inline]
    fn rhs(&self, t: f64, y: &[f64; RELEASE_STATES], dy: &mut [f64; RELEASE_STATES]) {
        let f = self.contact_forces_n(y);
        let mut ds = [0.0; MECH_STATES];
        for i in 0..2 {
            // F_c,i = -F_i
            self.mechanisms[i].derivatives(t, split(y, i), -f[i], &mut ds);
            dy[i * MECH_STATES..(i + 1) * MECH_STATES].copy_from_slice(&ds);
        }
        dy[IX] = y[IV];
        dy[IV] = (-f[0] + f[1]) / self.tm_mass_kg;
    }

    fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    #[inline]
    fn switching(&self, y: &[f64; RELEASE_STATES], g: &mut [f64; MAX_SWITCHES]) -> usize {
        let e = self.elongations_m(y);
        g[0] = e[0];
        g[1] = e[1];
        2
    }

    fn stop(&self, t: f64, y: &[f64; RELEASE_STATES], _dy: &[f64; RELEASE_STATES]) -> bool {
        self.stop_rule(t, self.elongations_m(y), self.elongation_rates(y))
    }

    fn scales(&self) -> [f64; RELEASE_STATES] {
        let mut s = [0.0; RELEASE_STATES];
        for i in 0..2 {
            s[i * MECH_STATES..(i + 1) * MECH_STATES]
                .copy_from_slice(&self.mechanisms[i].state_scales());
        }
        // TM displacement [m] and velocity [m/s]: nanometres and micrometres per second
        s[IX] = 1e-8;
        s[IV] = 1e-6;
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inputs::ReleaseInputs;
    use crate::integrator::DormandPrince;
    use geodesic_mechanism::PiezoMechanism;

    #[test]
    fn initial_state_is_a_balanced_equilibrium() {
        let mut r = ReleaseInputs::nominal();
        r.tip_radius_m = [0.0095, 0.0105];
        r.preload_n = 0.32;
        let m = r.model();
        let y0 = m.initial_state();
        let mut dy = [0.0; RELEASE_STATES];
        m.rhs(0.0, &y0, &mut dy);
        // TM balanced, tips and plungers at rest (accelerations relative to F0/m)
        assert!(dy[IV].abs() < 1e-12, "{dy:?}");
        assert!(
            dy[4].abs() < 1e-6 * 0.32 / 9e-4 && dy[9].abs() < 1e-6 * 0.32 / 9e-4,
            "{dy:?}"
        );
        let f = m.contact_forces_n(&y0);
        assert!(
            (f[0] + 0.32).abs() < 1e-12 && (f[1] + 0.32).abs() < 1e-12,
            "{f:?}"
        );
        let e = m.elongations_m(&y0);
        assert!(e[0] < e[1], "the sharper tip indents deeper: {e:?}");
    }

    /// A contact law other than Hertz + adhesion: a linear unilateral spring. The simulator runs
    /// it unchanged (the seam is the trait).
    struct LinearSpring(f64);
    impl ContactLaw for LinearSpring {
        fn force_n(&self, e_m: f64) -> f64 {
            if e_m < 0.0 { self.0 * e_m } else { 0.0 }
        }
        fn preload_elongation_m(&self, load_n: f64) -> f64 {
            -load_n / self.0
        }
        fn open_elongation_m(&self) -> f64 {
            5e-9
        }
        fn remaining_bond_fraction(&self, _e_m: f64) -> f64 {
            0.0
        }
    }

    #[test]
    fn contact_law_is_swappable() {
        let mech = PiezoMechanism::nominal();
        let sym = ReleaseModel::new(
            [mech, mech],
            [LinearSpring(4e6), LinearSpring(4e6)],
            1.96,
            0.3,
        );
        let out = sym.simulate(&DormandPrince::fast()).unwrap();
        assert!(out.v_tm_m_s.abs() < 1e-15, "{out:?}");
        // a stiffer spring on side 2 gives a different push history, hence a net velocity
        let asym = ReleaseModel::new(
            [mech, mech],
            [LinearSpring(4e6), LinearSpring(8e6)],
            1.96,
            0.3,
        );
        let out = asym.simulate(&DormandPrince::fast()).unwrap();
        assert!(out.v_tm_m_s.abs() > 1e-10 && !out.fallback_stop, "{out:?}");
    }
}
