//! Exponential Gauss collocation: the release integrator that is exact on the linear mechanisms.
//!
//! Each mechanism is linear (`s' = A s + b_v E(t) + b_f F_c`, thesis ch. 3) and the TM is a free
//! mass; only the two contact forces `F_i = F(e_i)` are nonlinear, and they are small beside the
//! stack forces (the tip rings at 73 kHz on `k_eff` = 1.9e8 N/m; Hertz adds about 4e6 N/m,
//! adhesion at most 1.5e5 N/m) and tiny for the 1.96 kg TM. Over a step `[t, t + h]` the
//! integrator represents the forces (and the command voltage) by their interpolating polynomial
//! at the three Gauss-Legendre nodes and propagates each mechanism through the exact response of
//! its linear system to that polynomial input (modal decomposition `A = V diag(lambda) V^-1`
//! from [`Mechanism::modes`], `phi` functions of `lambda h`), and the TM by integrating the
//! polynomial exactly. The node forces are found by fixed-point iteration (contraction factor
//! about 1e-3: the forces move the tips and the TM by sub-nanometres within a step).
//!
//! The tip's ringing and the voltage ramp are therefore exact whatever the step; what the step
//! must resolve is the force history itself, which the TM velocity integrates by three-point
//! Gauss quadrature (exact for polynomials of degree 5). Steps come from three fixed levels whose
//! transition tables are computed once per release: short steps while a contact is closed, long
//! steps once both bonds are stretching, and fine steps for a step in which a contact opens or
//! closes (the force's slope jumps there: Hertz slope 0, adhesion slope `A1`); such a step is
//! retaken as several steps of the next finer level. The stop rule is the model's own
//! ([`crate::model`]), checked at step ends like Dormand-Prince does.

// Index loops mirror the algebra of the tables: several arrays indexed by the same node, basis
// function or mode.
#![allow(clippy::needless_range_loop)]

use crate::integrator::{IntegrateError, Stats};
use crate::model::{ReleaseModel, ReleaseOutcome, T_MAX_S};
use geodesic_contact::ContactLaw;
use geodesic_mechanism::{Complex64, MECH_STATES, Mechanism, Modes, VoltageCommand};

/// Number of Gauss-Legendre nodes per step.
const S: usize = 3;
/// Gauss-Legendre nodes on [0, 1].
const NODES: [f64; S] = [
    0.5 - 0.387_298_334_620_741_7, // sqrt(15)/10
    0.5,
    0.5 + 0.387_298_334_620_741_7,
];
/// Convergence of the node forces: relative to the largest and absolute [N]. A force error
/// of 1e-9 relative moves `X'` by about 1e-13 m/s per release, far below the integrator's error.
const FORCE_RTOL: f64 = 1e-9;
const FORCE_ATOL_N: f64 = 1e-13;
/// Largest number of fixed-point iterations of one step.
const MAX_ITER: usize = 40;
/// Number of step levels (tail, long, short, fine).
const LEVELS: usize = 4;
const TAIL: usize = 0;
const LONG: usize = 1;
const SHORT: usize = 2;
const FINE: usize = 3;

/// Settings of the exponential Gauss collocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExpGauss {
    /// Long step [s], used once both contacts are open and both voltage ramps have ended.
    pub h_long_s: f64,
    /// Long steps per tail step (used once both bonds have stretched beyond
    /// `tail_from` of their release elongation and are still stretching; 1: no tail level).
    pub long_per_tail: u32,
    /// Fraction of the release elongation (12 lambda) beyond which the tail step is used.
    pub tail_from: f64,
    /// Fraction of the release elongation that ends the tail step once every bond has reached
    /// it (the stopping rule is then met at the long step's resolution).
    pub tail_to: f64,
    /// Short steps per long step (used while a contact is closed).
    pub short_per_long: u32,
    /// Fine steps per short step (a step in which a contact opens or closes is retaken with
    /// them).
    pub fine_per_short: u32,
}

impl Default for ExpGauss {
    fn default() -> Self {
        Self::fast()
    }
}

impl ExpGauss {
    /// The Monte Carlo setting (checked against [`crate::integrator::DormandPrince::reference`]
    /// in the tests): long steps of 7 us, short 1 us, fine 0.25 us, and tail steps of 21 us
    /// while both bonds are stretched beyond half their release elongation (6 lambda: the
    /// adhesion force there is under 1.5 % of `A1 lambda`, a twentieth of its peak) and one is
    /// still under 0.9 of it (the stopping rule is met at the long step's resolution: a tail
    /// level up to the stop delayed the stop of slow releases by half a millisecond, 1.6 times
    /// the tolerance off, tested). Against the rtol 1e-12 reference the worst error is 10.2 % of
    /// the 0.5 % / 0.001 um/s tolerance over 2000 draws of the tests (7.4 % without the tail
    /// level; long step 8 us: 13.5 %, 6 us: 5.6 %) and 17 % over 6 005 draws of the Monte Carlo's
    /// seed 1 (9.1 % without); the tail level takes 15 % off a release's cost there (18.3 to
    /// 15.6 us; tail steps of 14 us: 16.3 us and 9.2 %; 2026-11-26).
    pub fn fast() -> Self {
        Self {
            h_long_s: 7e-6,
            long_per_tail: 3,
            tail_from: 0.5,
            tail_to: 0.9,
            short_per_long: 7,
            fine_per_short: 4,
        }
    }

    /// Short name for reports.
    pub fn name(&self) -> String {
        format!(
            "expgauss3(h={:e} s/{}/{}, tail x{} from {} to {})",
            self.h_long_s,
            self.short_per_long,
            self.fine_per_short,
            self.long_per_tail,
            self.tail_from,
            self.tail_to
        )
    }

    /// One line for the evidence of the checks.
    pub fn description(&self) -> String {
        let h = self.steps();
        let tail = if self.long_per_tail > 1 {
            format!(
                "; {} us while both bonds are beyond {} of their release elongation and one under {}",
                h[TAIL] * 1e6,
                self.tail_from,
                self.tail_to
            )
        } else {
            String::new()
        };
        format!(
            "exponential Gauss collocation (3 nodes), exact on the linear mechanisms; steps {} / {} / {} us (bonds stretching / contact closed / contact opening or closing){tail}",
            h[LONG] * 1e6,
            h[SHORT] * 1e6,
            h[FINE] * 1e6
        )
    }

    fn steps(&self) -> [f64; LEVELS] {
        let short = self.h_long_s / f64::from(self.short_per_long);
        [
            self.h_long_s * f64::from(self.long_per_tail),
            self.h_long_s,
            short,
            short / f64::from(self.fine_per_short),
        ]
    }
}

/// Coefficients `L[l][k]` of the Lagrange basis `l_l(tau) = sum_k L[l][k] tau^k` at the nodes.
fn lagrange() -> [[f64; S]; S] {
    let mut out = [[0.0; S]; S];
    for (l, row) in out.iter_mut().enumerate() {
        // product over j != l of (tau - c_j) / (c_l - c_j)
        let mut poly = [1.0, 0.0, 0.0];
        let mut deg = 0;
        let mut den = 1.0;
        for (j, &cj) in NODES.iter().enumerate() {
            if j == l {
                continue;
            }
            let mut next = [0.0; S];
            for k in 0..=deg {
                next[k] -= cj * poly[k];
                next[k + 1] += poly[k];
            }
            poly = next;
            deg += 1;
            den *= NODES[l] - cj;
        }
        for k in 0..S {
            row[k] = poly[k] / den;
        }
    }
    out
}

/// Values of the Lagrange basis at `tau`.
#[inline]
fn basis_at(lag: &[[f64; S]; S], tau: f64) -> [f64; S] {
    let mut out = [0.0; S];
    for l in 0..S {
        out[l] = lag[l][0] + tau * (lag[l][1] + tau * lag[l][2]);
    }
    out
}

/// `1 / (n + 3)!` for `n = 0..20`.
const INV_FACT3: [f64; 20] = {
    let mut out = [0.0; 20];
    let mut inv = 1.0 / 6.0;
    let mut n = 0;
    while n < 20 {
        out[n] = inv;
        inv /= (n + 4) as f64;
        n += 1;
    }
    out
};

/// `(exp z, phi_1 z, phi_2 z, phi_3 z)` with `phi_k(z) = sum_n z^n / (n + k)!`.
fn phis(z: Complex64) -> [Complex64; 4] {
    phis_many([z])[0]
}

/// Terms of the Taylor series of `phi_3` for `|z|^2 = r2`, `None` at `|z| >= 1` (closed form).
/// The fewest whose first neglected one, `|z|^n / (n + 3)!`, is below 1e-17 of `phi_3` (about
/// 1/6) for every `|z|` of the band: 9 terms up to `|z| = 1/16`, ..., 17 up to 1 (20 before:
/// the series was a fifth of a Monte Carlo release's cost).
#[inline]
fn series_terms(r2: f64) -> Option<usize> {
    // (a NaN takes the closed form, as `r2 < 1` decided before)
    if r2 >= 1.0 || r2.is_nan() {
        None
    } else if r2 < 1.0 / 256.0 {
        Some(9)
    } else if r2 < 1.0 / 64.0 {
        Some(10)
    } else if r2 < 1.0 / 16.0 {
        Some(12)
    } else if r2 < 0.25 {
        Some(14)
    } else {
        Some(17)
    }
}

/// [`phis`] of each of `L` arguments, the same bits as one call each: the series' Horner
/// chains (a dependent complex multiply-add per term, latency-bound) run side by side, each
/// lane over its own terms (perf: the tables' series were an eighth of a Monte Carlo release,
/// one chain at a time).
fn phis_many<const L: usize>(zs: [Complex64; L]) -> [[Complex64; 4]; L] {
    let zero = Complex64::new(0.0, 0.0);
    let mut out = [[zero; 4]; L];
    let mut terms = [0usize; L];
    let mut most = 0;
    for (b, z) in zs.iter().enumerate() {
        match series_terms(z.norm_sqr()) {
            Some(n) => {
                terms[b] = n;
                most = most.max(n);
            }
            None => {
                // one complex reciprocal instead of three divisions
                let e = z.exp();
                let iz = z.inv();
                let p1 = (e - 1.0) * iz;
                let p2 = (p1 - 1.0) * iz;
                let p3 = (p2 - 0.5) * iz;
                out[b] = [e, p1, p2, p3];
            }
        }
    }
    // Taylor series of phi_3, then the stable backward recurrence phi_k = z phi_{k+1} + 1/k!
    let mut p3 = [zero; L];
    for k in (0..most).rev() {
        let c = INV_FACT3[k];
        for b in 0..L {
            if k < terms[b] {
                p3[b] = p3[b] * zs[b] + c;
            }
        }
    }
    for b in 0..L {
        if terms[b] > 0 {
            let z = zs[b];
            let p2 = z * p3[b] + 0.5;
            let p1 = z * p2 + 1.0;
            let e = z * p1 + 1.0;
            out[b] = [e, p1, p2, p3[b]];
        }
    }
    out
}

/// Inverse of a complex 5x5 matrix by Gauss-Jordan elimination with partial pivoting.
fn invert(
    mut a: [[Complex64; MECH_STATES]; MECH_STATES],
) -> Option<[[Complex64; MECH_STATES]; MECH_STATES]> {
    let n = MECH_STATES;
    let mut inv = [[Complex64::new(0.0, 0.0); MECH_STATES]; MECH_STATES];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = Complex64::new(1.0, 0.0);
    }
    for col in 0..n {
        let piv =
            (col..n).max_by(|&i, &j| a[i][col].norm_sqr().total_cmp(&a[j][col].norm_sqr()))?;
        let pivot = a[piv][col].norm_sqr();
        if pivot.is_nan() || pivot <= 1e-26 {
            return None;
        }
        a.swap(col, piv);
        inv.swap(col, piv);
        let d = Complex64::new(1.0, 0.0) / a[col][col];
        for k in 0..n {
            a[col][k] *= d;
            inv[col][k] *= d;
        }
        for i in 0..n {
            if i != col {
                let f = a[i][col];
                if f.re != 0.0 || f.im != 0.0 {
                    for k in 0..n {
                        a[i][k] -= f * a[col][k];
                        inv[i][k] -= f * inv[col][k];
                    }
                }
            }
        }
    }
    Some(inv)
}

/// Modal data of one mechanism. Only one member of each complex conjugate pair of modes is
/// kept, with weight 2 folded into its output rows: the real state is
/// `s = sum over kept modes of Re(weight V[:, m] z_m)`.
#[derive(Debug, Clone, Copy)]
struct Modal {
    n: usize,
    lam: [Complex64; MECH_STATES],
    /// Weighted tip-position and tip-velocity rows of `V`.
    tip_pos: [Complex64; MECH_STATES],
    tip_vel: [Complex64; MECH_STATES],
    /// Rows of `V^-1` of the kept modes (initial state) and the inputs in modal coordinates.
    w: [[Complex64; MECH_STATES]; MECH_STATES],
    beta_f: [Complex64; MECH_STATES],
    beta_v: [Complex64; MECH_STATES],
}

/// Indices of the tip position and velocity in a mechanism's state.
const TIP: usize = 3;
const TIP_VEL: usize = 4;

impl Modal {
    fn new(m: &Modes, scales: &[f64; MECH_STATES]) -> Option<Self> {
        // V_s = D^-1 V with unit columns (max norm): well conditioned; V = D V_s, W = V_s^-1 D^-1
        let mut vs = [[Complex64::new(0.0, 0.0); MECH_STATES]; MECH_STATES];
        let mut col_norm = [0.0f64; MECH_STATES];
        for j in 0..MECH_STATES {
            for i in 0..MECH_STATES {
                vs[i][j] = m.vectors[i][j] / scales[i];
                col_norm[j] = col_norm[j].max(vs[i][j].norm_sqr());
            }
            col_norm[j] = col_norm[j].sqrt();
            if !(col_norm[j] > 0.0 && col_norm[j].is_finite()) {
                return None;
            }
            for row in vs.iter_mut() {
                row[j] /= col_norm[j];
            }
        }
        let ws = invert(vs)?;
        let zero = Complex64::new(0.0, 0.0);
        let mut md = Modal {
            n: 0,
            lam: [zero; MECH_STATES],
            tip_pos: [zero; MECH_STATES],
            tip_vel: [zero; MECH_STATES],
            w: [[zero; MECH_STATES]; MECH_STATES],
            beta_f: [zero; MECH_STATES],
            beta_v: [zero; MECH_STATES],
        };
        let mut taken = [false; MECH_STATES];
        for a in 0..MECH_STATES {
            if taken[a] {
                continue;
            }
            let lam = m.eigenvalues[a];
            let partner = (a + 1..MECH_STATES).find(|&b| {
                !taken[b]
                    && lam.im != 0.0
                    && m.eigenvalues[b] == lam.conj()
                    && (0..MECH_STATES).all(|i| m.vectors[i][b] == m.vectors[i][a].conj())
            });
            let weight = match partner {
                Some(b) => {
                    taken[b] = true;
                    2.0
                }
                None if lam.im == 0.0 => 1.0,
                // a complex mode without its conjugate: the layout is not understood
                None => return None,
            };
            let k = md.n;
            md.lam[k] = lam;
            md.tip_pos[k] = vs[TIP][a] * (scales[TIP] * weight);
            md.tip_vel[k] = vs[TIP_VEL][a] * (scales[TIP_VEL] * weight);
            for c in 0..MECH_STATES {
                md.w[k][c] = ws[a][c] / scales[c];
                md.beta_f[k] += md.w[k][c] * m.b_force[c];
                md.beta_v[k] += md.w[k][c] * m.b_voltage[c];
            }
            md.n += 1;
        }
        Some(md)
    }

    /// Modal coordinates of the real state `s`.
    fn modal_coordinates(&self, s: &[f64; MECH_STATES]) -> [Complex64; MECH_STATES] {
        let mut z = [Complex64::new(0.0, 0.0); MECH_STATES];
        for k in 0..self.n {
            for c in 0..MECH_STATES {
                z[k] += self.w[k][c] * s[c];
            }
        }
        z
    }

    /// Tip position [m] and velocity [m/s] of the modal state `z`.
    #[inline]
    fn tip(&self, z: &[Complex64; MECH_STATES]) -> (f64, f64) {
        let (mut p, mut v) = (0.0, 0.0);
        for k in 0..self.n {
            p += (self.tip_pos[k] * z[k]).re;
            v += (self.tip_vel[k] * z[k]).re;
        }
        (p, v)
    }
}

/// Transition table of one mechanism for one step size, in modal coordinates.
#[derive(Debug, Clone, Copy)]
struct Table {
    /// `exp(lambda h)` per mode.
    decay: [Complex64; MECH_STATES],
    /// Modal response at the step end to a unit force / voltage shaped as Lagrange basis `l`.
    end_f: [[Complex64; MECH_STATES]; S],
    end_v: [[Complex64; MECH_STATES]; S],
    /// Tip position at node `j` per unit modal coordinate (real part of the product).
    rows: [[Complex64; MECH_STATES]; S],
    /// Tip position at node `j` per unit force / voltage in basis `l`.
    g_f: [[f64; S]; S],
    g_v: [[f64; S]; S],
}

impl Table {
    fn new(md: &Modal, h: f64, lag: &[[f64; S]; S]) -> Self {
        let zero = Complex64::new(0.0, 0.0);
        let mut t = Table {
            decay: [zero; MECH_STATES],
            end_f: [[zero; MECH_STATES]; S],
            end_v: [[zero; MECH_STATES]; S],
            rows: [[zero; MECH_STATES]; S],
            g_f: [[0.0; S]; S],
            g_v: [[0.0; S]; S],
        };
        // points: the nodes, then the step end; each mode's four at once
        let mut ph_all = [[[zero; 4]; S + 1]; MECH_STATES];
        for m in 0..md.n {
            let at = |c: f64| md.lam[m] * (c * h);
            ph_all[m] = phis_many([at(NODES[0]), at(NODES[1]), at(NODES[2]), at(1.0)]);
        }
        for p in 0..=S {
            let c = if p < S { NODES[p] } else { 1.0 };
            for m in 0..md.n {
                let ph = ph_all[m][p];
                // psi_l = int_0^{c h} exp(lambda (c h - s)) l_l(s / h) ds from the monomials
                // tau^k: h k! c^(k+1) phi_{k+1}(lambda c h)
                let mono = [
                    ph[1] * (h * c),
                    ph[2] * (h * c * c),
                    ph[3] * (2.0 * h * c * c * c),
                ];
                for l in 0..S {
                    let psi = mono[0] * lag[l][0] + mono[1] * lag[l][1] + mono[2] * lag[l][2];
                    if p < S {
                        let x = md.tip_pos[m] * psi;
                        t.g_f[p][l] += (x * md.beta_f[m]).re;
                        t.g_v[p][l] += (x * md.beta_v[m]).re;
                    } else {
                        t.end_f[l][m] = psi * md.beta_f[m];
                        t.end_v[l][m] = psi * md.beta_v[m];
                    }
                }
                if p < S {
                    t.rows[p][m] = md.tip_pos[m] * ph[0];
                } else {
                    t.decay[m] = ph[0];
                }
            }
        }
        t
    }
}

/// TM coefficients of one step size: displacement at node `j` and at the end, velocity at the
/// end, per unit acceleration in basis `l`.
#[derive(Debug, Clone, Copy)]
struct TmTable {
    x_nodes: [[f64; S]; S],
    x_end: [f64; S],
    v_end: [f64; S],
}

impl TmTable {
    fn new(h: f64, lag: &[[f64; S]; S]) -> Self {
        // int_0^c (c - s) tau^k ds = c^(k+2) / ((k+1)(k+2)); int_0^1 tau^k = 1/(k+1)
        let dbl = |c: f64, l: usize| -> f64 {
            (0..S)
                .map(|k| lag[l][k] * c.powi(k as i32 + 2) / ((k + 1) * (k + 2)) as f64)
                .sum::<f64>()
                * h
                * h
        };
        let mut t = TmTable {
            x_nodes: [[0.0; S]; S],
            x_end: [0.0; S],
            v_end: [0.0; S],
        };
        for l in 0..S {
            for j in 0..S {
                t.x_nodes[j][l] = dbl(NODES[j], l);
            }
            t.x_end[l] = dbl(1.0, l);
            t.v_end[l] = (0..S).map(|k| lag[l][k] / (k + 1) as f64).sum::<f64>() * h;
        }
        t
    }
}

/// The exponential collocation of one release: modal data and lazily built tables.
struct Solver<'a, M: Mechanism, C: ContactLaw> {
    model: &'a ReleaseModel<M, C>,
    commands: [VoltageCommand; 2],
    modal: [Modal; 2],
    lag: [[f64; S]; S],
    h: [f64; LEVELS],
    tables: [[Option<Table>; 2]; LEVELS],
    tm: [Option<TmTable>; LEVELS],
    /// Both mechanisms are the same: one table serves both.
    same: bool,
    ramps_end_s: f64,
    /// Whether the tail level is used, and the elongations [m] beyond which it is.
    tail_on: bool,
    tail_e: [f64; 2],
    tail_end_e: [f64; 2],
    tip0: [f64; 2],
    e0: [f64; 2],
}

/// State of the release between steps.
#[derive(Debug, Clone, Copy)]
struct State {
    t: f64,
    /// Modal coordinates of the two mechanisms.
    z: [[Complex64; MECH_STATES]; 2],
    /// TM position [m] and velocity [m/s].
    x: f64,
    v: f64,
    /// Elongations [m] and their rates [m/s].
    e: [f64; 2],
    de: [f64; 2],
}

/// A tried step (its end state is written into the caller's spare [`State`]: the run keeps
/// two and alternates, instead of copying 216 bytes twice per step; perf put a tenth of a
/// Monte Carlo release in those copies).
struct Trial {
    forces: [[f64; S]; 2],
    /// A contact opened or closed within the step.
    kink: bool,
    evals: u64,
}

impl<'a, M: Mechanism, C: ContactLaw> Solver<'a, M, C> {
    fn new(model: &'a ReleaseModel<M, C>, cfg: &ExpGauss) -> Option<Self> {
        let modes = [model.mechanisms[0].modes()?, model.mechanisms[1].modes()?];
        let scales = [
            model.mechanisms[0].state_scales(),
            model.mechanisms[1].state_scales(),
        ];
        let same = modes[0] == modes[1] && scales[0] == scales[1];
        let m0 = Modal::new(&modes[0], &scales[0])?;
        let m1 = if same {
            m0
        } else {
            Modal::new(&modes[1], &scales[1])?
        };
        let h = cfg.steps();
        if !h.iter().all(|x| x.is_finite() && *x > 0.0) {
            return None;
        }
        let ramps_end_s = modes
            .iter()
            .map(|m| {
                let t = m.command.ramp_end_s();
                if t.is_finite() { t.max(0.0) } else { 0.0 }
            })
            .fold(0.0, f64::max);
        Some(Self {
            model,
            commands: [modes[0].command, modes[1].command],
            modal: [m0, m1],
            lag: lagrange(),
            h,
            tables: [[None; 2]; LEVELS],
            tm: [None; LEVELS],
            same,
            ramps_end_s,
            tail_on: cfg.long_per_tail > 1,
            tail_e: model.open_m().map(|o| o * cfg.tail_from),
            tail_end_e: model.open_m().map(|o| o * cfg.tail_to),
            tip0: model.tip0(),
            e0: model.e0(),
        })
    }

    fn ensure(&mut self, level: usize) {
        if self.tables[level][0].is_none() {
            let t0 = Table::new(&self.modal[0], self.h[level], &self.lag);
            let t1 = if self.same {
                t0
            } else {
                Table::new(&self.modal[1], self.h[level], &self.lag)
            };
            self.tables[level] = [Some(t0), Some(t1)];
            self.tm[level] = Some(TmTable::new(self.h[level], &self.lag));
        }
    }

    /// Elongations and their rates from the modal state and the TM.
    #[inline]
    fn contact_state(
        &self,
        z: &[[Complex64; MECH_STATES]; 2],
        x: f64,
        v: f64,
    ) -> ([f64; 2], [f64; 2]) {
        let (p0, v0) = self.modal[0].tip(&z[0]);
        let (p1, v1) = self.modal[1].tip(&z[1]);
        (
            [
                x - (p0 - self.tip0[0]) + self.e0[0],
                -x - (p1 - self.tip0[1]) + self.e0[1],
            ],
            [v - v0, -v - v1],
        )
    }

    /// Exact modal response of mechanism `i`, a time `d` [s] after the end of its voltage
    /// ramp, to the input `em (t - t_r)_+`: `d^2 phi_2(lambda d) em beta_v` per mode.
    fn ramp_response(&self, i: usize, d: f64) -> [Complex64; MECH_STATES] {
        let mut out = [Complex64::new(0.0, 0.0); MECH_STATES];
        if d > 0.0 {
            let md = &self.modal[i];
            let em = self.commands[i].slope_v_s;
            for m in 0..md.n {
                out[m] = phis(md.lam[m] * d)[2] * (d * d * em) * md.beta_v[m];
            }
        }
        out
    }

    /// The voltages at the nodes of a step of `h` from `st`, the free tip positions (the state's
    /// and the voltage's response, no contact force), and where a voltage ramp ends inside the
    /// step (time after the step's start) [V, m, s].
    #[allow(clippy::type_complexity)]
    fn free_response(
        &self,
        tabs: [&Table; 2],
        st: &State,
        h: f64,
    ) -> ([[f64; S]; 2], [[f64; S]; 2], [Option<f64>; 2]) {
        let mut volt = [[0.0; S]; 2];
        let mut y_free = [[0.0; S]; 2];
        // a voltage ramp ending inside the step: E(t) = (E0 - em t) + em (t - t_r)_+, the
        // first term through the basis, the second by its exact response
        let mut ramp_end: [Option<f64>; 2] = [None; 2];
        for i in 0..2 {
            let cmd = &self.commands[i];
            let tr = cmd.ramp_end_s();
            let inside = tr > st.t && tr < st.t + h;
            if inside {
                ramp_end[i] = Some(tr - st.t);
            }
            let active = inside || cmd.voltage_v(st.t) != 0.0 || cmd.voltage_v(st.t + h) != 0.0;
            let md = &self.modal[i];
            for j in 0..S {
                let tj = st.t + NODES[j] * h;
                if active {
                    volt[i][j] = if inside {
                        cmd.e0_v - cmd.slope_v_s * tj
                    } else {
                        cmd.voltage_v(tj)
                    };
                }
                let mut acc = 0.0;
                for m in 0..md.n {
                    acc += (tabs[i].rows[j][m] * st.z[i][m]).re;
                }
                if active {
                    for l in 0..S {
                        acc += tabs[i].g_v[j][l] * volt[i][l];
                    }
                }
                if let Some(dt) = ramp_end[i] {
                    let r = self.ramp_response(i, NODES[j] * h - dt);
                    acc += (0..md.n).map(|m| (md.tip_pos[m] * r[m]).re).sum::<f64>();
                }
                y_free[i][j] = acc;
            }
        }
        (volt, y_free, ramp_end)
    }

    /// One collocation step of `level` from `st`, with node forces predicted by `guess`; the
    /// state at its end is written into `next`.
    fn step(
        &mut self,
        level: usize,
        st: &State,
        guess: &[[f64; S]; 2],
        next: &mut State,
    ) -> Result<Trial, IntegrateError> {
        self.ensure(level);
        let h = self.h[level];
        let (Some(tab0), Some(tab1), Some(tm)) = (
            self.tables[level][0].as_ref(),
            self.tables[level][1].as_ref(),
            self.tm[level].as_ref(),
        ) else {
            unreachable!("tables are built by ensure")
        };
        let tabs = [tab0, tab1];
        let inv_mass = 1.0 / self.model.tm_mass_kg;
        // voltages at the nodes and free tip positions (state + voltage)
        let (volt, y_free, ramp_end) = self.free_response(tabs, st, h);
        let mut x_free = [0.0; S];
        for j in 0..S {
            x_free[j] = st.x + st.v * NODES[j] * h;
        }
        let contacts = &self.model.contacts;
        let mut f = *guess;
        let mut e = [[0.0; S]; 2];
        let mut evals = 0u64;
        let mut converged = false;
        let mut diff_prev = f64::INFINITY;
        for _ in 0..MAX_ITER {
            // TM acceleration in basis l: (-F_1 + F_2) / M; mechanism input F_c,i = -F_i
            let mut x = x_free;
            for j in 0..S {
                for l in 0..S {
                    x[j] += tm.x_nodes[j][l] * (f[1][l] - f[0][l]) * inv_mass;
                }
            }
            for i in 0..2 {
                for j in 0..S {
                    let mut y = y_free[i][j];
                    for l in 0..S {
                        y -= tabs[i].g_f[j][l] * f[i][l];
                    }
                    let xi = if i == 0 { x[j] } else { -x[j] };
                    e[i][j] = xi - (y - self.tip0[i]) + self.e0[i];
                }
            }
            let mut diff = 0.0f64;
            let mut size = 0.0f64;
            for i in 0..2 {
                for j in 0..S {
                    let fnew = contacts[i].force_n(e[i][j]);
                    diff = diff.max((fnew - f[i][j]).abs());
                    size = size.max(fnew.abs());
                    f[i][j] = fnew;
                }
            }
            evals += S as u64;
            // the iteration contracts by rho = diff / diff_prev: the error left after this
            // update is about rho * diff (stop without a confirming iteration)
            let tol = FORCE_RTOL * size + FORCE_ATOL_N;
            let rho = if diff_prev.is_finite() && diff_prev > 0.0 {
                (diff / diff_prev).min(1.0)
            } else {
                1.0
            };
            if diff <= tol || (rho < 0.1 && rho * diff <= tol) {
                converged = true;
                break;
            }
            diff_prev = diff;
        }
        if !converged {
            return Err(IntegrateError::NoConvergence { t_s: st.t });
        }
        let z = &mut next.z;
        for i in 0..2 {
            let md = &self.modal[i];
            let tab = tabs[i];
            let ramp = ramp_end[i].map(|dt| self.ramp_response(i, h - dt));
            for m in 0..md.n {
                let mut acc = tab.decay[m] * st.z[i][m];
                for l in 0..S {
                    acc += tab.end_v[l][m] * volt[i][l] - tab.end_f[l][m] * f[i][l];
                }
                if let Some(r) = &ramp {
                    acc += r[m];
                }
                z[i][m] = acc;
            }
            // modes not kept (conjugates) stay as they were
            z[i][md.n..].copy_from_slice(&st.z[i][md.n..]);
        }
        let mut dx = 0.0;
        let mut dv = 0.0;
        for l in 0..S {
            let a = (f[1][l] - f[0][l]) * inv_mass;
            dx += tm.x_end[l] * a;
            dv += tm.v_end[l] * a;
        }
        let x = st.x + st.v * h + dx;
        let v = st.v + dv;
        let (e_end, de_end) = self.contact_state(&next.z, x, v);
        if !(v.is_finite() && x.is_finite() && e_end.iter().chain(&de_end).all(|q| q.is_finite())) {
            return Err(IntegrateError::NonFinite { t_s: st.t });
        }
        let mut kink = false;
        for i in 0..2 {
            let open = st.e[i] > 0.0;
            kink |= (e_end[i] > 0.0) != open || e[i].iter().any(|&q| (q > 0.0) != open);
        }
        next.t = st.t + h;
        next.x = x;
        next.v = v;
        next.e = e_end;
        next.de = de_end;
        Ok(Trial {
            forces: f,
            kink,
            evals,
        })
    }

    fn run(&mut self) -> Result<ReleaseOutcome, IntegrateError> {
        let y0 = self.model.initial_state();
        let s0: [f64; MECH_STATES] = y0[..MECH_STATES].try_into().expect("mechanism 1");
        let s1: [f64; MECH_STATES] = y0[MECH_STATES..2 * MECH_STATES]
            .try_into()
            .expect("mechanism 2");
        let z = [
            self.modal[0].modal_coordinates(&s0),
            self.modal[1].modal_coordinates(&s1),
        ];
        let (x, v) = (y0[2 * MECH_STATES], y0[2 * MECH_STATES + 1]);
        let (e, de) = self.contact_state(&z, x, v);
        // the current state and the spare one the next step is written into, alternating
        let st0 = State {
            t: 0.0,
            z,
            x,
            v,
            e,
            de,
        };
        let mut states = [st0, st0];
        let mut k = 0;
        let mut stats = Stats::default();
        let f0 = self.model.contact_forces_n(&y0);
        // the last accepted step: start, length and node forces (predictor by extrapolation)
        let mut prev: Option<(f64, f64, [[f64; S]; 2])> = None;
        let mut base = SHORT;
        let mut cur = SHORT;
        // steps left at each level before its parent step is complete
        let mut remaining = [0u32; LEVELS];
        let per_parent = [
            0,
            (self.h[TAIL] / self.h[LONG]).round() as u32,
            (self.h[LONG] / self.h[SHORT]).round() as u32,
            (self.h[SHORT] / self.h[FINE]).round() as u32,
        ];
        while states[k].t < T_MAX_S {
            let (st, next) = {
                let (a, b) = states.split_at_mut(1);
                if k == 0 {
                    (&a[0], &mut b[0])
                } else {
                    (&b[0], &mut a[0])
                }
            };
            let h = self.h[cur];
            let guess = match prev {
                Some((tp, hp, fp)) => {
                    let mut g = [[0.0; S]; 2];
                    for j in 0..S {
                        let b = basis_at(&self.lag, (st.t + NODES[j] * h - tp) / hp);
                        for i in 0..2 {
                            g[i][j] = b[0] * fp[i][0] + b[1] * fp[i][1] + b[2] * fp[i][2];
                        }
                    }
                    g
                }
                None => [[f0[0]; S], [f0[1]; S]],
            };
            let trial = self.step(cur, st, &guess, next)?;
            stats.rhs_evals += trial.evals;
            if trial.kink && cur < FINE {
                stats.rejected += 1;
                stats.events += 1;
                cur += 1;
                remaining[cur] = per_parent[cur];
                continue;
            }
            stats.accepted += 1;
            prev = Some((st.t, h, trial.forces));
            k ^= 1;
            let st = &states[k];
            if self.model.stop_rule(st.t, st.e, st.de) {
                return Ok(self.model.outcome_at(st.t, st.e, st.de, st.v, stats));
            }
            // pop the levels whose parent step is complete
            while cur > base {
                remaining[cur] -= 1;
                if remaining[cur] > 0 {
                    break;
                }
                cur -= 1;
            }
            if base == SHORT
                && cur == SHORT
                && st.t >= self.ramps_end_s
                && st.e[0] > 0.0
                && st.e[1] > 0.0
            {
                base = LONG;
                cur = LONG;
            }
            // the tail level between the bonds' tail_from and tail_to of their release
            // elongations: the stopping rule is met at the long step's resolution
            if (base == LONG || base == TAIL) && cur == base && self.tail_on {
                let tail = (0..2).all(|i| st.e[i] > self.tail_e[i] && st.de[i] > 0.0)
                    && (0..2).any(|i| st.e[i] < self.tail_end_e[i]);
                base = if tail { TAIL } else { LONG };
                cur = base;
            }
        }
        Err(IntegrateError::NoStop {
            t_max_s: T_MAX_S,
            steps: stats.accepted,
        })
    }
}

impl<M: Mechanism, C: ContactLaw> ReleaseModel<M, C> {
    /// Simulates the release with the exponential Gauss collocation; `None` when a mechanism
    /// gives no modal decomposition (use [`ReleaseModel::simulate`] with Dormand-Prince then).
    pub fn simulate_expgauss(
        &self,
        cfg: &ExpGauss,
    ) -> Option<Result<ReleaseOutcome, IntegrateError>> {
        let mut solver = Solver::new(self, cfg)?;
        Some(solver.run())
    }
}

#[cfg(test)]
mod tests;
