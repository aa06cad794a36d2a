//! A TM that the needle adhesion traps for good in a TMMF release (physics.md section 4): the
//! verdict ([`NeedleWell::trapped`]: its energy under the adhesion's escape energy, the tip out
//! of its reach) and the periodic continuation of its oscillation ([`Orbit`]), which the TMMF
//! integration ([`crate::tmmf`]) uses instead of integrating such a TM to the end of a long
//! record.

use crate::effects::Role;
use crate::model::Model;

/// Relative margin under the escape energy of the needle well within which a TM is not
/// treated as trapped ([`NeedleWell::trapped`]): a TM at the very edge of escape, where the
/// RK4 solution's small energy error could decide whether it leaves, keeps the full
/// integration.
pub const TRAP_MARGIN: f64 = 1e-3;

/// The needle well of a model whose forces are the fixed needles' contact and adhesion and the
/// tip's contact and adhesion (`needle_contact` + `needle_adhesion` [+ `tip_contact`]
/// [+ `tip_adhesion`], no other force and no internal state): what decides whether a TM that
/// the needle adhesion pulled back is trapped for good.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NeedleWell {
    /// Needle stiffness [N/m].
    k_nd: f64,
    /// Needle adhesion `A1` [N/m] and `lambda` [m].
    a1: f64,
    lambda: f64,
    /// Needle position at rest `x_n0` [m].
    x_n0: f64,
    /// Whether the model has the tip's contact.
    tip_contact: bool,
    /// `F_pre / k_c` [m] of the tip contact's elongation (0 without it).
    tip_offset: f64,
    /// Tip adhesion `A1` [N/m] and `lambda` [m], if the model has it.
    tip_adhesion: Option<(f64, f64)>,
    /// TM mass [kg].
    m: f64,
}

/// What the tip is doing when a trap is tested: its position [m], its speed [m/s] (which never
/// decreases after the trigger) and the time left to the end of the record [s].
#[derive(Debug, Clone, Copy)]
pub(crate) struct TipNow {
    pub(crate) y: f64,
    pub(crate) speed: f64,
    pub(crate) horizon: f64,
    /// The release tolerance [m] ([`crate::tmmf::RELEASE_TOL_M`]).
    pub(crate) tol_m: f64,
}

impl NeedleWell {
    /// The well of `model` at `p`, if the model is one.
    pub(crate) fn of(model: &Model, p: &[f64], m: f64) -> Option<NeedleWell> {
        let mut names: Vec<&str> = Vec::new();
        for e in &model.effects {
            match e.role() {
                Role::Force(f) => {
                    if f.n_states() != 0 {
                        return None;
                    }
                    names.push(e.name());
                }
                Role::Distortion(_) | Role::TimeShift(_) => {}
                Role::Mechanism(_) => return None,
            }
        }
        let allowed = [
            "needle_contact",
            "needle_adhesion",
            "tip_contact",
            "tip_adhesion",
        ];
        if !names.contains(&"needle_contact")
            || !names.contains(&"needle_adhesion")
            || names.iter().any(|n| !allowed.contains(n))
        {
            return None;
        }
        let k_nd = model.get(p, "needle_contact.k_nd")?;
        let f_pre = model.get(p, "needle_contact.F_pre")?;
        Some(NeedleWell {
            k_nd,
            a1: model.get(p, "needle_adhesion.A1")?,
            lambda: model.get(p, "needle_adhesion.lambda")?,
            x_n0: f_pre / k_nd,
            tip_contact: names.contains(&"tip_contact"),
            tip_offset: model.get(p, "tip_contact.k_c").map_or(0.0, |k| f_pre / k),
            tip_adhesion: model
                .get(p, "tip_adhesion.A1")
                .zip(model.get(p, "tip_adhesion.lambda")),
            m,
        })
    }

    /// Potential energy [J] of the needle forces at the gap `g = x - x_n0` [m]: the compressed
    /// needle spring `k_nd g^2 / 2` for `g < 0`, the adhesion's
    /// `int_0^g A1 s exp(-s/lambda) ds = A1 lambda^2 (1 - (1 + g/lambda) exp(-g/lambda))` for
    /// `g > 0` (the adhesion law of [`crate::effects::adhesion_force`]).
    fn potential(&self, g: f64) -> f64 {
        if g < 0.0 {
            0.5 * self.k_nd * g * g
        } else {
            let u = g / self.lambda;
            self.a1 * self.lambda * self.lambda * (1.0 - (1.0 + u) * (-u).exp())
        }
    }

    /// The harmonic estimate of the period [s]: half a period on the needle spring and half on
    /// the adhesion's curvature at the needles (`A1`); the adhesion softens away from them, so
    /// the true period is longer.
    pub(crate) fn period_estimate(&self) -> f64 {
        std::f64::consts::PI * ((self.m / self.k_nd).sqrt() + (self.m / self.a1).sqrt())
    }

    /// Whether a TM at `x` [m] moving at `v` [m/s] is trapped for good: its energy is under the
    /// adhesion's escape energy `A1 lambda^2` (by [`TRAP_MARGIN`]), and the tip has let go of
    /// it for good. The farthest point the TM can reach (bounded above) is `x_far`, and the tip
    /// only recedes, so the tip's elongation stays at least `e_far = y - x_far - F_pre/k_c`,
    /// growing at the tip's speed: the contact is open for good once `e_far > 0`, and the tip
    /// adhesion's remaining impulse is bounded as in its own release test
    /// ([`crate::effects::adhesion_tail_impulse`], 1e-15 m of displacement by the end of the
    /// record). Nothing else acts on it then: the motion is an oscillation in the well, periodic.
    pub(crate) fn trapped(&self, x: f64, v: f64, tip: TipNow) -> bool {
        // not while the tip touches it (the cheap test first: it is made at every sample)
        let clear = !self.tip_contact || (tip.y - x) - self.tip_offset > 0.0;
        if !clear {
            return false;
        }
        let barrier = self.a1 * self.lambda * self.lambda;
        let e = 0.5 * self.m * v * v + self.potential(x - self.x_n0);
        let bound = e < barrier * (1.0 - TRAP_MARGIN);
        if !bound {
            return false;
        }
        if !self.tip_contact && self.tip_adhesion.is_none() {
            return true;
        }
        // the farthest gap it can reach, bounded above: with u = g/lambda, (1 + u) exp(-u) <=
        // 2 exp(-u/2) for u >= 0, so the potential at u = 2 ln(2/q), q = 1 - e/barrier, is at
        // least e
        let q = 1.0 - e / barrier;
        let g_far = 2.0 * self.lambda * (2.0 / q).ln();
        let e_far = (tip.y - (self.x_n0 + g_far)) - self.tip_offset;
        let out_of_reach = e_far > 0.0;
        if !out_of_reach {
            return false;
        }
        match self.tip_adhesion {
            None => true,
            Some((a1, lambda)) => {
                let impulse = crate::effects::adhesion_tail_impulse(a1, lambda, e_far, tip.speed);
                impulse / self.m * tip.horizon < tip.tol_m
            }
        }
    }
}

/// The trapped TM's period is integrated at this fraction of the RK4 step. The error of that
/// one period is repeated coherently over the record (integrating throughout makes a different
/// error each period, at the steps' varying positions against the needle contact's kink): at a
/// quarter of the step the period was 1.3e-6 too long and the continuation drifted by as much
/// as integrating throughout errs; at a sixteenth it is within 1e-8 of the converged period;
/// at an eighth (about 1e-7, fourth order) the continuation is as close as at a sixteenth
/// (6.6e-10 m against 6.7e-10 m from integrating throughout over 1 s) for half the cost.
pub const ORBIT_REFINE: f64 = 8.0;

/// A trapped TM is continued periodically only when the rest of the record lasts this many
/// estimated periods: finding the period costs up to 16 periods' worth of full RK4 steps (two
/// periods at an eighth of the step), which on a short record is as much as integrating it.
pub const ORBIT_RECORD_PERIODS: f64 = 128.0;

/// One period of a trapped TM's oscillation ([`NeedleWell::trapped`]), integrated with RK4 at
/// the step `h` from `t0`, and the readings after it by periodicity.
pub(crate) struct Orbit {
    t0: f64,
    h: f64,
    x: Vec<f64>,
    v: Vec<f64>,
    /// The first time the velocity turns from negative to non-negative (the TM at its deepest
    /// in the needles) [s], and the period between two such times [s].
    t_c: f64,
    period: f64,
}

impl Orbit {
    /// Integrates from `(t0, s0)` until the velocity has turned upwards twice, for at most
    /// `max_steps` steps and not past `t_end`; `None` if it has not turned twice by then (or
    /// the state stopped being finite).
    pub(crate) fn find<F: Fn(f64, &[f64], &mut [f64])>(
        deriv: &F,
        t0: f64,
        s0: &[f64],
        h: f64,
        t_end: f64,
        max_steps: usize,
    ) -> Option<Orbit> {
        let mut s = s0.to_vec();
        let mut ws = crate::rk4::Rk4Work::new(s.len());
        let (mut x, mut v) = (vec![s[0]], vec![s[1]]);
        let mut turns = Vec::new();
        let max_steps = max_steps.min(((t_end - t0) / h).ceil().max(0.0) as usize);
        for k in 0..max_steps {
            let t = t0 + k as f64 * h;
            crate::rk4::rk4_step(deriv, t, h, &mut s, &mut ws);
            if !s.iter().all(|q| q.is_finite()) {
                return None;
            }
            x.push(s[0]);
            v.push(s[1]);
            let (va, vb) = (v[k], v[k + 1]);
            if va < 0.0 && vb >= 0.0 {
                turns.push(t + h * (-va) / (vb - va));
                if turns.len() == 2 {
                    return Some(Orbit {
                        t0,
                        h,
                        x,
                        v,
                        t_c: turns[0],
                        period: turns[1] - turns[0],
                    });
                }
            }
        }
        None
    }

    /// TM position [m] at `t >= t0`: the stored steps before the first turn, the period after,
    /// cubic Hermite interpolation between steps (position and velocity at both ends).
    pub(crate) fn x_at(&self, t: f64) -> f64 {
        let tau = if t < self.t_c {
            t
        } else {
            self.t_c + (t - self.t_c).rem_euclid(self.period)
        };
        let last = self.x.len() - 2;
        let k = (((tau - self.t0) / self.h).floor().max(0.0) as usize).min(last);
        let th = ((tau - self.t0) / self.h - k as f64).clamp(0.0, 1.0);
        let (t2, t3) = (th * th, th * th * th);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + th;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        h00 * self.x[k]
            + h10 * self.h * self.v[k]
            + h01 * self.x[k + 1]
            + h11 * self.h * self.v[k + 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A release tolerance [m]: the TMMF model's value (`tmmf::RELEASE_TOL_M`; that module
    /// uses this one, so it is not imported here). The verdict test derives its thresholds
    /// from it, whatever it is.
    const RELEASE_TOL_M: f64 = 1e-15;

    /// The trap verdict moves with each of its inputs: the energy across the escape energy's
    /// margin, the tip in and out of the farthest reach, the tip adhesion's remaining impulse
    /// across the release tolerance as the record lengthens.
    #[test]
    fn the_trap_verdict_follows_energy_reach_and_tip_adhesion() {
        let (m, a1, lambda) = (0.089, 3e4, 3e-7);
        let mut w = NeedleWell {
            k_nd: 8.95e6,
            a1,
            lambda,
            x_n0: 0.389 / 8.95e6,
            tip_contact: false,
            tip_offset: 0.0,
            tip_adhesion: None,
            m,
        };
        // at the needles' rest point the energy is kinetic only
        let e_max = a1 * lambda * lambda * (1.0 - TRAP_MARGIN);
        let v_of = |e: f64| (2.0 * e / m).sqrt();
        let far_tip = TipNow {
            y: 1e-3,
            speed: 3e-3,
            horizon: 1.0,
            tol_m: RELEASE_TOL_M,
        };
        assert!(w.trapped(w.x_n0, v_of(e_max * (1.0 - 1e-9)), far_tip));
        assert!(!w.trapped(w.x_n0, v_of(e_max * (1.0 + 1e-9)), far_tip));
        // the tip's contact: the farthest reach bound for half the escape energy is
        // 2 lambda ln(2 / q), q = 1 - 0.5 (1 - margin)
        w.tip_contact = true;
        w.tip_offset = 0.389 / 3.87e5;
        let v = v_of(0.5 * e_max);
        let q = 1.0 - 0.5 * (1.0 - TRAP_MARGIN);
        let reach = w.x_n0 + 2.0 * lambda * (2.0 / q).ln() + w.tip_offset;
        let tip_at = |y: f64| TipNow { y, ..far_tip };
        assert!(w.trapped(w.x_n0, v, tip_at(reach * (1.0 + 1e-9))));
        assert!(!w.trapped(w.x_n0, v, tip_at(reach * (1.0 - 1e-9))));
        // the tip adhesion: its remaining impulse from that reach, over the horizon, against
        // the 1e-15 m release tolerance
        w.tip_adhesion = Some((1e4, 1e-7));
        let y = reach + 20.0 * 1e-7;
        let imp = crate::effects::adhesion_tail_impulse(1e4, 1e-7, y - reach, 3e-3);
        let horizon_at_tol = RELEASE_TOL_M * m / imp;
        let tip = |horizon: f64| TipNow {
            y,
            speed: 3e-3,
            horizon,
            tol_m: RELEASE_TOL_M,
        };
        assert!(w.trapped(w.x_n0, v, tip(horizon_at_tol * 0.99)));
        assert!(!w.trapped(w.x_n0, v, tip(horizon_at_tol * 1.01)));
    }
}
