//! The adhesion population of a campaign of measured releases as the Monte Carlo's adhesion
//! (issue 14, item 3: "the release Monte Carlo takes its adhesion from a campaign result").
//!
//! A campaign result (`geodesic campaign --json`) states, for `tip_adhesion.A1` and
//! `tip_adhesion.lambda`, the population mean and spread with the measurement errors removed,
//! each with its own 1-sigma (`mean_sigma`, `sd_sigma`). [`AdhesionPopulation::apply`] puts a
//! population into a budget: each parameter Normal(mean, sd) truncated to be non-negative, the
//! two joined by the campaign's A1-lambda correlation (a Gaussian copula,
//! `AdhesionBudget::A1_lambda_correlation`; independent when the campaign states none).
//! [`AdhesionPopulation::draw`] draws a population from its identification uncertainty
//! (mean ~ Normal(mean, mean_sigma), sd ~ |Normal(sd, sd_sigma)|, the correlation's Fisher
//! transform `atanh(rho)` ~ Normal with the sigma of the campaign's 95 % interval, or
//! `1/sqrt(n - 3)` without one), so that repeated Monte Carlo runs carry the campaign's finite
//! size into the flight prediction.

use crate::budget::{Budget, Dist};
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// One population parameter with its identification uncertainty [SI].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct PopParam {
    /// Population mean.
    pub mean: f64,
    /// 1-sigma of the mean.
    pub mean_sigma: f64,
    /// Population spread (1-sigma).
    pub sd: f64,
    /// 1-sigma of the spread.
    pub sd_sigma: f64,
}

/// The adhesion population of a campaign.
#[derive(Debug, Clone, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct AdhesionPopulation {
    /// `A1` [N/m].
    pub a1: PopParam,
    /// `lambda` [m].
    pub lambda: PopParam,
    /// The campaign's A1-lambda correlation across the population, if it states one (used in
    /// the draws).
    pub rho: Option<f64>,
    /// Its 95 % interval, if the campaign states one (`correlation_ci95`).
    pub rho_ci95: Option<[f64; 2]>,
    /// Releases the population rests on (the smaller of the two counts), if stated.
    pub releases: Option<u64>,
    /// Where it came from.
    pub source: String,
}

fn param(v: &serde_json::Value, name: &str, label: &str) -> Result<PopParam, String> {
    let p = v.get(name).ok_or_else(|| {
        format!("{label}: no population.{name} (run geodesic campaign with --effects including tip_adhesion)")
    })?;
    let get = |k: &str| -> Result<f64, String> {
        let x = p
            .get(k)
            .and_then(serde_json::Value::as_f64)
            .ok_or_else(|| format!("{label}: population.{name}.{k} is missing or not a number"))?;
        if !x.is_finite() || x < 0.0 {
            return Err(format!(
                "{label}: population.{name}.{k} = {x} must be a finite non-negative number"
            ));
        }
        Ok(x)
    };
    let out = PopParam {
        mean: get("mean")?,
        mean_sigma: get("mean_sigma")?,
        sd: get("sd")?,
        sd_sigma: get("sd_sigma")?,
    };
    if out.mean <= 0.0 {
        return Err(format!("{label}: population.{name}.mean must be positive"));
    }
    Ok(out)
}

impl AdhesionPopulation {
    /// Reads the population from a campaign result's JSON text (`label` names it in errors).
    pub fn from_campaign_json(text: &str, label: &str) -> Result<Self, String> {
        let v: serde_json::Value = serde_json::from_str(text).map_err(|e| {
            format!(
                "{label}:{}: not a campaign result (JSON: {})",
                e.line(),
                geodesic_core_text(&e.to_string())
            )
        })?;
        let pop = v.get("population").ok_or_else(|| {
            format!("{label}: no `population` (a `geodesic campaign --json` result is expected)")
        })?;
        let a1 = param(pop, "tip_adhesion.A1", label)?;
        let lambda = param(pop, "tip_adhesion.lambda", label)?;
        let rho = pop
            .get("correlation")
            .and_then(|c| c.get("tip_adhesion.A1~tip_adhesion.lambda"))
            .and_then(serde_json::Value::as_f64);
        if rho.is_some_and(|r| !(-1.0..=1.0).contains(&r)) {
            return Err(format!(
                "{label}: population.correlation {} is not in [-1, 1]",
                rho.unwrap_or(f64::NAN)
            ));
        }
        let rho_ci95 = v
            .get("correlation_ci95")
            .and_then(|c| c.get("tip_adhesion.A1~tip_adhesion.lambda"))
            .and_then(serde_json::Value::as_array)
            .and_then(|a| match a.as_slice() {
                [lo, hi] => Some([lo.as_f64()?, hi.as_f64()?]),
                _ => None,
            })
            .filter(|[lo, hi]| (-1.0..=1.0).contains(lo) && (-1.0..=1.0).contains(hi) && lo <= hi);
        let releases = ["tip_adhesion.A1", "tip_adhesion.lambda"]
            .iter()
            .filter_map(|n| {
                pop.get(*n)
                    .and_then(|p| p.get("n"))
                    .and_then(serde_json::Value::as_u64)
            })
            .min();
        Ok(AdhesionPopulation {
            a1,
            lambda,
            rho,
            rho_ci95,
            releases,
            source: label.to_string(),
        })
    }

    /// `budget` with its adhesion replaced by this population (truncated normals joined by the
    /// population's correlation).
    pub fn apply(&self, budget: &Budget) -> Result<Budget, String> {
        let normal = |p: &PopParam, what: &str| -> Result<Dist, String> {
            let d = if p.sd > 0.0 {
                Dist::Normal {
                    mean: p.mean,
                    sd: Some(p.sd),
                    rel_sd: None,
                    min: Some(0.0),
                    max: None,
                    clip_sd: None,
                }
            } else {
                Dist::Fixed(p.mean)
            };
            d.validate()
                .map_err(|e| format!("{}: {what}: {e}", self.source))?;
            Ok(d)
        };
        let mut b = budget.clone();
        b.adhesion.A1_n_m = normal(&self.a1, "A1")?;
        b.adhesion.lambda_m = normal(&self.lambda, "lambda")?;
        b.adhesion.A1_lambda_correlation = self.rho;
        b.description = format!(
            "{} [adhesion from campaign {}]",
            budget.description, self.source
        );
        Ok(b)
    }

    /// A population drawn from this one's identification uncertainty.
    pub fn draw<R: Rng + ?Sized>(&self, rng: &mut R) -> AdhesionPopulation {
        let mut one = |p: &PopParam| {
            let z1: f64 = StandardNormal.sample(rng);
            let z2: f64 = StandardNormal.sample(rng);
            PopParam {
                // a mean drawn below zero would be unphysical: kept a hair above it
                mean: (p.mean + p.mean_sigma * z1).max(p.mean * 1e-3),
                mean_sigma: 0.0,
                sd: (p.sd + p.sd_sigma * z2).abs(),
                sd_sigma: 0.0,
            }
        };
        let a1 = one(&self.a1);
        let lambda = one(&self.lambda);
        let rho = self.rho.map(|r| {
            let z: f64 = StandardNormal.sample(rng);
            let sigma = self.rho_sigma_z();
            // Fisher's z of a correlation at +-1 is infinite: kept a hair inside
            let r = r.clamp(-0.999_999, 0.999_999);
            (r.atanh() + sigma * z).tanh()
        });
        AdhesionPopulation {
            a1,
            lambda,
            rho,
            rho_ci95: None,
            releases: self.releases,
            source: self.source.clone(),
        }
    }

    /// The 1-sigma of the correlation's Fisher transform `atanh(rho)`: from the campaign's 95 %
    /// interval when it states one, else `1/sqrt(n - 3)` (Fisher) for `n` releases, else 0.
    pub fn rho_sigma_z(&self) -> f64 {
        let c = |r: f64| r.clamp(-0.999_999, 0.999_999).atanh();
        match (self.rho_ci95, self.releases) {
            (Some([lo, hi]), _) => (c(hi) - c(lo)) / (2.0 * 1.959_964),
            (None, Some(n)) if n > 3 => 1.0 / ((n - 3) as f64).sqrt(),
            _ => 0.0,
        }
    }
}

/// The 99.73 % points of Monte Carlo runs whose adhesion populations are drawn from a
/// campaign's identification uncertainty.
#[derive(Debug, Clone, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct Identification {
    /// 99.73 % point of each run [um/s].
    pub p9973_um_s: Vec<f64>,
    /// Their 2.5 % and 97.5 % points (linear interpolation) [um/s].
    pub interval_um_s: [f64; 2],
    /// Releases per run.
    pub n_each: usize,
}

impl Identification {
    /// Fraction of the runs whose 99.73 % point is at or below `limit_um_s`.
    pub fn probability_met(&self, limit_um_s: f64) -> f64 {
        self.p9973_um_s.iter().filter(|v| **v <= limit_um_s).count() as f64
            / self.p9973_um_s.len() as f64
    }
}

/// `draws` Monte Carlo runs of `n_each` releases (case `case`), each with a population drawn
/// from `pop`'s identification uncertainty applied to `budget`; deterministic for a `seed`
/// (populations from one ChaCha8 stream, run `k` seeded `seed + 1 + k`).
pub fn identification(
    pop: &AdhesionPopulation,
    budget: &Budget,
    case: crate::montecarlo::Case,
    n_each: usize,
    draws: usize,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Identification, String> {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x005e_ed0f_a0d1_e51c);
    let mut p = Vec::with_capacity(draws);
    for k in 0..draws.max(1) {
        let b = pop.draw(&mut rng).apply(budget)?;
        let r = crate::montecarlo::run(
            &b,
            case,
            n_each,
            seed.wrapping_add(1 + k as u64),
            None,
            progress,
        )
        .map_err(|e| format!("Monte Carlo (population draw {k}): {e}"))?;
        p.push(r.summary().p9973_um_s);
    }
    let mut s = p.clone();
    s.sort_by(f64::total_cmp);
    let q = |f: f64| {
        let x = f * (s.len() - 1) as f64;
        let (i, w) = (x.floor() as usize, x - x.floor());
        s[i] * (1.0 - w) + s[(i + 1).min(s.len() - 1)] * w
    };
    Ok(Identification {
        interval_um_s: [q(0.025), q(0.975)],
        p9973_um_s: p,
        n_each,
    })
}

/// Applies a budget's `adhesion_from` (a path relative to `budget_path`'s folder; the working
/// directory for a built-in budget): the budget with the campaign's adhesion population, and the
/// population. A budget without the key is returned unchanged.
pub fn resolve(
    budget: Budget,
    budget_path: Option<&std::path::Path>,
) -> Result<(Budget, Option<AdhesionPopulation>), String> {
    let Some(rel) = budget.adhesion_from.clone() else {
        return Ok((budget, None));
    };
    let base = budget_path
        .and_then(|p| p.parent())
        .unwrap_or(std::path::Path::new("."));
    let path = base.join(&rel);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("adhesion_from {}: {e}", path.display()))?;
    let pop = AdhesionPopulation::from_campaign_json(&text, &path.display().to_string())?;
    Ok((pop.apply(&budget)?, Some(pop)))
}

fn geodesic_core_text(s: &str) -> String {
    let l = s.lines().next().unwrap_or("").trim();
    if l.chars().count() > 160 {
        let c: String = l.chars().take(160).collect();
        format!("{c}...")
    } else {
        l.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    const JSON: &str = r#"{"population": {"tip_adhesion.A1": {"mean": 70000, "mean_sigma": 5000, "sd": 30000, "sd_sigma": 4000, "n": 30},
        "tip_adhesion.lambda": {"mean": 6e-7, "mean_sigma": 2e-8, "sd": 1e-7, "sd_sigma": 1.5e-8, "n": 29},
        "correlation": {"tip_adhesion.A1~tip_adhesion.lambda": -0.2}}}"#;

    #[test]
    fn reads_and_applies_a_campaign_population() {
        let p = AdhesionPopulation::from_campaign_json(JSON, "c.json").unwrap();
        assert_eq!(p.releases, Some(29));
        assert_eq!(p.rho, Some(-0.2));
        let b = p.apply(&Budget::default_budget()).unwrap();
        // Normal(7e4, 3e4) truncated at 0: mean 7e4 + 3e4 phi(7/3) / Phi(7/3) = 70 795 N/m
        let z: f64 = 7.0 / 3.0;
        let phi = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
        let expect = 7e4 + 3e4 * phi / 0.990_185;
        assert!(
            (b.adhesion.A1_n_m.mean() - expect).abs() < 5.0,
            "{}",
            b.adhesion.A1_n_m.mean()
        );
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let d = p.draw(&mut rng);
        assert!(d.a1.mean != p.a1.mean && d.a1.sd >= 0.0);
        // the correlation goes into the budget, and its draws spread as Fisher's 1/sqrt(n - 3)
        assert_eq!(b.adhesion.A1_lambda_correlation, Some(-0.2));
        assert!((p.rho_sigma_z() - 1.0 / 26f64.sqrt()).abs() < 1e-12);
        let z: Vec<f64> = (0..4000)
            .map(|_| p.draw(&mut rng).rho.unwrap().atanh())
            .collect();
        let m = z.iter().sum::<f64>() / z.len() as f64;
        let sd = (z.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (z.len() - 1) as f64).sqrt();
        assert!(
            (m - (-0.2f64).atanh()).abs() < 4.0 * sd / 4000f64.sqrt(),
            "{m}"
        );
        assert!((sd * 26f64.sqrt() - 1.0).abs() < 0.05, "{sd}");
    }

    #[test]
    fn a_stated_interval_sets_the_correlation_uncertainty() {
        let j = JSON.replacen(
            "{\"population\"",
            "{\"correlation_ci95\": {\"tip_adhesion.A1~tip_adhesion.lambda\": [-0.6, 0.3]}, \"population\"",
            1,
        );
        let p = AdhesionPopulation::from_campaign_json(&j, "c.json").unwrap();
        assert_eq!(p.rho_ci95, Some([-0.6, 0.3]));
        let want = (0.3f64.atanh() - (-0.6f64).atanh()) / (2.0 * 1.959_964);
        assert!((p.rho_sigma_z() - want).abs() < 1e-12);
        let bad = JSON.replace("-0.2}", "-1.5}");
        let e = AdhesionPopulation::from_campaign_json(&bad, "c.json").unwrap_err();
        assert!(e.contains("not in [-1, 1]"), "{e}");
    }

    /// The correlation is used: the adhesion momentum goes with the bond energy `A1 lambda^2`,
    /// whose spread a negative A1-lambda correlation narrows and a positive one widens, so the
    /// 99.73 % point of the release velocity moves with it (same seed, 4 000 releases).
    #[test]
    fn the_campaign_correlation_moves_the_flight_prediction() {
        let p = AdhesionPopulation::from_campaign_json(JSON, "c.json").unwrap();
        let at = |rho: f64| {
            let mut q = p.clone();
            q.rho = Some(rho);
            let b = q.apply(&Budget::default_budget()).unwrap();
            crate::montecarlo::run(&b, crate::montecarlo::Case::All, 4000, 7, None, &|_| {})
                .unwrap()
                .summary()
                .p9973_um_s
        };
        // measured: 0.46, 1.18 and 1.67 um/s
        let (neg, zero, pos) = (at(-0.9), at(0.0), at(0.9));
        assert!(
            neg < 0.8 * zero && zero < 0.8 * pos,
            "rho -0.9: {neg} um/s, 0: {zero} um/s, +0.9: {pos} um/s"
        );
    }

    #[test]
    fn refuses_what_is_not_a_campaign() {
        let e = AdhesionPopulation::from_campaign_json("{\"x\": 1}", "c.json").unwrap_err();
        assert!(e.contains("no `population`"), "{e}");
        let e = AdhesionPopulation::from_campaign_json("{\n oops", "c.json").unwrap_err();
        assert!(e.starts_with("c.json:2:"), "{e}");
        let e = AdhesionPopulation::from_campaign_json(
            &JSON.replace("\"mean\": 70000", "\"mean\": -5"),
            "c.json",
        )
        .unwrap_err();
        assert!(e.contains("A1.mean"), "{e}");
    }
}
