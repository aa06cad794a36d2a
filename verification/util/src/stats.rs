//! Exact, distribution-free confidence bounds for the verdicts that rest on sampling: a Monte
//! Carlo quantile (REL-GPRM-VEL: the 99.73 % point of |X'|) and a probability estimated from
//! successes (the fraction of trials that succeed; a coverage).
//!
//! - **Quantile** `xi_p` of a continuous distribution from the sorted sample
//!   `X_(1) <= ... <= X_(n)`: `P(X_(k) >= xi_p) = P(Binomial(n, p) <= k - 1)` whatever the
//!   distribution, so the upper confidence bound at level `c` is `X_(k)` with the smallest rank
//!   `k` for which that binomial probability reaches `c` ([`quantile_upper_rank`]); the lower
//!   bound is `X_(k)` with the largest `k` for which `P(Binomial(n, p) >= k)` reaches `c`
//!   ([`quantile_lower_rank`]). When even the sample maximum is not an upper bound at level
//!   `c` (`1 - p^n < c`), the sample cannot show the quantile: no bound, never a clipped one.
//!   The smallest sample that can is [`min_n`] (`ln(1 - c) / ln p`, 1109 for 99.73 % at 95 %).
//!   Hahn and Meeker, *Statistical Intervals* (1991), sec. 5.2; no normal approximation.
//! - **Probability** from `k` successes in `n` trials: the Clopper-Pearson bounds
//!   ([`clopper_pearson_lower`], [`clopper_pearson_upper`]), the exact binomial inversion
//!   (one-sided at level `c`). With every trial a success the lower bound is `(1 - c)^(1/n)`,
//!   so showing a probability `p` needs the same [`min_n`].
//!
//! The binomial tails are summed exactly from the log-probability of each term (`ln Gamma` by
//! Lanczos' approximation, relative error below 1e-14), outward from the boundary until the
//! terms no longer change the sum. Written by hand: no lean crate offers order-statistic
//! bounds, and `statrs` is not in the tree (its `Beta::inverse_cdf` would give Clopper-Pearson
//! but not the ranks). Reference values: `verification/core/tests/stats_reference.py` (SciPy),
//! checked in `verification/core/tests/stats.rs`.

/// Nearest-rank quantile of sorted data (same unit as the data): the value of rank `ceil(q n)`
/// (1-based, clamped to `1..=n`), the estimate the order-statistic bounds below go with; NaN
/// for no data.
pub fn quantile_sorted(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let n = sorted.len();
    let k = ((q * n as f64).ceil() as usize).clamp(1, n);
    sorted[k - 1]
}

/// The median of `v` (same unit as the data), sorting `v` in place (total order): its middle
/// value, or the mean of its two middle values for an even count; NaN for no data.
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// `ln Gamma(x)` for `x > 0` (Lanczos, g = 7, 9 coefficients; relative error below 1e-14 for
/// the arguments used here, `x >= 1`).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // reflection
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// `ln P(Binomial(n, p) = j)`.
fn ln_pmf(j: u64, n: u64, p: f64) -> f64 {
    if p <= 0.0 {
        return if j == 0 { 0.0 } else { f64::NEG_INFINITY };
    }
    if p >= 1.0 {
        return if j == n { 0.0 } else { f64::NEG_INFINITY };
    }
    let (jf, nf) = (j as f64, n as f64);
    ln_gamma(nf + 1.0) - ln_gamma(jf + 1.0) - ln_gamma(nf - jf + 1.0)
        + jf * p.ln()
        + (nf - jf) * (-p).ln_1p()
}

/// `sum_{j in range} P(Binomial(n, p) = j)`, summed from `start` outward (`step` +1 or -1)
/// while the terms can still change the sum (they fall geometrically away from the mode).
fn tail_from(start: u64, end: u64, n: u64, p: f64, up: bool) -> f64 {
    let mut sum = 0.0;
    let mut j = start;
    loop {
        let t = ln_pmf(j, n, p).exp();
        sum += t;
        // beyond the mode the terms only fall: stop once they are negligible
        let beyond_mode = if up {
            j as f64 >= (n as f64 + 1.0) * p
        } else {
            (j as f64) <= (n as f64 + 1.0) * p - 1.0
        };
        if j == end || (beyond_mode && t <= 1e-17 * sum) || (beyond_mode && sum == 0.0 && t == 0.0)
        {
            break;
        }
        if up {
            j += 1;
        } else {
            j -= 1;
        }
    }
    sum
}

/// `P(Binomial(n, p) <= k)`, exact to about 1e-13 (relative, or absolute near 1).
pub fn binomial_cdf(k: u64, n: u64, p: f64) -> f64 {
    if k >= n {
        return 1.0;
    }
    // sum the smaller side directly: below the mean the lower tail, above it the upper one
    if (k as f64) < n as f64 * p {
        tail_from(k, 0, n, p, false).min(1.0)
    } else {
        (1.0 - tail_from(k + 1, n, n, p, true)).clamp(0.0, 1.0)
    }
}

/// `P(Binomial(n, p) >= k)`.
pub fn binomial_sf(k: u64, n: u64, p: f64) -> f64 {
    if k == 0 {
        return 1.0;
    }
    if k > n {
        return 0.0;
    }
    if (k as f64) > n as f64 * p {
        tail_from(k, n, n, p, true).min(1.0)
    } else {
        (1.0 - tail_from(k - 1, 0, n, p, false)).clamp(0.0, 1.0)
    }
}

/// The smallest sample size that can show a probability `p` (or bound the `p` quantile from
/// above) at confidence `c`: `ceil(ln(1 - c) / ln p)` (every draw a success, or the sample
/// maximum as the bound: `1 - p^n >= c`). 1109 for `p` = 0.9973 and `c` = 0.95.
pub fn min_n(p: f64, c: f64) -> u64 {
    if !(p > 0.0 && p < 1.0 && c > 0.0 && c < 1.0) {
        return 1;
    }
    let mut n = ((1.0 - c).ln() / p.ln()).ceil().max(1.0) as u64;
    // guard the rounding of the logarithms: the defining inequality decides
    while n > 1 && 1.0 - p.powf((n - 1) as f64) >= c {
        n -= 1;
    }
    while 1.0 - p.powf(n as f64) < c {
        n += 1;
    }
    n
}

/// The rank `k` (1-based) of the order statistic that bounds the `p` quantile from above at
/// confidence `c` in a sample of `n`: the smallest `k` with `P(Binomial(n, p) <= k - 1) >= c`;
/// `None` when no order statistic does (`n` below [`min_n`]).
pub fn quantile_upper_rank(n: u64, p: f64, c: f64) -> Option<u64> {
    if n == 0 || !(p > 0.0 && p < 1.0 && c > 0.0 && c < 1.0) {
        return None;
    }
    // P(Bin <= k - 1) rises with k; k = n needs 1 - p^n >= c
    if binomial_cdf(n - 1, n, p) < c {
        return None;
    }
    let (mut lo, mut hi) = (1u64, n); // cdf(hi - 1) >= c
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if binomial_cdf(mid - 1, n, p) >= c {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Some(lo)
}

/// The rank `k` (1-based) of the order statistic that bounds the `p` quantile from below at
/// confidence `c`: the largest `k` with `P(Binomial(n, p) >= k) >= c`; `None` when none does.
pub fn quantile_lower_rank(n: u64, p: f64, c: f64) -> Option<u64> {
    if n == 0 || !(p > 0.0 && p < 1.0 && c > 0.0 && c < 1.0) {
        return None;
    }
    if binomial_sf(1, n, p) < c {
        return None;
    }
    let (mut lo, mut hi) = (1u64, n); // sf(lo) >= c
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        if binomial_sf(mid, n, p) >= c {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    Some(lo)
}

/// Solves `f(x) = target` for `x` in `[lo, hi]` with `f` increasing, by bisection to the
/// resolution of f64.
fn bisect(f: impl Fn(f64) -> f64, target: f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// One-sided Clopper-Pearson lower confidence bound at level `c` of a probability from `k`
/// successes in `n` trials: the `p` with `P(Binomial(n, p) >= k) = 1 - c` (0 for `k = 0`,
/// `(1 - c)^(1/n)` for `k = n`).
pub fn clopper_pearson_lower(k: u64, n: u64, c: f64) -> f64 {
    if n == 0 || k == 0 {
        return 0.0;
    }
    let k = k.min(n);
    if k == n {
        return (1.0 - c).powf(1.0 / n as f64);
    }
    // P(Bin(n, p) >= k) rises with p
    bisect(|p| binomial_sf(k, n, p), 1.0 - c, 0.0, k as f64 / n as f64)
}

/// One-sided Clopper-Pearson upper confidence bound at level `c`: the `p` with
/// `P(Binomial(n, p) <= k) = 1 - c` (1 for `k = n`, `1 - (1 - c)^(1/n)` for `k = 0`).
pub fn clopper_pearson_upper(k: u64, n: u64, c: f64) -> f64 {
    if n == 0 || k >= n {
        return 1.0;
    }
    if k == 0 {
        return 1.0 - (1.0 - c).powf(1.0 / n as f64);
    }
    // P(Bin(n, p) <= k) falls with p: bisect its complement
    bisect(|p| 1.0 - binomial_cdf(k, n, p), c, k as f64 / n as f64, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact_cdf(k: u64, n: u64, p: f64) -> f64 {
        // direct sum with exact binomial coefficients (small n)
        let mut s = 0.0;
        for j in 0..=k {
            let mut c = 1.0f64;
            for i in 0..j {
                c = c * (n - i) as f64 / (i + 1) as f64;
            }
            s += c * p.powi(j as i32) * (1.0 - p).powi((n - j) as i32);
        }
        s
    }

    #[test]
    fn ln_gamma_of_integers_is_ln_factorial() {
        let mut f = 0.0f64;
        for n in 1..=170u32 {
            assert!(
                (ln_gamma(n as f64) - f).abs() <= 1e-12 * f.abs().max(1.0),
                "{n}"
            );
            f += (n as f64).ln();
        }
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-14);
    }

    #[test]
    fn binomial_tails_match_a_direct_sum() {
        for (n, p) in [(10u64, 0.3), (25, 0.9973), (40, 0.5), (60, 0.05)] {
            for k in 0..=n {
                let want = exact_cdf(k, n, p);
                let got = binomial_cdf(k, n, p);
                assert!(
                    (got - want).abs() <= 1e-13,
                    "cdf({k}; {n}, {p}) {got} vs {want}"
                );
                let sf = binomial_sf(k, n, p);
                let want_sf = if k == 0 {
                    1.0
                } else {
                    1.0 - exact_cdf(k - 1, n, p)
                };
                assert!((sf - want_sf).abs() <= 1e-13, "sf({k}; {n}, {p})");
            }
        }
    }

    #[test]
    fn min_n_closed_form() {
        // 1 - 0.9973^1108 = 0.949996 < 0.95 <= 1 - 0.9973^1109
        assert_eq!(min_n(0.9973, 0.95), 1109);
        assert_eq!(min_n(0.5, 0.95), 5);
        assert_eq!(min_n(0.95, 0.95), 59);
        assert_eq!(quantile_upper_rank(1108, 0.9973, 0.95), None);
        assert_eq!(quantile_upper_rank(1109, 0.9973, 0.95), Some(1109));
    }

    #[test]
    fn clopper_pearson_closed_forms() {
        for n in [1u64, 10, 200, 1109, 100_000] {
            let lo = clopper_pearson_lower(n, n, 0.95);
            assert!((lo - 0.05f64.powf(1.0 / n as f64)).abs() < 1e-15);
            let hi = clopper_pearson_upper(0, n, 0.95);
            assert!((hi - (1.0 - 0.05f64.powf(1.0 / n as f64))).abs() < 1e-15);
        }
        // the bound inverts the tail it is defined by
        let lo = clopper_pearson_lower(29, 32, 0.95);
        assert!((binomial_sf(29, 32, lo) - 0.05).abs() < 1e-12, "{lo}");
        let hi = clopper_pearson_upper(29, 32, 0.95);
        assert!((binomial_cdf(29, 32, hi) - 0.05).abs() < 1e-12, "{hi}");
    }
}
