//! `geodesic fit --posterior` (interface.md: `"posterior": {"PARAM": {"median", "lo68", "hi68",
//! "lo95", "hi95"}}`): the marginal posterior of each free parameter. By default it is sampled
//! (`crate::ensemble`); `--posterior-method laplace` gives the approximation below.
//!
//! **Laplace method, stated**: the Laplace approximation at the best fit, in the coordinate the fit
//! itself works in (the logarithm for the parameters the catalogue fits in log space, the
//! parameter otherwise), with flat priors over the parameter's range (the catalogue's, or
//! `--bound`): a normal of the reported 1-sigma (which already includes the profile-likelihood
//! widening of the fit) truncated to the range, its quantiles mapped back through the monotone
//! coordinate. It is exact for a linear model with Gaussian noise and says nothing about
//! multi-modal posteriors: a fit with a second minimum should be read with its profile. Normal
//! CDF and quantile from `geodesic_util::normal` (fractional error < 1.2e-7).

use serde::{Deserialize, Serialize};

/// The marginal posterior summary of one parameter [SI].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// The 95 % interval reaches within 1 % of the range's width of a bound (the ensemble
    /// sampler's flag; null for the Laplace approximation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prior_limited: Option<bool>,
    /// The marginal has two separated modes (the ensemble sampler's flag; null for the Laplace
    /// approximation, which cannot see one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub multimodal: Option<bool>,
    /// Integrated autocorrelation time of the chain [steps] (the ensemble sampler's; null for
    /// the Laplace approximation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub autocorr_steps: Option<f64>,
    /// The chain's kept steps per walker are at least 50 autocorrelation times (the ensemble
    /// sampler's; null for the Laplace approximation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub converged: Option<bool>,
}

impl From<crate::ensemble::Marginal> for Posterior {
    fn from(m: crate::ensemble::Marginal) -> Self {
        Posterior {
            median: m.median,
            lo68: m.lo68,
            hi68: m.hi68,
            lo95: m.lo95,
            hi95: m.hi95,
            prior_limited: Some(m.prior_limited),
            multimodal: Some(m.multimodal),
            autocorr_steps: Some(m.autocorr_steps),
            converged: Some(m.converged),
        }
    }
}

/// Standard normal CDF.
pub fn phi(z: f64) -> f64 {
    geodesic_util::normal::normal_cdf(z)
}

/// Inverse standard normal CDF.
pub fn phi_inv(p: f64) -> f64 {
    geodesic_util::normal::normal_quantile(p)
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
            prior_limited: None,
            multimodal: None,
            autocorr_steps: None,
            converged: None,
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
        prior_limited: None,
        multimodal: None,
        autocorr_steps: None,
        converged: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
