//! Levenberg-Marquardt least squares with box bounds and a finite-difference Jacobian.
//!
//! Minimises `sum r_i(u)^2` over internal coordinates `u` (log or scaled parameters, see
//! [`crate::fit`]). Bounds are enforced by projecting each trial step onto the box. The
//! `levenberg-marquardt` crate was not used because it has no bounds and our residuals come
//! from an ODE whose Jacobian is taken by finite differences anyway; this 100-line solver keeps
//! the damping, projection and stopping rules in one readable place.

use nalgebra::{DMatrix, DVector};

/// Options of [`minimize`].
#[derive(Debug, Clone, Copy)]
pub struct LmOptions {
    /// Maximum number of Jacobian evaluations.
    pub max_iter: usize,
    /// Stop when the relative decrease of the cost falls below this.
    pub ftol: f64,
    /// Forward-difference step in internal coordinates.
    pub fd_step: f64,
}

impl Default for LmOptions {
    fn default() -> Self {
        LmOptions {
            max_iter: 200,
            ftol: 1e-10,
            fd_step: 1e-3,
        }
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

/// Forward-difference Jacobian of `f` at `u` (`r0 = f(u)`), columns for `u`'s entries.
pub fn jacobian<F: Fn(&[f64]) -> Vec<f64>>(
    f: &F,
    u: &[f64],
    r0: &[f64],
    lo: &[f64],
    hi: &[f64],
    h: f64,
) -> DMatrix<f64> {
    let n = r0.len();
    let mut j = DMatrix::zeros(n, u.len());
    let mut up = u.to_vec();
    for k in 0..u.len() {
        // step away from an active upper bound
        let step = if u[k] + h > hi[k] && u[k] - h >= lo[k] {
            -h
        } else {
            h
        };
        up[k] = u[k] + step;
        let r1 = f(&up);
        for i in 0..n {
            j[(i, k)] = (r1[i] - r0[i]) / step;
        }
        up[k] = u[k];
    }
    j
}

/// Forward-difference Jacobian columns of `f` at `u` (`r0 = f(u)`), one vector per entry of `u`
/// (the layout the normal equations read without a transposed copy).
pub fn jacobian_columns<F: Fn(&[f64]) -> Vec<f64>>(
    f: &F,
    u: &[f64],
    r0: &[f64],
    lo: &[f64],
    hi: &[f64],
    h: f64,
) -> Vec<Vec<f64>> {
    let mut up = u.to_vec();
    let mut cols = Vec::with_capacity(u.len());
    for k in 0..u.len() {
        // step away from an active upper bound
        let step = if u[k] + h > hi[k] && u[k] - h >= lo[k] {
            -h
        } else {
            h
        };
        up[k] = u[k] + step;
        let mut c = f(&up);
        for (ci, r) in c.iter_mut().zip(r0) {
            *ci = (*ci - r) / step;
        }
        cols.push(c);
        up[k] = u[k];
    }
    cols
}

/// `J^T J` and `J^T r` from the columns of `J`: one pass of dot products, no `n x k` matrix
/// (the record can hold a million samples).
pub fn normal_equations(cols: &[Vec<f64>], r: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let n = cols.len();
    let mut a = DMatrix::zeros(n, n);
    let mut g = DVector::zeros(n);
    for k in 0..n {
        for l in 0..=k {
            let d = dot(&cols[k], &cols[l]);
            a[(k, l)] = d;
            a[(l, k)] = d;
        }
        g[k] = dot(&cols[k], r);
    }
    (a, g)
}

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
pub fn minimize<F: Fn(&[f64]) -> Vec<f64>>(
    f: &F,
    u0: &[f64],
    lo: &[f64],
    hi: &[f64],
    opts: &LmOptions,
) -> LmResult {
    let n = u0.len();
    let mut u: Vec<f64> = u0
        .iter()
        .zip(lo.iter().zip(hi))
        .map(|(v, (l, h))| v.clamp(*l, *h))
        .collect();
    let mut r = f(&u);
    let mut cost = cost_of(&r);
    let mut mu = 1e-3;
    let mut iterations = 0;
    if n == 0 || !cost.is_finite() {
        return LmResult {
            u,
            cost,
            r,
            iterations,
        };
    }
    let mut small = 0;
    while iterations < opts.max_iter {
        iterations += 1;
        let cols = jacobian_columns(f, &u, &r, lo, hi, opts.fd_step);
        let (a, g) = normal_equations(&cols, &r);
        drop(cols);
        let diag: Vec<f64> = (0..n)
            .map(|k| a[(k, k)].max(1e-12 * (1.0 + a.max())))
            .collect();
        let mut accepted = false;
        for _ in 0..12 {
            let mut m = a.clone();
            for k in 0..n {
                m[(k, k)] += mu * diag[k];
            }
            let Some(delta) = m.cholesky().map(|c| c.solve(&(-&g))) else {
                mu *= 10.0;
                continue;
            };
            let trial: Vec<f64> = (0..n)
                .map(|k| (u[k] + delta[k]).clamp(lo[k], hi[k]))
                .collect();
            let rt = f(&trial);
            let ct = cost_of(&rt);
            if ct < cost {
                let rel = (cost - ct) / cost.max(1e-300);
                let step: f64 = (0..n).map(|k| (trial[k] - u[k]).abs()).fold(0.0, f64::max);
                u = trial;
                r = rt;
                cost = ct;
                mu = (mu / 3.0).max(1e-12);
                accepted = true;
                if rel < opts.ftol || step < 1e-10 {
                    small += 1;
                } else {
                    small = 0;
                }
                break;
            }
            mu *= 4.0;
        }
        if !accepted || small >= 2 {
            break;
        }
    }
    LmResult {
        u,
        cost,
        r,
        iterations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
