//! The JSON document of `geodesic montecarlo` and `geodesic merge` (interface.md): a run's
//! summary, its wall time, the uncertainty of its 99.73 % point against REL-GPRM-VEL's limit,
//! the budget it read and, for a campaign population or a shard, what they add. A typed
//! document: the commands print it through `serde_json::Value`, whose keys are in
//! alphabetical order, as they always have been.

use crate::montecarlo::{McResult, Summary};
use crate::population::{AdhesionPopulation, Identification};
use crate::stats::{probability_quantile_below, quantile_interval_sorted};
use serde::Serialize;

/// The report of a run or of the merge of its shards.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct McReport {
    /// The run's statistics (interface.md keys).
    #[serde(flatten)]
    pub summary: Summary,
    /// Wall time [s].
    pub seconds: f64,
    /// 95 % distribution-free interval of the 99.73 % point [um/s] (of the population draws'
    /// 99.73 % points with a campaign population).
    pub p9973_interval_um_s: [f64; 2],
    /// Probability that the 99.73 % point is at or below [`McReport::limit_um_s`].
    pub probability_met: f64,
    /// REL-GPRM-VEL's limit on |X'| [um/s], read from the loaded requirement.
    pub limit_um_s: f64,
    /// What the interval and the probability include.
    pub uncertainty: String,
    /// The budget file read.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inputs: Option<RunInputs>,
    /// The campaign population the adhesion was taken from.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adhesion_from: Option<AdhesionFrom>,
    /// `I/K` of a shard.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    /// Draws of a shard.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub draws: Option<usize>,
    /// The partial result file written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub out: Option<String>,
}

/// The inputs a run read.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct RunInputs {
    /// The release budget.
    pub budget: BudgetRead,
}

/// A budget file read: as every command names it.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BudgetRead {
    /// Path as given, or `<built-in>/models/release/budget.yaml`.
    pub label: String,
    /// SHA-256 of its bytes.
    pub sha256: String,
    /// `given`, `repository` or `built-in`.
    pub origin: String,
}

/// The campaign population of a run and the identification-uncertainty draws made from it.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct AdhesionFrom {
    /// The campaign result the population was read from.
    pub source: String,
    /// The population.
    pub population: AdhesionPopulation,
    /// Whether the A1-lambda correlation was used in the draws.
    pub correlation_used: bool,
    /// 99.73 % point of each population draw [um/s].
    pub draws_p9973_um_s: Vec<f64>,
    /// Releases per draw.
    pub releases_per_draw: usize,
}

impl McReport {
    /// The report of `r` (its `summary`, `seconds` of wall time) against the limit `limit_um_s`
    /// [um/s]: the 95 % interval of the 99.73 % point and the probability that it meets the
    /// limit, from Monte Carlo sampling only (the adhesion budget taken as known).
    pub fn new(r: &McResult, summary: Summary, seconds: f64, limit_um_s: f64) -> McReport {
        let mut abs = r.abs_um_s();
        abs.sort_by(f64::total_cmp);
        let exceed = abs.iter().filter(|x| **x > limit_um_s).count();
        McReport {
            summary,
            seconds,
            p9973_interval_um_s: quantile_interval_sorted(&abs, 0.9973),
            probability_met: probability_quantile_below(abs.len(), exceed, 0.9973),
            limit_um_s,
            uncertainty:
                "Monte Carlo sampling only (adhesion identification uncertainty not propagated)"
                    .into(),
            inputs: r.budget_source.as_ref().map(|s| RunInputs {
                budget: BudgetRead {
                    label: s.label.clone(),
                    sha256: r.budget_hash.clone(),
                    origin: s.origin.clone(),
                },
            }),
            adhesion_from: None,
            shard: None,
            draws: None,
            out: None,
        }
    }

    /// The report with the identification uncertainty of a campaign population: the interval
    /// and the probability are those of the population draws' 99.73 % points.
    pub fn with_identification(mut self, pop: &AdhesionPopulation, id: &Identification) -> Self {
        self.p9973_interval_um_s = id.interval_um_s;
        self.probability_met = id.probability_met(self.limit_um_s);
        self.uncertainty = format!(
            "adhesion identification (the campaign population's mean, spread and A1-lambda correlation drawn {} times from their uncertainty, N / 10 releases each) and Monte Carlo sampling",
            id.p9973_um_s.len()
        );
        self.adhesion_from = Some(AdhesionFrom {
            source: pop.source.clone(),
            population: pop.clone(),
            correlation_used: pop.rho.is_some(),
            draws_p9973_um_s: id.p9973_um_s.clone(),
            releases_per_draw: id.n_each,
        });
        self
    }
}
