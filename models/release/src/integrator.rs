//! ODE integrators behind the [`Integrator`] trait, for switched (piecewise smooth) systems.
//!
//! The release problem (physics.md §3) is a 12-state, non-stiff ODE whose right-hand side has
//! kinks: at known times (end of each voltage ramp) and where a contact elongation `e_i` crosses
//! zero (Hertz on one side, adhesion on the other). [`DormandPrince`] is an adaptive embedded
//! Runge-Kutta 5(4) (Dormand & Prince 1980, the `dopri5` tableau) that steps exactly onto known
//! breakpoints and localises the `e_i = 0` switching events with its cubic Hermite interpolant,
//! so no step straddles a kink. [`Rk4Fixed`] is a fine fixed-step classical RK4 used as an
//! independent reference. A system implements [`SwitchedSystem`]; the simulator does not care
//! which integrator runs it.

use thiserror::Error;

/// Maximum number of switching functions a system may declare.
pub const MAX_SWITCHES: usize = 4;

/// A first-order ODE `y' = f(t, y)` with `N` states, known kink times, state-dependent switching
/// functions (affine in `y`) and a stopping rule.
pub trait SwitchedSystem<const N: usize> {
    /// Writes `f(t, y)` into `dy`.
    fn rhs(&self, t: f64, y: &[f64; N], dy: &mut [f64; N]);

    /// Times [s] where `f` has a kink, sorted ascending.
    fn breakpoints(&self) -> &[f64];

    /// Values of the switching functions (affine in `y`) whose zero crossings are kinks of `f`;
    /// returns how many are used.
    fn switching(&self, y: &[f64; N], g: &mut [f64; MAX_SWITCHES]) -> usize;

    /// Whether to stop after an accepted step ending at `(t, y)` with derivative `dy`.
    fn stop(&self, t: f64, y: &[f64; N], dy: &[f64; N]) -> bool;

    /// Typical magnitudes of the states; absolute tolerances are `atol * scale`.
    fn scales(&self) -> [f64; N];
}

/// Largest number of steps (accepted plus rejected) one integration may attempt: a nominal
/// release takes a few thousand; extreme but finite inputs (a stiffness of 1e19 N/m) would
/// otherwise shrink the step towards 1e-18 s and run for days.
pub const MAX_STEPS: u64 = 2_000_000;

/// Failure of an integration.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum IntegrateError {
    /// The stopping rule did not fire before `t_max`.
    #[error("no stop before t = {t_max_s} s ({steps} steps)")]
    NoStop {
        /// Time limit [s].
        t_max_s: f64,
        /// Steps taken.
        steps: u64,
    },
    /// The step size collapsed.
    #[error("step size too small ({h_s} s) at t = {t_s} s")]
    StepTooSmall {
        /// Step [s].
        h_s: f64,
        /// Time [s].
        t_s: f64,
    },
    /// The step budget ran out: the release is too stiff to resolve (extreme parameters).
    #[error(
        "gave up after {steps} steps at t = {t_s} s (step budget {MAX_STEPS}; the release is too stiff to resolve)"
    )]
    TooManySteps {
        /// Steps attempted.
        steps: u64,
        /// Time reached [s].
        t_s: f64,
    },
    /// The collocation's fixed-point iteration for the contact forces did not converge.
    #[error("contact forces did not converge at t = {t_s} s")]
    NoConvergence {
        /// Time [s].
        t_s: f64,
    },
    /// The state became non-finite.
    #[error("non-finite state at t = {t_s} s")]
    NonFinite {
        /// Time [s].
        t_s: f64,
    },
}

/// Integration statistics.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, schemars::JsonSchema)]
pub struct Stats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps (error too large or retaken onto an event).
    pub rejected: u64,
    /// Right-hand side evaluations.
    pub rhs_evals: u64,
    /// Switching events located.
    pub events: u64,
}

/// End of an integration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solution<const N: usize> {
    /// Time [s] at which the stopping rule fired.
    pub t: f64,
    /// State at `t`.
    pub y: [f64; N],
    /// Statistics.
    pub stats: Stats,
}

/// Something that integrates a [`SwitchedSystem`] from `t = 0` until its stopping rule fires.
pub trait Integrator: Send + Sync {
    /// Short name for reports.
    fn name(&self) -> String;

    /// Integrates from `(0, y0)` until `sys.stop` or `t_max` [s].
    fn solve<const N: usize, S: SwitchedSystem<N>>(
        &self,
        sys: &S,
        y0: [f64; N],
        t_max: f64,
    ) -> Result<Solution<N>, IntegrateError>;
}

// Dormand-Prince 5(4) tableau (Hairer, Norsett & Wanner, Solving ODEs I, Table 5.2).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// Adaptive Dormand-Prince 5(4) with breakpoints and event localisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DormandPrince {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance factor (times each state's scale).
    pub atol: f64,
    /// First step [s].
    pub h0: f64,
    /// Largest step [s].
    pub h_max: f64,
    /// Locate switching events (step onto `g = 0`).
    pub locate_events: bool,
}

impl DormandPrince {
    /// The fast Monte Carlo setting (checked against [`DormandPrince::reference`] in the tests).
    pub fn fast() -> Self {
        Self {
            rtol: 3e-5,
            atol: 3e-5,
            h0: 1e-8,
            h_max: 2e-5,
            locate_events: true,
        }
    }

    /// A tight-tolerance reference setting (rtol = atol factor = 1e-12).
    pub fn reference() -> Self {
        Self {
            rtol: 1e-12,
            atol: 1e-12,
            h0: 1e-10,
            h_max: 2e-6,
            locate_events: true,
        }
    }

    /// A tighter setting (rtol 1e-9) for figures computed from a few hundred releases.
    pub fn reference_fast() -> Self {
        Self {
            rtol: 1e-9,
            atol: 1e-9,
            h0: 1e-9,
            h_max: 2e-5,
            locate_events: true,
        }
    }

    /// A setting with the given tolerances.
    pub fn with_tolerance(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol,
            h0: 1e-8,
            h_max: f64::INFINITY,
            locate_events: true,
        }
    }
}

#[inline(always)]
fn axpy<const N: usize>(out: &mut [f64; N], y: &[f64; N], h: f64, terms: &[(f64, &[f64; N])]) {
    for i in 0..N {
        let mut acc = 0.0;
        for (c, k) in terms {
            acc += c * k[i];
        }
        out[i] = y[i] + h * acc;
    }
}

/// `x^p` for the step-size controller, in single precision (the factor is clamped and
/// safety-scaled; full precision buys nothing and `pow` was 8 % of the Monte Carlo time).
#[inline(always)]
fn powf32(x: f64, p: f32) -> f64 {
    f64::from((x as f32).powf(p))
}

// Step-size control: the PI controller of Hairer's DOPRI5 (beta = 0.04), which rejects fewer
// steps than the plain err^(-1/5) rule on this ringing problem.
const SAFE: f64 = 0.9;
const BETA: f32 = 0.04;
const EXPO1: f32 = 0.2 - 0.75 * BETA;
const FAC_MIN: f64 = 0.2;
const FAC_MAX: f64 = 10.0;

/// Cubic Hermite interpolation of a scalar over a step: values `g0`, `g1`, derivatives times
/// the step `d0`, `d1`, at fraction `th`.
#[inline]
fn hermite(g0: f64, g1: f64, d0: f64, d1: f64, th: f64) -> f64 {
    let th2 = th * th;
    let th3 = th2 * th;
    (2.0 * th3 - 3.0 * th2 + 1.0) * g0
        + (th3 - 2.0 * th2 + th) * d0
        + (-2.0 * th3 + 3.0 * th2) * g1
        + (th3 - th2) * d1
}

/// Root of the Hermite cubic in (0, 1) given a sign change, by the Illinois method.
fn hermite_root(g0: f64, g1: f64, d0: f64, d1: f64) -> f64 {
    let (mut a, mut b) = (0.0, 1.0);
    let (mut fa, mut fb) = (g0, g1);
    let mut side = 0i8;
    for _ in 0..60 {
        let c = (a * fb - b * fa) / (fb - fa);
        let fc = hermite(g0, g1, d0, d1, c);
        if fc == 0.0 || (b - a) < 1e-14 {
            return c;
        }
        if (fc > 0.0) == (fb > 0.0) {
            b = c;
            fb = fc;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            a = c;
            fa = fc;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (a + b)
}

impl Integrator for DormandPrince {
    fn name(&self) -> String {
        format!("dopri5(rtol={:e})", self.rtol)
    }

    fn solve<const N: usize, S: SwitchedSystem<N>>(
        &self,
        sys: &S,
        y0: [f64; N],
        t_max: f64,
    ) -> Result<Solution<N>, IntegrateError> {
        let scales = sys.scales();
        let mut atol = [0.0; N];
        for i in 0..N {
            atol[i] = self.atol * scales[i];
        }
        let bps = sys.breakpoints();
        let mut next_bp = 0usize;
        let mut stats = Stats::default();
        let mut t = 0.0f64;
        let mut y = y0;
        let mut k1 = [0.0; N];
        sys.rhs(t, &y, &mut k1);
        stats.rhs_evals += 1;
        let (mut k2, mut k3, mut k4, mut k5, mut k6, mut k7) =
            ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
        let mut tmp = [0.0; N];
        let mut ynew = [0.0; N];
        let mut g_old = [0.0; MAX_SWITCHES];
        let mut g_new = [0.0; MAX_SWITCHES];
        let mut g_tmp = [0.0; MAX_SWITCHES];
        let ns = sys.switching(&y, &mut g_old);
        let mut h = self.h0;
        // event index whose crossing the current step was shortened to land on
        let mut landing: Option<usize> = None;
        let mut err_old = 1e-4f64;
        let min_h = 1e-18;
        while t < t_max {
            while next_bp < bps.len() && bps[next_bp] <= t * (1.0 + 1e-14) {
                next_bp += 1;
            }
            let mut hit_bp = false;
            if next_bp < bps.len() && t + h >= bps[next_bp] {
                h = bps[next_bp] - t;
                hit_bp = true;
            }
            if h < min_h {
                return Err(IntegrateError::StepTooSmall { h_s: h, t_s: t });
            }
            if stats.accepted + stats.rejected >= MAX_STEPS {
                return Err(IntegrateError::TooManySteps {
                    steps: stats.accepted + stats.rejected,
                    t_s: t,
                });
            }
            // stages
            axpy(&mut tmp, &y, h, &[(A21, &k1)]);
            sys.rhs(t + C2 * h, &tmp, &mut k2);
            axpy(&mut tmp, &y, h, &[(A31, &k1), (A32, &k2)]);
            sys.rhs(t + C3 * h, &tmp, &mut k3);
            axpy(&mut tmp, &y, h, &[(A41, &k1), (A42, &k2), (A43, &k3)]);
            sys.rhs(t + C4 * h, &tmp, &mut k4);
            axpy(
                &mut tmp,
                &y,
                h,
                &[(A51, &k1), (A52, &k2), (A53, &k3), (A54, &k4)],
            );
            sys.rhs(t + C5 * h, &tmp, &mut k5);
            axpy(
                &mut tmp,
                &y,
                h,
                &[(A61, &k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
            );
            let t_new = if hit_bp { bps[next_bp] } else { t + h };
            sys.rhs(t_new, &tmp, &mut k6);
            axpy(
                &mut ynew,
                &y,
                h,
                &[(A71, &k1), (A73, &k3), (A74, &k4), (A75, &k5), (A76, &k6)],
            );
            sys.rhs(t_new, &ynew, &mut k7);
            stats.rhs_evals += 6;
            let mut err2 = 0.0;
            for i in 0..N {
                let e = h
                    * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
                let sc = atol[i] + self.rtol * y[i].abs().max(ynew[i].abs());
                err2 += (e / sc) * (e / sc);
            }
            let err = (err2 / N as f64).sqrt();
            if !err.is_finite() {
                return Err(IntegrateError::NonFinite { t_s: t });
            }
            if err > 1.0 {
                stats.rejected += 1;
                h /= (powf32(err, EXPO1) / SAFE).min(1.0 / FAC_MIN);
                landing = None;
                continue;
            }
            // event localisation: the earliest sign change of a switching function
            sys.switching(&ynew, &mut g_new);
            if self.locate_events && landing.is_none() {
                let mut theta_min = 1.0f64;
                let mut which = None;
                for j in 0..ns {
                    if g_old[j] != 0.0 && (g_old[j] > 0.0) != (g_new[j] > 0.0) {
                        // derivatives of the affine g along the step: g(y + h f) - g(y)
                        axpy(&mut tmp, &y, h, &[(1.0, &k1)]);
                        sys.switching(&tmp, &mut g_tmp);
                        let d0 = g_tmp[j] - g_old[j];
                        axpy(&mut tmp, &ynew, h, &[(1.0, &k7)]);
                        sys.switching(&tmp, &mut g_tmp);
                        let d1 = g_tmp[j] - g_new[j];
                        let th = hermite_root(g_old[j], g_new[j], d0, d1);
                        if th < theta_min {
                            theta_min = th;
                            which = Some(j);
                        }
                    }
                }
                if let Some(j) = which {
                    // land on the event unless it is already at the step's ends
                    if theta_min * h > 1e-15 && theta_min < 1.0 - 1e-9 {
                        stats.rejected += 1;
                        stats.events += 1;
                        h *= theta_min * (1.0 + 1e-10);
                        landing = Some(j);
                        continue;
                    }
                }
            }
            landing = None;
            // accept
            stats.accepted += 1;
            t = t_new;
            y = ynew;
            k1 = k7;
            g_old = g_new;
            if sys.stop(t, &y, &k1) {
                return Ok(Solution { t, y, stats });
            }
            // h_new = h / fac, fac = err^expo1 / err_old^beta / safe within [1/FAC_MAX, 1/FAC_MIN]
            let fac = (powf32(err, EXPO1) / powf32(err_old, BETA) / SAFE)
                .clamp(1.0 / FAC_MAX, 1.0 / FAC_MIN);
            err_old = err.max(1e-4);
            h = (h / fac).min(self.h_max);
        }
        Err(IntegrateError::NoStop {
            t_max_s: t_max,
            steps: stats.accepted,
        })
    }
}

/// Classical fixed-step Runge-Kutta 4, stepping onto breakpoints; a simple independent reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4Fixed {
    /// Step [s].
    pub h: f64,
}

impl Integrator for Rk4Fixed {
    fn name(&self) -> String {
        format!("rk4(h={:e})", self.h)
    }

    fn solve<const N: usize, S: SwitchedSystem<N>>(
        &self,
        sys: &S,
        y0: [f64; N],
        t_max: f64,
    ) -> Result<Solution<N>, IntegrateError> {
        let bps = sys.breakpoints();
        let mut next_bp = 0usize;
        let mut stats = Stats::default();
        let (mut t, mut y) = (0.0f64, y0);
        let (mut k1, mut k2, mut k3, mut k4, mut tmp) =
            ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
        while t < t_max {
            let mut h = self.h;
            while next_bp < bps.len() && bps[next_bp] <= t * (1.0 + 1e-14) {
                next_bp += 1;
            }
            if next_bp < bps.len() && t + h >= bps[next_bp] {
                h = bps[next_bp] - t;
            }
            sys.rhs(t, &y, &mut k1);
            axpy(&mut tmp, &y, 0.5 * h, &[(1.0, &k1)]);
            sys.rhs(t + 0.5 * h, &tmp, &mut k2);
            axpy(&mut tmp, &y, 0.5 * h, &[(1.0, &k2)]);
            sys.rhs(t + 0.5 * h, &tmp, &mut k3);
            axpy(&mut tmp, &y, h, &[(1.0, &k3)]);
            sys.rhs(t + h, &tmp, &mut k4);
            let y_old = y;
            axpy(
                &mut y,
                &y_old,
                h / 6.0,
                &[(1.0, &k1), (2.0, &k2), (2.0, &k3), (1.0, &k4)],
            );
            t += h;
            stats.accepted += 1;
            stats.rhs_evals += 4;
            if !y.iter().all(|v| v.is_finite()) {
                return Err(IntegrateError::NonFinite { t_s: t });
            }
            sys.rhs(t, &y, &mut k1);
            stats.rhs_evals += 1;
            if sys.stop(t, &y, &k1) {
                return Ok(Solution { t, y, stats });
            }
        }
        Err(IntegrateError::NoStop {
            t_max_s: t_max,
            steps: stats.accepted,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Harmonic oscillator with a kink: stiffness k1 for x < 0, k2 for x > 0; stops at t = 10.
    struct Kinked {
        bps: Vec<f64>,
    }
    impl SwitchedSystem<2> for Kinked {
        fn rhs(&self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
            dy[0] = y[1];
            dy[1] = if y[0] < 0.0 { -y[0] } else { -4.0 * y[0] };
        }
        fn breakpoints(&self) -> &[f64] {
            &self.bps
        }
        fn switching(&self, y: &[f64; 2], g: &mut [f64; MAX_SWITCHES]) -> usize {
            g[0] = y[0];
            1
        }
        fn stop(&self, t: f64, _y: &[f64; 2], _dy: &[f64; 2]) -> bool {
            t >= 10.0
        }
        fn scales(&self) -> [f64; 2] {
            [1.0, 1.0]
        }
    }

    /// Exact solution: start at x = -1, v = 0; half period pi/1 on the soft side at amplitude 1,
    /// pi/2 on the stiff side, amplitude 1/2. The period is pi + pi/2.
    fn exact(t: f64) -> f64 {
        let period = 1.5 * std::f64::consts::PI;
        let tau = t % period;
        let half = std::f64::consts::FRAC_PI_2;
        if tau < half {
            -tau.cos()
        } else if tau < half + std::f64::consts::FRAC_PI_2 {
            0.5 * (2.0 * (tau - half)).sin()
        } else {
            tau.sin()
        }
    }

    #[test]
    fn dopri_with_events_is_exact_on_kinked_oscillator() {
        let sys = Kinked { bps: vec![10.0] };
        let sol = DormandPrince::with_tolerance(1e-10, 1e-10)
            .solve(&sys, [-1.0, 0.0], 20.0)
            .unwrap();
        assert!((sol.t - 10.0).abs() < 1e-12);
        assert!(
            (sol.y[0] - exact(10.0)).abs() < 1e-8,
            "{} vs {}",
            sol.y[0],
            exact(10.0)
        );
        assert!(sol.stats.events >= 6, "{:?}", sol.stats);
    }

    #[test]
    fn rk4_reference_agrees() {
        let sys = Kinked { bps: vec![10.0] };
        let sol = Rk4Fixed { h: 1e-4 }.solve(&sys, [-1.0, 0.0], 20.0).unwrap();
        assert!(
            (sol.y[0] - exact(10.0)).abs() < 1e-6,
            "{} vs {}",
            sol.y[0],
            exact(10.0)
        );
    }

    #[test]
    fn no_stop_is_an_error() {
        let sys = Kinked { bps: vec![] };
        let e = DormandPrince::fast()
            .solve(&sys, [-1.0, 0.0], 1.0)
            .unwrap_err();
        assert!(matches!(e, IntegrateError::NoStop { .. }));
    }
}
