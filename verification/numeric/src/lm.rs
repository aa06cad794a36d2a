//! Levenberg-Marquardt least squares with box bounds and a finite-difference Jacobian (or the
//! exact one, when the residuals offer it: [`Residuals::jacobian`]).
//!
//! Minimises `sum r_i(u)^2` over internal coordinates `u` (log or scaled parameters, see
//! the fitting engine). Bounds are enforced by projecting each trial step onto the box. The
//! `levenberg-marquardt` crate was not used because it has no bounds and our residuals come
//! from an ODE whose Jacobian is taken by finite differences anyway; this 100-line solver keeps
//! the damping, projection and stopping rules in one readable place.

use nalgebra::{DMatrix, DVector};

use crate::observe::{ITERATION_SAMPLES, Observer, Silent};
use rayon::prelude::*;

/// A residual function of the internal coordinates `u`, with a form for several points at
/// once (a Jacobian's columns): a model may evaluate those together faster than one by one
/// (the TMMF model interleaves several integrations in one thread). Every closure
/// `Fn(&[f64]) -> Vec<f64>` is one, evaluating a set in parallel.
pub trait Residuals: Sync {
    /// The residuals at `u`.
    fn eval(&self, u: &[f64]) -> Vec<f64>;
    /// The residuals at each point of `us`, in order, the same bits as [`Residuals::eval`]
    /// at each.
    fn eval_many(&self, us: &[Vec<f64>]) -> Vec<Vec<f64>> {
        us.par_iter().map(|u| self.eval(u)).collect()
    }
    /// Whether [`Residuals::jacobian`] gives the exact Jacobian (then [`minimize`] uses it
    /// instead of finite differences, and needs no difference steps).
    fn has_jacobian(&self) -> bool {
        false
    }
    /// The exact Jacobian's columns at `u`, one vector per entry of `u`, if the residuals have
    /// one ([`Residuals::has_jacobian`]); `None` by default.
    fn jacobian(&self, _u: &[f64]) -> Option<Vec<Vec<f64>>> {
        None
    }
}

impl<F: Fn(&[f64]) -> Vec<f64> + Sync> Residuals for F {
    fn eval(&self, u: &[f64]) -> Vec<f64> {
        self(u)
    }
}

/// Options of [`minimize`].
#[derive(Clone, Copy)]
pub struct LmOptions<'a> {
    /// Maximum number of Jacobian evaluations.
    pub max_iter: usize,
    /// Stop when the relative decrease of the cost falls below this.
    pub ftol: f64,
    /// Stop when the decrease of the cost (in its own units) falls below this; 0 disables it.
    /// A profile likelihood compares costs against a threshold of about one unit of chi-square,
    /// so it needs them to a small fraction of a unit, not to `ftol` of a large total.
    pub atol: f64,
    /// Largest forward-difference step in internal coordinates; each parameter's step is
    /// halved from it until the difference is linear ([`fd_steps`]).
    pub fd_step: f64,
    /// Receives a progress line per iteration on records of [`ITERATION_SAMPLES`] residuals
    /// or more (default: [`Silent`]); it never changes the iterates.
    pub observer: &'a dyn Observer,
}

impl Default for LmOptions<'_> {
    fn default() -> Self {
        LmOptions {
            max_iter: 200,
            ftol: 1e-10,
            atol: 0.0,
            fd_step: 1e-3,
            observer: &Silent,
        }
    }
}

impl std::fmt::Debug for LmOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LmOptions")
            .field("max_iter", &self.max_iter)
            .field("ftol", &self.ftol)
            .field("atol", &self.atol)
            .field("fd_step", &self.fd_step)
            .finish_non_exhaustive()
    }
}

/// Result of [`minimize`].
#[derive(Debug, Clone)]
pub struct LmResult {
    /// Best point found.
    pub u: Vec<f64>,
    /// Cost `sum r^2` at `u`.
    pub cost: f64,
    /// Residuals at `u`.
    pub r: Vec<f64>,
    /// Iterations used.
    pub iterations: usize,
}

/// Forward-difference Jacobian columns of `f` at `u` (`r0 = f(u)`), one vector per entry of `u`
/// (the layout the normal equations read without a transposed copy), with the step `h[k]` for
/// entry `k` (see [`fd_steps`]).
///
/// The columns are evaluated as one set ([`Residuals::eval_many`]: in parallel, or together by
/// the model); each column's arithmetic is the same however they are evaluated.
pub fn jacobian_columns<F: Residuals + ?Sized>(
    f: &F,
    u: &[f64],
    r0: &[f64],
    lo: &[f64],
    hi: &[f64],
    h: &[f64],
) -> Vec<Vec<f64>> {
    let steps: Vec<f64> = (0..u.len())
        .map(|k| away_from_bound(u[k], h[k], lo[k], hi[k]))
        .collect();
    let points: Vec<Vec<f64>> = (0..u.len())
        .map(|k| {
            let mut up = u.to_vec();
            up[k] = u[k] + steps[k];
            up
        })
        .collect();
    let mut cols = f.eval_many(&points);
    for (c, step) in cols.iter_mut().zip(&steps) {
        for (ci, r) in c.iter_mut().zip(r0) {
            *ci = (*ci - r) / step;
        }
    }
    cols
}

/// Central-difference Jacobian columns of `f` at `u` (`r0 = f(u)`), with the step `h[k]` for
/// entry `k`: `(f(u + h e_k) - f(u - h e_k)) / 2h`, one-sided (as [`jacobian_columns`]) where
/// `u - h` or `u + h` would leave `[lo, hi]`.
///
/// The uncertainty stage uses it: a forward difference carries the curvature term
/// `h/2 d2f/du2`, which along a direction the data resolve only weakly can rival the
/// direction's own slope and move with the step, so that a weak direction looks like a symmetry
/// (the step test of `crate::identify::symmetries` halves the steps). The central difference's
/// error is of order `h^2 d3f/du3`: the slope of a resolved direction stays put when the step is
/// halved, while the slope along an exact symmetry still falls with it.
pub fn jacobian_columns_central<F: Residuals + ?Sized>(
    f: &F,
    u: &[f64],
    r0: &[f64],
    lo: &[f64],
    hi: &[f64],
    h: &[f64],
) -> Vec<Vec<f64>> {
    let n = u.len();
    let central: Vec<bool> = (0..n)
        .map(|k| u[k] - h[k] >= lo[k] && u[k] + h[k] <= hi[k])
        .collect();
    let mut points: Vec<Vec<f64>> = Vec::with_capacity(2 * n);
    for k in 0..n {
        let mut up = u.to_vec();
        up[k] = u[k] + away_from_bound(u[k], h[k], lo[k], hi[k]);
        points.push(up);
    }
    for k in (0..n).filter(|&k| central[k]) {
        let mut down = u.to_vec();
        down[k] = u[k] - h[k];
        points.push(down);
    }
    let evals = f.eval_many(&points);
    let (ups, downs) = evals.split_at(n);
    let mut downs = downs.iter();
    (0..n)
        .map(|k| {
            if central[k] {
                let down = downs.next().expect("a backward point per central entry");
                ups[k]
                    .iter()
                    .zip(down)
                    .map(|(a, b)| (a - b) / (2.0 * h[k]))
                    .collect()
            } else {
                let step = away_from_bound(u[k], h[k], lo[k], hi[k]);
                ups[k].iter().zip(r0).map(|(a, r)| (a - r) / step).collect()
            }
        })
        .collect()
}

/// `h`, or `-h` when `u + h` would cross an active upper bound.
fn away_from_bound(u: f64, h: f64, lo: f64, hi: f64) -> f64 {
    if u + h > hi && u - h >= lo { -h } else { h }
}

/// Most halvings of a finite-difference step in [`fd_steps`] (1e-3 becomes 1e-3 / 2^20, 1e-9).
const FD_HALVINGS: usize = 20;

/// Largest relative departure from linearity of a forward difference that [`fd_steps`] accepts.
const FD_LINEARITY: f64 = 0.05;

/// Forward-difference steps for the Jacobian of `f` at `u` (`r0 = f(u)`): for each entry, the
/// largest of `h0, h0/2, h0/4, ...` over which the residuals change linearly.
///
/// Why: a fixed step fails where a parameter moves the residuals far beyond the linear regime.
/// In a long record of a lightly damped oscillation (a 1 s retraction record holds thousands of
/// plunger cycles) a 0.1 % change of a stiffness turns the phase at the end by radians: the
/// forward difference is then no derivative at all, the Gauss-Newton step is wrong, and
/// Levenberg-Marquardt crawls for hundreds of iterations. The test compares the differences over
/// `h` and `h/2`: with `d(h) = f(u + h e_k) - r0`, linearity means `d(h) = 2 d(h/2)`, and
/// `|d(h) - 2 d(h/2)| / |d(h)|` estimates the relative error of the difference quotient (its
/// first-order truncation term). A step is accepted when that is below 5 %; a parameter that
/// does not move the residuals keeps `h0`. Cost: two or more extra evaluations per parameter,
/// once per [`minimize`] call. A model whose residuals move linearly over `h0` (the TMMF
/// fits of the public examples) keeps exactly the steps it had.
pub fn fd_steps<F: Residuals + ?Sized>(
    f: &F,
    u: &[f64],
    r0: &[f64],
    lo: &[f64],
    hi: &[f64],
    h0: f64,
) -> Vec<f64> {
    // the differences at step `h` of the entries `ks`, evaluated as one set
    let diffs = |ks: &[usize], h: &[f64]| -> Vec<Vec<f64>> {
        let points: Vec<Vec<f64>> = ks
            .iter()
            .map(|&k| {
                let mut up = u.to_vec();
                up[k] = u[k] + away_from_bound(u[k], h[k], lo[k], hi[k]);
                up
            })
            .collect();
        let mut d = f.eval_many(&points);
        for dk in &mut d {
            for (di, r) in dk.iter_mut().zip(r0) {
                *di -= r;
            }
        }
        d
    };
    // every entry halves its own step, all entries still halving in one round
    let n = u.len();
    let mut h = vec![h0; n];
    let all: Vec<usize> = (0..n).collect();
    let mut d_h = diffs(&all, &h);
    let mut pending = all;
    for _ in 0..FD_HALVINGS {
        pending.retain(|&k| {
            let norm: f64 = d_h[k].iter().map(|v| v * v).sum::<f64>().sqrt();
            norm > 0.0 && norm.is_finite()
        });
        if pending.is_empty() {
            break;
        }
        let half: Vec<f64> = h.iter().map(|v| v / 2.0).collect();
        let d_half = diffs(&pending, &half);
        let mut next = Vec::new();
        for (&k, dh2) in pending.iter().zip(d_half) {
            let norm: f64 = d_h[k].iter().map(|v| v * v).sum::<f64>().sqrt();
            let dev: f64 = d_h[k]
                .iter()
                .zip(&dh2)
                .map(|(a, b)| (a - 2.0 * b) * (a - 2.0 * b))
                .sum::<f64>()
                .sqrt();
            if dev > FD_LINEARITY * norm {
                h[k] /= 2.0;
                d_h[k] = dh2;
                next.push(k);
            }
        }
        pending = next;
    }
    h
}

/// `J^T J` and `J^T r` from the columns of `J`: one pass of dot products, no `n x k` matrix
/// (the record can hold a million samples).
///
/// On a long record the dot products (each on its own, so the same bits) are spread over the
/// threads: with the model's evaluations spread too, they were the serial part of a long fit's
/// iteration.
pub fn normal_equations(cols: &[Vec<f64>], r: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let n = cols.len();
    let mut a = DMatrix::zeros(n, n);
    let mut g = DVector::zeros(n);
    // (k, l) with l <= k for `J^T J`, (k, n) for `J^T r`
    let pairs: Vec<(usize, usize)> = (0..n)
        .flat_map(|k| (0..=k).map(move |l| (k, l)).chain(std::iter::once((k, n))))
        .collect();
    let col = |l: usize| if l == n { r } else { &cols[l][..] };
    let dots: Vec<f64> = if r.len() * pairs.len() >= PARALLEL_DOTS {
        pairs
            .par_iter()
            .map(|&(k, l)| dot(&cols[k], col(l)))
            .collect()
    } else {
        pairs.iter().map(|&(k, l)| dot(&cols[k], col(l))).collect()
    };
    for (&(k, l), d) in pairs.iter().zip(dots) {
        if l == n {
            g[k] = d;
        } else {
            a[(k, l)] = d;
            a[(l, k)] = d;
        }
    }
    (a, g)
}

/// Multiply-adds from which [`normal_equations`] spreads its dot products over the threads
/// (a 2 000-sample fit's stay in one: there the fits themselves run side by side).
const PARALLEL_DOTS: usize = 1 << 20;

/// Dot product with four partial sums (vectorises; the summation order is fixed, so results do
/// not depend on the thread count).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut s = [0.0f64; 4];
    let (ca, ra) = a.as_chunks::<4>();
    let (cb, rb) = b.as_chunks::<4>();
    for (x, y) in ca.iter().zip(cb) {
        for i in 0..4 {
            s[i] += x[i] * y[i];
        }
    }
    let mut t = (s[0] + s[1]) + (s[2] + s[3]);
    for (x, y) in ra.iter().zip(rb) {
        t += x * y;
    }
    t
}

fn cost_of(r: &[f64]) -> f64 {
    let c: f64 = r.iter().map(|v| v * v).sum();
    if c.is_finite() { c } else { f64::INFINITY }
}

/// Minimises `sum f(u)^2` from `u0` within `[lo, hi]`.
pub fn minimize<F: Residuals + ?Sized>(
    f: &F,
    u0: &[f64],
    lo: &[f64],
    hi: &[f64],
    opts: &LmOptions,
) -> LmResult {
    minimize_with_steps(f, u0, lo, hi, opts, None)
}

/// [`minimize`] with the finite-difference steps given (from [`fd_steps`] at a nearby point:
/// a profile likelihood makes dozens of short fits around one optimum) instead of chosen at
/// `u0`.
pub fn minimize_with_steps<F: Residuals + ?Sized>(
    f: &F,
    u0: &[f64],
    lo: &[f64],
    hi: &[f64],
    opts: &LmOptions,
    steps: Option<&[f64]>,
) -> LmResult {
    let mut run = LmRun::new(f, u0, lo, hi, opts, steps);
    run.advance(f, lo, hi, opts, opts.max_iter);
    run.result()
}

/// A [`minimize`] run that can be advanced in rounds: its iterates are those of one
/// [`minimize_with_steps`] call, bit for bit, however its iterations are split. A caller
/// refining several starts can then look at them between rounds (and stop those that cannot
/// catch up with the best, the fitting engine's refinement).
#[derive(Debug, Clone)]
pub struct LmRun {
    u: Vec<f64>,
    r: Vec<f64>,
    cost: f64,
    mu: f64,
    iterations: usize,
    small: usize,
    steps: Vec<f64>,
    finished: bool,
}

impl LmRun {
    /// The run at `u0` clamped to the bounds (one evaluation, and the difference steps of
    /// [`fd_steps`] unless `steps` are given); no iteration yet.
    pub fn new<F: Residuals + ?Sized>(
        f: &F,
        u0: &[f64],
        lo: &[f64],
        hi: &[f64],
        opts: &LmOptions,
        steps: Option<&[f64]>,
    ) -> LmRun {
        let u: Vec<f64> = u0
            .iter()
            .zip(lo.iter().zip(hi))
            .map(|(v, (l, h))| v.clamp(*l, *h))
            .collect();
        let r = f.eval(&u);
        let cost = cost_of(&r);
        let finished = u.is_empty() || !cost.is_finite();
        let steps = match (finished, steps) {
            (true, _) => Vec::new(),
            (false, Some(h)) => h.to_vec(),
            (false, None) if f.has_jacobian() => Vec::new(),
            (false, None) => fd_steps(f, &u, &r, lo, hi, opts.fd_step),
        };
        LmRun {
            u,
            r,
            cost,
            mu: 1e-3,
            iterations: 0,
            small: 0,
            steps,
            finished,
        }
    }

    /// Iterates until the run has made `until` iterations in all (at most `opts.max_iter`) or
    /// has converged or stalled.
    pub fn advance<F: Residuals + ?Sized>(
        &mut self,
        f: &F,
        lo: &[f64],
        hi: &[f64],
        opts: &LmOptions,
        until: usize,
    ) {
        let n = self.u.len();
        let until = until.min(opts.max_iter);
        while !self.finished && self.iterations < until {
            self.iterations += 1;
            let cols = match f.jacobian(&self.u) {
                Some(cols) => cols,
                None => {
                    if self.steps.len() != n {
                        self.steps = fd_steps(f, &self.u, &self.r, lo, hi, opts.fd_step);
                    }
                    jacobian_columns(f, &self.u, &self.r, lo, hi, &self.steps)
                }
            };
            let (a, g) = normal_equations(&cols, &self.r);
            drop(cols);
            let diag: Vec<f64> = (0..n)
                .map(|k| a[(k, k)].max(1e-12 * (1.0 + a.max())))
                .collect();
            let mut accepted = false;
            for _ in 0..12 {
                let mut m = a.clone();
                for k in 0..n {
                    m[(k, k)] += self.mu * diag[k];
                }
                let Some(delta) = m.cholesky().map(|c| c.solve(&(-&g))) else {
                    self.mu *= 10.0;
                    continue;
                };
                let trial: Vec<f64> = (0..n)
                    .map(|k| (self.u[k] + delta[k]).clamp(lo[k], hi[k]))
                    .collect();
                let rt = f.eval(&trial);
                let ct = cost_of(&rt);
                if ct < self.cost {
                    let cost_before = self.cost;
                    let rel = (self.cost - ct) / self.cost.max(1e-300);
                    let step: f64 = (0..n)
                        .map(|k| (trial[k] - self.u[k]).abs())
                        .fold(0.0, f64::max);
                    self.u = trial;
                    self.r = rt;
                    self.cost = ct;
                    self.mu = (self.mu / 3.0).max(1e-12);
                    accepted = true;
                    if rel < opts.ftol || step < 1e-10 || cost_before - ct < opts.atol {
                        self.small += 1;
                    } else {
                        self.small = 0;
                    }
                    break;
                }
                self.mu *= 4.0;
            }
            if !accepted || self.small >= 2 || self.iterations >= opts.max_iter {
                self.finished = true;
            }
            if self.r.len() >= ITERATION_SAMPLES {
                opts.observer.progress(
                    &format!(
                        "Levenberg-Marquardt iteration {}, chi2 {:.6e} ({} samples)",
                        self.iterations,
                        self.cost,
                        self.r.len()
                    ),
                    false,
                );
            }
        }
    }

    /// The cost `sum r^2` at the current point.
    pub fn cost(&self) -> f64 {
        self.cost
    }

    /// Iterations made so far.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// Whether the run has converged, stalled or used its `max_iter` iterations.
    pub fn finished(&self) -> bool {
        self.finished
    }

    /// The current point as a [`LmResult`].
    pub fn result(self) -> LmResult {
        LmResult {
            u: self.u,
            cost: self.cost,
            r: self.r,
            iterations: self.iterations,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The normal equations of a long record (its dot products spread over the threads) hold,
    /// entry by entry, the bits of each dot product taken on its own, whatever the threads.
    #[test]
    fn long_normal_equations_have_the_bits_of_each_dot_product() {
        let n = 60_000;
        let cols: Vec<Vec<f64>> = (0..6)
            .map(|k| {
                (0..n)
                    .map(|i| ((i * (k + 3)) as f64 * 0.37).sin() * (1.0 + k as f64))
                    .collect()
            })
            .collect();
        let r: Vec<f64> = (0..n).map(|i| (i as f64 * 0.011).cos()).collect();
        assert!(n * 27 >= PARALLEL_DOTS, "the parallel path is taken");
        for threads in [1, 2, 3] {
            let (a, g) = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| normal_equations(&cols, &r));
            for k in 0..6 {
                assert_eq!(g[k].to_bits(), dot(&cols[k], &r).to_bits());
                for l in 0..6 {
                    assert_eq!(a[(k, l)].to_bits(), dot(&cols[k], &cols[l]).to_bits());
                }
            }
        }
    }

    #[test]
    fn a_run_in_rounds_has_the_bits_of_one_call() {
        let t: Vec<f64> = (0..60).map(|i| i as f64 * 0.05).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|t| 1.7 * (-0.8 * t).exp() * (3.0 * t).cos())
            .collect();
        let f = |u: &[f64]| {
            t.iter()
                .zip(&y)
                .map(|(t, y)| u[0] * (-u[1] * t).exp() * (u[2] * t).cos() - y)
                .collect::<Vec<_>>()
        };
        let (lo, hi) = ([0.0, 0.0, 0.0], [10.0, 10.0, 10.0]);
        for max_iter in [1, 5, 40] {
            let opts = LmOptions {
                max_iter,
                ..LmOptions::default()
            };
            let whole = minimize(&f, &[1.0, 0.3, 2.2], &lo, &hi, &opts);
            for round in [1, 3, 7] {
                let mut run = LmRun::new(&f, &[1.0, 0.3, 2.2], &lo, &hi, &opts, None);
                let mut until = 0;
                while !run.finished() && until < max_iter {
                    until += round;
                    run.advance(&f, &lo, &hi, &opts, until);
                }
                let r = run.result();
                assert_eq!(r.iterations, whole.iterations, "{max_iter} by {round}");
                assert_eq!(r.cost.to_bits(), whole.cost.to_bits());
                assert!(
                    r.u.iter()
                        .zip(&whole.u)
                        .all(|(a, b)| a.to_bits() == b.to_bits())
                );
            }
        }
    }

    #[test]
    fn fits_an_exponential_within_bounds() {
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * (-1.3 * t).exp()).collect();
        let f = |u: &[f64]| {
            t.iter()
                .zip(&y)
                .map(|(t, y)| u[0] * (-u[1] * t).exp() - y)
                .collect::<Vec<_>>()
        };
        let r = minimize(
            &f,
            &[1.0, 0.5],
            &[0.0, 0.0],
            &[10.0, 10.0],
            &LmOptions::default(),
        );
        assert!(
            (r.u[0] - 2.0).abs() < 1e-6 && (r.u[1] - 1.3).abs() < 1e-6,
            "{:?}",
            r.u
        );
        let rb = minimize(
            &f,
            &[1.0, 0.5],
            &[0.0, 0.0],
            &[10.0, 1.0],
            &LmOptions::default(),
        );
        assert!((rb.u[1] - 1.0).abs() < 1e-12);
    }
}
