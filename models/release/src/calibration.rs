//! Calibration of the adhesion distribution against the TMMF campaign statistics (thesis ch. 5,
//! Tab. "Key parameters values for the intermediate TM"), used by the check `FAC-ADH-CAL`.
//!
//! Per contact, the budget draws `(A1, lambda)`. The ground facility measures, per release, the
//! peak pull-off force `F_peak = A1 lambda / e_Euler` and the transferred momentum, which is the
//! adhesion momentum `A1 lambda^2 / v_tip` (tip at about 4 mm/s in the facility: the bond energy
//! released at the tip speed) plus the catapult contribution of the needle preload (2-4 uN s,
//! thesis Tab. "Contribution of the effect of the residual preload").

use crate::budget::AdhesionBudget;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// TMMF intermediate-TM (0.089 kg) campaign statistics (thesis ch. 5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TmmfStatistics {
    /// Mean peak pull-off [mN].
    pub pull_off_mean_mn: f64,
    /// Standard deviation of the peak pull-off [mN].
    pub pull_off_sd_mn: f64,
    /// Largest peak pull-off of the campaign [mN].
    pub pull_off_max_mn: f64,
    /// Mean transferred momentum, catapult included [uN s].
    pub momentum_mean_uns: f64,
    /// Catapult contribution to the momentum, mid-range of 2-4 [uN s].
    pub catapult_uns: f64,
    /// Number of releases of the campaign, from sd / (sd of the mean) = 13 / 2 [-].
    pub releases: usize,
    /// Tip retraction speed of the facility [m/s].
    pub tip_speed_m_s: f64,
}

/// The thesis table.
pub const TMMF_INTERMEDIATE: TmmfStatistics = TmmfStatistics {
    pull_off_mean_mn: 20.0,
    pull_off_sd_mn: 13.0,
    pull_off_max_mn: 48.0,
    momentum_mean_uns: 11.0,
    catapult_uns: 3.0,
    releases: 42,
    tip_speed_m_s: 4e-3,
};

/// The same statistics simulated from an adhesion distribution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SimulatedStatistics {
    /// Draws.
    pub n: usize,
    /// Seed.
    pub seed: u64,
    /// Mean peak pull-off [mN].
    pub pull_off_mean_mn: f64,
    /// Standard deviation of the peak pull-off [mN].
    pub pull_off_sd_mn: f64,
    /// Expected largest pull-off of a campaign of `TMMF_INTERMEDIATE.releases` releases: the
    /// `1 - 1/(releases + 1)` quantile [mN].
    pub pull_off_campaign_max_mn: f64,
    /// Largest possible pull-off within the distribution's bounds [mN].
    pub pull_off_bound_mn: f64,
    /// Mean adhesion momentum at the facility tip speed [uN s].
    pub adhesion_momentum_mean_uns: f64,
    /// Adhesion momentum plus the catapult contribution [uN s] (compare with 11).
    pub momentum_mean_uns: f64,
    /// Relative error of the simulated mean pull-off against 20 mN.
    pub pull_off_mean_rel_error: f64,
}

/// Simulates the TMMF statistics of `adhesion` with `n` draws (ChaCha8, `seed`).
pub fn simulate_tmmf_statistics(
    adhesion: &AdhesionBudget,
    n: usize,
    seed: u64,
) -> SimulatedStatistics {
    let t = TMMF_INTERMEDIATE;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut f = Vec::with_capacity(n);
    let mut p_sum = 0.0;
    for _ in 0..n {
        let a1 = adhesion.A1_n_m.sample(&mut rng);
        let lam = adhesion.lambda_m.sample(&mut rng);
        f.push(a1 * lam / std::f64::consts::E * 1e3);
        p_sum += a1 * lam * lam / t.tip_speed_m_s * 1e6;
    }
    let m = f.iter().sum::<f64>() / n as f64;
    let sd = (f.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n as f64 - 1.0)).sqrt();
    f.sort_by(f64::total_cmp);
    let q = 1.0 - 1.0 / (t.releases as f64 + 1.0);
    let bound = |d: &crate::budget::Dist| match *d {
        crate::budget::Dist::Fixed(v) => v,
        crate::budget::Dist::Uniform { max, .. } => max,
        crate::budget::Dist::Normal { max, .. } => max.unwrap_or(f64::INFINITY),
    };
    let p_mean = p_sum / n as f64;
    SimulatedStatistics {
        n,
        seed,
        pull_off_mean_mn: m,
        pull_off_sd_mn: sd,
        pull_off_campaign_max_mn: crate::stats::quantile_sorted(&f, q),
        pull_off_bound_mn: bound(&adhesion.A1_n_m) * bound(&adhesion.lambda_m)
            / std::f64::consts::E
            * 1e3,
        adhesion_momentum_mean_uns: p_mean,
        momentum_mean_uns: p_mean + t.catapult_uns,
        pull_off_mean_rel_error: (m - t.pull_off_mean_mn) / t.pull_off_mean_mn,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::budget::Budget;

    #[test]
    fn default_budget_reproduces_the_campaign_within_its_uncertainty() {
        let s = simulate_tmmf_statistics(&Budget::default_budget().adhesion, 200_000, 1);
        // mean pull-off 20 +- 2 (sd of the mean) mN
        assert!((s.pull_off_mean_mn - 20.0).abs() < 2.0, "{s:?}");
        // momentum mean 11 +- 1 uN s
        assert!((s.momentum_mean_uns - 11.0).abs() < 1.0, "{s:?}");
        assert!(
            s.pull_off_bound_mn < 48.0,
            "the bounds cap the pull-off at 44 mN: {s:?}"
        );
    }
}
