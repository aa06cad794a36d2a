//! The Monte Carlo uncertainty budget: one YAML file (default `models/release/budget.yaml`,
//! embedded in the crate) giving a distribution for every input of a release (physics.md §3).
//!
//! Loading is two-step: the raw YAML (with source spans) is parsed by `serde-saphyr`, then each
//! distribution is checked (finite numbers, `sd >= 0`, `min < max`, a truncation window the
//! distribution can actually reach) and errors name the file and line.

use crate::stats::normal_cdf;
use geodesic_mechanism::PiezoParams;
use rand::{Rng, RngExt};
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};
use serde_saphyr::Spanned;
use std::fmt;
use thiserror::Error;

/// The default budget (physics.md §3), embedded from `models/release/budget.yaml`.
pub const DEFAULT_BUDGET_YAML: &str = include_str!("../budget.yaml");

/// Errors loading a budget.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum BudgetError {
    /// Malformed YAML or an unknown/missing field.
    #[error("{file}:{line}: {cause}")]
    Parse {
        /// File name.
        file: String,
        /// 1-based line (0 if unknown).
        line: u64,
        /// One-line cause.
        cause: String,
    },
    /// A distribution that cannot be sampled.
    #[error("{file}:{line}: {field}: {cause}")]
    Invalid {
        /// File name.
        file: String,
        /// 1-based line.
        line: u64,
        /// Field path, e.g. `adhesion.lambda_m`.
        field: String,
        /// One-line cause.
        cause: String,
    },
}

/// A probability distribution of one scalar input.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Dist {
    /// Always the same value.
    Fixed(f64),
    /// Uniform on `[min, max]`.
    Uniform {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// Normal, given `sd` or `rel_sd` (`sd = rel_sd * |mean|`), optionally truncated to
    /// `[min, max]` by rejection.
    Normal {
        /// Mean (before truncation).
        mean: f64,
        /// Standard deviation.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sd: Option<f64>,
        /// Standard deviation relative to `|mean|`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rel_sd: Option<f64>,
        /// Lower truncation bound.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min: Option<f64>,
        /// Upper truncation bound.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        max: Option<f64>,
        /// Truncation at `mean +- clip_sd * sd` (intersected with `min`/`max`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        clip_sd: Option<f64>,
    },
}

/// Smallest acceptance probability of a truncated normal (rejection sampling stays cheap).
const MIN_ACCEPTANCE: f64 = 1e-3;

impl Dist {
    fn sd(&self) -> f64 {
        match *self {
            Dist::Normal {
                mean, sd, rel_sd, ..
            } => sd.unwrap_or_else(|| rel_sd.unwrap_or(0.0) * mean.abs()),
            _ => 0.0,
        }
    }

    fn bounds(&self) -> (f64, f64) {
        match *self {
            Dist::Fixed(v) => (v, v),
            Dist::Uniform { min, max } => (min, max),
            Dist::Normal {
                mean,
                min,
                max,
                clip_sd,
                ..
            } => {
                let (mut lo, mut hi) = (
                    min.unwrap_or(f64::NEG_INFINITY),
                    max.unwrap_or(f64::INFINITY),
                );
                if let Some(c) = clip_sd {
                    lo = lo.max(mean - c * self.sd());
                    hi = hi.min(mean + c * self.sd());
                }
                (lo, hi)
            }
        }
    }

    /// Checks that the distribution can be sampled; returns a one-line cause if not.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            Dist::Fixed(v) if !v.is_finite() => Err(format!("fixed value {v} is not finite")),
            Dist::Fixed(_) => Ok(()),
            Dist::Uniform { min, max } => {
                if !(min.is_finite() && max.is_finite()) || min > max {
                    Err(format!(
                        "uniform needs finite min <= max, got [{min}, {max}]"
                    ))
                } else {
                    Ok(())
                }
            }
            Dist::Normal {
                mean,
                sd,
                rel_sd,
                clip_sd,
                ..
            } => {
                if !mean.is_finite() {
                    return Err(format!("mean {mean} is not finite"));
                }
                match (sd, rel_sd) {
                    (Some(_), Some(_)) => return Err("give sd or rel_sd, not both".into()),
                    (None, None) => return Err("normal needs sd or rel_sd".into()),
                    _ => {}
                }
                let s = self.sd();
                if !s.is_finite() || s < 0.0 {
                    return Err(format!("standard deviation {s} must be finite and >= 0"));
                }
                if clip_sd.is_some_and(|c| c.is_nan() || c <= 0.0) {
                    return Err("clip_sd must be > 0".into());
                }
                let (lo, hi) = self.bounds();
                if lo.is_nan() || hi.is_nan() || lo >= hi {
                    return Err(format!("truncation window [{lo}, {hi}] is empty"));
                }
                let p = if s == 0.0 {
                    if (lo..=hi).contains(&mean) { 1.0 } else { 0.0 }
                } else {
                    normal_cdf((hi - mean) / s) - normal_cdf((lo - mean) / s)
                };
                if p < MIN_ACCEPTANCE {
                    return Err(format!(
                        "truncation window [{lo}, {hi}] holds only {p:.1e} of the normal"
                    ));
                }
                Ok(())
            }
        }
    }

    /// Draws one value.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match *self {
            Dist::Fixed(v) => v,
            Dist::Uniform { min, max } => {
                let u: f64 = rng.random();
                min + (max - min) * u
            }
            Dist::Normal { mean, .. } => {
                let s = self.sd();
                let (lo, hi) = self.bounds();
                // acceptance >= 1e-3 was checked at load; the cap only guards against misuse
                for _ in 0..1_000_000 {
                    let z: f64 = StandardNormal.sample(rng);
                    let v = mean + s * z;
                    if v >= lo && v <= hi {
                        return v;
                    }
                }
                mean.clamp(lo, hi)
            }
        }
    }

    /// The value of this distribution at normal score `z`: its quantile at `Phi(z)` (the map
    /// of a Gaussian copula). An untruncated normal gives `mean + sd z` exactly; a truncated
    /// one inverts its CDF, `mean + sd Phi^-1(Phi(a) + Phi(z) (Phi(b) - Phi(a)))`.
    pub fn at_score(&self, z: f64) -> f64 {
        use geodesic_util::normal::normal_quantile;
        match *self {
            Dist::Fixed(v) => v,
            Dist::Uniform { min, max } => min + (max - min) * normal_cdf(z),
            Dist::Normal { mean, .. } => {
                let s = self.sd();
                let (lo, hi) = self.bounds();
                if s == 0.0 {
                    return mean.clamp(lo, hi);
                }
                if lo == f64::NEG_INFINITY && hi == f64::INFINITY {
                    return mean + s * z;
                }
                let (pa, pb) = (normal_cdf((lo - mean) / s), normal_cdf((hi - mean) / s));
                let p = (pa + normal_cdf(z) * (pb - pa)).clamp(1e-300, 1.0 - 1e-16);
                (mean + s * normal_quantile(p)).clamp(lo, hi)
            }
        }
    }

    /// Mean of the (truncated) distribution.
    pub fn mean(&self) -> f64 {
        match *self {
            Dist::Fixed(v) => v,
            Dist::Uniform { min, max } => 0.5 * (min + max),
            Dist::Normal { mean, .. } => {
                let s = self.sd();
                let (lo, hi) = self.bounds();
                if s == 0.0 {
                    return mean;
                }
                let (a, b) = ((lo - mean) / s, (hi - mean) / s);
                let phi = |x: f64| {
                    if x.is_finite() {
                        (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt()
                    } else {
                        0.0
                    }
                };
                mean + s * (phi(a) - phi(b)) / (normal_cdf(b) - normal_cdf(a))
            }
        }
    }
}

impl fmt::Display for Dist {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Dist::Fixed(v) => write!(f, "{v:e}"),
            Dist::Uniform { min, max } => write!(f, "U({min:e}, {max:e})"),
            Dist::Normal {
                mean,
                min,
                max,
                clip_sd,
                ..
            } => {
                write!(f, "N({mean:e}, {:e})", self.sd())?;
                if min.is_some() || max.is_some() || clip_sd.is_some() {
                    let (lo, hi) = self.bounds();
                    write!(f, " in [{lo:e}, {hi:e}]")?;
                }
                Ok(())
            }
        }
    }
}

/// Mechanism parameter distributions (per mechanism).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
#[allow(non_snake_case)]
pub struct MechanismBudget {
    /// `R` [ohm].
    pub R_ohm: Dist,
    /// `m` [kg].
    pub m_kg: Dist,
    /// `Ca` [F].
    pub Ca_f: Dist,
    /// `k` [N/m].
    pub k_n_m: Dist,
    /// `Kg` [N/m].
    pub Kg_n_m: Dist,
    /// `b` [N s/m].
    pub b_ns_m: Dist,
    /// `Mg` [kg].
    pub Mg_kg: Dist,
    /// `T` [C/m].
    pub T_c_m: Dist,
}

impl MechanismBudget {
    fn dists(&self) -> [Dist; 8] {
        [
            self.R_ohm,
            self.m_kg,
            self.Ca_f,
            self.k_n_m,
            self.Kg_n_m,
            self.b_ns_m,
            self.Mg_kg,
            self.T_c_m,
        ]
    }

    /// Draws one mechanism.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> PiezoParams {
        let d = self.dists();
        let mut a = [0.0; 8];
        for (v, dist) in a.iter_mut().zip(d.iter()) {
            *v = dist.sample(rng);
        }
        PiezoParams::from_array(a)
    }

    /// The mechanism at the distribution means.
    pub fn mean(&self) -> PiezoParams {
        PiezoParams::from_array(self.dists().map(|d| d.mean()))
    }
}

/// Adhesion distributions (per contact).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
#[allow(non_snake_case)]
pub struct AdhesionBudget {
    /// `A1` [N/m].
    pub A1_n_m: Dist,
    /// `lambda` [m].
    pub lambda_m: Dist,
    /// Correlation of `A1` and `lambda` within one contact (a Gaussian copula: the two normal
    /// scores correlated, each mapped through its own distribution); `None` draws them
    /// independently. YAML key `adhesion.A1_lambda_correlation`, in [-1, 1].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub A1_lambda_correlation: Option<f64>,
}

impl AdhesionBudget {
    /// Draws `(A1 [N/m], lambda [m])` of one contact. Without a correlation (or with 0) the two
    /// are drawn independently, as before the correlation existed (same random stream).
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> (f64, f64) {
        match self.A1_lambda_correlation {
            Some(rho) if rho != 0.0 => {
                let z1: f64 = StandardNormal.sample(rng);
                let z2: f64 = StandardNormal.sample(rng);
                let z2 = rho * z1 + (1.0 - rho * rho).max(0.0).sqrt() * z2;
                (self.A1_n_m.at_score(z1), self.lambda_m.at_score(z2))
            }
            _ => (self.A1_n_m.sample(rng), self.lambda_m.sample(rng)),
        }
    }
}

/// A checked uncertainty budget.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Budget {
    /// Free text naming the assumptions.
    pub description: String,
    /// Per mechanism.
    pub mechanism: MechanismBudget,
    /// Voltage slope `em` [V/s], per channel.
    pub em_v_s: Dist,
    /// Tip radius [m], per mechanism.
    pub tip_radius_m: Dist,
    /// Preload `F0` [N], one per release.
    pub preload_n: Dist,
    /// Adhesion, per contact.
    pub adhesion: AdhesionBudget,
    /// Effective modulus [Pa].
    pub e_star_pa: Dist,
    /// TM mass [kg].
    pub tm_mass_kg: Dist,
    /// Initial command voltage [V].
    pub e0_v: Dist,
    /// A campaign result (`geodesic campaign --json`, path relative to the budget file) whose
    /// adhesion population replaces `adhesion` (`crate::population::resolve`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adhesion_from: Option<String>,
}

type S = Spanned<Dist>;

/// The first line of a `serde-saphyr` message without its own `error: line L column C: ` prefix
/// (the file and line are printed in front of it already).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct RawMechanism {
    R_ohm: S,
    m_kg: S,
    Ca_f: S,
    k_n_m: S,
    Kg_n_m: S,
    b_ns_m: S,
    Mg_kg: S,
    T_c_m: S,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct RawAdhesion {
    A1_n_m: S,
    lambda_m: S,
    #[serde(default)]
    A1_lambda_correlation: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBudget {
    #[serde(default)]
    description: String,
    mechanism: RawMechanism,
    em_v_s: S,
    tip_radius_m: S,
    preload_n: S,
    adhesion: RawAdhesion,
    e_star_pa: S,
    tm_mass_kg: S,
    e0_v: S,
    #[serde(default)]
    adhesion_from: Option<Spanned<String>>,
    /// The parameters' pedigree (issue 49), read by `geodesic_core::pedigree`, not here.
    #[serde(default, rename = "pedigree")]
    _pedigree: Option<serde::de::IgnoredAny>,
}

/// Largest physically plausible value of a budget field [SI] (generous: 100 to 10^5 times the
/// nominal LPF values), beyond which a budget is refused as unphysical.
pub fn physical_max(field: &str) -> f64 {
    match field {
        "mechanism.R_ohm" => 1e8,
        "mechanism.m_kg" => 1.0,
        "mechanism.Ca_f" => 1e-3,
        "mechanism.k_n_m" => 1e11,
        "mechanism.Kg_n_m" => 1e10,
        "mechanism.b_ns_m" => 1e5,
        "mechanism.Mg_kg" => 10.0,
        "mechanism.T_c_m" => 1e4,
        "em_v_s" => 1e11,
        "tip_radius_m" => 1.0,
        "preload_n" => 100.0,
        "adhesion.A1_n_m" => 1e9,
        "adhesion.lambda_m" => 1e-3,
        "e_star_pa" => 1e13,
        "tm_mass_kg" => 100.0,
        "e0_v" => 1e4,
        _ => f64::INFINITY,
    }
}

impl Budget {
    /// The embedded default budget.
    pub fn default_budget() -> Self {
        Self::from_yaml(DEFAULT_BUDGET_YAML, "models/release/budget.yaml")
            .expect("embedded budget is valid")
    }

    /// Parses and checks a budget; `file` names the source in errors.
    pub fn from_yaml(text: &str, file: &str) -> Result<Self, BudgetError> {
        let raw: RawBudget = serde_saphyr::from_str(text).map_err(|e| {
            let y = geodesic_util::yaml_error(&e);
            BudgetError::Parse {
                file: file.to_string(),
                line: y.line.unwrap_or(0),
                cause: y.cause,
            }
        })?;
        let check = |field: &str, s: &S| -> Result<Dist, BudgetError> {
            s.value.validate().map_err(|cause| BudgetError::Invalid {
                file: file.to_string(),
                line: s.referenced.line(),
                field: field.to_string(),
                cause,
            })?;
            Ok(s.value)
        };
        let m = &raw.mechanism;
        let non_negative = |field: &str, s: &S| -> Result<Dist, BudgetError> {
            let d = check(field, s)?;
            let (lo, _) = d.bounds();
            if lo < 0.0 {
                return Err(BudgetError::Invalid {
                    file: file.to_string(),
                    line: s.referenced.line(),
                    field: field.to_string(),
                    cause: format!("must be non-negative (lower bound {lo:e}); add min: 0.0"),
                });
            }
            Ok(d)
        };
        // plainly unphysical values (orders of magnitude beyond any LPF hardware) are refused:
        // a draw at them cannot be integrated in bounded work
        let non_negative = |field: &str, s: &S| -> Result<Dist, BudgetError> {
            let d = non_negative(field, s)?;
            let max = physical_max(field);
            let (_, hi) = d.bounds();
            // the largest value drawn: the upper bound, or 8 sd above the mean when unbounded
            let top = if hi.is_finite() {
                hi
            } else {
                d.mean() + 8.0 * d.sd()
            };
            if top.is_nan() || top > max {
                return Err(BudgetError::Invalid {
                    file: file.to_string(),
                    line: s.referenced.line(),
                    field: field.to_string(),
                    cause: format!(
                        "draws up to {top:e}, beyond the physical maximum {max:e} accepted for it"
                    ),
                });
            }
            Ok(d)
        };
        Ok(Budget {
            description: raw.description.trim().to_string(),
            mechanism: MechanismBudget {
                R_ohm: non_negative("mechanism.R_ohm", &m.R_ohm)?,
                m_kg: non_negative("mechanism.m_kg", &m.m_kg)?,
                Ca_f: non_negative("mechanism.Ca_f", &m.Ca_f)?,
                k_n_m: non_negative("mechanism.k_n_m", &m.k_n_m)?,
                Kg_n_m: non_negative("mechanism.Kg_n_m", &m.Kg_n_m)?,
                b_ns_m: non_negative("mechanism.b_ns_m", &m.b_ns_m)?,
                Mg_kg: non_negative("mechanism.Mg_kg", &m.Mg_kg)?,
                T_c_m: non_negative("mechanism.T_c_m", &m.T_c_m)?,
            },
            em_v_s: non_negative("em_v_s", &raw.em_v_s)?,
            tip_radius_m: non_negative("tip_radius_m", &raw.tip_radius_m)?,
            preload_n: non_negative("preload_n", &raw.preload_n)?,
            adhesion: AdhesionBudget {
                A1_n_m: non_negative("adhesion.A1_n_m", &raw.adhesion.A1_n_m)?,
                lambda_m: non_negative("adhesion.lambda_m", &raw.adhesion.lambda_m)?,
                A1_lambda_correlation: match &raw.adhesion.A1_lambda_correlation {
                    Some(r) if !(-1.0..=1.0).contains(&r.value) => {
                        return Err(BudgetError::Invalid {
                            file: file.to_string(),
                            line: r.referenced.line(),
                            field: "adhesion.A1_lambda_correlation".into(),
                            cause: format!("{} is not a correlation in [-1, 1]", r.value),
                        });
                    }
                    r => r.as_ref().map(|r| r.value),
                },
            },
            e_star_pa: non_negative("e_star_pa", &raw.e_star_pa)?,
            tm_mass_kg: non_negative("tm_mass_kg", &raw.tm_mass_kg)?,
            e0_v: non_negative("e0_v", &raw.e0_v)?,
            adhesion_from: raw.adhesion_from.map(|a| a.value),
        })
    }

    /// A stable 64-bit FNV-1a hash (hex) of the checked budget, to match Monte Carlo partials.
    pub fn hash_hex(&self) -> String {
        let text = serde_json::to_string(self).expect("budget serialises");
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in text.bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        format!("{h:016x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn unphysical_budget_values_are_refused_with_file_line_and_field() {
        for (from, to, field) in [
            ("max: 1.5e5", "max: 1.0e30", "adhesion.A1_n_m"),
            ("mean: 2.15e6", "mean: 1.0e19", "mechanism.Kg_n_m"),
            ("mean: 4.91e7", "mean: 1.0e19", "mechanism.k_n_m"),
            ("mean: 0.300", "mean: 1.0e19", "preload_n"),
        ] {
            let text = DEFAULT_BUDGET_YAML.replacen(from, to, 1);
            assert_ne!(text, DEFAULT_BUDGET_YAML, "{from}");
            let e = Budget::from_yaml(&text, "b.yaml").unwrap_err().to_string();
            assert!(
                e.starts_with("b.yaml:") && e.contains(field) && e.contains("physical maximum"),
                "{e}"
            );
        }
    }

    #[test]
    fn default_budget_loads_with_physics_md_values() {
        let b = Budget::default_budget();
        assert_eq!(b.preload_n.mean(), 0.300 + 0.0); // truncation at 0 is 18 sd away
        assert_eq!(b.mechanism.mean(), PiezoParams::nominal());
        assert!((b.em_v_s.sd() - 1.02e7).abs() < 1.0);
        assert_eq!(b.hash_hex().len(), 16);
    }

    #[test]
    fn truncated_normal_mean() {
        let d = Dist::Normal {
            mean: 0.0,
            sd: Some(1.0),
            rel_sd: None,
            min: Some(0.0),
            max: None,
            clip_sd: None,
        };
        assert!((d.mean() - (2.0 / std::f64::consts::PI).sqrt()).abs() < 1e-6);
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let n = 200_000;
        let m: f64 = (0..n).map(|_| d.sample(&mut r)).sum::<f64>() / n as f64;
        assert!((m - d.mean()).abs() < 0.01, "{m}");
    }

    #[test]
    fn clip_sd_truncates_symmetrically() {
        let d = Dist::Normal {
            mean: 10.0,
            sd: None,
            rel_sd: Some(0.1),
            min: Some(0.0),
            max: None,
            clip_sd: Some(3.0),
        };
        assert_eq!(d.bounds(), (7.0, 13.0));
        assert!((d.mean() - 10.0).abs() < 1e-9);
        let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        assert!(
            (0..100_000)
                .map(|_| d.sample(&mut r))
                .all(|v| (7.0..=13.0).contains(&v))
        );
        let bad = Dist::Normal {
            mean: 10.0,
            sd: None,
            rel_sd: Some(0.1),
            min: None,
            max: None,
            clip_sd: Some(0.0),
        };
        assert!(bad.validate().is_err());
    }

    #[test]
    fn bad_distribution_names_file_and_line() {
        let text = DEFAULT_BUDGET_YAML.replace("sd: 0.0166", "sd: -0.0166");
        let e = Budget::from_yaml(&text, "b.yaml").unwrap_err().to_string();
        let line = DEFAULT_BUDGET_YAML
            .lines()
            .position(|l| l.starts_with("preload_n"))
            .unwrap()
            + 1;
        assert!(e.starts_with(&format!("b.yaml:{line}: preload_n")), "{e}");
    }

    #[test]
    fn unknown_field_is_a_parse_error_with_line() {
        let text = DEFAULT_BUDGET_YAML.replace("preload_n:", "preload:");
        let e = Budget::from_yaml(&text, "b.yaml").unwrap_err();
        assert!(
            matches!(e, BudgetError::Parse { line, .. } if line > 0),
            "{e}"
        );
        assert!(!e.to_string().contains("error: line"), "{e}");
    }

    #[test]
    fn empty_window_is_rejected() {
        let text = DEFAULT_BUDGET_YAML.replace(
            "mean: 7.0e-7, sd: 1.0e-7, min: 0.0",
            "mean: 7.0e-5, sd: 1.0e-7, min: 0.0",
        );
        let e = Budget::from_yaml(&text, "b.yaml").unwrap_err().to_string();
        assert!(e.contains("adhesion.lambda_m"), "{e}");
    }

    /// The copula keeps each marginal (its mean, checked against the truncated-normal closed
    /// form of `Dist::mean`) and gives the pair the stated correlation; without a correlation
    /// the draws are those of the independent path, number for number.
    #[test]
    fn correlated_adhesion_keeps_marginals_and_has_the_stated_correlation() {
        let mut a = Budget::default_budget().adhesion;
        a.A1_n_m = Dist::Normal {
            mean: 1e5,
            sd: Some(2.5e4),
            rel_sd: None,
            min: Some(0.0),
            max: None,
            clip_sd: None,
        };
        a.lambda_m = Dist::Normal {
            mean: 6e-7,
            sd: Some(3e-7),
            rel_sd: None,
            min: Some(0.0),
            max: Some(8e-7),
            clip_sd: None,
        };
        let n = 200_000;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        a.A1_lambda_correlation = Some(-0.8);
        let v: Vec<(f64, f64)> = (0..n).map(|_| a.sample(&mut rng)).collect();
        let (ma, ml) = (
            v.iter().map(|x| x.0).sum::<f64>() / n as f64,
            v.iter().map(|x| x.1).sum::<f64>() / n as f64,
        );
        let sd = |m: f64, f: &dyn Fn(&(f64, f64)) -> f64| {
            (v.iter().map(|x| (f(x) - m).powi(2)).sum::<f64>() / n as f64).sqrt()
        };
        let (sa, sl) = (sd(ma, &|x| x.0), sd(ml, &|x| x.1));
        // 4 standard errors of the sample mean
        assert!(
            (ma - a.A1_n_m.mean()).abs() < 4.0 * sa / (n as f64).sqrt(),
            "{ma}"
        );
        assert!(
            (ml - a.lambda_m.mean()).abs() < 4.0 * sl / (n as f64).sqrt(),
            "{ml}"
        );
        assert!(v.iter().all(|x| x.0 >= 0.0 && (0.0..=8e-7).contains(&x.1)));
        // the normal scores are correlated -0.8; the heavily truncated lambda keeps most of it
        let r = v.iter().map(|x| (x.0 - ma) * (x.1 - ml)).sum::<f64>() / n as f64 / (sa * sl);
        assert!((-0.8..=-0.6).contains(&r), "{r}");
        // with both marginals untruncated the Pearson correlation is the copula's
        let mut u = a;
        u.lambda_m = Dist::Normal {
            mean: 6e-7,
            sd: Some(9e-8),
            rel_sd: None,
            min: None,
            max: None,
            clip_sd: None,
        };
        u.A1_n_m = Dist::Normal {
            mean: 1e5,
            sd: Some(2.5e4),
            rel_sd: None,
            min: None,
            max: None,
            clip_sd: None,
        };
        let w: Vec<(f64, f64)> = (0..n).map(|_| u.sample(&mut rng)).collect();
        let (ma, ml) = (
            w.iter().map(|x| x.0).sum::<f64>() / n as f64,
            w.iter().map(|x| x.1).sum::<f64>() / n as f64,
        );
        let c = w.iter().map(|x| (x.0 - ma) * (x.1 - ml)).sum::<f64>();
        let ss = |f: &dyn Fn(&(f64, f64)) -> f64, m: f64| {
            w.iter().map(|x| (f(x) - m).powi(2)).sum::<f64>().sqrt()
        };
        let r = c / (ss(&|x| x.0, ma) * ss(&|x| x.1, ml));
        // standard error of r near -0.8: (1 - r^2) / sqrt(n) = 8e-4; 5 of them
        assert!((r + 0.8).abs() < 4e-3, "{r}");
        // no correlation: the independent path's numbers
        a.A1_lambda_correlation = None;
        let (mut r1, mut r2) = (
            rand_chacha::ChaCha8Rng::seed_from_u64(9),
            rand_chacha::ChaCha8Rng::seed_from_u64(9),
        );
        for _ in 0..100 {
            let (x, y) = a.sample(&mut r1);
            assert_eq!(x, a.A1_n_m.sample(&mut r2));
            assert_eq!(y, a.lambda_m.sample(&mut r2));
        }
    }

    #[test]
    fn a_correlation_outside_minus_one_one_is_refused_with_its_line() {
        let text = DEFAULT_BUDGET_YAML.replace(
            "  lambda_m: {normal:",
            "  A1_lambda_correlation: 1.5\n  lambda_m: {normal:",
        );
        let e = Budget::from_yaml(&text, "b.yaml").unwrap_err().to_string();
        assert!(e.contains("adhesion.A1_lambda_correlation"), "{e}");
        assert!(e.contains("b.yaml:35"), "{e}");
        let ok = DEFAULT_BUDGET_YAML.replace(
            "  lambda_m: {normal:",
            "  A1_lambda_correlation: -0.3\n  lambda_m: {normal:",
        );
        let b = Budget::from_yaml(&ok, "b.yaml").unwrap();
        assert_eq!(b.adhesion.A1_lambda_correlation, Some(-0.3));
        // an existing budget's hash does not move (the field is skipped when absent)
        assert_eq!(
            Budget::default_budget().hash_hex(),
            Budget::from_yaml(DEFAULT_BUDGET_YAML, "x")
                .unwrap()
                .hash_hex()
        );
    }
}
