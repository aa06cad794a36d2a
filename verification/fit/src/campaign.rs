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
//!   per parameter the DerSimonian-Laird random-effects estimate (`mean`, its 1-sigma
//!   `mean_sigma`, the spread `sd` = `tau`), `sd_sigma` from a bootstrap over releases (500
//!   resamples, a fixed ChaCha stream), and the correlation of A1 and lambda across the
//!   population: the covariance of the estimates minus the mean within-release covariance
//!   (from each fit's correlation matrix), over `sd_A1 sd_lambda`, clipped to [-1, 1], with a
//!   95 % percentile interval from a bootstrap over releases (`correlation_ci95`). On
//!   campaigns of 30 releases whose measurement errors are half the population spread and
//!   correlated -0.95 within a release, the estimate's bias is +0.01 to +0.04 (the naive
//!   correlation of the estimates is off by up to -0.3) and the interval covers 87-94 % of the
//!   time (tests below).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::FitError;
use crate::fit::{FitOptions, FitOutcome, FitReport, Prepared};

/// One fitted release.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Release {
    /// Dataset YAML.
    pub file: String,
    /// Reduced chi-square.
    pub chi2_red: f64,
    /// Parameters with 1-sigma.
    pub params: BTreeMap<String, crate::report::ParamOut>,
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Failed {
    /// Dataset YAML.
    pub file: String,
    /// Why.
    pub cause: String,
}

/// Statistics of a quantity over the releases.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct PopParam {
    /// Population mean [SI].
    pub mean: f64,
    /// Its 1-sigma.
    pub mean_sigma: f64,
    /// Population spread (1-sigma, measurement errors removed).
    pub sd: f64,
    /// Its 1-sigma (bootstrap over releases).
    pub sd_sigma: f64,
    /// Releases used.
    pub n: usize,
}

/// DerSimonian-Laird random-effects estimate of `x` with 1-sigma errors `s`: (mean, its sigma,
/// tau).
pub fn dersimonian_laird(x: &[f64], s: &[f64]) -> (f64, f64, f64) {
    let w: Vec<f64> = s.iter().map(|s| 1.0 / (s * s).max(1e-300)).collect();
    let sw: f64 = w.iter().sum();
    let mu_fe = x.iter().zip(&w).map(|(x, w)| w * x).sum::<f64>() / sw;
    let q: f64 = x.iter().zip(&w).map(|(x, w)| w * (x - mu_fe).powi(2)).sum();
    let k = x.len() as f64;
    let c = sw - w.iter().map(|w| w * w).sum::<f64>() / sw;
    let tau2 = if c > 0.0 {
        ((q - (k - 1.0)) / c).max(0.0)
    } else {
        0.0
    };
    let ws: Vec<f64> = s.iter().map(|s| 1.0 / (s * s + tau2).max(1e-300)).collect();
    let sws: f64 = ws.iter().sum();
    let mu = x.iter().zip(&ws).map(|(x, w)| w * x).sum::<f64>() / sws;
    (mu, 1.0 / sws.sqrt(), tau2.sqrt())
}

/// The population of one parameter over the releases that have it.
pub fn population_param(x: &[f64], s: &[f64], seed: u64) -> PopParam {
    let (mean, mean_sigma, sd) = dersimonian_laird(x, s);
    let n = x.len();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut taus = Vec::with_capacity(500);
    for _ in 0..500 {
        let idx: Vec<usize> = (0..n).map(|_| rng.random_range(0..n)).collect();
        let xb: Vec<f64> = idx.iter().map(|&i| x[i]).collect();
        let sb: Vec<f64> = idx.iter().map(|&i| s[i]).collect();
        taus.push(dersimonian_laird(&xb, &sb).2);
    }
    let m = taus.iter().sum::<f64>() / taus.len() as f64;
    let sd_sigma =
        (taus.iter().map(|t| (t - m).powi(2)).sum::<f64>() / (taus.len() as f64 - 1.0)).sqrt();
    PopParam {
        mean,
        mean_sigma,
        sd,
        sd_sigma,
        n,
    }
}

/// The campaign result (interface.md).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
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
                let ds = crate::Dataset::load(f).map_err(|e| fail(e.to_string()))?;
                let prep = Prepared::new(ds);
                let o = crate::fit::fit(&prep, effects, opts).map_err(|e| fail(e.to_string()))?;
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
    for (k, name) in ["tip_adhesion.A1", "tip_adhesion.lambda"]
        .iter()
        .enumerate()
    {
        let (x, s): (Vec<f64>, Vec<f64>) = releases
            .iter()
            .filter_map(|r| r.params.get(*name))
            .filter(|p| !p.fixed && p.sigma > 0.0 && p.value.is_finite())
            .map(|p| (p.value, p.sigma))
            .unzip();
        if x.len() >= 2 {
            let p = population_param(&x, &s, seed.wrapping_add(k as u64));
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
            let usable = |p: &crate::report::ParamOut| {
                !p.fixed && p.sigma > 0.0 && p.value.is_finite() && p.sigma.is_finite()
            };
            (usable(a) && usable(l)).then(|| Pair {
                a: a.value,
                sa: a.sigma,
                l: l.value,
                sl: l.sigma,
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
/// mean within-release covariance, over the product of the DerSimonian-Laird spreads, clipped
/// to [-1, 1]; NaN when a spread is 0 (no population spread to correlate).
fn deconvolved_rho(p: &[Pair]) -> f64 {
    let k = p.len() as f64;
    let (xa, sa): (Vec<f64>, Vec<f64>) = p.iter().map(|q| (q.a, q.sa)).unzip();
    let (xl, sl): (Vec<f64>, Vec<f64>) = p.iter().map(|q| (q.l, q.sl)).unzip();
    let (ta, tl) = (dersimonian_laird(&xa, &sa).2, dersimonian_laird(&xl, &sl).2);
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

/// A population to draw a synthetic campaign from (normal, truncated positive).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
pub struct TruePopulation {
    /// Mean of A1 [N/m].
    pub a1_mean: f64,
    /// Spread of A1 [N/m].
    pub a1_sd: f64,
    /// Mean of lambda [m].
    pub lambda_mean: f64,
    /// Spread of lambda [m].
    pub lambda_sd: f64,
    /// Correlation of A1 and lambda.
    pub rho: f64,
}

impl Default for TruePopulation {
    /// Near the public example's adhesion (A1 1.3e5 N/m, lambda 6e-7 m), a 25 % and 15 % spread.
    fn default() -> Self {
        TruePopulation {
            a1_mean: 1.0e5,
            a1_sd: 2.5e4,
            lambda_mean: 6.0e-7,
            lambda_sd: 0.9e-7,
            rho: 0.0,
        }
    }
}

/// Draws release `i` of a synthetic campaign: (A1, lambda, preload F_pre [N], tip speed [m/s],
/// noise [m]).
pub fn draw_release(pop: &TruePopulation, seed: u64, i: u64) -> (f64, f64, f64, f64, f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(i);
    let mut g = || {
        // Box-Muller from two uniforms (the stream is fixed: no distribution-crate state)
        let (u1, u2): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random_range(0.0..1.0));
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    let (z1, z2) = (g(), g());
    let z2 = pop.rho * z1 + (1.0 - pop.rho * pop.rho).max(0.0).sqrt() * z2;
    let a1 = (pop.a1_mean + pop.a1_sd * z1).max(0.05 * pop.a1_mean);
    let lambda = (pop.lambda_mean + pop.lambda_sd * z2).max(0.05 * pop.lambda_mean);
    let f_pre = 7e-3 * (1.0 + 0.2 * g()).clamp(0.5, 1.5);
    let v = 3e-3 * (1.0 + 0.15 * g()).clamp(0.5, 1.5);
    let noise = 8e-10 * (1.0 + 0.3 * g().abs());
    (a1, lambda, f_pre, v, noise)
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
}
