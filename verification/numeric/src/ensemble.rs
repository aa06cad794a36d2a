//! `geodesic fit --posterior` (issue 13, item 4): samples the parameters' posterior with the
//! affine-invariant ensemble sampler of Goodman and Weare (2010, "Ensemble samplers with affine
//! invariance", CAMCoS 5, 65; the "stretch move" of Python's emcee).
//!
//! * Target: `ln p(u) = -chi2(u)/2` (the fit's own whitened, normalised residual at the fit's
//!   noise figure) with flat priors over each free parameter's range in the fit's coordinates
//!   (log for the log-fitted ones), `-inf` outside; the other parameters held at the fit's
//!   values.
//! * Walkers: `max(8 k, 32)` (even; `EnsembleOptions::walkers` to choose), started in a small
//!   ball (0.1 of the fit's 1-sigma) around the best fit; the ensemble is split in two halves updated in turn, each walker moving along
//!   the line to a walker of the other half by `z ~ g(z) ∝ 1/sqrt(z)` on `[1/2, 2]`, accepted with
//!   `min(1, z^(k-1) p(new)/p(old))`; the halves' log posteriors are evaluated in parallel.
//!   Every walker's random numbers come from its own ChaCha8 stream (`seed`, step, walker), so
//!   the chain is the same for any thread count.
//! * `steps` per walker, the first third discarded as burn-in; the summary is the marginal
//!   quantiles of the rest, mapped back to physical units.
//! * Flags per parameter: `prior_limited` when the 95 % interval reaches within 1 % of the
//!   range's width of a bound; `multimodal` when the marginal histogram (24 bins over the 0.5-
//!   99.5 % span) has two local maxima, each at least a fifth of the highest, separated by a bin
//!   below half the lower one.
//!
//! * Convergence: the integrated autocorrelation time `tau` of each parameter, in steps, from
//!   the walkers' mean normalised autocorrelation function summed with Sokal's automatic window
//!   (the smallest lag `M >= 5 tau(M)`; Goodman and Weare 2010, emcee's `integrated_time`);
//!   `converged` when the kept steps per walker are at least [`CONVERGED_TAUS`] `tau` (emcee's
//!   rule of thumb), else the quantiles are not yet to be trusted and more `--posterior-steps`
//!   are needed. The effective number of independent samples is `walkers x kept / tau`.
//!
//! Why by hand: the one Rust crate with this sampler (`emcee` 0.3, 2018) computes the log
//! probability in `f32`, which cannot resolve chi-square differences of order 1 on values of
//! order 10^5; the move is 30 lines.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Settings of the sampler.
#[derive(Debug, Clone, Copy)]
pub struct EnsembleOptions {
    /// Steps per walker (a third discarded as burn-in).
    pub steps: usize,
    /// Seed.
    pub seed: u64,
    /// Walkers (`None`: `max(8 k, 32)`), rounded up to even.
    pub walkers: Option<usize>,
}

impl Default for EnsembleOptions {
    fn default() -> Self {
        EnsembleOptions {
            steps: 1500,
            seed: 1,
            walkers: None,
        }
    }
}

/// The samples and their diagnostics.
#[derive(Debug, Clone)]
pub struct Chain {
    /// Kept samples, in the fit's coordinates (one vector per sample, free parameters).
    pub samples: Vec<Vec<f64>>,
    /// Fraction of accepted moves.
    pub acceptance: f64,
    /// Walkers.
    pub walkers: usize,
}

/// Samples `ln_p` (in the fit's coordinates) from `u0` with per-coordinate scale `scale`,
/// bounds `lo`, `hi`.
pub fn sample(
    ln_p: &(dyn Fn(&[f64]) -> f64 + Sync),
    u0: &[f64],
    scale: &[f64],
    lo: &[f64],
    hi: &[f64],
    opts: &EnsembleOptions,
) -> Chain {
    let k = u0.len();
    let w = opts
        .walkers
        .unwrap_or((8 * k).max(32))
        .max(4)
        .next_multiple_of(2);
    let rng_of = |step: usize, walker: usize| {
        let mut r = ChaCha8Rng::seed_from_u64(opts.seed);
        r.set_stream((step * w + walker) as u64);
        r
    };
    let normal = |r: &mut ChaCha8Rng| -> f64 {
        let (u1, u2): (f64, f64) = (r.random_range(1e-300..1.0), r.random_range(0.0..1.0));
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    // initial ball around the best fit, inside the bounds
    let mut pos: Vec<Vec<f64>> = (0..w)
        .map(|j| {
            let mut r = rng_of(0, j);
            (0..k)
                .map(|i| {
                    let s = if scale[i].is_finite() && scale[i] > 0.0 {
                        scale[i]
                    } else {
                        1e-6 * (1.0 + u0[i].abs())
                    };
                    (u0[i] + 0.1 * s * normal(&mut r)).clamp(lo[i], hi[i])
                })
                .collect()
        })
        .collect();
    let mut lp: Vec<f64> = pos.par_iter().map(|u| ln_p(u)).collect();
    let burn = opts.steps / 3;
    let mut samples = Vec::with_capacity((opts.steps - burn) * w);
    let (mut accepted, mut proposed) = (0usize, 0usize);
    let half = w / 2;
    for step in 1..=opts.steps {
        for h in 0..2 {
            let (active, other) = if h == 0 {
                (0..half, half..w)
            } else {
                (half..w, 0..half)
            };
            let others: Vec<Vec<f64>> = other.map(|j| pos[j].clone()).collect();
            let moves: Vec<(usize, Vec<f64>, f64, f64)> = active
                .clone()
                .into_par_iter()
                .map(|j| {
                    let mut r = rng_of(step, j);
                    let c = &others[r.random_range(0..others.len())];
                    // z ~ 1/sqrt(z) on [1/2, 2]: z = (1 + (a - 1) x)^2 / a with a = 2
                    let x: f64 = r.random_range(0.0..1.0);
                    let z = (1.0 + x).powi(2) / 2.0;
                    let y: Vec<f64> = (0..k).map(|i| c[i] + z * (pos[j][i] - c[i])).collect();
                    let inside = y
                        .iter()
                        .zip(lo.iter().zip(hi))
                        .all(|(v, (l, h))| v >= l && v <= h);
                    let lpy = if inside { ln_p(&y) } else { f64::NEG_INFINITY };
                    let log_ratio = (k as f64 - 1.0) * z.ln() + lpy - lp[j];
                    let accept_u: f64 = r.random_range(0.0..1.0);
                    (j, y, lpy, if accept_u.ln() < log_ratio { 1.0 } else { 0.0 })
                })
                .collect();
            for (j, y, lpy, a) in moves {
                proposed += 1;
                if a > 0.0 {
                    accepted += 1;
                    pos[j] = y;
                    lp[j] = lpy;
                }
            }
        }
        if step > burn {
            samples.extend(pos.iter().cloned());
        }
    }
    Chain {
        samples,
        acceptance: accepted as f64 / proposed.max(1) as f64,
        walkers: w,
    }
}

/// Kept steps per walker, in integrated autocorrelation times, for a chain to count as
/// converged (emcee's documentation: "at least 50 tau").
pub const CONVERGED_TAUS: f64 = 50.0;

/// Sokal's window constant: the autocorrelation is summed up to the smallest lag `M` with
/// `M >= SOKAL_C tau(M)`.
const SOKAL_C: f64 = 5.0;

/// Integrated autocorrelation time [steps] of coordinate `i` of the chain: the walkers' mean
/// normalised autocorrelation function `rho(t)`, `tau(M) = 1 + 2 sum_{t=1..M} rho(t)`, at the
/// smallest `M >= 5 tau(M)`; when the window never closes within the kept steps, `tau` at the
/// last lag (a lower bound: the chain is then far too short). Each walker's series is centred
/// on its own mean; its autocovariance comes from an FFT of the series zero-padded to twice its
/// length (`rustfft`, as emcee does with numpy): O(n log n) per walker, where the direct sum over
/// lags was O(n^2), minutes for the 100 000 steps `--posterior-steps` allows.
pub fn autocorr_time(chain: &Chain, i: usize) -> f64 {
    let w = chain.walkers.max(1);
    let n = chain.samples.len() / w;
    if n < 2 {
        return f64::INFINITY;
    }
    let len = (2 * n).next_power_of_two();
    let mut planner = rustfft::FftPlanner::<f64>::new();
    let (fwd, inv) = (planner.plan_fft_forward(len), planner.plan_fft_inverse(len));
    let zero = rustfft::num_complex::Complex::new(0.0, 0.0);
    let mut rho = vec![0.0; n];
    let mut used = 0usize;
    let mut buf = vec![zero; len];
    for j in 0..w {
        let m = (0..n).map(|s| chain.samples[s * w + j][i]).sum::<f64>() / n as f64;
        buf.fill(zero);
        for (s, b) in buf.iter_mut().enumerate().take(n) {
            b.re = chain.samples[s * w + j][i] - m;
        }
        fwd.process(&mut buf);
        for b in buf.iter_mut() {
            *b = rustfft::num_complex::Complex::new(b.norm_sqr(), 0.0);
        }
        inv.process(&mut buf);
        // buf[t].re / len = sum_s x_s x_(s+t) (the zero padding keeps the lags from wrapping)
        let c0 = buf[0].re;
        if c0 > 0.0 {
            for (r, b) in rho.iter_mut().zip(&buf) {
                *r += b.re / c0;
            }
            used += 1;
        }
    }
    if used == 0 {
        return 1.0;
    }
    let mut tau = 1.0;
    for (t, r) in rho.iter().enumerate().skip(1) {
        tau += 2.0 * r / used as f64;
        if t as f64 >= SOKAL_C * tau {
            return tau.max(1.0);
        }
    }
    tau.max(1.0)
}

/// The marginal summary of one parameter from the chain [SI].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Marginal {
    /// Median.
    pub median: f64,
    /// 16 % quantile.
    pub lo68: f64,
    /// 84 % quantile.
    pub hi68: f64,
    /// 2.5 % quantile.
    pub lo95: f64,
    /// 97.5 % quantile.
    pub hi95: f64,
    /// The 95 % interval reaches within 1 % of the range's width of a bound.
    pub prior_limited: bool,
    /// The marginal has two separated modes.
    pub multimodal: bool,
    /// Integrated autocorrelation time [steps] ([`autocorr_time`]).
    pub autocorr_steps: f64,
    /// The kept steps per walker are at least [`CONVERGED_TAUS`] autocorrelation times.
    pub converged: bool,
}

/// Quantile `q` of sorted `v` (linear interpolation).
pub fn quantile(v: &[f64], q: f64) -> f64 {
    let x = q * (v.len() - 1) as f64;
    let (i, f) = (x.floor() as usize, x - x.floor());
    v[i] * (1.0 - f) + v[(i + 1).min(v.len() - 1)] * f
}

/// Whether sorted `v` has two separated modes (see the module documentation).
pub fn is_multimodal(v: &[f64]) -> bool {
    let (a, b) = (quantile(v, 0.005), quantile(v, 0.995));
    if b <= a {
        return false;
    }
    let nb = 24;
    let mut h = vec![0usize; nb];
    for x in v {
        if *x >= a && *x <= b {
            h[(((x - a) / (b - a) * nb as f64) as usize).min(nb - 1)] += 1;
        }
    }
    let top = *h.iter().max().unwrap_or(&0) as f64;
    let peaks: Vec<usize> = (0..nb)
        .filter(|&i| {
            let l = if i > 0 { h[i - 1] } else { 0 };
            let r = if i + 1 < nb { h[i + 1] } else { 0 };
            h[i] as f64 >= 0.2 * top && h[i] >= l && h[i] > r
        })
        .collect();
    for (x, &p) in peaks.iter().enumerate() {
        for &q in &peaks[x + 1..] {
            let lower = h[p].min(h[q]) as f64;
            if (p + 1..q).any(|m| (h[m] as f64) < 0.5 * lower) {
                return true;
            }
        }
    }
    false
}

/// The marginal of coordinate `i` of the chain, mapped back by `back` (monotone increasing),
/// with the range `[lo, hi]` in the fit's coordinates.
pub fn marginal(chain: &Chain, i: usize, lo: f64, hi: f64, back: &dyn Fn(f64) -> f64) -> Marginal {
    let tau = autocorr_time(chain, i);
    let kept = chain.samples.len() / chain.walkers.max(1);
    let mut v: Vec<f64> = chain.samples.iter().map(|s| s[i]).collect();
    v.sort_by(f64::total_cmp);
    let (l95, h95) = (quantile(&v, 0.025), quantile(&v, 0.975));
    let width = hi - lo;
    let prior_limited =
        width.is_finite() && ((l95 - lo) < 0.01 * width || (hi - h95) < 0.01 * width);
    Marginal {
        median: back(quantile(&v, 0.5)),
        lo68: back(quantile(&v, 0.158_655_253_931_457_05)),
        hi68: back(quantile(&v, 0.841_344_746_068_542_9)),
        lo95: back(l95),
        hi95: back(h95),
        prior_limited,
        multimodal: is_multimodal(&v),
        autocorr_steps: tau,
        converged: kept as f64 >= CONVERGED_TAUS * tau,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The autocorrelation time against an independent reference: walkers that are AR(1)
    /// series `x_t = phi x_(t-1) + e_t` have `tau = (1 + phi) / (1 - phi)` (19 for phi = 0.9,
    /// 1 for white noise); the estimate is within 10 %, and a chain of 40 steps of the phi = 0.9
    /// series (2 tau) does not count as converged.
    #[test]
    fn autocorrelation_time_of_ar1_walkers() {
        let ar1 = |phi: f64, n: usize, walkers: usize| -> Chain {
            let mut samples = vec![vec![0.0]; n * walkers];
            for j in 0..walkers {
                let mut r = ChaCha8Rng::seed_from_u64(7);
                r.set_stream(j as u64);
                let mut x = 0.0;
                for s in 0..n + 200 {
                    let (u1, u2): (f64, f64) =
                        (r.random_range(1e-300..1.0), r.random_range(0.0..1.0));
                    let e = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
                    x = phi * x + e;
                    if s >= 200 {
                        samples[(s - 200) * walkers + j][0] = x;
                    }
                }
            }
            Chain {
                samples,
                acceptance: 1.0,
                walkers,
            }
        };
        // the FFT autocovariance against the direct sum over lags on a short chain
        let c = ar1(0.7, 300, 4);
        let direct = |t: usize| -> f64 {
            let mut acc = 0.0;
            for j in 0..4 {
                let x: Vec<f64> = (0..300).map(|s| c.samples[s * 4 + j][0]).collect();
                let m = x.iter().sum::<f64>() / 300.0;
                let c0: f64 = x.iter().map(|v| (v - m) * (v - m)).sum();
                let ct: f64 = (0..300 - t).map(|s| (x[s] - m) * (x[s + t] - m)).sum();
                acc += ct / c0;
            }
            acc / 4.0
        };
        let mut tau_direct = 1.0;
        for t in 1..300 {
            tau_direct += 2.0 * direct(t);
            if t as f64 >= 5.0 * tau_direct {
                break;
            }
        }
        let tau_fft = autocorr_time(&c, 0);
        assert!(
            (tau_fft - tau_direct).abs() < 1e-9 * tau_direct,
            "{tau_fft} vs {tau_direct}"
        );
        for (phi, want) in [(0.9, 19.0), (0.5, 3.0), (0.0, 1.0)] {
            let tau = autocorr_time(&ar1(phi, 20_000, 16), 0);
            assert!(
                (tau / want - 1.0).abs() < 0.1,
                "phi {phi}: tau {tau} vs {want}"
            );
        }
        let short = ar1(0.9, 40, 16);
        let m = marginal(&short, 0, f64::NEG_INFINITY, f64::INFINITY, &|u| u);
        assert!(!m.converged, "{m:?}");
        let long = ar1(0.9, 20_000, 16);
        assert!(marginal(&long, 0, f64::NEG_INFINITY, f64::INFINITY, &|u| u).converged);
    }

    /// A correlated 2-D Gaussian (sigmas 1 and 3, correlation 0.9): the chain's quantiles match
    /// the normal's (median 0 +- 0.1, 68 % half-width within 10 %), the same for any thread
    /// count; a bound at the mean flags `prior_limited`; a two-bump density flags `multimodal`.
    #[test]
    fn samples_a_correlated_gaussian_and_flags_bounds_and_modes() {
        let (s1, s2, rho): (f64, f64, f64) = (1.0, 3.0, 0.9);
        let lnp = |u: &[f64]| {
            let (a, b) = (u[0] / s1, u[1] / s2);
            -0.5 * (a * a - 2.0 * rho * a * b + b * b) / (1.0 - rho * rho)
        };
        let inf = [f64::NEG_INFINITY, f64::NEG_INFINITY];
        let sup = [f64::INFINITY, f64::INFINITY];
        let opts = EnsembleOptions {
            steps: 3000,
            seed: 4,
            walkers: None,
        };
        let c = sample(&lnp, &[0.0, 0.0], &[1.0, 3.0], &inf, &sup, &opts);
        assert!(c.acceptance > 0.2 && c.acceptance < 0.9, "{}", c.acceptance);
        for (i, s) in [(0, s1), (1, s2)] {
            let m = marginal(&c, i, f64::NEG_INFINITY, f64::INFINITY, &|u| u);
            assert!(m.median.abs() < 0.1 * s, "{m:?}");
            let half = 0.5 * (m.hi68 - m.lo68);
            assert!((half / s - 1.0).abs() < 0.1, "{i}: {half} vs {s}");
            assert!(!m.prior_limited && !m.multimodal, "{m:?}");
            // the stretch move decorrelates a 2-D Gaussian in about 30 steps (32 and 31 here)
            assert!(
                m.converged && m.autocorr_steps > 10.0 && m.autocorr_steps < 60.0,
                "{m:?}"
            );
        }
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let c1 = one.install(|| sample(&lnp, &[0.0, 0.0], &[1.0, 3.0], &inf, &sup, &opts));
        assert_eq!(c1.samples, c.samples, "thread count changes the chain");
        // bounded at the mean: half a normal
        let lo = [0.0, f64::NEG_INFINITY];
        let h = sample(&lnp, &[0.5, 0.0], &[1.0, 3.0], &lo, &[10.0, 30.0], &opts);
        assert!(marginal(&h, 0, 0.0, 10.0, &|u| u).prior_limited);
        // two bumps at -3 and +3
        let two = |u: &[f64]| {
            let a = (-0.5 * (u[0] - 3.0).powi(2)).exp() + (-0.5 * (u[0] + 3.0).powi(2)).exp();
            a.ln() - 0.5 * u[1] * u[1]
        };
        let t = sample(&two, &[3.0, 0.0], &[3.0, 1.0], &inf, &sup, &opts);
        assert!(marginal(&t, 0, f64::NEG_INFINITY, f64::INFINITY, &|u| u).multimodal);
    }
}
