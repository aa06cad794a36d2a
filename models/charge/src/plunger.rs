//! The plungers' electrostatic attraction on the charged TM in the 25 s after the release (thesis
//! ch. 7, "TM-Plunger voltage and its effect on the TM motion"; issue 16, item 1).
//!
//! For 25 s after the tips retract, the TM drifts along z with its release velocity while the two
//! plungers retract from about the tip length (15 um) to their parking distance, and each
//! attracts the TM with `F = 1/2 |dC/dg| (V_pl - V_TM)^2` (plungers grounded, `V_pl = 0`; the
//! electrodes are off for the first 15 s and the FE analysis the thesis cites finds the housing's
//! and electrodes' contributions negligible while the plungers are within 500 um).
//!
//! **Capacitance.** The thesis's FE fits (Ansoft Maxwell) are not printed. Two replaceable
//! models ([`PlungerCapacitance`]):
//! - [`FlatDisc`] (the default): the plunger end as a flat disc of radius `r` facing the TM face,
//!   Kirchhoff's formula with fringing, `C = eps0 pi r^2 / g + eps0 r (ln(16 pi r / g) - 1)`,
//!   valid for `g << r`; `r` is calibrated so that `C(15 um)` is the thesis's FE `C_TM,Pyr`
//!   = 35 pF at contact loss (ASSUMPTION: that value applies at the 15 um start), which gives
//!   `r` of about 4.2 mm, the size of the GPRM plunger's end;
//! - [`SpherePlane`]: a sphere of radius `R` facing the plane, exact image-charge series
//!   `C = 4 pi eps0 R sinh(a) sum_n 1 / sinh(n a)`, `cosh a = 1 + g / R`, summed to a stated
//!   relative tolerance (the convergence check) with `dC/dg` from the differentiated series.
//!
//! **Dynamics.** 1-D along z, the TM's displacement `z` towards plunger 1 from the release
//! position; gaps `g1 = p(t) - z`, `g2 = p(t) + z` with the retraction profile `p(t)` linear
//! from `g0` to `g_end` over `t_ramp`, then held; `M z'' = F(g1) - F(g2)`. Classical RK4 with a
//! fixed step, and the same run at half the step as a convergence check (the difference is
//! reported). A gap reaching zero is a touch: the run stops there and says so.

use crate::capacitance::EPS0_F_M;
use std::f64::consts::PI;

/// A plunger-TM capacitance model: `C(g)` and `dC/dg` at the gap `g` [m].
pub trait PlungerCapacitance: Send + Sync {
    /// Capacitance [F] at gap `gap_m` [m].
    fn c_f(&self, gap_m: f64) -> f64;
    /// Derivative `dC/dg` [F/m] (negative: the capacitance falls as the gap opens).
    fn dc_dg_f_m(&self, gap_m: f64) -> f64;
    /// One-line description with the parameters.
    fn describe(&self) -> String;
}

/// The plunger end as a flat disc (Kirchhoff's formula with fringing).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlatDisc {
    /// Disc radius [m].
    pub radius_m: f64,
}

impl FlatDisc {
    /// The disc whose capacitance at `gap_m` is `c_f` (bisection on the radius).
    pub fn calibrated(c_f: f64, gap_m: f64) -> FlatDisc {
        let (mut lo, mut hi) = (1e-6, 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if (FlatDisc { radius_m: mid }).c_f(gap_m) < c_f {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        FlatDisc {
            radius_m: 0.5 * (lo + hi),
        }
    }
}

impl PlungerCapacitance for FlatDisc {
    fn c_f(&self, g: f64) -> f64 {
        let r = self.radius_m;
        EPS0_F_M * PI * r * r / g + EPS0_F_M * r * ((16.0 * PI * r / g).ln() - 1.0)
    }

    fn dc_dg_f_m(&self, g: f64) -> f64 {
        let r = self.radius_m;
        -EPS0_F_M * PI * r * r / (g * g) - EPS0_F_M * r / g
    }

    fn describe(&self) -> String {
        format!(
            "flat disc of radius {:.3} mm facing the TM face (Kirchhoff, with fringing)",
            self.radius_m * 1e3
        )
    }
}

/// A sphere facing a plane: the exact image-charge series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpherePlane {
    /// Sphere radius [m].
    pub radius_m: f64,
    /// Relative tolerance at which the series is stopped [-].
    pub rel_tol: f64,
}

impl SpherePlane {
    /// `(C [F], dC/dg [F/m], terms summed)`.
    pub fn series(&self, g: f64) -> (f64, f64, usize) {
        let r = self.radius_m;
        let ch = 1.0 + g / r;
        let a = ch.acosh();
        let sa = a.sinh();
        // da/dg = 1 / (R sinh a)
        let da_dg = 1.0 / (r * sa);
        let (mut s, mut ds) = (0.0, 0.0);
        let mut n = 1usize;
        loop {
            let na = n as f64 * a;
            let term = 1.0 / na.sinh();
            // d/da (1 / sinh(n a)) = -n cosh(n a) / sinh^2(n a)
            let dterm = -(n as f64) * na.cosh() / (na.sinh() * na.sinh());
            s += term;
            ds += dterm;
            // the terms fall at least geometrically (ratio about e^-a): the tail beyond this
            // term is bounded by term e^-a / (1 - e^-a), and the sum stops when that is below
            // the tolerance
            let q = (-a).exp();
            if term * q / (1.0 - q) < self.rel_tol * s || n >= 10_000_000 {
                break;
            }
            n += 1;
        }
        let k = 4.0 * PI * EPS0_F_M * r;
        let c = k * sa * s;
        // dC/da = k (cosh a s + sinh a ds)
        let dc_da = k * (a.cosh() * s + sa * ds);
        (c, dc_da * da_dg, n)
    }
}

impl PlungerCapacitance for SpherePlane {
    fn c_f(&self, g: f64) -> f64 {
        self.series(g).0
    }

    fn dc_dg_f_m(&self, g: f64) -> f64 {
        self.series(g).1
    }

    fn describe(&self) -> String {
        format!(
            "sphere of radius {:.3} mm facing the TM face (image series to {:.0e})",
            self.radius_m * 1e3,
            self.rel_tol
        )
    }
}

/// A plunger retraction procedure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Retraction {
    /// Gap at the release [m] (thesis: the tip length, about 15 um).
    pub g0_m: f64,
    /// Parking gap [m] (thesis: 500 um baseline, 1800-2400 um revised).
    pub g_end_m: f64,
    /// Duration of the linear retraction [s] (thesis: 15 s for the baseline).
    pub ramp_s: f64,
}

impl Retraction {
    /// The thesis's baseline: 15 um to 500 um in 15 s.
    pub const BASELINE: Retraction = Retraction {
        g0_m: 15e-6,
        g_end_m: 500e-6,
        ramp_s: 15.0,
    };
    /// The revised procedure, at the short end of its 1800-2400 um range (ASSUMPTION: the same
    /// 15 s ramp; the thesis gives the distance, not the timing).
    pub const REVISED: Retraction = Retraction {
        g0_m: 15e-6,
        g_end_m: 1800e-6,
        ramp_s: 15.0,
    };

    /// Plunger distance from the TM's release position at `t_s` [m].
    pub fn p_m(&self, t_s: f64) -> f64 {
        let f = (t_s / self.ramp_s).clamp(0.0, 1.0);
        self.g0_m + (self.g_end_m - self.g0_m) * f
    }
}

/// Inputs of one simulation.
#[derive(Debug, Clone, Copy)]
pub struct PlungerCase {
    /// TM mass [kg].
    pub mass_kg: f64,
    /// TM potential [V] (plungers at 0 V).
    pub v_tm_v: f64,
    /// Release velocity towards plunger 1 [m/s].
    pub v0_m_s: f64,
    /// Retraction procedure.
    pub retraction: Retraction,
    /// Simulated time [s] (thesis: 25 s, to the first velocity estimate).
    pub duration_s: f64,
    /// DFACS actuation authority along z [N] (thesis ch. 2: about 5e-7 N).
    pub authority_n: f64,
    /// Time at which the force is compared with the authority [s] (thesis: 4.3 s).
    pub compare_at_s: f64,
}

/// The result of one simulation.
#[derive(Debug, Clone)]
pub struct PlungerRun {
    /// Velocity change `v(end) - v0` [m/s] (positive: faster towards plunger 1).
    pub extra_velocity_m_s: f64,
    /// The same at half the step (convergence check) [m/s].
    pub extra_velocity_half_step_m_s: f64,
    /// Smallest TM-plunger gap [m] and when [s].
    pub min_gap_m: f64,
    /// Time of the smallest gap [s].
    pub min_gap_at_s: f64,
    /// When a gap closed (a touch, interpolated within the step); the run stops there and the
    /// velocity change is that before the touch.
    pub touched_at_s: Option<f64>,
    /// |net force| / authority at `compare_at_s` [-].
    pub force_ratio_at_compare: f64,
    /// Last time the |net force| is at or above 1 % of the authority [s] (0 if never).
    pub force_above_1pct_until_s: f64,
    /// Samples `(t [s], z [m], v [m/s], gap1 [m], |F| / authority [-])`, every 0.05 s.
    pub trace: Vec<(f64, f64, f64, f64, f64)>,
}

fn net_force(cap: &dyn PlungerCapacitance, c: &PlungerCase, t: f64, z: f64) -> (f64, f64, f64) {
    let p = c.retraction.p_m(t);
    let (g1, g2) = (p - z, p + z);
    let v2 = c.v_tm_v * c.v_tm_v;
    let f1 = 0.5 * (-cap.dc_dg_f_m(g1.max(1e-12))) * v2; // towards plunger 1 (+z)
    let f2 = 0.5 * (-cap.dc_dg_f_m(g2.max(1e-12))) * v2; // towards plunger 2 (-z)
    (f1 - f2, g1, g2)
}

fn integrate(
    cap: &dyn PlungerCapacitance,
    c: &PlungerCase,
    dt: f64,
    keep_trace: bool,
) -> PlungerRun {
    let (mut t, mut z, mut v) = (0.0f64, 0.0f64, c.v0_m_s);
    let acc = |t: f64, z: f64| net_force(cap, c, t, z).0 / c.mass_kg;
    let steps = (c.duration_s / dt).round() as usize;
    let every = ((0.05 / dt).round() as usize).max(1);
    let mut run = PlungerRun {
        extra_velocity_m_s: 0.0,
        extra_velocity_half_step_m_s: f64::NAN,
        min_gap_m: f64::INFINITY,
        min_gap_at_s: 0.0,
        touched_at_s: None,
        force_ratio_at_compare: f64::NAN,
        force_above_1pct_until_s: 0.0,
        trace: Vec::new(),
    };
    for k in 0..=steps {
        let (f, g1, g2) = net_force(cap, c, t, z);
        let g = g1.min(g2);
        if g < run.min_gap_m {
            run.min_gap_m = g;
            run.min_gap_at_s = t;
        }
        let ratio = f.abs() / c.authority_n;
        if ratio >= 0.01 {
            run.force_above_1pct_until_s = t;
        }
        if run.force_ratio_at_compare.is_nan() && t >= c.compare_at_s - 0.5 * dt {
            run.force_ratio_at_compare = ratio;
        }
        if keep_trace && k % every == 0 {
            run.trace.push((t, z, v, g1, ratio));
        }
        if g <= 0.0 {
            run.touched_at_s = Some(t);
            break;
        }
        if k == steps {
            break;
        }
        // classical RK4 on (z, v)
        let k1v = acc(t, z);
        let k1z = v;
        let k2v = acc(t + 0.5 * dt, z + 0.5 * dt * k1z);
        let k2z = v + 0.5 * dt * k1v;
        let k3v = acc(t + 0.5 * dt, z + 0.5 * dt * k2z);
        let k3z = v + 0.5 * dt * k2v;
        let k4v = acc(t + dt, z + dt * k3z);
        let k4z = v + dt * k3v;
        let z_new = z + dt / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z);
        let p_new = c.retraction.p_m(t + dt);
        if p_new - z_new.abs() <= 0.0 {
            // the gap closes within this step: a touch; the state before it is kept (the
            // attraction diverges at contact, nothing after it has a meaning)
            let g_now = c.retraction.p_m(t) - z.abs();
            let g_next = p_new - z_new.abs();
            run.touched_at_s = Some(t + dt * g_now / (g_now - g_next));
            run.min_gap_m = 0.0;
            break;
        }
        z = z_new;
        v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        t = (k + 1) as f64 * dt;
    }
    run.extra_velocity_m_s = v - c.v0_m_s;
    run
}

/// Fixed RK4 step [s]: 1 ms resolves the attraction's time scale (the gap opens by tens of nm
/// per step) from the first step on.
pub const STEP_S: f64 = 1e-3;

/// Simulates `case` with the capacitance model `cap`, and again at half the step.
pub fn simulate(cap: &dyn PlungerCapacitance, case: &PlungerCase) -> PlungerRun {
    let mut run = integrate(cap, case, STEP_S, true);
    let half = integrate(cap, case, 0.5 * STEP_S, false);
    run.extra_velocity_half_step_m_s = half.extra_velocity_m_s;
    run
}

/// The thesis's FE capacitance of the pyramidal plunger at contact loss [F].
pub const C_PYR_THESIS_F: f64 = 35e-12;

/// The default capacitance model: the flat disc calibrated to 35 pF at 15 um.
pub fn default_model() -> FlatDisc {
    FlatDisc::calibrated(C_PYR_THESIS_F, Retraction::BASELINE.g0_m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_derivative_and_calibration() {
        let d = default_model();
        assert!((d.c_f(15e-6) - 35e-12).abs() < 1e-16);
        assert!(d.radius_m > 3e-3 && d.radius_m < 5e-3, "{}", d.radius_m);
        for g in [15e-6, 100e-6, 500e-6] {
            let h = g * 1e-5;
            let num = (d.c_f(g + h) - d.c_f(g - h)) / (2.0 * h);
            assert!((num / d.dc_dg_f_m(g) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn sphere_series_converges_to_its_limits() {
        let s = SpherePlane {
            radius_m: 5e-3,
            rel_tol: 1e-12,
        };
        // far away: an isolated sphere 4 pi eps0 R; close: the proximity limit
        // 2 pi eps0 R ln(R / g) + const, whose derivative is -2 pi eps0 R / g
        let (c_far, _, _) = s.series(1.0);
        assert!(
            (c_far / (4.0 * PI * EPS0_F_M * 5e-3) - 1.0).abs() < 0.01,
            "{c_far}"
        );
        let g = 1e-6;
        let (_, dc, n) = s.series(g);
        assert!(
            (dc / (-2.0 * PI * EPS0_F_M * 5e-3 / g) - 1.0).abs() < 0.01,
            "{dc} {n}"
        );
        // the derivative of the series against a finite difference
        let h = 1e-9;
        let num = (s.series(g + h).0 - s.series(g - h).0) / (2.0 * h);
        assert!((num / dc - 1.0).abs() < 1e-4, "{num} {dc}");
        // tighter tolerance, more terms, same value to the looser tolerance
        let loose = SpherePlane { rel_tol: 1e-6, ..s }.series(20e-6);
        let tight = s.series(20e-6);
        assert!(tight.2 > loose.2);
        assert!((loose.0 / tight.0 - 1.0).abs() < 2e-6);
    }

    #[test]
    fn no_voltage_no_effect_and_symmetry() {
        let d = default_model();
        let mut c = PlungerCase {
            mass_kg: 1.96,
            v_tm_v: 0.0,
            v0_m_s: 5e-6,
            retraction: Retraction::BASELINE,
            duration_s: 25.0,
            authority_n: 5e-7,
            compare_at_s: 4.3,
        };
        let r = simulate(&d, &c);
        assert_eq!(r.extra_velocity_m_s, 0.0);
        // a TM at rest in the middle feels equal and opposite pulls: nothing happens
        c.v_tm_v = 1.0;
        c.v0_m_s = 0.0;
        let r = simulate(&d, &c);
        assert!(r.extra_velocity_m_s.abs() < 1e-15);
        // moving towards plunger 1: it is pulled on further (the near side wins)
        c.v0_m_s = 5e-6;
        let r = simulate(&d, &c);
        assert!(r.extra_velocity_m_s > 0.0);
        assert!((r.extra_velocity_m_s / r.extra_velocity_half_step_m_s - 1.0).abs() < 1e-6);
    }
}

#[cfg(test)]
mod touch_tests {
    use super::*;

    #[test]
    fn a_slow_retraction_touches_and_stops_before_the_divergence() {
        // plunger ramp 85 um over 25 s (3.4 um/s) against a TM at 7.5 um/s: the gap closes
        let c = PlungerCase {
            mass_kg: 1.96,
            v_tm_v: 2.0,
            v0_m_s: 7.5e-6,
            retraction: Retraction {
                g0_m: 15e-6,
                g_end_m: 100e-6,
                ramp_s: 25.0,
            },
            duration_s: 25.0,
            authority_n: 5e-7,
            compare_at_s: 4.3,
        };
        let r = simulate(&default_model(), &c);
        let t = r.touched_at_s.expect("a touch");
        // without attraction the gap 15 um closes at 7.5 - 3.4 um/s: about 3.7 s; the pull
        // brings it earlier
        assert!(t > 0.5 && t < 3.7, "{t}");
        assert!(r.extra_velocity_m_s.is_finite() && r.extra_velocity_m_s < 1e-3);
        assert_eq!(r.min_gap_m, 0.0);
    }
}
