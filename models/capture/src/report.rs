//! The document of `geodesic capture --json`: the quartic criterion for one TM state (sum,
//! verdict, terms, dominant states), the capture limits and their source, the requirement box,
//! and optionally the capture probability of a set of release velocities. Typed here, where it
//! is computed; the command prints it through `serde_json::Value` (keys in alphabetical order,
//! as it always has).

use crate::{
    CaptureProbability, Evaluation, StateName, TmState, Xlim, consistency_sum, max_box_scale,
    single_state_limits,
};
use serde::Serialize;
use std::collections::BTreeMap;

/// Values per state, keyed by the state's name (`x`, ..., `wz`) [SI].
pub type PerState = BTreeMap<&'static str, f64>;

fn per_state(values: &[f64; 12]) -> PerState {
    StateName::ALL
        .iter()
        .map(|s| (s.as_str(), values[s.index()]))
        .collect()
}

/// `geodesic capture`'s document; `F` names the capture inputs file (label, SHA-256, origin).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct CaptureReport<F: Serialize> {
    /// `sum_i (x_i / xlim_i)^4`.
    pub quartic_sum: f64,
    /// Whether the sum is below 1.
    pub captured: bool,
    /// The TM state [SI].
    pub state: PerState,
    /// Each state's term of the sum.
    pub terms: PerState,
    /// The dominant terms.
    pub dominant: Vec<DominantTerm>,
    /// The capture limits [SI].
    pub xlim: PerState,
    /// Where the limits come from.
    pub xlim_source: String,
    /// The requirement box [SI].
    pub requirement: PerState,
    /// Scale of the requirement box the limits were derived with.
    pub box_scale: f64,
    /// The quartic sum of the requirement box.
    pub consistency_sum: f64,
    /// Each state's limit alone [SI].
    pub single_state_limits: PerState,
    /// Largest capturable scale of the requirement box.
    pub max_box_scale: f64,
    /// The unit of each state.
    pub units: BTreeMap<&'static str, &'static str>,
    /// The capture probability of the given release velocities.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub capture_probability: Option<ProbabilityRow>,
    /// The input files read.
    pub inputs: BTreeMap<&'static str, F>,
}

/// A dominant term of the sum.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct DominantTerm {
    /// State name.
    pub state: &'static str,
    /// Its value [SI].
    pub value: f64,
    /// Its limit [SI].
    pub xlim: f64,
    /// Its term.
    pub term: f64,
    /// Its share of the sum.
    pub share: f64,
}

/// The capture probability and where the other states' distribution comes from.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct ProbabilityRow {
    /// Releases.
    pub n: usize,
    /// Captured releases.
    pub captured: usize,
    /// Fraction captured.
    pub probability: f64,
    /// One-sided 95 % lower bound (Clopper-Pearson).
    pub lower_95: f64,
    /// 99.73 % point of the sum.
    pub sum_p9973: f64,
    /// Largest sum.
    pub sum_max: f64,
    /// Seed.
    pub seed: u64,
    /// Source of the other states' distribution.
    pub distribution_source: String,
}

impl<F: Serialize> CaptureReport<F> {
    /// The document of `eval` (the criterion for `state` with the limits `xlim`), the optional
    /// capture probability with its source, and the capture inputs `file` (named `capture`).
    pub fn new(
        xlim: &Xlim,
        state: &TmState,
        eval: &Evaluation,
        prob: Option<&(CaptureProbability, String)>,
        file: F,
    ) -> Self {
        let terms: [f64; 12] = std::array::from_fn(|i| eval.terms[i].term);
        CaptureReport {
            quartic_sum: eval.quartic_sum,
            captured: eval.captured,
            state: per_state(&state.0),
            terms: per_state(&terms),
            dominant: eval
                .dominant
                .iter()
                .map(|t| DominantTerm {
                    state: t.state.as_str(),
                    value: t.value,
                    xlim: t.xlim,
                    term: t.term,
                    share: t.share,
                })
                .collect(),
            xlim: per_state(&xlim.xlim),
            xlim_source: xlim.source.clone(),
            requirement: per_state(&xlim.req),
            box_scale: xlim.box_scale,
            consistency_sum: consistency_sum(xlim),
            single_state_limits: per_state(&single_state_limits(xlim)),
            max_box_scale: max_box_scale(xlim),
            units: StateName::ALL
                .iter()
                .map(|s| (s.as_str(), s.unit()))
                .collect(),
            capture_probability: prob.map(|(p, source)| ProbabilityRow {
                n: p.n,
                captured: p.captured,
                probability: p.probability,
                lower_95: p.lower_95,
                sum_p9973: p.sum_p9973,
                sum_max: p.sum_max,
                seed: p.seed,
                distribution_source: source.clone(),
            }),
            inputs: BTreeMap::from([("capture", file)]),
        }
    }
}
