//! The retraction's linear algebra: the scaled, augmented state's matrices and their
//! exponential (shared by [`super::RtConfig`]'s propagation and the uniform tail, `super::tail`).

/// Size of the augmented state: `q, y, y', l, l'`, `E/E0`, ramp switch.
pub(super) const N_AUG: usize = 7;
/// Size of the homogeneous part of the state once the voltage is off: `q, y, y', l, l'`.
pub(super) const N_HOM: usize = 5;
pub(super) type Mat = [[f64; N_AUG]; N_AUG];

/// `a b` of `N x N` matrices (zero entries of `a` skipped).
fn matmul<const N: usize>(a: &[[f64; N]; N], b: &[[f64; N]; N]) -> [[f64; N]; N] {
    let mut c = [[0.0; N]; N];
    for i in 0..N {
        for k in 0..N {
            let aik = a[i][k];
            if aik != 0.0 {
                for j in 0..N {
                    c[i][j] += aik * b[k][j];
                }
            }
        }
    }
    c
}

/// `r . v` in a fixed order (left to right).
#[inline(always)]
pub(super) fn dotn<const N: usize>(r: &[f64; N], v: &[f64; N]) -> f64 {
    let mut s = r[0] * v[0];
    for i in 1..N {
        s += r[i] * v[i];
    }
    s
}

#[inline]
pub(super) fn apply(m: &Mat, z: &[f64; N_AUG]) -> [f64; N_AUG] {
    let mut o = [0.0; N_AUG];
    for (oi, row) in o.iter_mut().zip(m) {
        let mut s = 0.0;
        for (mij, zj) in row.iter().zip(z) {
            s += mij * zj;
        }
        *oi = s;
    }
    o
}

/// Largest absolute row sum of `a`.
pub(super) fn norm_inf(a: &Mat) -> f64 {
    a.iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// `exp(a*dt)` by scaling and squaring with a degree-16 Taylor series (the scaled matrix has
/// norm below 1/8 before squaring, so the series error is far below rounding).
pub(super) fn propagator(a: &Mat, dt: f64) -> Mat {
    expm_n(a, dt)
}

/// [`propagator`] of an `N x N` matrix (the irregular tail's balanced blocks).
pub(super) fn expm_n<const N: usize>(a: &[[f64; N]; N], dt: f64) -> [[f64; N]; N] {
    let norm = a
        .iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
        * dt;
    let mut s = 0;
    // (`2^s` itself: a cap of the divisor at 2^30 sent every norm above 1.3e8 to 60 squarings,
    // which double the rounding 60 times: a 5 ms gap of a stiff model, issue 50)
    while norm / 2f64.powi(s) > 0.125 && s < 60 {
        s += 1;
    }
    let h = dt / 2f64.powi(s);
    let mut term = [[0.0; N]; N];
    let mut sum = [[0.0; N]; N];
    for i in 0..N {
        term[i][i] = 1.0;
        sum[i][i] = 1.0;
    }
    let mut ah = *a;
    ah.iter_mut()
        .for_each(|r| r.iter_mut().for_each(|v| *v *= h));
    for k in 1..=16 {
        term = matmul(&term, &ah);
        let inv = 1.0 / k as f64;
        term.iter_mut()
            .for_each(|r| r.iter_mut().for_each(|v| *v *= inv));
        for i in 0..N {
            for j in 0..N {
                sum[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..s {
        sum = matmul(&sum, &sum);
    }
    sum
}
