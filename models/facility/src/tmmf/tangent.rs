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
//! springs, tip and needle adhesion) and whose distortions offer their gradient
//! ([`crate::effects::DistortionEffect::distortion_gradient`]: the reading `x + d(t, x)` has the tangent
//! `X (1 + dd/dx) + dd/dp`), and a needle body (`needle_mass`: its displacement `u` and
//! velocity `u'` join the state, their tangents `(U, U')` the augmented system, and the contact
//! force `F_c = k_tm (F_pre/k_tm + u - x) + c_tm (u' - v)`, while it pushes, depends on `v` as
//! well). Not covered (`None`, the fit takes finite differences): a TM trapped in the needle
//! well on a record long enough for [`super::simulate`]'s periodic continuation.
//!
//! Where the RK4 map is not differentiable the tangents are its derivative between the steps
//! where it is not: a TM grazing a contact (the time in contact grows as the square root of
//! the overlap) and a TM touching the needle body again (the damped contact force jumps by
//! `c_tm (u' - v)`). A fit's Levenberg-Marquardt steps take them as they take differences
//! there. Handing such evaluations over to differences instead was tried (2026-11-28): a
//! Jacobian that changes kind between iterations left the `needle_mass` candidate of a
//! 400 000-sample `diagnose` at chi2_red 1.092, against 1.0075 with the tangents throughout
//! and 1.0072 with differences throughout.

use super::{Run, step_for_mass};
use crate::effects::{ForceLaw, Role, exp_or_zero};
use crate::model::{Inputs, Model};
use rayon::prelude::*;

use super::TAIL_CHUNK;

/// Most parameters whose derivatives one integration carries.
pub const MAX_TANGENTS: usize = 12;

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

/// Whether [`simulate_with_tangents`] covers `model` (with `n_dirs` directions): a
/// `tmmf-release` model whose forces are springs and adhesions on the TM's two states, or a
/// needle body with its own two, and whose distortions offer their gradient.
pub fn covers(model: &Model, n_dirs: usize) -> bool {
    if n_dirs > MAX_TANGENTS || model.scenario.dynamics() != crate::scenario::Dynamics::TmRelease {
        return false;
    }
    model.effects.iter().all(|e| {
        let nominal: Vec<f64> = e.params().iter().map(|s| s.nominal).collect();
        match e.role() {
            Role::Force(f) => match f.law(&nominal) {
                Some(
                    ForceLaw::NeedleSpring { .. }
                    | ForceLaw::TipSpring { .. }
                    | ForceLaw::TipAdhesion { .. }
                    | ForceLaw::NeedleAdhesion { .. },
                ) => f.n_states() == 0,
                // its two own states beside the TM's (one needle body per model)
                Some(ForceLaw::NeedleBody { .. }) => f.n_states() == 2,
                _ => false,
            },
            Role::Distortion(d) => {
                let mut d_p = vec![0.0; nominal.len()];
                d.distortion_gradient(&nominal, 0.0, 0.0, &mut d_p)
                    .is_some()
            }
            Role::TimeShift(_) | Role::Mechanism(_) => false,
        }
    })
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
    carry(model, p, dirs, times, inputs, true)
}

/// The tangents of [`simulate_with_tangents`] alone (the same bits), without the readings of
/// the free-flight tail: a fit's Jacobian needs no readings, and on a long record with
/// distortions they were a third of the trigonometry of each iteration (the readings up to the
/// release are still made: the integration decides on them). `None` when [`covers`] does not
/// hold.
pub fn tangents_only(
    model: &Model,
    p: &[f64],
    dirs: &[usize],
    times: &[f64],
    inputs: &Inputs,
) -> Option<Vec<Vec<f64>>> {
    carry(model, p, dirs, times, inputs, false).map(|(_, tan)| tan)
}

/// [`simulate_with_tangents`]; without the tail's readings unless `readings`.
fn carry(
    model: &Model,
    p: &[f64],
    dirs: &[usize],
    times: &[f64],
    inputs: &Inputs,
    readings: bool,
) -> Option<(Vec<f64>, Vec<Vec<f64>>)> {
    if !covers(model, dirs.len()) {
        return None;
    }
    let h_max = step_for_mass(inputs.m_kg);
    let mut run = Run::new(model, p, times, inputs, h_max, true, true);
    let laws = run.laws.clone()?;
    let aug = Aug::new(model, p, dirs, &run, laws);
    let mut tan: Vec<Vec<f64>> = vec![Vec::with_capacity(times.len()); dirs.len()];
    let done = match run.s.len() {
        2 => aug.dispatch::<2>(&mut run, times, &mut tan, readings, dirs.len()),
        4 => aug.dispatch::<4>(&mut run, times, &mut tan, readings, dirs.len()),
        _ => return None,
    };
    if !done {
        return None;
    }
    Some((run.out, tan))
}

/// The augmented right-hand side: the laws with their parameters, and per direction its role
/// and the derivatives of the elongation and the gap with respect to it.
struct Aug {
    laws: Vec<ForceLaw>,
    /// Per direction, the distortion (index in `Run::distortions`) and the parameter within it
    /// that it is, if any.
    dist_dir: [Option<(usize, usize)>; MAX_TANGENTS],
    role: [usize; MAX_TANGENTS],
    de: [f64; MAX_TANGENTS],
    dg: [f64; MAX_TANGENTS],
    /// Per direction, 1 when it is the preload `F_pre` (which the needle body's law reads
    /// itself), else 0.
    d_fpre: [f64; MAX_TANGENTS],
    /// Per direction, which needle-body parameter it is ([`BODY_M`] ...), if any.
    body_role: [usize; MAX_TANGENTS],
    inv_m: f64,
}

/// The needle body's parameters as directions ([`Aug::body_role`]).
const BODY_M: usize = 1;
const BODY_KND: usize = 2;
const BODY_KTM: usize = 3;
const BODY_CND: usize = 4;
const BODY_CTM: usize = 5;

impl Aug {
    fn new(model: &Model, p: &[f64], dirs: &[usize], run: &Run, laws: Vec<ForceLaw>) -> Aug {
        let mut role = [NONE; MAX_TANGENTS];
        let mut de = [0.0; MAX_TANGENTS];
        let mut dg = [0.0; MAX_TANGENTS];
        let f_pre = run.sh.f_pre;
        let idx = |name: &str| model.index(name);
        // the needle stiffness of the gap's rest point: the body's contact with it, else the
        // fixed needles' (`Run::new`)
        let (i_fpre, i_knd, i_kc) = (
            idx("needle_contact.F_pre"),
            if run.sh.body {
                idx("needle_mass.k_tm")
            } else {
                idx("needle_contact.k_nd")
            },
            idx("tip_contact.k_c"),
        );
        let k_nd = i_knd.map(|i| p[i]);
        let mut d_fpre = [0.0; MAX_TANGENTS];
        let mut body_role = [0; MAX_TANGENTS];
        let names = model.param_names();
        // the distortions' parameter ranges, in the order of `Run::distortions`
        let ranges: Vec<std::ops::Range<usize>> = (0..model.effects.len())
            .filter(|&i| matches!(model.effects[i].role(), Role::Distortion(_)))
            .map(|i| model.range(i))
            .collect();
        let mut dist_dir = [None; MAX_TANGENTS];
        for (j, &q) in dirs.iter().enumerate() {
            dist_dir[j] = ranges
                .iter()
                .position(|r| r.contains(&q))
                .map(|d| (d, q - ranges[d].start));
        }
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
            body_role[j] = match names[q].as_str() {
                "needle_mass.m_nd" => BODY_M,
                "needle_mass.k_nd" => BODY_KND,
                "needle_mass.k_tm" => BODY_KTM,
                "needle_mass.c_nd" => BODY_CND,
                "needle_mass.c_tm" => BODY_CTM,
                _ => 0,
            };
            if Some(q) == i_fpre {
                d_fpre[j] = 1.0;
            }
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
            dist_dir,
            role,
            de,
            dg,
            d_fpre,
            body_role,
            inv_m: 1.0 / run.inputs.m_kg,
        }
    }

    /// [`Aug::integrate`] for a state of `N` components with as many tangent lanes as the
    /// `n_dirs` directions up to eight (the arithmetic of unused lanes is not free), twelve
    /// beyond.
    fn dispatch<const N: usize>(
        &self,
        run: &mut Run,
        times: &[f64],
        tan: &mut [Vec<f64>],
        readings: bool,
        n_dirs: usize,
    ) -> bool {
        match n_dirs {
            0 => self.integrate::<N, 0>(run, times, tan, readings),
            1 => self.integrate::<N, 1>(run, times, tan, readings),
            2 => self.integrate::<N, 2>(run, times, tan, readings),
            3 => self.integrate::<N, 3>(run, times, tan, readings),
            4 => self.integrate::<N, 4>(run, times, tan, readings),
            5 => self.integrate::<N, 5>(run, times, tan, readings),
            6 => self.integrate::<N, 6>(run, times, tan, readings),
            7 => self.integrate::<N, 7>(run, times, tan, readings),
            8 => self.integrate::<N, 8>(run, times, tan, readings),
            _ => self.integrate::<N, MAX_TANGENTS>(run, times, tan, readings),
        }
    }

    /// The readings (into `run.out`; those of the free-flight tail only when `readings`) and
    /// their tangents (into `tan`, one per direction; `P` of them) at `times`, integrated as
    /// [`super::simulate`] integrates them; false when the TM
    /// ends trapped in the needle well and [`super::simulate`] would continue the record
    /// periodically (not covered: the caller takes differences).
    fn integrate<const N: usize, const P: usize>(
        &self,
        run: &mut Run,
        times: &[f64],
        tan: &mut [Vec<f64>],
        readings: bool,
    ) -> bool {
        // the state starts where `simulate`'s does (at rest), the tangents at zero
        let mut s = [0.0f64; N];
        s.copy_from_slice(&run.s);
        let mut ts = [[0.0f64; P]; N];
        let mut t = 0.0;
        let mut grad = Grad::new(run);
        for (i, &ti) in times.iter().enumerate() {
            if ti > t {
                let steps = ((ti - t) / run.h_next() - 1e-9).ceil().max(1.0) as usize;
                let h = (ti - t) / steps as f64;
                self.steps(run, t, h, steps, &mut s, &mut ts);
                t = ti;
            }
            let x_true = if ti < 0.0 { 0.0 } else { s[0] };
            let r = run.reading(ti, x_true);
            run.out.push(r);
            let xs: [f64; P] = std::array::from_fn(|j| if ti < 0.0 { 0.0 } else { ts[0][j] });
            self.push_tangents(run, &mut grad, ti, x_true, &xs, tan);
            let finite = s.iter().all(|v| v.is_finite());
            let (released, tail) = run.released_and_tail(ti, &s);
            if released {
                let (tb, xb, vb) = (ti, s[0], s[1]);
                if run.distortions.is_empty() {
                    if readings {
                        run.out
                            .extend(times[i + 1..].iter().map(|&tk| xb + vb * (tk - tb)));
                    }
                    for (j, tj) in tan.iter_mut().enumerate() {
                        let (xj, vj) = (ts[0][j], ts[1][j]);
                        tj.extend(times[i + 1..].iter().map(|&tk| xj + vj * (tk - tb)));
                    }
                } else {
                    // each sample on its own (a distortion's trigonometry per sample is the
                    // cost of a long record's tail): in chunks over the threads, each sample's
                    // arithmetic the same whatever the chunks
                    let run_ref: &Run = run;
                    let parts: Vec<(Vec<f64>, Vec<Vec<f64>>)> = times[i + 1..]
                        .par_chunks(TAIL_CHUNK)
                        .map(|chunk| {
                            let mut grad = Grad::new(run_ref);
                            let mut out = Vec::with_capacity(chunk.len());
                            let mut tc = vec![Vec::with_capacity(chunk.len()); P];
                            for &tk in chunk {
                                let x = xb + vb * (tk - tb);
                                if readings {
                                    out.push(run_ref.reading(tk, x));
                                }
                                let xs: [f64; P] =
                                    std::array::from_fn(|j| ts[0][j] + ts[1][j] * (tk - tb));
                                self.push_tangents(run_ref, &mut grad, tk, x, &xs, &mut tc);
                            }
                            (out, tc)
                        })
                        .collect();
                    for (out, tc) in parts {
                        run.out.extend(out);
                        for (tj, c) in tan.iter_mut().zip(tc) {
                            tj.extend(c);
                        }
                    }
                }
                return true;
            }
            // a TM the needle well traps for good: `Run::sample` continues the record
            // periodically when the rest of it is long enough (whether or not it then finds the
            // orbit, the derivatives of that are not covered)
            if !run.trap_tried
                && ti > 0.0
                && finite
                && let Some(w) = &run.well
                && w.trapped(
                    s[0],
                    s[1],
                    crate::trap::TipNow {
                        y: run.inputs.profile.y(ti),
                        speed: run.inputs.profile.speed(ti),
                        horizon: (run.t_end - ti).max(0.0),
                        tol_m: super::RELEASE_TOL_M,
                    },
                )
            {
                if run.t_end - ti >= super::ORBIT_RECORD_PERIODS * w.period_estimate() {
                    return false;
                }
                run.trap_tried = true;
            }
            run.coarse = tail;
        }
        true
    }

    /// The tangents of the reading at `t` [s], true value `x_true` [m], from the tangents `xs`
    /// of the true value: `X (1 + sum d dist/dx) + d dist/dp` over the distortions.
    fn push_tangents<const P: usize>(
        &self,
        run: &Run,
        grad: &mut Grad,
        t: f64,
        x_true: f64,
        xs: &[f64; P],
        tan: &mut [Vec<f64>],
    ) {
        if run.distortions.is_empty() {
            for (tj, x) in tan.iter_mut().zip(xs) {
                tj.push(*x);
            }
            return;
        }
        let mut gx = 1.0;
        for (d, &(e, pe)) in run.distortions.iter().enumerate() {
            gx += e
                .distortion_gradient(pe, t, x_true, &mut grad.d_p[d])
                .unwrap_or(f64::NAN);
        }
        for (j, tj) in tan.iter_mut().enumerate() {
            let own = self.dist_dir[j].map_or(0.0, |(d, k)| grad.d_p[d][k]);
            tj.push(xs[j] * gx + own);
        }
    }

    /// The state's derivative (the bits of `Run::deriv_n`) and the tangents' derivatives at
    /// `t`.
    #[inline(always)]
    fn rhs<const N: usize, const P: usize>(
        &self,
        run: &Run,
        t: f64,
        s: [f64; N],
        ts: &[[f64; P]; N],
    ) -> ([f64; N], [[f64; P]; N]) {
        let (x, v) = (s[0], s[1]);
        let e = (run.tip_y(t) - x) - run.tip_offset;
        let g = x - run.sh.x_n0;
        let body = run.sh.body;
        let mut f = 0.0;
        // dF/de, dF/dg and the partials of the force by role
        let (mut fe, mut fg) = (0.0, 0.0);
        let mut part = [0.0f64; ROLES];
        // the needle body (N == 4): its acceleration, and its contact force's partials by the
        // states x, v, u, u' (while the contact pushes) and by k_tm, c_tm (`F_pre`'s is 1)
        let mut a_body = 0.0;
        let mut body_on = false;
        let (mut k_tm_, mut c_tm_, mut k_nd_, mut c_nd_, mut m_nd_) = (0.0, 0.0, 0.0, 0.0, 1.0);
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
                        let ex = exp_or_zero(-e / lambda);
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
                        let ex = exp_or_zero(-g / lambda);
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
                ForceLaw::NeedleBody {
                    m_nd,
                    k_nd,
                    k_tm,
                    c_nd,
                    c_tm,
                } => {
                    // the law itself, as `Run::deriv_n` calls it (so its bits); the contact
                    // pushes exactly when its force is positive
                    let st = crate::effects::LawState {
                        x,
                        v,
                        e_tip: e,
                        gap: g,
                        f_pre: run.sh.f_pre,
                        body,
                        own: if N == 4 { [s[2], s[3]] } else { [0.0; 2] },
                    };
                    let mut d_own = [0.0; 2];
                    let fc = law.force(&st, &mut d_own);
                    body_on = fc > 0.0;
                    f += fc;
                    a_body = d_own[1];
                    (k_tm_, c_tm_, k_nd_, c_nd_, m_nd_) = (k_tm, c_tm, k_nd, c_nd, m_nd);
                }
            }
        }
        let mut ds = [0.0; N];
        ds[0] = v;
        ds[1] = f / run.inputs.m_kg;
        if N == 4 {
            ds[2] = s[3];
            ds[3] = a_body;
        }
        let mut dts = [[0.0f64; P]; N];
        for j in 0..P {
            let xj = ts[0][j];
            let mut df = fe * (self.de[j] - xj) + fg * (xj + self.dg[j]) + part[self.role[j]];
            if N == 4 {
                let (vj, uj, duj) = (ts[1][j], ts[2][j], ts[3][j]);
                let (u, du) = (s[2], s[3]);
                // the contact force's derivative: by the states, by F_pre (through F_pre/k_tm,
                // times k_tm: 1), by k_tm (delta - F_pre/k_tm = u - x) and by c_tm
                let dfc = if body_on {
                    k_tm_ * (uj - xj)
                        + c_tm_ * (duj - vj)
                        + self.d_fpre[j]
                        + match self.body_role[j] {
                            BODY_KTM => u - x,
                            BODY_CTM => du - v,
                            _ => 0.0,
                        }
                } else {
                    0.0
                };
                df += dfc;
                // m_nd a = F_pre - k_nd u - c_nd u' - F_c
                let own = match self.body_role[j] {
                    BODY_M => -a_body,
                    BODY_KND => -u,
                    BODY_CND => -du,
                    _ => 0.0,
                };
                let dn = self.d_fpre[j] - k_nd_ * uj - c_nd_ * duj - dfc + own;
                dts[2][j] = duj;
                dts[3][j] = dn / m_nd_;
            }
            dts[0][j] = ts[1][j];
            dts[1][j] = df * self.inv_m;
        }
        (ds, dts)
    }

    /// `steps` RK4 steps of `h` from `t` of the state `s` and its tangents `ts`: the state's
    /// arithmetic is that of `super::lockstep` (the same bits).
    fn steps<const N: usize, const P: usize>(
        &self,
        run: &Run,
        t: f64,
        h: f64,
        steps: usize,
        s: &mut [f64; N],
        ts: &mut [[f64; P]; N],
    ) {
        let mut t = t;
        for _ in 0..steps {
            let (k1, l1) = self.rhs(run, t, *s, ts);
            let mut tmp = [0.0; N];
            let mut tt = [[0.0; P]; N];
            for i in 0..N {
                tmp[i] = s[i] + 0.5 * h * k1[i];
                for j in 0..P {
                    tt[i][j] = ts[i][j] + 0.5 * h * l1[i][j];
                }
            }
            let (k2, l2) = self.rhs(run, t + 0.5 * h, tmp, &tt);
            for i in 0..N {
                tmp[i] = s[i] + 0.5 * h * k2[i];
                for j in 0..P {
                    tt[i][j] = ts[i][j] + 0.5 * h * l2[i][j];
                }
            }
            let (k3, l3) = self.rhs(run, t + 0.5 * h, tmp, &tt);
            for i in 0..N {
                tmp[i] = s[i] + h * k3[i];
                for j in 0..P {
                    tt[i][j] = ts[i][j] + h * l3[i][j];
                }
            }
            let (k4, l4) = self.rhs(run, t + h, tmp, &tt);
            for i in 0..N {
                s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
                for j in 0..P {
                    ts[i][j] += h / 6.0 * (l1[i][j] + 2.0 * l2[i][j] + 2.0 * l3[i][j] + l4[i][j]);
                }
            }
            t += h;
        }
    }
}

/// Buffers of the distortions' parameter gradients (one per distortion of the run).
struct Grad {
    d_p: Vec<Vec<f64>>,
}

impl Grad {
    fn new(run: &Run) -> Grad {
        Grad {
            d_p: run
                .distortions
                .iter()
                .map(|&(_, pe)| vec![0.0; pe.len()])
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::Scenario;

    use super::super::tests::inputs;

    /// Asserts that the tangents alone are those carried with the readings, that the readings
    /// carried with the tangents of `dirs` are the bits of
    /// `simulate` and that each tangent agrees with central differences of `simulate` to 1e-5
    /// of the column's largest value. The step is relative 1e-6 (the cyclic error's phase,
    /// 3 000 rad by the end of a 0.5 s record, stays linear over it), at least 1e-13 (a TM
    /// 0.1 mm away by then: a 2e-15 m step of a nanometre amplitude would be lost in the
    /// reading's rounding).
    fn check_tangents(
        model: &Model,
        p: &[f64],
        dirs: &[usize],
        times: &[f64],
        inp: &Inputs,
        what: &str,
    ) {
        check_tangents_with(model, p, dirs, times, inp, what, &[1e-6], 1e-5);
    }

    /// [`check_tangents`] with the tolerance `tol` (of the column's largest value), each
    /// tangent against the central differences of relative step `rels` that agree with it best.
    #[allow(clippy::too_many_arguments)]
    fn check_tangents_with(
        model: &Model,
        p: &[f64],
        dirs: &[usize],
        times: &[f64],
        inp: &Inputs,
        what: &str,
        rels: &[f64],
        tol: f64,
    ) {
        let (x, tan) = simulate_with_tangents(model, p, dirs, times, inp).unwrap();
        // the fit's Jacobian, without the tail's readings: the same tangents
        let alone = tangents_only(model, p, dirs, times, inp).unwrap();
        assert!(
            alone
                .iter()
                .flatten()
                .zip(tan.iter().flatten())
                .all(|(a, b)| a.to_bits() == b.to_bits())
                && alone.iter().map(Vec::len).eq(tan.iter().map(Vec::len)),
            "{what}: the tangents alone are not the bits of those carried with the readings"
        );
        let plain = super::super::simulate(model, p, times, inp);
        assert!(
            x.iter()
                .zip(&plain)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{what}: the readings are not simulate's bits"
        );
        for (&q, col) in dirs.iter().zip(&tan) {
            let (mut best, mut best_scale) = (f64::INFINITY, 0.0f64);
            for rel in rels {
                let h = (p[q].abs() * rel).max(1e-13);
                let at = |d: f64| {
                    let mut pq = p.to_vec();
                    pq[q] += d;
                    super::super::simulate(model, &pq, times, inp)
                };
                let (up, down) = (at(h), at(-h));
                let fd: Vec<f64> = up
                    .iter()
                    .zip(&down)
                    .map(|(a, b)| (a - b) / (2.0 * h))
                    .collect();
                let scale = fd.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                assert!(scale > 0.0, "{what}: parameter {q} moves nothing");
                let err = col
                    .iter()
                    .zip(&fd)
                    .fold(0.0f64, |a, (c, f)| a.max((c - f).abs()));
                if err / scale < best / best_scale.max(f64::MIN_POSITIVE) {
                    (best, best_scale) = (err, scale);
                }
            }
            assert!(
                best < tol * best_scale,
                "{what}: parameter {q}: {best:e} of {best_scale:e}"
            );
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
            (
                &["needle_contact", "tip_contact", "needle_adhesion", "drift"][..],
                &[6.5e5, 6e-3, 1.1e6, 1e5, 3e-7, 1e-9, 1e-6, 1e-4][..],
            ),
            (
                &[
                    "needle_contact",
                    "tip_contact",
                    "tip_adhesion",
                    "interferometer_cyclic",
                ][..],
                &[
                    6.5e5, 6e-3, 1.1e6, 1.3e5, 6e-7, 3.164e-7, 2e-9, -1e-9, 5e-10, 1e-9,
                ][..],
            ),
        ] {
            let model = Model::new(Scenario::TmmfRelease, effects).unwrap();
            assert!(model.has_tangents(p.len()));
            for m in [0.0096, 0.089, 0.844] {
                let dirs: Vec<usize> = (0..p.len()).collect();
                check_tangents(
                    &model,
                    p,
                    &dirs,
                    &times,
                    &inputs(m),
                    &format!("{effects:?} m {m}"),
                );
            }
        }
    }

    /// A long free-flight tail with distortions is computed in parallel chunks: the readings
    /// are still the bits of `simulate`, and the tangents (of the adhesion's and the
    /// distortions' ten parameters), chunk boundaries included, agree with central differences
    /// (50 000 samples, four chunks).
    #[test]
    fn a_long_tail_in_chunks_keeps_the_bits_and_the_derivatives() {
        let model = Model::new(
            Scenario::TmmfRelease,
            &[
                "needle_contact",
                "tip_contact",
                "tip_adhesion",
                "interferometer_cyclic",
                "drift",
            ],
        )
        .unwrap();
        let p = [
            6.5e5, 6e-3, 1.1e6, 1.3e5, 6e-7, 3.164e-7, 2e-9, -1e-9, 5e-10, 1e-9, 1e-9, 1e-6, 1e-4,
        ];
        let times: Vec<f64> = (-50..50_000).map(|i| i as f64 * 1e-5).collect();
        let inp = inputs(0.089);
        let dirs: Vec<usize> = (3..p.len()).collect();
        check_tangents(&model, &p, &dirs, &times, &inp, "a 0.5 s tail");
    }

    /// A needle body's model (four states: the TM's and the body's): the readings carried
    /// with the tangents are `simulate`'s bits and each tangent agrees with central
    /// differences (the better of two steps) to 1e-4: every parameter of a light, much damped
    /// body (0.03 kg; the fixed needles' stiffness, which the body replaces, moves nothing)
    /// for a middle and a heavy TM, and, for a light, a middle and a heavy TM, those of the
    /// thesis body (1.74 kg) whose effect the readings resolve (its `k_nd` and `c_nd` move
    /// them by 1e-20 and 1e-15 m per unit, under their rounding).
    ///
    /// The steps are relative 1e-6 and 1e-4: once the body has let go, the integration takes
    /// the tail step from a sample that the parameters decide, and a difference whose two
    /// sides switch at different samples sees the jump of the integration error, which a
    /// small step magnifies (3e-5 of the body mass's column at 1e-6); a large one has the
    /// truncation error of the contacts' kinks instead (4e-2 of the tip stiffness's at 1e-4).
    /// Left out: the light body with the lightest TM (0.0096 kg), whose TM, dragged by the
    /// adhesion, comes back to graze the tip 2.7 ms after the trigger. At a grazing contact
    /// the readings are continuous but not differentiable in the parameters (the time in
    /// contact grows as the square root of the overlap), so differences of any step disagree
    /// with the tangent (the derivative of the RK4 map between the steps where a stage
    /// enters or leaves the contact) by 3 % there, as they do for the two-state model.
    #[test]
    fn a_needle_body_has_its_derivatives() {
        let model = Model::new(
            Scenario::TmmfRelease,
            &[
                "needle_contact",
                "tip_contact",
                "tip_adhesion",
                "needle_mass",
            ],
        )
        .unwrap();
        assert!(model.has_tangents(9));
        let times: Vec<f64> = (-50..800).map(|i| i as f64 * 1e-5).collect();
        // needle_contact.k_nd (index 0) is superseded by the body
        let light = (
            [
                6.5e5, 6e-3, 1.1e6, 1.3e5, 6e-7, 0.03, 1.12e6, 2.03e6, 5.0, 20.0,
            ],
            (1..10).collect::<Vec<usize>>(),
            &[0.089, 0.844][..],
        );
        let thesis = (
            [
                6.5e5, 6e-3, 1.1e6, 1.3e5, 6e-7, 1.74, 1.12e6, 2.03e6, 1.0, 1.0,
            ],
            vec![1, 2, 3, 4, 5, 7, 9],
            &[0.0096, 0.089, 0.844][..],
        );
        for (p, dirs, masses) in [light, thesis] {
            for &m in masses {
                check_tangents_with(
                    &model,
                    &p,
                    &dirs,
                    &times,
                    &inputs(m),
                    &format!("needle body m_nd {}, TM {m} kg", p[5]),
                    &[1e-6, 1e-4],
                    1e-4,
                );
            }
        }
    }

    /// Models outside the tangents' reach say so: more than [`MAX_TANGENTS`] directions; and a
    /// TM trapped in the needle well, whose record `simulate` continues periodically, gives no
    /// tangents (while the same model whose TM escapes does).
    #[test]
    fn other_models_keep_finite_differences() {
        let model = Model::new(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]).unwrap();
        assert!(model.has_tangents(MAX_TANGENTS) && !model.has_tangents(MAX_TANGENTS + 1));
        // the trapped TM of `a_trapped_tm_continues_periodically` (1 s at 100 kHz)
        let well = Model::new(
            Scenario::TmmfRelease,
            &["needle_contact", "tip_contact", "needle_adhesion", "drift"],
        )
        .unwrap();
        assert!(well.has_tangents(8));
        let times: Vec<f64> = (-100..100_000).map(|i| i as f64 / 1e5).collect();
        let trapped = [8.95e6, 0.389, 3.87e5, 3e4, 3e-7, 1e-9, 1e-6, 0.0];
        let dirs: Vec<usize> = (0..8).collect();
        assert!(
            well.predict_with_tangents(&trapped, &dirs, &times, &inputs(0.089))
                .is_none()
        );
        let escapes = [6.5e5, 6e-3, 1.1e6, 1e3, 3e-7, 1e-9, 1e-6, 0.0];
        let inp = inputs(0.089);
        let tail = super::super::integrate(
            &well,
            &escapes,
            &times,
            &inp,
            step_for_mass(0.089),
            true,
            true,
        )
        .1;
        assert!(!matches!(tail, super::super::Tail::Trapped(_)), "{tail:?}");
        assert!(
            well.predict_with_tangents(&escapes, &dirs, &times, &inputs(0.089))
                .is_some()
        );
    }
}
