//! Coloured measurement noise (issue 13, item 3): an autoregressive model of the noise estimated
//! from the samples before the trigger, and the whitening filter that turns the fit's residual
//! into innovations, so that chi-square, the model comparison and the whiteness test are those
//! of the whitened residual (the exact conditional Gaussian likelihood of an AR(p) process,
//! asymptotically the Whittle likelihood of its spectrum).
//!
//! * The pre-trigger samples carry the noise and nothing else the model does not predict (the
//!   TM at rest; a linear trend is removed). If they pass the Ljung-Box whiteness test at 1 %
//!   the noise is white, as before: nothing changes.
//! * Otherwise an AR(p) model is fitted by Burg's method (stable, good on short records), the
//!   order `p` chosen by BIC (`n ln sigma_p^2 + p ln n`) up to `min(12, n / 8)`. The residual is
//!   whitened by `e_i = r_i - sum_k a_k r_{i-k}` (the first `p` samples with the lags they
//!   have) and normalised by the innovation sigma.
//! * Whitening needs evenly spaced samples: a thinned copy of a long record (the fit's search)
//!   is fitted with the white approximation at the marginal sigma; the refinement on the whole
//!   record is whitened.
//!
//! Why by hand: Burg's recursion is 30 lines and the crates that have it (signal-processing
//! toolkits) would pull a large tree for it.

use serde::{Deserialize, Serialize};

pub use crate::residual::chi2_sf;
use crate::residual::ljung_box;

/// An autoregressive noise model `n_i = sum_k a_k n_{i-k} + e_i`, `e ~ N(0, innovation^2)`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct ArNoise {
    /// `a_1 .. a_p`.
    pub coefficients: Vec<f64>,
    /// 1-sigma of the innovations `e` [SI].
    pub innovation_sigma: f64,
    /// 1-sigma of the noise itself [SI].
    pub marginal_sigma: f64,
    /// Samples it was estimated from.
    pub samples: usize,
    /// Ljung-Box p-value of the (detrended) samples it was estimated from: why the noise was
    /// judged coloured.
    pub raw_whiteness_p_value: f64,
}

impl ArNoise {
    /// Order `p`.
    pub fn order(&self) -> usize {
        self.coefficients.len()
    }

    /// Whitens `r` in place: `r_i <- r_i - sum_k a_k r_{i-k}` (lags before the start omitted).
    pub fn whiten(&self, r: &mut [f64]) {
        filter(&self.coefficients, r);
    }

    /// Twice the log-likelihood ratio of this model's colour against white noise on the quiet
    /// samples `x` (the pre-trigger, where the TM is at rest and no model can misfit): the
    /// mean removed, `(n - p) ln(var(x) / var(e))` over the samples that have all `p` lags,
    /// `e` the whitened samples, each variance the maximum-likelihood one of its model (the
    /// coefficients fixed: estimated elsewhere, on the residual). Positive when the colour
    /// describes the quiet samples better than white noise; a colour that a smooth misfit
    /// lends the residual (a coefficient near 1 on white quiet samples) makes it negative:
    /// whitening white noise doubles its variance. 0 with fewer than `p + 2` samples.
    pub fn quiet_lr(&self, x: &[f64]) -> f64 {
        let p = self.order();
        if x.len() < p + 2 {
            return 0.0;
        }
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        let mut e: Vec<f64> = x.iter().map(|v| v - mean).collect();
        let var_x = e[p..].iter().map(|v| v * v).sum::<f64>();
        self.whiten(&mut e);
        let var_e = e[p..].iter().map(|v| v * v).sum::<f64>();
        if var_x <= 0.0 || var_e <= 0.0 {
            return 0.0;
        }
        (x.len() - p) as f64 * (var_x / var_e).ln()
    }

    /// Whether the differences of the residual `r` show this model's colour (issue 50, item 3:
    /// a pre-trigger too short to tell): differencing removes a smooth misfit, which lends a
    /// residual its low-frequency colour, and keeps the noise's correlation from sample to
    /// sample. Both the first and the second differences must show it: the lag-1
    /// autocorrelation of the first is -1/2 for white noise and `-(1 - rho)/2` for AR(1), of
    /// the second -2/3 and about -1/2 for AR(1) near 1; the colour is supported when each
    /// observed figure is nearer the model's than white noise's and off white noise's by more
    /// than 5 standard errors (`1/sqrt(n)` and, for the second, Bartlett's `0.55/sqrt(n)`).
    /// The second differences are there for a large misfit: a retraction missing its plunger
    /// (a ringing of hundreds of nm at 1.6 kHz, sampled at 1 MHz) keeps a nm in its first
    /// differences, enough to colour them, and a hundredth of that in its second. A white
    /// residual gives about -1/2 and -2/3 (refused); AR(1) 0.9 noise about -0.05 and -0.50
    /// (supported).
    pub fn differences_support(&self, r: &[f64]) -> bool {
        if r.len() < 16 {
            return false;
        }
        let lag1 = |d: &[f64]| -> Option<f64> {
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            let c0: f64 = d.iter().map(|v| (v - mean).powi(2)).sum();
            let c1: f64 = d.windows(2).map(|w| (w[0] - mean) * (w[1] - mean)).sum();
            (c0 > 0.0).then_some(c1 / c0)
        };
        let d1: Vec<f64> = r.windows(2).map(|w| w[1] - w[0]).collect();
        let d2: Vec<f64> = d1.windows(2).map(|w| w[1] - w[0]).collect();
        let (Some(o1), Some(o2)) = (lag1(&d1), lag1(&d2)) else {
            return false;
        };
        let (m1, m2) = self.differences_lag1s();
        let shows = |obs: f64, model: f64, white: f64, se: f64| {
            (obs - white).abs() > 5.0 * se && (obs - model).abs() < (obs - white).abs()
        };
        shows(o1, m1, -0.5, 1.0 / (d1.len() as f64).sqrt())
            && shows(o2, m2, -2.0 / 3.0, 0.55 / (d2.len() as f64).sqrt())
    }

    /// The lag-1 autocorrelation of the first differences of this process, from its
    /// autocovariances (sums over its impulse response, truncated where it has decayed below
    /// 1e-12 of its start).
    pub fn differences_lag1(&self) -> f64 {
        self.differences_lag1s().0
    }

    /// [`ArNoise::differences_lag1`] and the lag-1 autocorrelation of the second differences,
    /// `(-4 g0 + 7 g1 - 4 g2 + g3) / (6 g0 - 8 g1 + 2 g2)` (-2/3 for white noise).
    pub fn differences_lag1s(&self) -> (f64, f64) {
        let a = &self.coefficients;
        let mut h: Vec<f64> = vec![1.0];
        while h.len() < 200_000 {
            let i = h.len();
            let v: f64 = a
                .iter()
                .enumerate()
                .filter(|(k, _)| i > *k)
                .map(|(k, ak)| ak * h[i - k - 1])
                .sum();
            h.push(v);
            if i > a.len() && h[i - a.len().max(1)..].iter().all(|x| x.abs() < 1e-12) {
                break;
            }
        }
        let g = |k: usize| -> f64 { h.iter().zip(&h[k.min(h.len())..]).map(|(x, y)| x * y).sum() };
        let (g0, g1, g2, g3) = (g(0), g(1), g(2), g(3));
        (
            (2.0 * g1 - g0 - g2) / (2.0 * (g0 - g1)),
            (-4.0 * g0 + 7.0 * g1 - 4.0 * g2 + g3) / (6.0 * g0 - 8.0 * g1 + 2.0 * g2),
        )
    }

    /// Whether `other` is the same model within [`SETTLED`]: the same order and every
    /// coefficient within it (an iteration of the noise model with the fit has converged).
    pub fn settled(&self, other: &ArNoise) -> bool {
        self.order() == other.order()
            && self
                .coefficients
                .iter()
                .zip(&other.coefficients)
                .all(|(a, b)| (a - b).abs() <= SETTLED)
    }
}

/// Largest change of any AR coefficient between two iterations of a noise model estimated
/// from a fit's residual that counts as settled: the standard error `sqrt((1 - phi^2) / n)` of
/// an AR(1) coefficient of 0.95 estimated from 1 000 samples.
pub const SETTLED: f64 = 0.01;

/// `r_i <- r_i - sum_k a_k r_{i-k}` in place, from the end (lags before the start omitted).
fn filter(a: &[f64], r: &mut [f64]) {
    for i in (0..r.len()).rev() {
        let mut s = 0.0;
        for (k, ak) in a.iter().enumerate() {
            if i > k {
                s += ak * r[i - k - 1];
            }
        }
        r[i] -= s;
    }
}

/// `v` minus its least-squares line against the sample index.
pub fn detrend(v: &[f64]) -> Vec<f64> {
    let n = v.len() as f64;
    let mi = (n - 1.0) / 2.0;
    let mv = v.iter().sum::<f64>() / n;
    let sxx: f64 = (0..v.len()).map(|i| (i as f64 - mi).powi(2)).sum();
    let sxy: f64 = v
        .iter()
        .enumerate()
        .map(|(i, x)| (i as f64 - mi) * (x - mv))
        .sum();
    let b = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    v.iter()
        .enumerate()
        .map(|(i, x)| x - mv - b * (i as f64 - mi))
        .collect()
}

/// Burg's method: AR coefficients of orders `1..=pmax` and their innovation variances
/// (`out[p] = (a_1..a_p, sigma_p^2)`, `out[0]` the sample variance).
pub fn burg(x: &[f64], pmax: usize) -> Vec<(Vec<f64>, f64)> {
    let n = x.len();
    let mut f: Vec<f64> = x.to_vec();
    let mut b: Vec<f64> = x.to_vec();
    let mut a: Vec<f64> = Vec::new();
    let mut e = x.iter().map(|v| v * v).sum::<f64>() / n.max(1) as f64;
    let mut out = vec![(Vec::new(), e)];
    for m in 0..pmax.min(n.saturating_sub(2)) {
        // reflection coefficient from the forward and backward errors
        let (mut num, mut den) = (0.0, 0.0);
        for i in m + 1..n {
            num += f[i] * b[i - 1];
            den += f[i] * f[i] + b[i - 1] * b[i - 1];
        }
        if den <= 0.0 {
            break;
        }
        let k = 2.0 * num / den;
        // Levinson update of the coefficients
        let prev = a.clone();
        a.push(k);
        for j in 0..m {
            a[j] = prev[j] - k * prev[m - 1 - j];
        }
        for i in (m + 1..n).rev() {
            let fi = f[i];
            f[i] = fi - k * b[i - 1];
            b[i] = b[i - 1] - k * fi;
        }
        e *= 1.0 - k * k;
        out.push((a.clone(), e));
    }
    out
}

/// Ljung-Box p-value of `v`.
pub fn whiteness_p_value(v: &[f64]) -> f64 {
    ljung_box(v).p_value
}

/// BIC margin within which the lowest AR order is preferred (6: "strong" evidence on the
/// Kass-Raftery scale is needed for a higher order).
pub const ORDER_MARGIN: f64 = 6.0;

/// Fewest pre-trigger samples an AR model is estimated from.
pub const MIN_SAMPLES: usize = 32;

/// The noise model of pre-trigger samples `pre`: `None` when there are fewer than
/// [`MIN_SAMPLES`] or they pass the whiteness test at 1 % (white noise), else the AR model of
/// the order BIC selects (`None` too if that order is 0).
pub fn estimate(pre: &[f64]) -> Option<ArNoise> {
    if pre.len() < MIN_SAMPLES {
        return None;
    }
    let x = detrend(pre);
    let p_raw = whiteness_p_value(&x);
    if p_raw >= 0.01 {
        return None;
    }
    fit_order(&x, p_raw)
}

/// The AR model of a series `v` (detrended) of the order BIC selects, without the whiteness
/// gate of [`estimate`]; `None` when the order is 0 or there are too few samples.
pub fn estimate_any(v: &[f64]) -> Option<ArNoise> {
    if v.len() < MIN_SAMPLES {
        return None;
    }
    let x = detrend(v);
    let p_raw = whiteness_p_value(&x);
    fit_order(&x, p_raw)
}

fn fit_order(x: &[f64], p_raw: f64) -> Option<ArNoise> {
    let n = x.len() as f64;
    let pmax = (x.len() / 8).clamp(1, 12);
    let orders = burg(x, pmax);
    let bic: Vec<f64> = orders
        .iter()
        .enumerate()
        .map(|(p, (_, s2))| n * s2.max(1e-300).ln() + p as f64 * n.ln())
        .collect();
    let min = bic.iter().copied().fold(f64::INFINITY, f64::min);
    // the lowest order not strongly worse than the best (BIC within ORDER_MARGIN): a short
    // pre-trigger record lets a higher order win by chance, and an over-fitted filter leaves
    // the rest of the record less white than the true low order does
    let best = bic.iter().position(|b| *b <= min + ORDER_MARGIN)?;
    if best == 0 {
        return None;
    }
    let (coefficients, s2) = orders[best].clone();
    let marginal = (x.iter().map(|v| v * v).sum::<f64>() / (n - 2.0).max(1.0)).sqrt();
    Some(ArNoise {
        coefficients,
        innovation_sigma: s2.sqrt() * (n / (n - 2.0 - best as f64).max(1.0)).sqrt(),
        marginal_sigma: marginal,
        samples: x.len(),
        raw_whiteness_p_value: p_raw,
    })
}

#[cfg(test)]
mod tests {

    fn model1(rho: f64) -> ArNoise {
        ArNoise {
            coefficients: vec![rho],
            innovation_sigma: 1.0,
            marginal_sigma: 1.0 / (1.0 - rho * rho).sqrt(),
            samples: 0,
            raw_whiteness_p_value: 0.0,
        }
    }

    #[test]
    fn differences_tell_the_noise_colour_from_a_smooth_misfit() {
        // the model's own figure: -(1 - rho)/2 for AR(1)
        assert!((model1(0.9).differences_lag1() + 0.05).abs() < 1e-9);
        assert!((model1(0.0).differences_lag1() + 0.5).abs() < 1e-9);
        // the second differences': -2/3 for white noise, about -1/2 for AR(1) near 1
        assert!((model1(0.0).differences_lag1s().1 + 2.0 / 3.0).abs() < 1e-9);
        assert!((model1(0.9).differences_lag1s().1 + 0.502).abs() < 1e-3);
        let n = 1800;
        // a smooth misfit 30 sigma tall over the record
        let misfit: Vec<f64> = (0..n)
            .map(|i| 30.0 * (i as f64 / n as f64 * 3.0).sin())
            .collect();
        let with =
            |noise: &[f64]| -> Vec<f64> { noise.iter().zip(&misfit).map(|(a, b)| a + b).collect() };
        for seed in 0..5 {
            let white = ar1(n, 0.0, 1.0, 100 + seed);
            let coloured = ar1(n, 0.9, 1.0, 200 + seed);
            // the model a residual with a smooth misfit lends: a coefficient near 1
            assert!(!model1(0.99).differences_support(&with(&white)));
            assert!(!model1(0.9).differences_support(&with(&white)));
            assert!(model1(0.9).differences_support(&with(&coloured)));
            assert!(model1(0.9).differences_support(&coloured));
            // a fast misfit 100 sigma tall (a ringing 1/600 of the sampling rate, a
            // retraction's plunger at 1 MHz) colours the first differences, not the second
            let ringing: Vec<f64> = white
                .iter()
                .enumerate()
                .map(|(i, w)| w + 100.0 * (i as f64 * std::f64::consts::TAU / 600.0).sin())
                .collect();
            assert!(!model1(0.9).differences_support(&ringing), "seed {seed}");
        }
    }

    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    fn ar1(n: usize, phi: f64, sd: f64, seed: u64) -> Vec<f64> {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let d = Normal::new(0.0, 1.0).unwrap();
        let e = sd * (1.0 - phi * phi).sqrt();
        let mut x = sd * d.sample(&mut r);
        (0..n)
            .map(|_| {
                x = phi * x + e * d.sample(&mut r);
                x
            })
            .collect()
    }

    /// Burg recovers an AR(1)'s coefficient and innovation sigma (standard error of phi:
    /// sqrt((1 - phi^2) / n) = 0.01 at n = 2000, phi = 0.9).
    #[test]
    fn burg_recovers_an_ar1() {
        let x = ar1(2000, 0.9, 2.0, 3);
        let m = estimate(&x).expect("coloured");
        assert_eq!(m.order(), 1, "{m:?}");
        assert!((m.coefficients[0] - 0.9).abs() < 0.03, "{m:?}");
        let want = 2.0 * (1.0f64 - 0.81).sqrt();
        assert!((m.innovation_sigma / want - 1.0).abs() < 0.05, "{m:?}");
        assert!((m.marginal_sigma / 2.0 - 1.0).abs() < 0.15, "{m:?}");
        // whitening leaves white innovations of the stated sigma
        let mut w = detrend(&x);
        m.whiten(&mut w);
        assert!(whiteness_p_value(&w[1..]) > 0.01);
        let sd = (w.iter().map(|v| v * v).sum::<f64>() / w.len() as f64).sqrt();
        assert!((sd / m.innovation_sigma - 1.0).abs() < 0.05, "{sd}");
    }

    /// White noise is left white (no model), and a short AR(2) record finds order >= 2.
    #[test]
    fn white_noise_has_no_model_and_an_ar2_is_found() {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let d = Normal::new(0.0, 1.0).unwrap();
        let white: Vec<f64> = (0..200).map(|_| d.sample(&mut r)).collect();
        assert!(estimate(&white).is_none());
        // x_i = 1.2 x_{i-1} - 0.5 x_{i-2} + e_i
        let mut x = vec![0.0f64; 2];
        for i in 2..402 {
            let v = 1.2 * x[i - 1] - 0.5 * x[i - 2] + d.sample(&mut r);
            x.push(v);
        }
        let m = estimate(&x[2..]).expect("coloured");
        assert!(m.order() >= 2, "{m:?}");
        assert!((m.coefficients[0] - 1.2).abs() < 0.15 && (m.coefficients[1] + 0.5).abs() < 0.15);
        assert!(estimate(&x[2..20]).is_none(), "too few samples");
    }

    /// 20 quiet samples of AR(1) 0.95 noise are better described by that colour than by white
    /// noise; 20 white samples are not, under the colour a smooth misfit lends a residual
    /// (0.99): the gate that keeps a misfit from being taken for coloured noise.
    #[test]
    fn quiet_samples_tell_coloured_noise_from_a_misfit() {
        let model = |a: f64| ArNoise {
            coefficients: vec![a],
            innovation_sigma: 1.0,
            marginal_sigma: 1.0,
            samples: 1000,
            raw_whiteness_p_value: 0.0,
        };
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let d = Normal::new(0.0, 1.0).unwrap();
        let (mut coloured, mut misfit) = (0, 0);
        for seed in 0..20 {
            let x = ar1(20, 0.95, 1.0, 100 + seed);
            if model(0.95).quiet_lr(&x) > 6.63 {
                coloured += 1;
            }
            let w: Vec<f64> = (0..20).map(|_| d.sample(&mut r)).collect();
            if model(0.99).quiet_lr(&w) > 0.0 {
                misfit += 1;
            }
        }
        assert!(
            coloured >= 16,
            "{coloured} of 20 coloured records recognised"
        );
        assert_eq!(misfit, 0, "white quiet samples taken for coloured");
        assert!(model(0.95).settled(&model(0.955)) && !model(0.95).settled(&model(0.9)));
        assert_eq!(model(0.5).quiet_lr(&[1.0, 2.0]), 0.0, "too few samples");
    }

    #[test]
    fn chi2_survival_matches_known_points() {
        // chi2(20) 99 % point 37.566; chi2(10) 95 % point 18.307
        assert!((chi2_sf(37.566, 20.0) - 0.01).abs() < 1e-3);
        assert!((chi2_sf(18.307, 10.0) - 0.05).abs() < 2e-3);
    }
}
