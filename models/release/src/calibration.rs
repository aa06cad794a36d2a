//! The TMMF campaign tables of the thesis (ch. 5) as data, and the comparison of the release
//! Monte Carlo's adhesion distribution with them, used by the check `FAC-ADH-CAL`.
//!
//! Per contact, the budget draws `(A1, lambda)`. The ground facility measures, per release, the
//! peak pull-off force `F_peak = A1 lambda / e_Euler` and the transferred momentum, which is the
//! adhesion momentum `A1 lambda^2 / v_tip` (tip at about 4 mm/s in the facility: the bond energy
//! released at the tip speed) plus the catapult contribution of the needle preload (thesis Tab.
//! "Contribution of the effect of the residual preload", `tab:catapult`).
//!
//! The budget was calibrated on the intermediate-TM campaign (`tab:0.1kg`). It is judged against
//! the heavy-TM campaign (`tab:1kg`, [`HOLD_OUT`]): same facility set-up (stiff blades, DOSS,
//! low residual load, the same `F_peak` definition), and the peak pull-off of the exponential
//! law does not depend on the TM mass (thesis: "Both the momentum and the peak force are
//! expected to be independent of the mass"). The light-TM campaigns are not used: the thesis
//! attributes their much lower pull-off to spurious dynamic effects of the light TM (rotations
//! breaking the bond). The high-residual-load campaign (`tab:res01kghl`) is not used: a different
//! procedure (300 mN left at retraction) and a pull-off obtained by subtracting a needle model
//! from the acceleration; it prints neither the sd of the mean nor the maximum.
//!
//! Figures of merit, each with the campaign's own sampling uncertainty (see [`compare`]):
//! `z_mean = (simulated mean - campaign mean) / campaign sd of the mean` (as printed),
//! `z_sd = (simulated sd - campaign sd) / (campaign sd / sqrt(2 (n - 1)))` (the standard error of
//! a sample sd of `n` normal draws), and `z_max = (campaign max - E[max of n draws]) / sd[max of
//! n draws]`, with the distribution of the maximum of `n` draws computed exactly from the
//! empirical distribution of the simulated pull-offs (`P(max <= f_(k)) = (k/N)^n`); the exact
//! probability `P(max of n draws >= campaign max)` is given beside it.

use crate::budget::{AdhesionBudget, Dist};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// One row of a TMMF table, each figure as printed in the thesis (the text keeps the printed
/// precision, from which the number of releases is bounded: see [`TmmfCampaign::releases`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Row {
    /// Mean.
    pub mean: &'static str,
    /// Standard deviation.
    pub sd: &'static str,
    /// Standard deviation of the mean, if printed.
    pub sd_mean: Option<&'static str>,
    /// Minimum, if printed.
    pub min: Option<&'static str>,
    /// Maximum, if printed.
    pub max: Option<&'static str>,
}

/// A printed figure's value and half a unit of its last printed digit.
pub fn printed(s: &str) -> (f64, f64) {
    let v: f64 = s.parse().unwrap_or(f64::NAN);
    let decimals = s.split_once('.').map_or(0, |(_, d)| d.len());
    (v, 0.5 * 10f64.powi(-(decimals as i32)))
}

fn val(s: &str) -> f64 {
    printed(s).0
}

/// One TMMF campaign table of the thesis, ch. 5.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TmmfCampaign {
    /// LaTeX label of the table.
    pub label: &'static str,
    /// The table's caption.
    pub caption: &'static str,
    /// TM mock-up mass [kg].
    pub tm_mass_kg: f64,
    /// Transferred momentum `P_x` [uN s].
    pub momentum_uns: Row,
    /// Peak (apparent) pull-off force `F_peak` [mN].
    pub pull_off_mn: Row,
    /// Event duration `Delta t` [ms], if printed.
    pub duration_ms: Option<Row>,
    /// Number of releases, if the thesis prints it.
    pub releases_printed: Option<usize>,
    /// Catapult momentum range of the set-up [uN s] (`tab:catapult`).
    pub catapult_uns: (f64, f64),
}

const fn row(
    mean: &'static str,
    sd: &'static str,
    sd_mean: &'static str,
    min: &'static str,
    max: &'static str,
) -> Row {
    Row {
        mean,
        sd,
        sd_mean: Some(sd_mean),
        min: Some(min),
        max: Some(max),
    }
}

/// Light TM, old campaign (soft blades), thesis Tab. `tab:0.01kg`.
pub const TMMF_LIGHT_OLD: TmmfCampaign = TmmfCampaign {
    label: "tab:0.01kg",
    caption: "Key parameters values for the light TM (old campaign)",
    tm_mass_kg: 0.0096,
    momentum_uns: row("2.4", "1.1", "0.06", "0.34", "8"),
    pull_off_mn: row("4.9", "2", "0.1", "0.37", "17"),
    duration_ms: Some(row("1.2", "0.2", "0.01", "0.38", "1.9")),
    releases_printed: None,
    catapult_uns: (0.1, 0.4),
};

/// Light TM, 2014 campaign (single stiff blade), thesis Tab. `tab:0.01kgb`.
pub const TMMF_LIGHT_2014: TmmfCampaign = TmmfCampaign {
    label: "tab:0.01kgb",
    caption: "Key parameters values for the light TM (2014)",
    tm_mass_kg: 0.0096,
    momentum_uns: row("1.38", "0.58", "0.09", "0.22", "2.54"),
    pull_off_mn: row("3.1", "1.13", "0.18", "0.72", "5.38"),
    duration_ms: Some(row("0.9", "0.18", "0.03", "0.48", "1.52")),
    releases_printed: None,
    catapult_uns: (0.4, 1.3),
};

/// Intermediate TM (0.089 kg, stiff blades, DOSS), thesis Tab. `tab:0.1kg`: the calibration
/// campaign of the budget.
pub const TMMF_INTERMEDIATE: TmmfCampaign = TmmfCampaign {
    label: "tab:0.1kg",
    caption: "Key parameters values for the intermediate TM",
    tm_mass_kg: 0.089,
    momentum_uns: row("11", "8", "1", "1.9", "27"),
    pull_off_mn: row("20", "13", "2", "3.4", "48"),
    duration_ms: Some(row("1.45", "0.4", "0.06", "1.0", "2.6")),
    releases_printed: None,
    catapult_uns: (2.0, 4.0),
};

/// Heavy TM (0.844 kg, same set-up as the intermediate TM), thesis Tab. `tab:1kg`: the hold-out
/// campaign of FAC-ADH-CAL.
pub const TMMF_HEAVY: TmmfCampaign = TmmfCampaign {
    label: "tab:1kg",
    caption: "Key parameters values for the heavy TM",
    tm_mass_kg: 0.844,
    momentum_uns: row("17.5", "5", "0.9", "8", "27"),
    pull_off_mn: row("12", "9", "2", "5", "54"),
    duration_ms: Some(row("3.1", "1.2", "0.2", "0.8", "5.6")),
    releases_printed: None,
    catapult_uns: (5.0, 13.0),
};

/// Intermediate TM with a high (300 mN) residual load, thesis Tab. `tab:res01kghl` (adhesion
/// part after subtracting the needle model; momentum printed in N s, here uN s; 107
/// force-to-elongation functions "available", Fig. `fig:ftoelhl`).
pub const TMMF_HIGH_LOAD: TmmfCampaign = TmmfCampaign {
    label: "tab:res01kghl",
    caption: "Results of the test campaign with high residual preload",
    tm_mass_kg: 0.089,
    momentum_uns: Row {
        mean: "4.68",
        sd: "1.32",
        sd_mean: None,
        min: None,
        max: None,
    },
    pull_off_mn: Row {
        mean: "9.5",
        sd: "2.5",
        sd_mean: None,
        min: None,
        max: None,
    },
    duration_ms: None,
    releases_printed: Some(107),
    catapult_uns: (0.0, 0.0),
};

/// Every campaign table of thesis ch. 5, in the thesis's order.
pub const TMMF_CAMPAIGNS: [TmmfCampaign; 5] = [
    TMMF_LIGHT_OLD,
    TMMF_LIGHT_2014,
    TMMF_INTERMEDIATE,
    TMMF_HEAVY,
    TMMF_HIGH_LOAD,
];

/// The campaign the budget was calibrated on.
pub const CALIBRATION: TmmfCampaign = TMMF_INTERMEDIATE;
/// The campaign the budget is judged against (not used for the calibration).
pub const HOLD_OUT: TmmfCampaign = TMMF_HEAVY;

/// Tip retraction speed of the facility [m/s] (thesis: about 4 mm/s in the first 10 um).
pub const TIP_SPEED_M_S: f64 = 4e-3;

impl TmmfCampaign {
    /// The range of release counts `n` consistent with every printed `sd / sd of the mean` of
    /// the table, each figure anywhere within its printed rounding (`None` without an sd of the
    /// mean).
    pub fn releases_range(&self) -> Option<(usize, usize)> {
        let mut lo = 1.0_f64;
        let mut hi = f64::INFINITY;
        let rows = [
            Some(self.momentum_uns),
            Some(self.pull_off_mn),
            self.duration_ms,
        ];
        let mut any = false;
        for r in rows.into_iter().flatten() {
            let Some(sm) = r.sd_mean else { continue };
            let ((sd, dsd), (m, dm)) = (printed(r.sd), printed(sm));
            lo = lo.max(((sd - dsd) / (m + dm)).powi(2));
            hi = hi.min(((sd + dsd) / (m - dm)).powi(2));
            any = true;
        }
        // 1e-9 guards exact squares against rounding of the division
        (any && lo.ceil() <= hi.floor())
            .then(|| ((lo - 1e-9).ceil() as usize, (hi + 1e-9).floor() as usize))
    }

    /// Releases used for the campaign's sampling uncertainty: the printed count, else the
    /// smallest count consistent with the table (the largest standard errors, the most lenient
    /// to the model).
    pub fn releases(&self) -> Option<usize> {
        self.releases_printed
            .or_else(|| self.releases_range().map(|r| r.0))
    }
}

/// Peak pull-offs `A1 lambda / e` [mN] and adhesion momenta `A1 lambda^2 / v_tip` [uN s] of `n`
/// draws of `adhesion` (ChaCha8, `seed`), the pull-offs sorted.
pub fn draw_pull_offs(adhesion: &AdhesionBudget, n: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut f = Vec::with_capacity(n);
    let mut p = Vec::with_capacity(n);
    for _ in 0..n {
        let (a1, lam) = adhesion.sample(&mut rng);
        f.push(a1 * lam / std::f64::consts::E * 1e3);
        p.push(a1 * lam * lam / TIP_SPEED_M_S * 1e6);
    }
    f.sort_by(f64::total_cmp);
    (f, p)
}

/// The largest pull-off the distribution's bounds allow [mN].
pub fn pull_off_bound_mn(adhesion: &AdhesionBudget) -> f64 {
    let bound = |d: &Dist| match *d {
        Dist::Fixed(v) => v,
        Dist::Uniform { max, .. } => max,
        Dist::Normal { max, .. } => max.unwrap_or(f64::INFINITY),
    };
    bound(&adhesion.A1_n_m) * bound(&adhesion.lambda_m) / std::f64::consts::E * 1e3
}

/// Mean and sd (`n - 1`) of `v`.
pub fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, var.sqrt())
}

/// Distribution of the maximum of `n` independent draws from the empirical distribution of
/// `sorted` (ascending): `P(max <= sorted[k-1]) = (k/N)^n`. Returns its mean, its sd and
/// `P(max >= x)`.
pub fn max_of_n(sorted: &[f64], n: usize, x: f64) -> (f64, f64, f64) {
    let big = sorted.len() as f64;
    let cdf = |k: usize| (k as f64 / big).powi(n as i32);
    let (mut m1, mut m2) = (0.0, 0.0);
    for (k, v) in sorted.iter().enumerate() {
        let w = cdf(k + 1) - cdf(k);
        m1 += w * v;
        m2 += w * v * v;
    }
    // draws strictly below x
    let below = sorted.partition_point(|v| *v < x);
    let p_ge = 1.0 - cdf(below);
    (m1, (m2 - m1 * m1).max(0.0).sqrt(), p_ge)
}

/// One statistic, simulated against a campaign.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Statistic {
    /// Simulated value [mN] (for the maximum: the mean of the maximum of `n` draws).
    pub simulated: f64,
    /// The campaign's value [mN].
    pub campaign: f64,
    /// The campaign's standard error of it [mN] (for the maximum: the sd of the simulated
    /// maximum of `n` draws).
    pub standard_error: f64,
    /// Discrepancy in standard errors (for the maximum: campaign minus simulated, so that a
    /// campaign maximum the model cannot reach is positive).
    pub z: f64,
}

/// The peak pull-off distribution of an adhesion budget against one campaign.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Comparison {
    /// The campaign's table label.
    pub campaign: &'static str,
    /// Releases of the campaign used for the standard errors.
    pub releases: usize,
    /// The releases consistent with the table's rounding (`None` if the count is printed).
    pub releases_range: Option<(usize, usize)>,
    /// Simulated draws.
    pub draws: usize,
    /// Seed.
    pub seed: u64,
    /// Mean peak pull-off.
    pub mean: Statistic,
    /// Standard deviation of the peak pull-off.
    pub sd: Statistic,
    /// Maximum peak pull-off of a campaign of `releases` releases.
    pub max: Statistic,
    /// `P(max of releases draws >= campaign max)`.
    pub p_max_at_least: f64,
    /// Largest pull-off within the budget's bounds [mN].
    pub bound_mn: f64,
    /// Simulated mean momentum, adhesion + the campaign's mid-range catapult [uN s].
    pub momentum_mean_uns: f64,
    /// The campaign's mean momentum [uN s].
    pub campaign_momentum_mean_uns: f64,
    /// Figure of merit: the largest `|z|` of mean, sd and max.
    pub worst_z: f64,
}

/// Compares the peak pull-off distribution of `adhesion` (`draws` draws, `seed`) with
/// `campaign` (which must print a mean, an sd, an sd of the mean and a maximum pull-off, and give
/// a release count).
pub fn compare(
    adhesion: &AdhesionBudget,
    campaign: &TmmfCampaign,
    draws: usize,
    seed: u64,
) -> Result<Comparison, String> {
    let row = campaign.pull_off_mn;
    let missing = |w: &str| format!("{}: no printed {w} of the pull-off", campaign.label);
    let n = campaign
        .releases()
        .ok_or_else(|| missing("release count"))?;
    let sem = val(row.sd_mean.ok_or_else(|| missing("sd of the mean"))?);
    let obs_max = val(row.max.ok_or_else(|| missing("maximum"))?);
    let (obs_mean, obs_sd) = (val(row.mean), val(row.sd));
    let (f, p) = draw_pull_offs(adhesion, draws, seed);
    let (m, sd) = mean_sd(&f);
    let se_sd = obs_sd / (2.0 * (n as f64 - 1.0)).sqrt();
    let (max_mean, max_sd, p_ge) = max_of_n(&f, n, obs_max);
    let stat = |simulated: f64, campaign: f64, se: f64, z: f64| Statistic {
        simulated,
        campaign,
        standard_error: se,
        z,
    };
    let mean = stat(m, obs_mean, sem, (m - obs_mean) / sem);
    let sdv = stat(sd, obs_sd, se_sd, (sd - obs_sd) / se_sd);
    let max = stat(max_mean, obs_max, max_sd, (obs_max - max_mean) / max_sd);
    let p_mean = p.iter().sum::<f64>() / p.len() as f64;
    Ok(Comparison {
        campaign: campaign.label,
        releases: n,
        releases_range: campaign
            .releases_printed
            .is_none()
            .then(|| campaign.releases_range())
            .flatten(),
        draws,
        seed,
        worst_z: mean.z.abs().max(sdv.z.abs()).max(max.z.abs()),
        mean,
        sd: sdv,
        max,
        p_max_at_least: p_ge,
        bound_mn: pull_off_bound_mn(adhesion),
        momentum_mean_uns: p_mean + 0.5 * (campaign.catapult_uns.0 + campaign.catapult_uns.1),
        campaign_momentum_mean_uns: val(campaign.momentum_uns.mean),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::budget::Budget;

    #[test]
    fn printed_figures_keep_their_precision() {
        for (s, v, h) in [("0.9", 0.9, 0.05), ("54", 54.0, 0.5), ("1.13", 1.13, 0.005)] {
            let (pv, ph) = printed(s);
            assert!((pv - v).abs() < 1e-12 && (ph - h).abs() < 1e-12, "{s}");
        }
    }

    #[test]
    fn release_counts_follow_from_the_printed_rounding() {
        // heavy TM: F 9/2 -> [11.6, 40.1], P 5/0.9 -> [22.4, 41.9], dt 1.2/0.2 -> [21.2, 69.4]
        assert_eq!(TMMF_HEAVY.releases_range(), Some((23, 40)));
        assert_eq!(TMMF_HEAVY.releases(), Some(23));
        // intermediate TM: dt 0.4/0.06 -> [29.0, 66.9] is the tightest
        assert_eq!(TMMF_INTERMEDIATE.releases_range(), Some((29, 66)));
        assert_eq!(TMMF_LIGHT_2014.releases_range(), Some((37, 42)));
        assert_eq!(TMMF_HIGH_LOAD.releases(), Some(107));
    }

    #[test]
    fn maximum_of_n_draws_matches_a_hand_computation() {
        // four equally likely values, n = 2: P(max = v_k) = (k^2 - (k-1)^2) / 16
        let s = [1.0, 2.0, 3.0, 4.0];
        let (m, sd, p) = max_of_n(&s, 2, 3.0);
        let mean = (1.0 + 2.0 * 3.0 + 3.0 * 5.0 + 4.0 * 7.0) / 16.0;
        let m2 = (1.0 + 4.0 * 3.0 + 9.0 * 5.0 + 16.0 * 7.0) / 16.0;
        assert!((m - mean).abs() < 1e-12);
        assert!((sd - (m2 - mean * mean).sqrt()).abs() < 1e-12);
        assert!((p - (1.0 - 4.0 / 16.0)).abs() < 1e-12);
        assert_eq!(max_of_n(&s, 2, 4.5).2, 0.0);
    }

    #[test]
    fn default_budget_against_the_calibration_campaign() {
        let b = Budget::default_budget().adhesion;
        let c = compare(&b, &TMMF_INTERMEDIATE, 200_000, 1).unwrap();
        // in-sample: mean within one standard error, momentum 11 +- 1 uN s
        assert!(c.mean.z.abs() < 1.0, "{c:?}");
        assert!((c.momentum_mean_uns - 11.0).abs() < 1.0, "{c:?}");
        // the bounds cap the pull-off at 44 mN, below the campaign's 48 mN
        assert!(c.bound_mn < 48.0 && c.p_max_at_least == 0.0, "{c:?}");
    }
}
