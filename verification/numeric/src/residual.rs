//! Where a model fails: noise estimates, reduced chi-square, a whiteness test of the residual,
//! and the time windows where the residual leaves the noise band.

use serde::{Deserialize, Serialize};

/// Noise estimated from samples that carry no signal change beyond a slow trend: the standard
/// deviation of first differences divided by sqrt(2) (insensitive to offsets and linear drift).
/// Returns `None` with fewer than 5 samples.
pub fn noise_from_differences(v: &[f64]) -> Option<f64> {
    if v.len() < 5 {
        return None;
    }
    let d: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (d.len() - 1) as f64;
    Some((var / 2.0).sqrt())
}

/// Ljung-Box portmanteau test of whiteness on normalised residuals.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Whiteness {
    /// Statistic `Q = N(N+2) sum_k rho_k^2/(N-k)`.
    pub q: f64,
    /// Number of lags.
    pub lags: usize,
    /// 99 % quantile of chi-square with `lags` degrees of freedom (Wilson-Hilferty).
    pub threshold: f64,
    /// `q <= threshold`.
    pub white: bool,
    /// `P(chi2(lags) > q)` (Wilson-Hilferty): the probability of a `q` this large from white
    /// noise.
    #[serde(default)]
    pub p_value: f64,
}

/// Ljung-Box test with `min(20, N/5)` lags at the 1 % level.
pub fn ljung_box(r: &[f64]) -> Whiteness {
    ljung_box_dof(r, 0)
}

/// [`ljung_box`] of the residual of an AR(`p`) model fitted to the same series: the
/// statistic's degrees of freedom are the lags less `p`.
pub fn ljung_box_dof(r: &[f64], p: usize) -> Whiteness {
    let n = r.len();
    let lags = (n / 5).clamp(1, 20);
    let mean = r.iter().sum::<f64>() / n.max(1) as f64;
    let c0: f64 = r.iter().map(|x| (x - mean).powi(2)).sum::<f64>();
    let mut q = 0.0;
    if c0 > 0.0 {
        for k in 1..=lags {
            let ck: f64 = (0..n - k).map(|i| (r[i] - mean) * (r[i + k] - mean)).sum();
            let rho = ck / c0;
            q += rho * rho / (n - k) as f64;
        }
        q *= (n * (n + 2)) as f64;
    }
    let h = (lags.saturating_sub(p)).max(1) as f64;
    let z = 2.326_347_874;
    let threshold = h * (1.0 - 2.0 / (9.0 * h) + z * (2.0 / (9.0 * h)).sqrt()).powi(3);
    Whiteness {
        q,
        lags,
        threshold,
        white: q <= threshold,
        p_value: chi2_sf(q, h),
    }
}

/// Chi-square survival function `P(X > q)` for `dof` degrees of freedom (Wilson-Hilferty).
pub fn chi2_sf(q: f64, dof: f64) -> f64 {
    let h = 2.0 / (9.0 * dof);
    let z = ((q / dof).cbrt() - (1.0 - h)) / h.sqrt();
    1.0 - geodesic_util::normal::normal_cdf(z)
}

/// A time window where the residual leaves the noise band.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Failure {
    /// Channel.
    pub channel: String,
    /// Window start [s].
    pub t_start: f64,
    /// Window end [s].
    pub t_end: f64,
    /// Residual (data - model) of largest magnitude in the window [channel unit, SI].
    pub peak: f64,
    /// `|peak| / sigma`.
    pub peak_sigma: f64,
}

/// Finds the windows where the residual leaves the noise band: a sample beyond 5 sigma, or a
/// running mean over `w = 8` samples beyond `4 sigma/sqrt(w)` (a systematic excursion smaller
/// than the noise). Flagged samples closer than `w` merge into one window.
pub fn failures(channel: &str, t: &[f64], resid: &[f64], sigma: f64) -> Vec<Failure> {
    let n = resid.len();
    let w = 8.min(n.max(1));
    let mut flag = vec![false; n];
    for i in 0..n {
        if resid[i].abs() > 5.0 * sigma {
            flag[i] = true;
        }
    }
    let band = 4.0 * sigma / (w as f64).sqrt();
    let mut sum: f64 = resid[..w].iter().sum();
    for s in 0..=n - w {
        if s > 0 {
            sum += resid[s + w - 1] - resid[s - 1];
        }
        if (sum / w as f64).abs() > band {
            flag[s..s + w].iter_mut().for_each(|f| *f = true);
        }
    }
    let mut out = Vec::new();
    let mut i = 0;
    while i < n {
        if !flag[i] {
            i += 1;
            continue;
        }
        let start = i;
        let mut end = i;
        let mut j = i;
        while j < n && j <= end + w {
            if flag[j] {
                end = j;
            }
            j += 1;
        }
        let (mut pk, mut pv) = (start, 0.0f64);
        for (k, &r) in resid.iter().enumerate().take(end + 1).skip(start) {
            if r.abs() > pv.abs() {
                pk = k;
                pv = r;
            }
        }
        let _ = pk;
        out.push(Failure {
            channel: channel.to_string(),
            t_start: t[start],
            t_end: t[end],
            peak: pv,
            peak_sigma: pv.abs() / sigma,
        });
        i = end + 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let d = Normal::new(0.0, 1.0).unwrap();
        (0..n).map(|_| d.sample(&mut r)).collect()
    }

    #[test]
    fn white_noise_is_white_and_has_no_failures() {
        let r = noise(2000, 1);
        assert!(ljung_box(&r).white);
        let t: Vec<f64> = (0..2000).map(|i| i as f64).collect();
        assert!(failures("x", &t, &r, 1.0).is_empty());
        let s = noise_from_differences(&r).unwrap();
        assert!((s - 1.0).abs() < 0.05, "{s}");
    }

    #[test]
    fn a_bump_is_not_white_and_is_located() {
        let mut r = noise(2000, 2);
        let t: Vec<f64> = (0..2000).map(|i| i as f64).collect();
        for (i, v) in r.iter_mut().enumerate().take(1100).skip(1000) {
            *v += 3.0 * (std::f64::consts::PI * (i - 1000) as f64 / 100.0).sin();
        }
        assert!(!ljung_box(&r).white);
        let f = failures("x", &t, &r, 1.0);
        assert!(!f.is_empty());
        assert!(
            f.iter().all(|w| w.t_start >= 990.0 && w.t_end <= 1110.0),
            "{f:?}"
        );
    }
}
