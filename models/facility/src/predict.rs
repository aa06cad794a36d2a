//! Prediction of a model's fitted channel: the dispatch from a [`Model`] to its scenario's
//! simulation. Kept apart from `model` so that the modules form a chain without cycles:
//! `effects -> retraction -> rk4`, `model -> effects`, `tmmf -> model, effects, rk4`,
//! `predict -> model, tmmf, retraction` (checked by a test in `lib.rs`).

use crate::effects::Role;
use crate::model::{Inputs, Model};
use crate::retraction::RtConfig;
use crate::scenario::Dynamics;
use crate::tmmf;

impl Model {
    /// Predicted fitted channel (`x` for `tmmf-release`, `y` for `rt-retraction`) [m] at `times`
    /// [s] for parameters `p`.
    pub fn predict(&self, p: &[f64], times: &[f64], inputs: &Inputs) -> Vec<f64> {
        if let Some(d) = self.time_shift(p) {
            // an effect delays the record's time axis: the model at `t - d` (issue 36)
            let shifted: Vec<f64> = times.iter().map(|t| t - d).collect();
            return self.predict_unshifted(p, &shifted, inputs);
        }
        self.predict_unshifted(p, times, inputs)
    }

    /// [`Model::predict`] without the effects' time shift.
    fn predict_unshifted(&self, p: &[f64], times: &[f64], inputs: &Inputs) -> Vec<f64> {
        match self.scenario.dynamics() {
            Dynamics::TmRelease => tmmf::simulate(self, p, times, inputs),
            Dynamics::TipMechanism => retraction(self, p, times, inputs.e0_v),
        }
    }

    /// [`Model::predict`] at each parameter vector of `ps`, in order, with the same bits;
    /// `tmmf-release` models whose forces are all [`ForceLaw`](crate::effects::ForceLaw)s
    /// integrate up to [`Model::lanes`] of them in lockstep in this thread
    /// ([`tmmf::simulate_many`]); otherwise one after the other.
    pub fn predict_many(&self, ps: &[Vec<f64>], times: &[f64], inputs: &Inputs) -> Vec<Vec<f64>> {
        match self.scenario.dynamics() {
            Dynamics::TmRelease if self.lanes() > 1 && !self.shifts_time() => {
                tmmf::simulate_many(self, ps, times, inputs)
            }
            Dynamics::TipMechanism if self.lanes() > 1 => {
                retraction_many(self, ps, times, inputs.e0_v)
            }
            _ => ps.iter().map(|p| self.predict(p, times, inputs)).collect(),
        }
    }

    /// [`Model::predict_many`] over `ps` in as few groups as the lanes allow, of balanced sizes
    /// (five parameter vectors in lanes of four: three and two), the groups spread over the
    /// thread pool; in order, each the bits of [`Model::predict`] at it.
    pub fn predict_in_lanes(
        &self,
        ps: &[Vec<f64>],
        times: &[f64],
        inputs: &Inputs,
    ) -> Vec<Vec<f64>> {
        use rayon::prelude::*;
        let lanes = self.lanes().max(1);
        let groups = ps.len().div_ceil(lanes).max(1);
        let size = ps.len().div_ceil(groups).max(1);
        ps.par_chunks(size)
            .flat_map_iter(|c| self.predict_many(c, times, inputs))
            .collect()
    }

    /// The mean of [`Model::predict`] over each group of `k` consecutive times of `fine` (the
    /// sub-samples of a sampled record, `geodesic synth --oversample`): a TM release without a
    /// time shift is integrated with its contact step divided by `k`
    /// ([`tmmf::simulate_with_step`]), the others predicted at each sub-sample.
    pub fn predict_subsampled(
        &self,
        p: &[f64],
        fine: &[f64],
        inputs: &Inputs,
        k: usize,
    ) -> Vec<f64> {
        let k = k.max(1);
        let v = if self.scenario.dynamics() == Dynamics::TmRelease && !self.shifts_time() {
            let h = tmmf::step_for_mass(inputs.m_kg) / k as f64;
            tmmf::simulate_with_step(self, p, fine, inputs, h)
        } else {
            self.predict(p, fine, inputs)
        };
        v.chunks(k)
            .map(|c| c.iter().sum::<f64>() / k as f64)
            .collect()
    }

    /// [`Model::predict`] and its derivatives with respect to the parameters `p[dirs[j]]`
    /// (forward sensitivities: [`tmmf::simulate_with_tangents`]), for the models
    /// [`Model::has_tangents`] covers; `None` for the others.
    pub fn predict_with_tangents(
        &self,
        p: &[f64],
        dirs: &[usize],
        times: &[f64],
        inputs: &Inputs,
    ) -> Option<(Vec<f64>, Vec<Vec<f64>>)> {
        tmmf::simulate_with_tangents(self, p, dirs, times, inputs)
    }

    /// The derivatives of [`Model::predict_with_tangents`] alone, the same bits, without the
    /// free-flight tail's readings (a Jacobian needs none: [`tmmf::tangents_only`]); `None`
    /// for the models [`Model::has_tangents`] does not cover.
    pub fn tangents(
        &self,
        p: &[f64],
        dirs: &[usize],
        times: &[f64],
        inputs: &Inputs,
    ) -> Option<Vec<Vec<f64>>> {
        tmmf::tangents_only(self, p, dirs, times, inputs)
    }

    /// Whether [`Model::predict_with_tangents`] gives the derivatives with respect to
    /// `n_dirs` parameters: a `tmmf-release` model whose forces are the needles' and the tip's
    /// springs and the tip adhesion, without distortions (the others keep finite differences).
    pub fn has_tangents(&self, n_dirs: usize) -> bool {
        !self.shifts_time() && tmmf::tangents_cover(self, n_dirs)
    }

    /// How many evaluations [`Model::predict_many`] interleaves in one thread: [`tmmf::LANES`]
    /// for a `tmmf-release` model whose forces all have a law, else 1 (a caller then gains
    /// nothing from grouping evaluations and should spread them over threads).
    pub fn lanes(&self) -> usize {
        // every force a law, and at most one needle body's two states (tmmf::Run::new)
        let states: usize = self
            .effects
            .iter()
            .map(|e| match e.role() {
                Role::Force(f) => f.n_states(),
                _ => 0,
            })
            .sum();
        let laws = self.scenario.dynamics() == Dynamics::TmRelease
            && (states == 0 || states == 2)
            && self.effects.iter().all(|e| match e.role() {
                Role::Force(f) => {
                    let nominal: Vec<f64> = e.params().iter().map(|s| s.nominal).collect();
                    f.law(&nominal).is_some()
                }
                Role::Distortion(_) | Role::TimeShift(_) => true,
                Role::Mechanism(_) => false,
            });
        if laws && !self.shifts_time() {
            tmmf::LANES
        } else if self.scenario.dynamics() == Dynamics::TipMechanism && !self.shifts_time() {
            crate::retraction::LANES
        } else {
            1
        }
    }
}

/// `rt-retraction`: builds the mechanism configuration of `model` for `p` (each effect's
/// `configure_rt`) and returns `y(t) - y(0)` [m] at `times` [s], with the distortions of the
/// reading added (an effect of kind `Distortion` of this scenario, e.g. one written by
/// `discover --scaffold`, issue 36).
pub fn retraction(model: &Model, p: &[f64], times: &[f64], e0_v: f64) -> Vec<f64> {
    let mut y = rt_config(model, p, e0_v).retraction(times);
    add_distortions(model, p, times, &mut y);
    y
}

/// [`retraction`] at each parameter vector of `ps`: the same readings, bit for bit, with the
/// mechanism's tails computed side by side ([`RtConfig::retraction_many`]).
pub fn retraction_many(model: &Model, ps: &[Vec<f64>], times: &[f64], e0_v: f64) -> Vec<Vec<f64>> {
    let cfgs: Vec<RtConfig> = ps.iter().map(|p| rt_config(model, p, e0_v)).collect();
    let mut ys = RtConfig::retraction_many(&cfgs, times);
    for (y, p) in ys.iter_mut().zip(ps) {
        add_distortions(model, p, times, y);
    }
    ys
}

/// The mechanism configuration of `model` at `p` (each effect's `configure_rt`).
fn rt_config(model: &Model, p: &[f64], e0_v: f64) -> RtConfig {
    let mut cfg = RtConfig {
        e0_v,
        ..RtConfig::default()
    };
    for (i, e) in model.effects.iter().enumerate() {
        if let Role::Mechanism(m) = e.role() {
            m.configure_rt(&p[model.range(i)], &mut cfg);
        }
    }
    cfg
}

/// The distortions of the reading (effects of kind `Distortion`) added to `y` at `times`.
fn add_distortions(model: &Model, p: &[f64], times: &[f64], y: &mut [f64]) {
    for (i, e) in model.effects.iter().enumerate() {
        if let Role::Distortion(d) = e.role() {
            let pe = &p[model.range(i)];
            for (yi, &t) in y.iter_mut().zip(times) {
                *yi += d.distortion(pe, t, *yi);
            }
        }
    }
}
