//! Exact derivatives of the TMMF readings with respect to the model's parameters (forward
//! sensitivities), for the fit's Levenberg-Marquardt Jacobian.
//!
//! The readings are integrated by fixed-step RK4 ([`super::simulate`]); their derivative with
//! respect to a parameter `q` is the derivative of that discrete map, which RK4 applied to the
//! system augmented with the tangent `(X, V) = d(x, v)/dq` gives exactly:
//!
//! `X' = V`, `V' = (dF/de (-X + de/dq) + dF/dg (X + dg/dq) + dF/dq) / m`,
//!
//! with the elongation `e = (y - x) - F_pre/k_c` and the needle gap `g = x - F_pre/k_nd` (the
//! forces of the laws depend on `x` through them only, not on `v`). The TM starts at rest in
//! equilibrium for every parameter value: the tangents start at zero. Once every force has let
//! go ([`super::Run::released`], decided on the state as in [`super::simulate`]) the TM flies
//! freely, `x = x_b + v_b (t - t_b)`, and so do the tangents.
//!
//! Why by hand rather than finite differences: a difference column costs one integration each
//! (five per Levenberg-Marquardt iteration of a release fit, plus the search for their steps),
//! while the tangents ride along one integration, sharing its `exp` and divisions. The readings
//! of the integration carrying them are the bits of [`super::simulate`] (the same arithmetic in
//! the same order; tested), so the Jacobian is that of the residuals the fit minimises.
//!
//! Covered: models whose forces are all inline laws on the TM's two states (needle and tip
//! springs, tip and needle adhesion), without distortions and without a needle well (whose
//! trapped TM is continued periodically). Other models return `None` and keep finite
//! differences.

use super::{Run, step_for_mass};
use crate::effects::{EffectKind, ForceLaw};
use crate::model::{Inputs, Model};

/// Most parameters whose derivatives one integration carries.
pub const MAX_TANGENTS: usize = 8;

/// What a parameter is to the right-hand side: which partial derivative of the force it
/// selects (index into the partials of [`Aug::rhs`]); 0 for none.
const NONE: usize = 0;
const NEEDLE_K: usize = 1;
const TIP_K: usize = 2;
const TIP_A1: usize = 3;
const TIP_LAMBDA: usize = 4;
const NEEDLE_A1: usize = 5;
const NEEDLE_LAMBDA: usize = 6;
const ROLES: usize = 7;

/// Whether [`simulate_with_tangents`] covers `model` (with `n_dirs` directions).
pub fn covers(model: &Model, n_dirs: usize) -> bool {
    if n_dirs > MAX_TANGENTS || model.scenario != crate::effects::Scenario::TmmfRelease {
        return false;
    }
    let mut has_adhesion_well = false;
    for e in &model.effects {
        match e.kind() {
            EffectKind::Force => {
                if e.n_states() != 0 {
                    return false;
                }
                let nominal: Vec<f64> = e.params().iter().map(|s| s.nominal).collect();
                match e.law(&nominal) {
                    Some(
                        ForceLaw::NeedleSpring { .. }
                        | ForceLaw::TipSpring { .. }
                        | ForceLaw::TipAdhesion { .. },
                    ) => {}
                    Some(ForceLaw::NeedleAdhesion { .. }) => has_adhesion_well = true,
                    _ => return false,
                }
            }
            EffectKind::Distortion | EffectKind::Mechanism => return false,
        }
    }
    // a needle adhesion may trap the TM, whose record is then continued periodically
    !has_adhesion_well
}

/// The readings [m] at `times` [s] (the bits of [`super::simulate`]) and, for each parameter
/// index of `dirs`, their derivatives with respect to `p[dirs[j]]` [m per parameter unit];
/// `None` when [`covers`] does not hold.
pub fn simulate_with_tangents(
    model: &Model,
    p: &[f64],
    dirs: &[usize],
    times: &[f64],
    inputs: &Inputs,
) -> Option<(Vec<f64>, Vec<Vec<f64>>)> {
    if !covers(model, dirs.len()) {
        return None;
    }
    let h_max = step_for_mass(inputs.m_kg);
    let mut run = Run::new(model, p, times, inputs, h_max, true, true);
    let laws = run.laws.clone()?;
    if run.s.len() != 2 || !run.distortions.is_empty() || run.well.is_some() {
        return None;
    }
    let aug = Aug::new(model, p, dirs, &run, laws);
    let mut tan: Vec<Vec<f64>> = vec![Vec::with_capacity(times.len()); dirs.len()];
    // as many tangent lanes as directions (the arithmetic of unused lanes is not free)
    match dirs.len() {
        0 => aug.integrate::<0>(&mut run, times, h_max, &mut tan),
        1 => aug.integrate::<1>(&mut run, times, h_max, &mut tan),
        2 => aug.integrate::<2>(&mut run, times, h_max, &mut tan),
        3 => aug.integrate::<3>(&mut run, times, h_max, &mut tan),
        4 => aug.integrate::<4>(&mut run, times, h_max, &mut tan),
        5 => aug.integrate::<5>(&mut run, times, h_max, &mut tan),
        6 => aug.integrate::<6>(&mut run, times, h_max, &mut tan),
        7 => aug.integrate::<7>(&mut run, times, h_max, &mut tan),
        _ => aug.integrate::<MAX_TANGENTS>(&mut run, times, h_max, &mut tan),
    }
    Some((run.out, tan))
}

/// The augmented right-hand side: the laws with their parameters, and per direction its role
/// and the derivatives of the elongation and the gap with respect to it.
struct Aug {
    laws: Vec<ForceLaw>,
    role: [usize; MAX_TANGENTS],
    de: [f64; MAX_TANGENTS],
    dg: [f64; MAX_TANGENTS],
    inv_m: f64,
}

impl Aug {
    fn new(model: &Model, p: &[f64], dirs: &[usize], run: &Run, laws: Vec<ForceLaw>) -> Aug {
        let mut role = [NONE; MAX_TANGENTS];
        let mut de = [0.0; MAX_TANGENTS];
        let mut dg = [0.0; MAX_TANGENTS];
        let f_pre = run.sh.f_pre;
        let idx = |name: &str| model.index(name);
        let (i_fpre, i_knd, i_kc) = (
            idx("needle_contact.F_pre"),
            idx("needle_contact.k_nd"),
            idx("tip_contact.k_c"),
        );
        let k_nd = i_knd.map(|i| p[i]);
        let names = model.param_names();
        for (j, &q) in dirs.iter().enumerate() {
            role[j] = match names[q].as_str() {
                "needle_contact.k_nd" => NEEDLE_K,
                "tip_contact.k_c" => TIP_K,
                "tip_adhesion.A1" => TIP_A1,
                "tip_adhesion.lambda" => TIP_LAMBDA,
                "needle_adhesion.A1" => NEEDLE_A1,
                "needle_adhesion.lambda" => NEEDLE_LAMBDA,
                _ => NONE,
            };
            // e = (y - x) - F_pre / k_c, g = x - F_pre / k_nd
            if Some(q) == i_fpre {
                de[j] = -run.sh.inv_kc;
                dg[j] = k_nd.map_or(0.0, |k| -1.0 / k);
            }
            if Some(q) == i_kc {
                de[j] = f_pre * run.sh.inv_kc * run.sh.inv_kc;
            }
            if Some(q) == i_knd
                && let Some(k) = k_nd
            {
                dg[j] = f_pre / (k * k);
            }
        }
        Aug {
            laws,
            role,
            de,
            dg,
            inv_m: 1.0 / run.inputs.m_kg,
        }
    }

    /// The readings (into `run.out`) and their tangents (into `tan`, one per direction; `P` of
    /// them) at `times`, integrated as [`super::simulate`] integrates them.
    fn integrate<const P: usize>(
        &self,
        run: &mut Run,
        times: &[f64],
        h_max: f64,
        tan: &mut [Vec<f64>],
    ) {
        let mut s = [0.0f64; 2];
        let mut ts = [[0.0f64; P]; 2];
        let mut t = 0.0;
        for (i, &ti) in times.iter().enumerate() {
            if ti > t {
                let steps = ((ti - t) / h_max - 1e-9).ceil().max(1.0) as usize;
                let h = (ti - t) / steps as f64;
                self.steps(run, t, h, steps, &mut s, &mut ts);
                t = ti;
            }
            let x_true = if ti < 0.0 { 0.0 } else { s[0] };
            run.out.push(x_true);
            for (j, tj) in tan.iter_mut().enumerate() {
                tj.push(if ti < 0.0 { 0.0 } else { ts[0][j] });
            }
            let finite = s.iter().all(|v| v.is_finite());
            if ti > 0.0 && finite && run.released(ti, &s) {
                let (tb, xb, vb) = (ti, s[0], s[1]);
                run.out
                    .extend(times[i + 1..].iter().map(|&tk| xb + vb * (tk - tb)));
                for (j, tj) in tan.iter_mut().enumerate() {
                    let (xj, vj) = (ts[0][j], ts[1][j]);
                    tj.extend(times[i + 1..].iter().map(|&tk| xj + vj * (tk - tb)));
                }
                return;
            }
        }
    }

    /// The state's derivative (the bits of `Run::deriv_n`) and the tangents' derivatives at
    /// `t`.
    #[inline(always)]
    fn rhs<const P: usize>(
        &self,
        run: &Run,
        t: f64,
        s: [f64; 2],
        ts: &[[f64; P]; 2],
    ) -> ([f64; 2], [[f64; P]; 2]) {
        let (x, v) = (s[0], s[1]);
        let e = (run.tip_y(t) - x) - run.tip_offset;
        let g = x - run.sh.x_n0;
        let body = run.sh.body;
        let mut f = 0.0;
        // dF/de, dF/dg and the partials of the force by role
        let (mut fe, mut fg) = (0.0, 0.0);
        let mut part = [0.0f64; ROLES];
        for law in &self.laws {
            match *law {
                ForceLaw::NeedleSpring { k } => {
                    if body || g >= 0.0 {
                        f += 0.0;
                    } else {
                        f += -k * g;
                        fg -= k;
                        part[NEEDLE_K] = -g;
                    }
                }
                ForceLaw::TipSpring { k } => {
                    if e <= 0.0 {
                        f += k * e;
                        fe += k;
                        part[TIP_K] = e;
                    } else {
                        f += 0.0;
                    }
                }
                ForceLaw::TipAdhesion { a1, lambda } => {
                    if e > 0.0 {
                        let ex = (-e / lambda).exp();
                        let force = a1 * e * ex;
                        f += force;
                        let r = e / lambda;
                        fe += a1 * ex * (1.0 - r);
                        part[TIP_A1] = e * ex;
                        part[TIP_LAMBDA] = force * r / lambda;
                    } else {
                        f += 0.0;
                    }
                }
                ForceLaw::NeedleAdhesion { a1, lambda } => {
                    if g > 0.0 {
                        let ex = (-g / lambda).exp();
                        let force = a1 * g * ex;
                        f += -force;
                        let r = g / lambda;
                        fg -= a1 * ex * (1.0 - r);
                        part[NEEDLE_A1] = -g * ex;
                        part[NEEDLE_LAMBDA] = -force * r / lambda;
                    } else {
                        f += -0.0;
                    }
                }
                ForceLaw::NeedleBody { .. } => unreachable!("excluded by covers"),
            }
        }
        let ds = [v, f / run.inputs.m_kg];
        let mut dts = [[0.0f64; P]; 2];
        for j in 0..P {
            let xj = ts[0][j];
            let df = fe * (self.de[j] - xj) + fg * (xj + self.dg[j]) + part[self.role[j]];
            dts[0][j] = ts[1][j];
            dts[1][j] = df * self.inv_m;
        }
        (ds, dts)
    }

    /// `steps` RK4 steps of `h` from `t` of the state `s` and its tangents `ts`: the state's
    /// arithmetic is that of `super::lockstep` (the same bits).
    fn steps<const P: usize>(
        &self,
        run: &Run,
        t: f64,
        h: f64,
        steps: usize,
        s: &mut [f64; 2],
        ts: &mut [[f64; P]; 2],
    ) {
        let mut t = t;
        for _ in 0..steps {
            let (k1, l1) = self.rhs(run, t, *s, ts);
            let mut tmp = [0.0; 2];
            let mut tt = [[0.0; P]; 2];
            for i in 0..2 {
                tmp[i] = s[i] + 0.5 * h * k1[i];
                for j in 0..P {
                    tt[i][j] = ts[i][j] + 0.5 * h * l1[i][j];
                }
            }
            let (k2, l2) = self.rhs(run, t + 0.5 * h, tmp, &tt);
            for i in 0..2 {
                tmp[i] = s[i] + 0.5 * h * k2[i];
                for j in 0..P {
                    tt[i][j] = ts[i][j] + 0.5 * h * l2[i][j];
                }
            }
            let (k3, l3) = self.rhs(run, t + 0.5 * h, tmp, &tt);
            for i in 0..2 {
                tmp[i] = s[i] + h * k3[i];
                for j in 0..P {
                    tt[i][j] = ts[i][j] + h * l3[i][j];
                }
            }
            let (k4, l4) = self.rhs(run, t + h, tmp, &tt);
            for i in 0..2 {
                s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                for j in 0..P {
                    ts[i][j] += h / 6.0 * (l1[i][j] + 2.0 * l2[i][j] + 2.0 * l3[i][j] + l4[i][j]);
                }
            }
            t += h;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::Scenario;
    use crate::profile::TipProfile;

    fn inputs(m: f64) -> Inputs {
        Inputs {
            m_kg: m,
            profile: TipProfile {
                jerk_m_s3: 6000.0,
                v_m_s: 3e-3,
            },
            e0_v: 120.0,
        }
    }

    /// The readings that carry the tangents are the bits of `simulate`, and each tangent is
    /// the derivative of those readings: it agrees with central differences of `simulate`
    /// (relative step 1e-6) to 1e-5 of the column's largest value, for every parameter of the
    /// covered models, for a light and a heavy TM, over the contact phase and the free flight.
    #[test]
    fn tangents_are_the_derivatives_of_the_readings() {
        let times: Vec<f64> = (-50..800).map(|i| i as f64 * 1e-5).collect();
        for (effects, p) in [
            (
                &["needle_contact", "tip_contact", "tip_adhesion"][..],
                &[6.5e5, 6e-3, 1.1e6, 1.3e5, 6e-7][..],
            ),
            (
                &["needle_contact", "tip_contact"][..],
                &[6.5e5, 6e-3, 1.1e6][..],
            ),
        ] {
            let model = Model::new(Scenario::TmmfRelease, effects).unwrap();
            assert!(model.has_tangents(p.len()));
            for m in [0.0096, 0.089, 0.844] {
                let inp = inputs(m);
                let dirs: Vec<usize> = (0..p.len()).collect();
                let (x, tan) = simulate_with_tangents(&model, p, &dirs, &times, &inp).unwrap();
                let plain = super::super::simulate(&model, p, &times, &inp);
                assert_eq!(
                    x.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    plain.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
                );
                for (q, col) in tan.iter().enumerate() {
                    let h = p[q] * 1e-6;
                    let at = |d: f64| {
                        let mut pq = p.to_vec();
                        pq[q] += d;
                        super::super::simulate(&model, &pq, &times, &inp)
                    };
                    let (up, down) = (at(h), at(-h));
                    let fd: Vec<f64> = up
                        .iter()
                        .zip(&down)
                        .map(|(a, b)| (a - b) / (2.0 * h))
                        .collect();
                    let scale = fd.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                    assert!(
                        scale > 0.0,
                        "{effects:?} m {m}: parameter {q} moves nothing"
                    );
                    let err = col
                        .iter()
                        .zip(&fd)
                        .fold(0.0f64, |a, (c, f)| a.max((c - f).abs()));
                    assert!(
                        err < 1e-5 * scale,
                        "{effects:?} m {m}: parameter {q}: {err:e} of {scale:e}"
                    );
                }
            }
        }
    }

    /// Models outside the tangents' reach say so: a needle well (periodic continuation), a
    /// needle body (own states), a distortion, more than [`MAX_TANGENTS`] directions.
    #[test]
    fn other_models_keep_finite_differences() {
        for effects in [
            &["needle_contact", "tip_contact", "needle_adhesion"][..],
            &["needle_contact", "tip_contact", "needle_mass"][..],
            &["needle_contact", "tip_contact", "drift"][..],
            &["needle_contact", "tip_contact", "interferometer_cyclic"][..],
        ] {
            let model = Model::new(Scenario::TmmfRelease, effects).unwrap();
            assert!(!model.has_tangents(1), "{effects:?}");
            let p = model.nominal();
            assert!(
                model
                    .predict_with_tangents(&p, &[0], &[0.0, 1e-5], &inputs(0.089))
                    .is_none()
            );
        }
        let model = Model::new(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]).unwrap();
        assert!(model.has_tangents(MAX_TANGENTS) && !model.has_tangents(MAX_TANGENTS + 1));
    }
}
