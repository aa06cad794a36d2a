//! Capture probability of a release Monte Carlo (requirement CAP-RELEASE-PROB): the z velocity
//! of each draw comes from the release model (given here as a slice, so this crate does not
//! depend on `geodesic-release`), the other 11 states are drawn from configurable
//! distributions, and each draw is judged by the quartic criterion (thesis ch. 7).
//!
//! Determinism: draw `k` uses its own ChaCha8 stream (`seed`, stream `k`), so the result
//! depends on the seed and the velocities only, never on thread count or chunking.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal, StandardUniform};
use serde::Deserialize;

use crate::criterion::quartic_sum;
use crate::error::CaptureError;
use crate::limits::Xlim;
use crate::state::{N_STATES, NamedMap, StateName, TmState, named_entries};

/// The default state distributions (embedded): zero-mean normals with sigma = req_i / 3, so
/// the requirement box is each state's 3-sigma (99.73 %) bound.
pub const DEFAULT_DISTRIBUTION_YAML: &str = include_str!("../state-distribution.yaml");

/// Label used in messages for the embedded default distribution file.
pub const DEFAULT_DISTRIBUTION_LABEL: &str =
    "models/capture/state-distribution.yaml (embedded default)";

/// Distribution of one TM state after release [SI unit of the state].
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum StateDist {
    /// Always 0.
    Zero,
    /// Always `value`.
    Fixed {
        /// The value [SI].
        value: f64,
    },
    /// Normal(mean, sigma).
    Normal {
        /// Mean [SI].
        mean: f64,
        /// Standard deviation [SI], >= 0.
        sigma: f64,
    },
    /// Uniform on [min, max).
    Uniform {
        /// Lower bound [SI].
        min: f64,
        /// Upper bound [SI], >= min.
        max: f64,
    },
}

impl StateDist {
    fn check(&self) -> Result<(), String> {
        let finite = |v: f64| v.is_finite();
        match *self {
            StateDist::Zero => Ok(()),
            StateDist::Fixed { value } if finite(value) => Ok(()),
            StateDist::Normal { mean, sigma } if finite(mean) && finite(sigma) && sigma >= 0.0 => {
                Ok(())
            }
            StateDist::Uniform { min, max } if finite(min) && finite(max) && max >= min => Ok(()),
            _ => Err("parameters must be finite, sigma >= 0, max >= min".into()),
        }
    }

    fn sample(&self, rng: &mut ChaCha8Rng) -> f64 {
        match *self {
            StateDist::Zero => 0.0,
            StateDist::Fixed { value } => value,
            StateDist::Normal { mean, sigma } => {
                let z: f64 = StandardNormal.sample(rng);
                mean + sigma * z
            }
            StateDist::Uniform { min, max } => {
                let u: f64 = StandardUniform.sample(rng);
                min + (max - min) * u
            }
        }
    }
}

/// Distributions of the 11 states other than `vz` (which the release Monte Carlo supplies).
#[derive(Clone, Debug, PartialEq)]
pub struct StateDistribution {
    /// One distribution per state, canonical order; the `vz` entry is unused.
    pub dists: [StateDist; N_STATES],
    /// Where it came from (file path or the embedded-default label).
    pub source: String,
}

impl StateDistribution {
    /// The embedded default (Normal(0, req_i/3) for the 11 states).
    pub fn default_set() -> StateDistribution {
        StateDistribution::from_yaml_str(DEFAULT_DISTRIBUTION_YAML, DEFAULT_DISTRIBUTION_LABEL)
            .expect("embedded state-distribution.yaml is valid (unit-tested)")
    }

    /// All 11 states fixed at zero (only the release z velocity counts).
    pub fn zeros() -> StateDistribution {
        StateDistribution {
            dists: [StateDist::Zero; N_STATES],
            source: "all states zero".into(),
        }
    }

    /// Reads a distribution file: a mapping from state name to one of `zero`,
    /// `{fixed: {value: V}}`, `{normal: {mean: M, sigma: S}}`, `{uniform: {min: A, max: B}}`.
    /// States not listed are zero. `vz` is rejected: it comes from the release Monte Carlo.
    pub fn from_yaml_str(text: &str, file: &str) -> Result<StateDistribution, CaptureError> {
        let raw: NamedMap<StateDist> =
            serde_saphyr::from_str(text).map_err(|e| CaptureError::yaml(file, &e))?;
        let mut dists = [StateDist::Zero; N_STATES];
        for (name, d, line) in named_entries(raw, file)? {
            let bad = |cause: String| CaptureError::BadValue {
                file: file.to_owned(),
                line,
                name: name.to_string(),
                value: format!("{d:?}"),
                cause,
            };
            if name == StateName::Vz {
                return Err(bad(
                    "vz comes from the release Monte Carlo and cannot be set here".into(),
                ));
            }
            d.check().map_err(bad)?;
            dists[name.index()] = d;
        }
        Ok(StateDistribution {
            dists,
            source: file.to_owned(),
        })
    }

    /// Reads a distribution file from disk (see [`StateDistribution::from_yaml_str`]).
    pub fn load(path: &std::path::Path) -> Result<StateDistribution, CaptureError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| CaptureError::Io {
            file: file.clone(),
            cause: e.to_string(),
        })?;
        StateDistribution::from_yaml_str(&text, &file)
    }

    /// Draws the state of draw `k`: `vz` as given, the others from stream `k` of `seed`.
    pub fn draw(&self, vz_m_s: f64, seed: u64, k: u64) -> TmState {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(k);
        let mut s = TmState::zero();
        for name in StateName::ALL {
            let v = if name == StateName::Vz {
                vz_m_s
            } else {
                self.dists[name.index()].sample(&mut rng)
            };
            s.set(name, v);
        }
        s
    }
}

/// Capture probability of a set of release draws.
#[derive(Clone, Debug, PartialEq)]
pub struct CaptureProbability {
    /// Number of draws.
    pub n: usize,
    /// Draws with quartic sum < 1.
    pub captured: usize,
    /// `captured / n` [-].
    pub probability: f64,
    /// One-sided 95 % lower confidence bound on the probability (Wilson score) [-].
    pub lower_95: f64,
    /// 99.73 % quantile of the quartic sum over the draws [-].
    pub sum_p9973: f64,
    /// Largest quartic sum [-].
    pub sum_max: f64,
    /// Seed of the 11 other states.
    pub seed: u64,
}

/// Capture probability of the release draws `vz_m_s` (z velocities [m/s], one per release),
/// with the other 11 states drawn from `dist` (draw `k` on stream `k` of `seed`).
///
/// ```
/// use geodesic_capture::{capture_probability, StateDistribution, Xlim};
/// let p = capture_probability(&[1e-6, -2e-6, 13e-6], &StateDistribution::zeros(),
///                             &Xlim::default_set(), 1);
/// assert_eq!(p.captured, 2);
/// ```
///
/// Returns `n = 0` and probability NaN for an empty slice.
pub fn capture_probability(
    vz_m_s: &[f64],
    dist: &StateDistribution,
    xlim: &Xlim,
    seed: u64,
) -> CaptureProbability {
    let sums: Vec<f64> = vz_m_s
        .iter()
        .enumerate()
        .map(|(k, &vz)| quartic_sum(xlim, &dist.draw(vz, seed, k as u64)))
        .collect();
    CaptureProbability::from_sums(sums, seed)
}

impl CaptureProbability {
    /// The statistics of a set of quartic sums (one per draw); NaN sums count as not captured.
    pub fn from_sums(mut sums: Vec<f64>, seed: u64) -> CaptureProbability {
        let n = sums.len();
        let captured = sums.iter().filter(|&&s| s < 1.0).count();
        sums.sort_by(f64::total_cmp);
        let quantile = |p: f64| -> f64 {
            if n == 0 {
                f64::NAN
            } else {
                let idx = ((p * n as f64).ceil() as usize).clamp(1, n) - 1;
                sums[idx]
            }
        };
        CaptureProbability {
            n,
            captured,
            probability: captured as f64 / n as f64,
            lower_95: wilson_lower(captured, n, 1.644_853_626_951_472_2),
            sum_p9973: quantile(0.9973),
            sum_max: sums.last().copied().unwrap_or(f64::NAN),
            seed,
        }
    }
}

/// Lower Wilson score bound of a binomial proportion at `z` standard deviations [-].
fn wilson_lower(k: usize, n: usize, z: f64) -> f64 {
    if n == 0 {
        return f64::NAN;
    }
    let n = n as f64;
    let p = k as f64 / n;
    let z2 = z * z;
    let centre = p + z2 / (2.0 * n);
    let half = z * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((centre - half) / (1.0 + z2 / n)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_distribution_is_req_over_3() {
        let d = StateDistribution::default_set();
        let x = Xlim::default_set();
        for s in StateName::ALL {
            if s == StateName::Vz {
                assert_eq!(d.dists[s.index()], StateDist::Zero);
                continue;
            }
            match d.dists[s.index()] {
                StateDist::Normal { mean, sigma } => {
                    assert_eq!(mean, 0.0);
                    let rel = (sigma - x.requirement(s) / 3.0).abs() / sigma;
                    assert!(rel < 1e-6, "{s}: {sigma}");
                }
                other => panic!("{s}: {other:?}"),
            }
        }
    }

    #[test]
    fn draws_are_deterministic_and_independent_of_order() {
        let d = StateDistribution::default_set();
        let a = d.draw(1e-6, 7, 42);
        let b = d.draw(1e-6, 7, 42);
        assert_eq!(a, b);
        assert_ne!(a, d.draw(1e-6, 7, 43));
        assert_ne!(a, d.draw(1e-6, 8, 42));
        assert_eq!(a.get(StateName::Vz), 1e-6);
    }

    #[test]
    fn zero_distribution_judges_vz_alone() {
        let x = Xlim::default_set();
        let p = capture_probability(
            &[0.0, 11.9e-6, -11.9e-6, 12.1e-6],
            &StateDistribution::zeros(),
            &x,
            0,
        );
        assert_eq!(p.n, 4);
        assert_eq!(p.captured, 3);
        assert_eq!(p.probability, 0.75);
        assert!(p.sum_max > 1.0);
    }

    #[test]
    fn sampled_normal_has_the_requested_sigma() {
        let d = StateDistribution::default_set();
        let n = 20_000;
        let xs: Vec<f64> = (0..n)
            .map(|k| d.draw(0.0, 3, k).get(StateName::X))
            .collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let sigma = 200e-6 / 3.0;
        // standard error of the sd estimate: sigma / sqrt(2n) = 0.5 %; allow 4 of them.
        assert!((var.sqrt() - sigma).abs() < 0.02 * sigma, "{}", var.sqrt());
        assert!(mean.abs() < 4.0 * sigma / (n as f64).sqrt(), "{mean}");
    }

    #[test]
    fn vz_in_distribution_file_is_rejected_with_line() {
        let e = StateDistribution::from_yaml_str("x: zero\nvz: zero\n", "d.yaml").unwrap_err();
        assert!(e.to_string().starts_with("d.yaml:2:"), "{e}");
    }

    #[test]
    fn bad_parameters_are_rejected_with_line() {
        let e =
            StateDistribution::from_yaml_str("x:\n  normal: {mean: 0.0, sigma: -1.0}\n", "d.yaml")
                .unwrap_err();
        assert!(e.to_string().starts_with("d.yaml:1:"), "{e}");
        let e =
            StateDistribution::from_yaml_str("x:\n  gauss: {mean: 0.0}\n", "d.yaml").unwrap_err();
        assert!(e.to_string().starts_with("d.yaml:"), "{e}");
    }

    #[test]
    fn wilson_bound_is_below_the_estimate() {
        let lo = wilson_lower(100_000, 100_000, 1.6448536269514722);
        assert!(lo < 1.0 && lo > 0.9999, "{lo}");
        let lo = wilson_lower(9_973, 10_000, 1.6448536269514722);
        assert!(lo < 0.9973 && lo > 0.996, "{lo}");
    }
}
