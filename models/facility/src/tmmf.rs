//! TM mock-up dynamics of the TMMF release (physics.md section 4): `m*x'' = F_needles + F_tip`.
//!
//! The TM starts at rest at `x = 0` at the trigger, held by the needle preload against the tip;
//! the tip follows the smooth retraction profile. The force effects of the model are summed; the
//! distortion effects are added to the predicted reading. Integrated with fixed-step RK4, the
//! step depending only on the sampling and, per sample, on whether the contacts are open (so
//! that finite-difference Jacobians are smooth: see the tail step below), until
//! every force effect has let go of the TM for good ([`ForceEffect::released`]): from
//! then on the TM is propagated exactly in free flight, `x = x_b + v_b (t - t_b)`, so that the
//! cost of the long free-flight part of a record (a 2 s facility record at 200 kHz is
//! 400 000 samples, the contact phase a few ms) is one multiply-add per sample.
//!
//! Between the two, once the contacts are open and the forces left are smooth on a longer step
//! (the adhesions past the bond, [`ForceEffect::smooth`]), the TM is integrated with
//! steps [`TAIL_STEP_FACTOR`] times the contact step, asked again at every sample: the
//! adhesion's tail, which on a 4 ms record outlasts the record before its remaining impulse
//! falls under [`RELEASE_TOL_M`], was most of a release fit's RK4 steps.
//!
//! A TM that the needle adhesion holds for good (its energy under the adhesion's escape energy,
//! the tip out of its reach: a parameter point a `diagnose` search meets often, and which used
//! to be integrated to the end of a 2 s record, half a million RK4 steps per evaluation)
//! oscillates in the needle well: one period is integrated at an eighth of the step and the
//! rest of the record read from it by periodicity. The continuation departs from integrating
//! throughout by less than integrating throughout departs from a 16 times finer integration
//! (tested); a model with other forces than the needles' and the tip's contact and adhesion
//! keeps the full integration.
//!
//! The derivatives of the readings with respect to the parameters (the fit's exact Jacobian)
//! ride along the same RK4 steps in [`tangent`] ([`simulate_with_tangents`]).

mod tangent;
pub use tangent::{MAX_TANGENTS, covers as tangents_cover, simulate_with_tangents, tangents_only};

use crate::effects::{
    DistortionEffect, ForceEffect, ForceLaw, LawState, ReleaseCheck, Role, TmState,
};
use crate::model::{Inputs, Model};
use crate::trap::{NeedleWell, Orbit, TipNow};
pub use crate::trap::{ORBIT_RECORD_PERIODS, ORBIT_REFINE, TRAP_MARGIN};
use rayon::prelude::*;

/// RK4 step for the lightest TM mock-up (0.0096 kg) [s]; the step grows as `sqrt(m)` (the
/// contact periods do), between 0.5 and 5 us. The error against a 10 ns reference stays below
/// 2e-11 m (tested), 40 times under the smallest noise of the examples.
pub const H_MAX_S: f64 = 1.25e-6;

/// Largest displacement [m] of the TM by the end of the record that each force effect may
/// neglect when it declares itself released (free flight from then on): 1e-15 m, four orders
/// of magnitude under the RK4 step error and six under the smallest noise of the examples.
pub const RELEASE_TOL_M: f64 = 1e-15;

/// The RK4 step [s] for a TM mass `m_kg` [kg].
pub fn step_for_mass(m_kg: f64) -> f64 {
    (H_MAX_S * (m_kg / 0.0096).sqrt()).clamp(0.5e-6, 5e-6)
}

/// The tail step over the contact step: once the contacts are open and every force left is
/// smooth on the tail step ([`ForceEffect::smooth`]: the adhesion laws, when the step
/// advances their argument by at most `lambda / 8` and turns their well's oscillation by at
/// most a quarter radian), the TM is integrated with steps this many times longer, until a
/// force is no longer smooth. Over 480 cases (tip or needle adhesion with `A1` 3e4 to 1e7 N/m
/// and `lambda` 10 nm to 3 um, TM masses 0.0096 to 1.96 kg, sampling at 100 kHz to 1 MHz,
/// 2026-11-26) the readings stay within 5.2e-12 m of an RK4 integration 16 times finer: at most
/// 2.5 times the contact step's own error there, and under the 2e-11 m of [`H_MAX_S`]
/// (tested).
pub const TAIL_STEP_FACTOR: f64 = 3.0;

/// Samples per parallel chunk of a free-flight tail with distortions (the readings' and, in
/// [`tangent`], their derivatives'): a chunk is a few hundred microseconds of work, so that a
/// long record's tail spreads over the threads and a short one stays in one.
const TAIL_CHUNK: usize = 16_384;

/// How the end of a record was computed (for the tests).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tail {
    /// Integrated to the last sample.
    Integrated,
    /// Free flight from this time [s].
    FreeFlight(f64),
    /// A trapped TM's periodic oscillation from this time [s].
    Trapped(f64),
}

struct Shared {
    f_pre: f64,
    inv_kc: f64,
    x_n0: f64,
    body: bool,
}

/// Predicted interferometer reading `x` [m] at `times` [s] (0 before the trigger, plus the
/// distortions over the whole record).
pub fn simulate(model: &Model, p: &[f64], times: &[f64], inputs: &Inputs) -> Vec<f64> {
    simulate_with_step(model, p, times, inputs, step_for_mass(inputs.m_kg))
}

/// [`simulate`] with the largest RK4 step `h_max` [s].
pub fn simulate_with_step(
    model: &Model,
    p: &[f64],
    times: &[f64],
    inputs: &Inputs,
    h_max: f64,
) -> Vec<f64> {
    integrate(model, p, times, inputs, h_max, true, true).0
}

/// [`simulate`] integrating to the end of the record, never switching to free flight (the
/// reference of the tests and benchmarks).
pub fn simulate_integrated_throughout(
    model: &Model,
    p: &[f64],
    times: &[f64],
    inputs: &Inputs,
) -> Vec<f64> {
    integrate(
        model,
        p,
        times,
        inputs,
        step_for_mass(inputs.m_kg),
        false,
        true,
    )
    .0
}

/// The readings at `times`, and how the end of the record was computed; `inline_laws` false
/// keeps the virtual call per force effect even when every force has a [`ForceLaw`] (the
/// tests' reference for the inline path's bits).
fn integrate(
    model: &Model,
    p: &[f64],
    times: &[f64],
    inputs: &Inputs,
    h_max: f64,
    may_release: bool,
    inline_laws: bool,
) -> (Vec<f64>, Tail) {
    let mut run = Run::new(model, p, times, inputs, h_max, may_release, inline_laws);
    let tail = integrate_run(&mut run, times);
    (run.out, tail)
}

/// [`integrate`] of a prepared [`Run`]: its readings into `run.out`.
fn integrate_run(run: &mut Run, times: &[f64]) -> Tail {
    let mut t = 0.0;
    for (i, &ti) in times.iter().enumerate() {
        if ti > t {
            let steps = ((ti - t) / run.h_next() - 1e-9).ceil().max(1.0) as usize;
            let h = (ti - t) / steps as f64;
            run.tail_intervals += usize::from(run.coarse);
            if run.laws.is_some() {
                lockstep_dyn(std::slice::from_mut(run), &[0], t, h, steps);
            } else {
                let mut ws = std::mem::replace(&mut run.ws, crate::rk4::Rk4Work::new(0));
                let mut s = std::mem::take(&mut run.s);
                for _ in 0..steps {
                    crate::rk4::rk4_step(
                        &|t, s: &[f64], ds: &mut [f64]| run.deriv(t, s, ds),
                        t,
                        h,
                        &mut s,
                        &mut ws,
                    );
                    t += h;
                }
                run.s = s;
                run.ws = ws;
            }
            t = ti;
        }
        if let Some(tail) = run.sample(i, times) {
            return tail;
        }
    }
    Tail::Integrated
}

/// Lanes of [`simulate_many`]'s lockstep integration: independent RK4 chains interleaved in
/// one thread. A step is a chain of four dependent force evaluations whose divisions and `exp`
/// wait on each other (latency, not arithmetic, bounds it): four chains side by side fill
/// some of those waits (criterion `forward_model_4_vectors`: 862 us one by one, 812 us in
/// lockstep; FAC-FIT-QUAL 9 % faster, 2026-11-26).
pub const LANES: usize = 4;

/// [`simulate`] at each parameter vector of `ps`: the same readings, bit for bit, as one
/// [`simulate`] call per vector (tested), computed [`LANES`] at a time in lockstep when every
/// force of the model is a [`ForceLaw`] (one call per vector otherwise). A finite-difference
/// Jacobian's columns and a search's starts are such sets.
pub fn simulate_many(
    model: &Model,
    ps: &[Vec<f64>],
    times: &[f64],
    inputs: &Inputs,
) -> Vec<Vec<f64>> {
    let h_max = step_for_mass(inputs.m_kg);
    let mut out = Vec::with_capacity(ps.len());
    for chunk in ps.chunks(LANES) {
        let mut runs: Vec<Run> = chunk
            .iter()
            .map(|p| Run::new(model, p, times, inputs, h_max, true, true))
            .collect();
        if runs.iter().any(|r| r.laws.is_none()) {
            out.extend(
                chunk
                    .iter()
                    .map(|p| integrate(model, p, times, inputs, h_max, true, true).0),
            );
            continue;
        }
        let mut active: Vec<usize> = (0..runs.len()).collect();
        let mut t = 0.0;
        for (i, &ti) in times.iter().enumerate() {
            if ti > t {
                // the runs on the contact step side by side, then those on the tail step
                for coarse in [false, true] {
                    let mut lanes = [0usize; LANES];
                    let mut n = 0;
                    for &j in active.iter().filter(|&&j| runs[j].coarse == coarse) {
                        lanes[n] = j;
                        n += 1;
                    }
                    if n > 0 {
                        let hs = runs[lanes[0]].h_next();
                        let steps = ((ti - t) / hs - 1e-9).ceil().max(1.0) as usize;
                        let h = (ti - t) / steps as f64;
                        lockstep_dyn(&mut runs, &lanes[..n], t, h, steps);
                    }
                }
                t = ti;
            }
            active.retain(|&j| runs[j].sample(i, times).is_none());
            if active.is_empty() {
                break;
            }
        }
        out.extend(runs.into_iter().map(|r| r.out));
    }
    out
}

/// `steps` RK4 steps of `h` from `t` of the `K` runs `active` (each a two-component state with
/// force laws), interleaved: [`crate::rk4::rk4_step`]'s arithmetic per run, in the same order, so its bits
/// (a single run is `K = 1`).
fn lockstep<const K: usize, const N: usize>(
    runs: &mut [Run],
    active: &[usize],
    t: f64,
    h: f64,
    steps: usize,
) {
    let mut s = [[0.0f64; N]; K];
    for (b, sb) in s.iter_mut().enumerate() {
        sb.copy_from_slice(&runs[active[b]].s);
    }
    {
        let lanes: [&Run; K] = std::array::from_fn(|b| &runs[active[b]]);
        let mut t = t;
        let (mut k1, mut k2, mut k3, mut k4) = (
            [[0.0f64; N]; K],
            [[0.0; N]; K],
            [[0.0; N]; K],
            [[0.0; N]; K],
        );
        let mut tmp = [[0.0f64; N]; K];
        for _ in 0..steps {
            for b in 0..K {
                k1[b] = lanes[b].deriv_n(t, s[b]);
            }
            for b in 0..K {
                for i in 0..N {
                    tmp[b][i] = s[b][i] + 0.5 * h * k1[b][i];
                }
                k2[b] = lanes[b].deriv_n(t + 0.5 * h, tmp[b]);
            }
            for b in 0..K {
                for i in 0..N {
                    tmp[b][i] = s[b][i] + 0.5 * h * k2[b][i];
                }
                k3[b] = lanes[b].deriv_n(t + 0.5 * h, tmp[b]);
            }
            for b in 0..K {
                for i in 0..N {
                    tmp[b][i] = s[b][i] + h * k3[b][i];
                }
                k4[b] = lanes[b].deriv_n(t + h, tmp[b]);
            }
            for b in 0..K {
                for i in 0..N {
                    s[b][i] += h / 6.0 * (k1[b][i] + 2.0 * k2[b][i] + 2.0 * k3[b][i] + k4[b][i]);
                }
            }
            t += h;
        }
    }
    for b in 0..K {
        runs[active[b]].s.copy_from_slice(&s[b]);
    }
}

/// [`lockstep`] for `active.len()` runs (1 to [`LANES`]) of state dimension `dim` (2 or 4).
fn lockstep_dyn(runs: &mut [Run], active: &[usize], t: f64, h: f64, steps: usize) {
    let dim = runs[active[0]].s.len();
    match (active.len(), dim) {
        (1, 2) => lockstep::<1, 2>(runs, active, t, h, steps),
        (2, 2) => lockstep::<2, 2>(runs, active, t, h, steps),
        (3, 2) => lockstep::<3, 2>(runs, active, t, h, steps),
        (4, 2) => lockstep::<4, 2>(runs, active, t, h, steps),
        (1, 4) => lockstep::<1, 4>(runs, active, t, h, steps),
        (2, 4) => lockstep::<2, 4>(runs, active, t, h, steps),
        (3, 4) => lockstep::<3, 4>(runs, active, t, h, steps),
        (4, 4) => lockstep::<4, 4>(runs, active, t, h, steps),
        _ => unreachable!("1 to {LANES} runs of 2 or 4 states"),
    }
}

/// One evaluation of the TMMF model in progress: the forces and distortions listed once, the
/// state, and the readings so far.
struct Run<'a> {
    inputs: &'a Inputs,
    /// Force effects with their parameter slice, state offset and state count.
    forces: Vec<(&'static dyn ForceEffect, &'a [f64], usize, usize)>,
    distortions: Vec<(&'static dyn DistortionEffect, &'a [f64])>,
    sh: Shared,
    /// Every force as an inline law (a two-component state), if each has one.
    laws: Option<Vec<ForceLaw>>,
    /// `F_pre / k_c` [m].
    tip_offset: f64,
    /// The tip profile's phase boundary [s], jerk [m/s^3], final speed [m/s] and displacement
    /// at the boundary [m].
    t1: f64,
    jerk: f64,
    v_tip: f64,
    y1: f64,
    well: Option<NeedleWell>,
    trap_tried: bool,
    may_release: bool,
    /// The contact step and the tail step [s].
    h_max: f64,
    h_tail: f64,
    /// Whether the next sample interval is integrated with the tail step.
    coarse: bool,
    /// Sample intervals integrated with the tail step (by [`integrate_run`], for the tests).
    tail_intervals: usize,
    t_end: f64,
    s: Vec<f64>,
    ws: crate::rk4::Rk4Work,
    out: Vec<f64>,
}

impl<'a> Run<'a> {
    fn new(
        model: &'a Model,
        p: &'a [f64],
        times: &'a [f64],
        inputs: &'a Inputs,
        h_max: f64,
        may_release: bool,
        inline_laws: bool,
    ) -> Run<'a> {
        let f_pre = model.get(p, "needle_contact.F_pre").unwrap_or(0.0);
        let body = model.has("needle_mass");
        let k_needle = if body {
            model.get(p, "needle_mass.k_tm")
        } else {
            model.get(p, "needle_contact.k_nd")
        };
        let sh = Shared {
            f_pre,
            inv_kc: model.get(p, "tip_contact.k_c").map_or(0.0, |k| 1.0 / k),
            x_n0: k_needle.map_or(0.0, |k| f_pre / k),
            body,
        };
        // state layout: x, v, then each effect's own states; the force effects are listed once
        // with their parameter slice and state range, out of the inner loop
        let mut forces = Vec::new();
        let mut distortions = Vec::new();
        let mut n = 2;
        for (i, e) in model.effects.iter().enumerate() {
            match e.role() {
                Role::Force(f) => {
                    let k = f.n_states();
                    forces.push((f, &p[model.range(i)], n, k));
                    n += k;
                }
                Role::Distortion(d) => distortions.push((d, &p[model.range(i)])),
                // a time shift acts on the times handed in (`Model::predict`)
                Role::TimeShift(_) | Role::Mechanism(_) => {}
            }
        }
        // every force as a closed-form law, evaluated inline, when each force effect offers one
        // and the state is the TM's alone: the same arithmetic in the same order as `deriv`, so
        // the same bits (ForceLaw's contract), at half the cost of a step
        let laws: Option<Vec<ForceLaw>> = if inline_laws && (n == 2 || n == 4) {
            forces.iter().map(|&(e, pe, _, _)| e.law(pe)).collect()
        } else {
            None
        };
        // the tip's profile with its phase boundary and the displacement there computed once
        // (the same expressions as `TipProfile::y`, so the same values), out of the RK4 stages
        let (t1, jerk, v_tip) = (
            inputs.profile.t1_s(),
            inputs.profile.jerk_m_s3,
            inputs.profile.v_m_s,
        );
        Run {
            inputs,
            forces,
            distortions,
            tip_offset: sh.f_pre * sh.inv_kc,
            sh,
            laws,
            t1,
            jerk,
            v_tip,
            y1: jerk * t1 * t1 * t1 / 6.0,
            well: NeedleWell::of(model, p, inputs.m_kg),
            trap_tried: false,
            may_release,
            h_max,
            h_tail: h_max * TAIL_STEP_FACTOR,
            coarse: false,
            tail_intervals: 0,
            t_end: times.last().copied().unwrap_or(0.0),
            s: vec![0.0; n],
            ws: crate::rk4::Rk4Work::new(n),
            out: Vec::with_capacity(times.len()),
        }
    }

    /// Tip displacement [m] at `t` [s].
    #[inline(always)]
    fn tip_y(&self, t: f64) -> f64 {
        if t <= 0.0 {
            0.0
        } else if t < self.t1 {
            self.jerk * t * t * t / 6.0
        } else {
            self.y1 + self.v_tip * (t - self.t1)
        }
    }

    /// Tip speed [m/s] at `t` [s] (`TipProfile::speed`'s expressions, its phase boundary computed
    /// once).
    #[inline(always)]
    fn tip_speed(&self, t: f64) -> f64 {
        if t <= 0.0 {
            0.0
        } else if t < self.t1 {
            0.5 * self.jerk * t * t
        } else {
            self.v_tip
        }
    }

    /// The state's time derivative through the effects' `force` (any model).
    fn deriv(&self, t: f64, s: &[f64], ds: &mut [f64]) {
        let y = self.tip_y(t);
        let (x, v) = (s[0], s[1]);
        let sh = &self.sh;
        let mut f = 0.0;
        for &(e, pe, off, k) in &self.forces {
            let st = TmState {
                t,
                x,
                v,
                y,
                e_tip: (y - x) - sh.f_pre * sh.inv_kc,
                needle_gap: x - sh.x_n0,
                f_pre: sh.f_pre,
                needle_body: sh.body,
                m_kg: self.inputs.m_kg,
                own: &s[off..off + k],
            };
            f += e.force(pe, &st, &mut ds[off..off + k]);
        }
        ds[0] = v;
        ds[1] = f / self.inputs.m_kg;
    }

    /// [`Run::deriv`] through the inline laws (a model whose forces all have one, with `N`
    /// states: the TM's two and a needle body's two when `N = 4`).
    #[inline(always)]
    fn deriv_n<const N: usize>(&self, t: f64, s: [f64; N]) -> [f64; N] {
        let (x, v) = (s[0], s[1]);
        let st = LawState {
            x,
            v,
            e_tip: (self.tip_y(t) - x) - self.tip_offset,
            gap: x - self.sh.x_n0,
            f_pre: self.sh.f_pre,
            body: self.sh.body,
            own: if N == 4 { [s[2], s[3]] } else { [0.0; 2] },
        };
        let mut d_own = [0.0; 2];
        let mut f = 0.0;
        for law in self.laws.as_deref().unwrap_or(&[]) {
            f += law.force(&st, &mut d_own);
        }
        let mut ds = [0.0; N];
        ds[0] = v;
        ds[1] = f / self.inputs.m_kg;
        if N == 4 {
            ds[2] = d_own[0];
            ds[3] = d_own[1];
        }
        ds
    }

    /// The reading: the TM's position plus every distortion (listed once: a virtual call per
    /// effect and sample was a quarter of a long record's cost).
    fn reading(&self, t: f64, x_true: f64) -> f64 {
        let mut x = x_true;
        for &(e, pe) in &self.distortions {
            x += e.distortion(pe, t, x_true);
        }
        x
    }

    /// Whether every force has let go of the TM for good at `t` [s] in state `s`, and whether
    /// the sample interval after `t` takes the tail step: every force released or smooth on
    /// the tail step ([`ForceEffect::smooth`]), and an effect's own states (a needle body's,
    /// whose contact has contact-scale dynamics) only once their force is released and they
    /// are slow on the tail step ([`ForceEffect::own_states_slow`]). Neither before the
    /// trigger, for a state that is not finite, or in a run that may not release (the tests'
    /// integrate-throughout reference). One pass over the forces, asked at every sample.
    fn released_and_tail(&self, t: f64, s: &[f64]) -> (bool, bool) {
        if !(self.may_release && t > 0.0 && s.iter().all(|v| v.is_finite())) {
            return (false, false);
        }
        let mut released = true;
        let mut tail = true;
        self.every_force(t, s, |e, pe, st, rc| {
            let rel = e.released(pe, st, rc);
            released &= rel;
            // an effect's own states (a needle body's) keep the contact step until the force
            // has let go and they are slow on the tail step
            let own_ok = st.own.is_empty() || (rel && e.own_states_slow(pe, self.h_tail));
            tail = tail && own_ok && (rel || e.smooth(pe, st, rc, self.h_tail));
            released || tail
        });
        (released, tail)
    }

    /// The step of the next sample interval [s].
    #[inline]
    fn h_next(&self) -> f64 {
        if self.coarse { self.h_tail } else { self.h_max }
    }

    /// Whether `test` holds for every force effect at `t` in state `s` (stops at the first
    /// that fails).
    fn every_force(
        &self,
        t: f64,
        s: &[f64],
        mut test: impl FnMut(&dyn ForceEffect, &[f64], &TmState, &ReleaseCheck) -> bool,
    ) -> bool {
        let sh = &self.sh;
        let y = self.tip_y(t);
        let rc = ReleaseCheck {
            tip_speed_m_s: self.tip_speed(t),
            horizon_s: (self.t_end - t).max(0.0),
            m_kg: self.inputs.m_kg,
            tol_m: RELEASE_TOL_M,
        };
        self.forces.iter().all(|&(e, pe, off, k)| {
            let st = TmState {
                t,
                x: s[0],
                v: s[1],
                y,
                e_tip: (y - s[0]) - sh.f_pre * sh.inv_kc,
                needle_gap: s[0] - sh.x_n0,
                f_pre: sh.f_pre,
                needle_body: sh.body,
                m_kg: self.inputs.m_kg,
                own: &s[off..off + k],
            };
            test(e, pe, &st, &rc)
        })
    }

    /// Records the reading at sample `i` (the state integrated to `times[i]`); when the TM is
    /// released or trapped for good from there, fills the rest of the record and returns how.
    fn sample(&mut self, i: usize, times: &[f64]) -> Option<Tail> {
        let ti = times[i];
        let s = &self.s;
        let x_true = if ti < 0.0 { 0.0 } else { s[0] };
        let r = self.reading(ti, x_true);
        self.out.push(r);
        let finite = s.iter().all(|v| v.is_finite());
        let (released, tail) = self.released_and_tail(ti, s);
        if released {
            // free flight for the rest of the record, in one tight loop
            let (tb, xb, vb) = (ti, s[0], s[1]);
            if self.distortions.is_empty() {
                self.out
                    .extend(times[i + 1..].iter().map(|&tj| xb + vb * (tj - tb)));
            } else {
                // each sample on its own (a distortion's trigonometry per sample is the cost of
                // a long record's tail): in chunks over the threads, each sample's arithmetic
                // the same whatever the chunks (as `tangent`'s tail)
                let run: &Run = self;
                let parts: Vec<Vec<f64>> = times[i + 1..]
                    .par_chunks(TAIL_CHUNK)
                    .map(|chunk| {
                        chunk
                            .iter()
                            .map(|&tj| run.reading(tj, xb + vb * (tj - tb)))
                            .collect()
                    })
                    .collect();
                self.out.reserve(times.len() - i - 1);
                for part in parts {
                    self.out.extend(part);
                }
            }
            return Some(Tail::FreeFlight(tb));
        }
        // a TM the needle adhesion holds for good oscillates in the well for the rest of the
        // record: one period is integrated (at an eighth of the step) and repeated, instead
        // of RK4 to the end of a 2 s record (half a million steps)
        if self.may_release
            && !self.trap_tried
            && ti > 0.0
            && finite
            && let Some(w) = &self.well
            && w.trapped(
                s[0],
                s[1],
                TipNow {
                    y: self.inputs.profile.y(ti),
                    speed: self.inputs.profile.speed(ti),
                    horizon: (self.t_end - ti).max(0.0),
                    tol_m: RELEASE_TOL_M,
                },
            )
        {
            self.trap_tried = true;
            // worth it only on a record much longer than the period; the period is at least
            // the harmonic estimate, and the search for it is given half the cost of
            // integrating the rest of the record at the full step
            let rest = self.t_end - ti;
            let budget = (rest / self.h_max / 2.0) as usize;
            if rest >= ORBIT_RECORD_PERIODS * w.period_estimate()
                && let Some(orbit) = Orbit::find(
                    &|t, s: &[f64], ds: &mut [f64]| self.deriv(t, s, ds),
                    ti,
                    &self.s,
                    self.h_max / ORBIT_REFINE,
                    self.t_end,
                    budget,
                )
            {
                let rest: Vec<f64> = times[i + 1..]
                    .iter()
                    .map(|&tj| self.reading(tj, orbit.x_at(tj)))
                    .collect();
                self.out.extend(rest);
                return Some(Tail::Trapped(ti));
            }
        }
        self.coarse = tail;
        None
    }
}

#[cfg(test)]
mod tests;
