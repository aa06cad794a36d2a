//! Small statistics helpers: the normal CDF and order statistics.

pub use geodesic_util::normal::{erfc, normal_cdf};

/// Nearest-rank quantile of sorted data: the value at index `ceil(q n) - 1` (one
/// implementation, in `geodesic-util`).
pub use geodesic_util::stats::quantile_sorted;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdf_values() {
        assert!((normal_cdf(0.0) - 0.5).abs() < 1e-7);
        assert!((normal_cdf(1.0) - 0.841_344_746).abs() < 1e-7);
        assert!((normal_cdf(-3.0) - 0.001_349_898).abs() < 1e-8);
    }

    #[test]
    fn nearest_rank() {
        let d: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(quantile_sorted(&d, 0.5), 50.0);
        assert_eq!(quantile_sorted(&d, 0.9973), 100.0);
        assert_eq!(quantile_sorted(&d, 0.99), 99.0);
    }
}

/// Distribution-free 95 % confidence interval of the `q` quantile from sorted data: the order
/// statistics whose ranks bound the true quantile with 97.5 % each (exact binomial ranks,
/// [`geodesic_util::stats`]; Hahn and Meeker, "Statistical Intervals", 1991, section 5.2),
/// NaN on a side the sample cannot bound (no clipping to the sample's extremes: below 1365
/// draws for the 99.73 % point's upper side: 1 - 0.9973^1364 < 0.975). It measures the Monte Carlo's sampling
/// uncertainty only.
pub fn quantile_interval_sorted(sorted: &[f64], q: f64) -> [f64; 2] {
    use geodesic_util::stats::{quantile_lower_rank, quantile_upper_rank};
    let n = sorted.len() as u64;
    let at = |k: Option<u64>| k.map_or(f64::NAN, |k| sorted[(k - 1) as usize]);
    [
        at(quantile_lower_rank(n, q, 0.975)),
        at(quantile_upper_rank(n, q, 0.975)),
    ]
}

/// Probability that the true `q` quantile lies at or below `limit`, given `exceed` of `n` draws
/// above it: the exceedance probability `p = 1 - F(limit)` has the posterior `Beta(exceed + 1,
/// n - exceed + 1)` (uniform prior), close to `Gamma(exceed + 1, n)` for small `p`, so
/// `P(p <= 1 - q) = P(Poisson(n (1 - q)) >= exceed + 1)`. Monte Carlo sampling uncertainty only.
pub fn probability_quantile_below(n: usize, exceed: usize, q: f64) -> f64 {
    let mu = n as f64 * (1.0 - q);
    if mu <= 0.0 {
        return f64::NAN;
    }
    // P(Poisson(mu) <= exceed), summed in log space
    let mut log_term = -mu;
    let mut cdf = log_term.exp();
    for i in 1..=exceed {
        log_term += mu.ln() - (i as f64).ln();
        cdf += log_term.exp();
    }
    (1.0 - cdf).clamp(0.0, 1.0)
}

#[cfg(test)]
mod interval_tests {
    use super::*;

    #[test]
    fn a_sample_too_small_has_no_upper_side() {
        // 1 - 0.9973^1364 = 0.97497 < 0.975 <= 1 - 0.9973^1365
        let small: Vec<f64> = (1..=1364).map(f64::from).collect();
        assert!(quantile_interval_sorted(&small, 0.9973)[1].is_nan());
        let enough: Vec<f64> = (1..=1365).map(f64::from).collect();
        assert_eq!(quantile_interval_sorted(&enough, 0.9973)[1], 1365.0);
    }

    #[test]
    fn quantile_interval_brackets_the_quantile_and_narrows_with_n() {
        let small: Vec<f64> = (1..=2000).map(|i| f64::from(i) / 2.0).collect();
        let big: Vec<f64> = (1..=100_000).map(|i| f64::from(i) / 100.0).collect();
        let a = quantile_interval_sorted(&small, 0.9973);
        let b = quantile_interval_sorted(&big, 0.9973);
        assert!(a[0] <= 997.3 && 997.3 <= a[1], "{a:?}");
        assert!(b[0] <= 997.3 && 997.3 <= b[1], "{b:?}");
        assert!(b[1] - b[0] < a[1] - a[0]);
    }

    #[test]
    fn probability_below_follows_the_poisson_tail() {
        // no exceedance in 1000 draws: 1 - exp(-2.7)
        let p = probability_quantile_below(1000, 0, 0.9973);
        assert!((p - (1.0 - (-2.7f64).exp())).abs() < 1e-12, "{p}");
        // the expected count of exceedances (270 of 1e5) gives about one half
        let p = probability_quantile_below(100_000, 270, 0.9973);
        assert!((p - 0.5).abs() < 0.05, "{p}");
        assert!(probability_quantile_below(100_000, 0, 0.9973) > 1.0 - 1e-12);
    }
}
