//! The uniform tail of a retraction record ([`super::RtConfig::retraction`]): once the voltage
//! is off and the samples lie on a uniform grid, one `exp(A h)` carries the state from grid
//! point to grid point and each sample's offset from its grid point is applied to the output
//! through a short Taylor series ([`Tail`]); several evaluations' tails run side by side in
//! one thread ([`run_lanes`], the same bits as each alone).

use super::expm::{Mat, N_AUG, N_HOM, norm_inf, propagator};

/// `|A e|` up to which a sample `e` off its uniform grid point is reached by the Taylor series
/// of `exp(A e)` (at most five terms: the first one left out is below `1e-3^5 / 5! ~ 8e-18`
/// relative; a record whose largest offset is smaller takes fewer, to the same bound).
const GRID_OFFSET_NORM: f64 = 1e-3;

/// `r . v` with the additions in a fixed order, `-0.0 + r0 v0 + r1 v1 + ...` (the order of
/// `Iterator::sum`, which it replaced): [`Tail::run`] and [`run_lanes`] share this arithmetic,
/// so a lane gives the bits of a single evaluation.
#[inline(always)]
fn dot5(r: &[f64; N_HOM], v: &[f64; N_HOM]) -> f64 {
    -0.0 + r[0] * v[0] + r[1] * v[1] + r[2] * v[2] + r[3] * v[3] + r[4] * v[4]
}

/// The uniform grid `t0 + k h` of the samples `times` after `t0` (`h` from the first and last)
/// and their largest offset from it: what [`Tail::new`] checks, the same for every parameter
/// vector (computed once for the lanes of [`super::RtConfig::retraction_many`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Grid {
    /// The sample the tail starts at, and `t0`.
    pub(super) idx: usize,
    pub(super) t0: f64,
    h: f64,
    /// The largest `|t_k - (t0 + (k + 1) h)|` [s].
    e_max: f64,
    /// Whether an offset is not a number.
    nan: bool,
}

impl Grid {
    /// The grid of `times` (the record's from sample `idx` on) after `t0`.
    pub(super) fn of(idx: usize, t0: f64, times: &[f64]) -> Grid {
        let n = times.len();
        let h = match times.last() {
            Some(&last) => (last - t0) / n as f64,
            None => f64::NAN,
        };
        // four partial maxima (the largest of a set of numbers does not depend on the order)
        // and no branch per sample, so that the pass over a million time stamps is vectorised
        let offset = |k: usize, ti: f64| (ti - (t0 + (k + 1) as f64 * h)).abs();
        let mut e_max4 = [0.0f64; 4];
        let mut nan4 = [false; 4];
        let (quads, rest) = times.as_chunks::<4>();
        for (q, quad) in quads.iter().enumerate() {
            for (j, &ti) in quad.iter().enumerate() {
                let e = offset(4 * q + j, ti);
                nan4[j] |= e.is_nan();
                e_max4[j] = e_max4[j].max(e);
            }
        }
        let mut e_max = e_max4.iter().copied().fold(0.0f64, f64::max);
        let mut nan = nan4.iter().any(|&o| o);
        for (j, &ti) in rest.iter().enumerate() {
            let e = offset(4 * quads.len() + j, ti);
            nan |= e.is_nan();
            e_max = e_max.max(e);
        }
        Grid {
            idx,
            t0,
            h,
            e_max,
            nan,
        }
    }
}

/// The tip's output on a uniform grid, set up ([`Tail::new`]) and then run ([`Tail::run`], or
/// several side by side: [`run_lanes`]).
///
/// The samples `times` (increasing, after `t0`, every one of them after the voltage is off)
/// lie on a uniform grid `t0 + k h` to within the rounding of their time stamps
/// (`|A e| <= GRID_OFFSET_NORM`). Then one `exp(A h)` of the homogeneous 5 x 5 block carries
/// the state from grid point to grid point, and each sample's offset `e` from its grid point
/// is applied to the output only, through the Taylor series of `exp(A e)` (rows of `A^m / m!`):
/// the state never absorbs the rounding of the time stamps, and there is no propagator per
/// sample.
pub(super) struct Tail {
    /// `exp(A h)` of the homogeneous block.
    m: [[f64; N_HOM]; N_HOM],
    /// `rows[j] = e_y^T A^j / j!`: the output's Taylor coefficients in the offset.
    rows: [[f64; N_HOM]; 5],
    /// Terms of the series the record's offsets need.
    pub(super) n_terms: usize,
    /// The scaled state at `t0`.
    v: [f64; N_HOM],
    t0: f64,
    h: f64,
    scale_y: f64,
    d0: f64,
}

impl Tail {
    /// The tail from the scaled state `z` at `grid.t0` over `times` (those of `grid`), or
    /// `None` for a record that is not uniform (the caller propagates it interval by interval).
    pub(super) fn new(
        a: &Mat,
        z: &[f64; N_AUG],
        times: &[f64],
        grid: &Grid,
        scale_y: f64,
        d0: f64,
    ) -> Option<Tail> {
        let t0 = grid.t0;
        if times.len() < 2 || z[N_HOM..].iter().any(|&v| v != 0.0) {
            return None;
        }
        let Grid { h, e_max, nan, .. } = *grid;
        let a_norm = norm_inf(a);
        let tol = GRID_OFFSET_NORM / a_norm;
        // every sample within `tol` of its grid point (none beyond it, none not a number)
        let within = e_max <= tol;
        if nan || !within || !(h > 0.0 && tol.is_finite()) {
            return None;
        }
        let full = propagator(a, h);
        let mut m = [[0.0; N_HOM]; N_HOM];
        let mut a5 = [[0.0; N_HOM]; N_HOM];
        for i in 0..N_HOM {
            m[i].copy_from_slice(&full[i][..N_HOM]);
            a5[i].copy_from_slice(&a[i][..N_HOM]);
        }
        let mut rows = [[0.0; N_HOM]; 5];
        rows[0][1] = 1.0;
        for j in 1..rows.len() {
            for c in 0..N_HOM {
                rows[j][c] = (0..N_HOM).map(|k| rows[j - 1][k] * a5[k][c]).sum::<f64>() / j as f64;
            }
        }
        // terms of the series the record's offsets need: the first one left out, bounded by
        // `(|A| e_max)^j / j!` relative to the state, below 8e-18 as the fifth is at
        // `GRID_OFFSET_NORM` (the time stamps' rounding, e.g. 1e-16 s, needs two to four: the
        // series was most of the cost of a long record's evaluation, issue 35)
        let x = a_norm * e_max;
        let mut n_terms = 1;
        let mut bound = x;
        while n_terms < rows.len() && bound > 8e-18 {
            n_terms += 1;
            bound *= x / n_terms as f64;
        }
        let mut v = [0.0; N_HOM];
        v.copy_from_slice(&z[..N_HOM]);
        Some(Tail {
            m,
            rows,
            n_terms,
            v,
            t0,
            h,
            scale_y,
            d0,
        })
    }

    /// The output at `times` (those of [`Tail::new`]) pushed onto `out`.
    pub(super) fn run(&self, times: &[f64], out: &mut Vec<f64>) {
        let n = times.len();
        let (m, rows, n_terms) = (&self.m, &self.rows[..self.n_terms], self.n_terms);
        let mut v = self.v;
        for (k, &ti) in times.iter().enumerate() {
            let mut w = [0.0; N_HOM];
            for (wi, row) in w.iter_mut().zip(m) {
                *wi = dot5(row, &v);
            }
            v = w;
            if v.iter().all(|x| x.abs() < 1e-30) {
                // at rest (see `retraction`): held at -d0 exactly
                out.extend(std::iter::repeat_n(-self.d0, n - k));
                return;
            }
            let e = ti - (self.t0 + (k + 1) as f64 * self.h);
            let y = if e == 0.0 {
                v[1]
            } else {
                let mut acc = dot5(&rows[n_terms - 1], &v);
                for r in rows[..n_terms - 1].iter().rev() {
                    acc = acc * e + dot5(r, &v);
                }
                acc
            };
            out.push(y * self.scale_y - self.d0);
        }
    }
}

/// [`Tail::run`] of `L` tails over the same `times` (the same `t0` and grid) and with the
/// same number of series terms, side by side in one thread: each lane's arithmetic is
/// [`Tail::run`]'s, in the same order, so its bits (tested), with the lanes innermost and no
/// branch per lane in the loop, so that the compiler computes them in vector registers.
pub(super) fn run_lanes<const L: usize>(tails: [&Tail; L], times: &[f64], outs: &mut [Vec<f64>]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (checked just above)
        unsafe { run_lanes_avx(tails, times, outs) };
        return;
    }
    run_lanes_body(tails, times, outs);
}

/// [`run_lanes_body`] compiled for AVX (four lanes in one register instead of two): the same
/// operations in the same order, without fused multiply-adds, so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn run_lanes_avx<const L: usize>(tails: [&Tail; L], times: &[f64], outs: &mut [Vec<f64>]) {
    run_lanes_body(tails, times, outs);
}

/// The body of [`run_lanes`].
#[inline(always)]
fn run_lanes_body<const L: usize>(tails: [&Tail; L], times: &[f64], outs: &mut [Vec<f64>]) {
    let n = times.len();
    let n_terms = tails[0].n_terms;
    debug_assert!(tails.iter().all(|t| t.n_terms == n_terms));
    let mut m = [[[0.0; L]; N_HOM]; N_HOM];
    let mut rows = [[[0.0; L]; N_HOM]; 5];
    let mut v = [[0.0; L]; N_HOM];
    let mut scale_y = [0.0; L];
    let mut d0 = [0.0; L];
    for (b, t) in tails.iter().enumerate() {
        for (mi, (ti, (vi, tvi))) in m.iter_mut().zip(t.m.iter().zip(v.iter_mut().zip(&t.v))) {
            for (mij, tij) in mi.iter_mut().zip(ti) {
                mij[b] = *tij;
            }
            vi[b] = *tvi;
        }
        for (r, tr) in rows.iter_mut().zip(&t.rows) {
            for (rj, trj) in r.iter_mut().zip(tr) {
                rj[b] = *trj;
            }
        }
        scale_y[b] = t.scale_y;
        d0[b] = t.d0;
    }
    let rows = &rows[..n_terms];
    let (t0, h) = (tails[0].t0, tails[0].h);
    let dot = |r: &[[f64; L]; N_HOM], v: &[[f64; L]; N_HOM]| -> [f64; L] {
        std::array::from_fn(|b| {
            -0.0 + r[0][b] * v[0][b]
                + r[1][b] * v[1][b]
                + r[2][b] * v[2][b]
                + r[3][b] * v[3][b]
                + r[4][b] * v[4][b]
        })
    };
    // lanes still running (a lane at rest is filled to the end and left)
    let mut running = [true; L];
    for (k, &ti) in times.iter().enumerate() {
        let mut w = [[0.0; L]; N_HOM];
        for (wi, mi) in w.iter_mut().zip(&m) {
            *wi = dot(mi, &v);
        }
        v = w;
        let rest: [bool; L] = std::array::from_fn(|b| {
            (v[0][b].abs() < 1e-30)
                & (v[1][b].abs() < 1e-30)
                & (v[2][b].abs() < 1e-30)
                & (v[3][b].abs() < 1e-30)
                & (v[4][b].abs() < 1e-30)
        });
        if (0..L).any(|b| rest[b] && running[b]) {
            for b in 0..L {
                if rest[b] && running[b] {
                    outs[b].extend(std::iter::repeat_n(-d0[b], n - k));
                    running[b] = false;
                }
            }
            if !running.iter().any(|&r| r) {
                return;
            }
        }
        let e = ti - (t0 + (k + 1) as f64 * h);
        let y = if e == 0.0 {
            v[1]
        } else {
            let mut acc = dot(&rows[n_terms - 1], &v);
            for r in rows[..n_terms - 1].iter().rev() {
                let d = dot(r, &v);
                for b in 0..L {
                    acc[b] = acc[b] * e + d[b];
                }
            }
            acc
        };
        for b in 0..L {
            if running[b] {
                outs[b].push(y[b] * scale_y[b] - d0[b]);
            }
        }
    }
}

/// [`Tail::new`] and [`Tail::run`] in one: `false`, pushing nothing, for a record that is not
/// uniform.
#[cfg(test)]
pub(super) fn uniform_tail(
    a: &Mat,
    z: &[f64; N_AUG],
    t0: f64,
    times: &[f64],
    scale_y: f64,
    d0: f64,
    out: &mut Vec<f64>,
) -> bool {
    match Tail::new(a, z, times, &Grid::of(0, t0, times), scale_y, d0) {
        Some(tail) => {
            tail.run(times, out);
            true
        }
        None => false,
    }
}
