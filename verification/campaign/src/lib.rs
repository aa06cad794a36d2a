//! A campaign of measured releases (thesis ch. 5: many TMMF releases per campaign, summarised in
//! tables of transferred momentum `P_x`, peak pull-off force `F_peak` and pull duration `dt`):
//! fit every release, tabulate, and estimate the adhesion population.
//!
//! * Per release, from the fitted model: `P_x = m v_end` (the model's velocity over the last
//!   fifth of the record, in free flight), `F_peak = m max(a)` (the largest acceleration along
//!   the retraction, the adhesion pulling the TM after the tip) and `dt` (how long the
//!   acceleration exceeds 5 % of that peak), `a` from second differences of the model
//!   prediction. From the data directly: `P_x` from a straight-line fit to the last fifth of `x`;
//!   `F_peak` and `dt` need a second derivative of the measured position, which the noise
//!   swamps at these rates, so they are given from the model only (`null` for the data).
//! * The table per quantity: mean, standard deviation, standard deviation of the mean, min, max.
//! * The population of `(A1, lambda)` across releases with the measurement errors deconvolved:
//!   per parameter the plain moments (`mean`; the spread `sd` = `sqrt(var - mean(s^2))`, the
//!   estimates' variance less the mean measurement variance: no inverse-variance weights, since
//!   a fit's sigma depends on the value it estimates; see [`population_param`]), the mean's
//!   95 % Student-t interval (`mean_ci95`; `mean_sigma` its half-width over 1.96), the
//!   spread's 95 % chi-square interval (`sd_ci95`; `sd_sigma` its width over 2 x 1.96; both
//!   cover the truth about 95 % of the time for 5 to 100 releases, tests below), and the
//!   correlation of A1 and lambda across the
//!   population: the covariance of the estimates minus the mean within-release covariance
//!   (from each fit's correlation matrix), over `sd_A1 sd_lambda`, clipped to [-1, 1], with a
//!   95 % percentile interval from a bootstrap over releases (`correlation_ci95`). On
//!   campaigns of 30 releases whose measurement errors are half the population spread and
//!   correlated -0.95 within a release, the estimate's bias is +0.01 to +0.04 (the naive
//!   correlation of the estimates is off by up to -0.3) and the interval covers 87-94 % of the
//!   time (tests below).

//!
//! LISA Pathfinder's (the adhesion population of a release campaign, which its release budget
//! takes through `adhesion_from`): the `campaign` command is a command of that mission
//! (`geodesic_missions::cmd::campaign`); [`page`] writes the campaign's page.

pub mod page;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use geodesic_fit::FitError;
use geodesic_fit::estimate::{FitOptions, FitOutcome};
use geodesic_fit::prepare::Prepared;
use geodesic_fit::report::FitReport;

/// One fitted release.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Release {
    /// Dataset YAML.
    pub file: String,
    /// Reduced chi-square.
    pub chi2_red: f64,
    /// Parameters with 1-sigma.
    pub params: BTreeMap<String, geodesic_fit::report::ParamOut>,
    /// Transferred momentum from the model [kg m/s].
    pub p_x_model: f64,
    /// Transferred momentum from the data (line fit to the free flight) [kg m/s].
    pub p_x_data: f64,
    /// Peak pull force from the model [N].
    pub f_peak_model: f64,
    /// Pull duration from the model [s].
    pub dt_model: f64,
    /// Correlation of A1 and lambda in this fit (when both are free).
    pub corr_a1_lambda: Option<f64>,
}

/// A failed release.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Failed {
    /// Dataset YAML.
    pub file: String,
    /// Why.
    pub cause: String,
}

/// Statistics of a quantity over the releases.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Stats {
    /// Mean.
    pub mean: f64,
    /// Standard deviation (n - 1).
    pub sd: f64,
    /// Standard deviation of the mean.
    pub sd_mean: f64,
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
}

/// Stats of `v` (`None` when empty).
pub fn stats(v: &[f64]) -> Option<Stats> {
    if v.is_empty() {
        return None;
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let sd = if v.len() > 1 {
        (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    Some(Stats {
        mean,
        sd,
        sd_mean: sd / n.sqrt(),
        min: v.iter().copied().fold(f64::INFINITY, f64::min),
        max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    })
}

/// A population parameter (interface.md `population.PARAM`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct PopParam {
    /// Population mean [SI].
    pub mean: f64,
    /// Its 1-sigma: the half-width of `mean_ci95` over 1.96.
    pub mean_sigma: f64,
    /// Population spread (1-sigma, measurement errors removed).
    pub sd: f64,
    /// Its 1-sigma: the width of `sd_ci95` over 2 x 1.96.
    pub sd_sigma: f64,
    /// Releases used.
    pub n: usize,
    /// The mean's 95 % interval (Student-t with `n - 1` degrees of freedom) [SI].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_ci95: Option<[f64; 2]>,
    /// The spread's 95 % interval (chi-square with `n - 1` degrees of freedom) [SI].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sd_ci95: Option<[f64; 2]>,
}

/// `P(|T| < t)` for Student's t with `nu` (integer) degrees of freedom, from the finite series
/// in `theta = atan(t / sqrt(nu))` (Abramowitz & Stegun 26.7.3-4): exact to rounding.
fn t_two_sided(t: f64, nu: usize) -> f64 {
    let th = (t / (nu as f64).sqrt()).atan();
    let (s, c2) = (th.sin(), th.cos().powi(2));
    if !nu.is_multiple_of(2) {
        let mut sum = 0.0;
        if nu > 1 {
            let (mut term, mut acc) = (1.0, 1.0);
            for j in (2..nu - 1).step_by(2) {
                term *= j as f64 / (j + 1) as f64 * c2;
                acc += term;
            }
            sum = s * th.cos() * acc;
        }
        2.0 / std::f64::consts::PI * (th + sum)
    } else {
        let (mut term, mut acc) = (1.0, 1.0);
        for j in (1..nu - 1).step_by(2) {
            term *= j as f64 / (j + 1) as f64 * c2;
            acc += term;
        }
        s * acc
    }
}

/// The `x >= 0` where the increasing `g` reaches `target`: doubling from `x0` to bracket it,
/// then bisection to a relative 1e-14.
fn invert_increasing(g: impl Fn(f64) -> f64, target: f64, x0: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, x0);
    while g(hi) < target && hi < 1e12 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-14 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// Student-t quantile `t_{nu}(p)` for `p` > 0.5 and integer `nu` >= 1: the exact distribution
/// function [`t_two_sided`] inverted (checked against tabulated values in the tests).
pub fn t_quantile(nu: usize, p: f64) -> f64 {
    invert_increasing(|t| t_two_sided(t, nu.max(1)), 2.0 * p - 1.0, 1.0)
}

/// Chi-square survival function `P(X > x)` for `nu` (integer) degrees of freedom: the finite
/// Poisson and normal series (Abramowitz & Stegun 26.4.4-5), exact to rounding; Wilson-Hilferty
/// above 200 degrees of freedom (relative error of the quantiles below 1e-4 there).
fn chi2_sf(x: f64, nu: usize) -> f64 {
    use geodesic_util::normal::normal_cdf;
    if x <= 0.0 {
        return 1.0;
    }
    if nu > 200 {
        let n = nu as f64;
        let a = 2.0 / (9.0 * n);
        return 1.0 - normal_cdf(((x / n).cbrt() - 1.0 + a) / a.sqrt());
    }
    let h = 0.5 * x;
    if nu.is_multiple_of(2) {
        let (mut term, mut acc) = ((-h).exp(), 0.0);
        for j in 0..nu / 2 {
            if j > 0 {
                term *= h / j as f64;
            }
            acc += term;
        }
        acc
    } else {
        let r = x.sqrt();
        let mut acc = 2.0 * (1.0 - normal_cdf(r));
        let mut term = (2.0 * x / std::f64::consts::PI).sqrt() * (-h).exp();
        for j in 1..=(nu - 1) / 2 {
            if j > 1 {
                term *= x / (2 * j - 1) as f64;
            }
            acc += term;
        }
        acc
    }
}

/// Chi-square quantile: the `x` with `P(X > x) = q`, [`chi2_sf`] inverted.
pub fn chi2_isf(q: f64, nu: usize) -> f64 {
    invert_increasing(|x| -chi2_sf(x, nu), -q, nu.max(1) as f64)
}

/// The population of one parameter over the releases that have it, by the method of moments
/// without weights: `mean` the plain mean of the estimates, `sd` = `sqrt(var - mean(s^2))`
/// (the spread of the estimates less the mean measurement variance, clipped at 0).
///
/// Why no weights: a fit's 1-sigma depends on the value it estimates (a weak adhesion is
/// poorly determined: across synthetic campaigns the correlation of lambda's estimate with its
/// sigma is -0.4 to -0.6), so inverse-variance weights favour the strong releases. The
/// DerSimonian-Laird estimate used before, whose between-release variance rests on those
/// weights, put the lambda spread of a 50-release campaign at 3.84e-8 m against 5.25e-8 m for
/// the drawn releases (the plain moments: 4.82e-8); the plain moments
/// do not depend on that correlation. The cost, a wider interval when the sigmas differ much,
/// is small here: the measurement errors are a fraction of the spread.
///
/// Intervals (95 %): the mean's `mean +- t_{n-1}(0.975) sd(x) / sqrt(n)` (`mean_ci95`;
/// `mean_sigma` its half-width over 1.96); the spread's from `(n - 1) var / (tau^2 + mean(s^2))`
/// ~ chi-square with `n - 1` degrees of freedom (exact when the errors are equal; `sd_ci95`;
/// `sd_sigma` its width over 2 x 1.96). Coverage measured in the tests below over simulated
/// campaigns of 5 to 100 releases, sigmas equal or tied to the value.
pub fn population_param(x: &[f64], s: &[f64]) -> PopParam {
    let n = x.len();
    let k = n as f64;
    let mean = x.iter().sum::<f64>() / k;
    let z = geodesic_util::normal::normal_quantile(0.975);
    if n < 2 {
        return PopParam {
            mean,
            mean_sigma: f64::INFINITY,
            sd: 0.0,
            sd_sigma: f64::INFINITY,
            n,
            mean_ci95: None,
            sd_ci95: None,
        };
    }
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (k - 1.0);
    let s2 = s.iter().map(|s| s * s).sum::<f64>() / k;
    let sd = (var - s2).max(0.0).sqrt();
    let half = t_quantile(n - 1, 0.975) * (var / k).sqrt();
    let bound = |chi2: f64| ((k - 1.0) * var / chi2 - s2).max(0.0).sqrt();
    let sd_ci95 = [bound(chi2_isf(0.025, n - 1)), bound(chi2_isf(0.975, n - 1))];
    PopParam {
        mean,
        mean_sigma: half / z,
        sd,
        sd_sigma: (sd_ci95[1] - sd_ci95[0]) / (2.0 * z),
        n,
        mean_ci95: Some([mean - half, mean + half]),
        sd_ci95: Some(sd_ci95),
    }
}

/// The campaign result (interface.md).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct CampaignReport {
    /// Fitted releases.
    pub releases: Vec<Release>,
    /// Releases that could not be fitted.
    pub failed: Vec<Failed>,
    /// The table: quantity -> {model, data} statistics.
    pub table: BTreeMap<String, BTreeMap<String, Option<Stats>>>,
    /// Population of the adhesion parameters, with `correlation`.
    pub population: serde_json::Value,
    /// 95 % interval of each population correlation (a bootstrap over releases), by the key
    /// it has in `population.correlation`.
    #[serde(default)]
    pub correlation_ci95: BTreeMap<String, [f64; 2]>,
}

/// The release datasets of a campaign: a folder (every `*.yaml` that is a dataset, sorted) or a
/// campaign YAML with `releases: [file, ...]` (paths relative to it).
pub fn list(path: &Path) -> Result<Vec<PathBuf>, FitError> {
    if path.is_dir() {
        let mut v: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| {
                FitError::input(
                    path.display().to_string(),
                    0,
                    format!("cannot read the folder: {e}"),
                )
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.extension().is_some_and(|e| e == "yaml" || e == "yml")
                    && std::fs::read_to_string(p).is_ok_and(|t| t.contains("scenario:"))
            })
            .collect();
        v.sort();
        if v.is_empty() {
            return Err(FitError::input(
                path.display().to_string(),
                0,
                "no dataset YAML (with `scenario:`) in the folder",
            ));
        }
        return Ok(v);
    }
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Raw {
        releases: Vec<String>,
        #[serde(default)]
        #[allow(dead_code)]
        description: Option<String>,
    }
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| FitError::input(&file, 0, format!("cannot read: {e}")))?;
    let raw: Raw = serde_saphyr::from_str(&text).map_err(|e| {
        let line = e.location().map(|l| l.line() as usize).unwrap_or(0);
        FitError::input(
            &file,
            line,
            e.to_string().lines().next().unwrap_or("").to_string(),
        )
    })?;
    if raw.releases.is_empty() {
        return Err(FitError::input(&file, 0, "`releases` is empty"));
    }
    let base = path.parent().unwrap_or(Path::new("."));
    Ok(raw.releases.iter().map(|r| base.join(r)).collect())
}

/// Derived quantities of one fitted release.
fn derived(prep: &Prepared, o: &FitOutcome) -> (f64, f64, f64, f64) {
    let t = &prep.dataset.t;
    let m = prep.dataset.known.get("m").copied().unwrap_or(f64::NAN);
    let n = t.len();
    let tail: Vec<usize> = (0..n).filter(|&i| t[i] >= 0.8 * t[n - 1]).collect();
    let slope = |y: &dyn Fn(usize) -> f64| -> f64 {
        let k = tail.len() as f64;
        let (mt, my) = (
            tail.iter().map(|&i| t[i]).sum::<f64>() / k,
            tail.iter().map(|&i| y(i)).sum::<f64>() / k,
        );
        let sxy: f64 = tail.iter().map(|&i| (t[i] - mt) * (y(i) - my)).sum();
        let sxx: f64 = tail.iter().map(|&i| (t[i] - mt).powi(2)).sum();
        if sxx > 0.0 { sxy / sxx } else { f64::NAN }
    };
    let data = prep.data();
    let v_model = slope(&|i| o.pred[i]);
    let v_data = slope(&|i| data[i]);
    let acc: Vec<f64> = (1..n.saturating_sub(1))
        .map(|i| {
            let (h1, h2) = (t[i] - t[i - 1], t[i + 1] - t[i]);
            2.0 * ((o.pred[i + 1] - o.pred[i]) / h2 - (o.pred[i] - o.pred[i - 1]) / h1) / (h1 + h2)
        })
        .collect();
    let peak = acc.iter().copied().fold(0.0f64, f64::max);
    let dts: f64 = (1..n.saturating_sub(1))
        .filter(|&i| acc[i - 1] > 0.05 * peak && peak > 0.0)
        .map(|i| 0.5 * (t[i + 1] - t[i - 1]))
        .sum();
    (m * v_model, m * v_data, m * peak, dts)
}

/// Fits every release of the list in parallel (`progress` after each).
pub fn run(
    files: &[PathBuf],
    effects: &[&str],
    opts: &FitOptions,
    seed: u64,
    progress: &(dyn Fn() + Sync),
) -> CampaignReport {
    let results: Vec<Result<Release, Failed>> = files
        .par_iter()
        .map(|f| {
            let fail = |cause: String| Failed {
                file: f.display().to_string(),
                cause,
            };
            let out = (|| {
                let ds = geodesic_dataset::Dataset::load(f).map_err(|e| fail(e.to_string()))?;
                let prep = Prepared::new(ds);
                let o = geodesic_fit::estimate::fit(&prep, effects, opts)
                    .map_err(|e| fail(e.to_string()))?;
                let r = FitReport::new(&prep, &o);
                let (p_x_model, p_x_data, f_peak_model, dt_model) = derived(&prep, &o);
                let idx = |n: &str| {
                    let i = o.model.index(n)?;
                    o.free[i].then(|| (0..=i).filter(|&j| o.free[j]).count() - 1)
                };
                let corr_a1_lambda = match (idx("tip_adhesion.A1"), idx("tip_adhesion.lambda")) {
                    (Some(a), Some(b)) => Some(o.corr[(a, b)]),
                    _ => None,
                };
                Ok(Release {
                    file: f.display().to_string(),
                    chi2_red: r.chi2_red,
                    params: r.params,
                    p_x_model,
                    p_x_data,
                    f_peak_model,
                    dt_model,
                    corr_a1_lambda,
                })
            })();
            progress();
            out
        })
        .collect();
    let mut releases = Vec::new();
    let mut failed = Vec::new();
    for r in results {
        match r {
            Ok(x) => releases.push(x),
            Err(e) => failed.push(e),
        }
    }
    let col = |f: &dyn Fn(&Release) -> f64| -> Vec<f64> {
        releases.iter().map(f).filter(|v| v.is_finite()).collect()
    };
    let mut table = BTreeMap::new();
    let both = |m: Vec<f64>, d: Option<Vec<f64>>| {
        let mut x = BTreeMap::new();
        x.insert("model".to_string(), stats(&m));
        x.insert("data".to_string(), d.and_then(|d| stats(&d)));
        x
    };
    table.insert(
        "P_x_kg_m_s".to_string(),
        both(col(&|r| r.p_x_model), Some(col(&|r| r.p_x_data))),
    );
    table.insert("F_peak_N".to_string(), both(col(&|r| r.f_peak_model), None));
    table.insert("dt_s".to_string(), both(col(&|r| r.dt_model), None));
    let mut pop = serde_json::Map::new();
    let mut sds = BTreeMap::new();
    for name in ["tip_adhesion.A1", "tip_adhesion.lambda"].iter() {
        let (x, s): (Vec<f64>, Vec<f64>) = releases
            .iter()
            .filter_map(|r| r.params.get(*name))
            .filter(|p| !p.fixed && p.sigma.is_some_and(|s| s > 0.0) && p.value.is_finite())
            .map(|p| (p.value, p.sigma.unwrap_or(0.0)))
            .unzip();
        if x.len() >= 2 {
            let p = population_param(&x, &s);
            sds.insert(*name, p.sd);
            pop.insert(
                name.to_string(),
                serde_json::to_value(&p).expect("serialisable"),
            );
        }
    }
    // correlation across the population, within-release covariance removed
    let pairs: Vec<Pair> = releases
        .iter()
        .filter_map(|r| {
            let a = r.params.get("tip_adhesion.A1")?;
            let l = r.params.get("tip_adhesion.lambda")?;
            let usable = |p: &geodesic_fit::report::ParamOut| {
                !p.fixed && p.sigma.is_some_and(|s| s > 0.0 && s.is_finite()) && p.value.is_finite()
            };
            (usable(a) && usable(l)).then(|| Pair {
                a: a.value,
                sa: a.sigma.unwrap_or(0.0),
                l: l.value,
                sl: l.sigma.unwrap_or(0.0),
                corr: r.corr_a1_lambda.unwrap_or(0.0),
            })
        })
        .collect();
    let mut correlation_ci95 = BTreeMap::new();
    if pairs.len() >= 3 {
        let rho = deconvolved_rho(&pairs);
        pop.insert(
            "correlation".into(),
            serde_json::json!({PAIR: if rho.is_finite() { serde_json::json!(rho) } else { serde_json::Value::Null }}),
        );
        if rho.is_finite() {
            let ci = bootstrap_rho_ci95(&pairs, seed.wrapping_add(2));
            if ci.iter().all(|c| c.is_finite()) {
                correlation_ci95.insert(PAIR.to_string(), ci);
            }
        }
    } else {
        pop.insert("correlation".into(), serde_json::json!({}));
    }
    CampaignReport {
        releases,
        failed,
        table,
        population: serde_json::Value::Object(pop),
        correlation_ci95,
    }
}

/// The key of the A1-lambda correlation in `population.correlation` and `correlation_ci95`.
pub const PAIR: &str = "tip_adhesion.A1~tip_adhesion.lambda";

/// One release's A1 and lambda estimates with their 1-sigma and within-fit correlation.
#[derive(Debug, Clone, Copy)]
struct Pair {
    a: f64,
    sa: f64,
    l: f64,
    sl: f64,
    corr: f64,
}

/// The A1-lambda correlation across the population: the covariance of the estimates minus the
/// mean within-release covariance, over the product of the moment spreads, clipped
/// to [-1, 1]; NaN when a spread is 0 (no population spread to correlate).
fn deconvolved_rho(p: &[Pair]) -> f64 {
    let k = p.len() as f64;
    let (xa, sa): (Vec<f64>, Vec<f64>) = p.iter().map(|q| (q.a, q.sa)).unzip();
    let (xl, sl): (Vec<f64>, Vec<f64>) = p.iter().map(|q| (q.l, q.sl)).unzip();
    let (ta, tl) = (population_param(&xa, &sa).sd, population_param(&xl, &sl).sd);
    let (ma, ml) = (xa.iter().sum::<f64>() / k, xl.iter().sum::<f64>() / k);
    let cov = p.iter().map(|q| (q.a - ma) * (q.l - ml)).sum::<f64>() / (k - 1.0);
    let within = p.iter().map(|q| q.corr * q.sa * q.sl).sum::<f64>() / k;
    if ta > 0.0 && tl > 0.0 {
        ((cov - within) / (ta * tl)).clamp(-1.0, 1.0)
    } else {
        f64::NAN
    }
}

/// 95 % percentile interval of [`deconvolved_rho`] from a bootstrap over releases (500
/// resamples, ChaCha8 `seed`; resamples without a population spread are skipped).
fn bootstrap_rho_ci95(p: &[Pair], seed: u64) -> [f64; 2] {
    let n = p.len();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut v: Vec<f64> = (0..500)
        .map(|_| {
            let b: Vec<Pair> = (0..n).map(|_| p[rng.random_range(0..n)]).collect();
            deconvolved_rho(&b)
        })
        .filter(|r| r.is_finite())
        .collect();
    if v.len() < 100 {
        return [f64::NAN; 2];
    }
    v.sort_by(f64::total_cmp);
    let q = |f: f64| v[((f * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
    [q(0.025), q(0.975)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_distr::{Distribution, StandardNormal};

    /// `k` campaigns of `n` releases whose (A1, lambda) come from a population with correlation
    /// `rho`, each estimate off by a measurement error as large as half the population spread
    /// and correlated -0.95 within the release (as the fits' A1 and lambda are): the naive
    /// correlation of the estimates is pulled towards -0.95 (to -0.19 at rho = 0), the
    /// deconvolved one is not, and its bootstrap interval holds the truth about 95 % of the time.
    fn campaigns(rho: f64, k: usize, n: usize, seed: u64) -> (f64, f64, usize) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (ta, tl) = (2.5e4, 9e-8);
        let mut sum = 0.0;
        let mut naive = 0.0;
        let mut covered = 0;
        for c in 0..k {
            let p: Vec<Pair> = (0..n)
                .map(|_| {
                    let mut z = || -> f64 { StandardNormal.sample(&mut rng) };
                    let (z1, z2) = (z(), z());
                    let a = 1e5 + ta * z1;
                    let l = 6e-7 + tl * (rho * z1 + (1.0 - rho * rho).sqrt() * z2);
                    let (sa, sl, w) = (0.5 * ta, 0.5 * tl, -0.95);
                    let (e1, e2) = (z(), z());
                    Pair {
                        a: a + sa * e1,
                        sa,
                        l: l + sl * (w * e1 + (1.0 - w * w).sqrt() * e2),
                        sl,
                        corr: w,
                    }
                })
                .collect();
            let r = deconvolved_rho(&p);
            sum += r;
            let m = |f: &dyn Fn(&Pair) -> f64| p.iter().map(f).sum::<f64>() / n as f64;
            let (ma, ml) = (m(&|q| q.a), m(&|q| q.l));
            naive += m(&|q| (q.a - ma) * (q.l - ml))
                / (m(&|q| (q.a - ma).powi(2)) * m(&|q| (q.l - ml).powi(2))).sqrt();
            let [lo, hi] = bootstrap_rho_ci95(&p, seed + c as u64);
            if (lo..=hi).contains(&rho) {
                covered += 1;
            }
        }
        (sum / k as f64, naive / k as f64, covered)
    }

    #[test]
    fn the_population_correlation_is_deconvolved_and_its_interval_covers() {
        for (rho, seed) in [(0.0, 11), (-0.6, 12), (0.5, 13)] {
            let (mean, naive, covered) = campaigns(rho, 400, 30, seed);
            // the mean of 400 estimates: standard error about 0.2 / 20 = 0.01; the estimator's
            // own bias (a ratio with noisy spreads) measured +0.006 to +0.04 over 5 x 400
            assert!((mean - rho).abs() < 0.05, "rho {rho}: mean estimate {mean}");
            // the naive correlation is where the closed form puts it: (rho tau^2 - 0.95 s^2) /
            // (tau^2 + s^2) with s = tau / 2, i.e. -0.19 at 0, -0.67 at -0.6, 0.21 at 0.5
            let want = (rho - 0.25 * 0.95) / 1.25;
            assert!(
                (naive - want).abs() < 0.05,
                "rho {rho}: naive {naive}, want {want}"
            );
            // 95 % nominal; a percentile bootstrap of 30 releases under-covers a little
            // (measured 87-94 %)
            assert!(covered >= 340, "rho {rho}: covered {covered} of 400");
        }
    }

    #[test]
    fn t_quantiles_match_the_tables() {
        // two-sided 95 % points of Student's t (Abramowitz & Stegun, table 26.10)
        for (nu, want) in [
            (1, 12.706_205),
            (2, 4.302_653),
            (3, 3.182_446),
            (4, 2.776_445),
            (5, 2.570_582),
            (10, 2.228_139),
            (29, 2.045_230),
            (99, 1.984_217),
        ] {
            let t = t_quantile(nu, 0.975);
            assert!((t / want - 1.0).abs() < 1e-6, "nu {nu}: {t} vs {want}");
        }
    }

    #[test]
    fn chi2_quantiles_match_the_tables() {
        // lower and upper 2.5 % points (Abramowitz & Stegun, table 26.8)
        for (nu, lo, hi) in [
            (1, 0.000_982_069, 5.023_886),
            (2, 0.050_635_6, 7.377_759),
            (4, 0.484_419, 11.143_287),
            (9, 2.700_389, 19.022_768),
            (29, 16.047_07, 45.722_29),
            (99, 73.361_1, 128.422_0),
        ] {
            let (a, b) = (chi2_isf(0.975, nu), chi2_isf(0.025, nu));
            assert!((a / lo - 1.0).abs() < 1e-5, "nu {nu}: {a} vs {lo}");
            assert!((b / hi - 1.0).abs() < 1e-5, "nu {nu}: {b} vs {hi}");
        }
    }

    /// The population's stated uncertainty means what it says: over 400 simulated campaigns of
    /// 5, 10, 30 and 100 releases, measurement errors 15 % and 50 % of the spread, varying by
    /// +-30 % between releases or tied to the value as the fits' are (a weak release three
    /// times as uncertain as a strong one), the true mean lies within 2 `mean_sigma` of the
    /// estimate, the true spread within 2 `sd_sigma`, and `sd_ci95` holds it, about 95 % of the
    /// time each: measured 94-97 %, except the spread's interval with errors half the spread
    /// tied to the value, 91 % (363 of 400; the chi-square interval assumes equal errors). The
    /// floor 360 of 400 is 3.3 binomial sigma below 95 %.
    #[test]
    fn the_population_mean_and_spread_cover_the_truth() {
        for (n, frac, tied, seed) in [
            (5usize, 0.15, false, 1),
            (10, 0.5, false, 2),
            (30, 0.15, false, 3),
            (30, 0.5, true, 4),
            (100, 0.15, true, 5),
            (10, 0.3, true, 6),
        ] {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (mut mean_in, mut sd_in, mut ci_in) = (0, 0, 0);
            let (mu, tau) = (1e5, 2e4);
            for _ in 0..400 {
                let (mut x, mut s) = (Vec::with_capacity(n), Vec::with_capacity(n));
                for _ in 0..n {
                    let z: f64 = StandardNormal.sample(&mut rng);
                    let e: f64 = StandardNormal.sample(&mut rng);
                    let si = if tied {
                        frac * tau * (-0.55 * z).exp()
                    } else {
                        frac * tau * rng.random_range(0.7..1.3)
                    };
                    x.push(mu + tau * z + si * e);
                    s.push(si);
                }
                let p = population_param(&x, &s);
                mean_in += ((p.mean - mu).abs() <= 2.0 * p.mean_sigma) as usize;
                sd_in += ((p.sd - tau).abs() <= 2.0 * p.sd_sigma) as usize;
                let [lo, hi] = p.sd_ci95.expect("interval");
                ci_in += (lo <= tau && tau <= hi) as usize;
            }
            for (what, c) in [("mean", mean_in), ("sd", sd_in), ("sd_ci95", ci_in)] {
                assert!(
                    c >= 360,
                    "{n} releases, errors {frac} of the spread (tied {tied}): {what} covered {c} of 400"
                );
            }
        }
    }
}
