//! Prediction of a model's fitted channel: the dispatch from a [`Model`] to its scenario's
//! simulation. Kept apart from `model` so that the modules form a chain without cycles:
//! `effects -> retraction -> rk4`, `model -> effects`, `tmmf -> model, effects, rk4`,
//! `predict -> model, tmmf, retraction` (checked by a test in `lib.rs`).

use crate::effects::Scenario;
use crate::model::{Inputs, Model};
use crate::retraction::RtConfig;
use crate::tmmf;

impl Model {
    /// Predicted fitted channel (`x` for `tmmf-release`, `y` for `rt-retraction`) [m] at `times`
    /// [s] for parameters `p`.
    pub fn predict(&self, p: &[f64], times: &[f64], inputs: &Inputs) -> Vec<f64> {
        match self.scenario {
            Scenario::TmmfRelease => tmmf::simulate(self, p, times, inputs),
            Scenario::RtRetraction => retraction(self, p, times, inputs.e0_v),
        }
    }
}

/// `rt-retraction`: builds the mechanism configuration of `model` for `p` (each effect's
/// `configure_rt`) and returns `y(t) - y(0)` [m] at `times` [s].
pub fn retraction(model: &Model, p: &[f64], times: &[f64], e0_v: f64) -> Vec<f64> {
    let mut cfg = RtConfig {
        e0_v,
        ..RtConfig::default()
    };
    for (i, e) in model.effects.iter().enumerate() {
        e.configure_rt(&p[model.range(i)], &mut cfg);
    }
    cfg.retraction(times)
}
