//! Statistics of a capture probability (requirement CAP-RELEASE-PROB): the fraction of draws
//! captured, its one-sided 95 % Wilson lower bound and the quantiles of the quartic sums. The
//! draws themselves come from [`crate::inputs::StateModel::capture_probability`].

/// Capture probability of a set of release draws.
#[derive(Clone, Debug, PartialEq)]
pub struct CaptureProbability {
    /// Number of draws.
    pub n: usize,
    /// Draws with quartic sum < 1.
    pub captured: usize,
    /// `captured / n` [-].
    pub probability: f64,
    /// One-sided 95 % lower confidence bound on the probability (Wilson score) [-].
    pub lower_95: f64,
    /// 99.73 % quantile of the quartic sum over the draws [-].
    pub sum_p9973: f64,
    /// Largest quartic sum [-].
    pub sum_max: f64,
    /// Seed of the 11 other states.
    pub seed: u64,
}

impl CaptureProbability {
    /// The statistics of a set of quartic sums (one per draw); NaN sums count as not captured.
    pub fn from_sums(mut sums: Vec<f64>, seed: u64) -> CaptureProbability {
        let n = sums.len();
        let captured = sums.iter().filter(|&&s| s < 1.0).count();
        sums.sort_by(f64::total_cmp);
        let quantile = |p: f64| -> f64 {
            if n == 0 {
                f64::NAN
            } else {
                let idx = ((p * n as f64).ceil() as usize).clamp(1, n) - 1;
                sums[idx]
            }
        };
        CaptureProbability {
            n,
            captured,
            probability: captured as f64 / n as f64,
            lower_95: wilson_lower(captured, n, 1.644_853_626_951_472_2),
            sum_p9973: quantile(0.9973),
            sum_max: sums.last().copied().unwrap_or(f64::NAN),
            seed,
        }
    }
}

/// Lower Wilson score bound of a binomial proportion at `z` standard deviations [-].
fn wilson_lower(k: usize, n: usize, z: f64) -> f64 {
    if n == 0 {
        return f64::NAN;
    }
    let n = n as f64;
    let p = k as f64 / n;
    let z2 = z * z;
    let centre = p + z2 / (2.0 * n);
    let half = z * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((centre - half) / (1.0 + z2 / n)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_of_sums() {
        let p = CaptureProbability::from_sums(vec![0.1, 0.5, 2.0, f64::NAN], 3);
        assert_eq!((p.n, p.captured, p.seed), (4, 2, 3));
        assert_eq!(p.probability, 0.5);
        assert!(p.sum_max.is_nan() || p.sum_max >= 2.0);
    }

    #[test]
    fn wilson_bound_is_below_the_estimate() {
        for (k, n) in [(0, 10), (5, 10), (10, 10), (9973, 10_000)] {
            let lo = wilson_lower(k, n, 1.644_853_626_951_472_2);
            assert!(lo <= k as f64 / n as f64 + 1e-15, "{k}/{n}: {lo}");
            assert!(lo >= 0.0);
        }
    }
}
