//! The tail of a retraction record whose samples are not on a uniform grid (jittered time
//! stamps, gaps; issue 50, item 5): the state is carried on a grid `t0 + g h` of the typical
//! step `h` by one `exp(A h)`, and each sample is read from the grid point at or before it,
//! `g = floor((t - t0) / h)`, through `exp(A e)` of its offset `e` in `[0, h)`: the offsets
//! are cut into bins of width `h / nb`, each with the rows `e_y^T exp(A c) A^m / m!` at its
//! centre `c`, and a sample's reading is their Taylor series in `e - c` (`|A (e - c)|` at most
//! `OFFSET_NORM`). No exponential per sample: the cost per sample is the uniform tail's
//! ([`super::tail`]) with a few more terms of the series.

use super::expm::{Mat, N_AUG, norm_inf, propagator};

/// Size of the homogeneous part of the state once the voltage is off: `q, y, y', l, l'`.
const N_HOM: usize = 5;

/// Largest `|A| (e - c)` the series of a bin is asked to cover (half a bin): below it the
/// first term left out of `MAX_TERMS` is far below rounding; the bins are narrowed until it
/// holds, up to `MAX_BINS`.
const OFFSET_NORM: f64 = 1e-3;

/// Most bins of offsets (a stiffer model takes fewer, wider bins and more terms).
const MAX_BINS: usize = 4096;

/// Most terms of a bin's series.
const MAX_TERMS: usize = 16;

/// Grid steps a gap is crossed by, one `exp(A h)` each; a longer gap takes one exponential.
const GAP_STEPS: u64 = 64;

/// Intervals the typical step of a long record is the median of.
const STEP_SAMPLE: usize = 4095;

/// `r . v` in a fixed order.
#[inline(always)]
fn dot5(r: &[f64; N_HOM], v: &[f64; N_HOM]) -> f64 {
    r[0] * v[0] + r[1] * v[1] + r[2] * v[2] + r[3] * v[3] + r[4] * v[4]
}

/// `v^T m` (a row times a matrix).
fn row_times(v: &[f64; N_HOM], m: &[[f64; N_HOM]; N_HOM]) -> [f64; N_HOM] {
    std::array::from_fn(|c| (0..N_HOM).map(|k| v[k] * m[k][c]).sum())
}

/// The homogeneous 5 x 5 block of `m`.
fn block(m: &Mat) -> [[f64; N_HOM]; N_HOM] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[i][j]))
}

/// Whether the intervals of `times` change (by more than `tol` [s] from one to the next) often
/// enough, more than 32 times and one interval in 16, that an exponential per change, what the
/// interval-by-interval propagation costs, would be dearer than this tail's bins. A record
/// uniform by pieces (the fit's search subset: a dense head, a thinned tail; a few gaps) keeps
/// the interval-by-interval propagation and its bits.
pub(super) fn steps_change_often(times: &[f64], tol: f64) -> bool {
    let changes = times
        .windows(3)
        .filter(|w| ((w[2] - w[1]) - (w[1] - w[0])).abs() > tol)
        .count();
    changes > 32 && changes > times.len() / 16
}

/// The typical step of `times` after `t0`: the median of its intervals, or of
/// [`STEP_SAMPLE`] of them at fixed pseudo-random places; `None` for fewer than two samples, a time stamp that is not a
/// number or not after the one before it (the caller then propagates interval by interval).
pub(super) fn typical_step(t0: f64, times: &[f64]) -> Option<f64> {
    let n = times.len();
    if n < 2 || times[0].partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // a NaN compares as nothing: refused too
    if times
        .windows(2)
        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        || !times[n - 1].is_finite()
    {
        return None;
    }
    // every interval of a short record; of a long one, intervals at fixed pseudo-random places
    // (a stride would alias with a periodic pattern of gaps)
    let mut d: Vec<f64> = if n - 1 <= STEP_SAMPLE {
        times.windows(2).map(|w| w[1] - w[0]).collect()
    } else {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        (0..STEP_SAMPLE)
            .map(|_| {
                s = s
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let i = 1 + ((s >> 33) as usize) % (n - 1);
                times[i] - times[i - 1]
            })
            .collect()
    };
    let mid = d.len() / 2;
    let (_, &mut h, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    (h > 0.0 && h.is_finite()).then_some(h)
}

/// The readings of an irregular record's tail, set up ([`Irregular::new`]) then run
/// ([`Irregular::run`]).
pub(super) struct Irregular {
    /// `exp(A h)` of the homogeneous block.
    m: [[f64; N_HOM]; N_HOM],
    /// `rows[b * MAX_TERMS + j] = e_y^T exp(A c_b) A^j / j!` for the centre `c_b` of bin `b`.
    rows: Vec<[f64; N_HOM]>,
    /// Bins of the offsets in `[0, h)`.
    pub(super) nb: usize,
    /// Terms of each bin's series.
    pub(super) n_terms: usize,
    /// The homogeneous system matrix (for a long gap's exponential).
    a: Mat,
    /// The scaled state at `t0`.
    v: [f64; N_HOM],
    t0: f64,
    h: f64,
    scale_y: f64,
    d0: f64,
}

impl Irregular {
    /// The tail from the scaled state `z` at `t0` over `times` (increasing, after `t0`) with
    /// the grid step `h`, or `None` when the voltage is still on or the model is so stiff
    /// that [`MAX_BINS`] bins of [`MAX_TERMS`] terms do not reach rounding.
    pub(super) fn new(
        a: &Mat,
        z: &[f64; N_AUG],
        t0: f64,
        h: f64,
        scale_y: f64,
        d0: f64,
    ) -> Option<Irregular> {
        if z[N_HOM..].iter().any(|&v| v != 0.0) || h.is_nan() || h <= 0.0 {
            return None;
        }
        let a_norm = norm_inf(a);
        if !a_norm.is_finite() {
            return None;
        }
        // bins: half a bin's width within OFFSET_NORM, at most MAX_BINS
        let want = (a_norm * h / (2.0 * OFFSET_NORM)).ceil();
        let nb = if want >= MAX_BINS as f64 {
            MAX_BINS
        } else {
            (want as usize).max(1)
        };
        let w = h / nb as f64;
        // terms: the first one left out, `(|A| w / 2)^j / j!` relative to the state, below
        // 8e-18 (as the uniform tail's series)
        let x = a_norm * w / 2.0;
        let mut n_terms = 1;
        let mut bound = x;
        while bound > 8e-18 {
            n_terms += 1;
            if n_terms > MAX_TERMS {
                return None;
            }
            bound *= x / n_terms as f64;
        }
        let m = block(&propagator(a, h));
        let step = block(&propagator(a, w));
        let a5 = block(a);
        let mut rows = vec![[0.0; N_HOM]; nb * n_terms];
        // e_y^T exp(A w / 2), then one bin's width after the other
        let mut c = block(&propagator(a, w / 2.0))[1];
        for b in 0..nb {
            if b > 0 {
                c = row_times(&c, &step);
            }
            rows[b * n_terms] = c;
            for j in 1..n_terms {
                let r = row_times(&rows[b * n_terms + j - 1], &a5);
                rows[b * n_terms + j] = r.map(|v| v / j as f64);
            }
        }
        let mut v = [0.0; N_HOM];
        v.copy_from_slice(&z[..N_HOM]);
        Some(Irregular {
            m,
            rows,
            nb,
            n_terms,
            a: *a,
            v,
            t0,
            h,
            scale_y,
            d0,
        })
    }

    /// The output at `times` (increasing, after `t0`) pushed onto `out`.
    pub(super) fn run(&self, times: &[f64], out: &mut Vec<f64>) {
        let n = times.len();
        let (m, nt) = (&self.m, self.n_terms);
        let inv_h = 1.0 / self.h;
        let bins = self.nb as f64 / self.h;
        let w = self.h / self.nb as f64;
        let mut v = self.v;
        let mut g = 0u64;
        for (k, &ti) in times.iter().enumerate() {
            let gi = ((ti - self.t0) * inv_h).floor().max(0.0) as u64;
            if gi > g {
                if gi - g > GAP_STEPS {
                    let p = block(&propagator(&self.a, (gi - g) as f64 * self.h));
                    v = std::array::from_fn(|i| dot5(&p[i], &v));
                } else {
                    for _ in g..gi {
                        v = std::array::from_fn(|i| dot5(&m[i], &v));
                    }
                }
                g = gi;
                if v.iter().all(|x| x.abs() < 1e-30) {
                    // at rest (see `retraction`): held at -d0 exactly
                    out.extend(std::iter::repeat_n(-self.d0, n - k));
                    return;
                }
            }
            let e = ti - (self.t0 + g as f64 * self.h);
            let b = ((e * bins).floor().max(0.0) as usize).min(self.nb - 1);
            let r = e - (b as f64 + 0.5) * w;
            let rows = &self.rows[b * nt..(b + 1) * nt];
            let mut acc = dot5(&rows[nt - 1], &v);
            for row in rows[..nt - 1].iter().rev() {
                acc = acc * r + dot5(row, &v);
            }
            out.push(acc * self.scale_y - self.d0);
        }
    }
}
