//! Unloaded retraction of the GPRM release tip (physics.md sections 1 and 5): a linear ODE in the
//! piezo charge `q`, the plunger `l` and the tip `y`, with `F_c = 0`.
//!
//! `R*Ca*q' + q - T*(y - l) = Ca*E(t)`;
//! `Mg*l'' + Kg*l - b*(y' - l') - (k + T^2/Ca)*(y - l) + (T/Ca)*q = 0` (without
//! `plunger_compliance`, `l = 0`); `m*y'' + b*(y' - l') + (k + T^2/Ca)*(y - l) - (T/Ca)*q = 0`.
//! Initial state: static equilibrium at `E0` (`d0 = T*E0/k`, `q0 = Ca*E0 + T*d0`); for `t >= 0`
//! `E = 0` (ideal step) or `max(0, E0 - em*t)` (`voltage_ramp`). Output `y(t) - y(0)`.
//!
//! This is the identification model of the facility (effects `piezo`, `plunger_compliance`,
//! `voltage_ramp`); it does not depend on `geodesic-mechanism`. Integrated with fixed-step RK4
//! (step at most [`H_MAX_S`], depending only on the sampling).

use crate::model::Model;
use crate::tmmf::{Rk4Work, rk4_step};

/// Largest RK4 step [s]: 0.03 rad per step at the 73 kHz tip resonance.
pub const H_MAX_S: f64 = 6.25e-8;

/// Mechanism parameters (physics.md section 1), written by the effects' `configure_rt`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RtConfig {
    /// Series resistance R [ohm].
    pub r_ohm: f64,
    /// Tip mass m [kg].
    pub m_kg: f64,
    /// Piezo capacitance Ca [F].
    pub ca_f: f64,
    /// Piezo stiffness k [N/m].
    pub k_n_m: f64,
    /// Damping b [N s/m].
    pub b_ns_m: f64,
    /// Electromechanical coupling T [C/m].
    pub t_c_m: f64,
    /// Plunger mass Mg [kg] and stiffness Kg [N/m]; `None`: rigid plunger.
    pub plunger: Option<(f64, f64)>,
    /// Voltage slope em [V/s]; `None`: ideal step.
    pub em_v_s: Option<f64>,
    /// Initial voltage E0 [V].
    pub e0_v: f64,
}

impl Default for RtConfig {
    /// The thesis table "Example of estimated model parameters", rigid plunger, ideal step.
    fn default() -> Self {
        RtConfig {
            r_ohm: 371.2,
            m_kg: 9e-4,
            ca_f: 2.3e-7,
            k_n_m: 4.91e7,
            b_ns_m: 9.77,
            t_c_m: 5.73,
            plunger: None,
            em_v_s: None,
            e0_v: 120.0,
        }
    }
}

impl RtConfig {
    /// Command voltage [V] at `t` [s] (physics.md section 1).
    pub fn voltage(&self, t: f64) -> f64 {
        if t < 0.0 {
            return self.e0_v;
        }
        match self.em_v_s {
            Some(em) => (self.e0_v - em * t).max(0.0),
            None => 0.0,
        }
    }

    /// Static elongation at `E0` with no contact, `d0 = T*E0/k` [m].
    pub fn d0_m(&self) -> f64 {
        self.t_c_m * self.e0_v / self.k_n_m
    }

    /// Time derivative of the state `[q, y, y', l, l']`.
    pub fn deriv(&self, t: f64, s: &[f64], ds: &mut [f64]) {
        let (q, y, dy, l, dl) = (s[0], s[1], s[2], s[3], s[4]);
        let kk = self.k_n_m + self.t_c_m * self.t_c_m / self.ca_f;
        let tc = self.t_c_m / self.ca_f;
        let e = self.voltage(t);
        ds[0] = (self.ca_f * e + self.t_c_m * (y - l) - q) / (self.r_ohm * self.ca_f);
        ds[1] = dy;
        ds[2] = (-self.b_ns_m * (dy - dl) - kk * (y - l) + tc * q) / self.m_kg;
        match self.plunger {
            Some((mg, kg)) => {
                ds[3] = dl;
                ds[4] = (-kg * l + self.b_ns_m * (dy - dl) + kk * (y - l) - tc * q) / mg;
            }
            None => {
                ds[3] = 0.0;
                ds[4] = 0.0;
            }
        }
    }

    /// Tip displacement from its position at `t = 0`, `y(t) - y(0)` [m], at `times` [s].
    pub fn retraction(&self, times: &[f64]) -> Vec<f64> {
        let d0 = self.d0_m();
        let mut s = [self.ca_f * self.e0_v + self.t_c_m * d0, d0, 0.0, 0.0, 0.0];
        let f = |t: f64, s: &[f64], ds: &mut [f64]| self.deriv(t, s, ds);
        let mut w = Rk4Work::new(5);
        let mut t = 0.0;
        let mut out = Vec::with_capacity(times.len());
        for &ti in times {
            if ti > t {
                let steps = ((ti - t) / H_MAX_S - 1e-9).ceil().max(1.0) as usize;
                let h = (ti - t) / steps as f64;
                for _ in 0..steps {
                    rk4_step(&f, t, h, &mut s, &mut w);
                    t += h;
                }
                t = ti;
            }
            out.push(if ti < 0.0 { 0.0 } else { s[1] - d0 });
        }
        out
    }
}

/// Builds the configuration of `model` for `p` and returns `y(t) - y(0)` [m] at `times` [s].
pub fn simulate(model: &Model, p: &[f64], times: &[f64], e0_v: f64) -> Vec<f64> {
    let mut cfg = RtConfig {
        e0_v,
        ..RtConfig::default()
    };
    for (i, e) in model.effects.iter().enumerate() {
        e.configure_rt(&p[model.range(i)], &mut cfg);
    }
    cfg.retraction(times)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn static_stroke_is_14_um() {
        // physics.md section 1: d = T*E/k = 14.0 um.
        assert!((RtConfig::default().d0_m() - 14.0e-6).abs() < 0.05e-6);
    }

    #[test]
    fn retracts_by_the_full_stroke() {
        let cfg = RtConfig::default();
        let times: Vec<f64> = (0..=3000).map(|i| i as f64 * 1e-6).collect();
        let y = cfg.retraction(&times);
        // settles at -d0 once the charge has drained (tau = R*(Ca + T^2/k) ~ 0.35 ms)
        assert!(
            (y[3000] + cfg.d0_m()).abs() < 0.01 * cfg.d0_m(),
            "{}",
            y[3000]
        );
        assert!(y[1] < 0.0);
    }

    #[test]
    fn ramp_slows_the_start() {
        let step = RtConfig::default();
        let ramp = RtConfig {
            em_v_s: Some(5e7),
            ..step
        };
        let t = [2e-6];
        assert!(ramp.retraction(&t)[0] > step.retraction(&t)[0]);
    }
}
