//! `geodesic fit --posterior` (interface.md: `"posterior": {"PARAM": {"median", "lo68", "hi68",
//! "lo95", "hi95"}}`): the marginal posterior of each free parameter.
//!
//! **Method, stated**: the Laplace approximation at the best fit, in the coordinate the fit
//! itself works in (the logarithm for the parameters the catalogue fits in log space, the
//! parameter otherwise), with flat priors over the parameter's range (the catalogue's, or
//! `--bound`): a normal of the reported 1-sigma (which already includes the profile-likelihood
//! widening of the fit) truncated to the range, its quantiles mapped back through the monotone
//! coordinate. It is exact for a linear model with Gaussian noise and says nothing about
//! multi-modal posteriors: a fit with a second minimum should be read with its profile. Normal
//! CDF from the Numerical Recipes `erfcc` rational approximation (fractional error < 1.2e-7),
//! its inverse by Acklam's algorithm refined by one Newton step; hand-written because these
//! three functions are all the project needs of a statistics crate.

use serde::{Deserialize, Serialize};

/// The marginal posterior summary of one parameter [SI].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Posterior {
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
}

/// Complementary error function (Numerical Recipes `erfcc`, fractional error < 1.2e-7).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87
                                        + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

/// Standard normal CDF.
pub fn phi(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// Inverse standard normal CDF (Acklam, then one Newton step on [`phi`]).
pub fn phi_inv(p: f64) -> f64 {
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let pl = 0.02425;
    let x = if p < pl {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - pl {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        let q = (-2.0 * (1.0 - p).ln()).sqrt();
        -(((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    // one Newton step on phi(x) = p
    let e = phi(x) - p;
    let dens = (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt();
    if dens > 0.0 { x - e / dens } else { x }
}

/// The summary of a normal `N(mu, s)` truncated to `[lo, hi]`, mapped through `back` (a
/// monotone increasing map from the fit coordinate to the parameter).
pub fn truncated_normal(mu: f64, s: f64, lo: f64, hi: f64, back: &dyn Fn(f64) -> f64) -> Posterior {
    if !(s.is_finite() && s > 0.0) {
        let v = back(mu);
        return Posterior {
            median: v,
            lo68: v,
            hi68: v,
            lo95: v,
            hi95: v,
        };
    }
    let (fa, fb) = (phi((lo - mu) / s), phi((hi - mu) / s));
    let q = |p: f64| {
        let u = mu + s * phi_inv(fa + p * (fb - fa));
        back(u.clamp(lo, hi))
    };
    Posterior {
        median: q(0.5),
        lo68: q(0.158_655_253_931_457_05),
        hi68: q(0.841_344_746_068_542_9),
        lo95: q(0.025),
        hi95: q(0.975),
    }
}

/// The posterior summary of every free parameter of a fit outcome, `bounds` the user's
/// `--bound` ranges (the catalogue's range otherwise).
pub fn of_fit(
    o: &crate::fit::FitOutcome,
    bounds: &std::collections::BTreeMap<String, (f64, f64)>,
) -> std::collections::BTreeMap<String, Posterior> {
    let names = o.model.param_names();
    let specs = o.model.specs();
    let mut out = std::collections::BTreeMap::new();
    for (i, n) in names.iter().enumerate() {
        if !o.free[i] {
            continue;
        }
        let s = &specs[i];
        let (lo, hi) = bounds.get(n).copied().unwrap_or((s.lower, s.upper));
        let p = o.p[i];
        let sp = o.sigma_p[i];
        let post = if s.log {
            // u = ln p, sigma_u = sigma_p / p (delta method)
            truncated_normal(
                p.max(1e-300).ln(),
                sp / p.abs().max(1e-300),
                lo.max(1e-300).ln(),
                hi.ln(),
                &f64::exp,
            )
        } else {
            truncated_normal(p, sp, lo, hi, &|u| u)
        };
        out.insert(n.clone(), post);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_cdf_and_its_inverse() {
        // tabulated values
        assert!((phi(1.0) - 0.841_344_746).abs() < 2e-7);
        assert!((phi(-1.959_963_985) - 0.025).abs() < 2e-7);
        for p in [1e-6, 0.01, 0.025, 0.16, 0.5, 0.9, 0.999] {
            assert!((phi(phi_inv(p)) / p - 1.0).abs() < 1e-5, "{p}");
        }
    }

    #[test]
    fn untruncated_is_the_normal_and_truncation_moves_it() {
        let id = |u: f64| u;
        let p = truncated_normal(10.0, 2.0, f64::NEG_INFINITY, f64::INFINITY, &id);
        assert!((p.median - 10.0).abs() < 1e-6);
        assert!((p.hi68 - 12.0).abs() < 1e-4 && (p.lo95 - (10.0 - 3.919_928)).abs() < 1e-3);
        // a bound at the best fit: the median moves inside the range, nothing outside it
        let t = truncated_normal(0.0, 1.0, 0.0, f64::INFINITY, &id);
        assert!(t.lo95 >= 0.0 && (t.median - 0.674_49).abs() < 1e-3);
        // the log coordinate: quantiles map through exp
        let l = truncated_normal(0.0, 0.1, f64::NEG_INFINITY, f64::INFINITY, &f64::exp);
        // the normal CDF is good to 1.2e-7 (erfcc): quantiles to about that times sigma
        assert!((l.median - 1.0).abs() < 1e-6 && (l.hi68 - 0.1f64.exp()).abs() < 1e-4);
    }
}
