//! TM mock-up dynamics of the TMMF release (physics.md section 4): `m*x'' = F_needles + F_tip`.
//!
//! The TM starts at rest at `x = 0` at the trigger, held by the needle preload against the tip;
//! the tip follows the smooth retraction profile. The force effects of the model are summed; the
//! distortion effects are added to the predicted reading. Integrated with fixed-step RK4, the
//! step depending only on the sampling (so that finite-difference Jacobians are smooth), until
//! every force effect has let go of the TM for good ([`Effect::released`](crate::Effect)): from
//! then on the TM is propagated exactly in free flight, `x = x_b + v_b (t - t_b)`, so that the
//! cost of the long free-flight part of a record (a 2 s facility record at 200 kHz is
//! 400 000 samples, the contact phase a few ms) is one multiply-add per sample.

use crate::effects::{EffectKind, ReleaseCheck, TmState};
use crate::model::{Inputs, Model};

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
    integrate(model, p, times, inputs, h_max, true)
}

/// [`simulate`] integrating to the end of the record, never switching to free flight (the
/// reference of the tests and benchmarks).
pub fn simulate_integrated_throughout(
    model: &Model,
    p: &[f64],
    times: &[f64],
    inputs: &Inputs,
) -> Vec<f64> {
    integrate(model, p, times, inputs, step_for_mass(inputs.m_kg), false)
}

fn integrate(
    model: &Model,
    p: &[f64],
    times: &[f64],
    inputs: &Inputs,
    h_max: f64,
    may_release: bool,
) -> Vec<f64> {
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
        let k = e.n_states();
        match e.kind() {
            EffectKind::Force => forces.push((*e, &p[model.range(i)], n, k)),
            EffectKind::Distortion => distortions.push((*e, &p[model.range(i)])),
            EffectKind::Mechanism => {}
        }
        n += k;
    }
    // the reading: the TM's position plus every distortion (listed once: a virtual call per
    // effect and sample was a quarter of a long record's cost)
    let reading = |t: f64, x_true: f64| -> f64 {
        let mut x = x_true;
        for &(e, pe) in &distortions {
            x += e.distortion(pe, t, x_true);
        }
        x
    };
    // the tip's profile with its phase boundary and the displacement there computed once (the
    // same expressions as `TipProfile::y`, so the same values), out of the RK4 stages
    let (t1, jerk, v_tip) = (
        inputs.profile.t1_s(),
        inputs.profile.jerk_m_s3,
        inputs.profile.v_m_s,
    );
    let y1 = jerk * t1 * t1 * t1 / 6.0;
    let tip_y = |t: f64| -> f64 {
        if t <= 0.0 {
            0.0
        } else if t < t1 {
            jerk * t * t * t / 6.0
        } else {
            y1 + v_tip * (t - t1)
        }
    };
    let deriv = |t: f64, s: &[f64], ds: &mut [f64]| {
        let y = tip_y(t);
        let (x, v) = (s[0], s[1]);
        let mut f = 0.0;
        for &(e, pe, off, k) in &forces {
            let st = TmState {
                t,
                x,
                v,
                y,
                e_tip: (y - x) - sh.f_pre * sh.inv_kc,
                needle_gap: x - sh.x_n0,
                f_pre: sh.f_pre,
                needle_body: sh.body,
                own: &s[off..off + k],
            };
            f += e.force(pe, &st, &mut ds[off..off + k]);
        }
        ds[0] = v;
        ds[1] = f / inputs.m_kg;
    };
    let mut s = vec![0.0; n];
    let mut t = 0.0;
    let mut out = Vec::with_capacity(times.len());
    let mut ws = crate::rk4::Rk4Work::new(n);
    let t_end = times.last().copied().unwrap_or(0.0);
    let released = |t: f64, s: &[f64]| -> bool {
        let y = inputs.profile.y(t);
        let rc = ReleaseCheck {
            tip_speed_m_s: inputs.profile.speed(t),
            horizon_s: (t_end - t).max(0.0),
            m_kg: inputs.m_kg,
            tol_m: RELEASE_TOL_M,
        };
        forces.iter().all(|&(e, pe, off, k)| {
            let st = TmState {
                t,
                x: s[0],
                v: s[1],
                y,
                e_tip: (y - s[0]) - sh.f_pre * sh.inv_kc,
                needle_gap: s[0] - sh.x_n0,
                f_pre: sh.f_pre,
                needle_body: sh.body,
                own: &s[off..off + k],
            };
            e.released(pe, &st, &rc)
        })
    };
    for (i, &ti) in times.iter().enumerate() {
        if ti > t {
            let steps = ((ti - t) / h_max - 1e-9).ceil().max(1.0) as usize;
            let h = (ti - t) / steps as f64;
            for _ in 0..steps {
                crate::rk4::rk4_step(&deriv, t, h, &mut s, &mut ws);
                t += h;
            }
            t = ti;
        }
        let x_true = if ti < 0.0 { 0.0 } else { s[0] };
        out.push(reading(ti, x_true));
        if may_release && ti > 0.0 && s.iter().all(|v| v.is_finite()) && released(ti, &s) {
            // free flight for the rest of the record, in one tight loop
            let (tb, xb, vb) = (ti, s[0], s[1]);
            if distortions.is_empty() {
                out.extend(times[i + 1..].iter().map(|&tj| xb + vb * (tj - tb)));
            } else {
                out.extend(
                    times[i + 1..]
                        .iter()
                        .map(|&tj| reading(tj, xb + vb * (tj - tb))),
                );
            }
            break;
        }
    }
    out
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

    #[test]
    fn catapult_velocity_matches_the_impulse_formula() {
        // A fast tip and no adhesion: the needles alone give I = F_pre*sqrt(m/k_nd) (thesis ch. 5).
        let model = Model::new(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]).unwrap();
        let (k_nd, f_pre, m) = (6.5e5, 6e-3, 0.089);
        let times: Vec<f64> = (0..1601).map(|i| i as f64 * 5e-6).collect();
        let mut inp = inputs(m);
        inp.profile = TipProfile {
            jerk_m_s3: 1e9,
            v_m_s: 1.0,
        };
        let x = simulate(&model, &[k_nd, f_pre, 1e6], &times, &inp);
        let v_late = (x[1600] - x[1500]) / (times[1600] - times[1500]);
        let v_expected = f_pre * (m / k_nd).sqrt() / m;
        assert!(
            (v_late / v_expected - 1.0).abs() < 0.01,
            "{v_late} vs {v_expected}"
        );
    }

    #[test]
    fn step_size_error_is_far_below_the_noise() {
        let model = Model::new(
            Scenario::TmmfRelease,
            &["needle_contact", "tip_contact", "tip_adhesion"],
        )
        .unwrap();
        let p = [6.5e5, 6e-3, 1.1e6, 1.3e5, 6e-7];
        let times: Vec<f64> = (0..1601).map(|i| i as f64 * 5e-6).collect();
        for m in [0.0096, 0.089, 0.844] {
            let a = simulate(&model, &p, &times, &inputs(m));
            let b = simulate_with_step(&model, &p, &times, &inputs(m), 1e-8);
            let err = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(err < 2e-11, "m {m}: {err}");
        }
    }

    #[test]
    fn free_flight_after_release_agrees_with_integrating_throughout() {
        // 0.1 s at 200 kHz: the contact phase lasts a few ms, the rest is free flight
        let times: Vec<f64> = (-200..20_000).map(|i| i as f64 / 2e5).collect();
        for (effects, p) in [
            (
                &["needle_contact", "tip_contact", "tip_adhesion"][..],
                &[6.5e5, 6e-3, 1.1e6, 1.3e5, 6e-7][..],
            ),
            (
                &["needle_contact", "tip_contact", "needle_adhesion", "drift"][..],
                &[6.5e5, 6e-3, 1.1e6, 1e5, 3e-7, 1e-9, 1e-6, 0.0][..],
            ),
            (
                &["needle_contact", "tip_contact", "needle_mass"][..],
                &[6.5e5, 6e-3, 1.1e6, 1.74, 1.12e6, 2.03e6, 1.0, 1.0][..],
            ),
        ] {
            let model = Model::new(Scenario::TmmfRelease, effects).unwrap();
            let a = simulate(&model, p, &times, &inputs(0.089));
            let b = simulate_integrated_throughout(&model, p, &times, &inputs(0.089));
            let err = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            // rounding of the integration over 20 000 samples, far under the RK4 step error
            assert!(err < 1e-13, "{effects:?}: {err}");
            assert!(a[20_199] > a[10_000], "{effects:?}: the TM flies away");
        }
    }

    #[test]
    fn at_rest_before_the_trigger() {
        let model = Model::new(
            Scenario::TmmfRelease,
            &["needle_contact", "tip_contact", "drift"],
        )
        .unwrap();
        let x = simulate(
            &model,
            &[6.5e5, 6e-3, 1e6, 1e-9, 0.0, 0.0],
            &[-1e-3, -5e-4],
            &inputs(0.089),
        );
        assert_eq!(x, vec![1e-9, 1e-9]);
    }
}
