//! The tail of a retraction record whose samples are not on a uniform grid (jittered time
//! stamps, gaps; issue 50, item 5): the state is carried on a grid `t0 + g h` of the typical
//! step `h` by one `exp(A h)`, and each sample is read from the grid point at or before it,
//! `g = floor((t - t0) / h)`, through `exp(A e)` of its offset `e` in `[0, h)`: the offsets
//! are cut into bins of width `h / nb`, each with the rows `e_y^T exp(A c) A^m / m!` at its
//! centre `c`, and a sample's reading is their Taylor series in `e - c` (`|A (e - c)|` at most
//! `OFFSET_NORM`, or as many bins as cost least: [`cheapest_bins`]). A record whose samples
//! all sit on the grid (gaps, no jitter) is read from the nearest grid point with one bin
//! centred on it, the few terms of its time stamps' rounding, as the uniform tail
//! ([`super::tail`]). No exponential per sample, and several parameter vectors run side by
//! side ([`run_lanes`]): the cost per sample is the uniform tail's with a few more terms of
//! the series (measured in `docs/fitting.md`, "Irregular time stamps").

use super::expm::{Mat, N_AUG, norm_inf, propagator};

/// Size of the homogeneous part of the state once the voltage is off: `q, y, y', l, l'`.
const N_HOM: usize = 5;

/// Largest `|A| (e - c)` the series of a bin is asked to cover (half a bin) at most: the
/// bins are narrowed until it holds, up to `MAX_BINS` ([`cheapest_bins`] may then take
/// fewer, wider bins with more terms). Also the largest `|A| e` of a record read from its
/// nearest grid points with one bin.
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

/// `v^T m` (a row times a matrix), written out so that the columns are computed side by side.
#[inline(always)]
fn row_times(v: &[f64; N_HOM], m: &[[f64; N_HOM]; N_HOM]) -> [f64; N_HOM] {
    std::array::from_fn(|c| {
        v[0] * m[0][c] + v[1] * m[1][c] + v[2] * m[2][c] + v[3] * m[3][c] + v[4] * m[4][c]
    })
}

/// The cheapest bins for `n` samples whose offsets span `span` [s] with `|A| = a_norm`: the
/// number of bins and the terms of each bin's series. A bin costs its `n_terms` rows to set
/// up (a row times a matrix each) and a sample its `n_terms` rows to read, so the count
/// minimises `nb * n_terms * 5 + n * n_terms` (in dot products) over powers of two from the
/// fewest that keep half a bin within `OFFSET_NORM` downwards, as long as the series reaches
/// rounding within [`MAX_TERMS`]; `None` when even [`MAX_BINS`] bins do not.
fn cheapest_bins(a_norm: f64, span: f64, n: usize) -> Option<(usize, usize)> {
    let want = (a_norm * span / (2.0 * OFFSET_NORM)).ceil();
    let mut nb = if want >= MAX_BINS as f64 {
        MAX_BINS
    } else {
        (want as usize).max(1)
    };
    let mut best: Option<(usize, usize, f64)> = None;
    loop {
        if let Some(nt) = terms(a_norm * span / (2.0 * nb as f64)) {
            let cost = (nb * nt * N_HOM + n * nt) as f64;
            if best.is_none_or(|(_, _, c)| cost < c) {
                best = Some((nb, nt, cost));
            }
        }
        if nb == 1 {
            break;
        }
        nb = nb.div_ceil(2);
    }
    best.map(|(nb, nt, _)| (nb, nt))
}

/// Terms of a series in `x = |A| r` whose first term left out, `x^j / j!` relative to the
/// state, is below 8e-18 (as the uniform tail's series); `None` beyond [`MAX_TERMS`].
fn terms(x: f64) -> Option<usize> {
    let mut n_terms = 1;
    let mut bound = x;
    while bound > 8e-18 {
        n_terms += 1;
        if n_terms > MAX_TERMS {
            return None;
        }
        bound *= x / n_terms as f64;
    }
    Some(n_terms)
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
fn typical_step(t0: f64, times: &[f64]) -> Option<f64> {
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

/// The grid of an irregular record's samples after `t0` ([`typical_step`]) and their largest
/// offset from its nearest point: the same for every parameter vector (computed once for the
/// lanes of [`super::RtConfig::retraction_many`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Stamps {
    /// The time the tail starts from [s].
    pub(super) t0: f64,
    /// The grid step [s].
    pub(super) h: f64,
    /// The largest `|t - (t0 + g h)|` [s] over the samples, `g` the nearest grid point.
    e_max: f64,
    /// The number of samples.
    n: usize,
}

impl Stamps {
    /// The grid of `times` (increasing, after `t0`), or `None` where [`typical_step`] has
    /// none.
    pub(super) fn of(t0: f64, times: &[f64]) -> Option<Stamps> {
        let h = typical_step(t0, times)?;
        let inv_h = 1.0 / h;
        let e_max = times
            .iter()
            .map(|&ti| {
                let g = ((ti - t0) * inv_h + 0.5) as u64;
                (ti - (t0 + g as f64 * h)).abs()
            })
            .fold(0.0f64, f64::max);
        e_max.is_finite().then_some(Stamps {
            t0,
            h,
            e_max,
            n: times.len(),
        })
    }
}

/// The readings of an irregular record's tail, set up ([`Irregular::new`]) then run
/// ([`Irregular::run`], or several side by side: [`run_lanes`]).
pub(super) struct Irregular {
    /// `exp(A h)` of the homogeneous block.
    m: [[f64; N_HOM]; N_HOM],
    /// `rows[b * n_terms + j] = e_y^T exp(A c_b) A^j / j!` for the centre `c_b` of bin `b`.
    rows: Vec<[f64; N_HOM]>,
    /// Bins of the offsets in `[0, h)` from the grid point at or before a sample; or one,
    /// centred on the nearest grid point, when every sample of the record is within
    /// `OFFSET_NORM / |A|` of its nearest one (a gapped record: few terms, no bins to build).
    pub(super) nb: usize,
    /// Terms of each bin's series.
    pub(super) n_terms: usize,
    /// Whether the one bin is centred on the nearest grid point.
    pub(super) centred: bool,
    /// The homogeneous system matrix (for a long gap's exponential).
    a: Mat,
    /// The scaled state at `t0`.
    v: [f64; N_HOM],
    t0: f64,
    h: f64,
    /// Width of a bin and the lower end of the first [s] (`-h/2` with one bin, else 0).
    w: f64,
    lo: f64,
    scale_y: f64,
    d0: f64,
}

impl Irregular {
    /// The tail from the scaled state `z` at `stamps.t0` over the samples of `stamps`, or
    /// `None` when the voltage is still on or the model is so stiff that [`MAX_BINS`] bins of
    /// [`MAX_TERMS`] terms do not reach rounding.
    pub(super) fn new(
        a: &Mat,
        z: &[f64; N_AUG],
        stamps: &Stamps,
        scale_y: f64,
        d0: f64,
    ) -> Option<Irregular> {
        let Stamps { t0, h, e_max, .. } = *stamps;
        if z[N_HOM..].iter().any(|&v| v != 0.0) || h.is_nan() || h <= 0.0 {
            return None;
        }
        let a_norm = norm_inf(a);
        if !a_norm.is_finite() {
            return None;
        }
        // every sample within OFFSET_NORM of its nearest grid point: one bin centred on it,
        // and the terms the largest offset needs; otherwise bins across the step after the
        // grid point at or before a sample (forwards only: an exponential backwards in time
        // would amplify a stiff model's decayed modes), as many as cost least
        let centred = a_norm * e_max <= OFFSET_NORM;
        let (nb, n_terms, lo) = if centred {
            (1, terms(a_norm * e_max)?, -0.5 * h)
        } else {
            let (nb, nt) = cheapest_bins(a_norm, h, stamps.n)?;
            (nb, nt, 0.0)
        };
        let w = h / nb as f64;
        let m = block(&propagator(a, h));
        let a5 = block(a);
        // the first row of each bin: e_y (the grid point itself), or e_y^T exp(A w / 2) then
        // one bin's width after the other
        let mut first = Vec::with_capacity(nb);
        if centred {
            first.push(std::array::from_fn(|i| if i == 1 { 1.0 } else { 0.0 }));
        } else {
            let step = block(&propagator(a, w));
            let mut c = block(&propagator(a, w / 2.0))[1];
            for b in 0..nb {
                if b > 0 {
                    c = row_times(&c, &step);
                }
                first.push(c);
            }
        }
        // `A^j / j!`, then each bin's rows from its first, independent of one another (no
        // chain of rows per bin, no zeroed table first: they were most of the cost of setting
        // up a stiff model's bins)
        let mut powers = vec![[[0.0; N_HOM]; N_HOM]; n_terms];
        powers[0] = std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))));
        for j in 1..n_terms {
            let p = powers[j - 1];
            powers[j] = std::array::from_fn(|i| row_times(&p[i], &a5).map(|v| v / j as f64));
        }
        let mut rows = Vec::with_capacity(nb * n_terms);
        for c in &first {
            rows.push(*c);
            rows.extend(powers[1..].iter().map(|p| row_times(c, p)));
        }
        let mut v = [0.0; N_HOM];
        v.copy_from_slice(&z[..N_HOM]);
        Some(Irregular {
            m,
            rows,
            nb,
            n_terms,
            centred,
            a: *a,
            v,
            t0,
            h,
            w,
            lo,
            scale_y,
            d0,
        })
    }

    /// The work of [`Irregular::run`] over `times` in dot products of five: the bins' rows,
    /// one step of the state per grid point crossed (five dot products), a long gap's
    /// exponential (`exp_dots`) and each sample's series (a mechanism test of issue 50, item
    /// 5: the cost, not the time).
    #[cfg(test)]
    pub(super) fn work(&self, times: &[f64], exp_dots: f64) -> f64 {
        let half = if self.centred { 0.5 } else { 0.0 };
        let mut g = 0u64;
        let mut dots = (self.nb * (self.n_terms + 1) * N_HOM) as f64;
        for &ti in times {
            let gi = ((ti - self.t0) / self.h + half) as u64;
            if gi > g {
                dots += if gi - g > GAP_STEPS {
                    exp_dots
                } else {
                    ((gi - g) * N_HOM as u64) as f64
                };
                g = gi;
            }
            dots += self.n_terms as f64;
        }
        dots
    }

    /// The output at `times` (increasing, after `t0`) pushed onto `out`: [`run_lanes`] with
    /// one lane, so that a lane of several gives these bits.
    pub(super) fn run(&self, times: &[f64], out: &mut Vec<f64>) {
        run_lanes([self], times, std::slice::from_mut(out));
    }
}

/// [`Irregular::run`] of `L` tails over the same `times` (the same [`Stamps`]) with the same
/// bins and terms, side by side in one thread: each lane's arithmetic is that of one tail
/// alone, in the same order (its bits, tested), with the lanes innermost so that the compiler
/// computes them in vector registers (the uniform tail's `run_lanes`, issue 50 item 5).
pub(super) fn run_lanes<const L: usize>(
    tails: [&Irregular; L],
    times: &[f64],
    outs: &mut [Vec<f64>],
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (checked just above)
        unsafe { run_lanes_avx(tails, times, outs) };
        return;
    }
    run_lanes_body(tails, times, outs);
}

/// [`run_lanes_body`] compiled for AVX: the same operations in the same order, without fused
/// multiply-adds, so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn run_lanes_avx<const L: usize>(tails: [&Irregular; L], times: &[f64], outs: &mut [Vec<f64>]) {
    run_lanes_body(tails, times, outs);
}

/// The body of [`run_lanes`]. The grid point of a sample is the one at or before it, `g =
/// floor((t - t0) / h)`, or with one bin the nearest (`(t - t0) / h + 1/2`), by a truncating
/// conversion (no `floor` call; a negative number converts to 0), and its offset `e` falls in
/// bin `(e - lo) / w`; both are the same for every lane.
#[inline(always)]
fn run_lanes_body<const L: usize>(tails: [&Irregular; L], times: &[f64], outs: &mut [Vec<f64>]) {
    let n = times.len();
    let t = tails[0];
    let (nt, nb) = (t.n_terms, t.nb);
    debug_assert!(
        tails
            .iter()
            .all(|x| x.n_terms == nt && x.nb == nb && x.centred == t.centred)
    );
    let m: [[[f64; L]; N_HOM]; N_HOM] =
        std::array::from_fn(|i| std::array::from_fn(|j| std::array::from_fn(|b| tails[b].m[i][j])));
    let mut v: [[f64; L]; N_HOM] = std::array::from_fn(|i| std::array::from_fn(|b| tails[b].v[i]));
    // several lanes' rows side by side, so that a sample's terms are read whole (one lane
    // reads its own)
    let table: Vec<[[f64; L]; N_HOM]> = if L > 1 {
        (0..nb * nt)
            .map(|k| std::array::from_fn(|i| std::array::from_fn(|b| tails[b].rows[k][i])))
            .collect()
    } else {
        Vec::new()
    };
    let row_at = |k: usize| -> [[f64; L]; N_HOM] {
        if L > 1 {
            table[k]
        } else {
            std::array::from_fn(|i| std::array::from_fn(|_| t.rows[k][i]))
        }
    };
    let scale_y: [f64; L] = std::array::from_fn(|b| tails[b].scale_y);
    let d0: [f64; L] = std::array::from_fn(|b| tails[b].d0);
    let (t0, h, w, lo) = (t.t0, t.h, t.w, t.lo);
    let inv_h = 1.0 / h;
    let half = if t.centred { 0.5 } else { 0.0 };
    let inv_w = nb as f64 / h;
    let dot = |r: &[[f64; L]; N_HOM], v: &[[f64; L]; N_HOM]| -> [f64; L] {
        std::array::from_fn(|b| {
            r[0][b] * v[0][b]
                + r[1][b] * v[1][b]
                + r[2][b] * v[2][b]
                + r[3][b] * v[3][b]
                + r[4][b] * v[4][b]
        })
    };
    let mut running = [true; L];
    let mut g = 0u64;
    for (k, &ti) in times.iter().enumerate() {
        let gi = ((ti - t0) * inv_h + half) as u64;
        if gi > g {
            if gi - g > GAP_STEPS {
                // a long gap: one exponential per lane
                for (b, x) in tails.iter().enumerate() {
                    let p = block(&propagator(&x.a, (gi - g) as f64 * h));
                    let vb: [f64; N_HOM] = std::array::from_fn(|i| v[i][b]);
                    for i in 0..N_HOM {
                        v[i][b] = dot5(&p[i], &vb);
                    }
                }
            } else {
                for _ in g..gi {
                    let mut u = [[0.0; L]; N_HOM];
                    for (ui, mi) in u.iter_mut().zip(&m) {
                        *ui = dot(mi, &v);
                    }
                    v = u;
                }
            }
            g = gi;
            let rest: [bool; L] =
                std::array::from_fn(|b| (0..N_HOM).all(|i| v[i][b].abs() < 1e-30));
            if (0..L).any(|b| rest[b] && running[b]) {
                // at rest (see `retraction`): held at -d0 exactly
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
        }
        let e = ti - (t0 + g as f64 * h);
        let bin = (((e - lo) * inv_w) as usize).min(nb - 1);
        let r = e - (lo + (bin as f64 + 0.5) * w);
        let mut acc = dot(&row_at(bin * nt + nt - 1), &v);
        for j in (0..nt - 1).rev() {
            let d = dot(&row_at(bin * nt + j), &v);
            for b in 0..L {
                acc[b] = acc[b] * r + d[b];
            }
        }
        for b in 0..L {
            if running[b] {
                outs[b].push(acc[b] * scale_y[b] - d0[b]);
            }
        }
    }
}
