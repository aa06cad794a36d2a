//! The in-flight release Monte Carlo (thesis ch. 6, physics.md §3, interface.md).
//!
//! Draw `i` of a run with seed `s` uses its own random stream (`ChaCha8Rng` seeded with `s`,
//! stream `i`), so a draw's inputs depend only on `(budget, case, s, i)`: results are the same
//! whatever the thread count or sharding. Shard `I/K` runs the contiguous draws
//! `[(I-1) N / K, I N / K)`. A [`McResult`] keeps the signed `X'` of its draws in draw order
//! (8 bytes a draw: 8 MB for 10^6), and [`merge`] concatenates shards, so a merged run has
//! exactly the values, hence the summary, of a single run.

use crate::budget::Budget;
use crate::expgauss::ExpGauss;
use crate::inputs::ReleaseInputs;
#[cfg(doc)]
use crate::integrator::DormandPrince;
use crate::integrator::IntegrateError;
use crate::stats::quantile_sorted;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::ops::Range;
use std::str::FromStr;
use thiserror::Error;

/// Default number of releases of `geodesic montecarlo`.
pub const DEFAULT_N: usize = 100_000;

/// Largest number of draws of a run (a hundred times the default; 80 MB of velocities).
pub const MAX_N: usize = 10_000_000;

/// Largest number of shards a run may be split into.
pub const MAX_SHARDS: usize = 100_000;

/// Which uncertainties a run samples (interface.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Case {
    /// Every effect of the budget.
    All,
    /// Random adhesion on equal nominal mechanisms (nominal slope, radii and preload).
    Adhesion,
    /// Random mechanisms, slopes, tip radii and preload; equal adhesion on both sides at the mean
    /// `A1` and mean `lambda` of the adhesion distribution.
    Mechanisms,
}

impl Case {
    /// The case name used on the command line and in JSON.
    pub fn as_str(&self) -> &'static str {
        match self {
            Case::All => "all",
            Case::Adhesion => "adhesion",
            Case::Mechanisms => "mechanisms",
        }
    }
}

impl fmt::Display for Case {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Case {
    type Err = McError;
    fn from_str(s: &str) -> Result<Self, McError> {
        match s {
            "all" => Ok(Case::All),
            "adhesion" => Ok(Case::Adhesion),
            "mechanisms" => Ok(Case::Mechanisms),
            other => Err(McError::UnknownCase(other.to_string())),
        }
    }
}

/// Errors of a Monte Carlo run or merge.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum McError {
    /// A case name other than all, adhesion, mechanisms.
    #[error("unknown case '{0}' (expected all, adhesion or mechanisms)")]
    UnknownCase(String),
    /// Shard numbers out of range.
    #[error("bad shard {index}/{count}: need 1 <= I <= K")]
    BadShard {
        /// I.
        index: usize,
        /// K.
        count: usize,
    },
    /// N = 0.
    #[error("n must be at least 1")]
    EmptyRun,
    /// One release failed to integrate.
    #[error("draw {index} ({inputs}): {source}")]
    Release {
        /// Draw index.
        index: usize,
        /// The draw's inputs, for the message.
        inputs: String,
        /// Integrator failure.
        source: IntegrateError,
    },
    /// A count beyond its stated maximum.
    #[error("{0}")]
    TooLarge(String),
    /// Partials that cannot be merged (different run, missing or duplicate shards).
    #[error("{0}")]
    Merge(String),
}

/// Draws the inputs of draw `index` of a run.
pub fn draw_inputs(budget: &Budget, case: Case, seed: u64, index: u64) -> ReleaseInputs {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(index);
    // Always draw everything in the same order, then apply the case: the cases share their
    // random numbers (common random numbers), which makes them directly comparable.
    let mech = [
        budget.mechanism.sample(&mut rng),
        budget.mechanism.sample(&mut rng),
    ];
    let em = [
        budget.em_v_s.sample(&mut rng),
        budget.em_v_s.sample(&mut rng),
    ];
    let rt = [
        budget.tip_radius_m.sample(&mut rng),
        budget.tip_radius_m.sample(&mut rng),
    ];
    let f0 = budget.preload_n.sample(&mut rng);
    let a = &budget.adhesion;
    let (a1_1, lam_1) = a.sample(&mut rng);
    let (a1_2, lam_2) = a.sample(&mut rng);
    let mut r = ReleaseInputs {
        mech,
        em_v_s: em,
        e0_v: budget.e0_v.sample(&mut rng),
        tip_radius_m: rt,
        e_star_pa: budget.e_star_pa.sample(&mut rng),
        preload_n: f0,
        a1_n_m: [a1_1, a1_2],
        lambda_m: [lam_1, lam_2],
        tm_mass_kg: budget.tm_mass_kg.sample(&mut rng),
    };
    match case {
        Case::All => {}
        Case::Adhesion => {
            r.mech = [budget.mechanism.mean(); 2];
            r.em_v_s = [budget.em_v_s.mean(); 2];
            r.tip_radius_m = [budget.tip_radius_m.mean(); 2];
            r.preload_n = budget.preload_n.mean();
        }
        Case::Mechanisms => {
            r.a1_n_m = [a.A1_n_m.mean(); 2];
            r.lambda_m = [a.lambda_m.mean(); 2];
        }
    }
    r
}

/// The sampled inputs of a draw in one line (for the message of a failed draw).
pub fn describe(r: &ReleaseInputs) -> String {
    let m = &r.mech;
    format!(
        "preload {:e} N, A1 {:e}/{:e} N/m, lambda {:e}/{:e} m, k {:e}/{:e} N/m, Kg {:e}/{:e} N/m, \
         m {:e}/{:e} kg, em {:e}/{:e} V/s, tip radius {:e}/{:e} m, E* {:e} Pa, TM {:e} kg",
        r.preload_n,
        r.a1_n_m[0],
        r.a1_n_m[1],
        r.lambda_m[0],
        r.lambda_m[1],
        m[0].k_n_m,
        m[1].k_n_m,
        m[0].kg_n_m,
        m[1].kg_n_m,
        m[0].m_kg,
        m[1].m_kg,
        r.em_v_s[0],
        r.em_v_s[1],
        r.tip_radius_m[0],
        r.tip_radius_m[1],
        r.e_star_pa,
        r.tm_mass_kg
    )
}

/// Refuses a run of more than [`MAX_N`] draws, or split into more than [`MAX_SHARDS`] shards
/// or into more shards than draws (a shard would be empty).
pub fn check_size(n: usize, shards: Option<usize>) -> Result<(), McError> {
    if n > MAX_N {
        return Err(McError::TooLarge(format!(
            "n = {n} draws is more than the maximum {MAX_N}"
        )));
    }
    if let Some(k) = shards {
        if k > MAX_SHARDS {
            return Err(McError::TooLarge(format!(
                "{k} shards is more than the maximum {MAX_SHARDS}"
            )));
        }
        if k > n {
            return Err(McError::TooLarge(format!(
                "{k} shards of {n} draws would leave a shard empty"
            )));
        }
    }
    Ok(())
}

/// `I/K` of a shard, `whole run` for none.
fn shard_name(s: Option<(usize, usize)>) -> String {
    match s {
        Some((i, k)) => format!("{i}/{k}"),
        None => "whole run".into(),
    }
}

/// Contiguous draw range of shard `index` (1-based) of `count` over `n` draws.
pub fn shard_range(n: usize, index: usize, count: usize) -> Result<Range<usize>, McError> {
    if count == 0 || index == 0 || index > count {
        return Err(McError::BadShard { index, count });
    }
    let lo = (n as u128 * (index as u128 - 1) / count as u128) as usize;
    let hi = (n as u128 * index as u128 / count as u128) as usize;
    Ok(lo..hi)
}

/// The budget file a run read: its label (path, or `<built-in>/...`) and origin (`given`,
/// `repository`, `built-in`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BudgetSource {
    /// Path as given, or `<built-in>/models/release/budget.yaml`.
    pub label: String,
    /// `given`, `repository` or `built-in`.
    pub origin: String,
}

/// The values of a run (or of one shard of it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct McResult {
    /// Draws of the whole run.
    pub n: usize,
    /// Seed.
    pub seed: u64,
    /// Case.
    pub case: Case,
    /// Identifies the budget used: [`Budget::hash_hex`] from [`run`]; `geodesic montecarlo`
    /// sets the SHA-256 of the budget file's bytes, as every command identifies it.
    pub budget_hash: String,
    /// The budget's description.
    pub budget_description: String,
    /// The budget file the run read and where it was resolved from (set by `geodesic
    /// montecarlo`, carried by partial results so that `merge` says it as the whole run does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub budget_source: Option<BudgetSource>,
    /// Shard `(I, K)`, `None` for a whole run.
    pub shard: Option<(usize, usize)>,
    /// First draw index held.
    pub start: usize,
    /// Signed final TM velocities `X'` [m/s] of draws `start..start + len`, in draw order.
    /// In JSON: each the IEEE-754 bit pattern of the f64 (an exact round trip).
    #[serde(with = "f64_bits")]
    #[schemars(with = "Vec<u64>")]
    pub v_m_s: Vec<f64>,
    /// Draws ended by the fallback stopping rule (see [`crate::model`]).
    pub fallback_stops: u64,
    /// Right-hand side evaluations (Dormand-Prince) or contact-force evaluations at the
    /// collocation nodes (exponential Gauss collocation) over all draws (cost).
    pub rhs_evals: u64,
}

/// Exact JSON round trip of f64 vectors: stored as their IEEE-754 bit patterns (u64).
mod f64_bits {
    use serde::{Deserialize, Deserializer, Serializer};
    pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|x| x.to_bits()))
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Ok(Vec::<u64>::deserialize(d)?
            .into_iter()
            .map(f64::from_bits)
            .collect())
    }
}

/// Summary statistics of a run (interface.md `geodesic montecarlo --json`, without `seconds`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Summary {
    /// Draws.
    pub n: usize,
    /// Seed.
    pub seed: u64,
    /// Case.
    pub case: Case,
    /// 99.73 % (nearest-rank) quantile of |X'| [um/s].
    pub p9973_um_s: f64,
    /// Mean |X'| [um/s].
    pub mean_um_s: f64,
    /// Largest |X'| [um/s].
    pub max_um_s: f64,
    /// Median |X'| [um/s].
    pub p50_um_s: f64,
    /// 99 % quantile of |X'| [um/s].
    pub p99_um_s: f64,
    /// Mean signed X' [um/s].
    pub signed_mean_um_s: f64,
    /// Standard deviation of signed X' [um/s].
    pub sd_um_s: f64,
    /// Draws ended by the fallback stopping rule.
    pub fallback_stops: u64,
    /// Budget hash.
    pub budget_hash: String,
    /// Budget description.
    pub budget: String,
}

impl Summary {
    /// The summary as text lines (the case, N and seed, then the statistics of |X'| and the
    /// fallback stops), as `geodesic montecarlo` and `geodesic merge` print it.
    pub fn text_lines(&self) -> Vec<String> {
        vec![
            format!(
                "in-flight release Monte Carlo: case {}, N = {}, seed {}",
                self.case, self.n, self.seed
            ),
            format!("  |X'| 99.73 %  {:.4} um/s", self.p9973_um_s),
            format!("  |X'| 99 %     {:.4} um/s", self.p99_um_s),
            format!("  |X'| median   {:.4} um/s", self.p50_um_s),
            format!("  |X'| mean     {:.4} um/s", self.mean_um_s),
            format!("  |X'| max      {:.4} um/s", self.max_um_s),
            format!(
                "  X' mean, sd   {:+.4}, {:.4} um/s",
                self.signed_mean_um_s, self.sd_um_s
            ),
            format!("  fallback stops {}", self.fallback_stops),
        ]
    }
}

impl McResult {
    /// |X'| [um/s] of the held draws, in draw order.
    pub fn abs_um_s(&self) -> Vec<f64> {
        self.v_m_s.iter().map(|v| v.abs() * 1e6).collect()
    }

    /// Whether this result holds every draw of its run.
    pub fn is_complete(&self) -> bool {
        self.start == 0 && self.v_m_s.len() == self.n
    }

    /// Summary statistics of the held draws (sums in draw order: bit-identical for equal data).
    pub fn summary(&self) -> Summary {
        let n = self.v_m_s.len();
        let mut abs = self.abs_um_s();
        let mean = abs.iter().sum::<f64>() / n as f64;
        let smean = self.v_m_s.iter().map(|v| v * 1e6).sum::<f64>() / n as f64;
        let var = self
            .v_m_s
            .iter()
            .map(|v| (v * 1e6 - smean).powi(2))
            .sum::<f64>()
            / (n.max(2) - 1) as f64;
        abs.sort_by(f64::total_cmp);
        Summary {
            n: self.n,
            seed: self.seed,
            case: self.case,
            p9973_um_s: quantile_sorted(&abs, 0.9973),
            mean_um_s: mean,
            max_um_s: abs.last().copied().unwrap_or(f64::NAN),
            p50_um_s: quantile_sorted(&abs, 0.5),
            p99_um_s: quantile_sorted(&abs, 0.99),
            signed_mean_um_s: smean,
            sd_um_s: var.sqrt(),
            fallback_stops: self.fallback_stops,
            budget_hash: self.budget_hash.clone(),
            budget: self.budget_description.clone(),
        }
    }

    /// The title of this run's histogram of |X'| (its values: [`McResult::abs_um_s`]; drawn by
    /// `geodesic_plot::histogram`).
    pub fn title(&self) -> String {
        format!(
            "|X'| after release: case {}, N = {}, seed {}",
            self.case, self.n, self.seed
        )
    }
}

/// Values, fallback stops and right-hand side evaluations of one chunk of draws.
type ChunkResult = (Vec<f64>, u64, u64);

/// Draws per parallel work item (also the progress granularity).
const CHUNK: usize = 256;

/// Runs the Monte Carlo with the exponential Gauss collocation ([`ExpGauss::fast`], exact on
/// the linear mechanisms; [`DormandPrince::fast`] for a draw whose mechanisms give no modal
/// decomposition): `n` draws of `case`
/// from `budget` with `seed`, or only shard `(I, K)` of them. `progress` is called with the
/// number of draws just finished (from worker threads).
pub fn run(
    budget: &Budget,
    case: Case,
    n: usize,
    seed: u64,
    shard: Option<(usize, usize)>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<McResult, McError> {
    if n == 0 {
        return Err(McError::EmptyRun);
    }
    check_size(n, shard.map(|s| s.1))?;
    let range = match shard {
        Some((i, k)) => shard_range(n, i, k)?,
        None => 0..n,
    };
    let integ = ExpGauss::fast();
    let chunks: Vec<Range<usize>> = range
        .clone()
        .step_by(CHUNK)
        .map(|s| s..(s + CHUNK).min(range.end))
        .collect();
    let parts: Vec<Result<ChunkResult, McError>> = chunks
        .into_par_iter()
        .map(|c| {
            let mut v = Vec::with_capacity(c.len());
            let (mut fb, mut evals) = (0u64, 0u64);
            for i in c.clone() {
                let r = draw_inputs(budget, case, seed, i as u64);
                let out = r.simulate_fast(&integ).map_err(|source| McError::Release {
                    index: i,
                    inputs: describe(&r),
                    source,
                })?;
                if !out.v_tm_m_s.is_finite() {
                    return Err(McError::Release {
                        index: i,
                        inputs: describe(&r),
                        source: IntegrateError::NonFinite { t_s: f64::NAN },
                    });
                }
                v.push(out.v_tm_m_s);
                fb += u64::from(out.fallback_stop);
                evals += out.stats.rhs_evals;
            }
            progress(c.len() as u64);
            Ok((v, fb, evals))
        })
        .collect();
    let mut v_m_s = Vec::with_capacity(range.len());
    let (mut fallback_stops, mut rhs_evals) = (0, 0);
    for p in parts {
        let (v, fb, ev) = p?;
        v_m_s.extend(v);
        fallback_stops += fb;
        rhs_evals += ev;
    }
    Ok(McResult {
        n,
        seed,
        case,
        budget_hash: budget.hash_hex(),
        budget_description: budget.description.clone(),
        budget_source: None,
        shard,
        start: range.start,
        v_m_s,
        fallback_stops,
        rhs_evals,
    })
}

/// Merges partial results of one run into the whole run. Checks that N, seed, case, budget hash
/// and K agree, and that the shards cover every draw exactly once.
pub fn merge(mut parts: Vec<McResult>) -> Result<McResult, McError> {
    let first = parts
        .first()
        .ok_or_else(|| McError::Merge("no partial results given".into()))?
        .clone();
    let k = match first.shard {
        Some((_, k)) => k,
        None => 1,
    };
    check_size(first.n, Some(k))
        .map_err(|e| McError::Merge(format!("shard {}: {e}", shard_name(first.shard))))?;
    for p in &parts {
        let same = p.n == first.n
            && p.seed == first.seed
            && p.case == first.case
            && p.budget_hash == first.budget_hash;
        if !same {
            return Err(McError::Merge(format!(
                "partial of shard {} is from another run (n {}, seed {}, case {}, budget {}) than shard {} (n {}, seed {}, case {}, budget {})",
                shard_name(p.shard),
                p.n,
                p.seed,
                p.case,
                p.budget_hash,
                shard_name(first.shard),
                first.n,
                first.seed,
                first.case,
                first.budget_hash
            )));
        }
        let pk = p.shard.map(|s| s.1).unwrap_or(1);
        if pk != k {
            return Err(McError::Merge(format!(
                "partials split the run into different shard counts ({k} and {pk})"
            )));
        }
        let idx = p.shard.map(|s| s.0).unwrap_or(1);
        if let Some(j) = p.v_m_s.iter().position(|v| !v.is_finite()) {
            return Err(McError::Merge(format!(
                "shard {idx}/{k}: draw {} has a non-finite velocity {}",
                p.start.saturating_add(j),
                p.v_m_s[j]
            )));
        }
        let expect = shard_range(p.n, idx, k)?;
        if p.start != expect.start || p.v_m_s.len() != expect.len() {
            return Err(McError::Merge(format!(
                "shard {idx}/{k} holds {} draws from draw {}, expected draws {}..{}",
                p.v_m_s.len(),
                p.start,
                expect.start,
                expect.end
            )));
        }
    }
    parts.sort_by_key(|p| p.shard.map(|s| s.0).unwrap_or(1));
    let mut seen = vec![false; k];
    for p in &parts {
        let idx = p.shard.map(|s| s.0).unwrap_or(1);
        if seen[idx - 1] {
            return Err(McError::Merge(format!("shard {idx}/{k} given twice")));
        }
        seen[idx - 1] = true;
    }
    let missing: Vec<String> = (0..k)
        .filter(|i| !seen[*i])
        .map(|i| format!("{}/{k}", i + 1))
        .collect();
    if !missing.is_empty() {
        return Err(McError::Merge(format!(
            "missing shard(s) {}",
            missing.join(", ")
        )));
    }
    let mut v_m_s = Vec::with_capacity(first.n);
    let (mut fallback_stops, mut rhs_evals) = (0, 0);
    for p in parts {
        v_m_s.extend(p.v_m_s);
        fallback_stops += p.fallback_stops;
        rhs_evals += p.rhs_evals;
    }
    Ok(McResult {
        shard: None,
        start: 0,
        v_m_s,
        fallback_stops,
        rhs_evals,
        ..first
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::integrator::DormandPrince;

    #[test]
    fn an_extreme_draw_ends_with_a_named_failure_in_bounded_work() {
        let mut r = ReleaseInputs::nominal();
        r.mech[0].k_n_m = 1e19;
        r.mech[1].kg_n_m = 1e19;
        let t0 = std::time::Instant::now();
        let e = r.simulate(&DormandPrince::fast()).unwrap_err();
        assert!(t0.elapsed().as_secs() < 120, "{e}");
        let m = McError::Release {
            index: 7,
            inputs: describe(&r),
            source: e,
        }
        .to_string();
        assert!(m.starts_with("draw 7 (") && m.contains("k 1e19"), "{m}");
    }

    #[test]
    fn counts_are_bounded() {
        let b = Budget::default_budget();
        let e = run(&b, Case::All, MAX_N + 1, 1, None, &|_| {}).unwrap_err();
        assert!(e.to_string().contains("maximum"), "{e}");
        let e = run(&b, Case::All, 3, 1, Some((1, 5)), &|_| {}).unwrap_err();
        assert!(e.to_string().contains("empty"), "{e}");
        let mut p = run(&b, Case::All, 4, 1, Some((1, 2)), &|_| {}).unwrap();
        p.shard = Some((1, 1 << 62));
        let e = merge(vec![p]).unwrap_err().to_string();
        assert!(e.contains("maximum") && !e.contains("Some("), "{e}");
    }

    #[test]
    fn shards_cover_the_run_contiguously() {
        for (n, k) in [(10, 3), (100_000, 7), (5, 8)] {
            let mut next = 0;
            for i in 1..=k {
                let r = shard_range(n, i, k).unwrap();
                assert_eq!(r.start, next);
                next = r.end;
            }
            assert_eq!(next, n);
        }
        assert!(shard_range(10, 0, 3).is_err());
        assert!(shard_range(10, 4, 3).is_err());
    }

    #[test]
    fn case_parsing() {
        assert_eq!("adhesion".parse::<Case>().unwrap(), Case::Adhesion);
        assert!("everything".parse::<Case>().is_err());
    }

    #[test]
    fn draws_depend_only_on_seed_and_index() {
        let b = Budget::default_budget();
        assert_eq!(
            draw_inputs(&b, Case::All, 7, 42),
            draw_inputs(&b, Case::All, 7, 42)
        );
        assert_ne!(
            draw_inputs(&b, Case::All, 7, 42),
            draw_inputs(&b, Case::All, 7, 43)
        );
        assert_ne!(
            draw_inputs(&b, Case::All, 7, 42),
            draw_inputs(&b, Case::All, 8, 42)
        );
        let a = draw_inputs(&b, Case::Adhesion, 7, 42);
        assert_eq!(a.mech[0], a.mech[1]);
        assert_eq!(a.a1_n_m, draw_inputs(&b, Case::All, 7, 42).a1_n_m);
        let m = draw_inputs(&b, Case::Mechanisms, 7, 42);
        assert_eq!(m.a1_n_m[0], m.a1_n_m[1]);
        assert_eq!(m.lambda_m[0], m.lambda_m[1]);
    }

    #[test]
    fn sharded_run_merges_to_the_single_run_exactly() {
        let b = Budget::default_budget();
        let whole = run(&b, Case::All, 50, 3, None, &|_| {}).unwrap();
        let parts: Vec<McResult> = (1..=3)
            .rev()
            .map(|i| run(&b, Case::All, 50, 3, Some((i, 3)), &|_| {}).unwrap())
            .collect();
        // JSON round trip is exact
        let parts: Vec<McResult> = parts
            .iter()
            .map(|p| serde_json::from_str(&serde_json::to_string(p).unwrap()).unwrap())
            .collect();
        let merged = merge(parts.clone()).unwrap();
        assert_eq!(merged.v_m_s, whole.v_m_s);
        assert_eq!(merged.summary(), whole.summary());
        assert!(
            merge(parts[..2].to_vec())
                .unwrap_err()
                .to_string()
                .contains("missing shard(s) 1/3")
        );
        let dup = vec![parts[0].clone(), parts[0].clone(), parts[1].clone()];
        assert!(merge(dup).unwrap_err().to_string().contains("given twice"));
        let mut other = parts.clone();
        other[1].seed = 4;
        assert!(
            merge(other)
                .unwrap_err()
                .to_string()
                .contains("another run")
        );
    }
}
