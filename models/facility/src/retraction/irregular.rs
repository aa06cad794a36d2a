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
//! the series (measured in `docs/performance.md`, "Irregular sampling"). The bins are set up
//! in balanced coordinates ([`balance`]), where the norm that sets the terms is that of the
//! dynamics, not of the units; a stiff model's fast real modes, gone from the first grid point
//! on, are split off the bins' matrix ([`without_fast_modes`], `super::spectral`), and what
//! stiffness remains takes two levels of bins (row bins times sub-bins: [`cheapest_bins`]). With `N = N_AUG` the same reads the samples before a
//! voltage ramp ends ([`Irregular::run_to`]). The grid step is the median interval, or the
//! shortest common one when the steps come in a few sizes ([`typical_step`]).

use super::expm::{Mat, N_AUG, N_HOM, dotn, expm_n as expm, propagator};
use super::spectral::{FAST_DECAY, balance, without_fast_modes};

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

/// Intervals the typical step of a long record is taken from.
const STEP_SAMPLE: usize = 4095;

/// `v^T m` (a row times a matrix), the columns computed side by side, each sum left to right.
#[inline(always)]
fn row_times<const N: usize>(v: &[f64; N], m: &[[f64; N]; N]) -> [f64; N] {
    std::array::from_fn(|c| {
        let mut s = v[0] * m[0][c];
        for i in 1..N {
            s += v[i] * m[i][c];
        }
        s
    })
}

/// The cheapest bins for `n` samples whose offsets span `span` [s] with `|A| = a_norm`: the
/// number of bins, the terms of each bin's series and the sub-bins `k2` of each row bin (1:
/// one level). One level: a bin costs its `n_terms` rows to set up (a row times a matrix
/// each) and a sample its `n_terms` rows to read, `nb * n_terms * 5 + n * n_terms` dot
/// products. Two levels (a stiff model, whose series needs many bins): `nb = k1 k2` bins whose
/// exponentials are those of `k1` row bins times those of `k2` sub-bins, `k1 * n_terms` rows
/// and `k2` matrices to set up, and per sample a matrix times the state (5 dot products) more,
/// `k1 * n_terms * 5 + k2 * 25 + n * (n_terms + 5)`. The count minimises the cost over halvings
/// from the fewest bins that keep half a bin within `OFFSET_NORM` downwards, as long as the
/// series reaches rounding within [`MAX_TERMS`]; `None` when even [`MAX_BINS`] bins do not.
fn cheapest_bins(a_norm: f64, span: f64, n: usize) -> Option<(usize, usize, usize)> {
    let want = (a_norm * span / (2.0 * OFFSET_NORM)).ceil();
    let mut nb = if want >= MAX_BINS as f64 {
        MAX_BINS
    } else {
        (want as usize).max(1)
    };
    let mut best: Option<(usize, usize, usize, f64)> = None;
    loop {
        if let Some(nt) = terms(a_norm * span / (2.0 * nb as f64)) {
            let one = (nb * nt * N_HOM + n * nt) as f64;
            if best.is_none_or(|(.., c)| one < c) {
                best = Some((nb, nt, 1, one));
            }
            // two levels: k1 row bins of k2 sub-bins each (at least nb bins in all)
            let k1 = (nb as f64).sqrt().ceil() as usize;
            let k2 = nb.div_ceil(k1);
            if k2 > 1 {
                let two = (k1 * nt * N_HOM + k2 * N_HOM * N_HOM + n * (nt + N_HOM)) as f64;
                if best.is_none_or(|(.., c)| two < c) {
                    best = Some((k1 * k2, nt, k2, two));
                }
            }
        }
        if nb == 1 {
            break;
        }
        nb = nb.div_ceil(2);
    }
    best.map(|(nb, nt, k2, _)| (nb, nt, k2))
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

/// The leading `N x N` block of `m` (`N_HOM`: the homogeneous part once the voltage is off;
/// `N_AUG`: all of it, the voltage and its ramp included).
fn block<const N: usize>(m: &Mat) -> [[f64; N]; N] {
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

/// The typical step of `times` after `t0`: the median of its intervals (or of [`STEP_SAMPLE`]
/// of them at fixed pseudo-random places), or their tenth percentile when that is below two
/// thirds of the median; `None` for fewer than two samples, a time stamp that is not a number
/// or not after the one before it (the caller then propagates interval by interval). The
/// percentile: the fit's search copy of a gapped record (its dense head one sample in 7
/// missing, its tail thinned to one in 12) has more intervals of two steps and more than of
/// one, and a grid of two steps put half its samples half a step off it (a stiff start's bins
/// then refused, an exponential per interval: 8.5 million in one `discover`). Jittered stamps
/// (sd 10 %, intervals of sd 14 %) keep the median: one grid step per sample.
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
    let (_, &mut median, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    let q = d.len() / 10;
    let low = if q < mid {
        *d[..mid].select_nth_unstable_by(q, f64::total_cmp).1
    } else {
        median
    };
    // steps of a few sizes (gaps, a thinned copy): the shortest common one; a continuous
    // spread (jitter): the median, one grid step per sample
    let h = if low < median / 1.5 { low } else { median };
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
    /// A fit evaluates the same record's stamps for every parameter vector: the last ones
    /// each thread computed are kept with a copy of their time stamps, and given again when
    /// the stamps are the same bit for bit (comparing them costs a tenth of the median's
    /// selection, 4 % of a `discover` on a 1 000-sample jittered record).
    pub(super) fn of(t0: f64, times: &[f64]) -> Option<Stamps> {
        thread_local! {
            static LAST: std::cell::RefCell<(u64, Vec<u64>, Option<Stamps>)> =
                const { std::cell::RefCell::new((0, Vec::new(), None)) };
        }
        let same = |last: &(u64, Vec<u64>, Option<Stamps>)| {
            last.0 == t0.to_bits()
                && last.1.len() == times.len()
                && last.1.iter().zip(times).all(|(a, b)| *a == b.to_bits())
        };
        if let Some(s) = LAST.with_borrow(|last| same(last).then_some(last.2)) {
            return s;
        }
        let s = Stamps::compute(t0, times);
        LAST.with_borrow_mut(|last| {
            last.0 = t0.to_bits();
            last.1.clear();
            last.1.extend(times.iter().map(|t| t.to_bits()));
            last.2 = s;
        });
        s
    }

    fn compute(t0: f64, times: &[f64]) -> Option<Stamps> {
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
/// ([`Irregular::run`], or several side by side: [`run_lanes`]). `N`: the states carried,
/// `N_HOM` once the voltage is off, `N_AUG` while its ramp runs (the augmented system is
/// homogeneous as well until the ramp ends: [`Irregular::run_to`]).
pub(super) struct Irregular<const N: usize = N_HOM> {
    /// `exp(A h)` of the leading `N x N` block.
    m: [[f64; N]; N],
    /// `rows[b * n_terms + j] = e_y^T exp(A c_b) A^j / j!` for the centre `c_b` of bin `b`;
    /// with two levels (`k2 > 1`), `c_b` is the start `b k2 w` of row bin `b`.
    rows: Vec<[f64; N]>,
    /// `rows` by row bin with its terms innermost (`rows_t[(b * N + i) * n_terms + j]` is
    /// entry `i` of term `j` of bin `b`): a lane alone computes a sample's terms side by side
    /// ([`run_lanes_body`]).
    rows_t: Vec<f64>,
    /// With two levels, `sub[k] = exp(A (k + 1/2) w)` for the sub-bins of a row bin: a
    /// sample in bin `k1 k2 + k` reads the rows of `k1` against `sub[k]` times the state.
    sub: Vec<[[f64; N]; N]>,
    /// Sub-bins per row bin (1: one level, `sub` empty).
    pub(super) k2: usize,
    /// Bins of the offsets in `[0, h)` from the grid point at or before a sample; or one,
    /// centred on the nearest grid point, when every sample of the record is within
    /// `OFFSET_NORM / |A|` of its nearest one (a gapped record: few terms, no bins to build).
    pub(super) nb: usize,
    /// Terms of each bin's series.
    pub(super) n_terms: usize,
    /// Whether the one bin is centred on the nearest grid point.
    pub(super) centred: bool,
    /// Whether the bins cover the model without its fast modes ([`without_fast_modes`]): the
    /// samples before the first grid point after `t0`, where those modes have not decayed
    /// yet, are then read by an exponential each.
    pub(super) fast: bool,
    /// The homogeneous system matrix (for a long gap's exponential).
    a: Mat,
    /// The balancing scales (powers of two): the state is carried as `D^-1 v`, `m` is
    /// `D^-1 exp(A h) D` and the rows `e_y^T exp(A c) A^j D / j!` ([`balance`]).
    d: [f64; N],
    /// The scaled state at `t0`, balanced (`D^-1 z`).
    v: [f64; N],
    t0: f64,
    h: f64,
    /// Width of a bin and the lower end of the first [s] (`-h/2` with one bin, else 0).
    w: f64,
    lo: f64,
    scale_y: f64,
    d0: f64,
}

impl<const N: usize> Irregular<N> {
    /// The tail from the scaled state `z` at `stamps.t0` over the samples of `stamps`, or
    /// `None` when the voltage is still on (for `N_HOM` states) or the model is so stiff that
    /// [`MAX_BINS`] bins of [`MAX_TERMS`] terms do not reach rounding.
    pub(super) fn new(
        a: &Mat,
        z: &[f64; N_AUG],
        stamps: &Stamps,
        scale_y: f64,
        d0: f64,
    ) -> Option<Irregular<N>> {
        let Stamps { t0, h, e_max, .. } = *stamps;
        if z[N..].iter().any(|&v| v != 0.0) || h.is_nan() || h <= 0.0 {
            return None;
        }
        // in balanced coordinates (`D^-1 A D`, `D` powers of two: exact), where the norm that
        // sets the series' terms is nearer the dynamics than the unbalanced matrix's row sums
        // (a light plunger, `Mg` 1e-5 kg as a search start at its bound: `|A| h` 96 against
        // 7.4; the thesis model with its plunger 1.06 against 0.77)
        let a_raw = block::<N>(a);
        if a_raw.iter().flatten().any(|v| !v.is_finite()) {
            return None;
        }
        let d = balance(&a_raw);
        let sim = |x: &[[f64; N]; N]| -> [[f64; N]; N] {
            std::array::from_fn(|i| std::array::from_fn(|j| x[i][j] * d[j] / d[i]))
        };
        let a5 = sim(&a_raw);
        let a_norm = a5
            .iter()
            .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0f64, f64::max);
        if !a_norm.is_finite() {
            return None;
        }
        // every sample within OFFSET_NORM of its nearest grid point: one bin centred on it,
        // and the terms the largest offset needs; otherwise bins across the step after the
        // grid point at or before a sample (forwards only: an exponential backwards in time
        // would amplify a stiff model's decayed modes), as many as cost least
        let centred = a_norm * e_max <= OFFSET_NORM;
        // the matrix the bins' series cover: a stiff model's without its fast modes, gone from
        // the first grid point on (the samples before it are read exactly: `fast`); only a
        // norm of at least |FAST_DECAY| / h can hold such a mode
        let split = (!centred && a_norm * h >= -FAST_DECAY)
            .then(|| without_fast_modes(&a5, h))
            .flatten();
        let fast = split.is_some();
        let ser = split.unwrap_or(a5);
        let ser_norm = ser
            .iter()
            .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0f64, f64::max);
        let (nb, n_terms, k2, lo) = if centred {
            (1, terms(a_norm * e_max)?, 1, -0.5 * h)
        } else {
            let (nb, nt, k2) = cheapest_bins(ser_norm, h, stamps.n)?;
            (nb, nt, k2, 0.0)
        };
        let w = h / nb as f64;
        // the exponentials of the balanced N x N block itself (the leading block of the
        // augmented exponential: the voltage's rows do not depend on the mechanics), whose
        // norm needs fewer squarings than the augmented matrix's (a third of `new`'s cost on
        // a 1 000-sample record went to three exponentials of the unbalanced 7 x 7 matrix)
        let m = expm(&a5, h);
        // (the grid step with every mode, fast ones included: they decay on it, rounding too);
        // the first row of each bin: e_y^T D (the grid point itself), or e_y^T exp(A w / 2) D
        // then one bin's width after the other, `A` the series' matrix `ser`
        let mut first = Vec::with_capacity(nb);
        let mut sub = Vec::new();
        if centred {
            first.push(std::array::from_fn(|i| if i == 1 { d[1] } else { 0.0 }));
        } else if k2 > 1 {
            // the row bins' starts, k2 bins apart, and the sub-bins' centres
            let step = expm(&ser, w * k2 as f64);
            let mut c: [f64; N] = std::array::from_fn(|i| if i == 1 { d[1] } else { 0.0 });
            for b in 0..nb / k2 {
                if b > 0 {
                    c = row_times(&c, &step);
                }
                first.push(c);
            }
            let fine = expm(&ser, w);
            let mut s_k = expm(&ser, w / 2.0);
            for k in 0..k2 {
                if k > 0 {
                    s_k = std::array::from_fn(|i| {
                        std::array::from_fn(|j| {
                            let mut acc = fine[i][0] * s_k[0][j];
                            for l in 1..N {
                                acc += fine[i][l] * s_k[l][j];
                            }
                            acc
                        })
                    });
                }
                sub.push(s_k);
            }
        } else {
            // exp(A w) as the square of exp(A w / 2): one product instead of an exponential
            // (a third of `new`'s exponentials)
            let half = expm(&ser, w / 2.0);
            let step: [[f64; N]; N] = std::array::from_fn(|i| row_times(&half[i], &half));
            let mut c: [f64; N] = half[1].map(|v| v * d[1]);
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
        let mut powers = vec![[[0.0; N]; N]; n_terms];
        powers[0] = std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))));
        for j in 1..n_terms {
            let p = powers[j - 1];
            powers[j] = std::array::from_fn(|i| row_times(&p[i], &ser).map(|v| v / j as f64));
        }
        let mut rows = Vec::with_capacity(nb * n_terms);
        for c in &first {
            rows.push(*c);
            rows.extend(powers[1..].iter().map(|p| row_times(c, p)));
        }
        let mut rows_t = Vec::with_capacity(rows.len() * N);
        for bin in rows.chunks(n_terms) {
            for i in 0..N {
                rows_t.extend(bin.iter().map(|r| r[i]));
            }
        }
        let v: [f64; N] = std::array::from_fn(|i| z[i] / d[i]);
        Some(Irregular {
            m,
            rows,
            rows_t,
            nb,
            n_terms,
            sub,
            k2,
            centred,
            fast,
            a: *a,
            d,
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
        let rows = self.nb / self.k2;
        let mut dots = (rows * (self.n_terms + 1) * N) as f64;
        let per_sample = if self.k2 > 1 {
            dots += (self.k2 * N * N) as f64;
            self.n_terms + N
        } else {
            self.n_terms
        };
        for &ti in times {
            let gi = ((ti - self.t0) / self.h + half) as u64;
            if gi > g {
                dots += if gi - g > GAP_STEPS {
                    exp_dots
                } else {
                    ((gi - g) * N as u64) as f64
                };
                g = gi;
            }
            dots += per_sample as f64;
        }
        dots
    }

    /// The output at `times` (increasing, after `t0`) pushed onto `out`: [`run_lanes`] with
    /// one lane, so that a lane of several gives these bits.
    pub(super) fn run(&self, times: &[f64], out: &mut Vec<f64>) {
        run_lanes_state([self], times, std::slice::from_mut(out));
    }

    /// [`Irregular::run`], and the scaled state at the grid point of the last sample (the one
    /// at or before it, or the nearest with one centred bin) with that point's time [s]: where
    /// the voltage ramp's segment ends, the state is carried on from there to the ramp's end.
    pub(super) fn run_to(&self, times: &[f64], out: &mut Vec<f64>) -> ([f64; N], f64) {
        let (v, g) = run_lanes_state([self], times, std::slice::from_mut(out));
        (
            std::array::from_fn(|i| v[i][0] * self.d[i]),
            self.t0 + g as f64 * self.h,
        )
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
    run_lanes_state(tails, times, outs);
}

/// [`run_lanes`] for any number of states, returning the lanes' state at the last grid point
/// reached and its index.
fn run_lanes_state<const N: usize, const L: usize>(
    tails: [&Irregular<N>; L],
    times: &[f64],
    outs: &mut [Vec<f64>],
) -> ([[f64; L]; N], u64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the processor has AVX (checked just above)
        return unsafe { run_lanes_avx(tails, times, outs) };
    }
    run_lanes_body(tails, times, outs)
}

/// [`run_lanes_body`] compiled for AVX: the same operations in the same order, without fused
/// multiply-adds, so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn run_lanes_avx<const N: usize, const L: usize>(
    tails: [&Irregular<N>; L],
    times: &[f64],
    outs: &mut [Vec<f64>],
) -> ([[f64; L]; N], u64) {
    run_lanes_body(tails, times, outs)
}

/// A lane alone's reading of a sample: the `NT` terms' dot products with the state `u` (each
/// summed over the state left to right, as `run_lanes_body`'s `dot`), side by side in
/// registers, then Horner's scheme in `r`: the bits of the lanes' reading. `rt`: the bin's
/// rows, terms innermost.
#[inline(always)]
fn read_nt<const N: usize, const NT: usize>(rt: &[f64], u: &[f64; N], r: f64) -> f64 {
    let rt = &rt[..N * NT];
    let mut d = [0.0; NT];
    for (j, dj) in d.iter_mut().enumerate() {
        *dj = rt[j] * u[0];
    }
    for (i, ui) in u.iter().enumerate().skip(1) {
        for (j, dj) in d.iter_mut().enumerate() {
            *dj += rt[i * NT + j] * ui;
        }
    }
    let mut acc = d[NT - 1];
    for j in (0..NT - 1).rev() {
        acc = acc * r + d[j];
    }
    acc
}

/// [`read_nt`] for `nt` terms (1 to [`MAX_TERMS`]): the count a constant, so that the terms
/// stay in registers (with a count known only at run time they went through memory, and a
/// lane alone took three times a lane of four per sample).
#[inline(always)]
fn read_terms<const N: usize>(nt: usize, rt: &[f64], u: &[f64; N], r: f64) -> f64 {
    macro_rules! by_count {
        ($($k:literal)*) => {
            match nt {
                $($k => read_nt::<N, $k>(rt, u, r),)*
                _ => unreachable!("1 to {MAX_TERMS} terms"),
            }
        };
    }
    by_count!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// The body of [`run_lanes`]. The grid point of a sample is the one at or before it, `g =
/// floor((t - t0) / h)`, or with one bin the nearest (`(t - t0) / h + 1/2`), by a truncating
/// conversion (no `floor` call; a negative number converts to 0), and its offset `e` falls in
/// bin `(e - lo) / w`; both are the same for every lane.
#[inline(always)]
fn run_lanes_body<const N: usize, const L: usize>(
    tails: [&Irregular<N>; L],
    times: &[f64],
    outs: &mut [Vec<f64>],
) -> ([[f64; L]; N], u64) {
    let n = times.len();
    let t = tails[0];
    let (nt, nb) = (t.n_terms, t.nb);
    debug_assert!(tails.iter().all(|x| x.n_terms == nt
        && x.nb == nb
        && x.k2 == t.k2
        && x.centred == t.centred
        && x.fast == t.fast));
    let m: [[[f64; L]; N]; N] =
        std::array::from_fn(|i| std::array::from_fn(|j| std::array::from_fn(|b| tails[b].m[i][j])));
    let mut v: [[f64; L]; N] = std::array::from_fn(|i| std::array::from_fn(|b| tails[b].v[i]));
    // several lanes' rows side by side, so that a sample's terms are read whole (one lane
    // reads its own)
    let table: Vec<[[f64; L]; N]> = if L > 1 {
        (0..(nb / t.k2) * nt)
            .map(|k| std::array::from_fn(|i| std::array::from_fn(|b| tails[b].rows[k][i])))
            .collect()
    } else {
        Vec::new()
    };
    let row_at = |k: usize| -> [[f64; L]; N] { table[k] };
    // the sub-bins' matrices of every lane side by side (two levels only)
    let k2 = t.k2;
    let subs: Vec<[[[f64; L]; N]; N]> = (0..if k2 > 1 { k2 } else { 0 })
        .map(|k| {
            std::array::from_fn(|i| {
                std::array::from_fn(|j| std::array::from_fn(|b| tails[b].sub[k][i][j]))
            })
        })
        .collect();
    let scale_y: [f64; L] = std::array::from_fn(|b| tails[b].scale_y);
    let d0: [f64; L] = std::array::from_fn(|b| tails[b].d0);
    let (t0, h, w, lo) = (t.t0, t.h, t.w, t.lo);
    let inv_h = 1.0 / h;
    let half = if t.centred { 0.5 } else { 0.0 };
    let inv_w = nb as f64 / h;
    let dot = |r: &[[f64; L]; N], v: &[[f64; L]; N]| -> [f64; L] {
        std::array::from_fn(|b| {
            let mut s = r[0][b] * v[0][b];
            for i in 1..N {
                s += r[i][b] * v[i][b];
            }
            s
        })
    };
    let mut running = [true; L];
    let mut g = 0u64;
    // a lane alone reads its samples a chunk at a time, after the chunk's states: the
    // readings are then independent of one another and of the state's chain, and overlap
    let mut pending: Vec<(usize, [f64; N], f64)> =
        Vec::with_capacity(if L == 1 { CHUNK } else { 0 });
    let flush = |pending: &mut Vec<(usize, [f64; N], f64)>, out: &mut Vec<f64>| {
        out.extend(pending.drain(..).map(|(rb, u, r)| {
            let rt = &t.rows_t[rb * N * nt..(rb + 1) * N * nt];
            read_terms(nt, rt, &u, r) * scale_y[0] - d0[0]
        }));
    };
    for (k, &ti) in times.iter().enumerate() {
        let gi = ((ti - t0) * inv_h + half) as u64;
        if gi > g {
            if gi - g > GAP_STEPS {
                cross_gap(&tails, &mut v, (gi - g) as f64 * h);
            } else {
                for _ in g..gi {
                    let mut u = [[0.0; L]; N];
                    for (ui, mi) in u.iter_mut().zip(&m) {
                        *ui = dot(mi, &v);
                    }
                    v = u;
                }
            }
            g = gi;
            let rest: [bool; L] = std::array::from_fn(|b| (0..N).all(|i| v[i][b].abs() < 1e-30));
            if (0..L).any(|b| rest[b] && running[b]) {
                // at rest (see `retraction`): held at -d0 exactly
                if L == 1 {
                    flush(&mut pending, &mut outs[0]);
                }
                for b in 0..L {
                    if rest[b] && running[b] {
                        outs[b].extend(std::iter::repeat_n(-d0[b], n - k));
                        running[b] = false;
                    }
                }
                if !running.iter().any(|&r| r) {
                    return (v, g);
                }
            }
        }
        let e = ti - (t0 + g as f64 * h);
        if t.fast && g == 0 {
            // before the first grid point the fast modes have not decayed: exactly
            if L == 1 {
                flush(&mut pending, &mut outs[0]);
            }
            read_exactly(&tails, &v, e, &running, outs);
            continue;
        }
        let bin = (((e - lo) * inv_w) as usize).min(nb - 1);
        let r = e - (lo + (bin as f64 + 0.5) * w);
        // two levels: the state carried to the sub-bin's centre within its row bin first
        let (rb, u) = if k2 > 1 {
            let s = &subs[bin % k2];
            let mut u = [[0.0; L]; N];
            for (ui, si) in u.iter_mut().zip(s) {
                *ui = dot(si, &v);
            }
            (bin / k2, u)
        } else {
            (bin, v)
        };
        if L == 1 {
            // a lane alone: the terms' dot products side by side (each summed over the state
            // left to right, as `dot`), then Horner's scheme as below ([`read_terms`]): the
            // same bits
            pending.push((rb, std::array::from_fn(|i| u[i][0]), r));
            if pending.len() == CHUNK {
                flush(&mut pending, &mut outs[0]);
            }
            continue;
        }
        let mut acc = dot(&row_at(rb * nt + nt - 1), &u);
        for j in (0..nt - 1).rev() {
            let d = dot(&row_at(rb * nt + j), &u);
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
    if L == 1 {
        flush(&mut pending, &mut outs[0]);
    }
    (v, g)
}

/// A long gap of `dt` [s] crossed by one exponential per lane (the lanes' balanced states `v`).
fn cross_gap<const N: usize, const L: usize>(
    tails: &[&Irregular<N>; L],
    v: &mut [[f64; L]; N],
    dt: f64,
) {
    for (b, x) in tails.iter().enumerate() {
        let p = block::<N>(&propagator(&x.a, dt));
        let p: [[f64; N]; N] =
            std::array::from_fn(|i| std::array::from_fn(|j| p[i][j] * x.d[j] / x.d[i]));
        let vb: [f64; N] = std::array::from_fn(|i| v[i][b]);
        for i in 0..N {
            v[i][b] = dotn(&p[i], &vb);
        }
    }
}

/// The reading `e` [s] after the lanes' first grid point (balanced states `v`) by an
/// exponential each: a fast mode split off the bins has not decayed there.
fn read_exactly<const N: usize, const L: usize>(
    tails: &[&Irregular<N>; L],
    v: &[[f64; L]; N],
    e: f64,
    running: &[bool; L],
    outs: &mut [Vec<f64>],
) {
    for (b, x) in tails.iter().enumerate() {
        if running[b] {
            let p = propagator(&x.a, e);
            let y: f64 = (0..N).map(|j| p[1][j] * (v[j][b] * x.d[j])).sum();
            outs[b].push(y * x.scale_y - x.d0);
        }
    }
}

/// Samples a lane alone reads together ([`run_lanes_body`]).
const CHUNK: usize = 64;
#[cfg(test)]
mod tests {
    use super::*;
    use crate::retraction::RtConfig;

    /// The largest absolute row sum of a 5 x 5 matrix times the 1 us step.
    fn norm_h(m: &[[f64; N_HOM]; N_HOM]) -> f64 {
        m.iter()
            .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max)
            * 1e-6
    }

    /// Balancing is an exact similarity (powers of two, the diagonal kept) that brings the
    /// norm that sets the bins towards the dynamics: a light plunger (`Mg` 1e-5 kg, a start
    /// at its lower bound) has `|A| h` 96 unbalanced and 7.4 balanced (measured), and a
    /// 20 000-sample jittered record then reads each sample with 6 terms of its series instead
    /// of 9; the thesis model with its plunger is nearly balanced already (1.06 and 0.77).
    #[test]
    fn balancing_brings_the_norm_to_the_dynamics() {
        let light_plunger = RtConfig {
            plunger: Some((1e-5, 2.15e6)),
            ..RtConfig::default()
        };
        let (_, a, _) = light_plunger.scaled_start();
        let a5 = block::<N_HOM>(&a);
        let d = balance(&a5);
        assert!(d.iter().all(|v| v.log2().fract() == 0.0), "{d:?}");
        let b: [[f64; N_HOM]; N_HOM] =
            std::array::from_fn(|i| std::array::from_fn(|j| a5[i][j] * d[j] / d[i]));
        assert!((0..N_HOM).all(|i| b[i][i] == a5[i][i]));
        let (raw, bal) = (norm_h(&a5), norm_h(&b));
        assert!(raw > 90.0 && bal < raw / 10.0, "{raw} -> {bal}");
        let u = cheapest_bins(raw / 1e-6, 1e-6, 20_000).unwrap();
        let b_ = cheapest_bins(bal / 1e-6, 1e-6, 20_000).unwrap();
        // measured: 1 024 bins of 9 terms unbalanced, 924 of 6 balanced
        assert!(u.1 >= b_.1 + 3 && b_.0 <= u.0, "{u:?} against {b_:?}");
        // ... and the tail sets its bins up so: 20 000 time stamps at 1 us jittered by a
        // deterministic +-0.2 us
        let times: Vec<f64> = (1..=20_000)
            .map(|i| i as f64 * 1e-6 + 2e-7 * ((i as f64 * 0.618_034).fract() - 0.5))
            .collect();
        let (_, a, z) = light_plunger.scaled_start();
        let stamps = Stamps::of(0.0, &times).expect("increasing");
        let irr: Irregular = Irregular::new(&a, &z, &stamps, 1.0, 0.0).expect("bins");
        assert!(irr.n_terms <= b_.1, "{} terms", irr.n_terms);
        let (_, a, _) = RtConfig {
            plunger: Some((0.019, 2.15e6)),
            ..RtConfig::default()
        }
        .scaled_start();
        let a5 = block::<N_HOM>(&a);
        let d = balance(&a5);
        let b: [[f64; N_HOM]; N_HOM] =
            std::array::from_fn(|i| std::array::from_fn(|j| a5[i][j] * d[j] / d[i]));
        assert!(norm_h(&b) <= norm_h(&a5), "{} {}", norm_h(&b), norm_h(&a5));
    }
}
