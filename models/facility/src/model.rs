//! A model: a scenario and a list of effects from the catalogue, with its flat parameter vector.
//!
//! Parameters are ordered effect by effect, in the order of [`ParamSpec`]s, and named
//! `effect.param` (interface.md). [`Model::predict`] evaluates the fitted channel at the sample
//! times for a parameter vector.

use crate::effects::{Effect, ParamSpec, Role, Scenario, by_name};
use crate::profile::TipProfile;

/// Errors building a model.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ModelError {
    /// No effect of that name in the catalogue.
    #[error("unknown effect `{name}` (known for {scenario}: {known})")]
    UnknownEffect {
        /// The name given.
        name: String,
        /// The dataset's scenario.
        scenario: String,
        /// The effects of that scenario.
        known: String,
    },
    /// The effect exists but belongs to another scenario.
    #[error("effect `{name}` belongs to scenario {other}, not {scenario}")]
    WrongScenario {
        /// The effect.
        name: String,
        /// The dataset's scenario.
        scenario: String,
        /// The effect's scenario.
        other: String,
    },
    /// A model of the scenario must contain this effect.
    #[error("a {scenario} model needs the effect `{name}`")]
    MissingBase {
        /// The scenario.
        scenario: String,
        /// The missing base effect.
        name: String,
    },
}

/// Inputs of a prediction that are not fitted.
#[derive(Debug, Clone, Copy)]
pub struct Inputs {
    /// TM mock-up mass [kg] (`tmmf-release`, `known.m`).
    pub m_kg: f64,
    /// Smooth tip retraction profile driving the TM (`tmmf-release`).
    pub profile: TipProfile,
    /// Initial command voltage [V] (`rt-retraction`, `known.E0`).
    pub e0_v: f64,
}

/// A scenario with a set of effects.
#[derive(Clone)]
pub struct Model {
    /// The scenario.
    pub scenario: Scenario,
    /// The effects, without duplicates, in catalogue order.
    pub effects: Vec<&'static dyn Effect>,
    offsets: Vec<usize>,
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Model({}: {})",
            self.scenario.name(),
            self.effect_names().join(",")
        )
    }
}

impl Model {
    /// Builds a model from effect names; checks names, scenario and the scenario's base effects.
    pub fn new(scenario: Scenario, names: &[&str]) -> Result<Model, ModelError> {
        let known = || {
            crate::effects::of_scenario(scenario)
                .iter()
                .map(|e| e.name())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let effects = names
            .iter()
            .map(|n| {
                by_name(n).ok_or_else(|| ModelError::UnknownEffect {
                    name: n.to_string(),
                    scenario: scenario.name().into(),
                    known: known(),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Model::with_effects(scenario, &effects)
    }

    /// Builds a model from effects themselves, catalogue ones or not (an effect a project or a
    /// test defines, before it is registered); checks scenario and the scenario's base effects,
    /// drops duplicate names. The catalogue's effects keep the catalogue's order, after the
    /// others in the order given.
    pub fn with_effects(
        scenario: Scenario,
        effects: &[&'static dyn Effect],
    ) -> Result<Model, ModelError> {
        let mut chosen: Vec<&'static dyn Effect> = Vec::new();
        for &e in effects {
            if e.scenario() != scenario {
                return Err(ModelError::WrongScenario {
                    name: e.name().to_string(),
                    scenario: scenario.name().into(),
                    other: e.scenario().name().into(),
                });
            }
            if !chosen.iter().any(|c| c.name() == e.name()) {
                chosen.push(e);
            }
        }
        for b in scenario.base_effects() {
            if !chosen.iter().any(|c| c.name() == *b) {
                return Err(ModelError::MissingBase {
                    scenario: scenario.name().into(),
                    name: b.to_string(),
                });
            }
        }
        let order = |e: &&dyn Effect| {
            crate::effects::catalogue()
                .iter()
                .position(|c| c.name() == e.name())
        };
        chosen.sort_by_key(order);
        let mut offsets = Vec::with_capacity(chosen.len() + 1);
        let mut o = 0;
        for e in &chosen {
            offsets.push(o);
            o += e.params().len();
        }
        offsets.push(o);
        Ok(Model {
            scenario,
            effects: chosen,
            offsets,
        })
    }

    /// The delay of the record's time axis [s] under `p`: the sum of the effects'
    /// [`TimeShiftEffect::time_shift`](crate::effects::TimeShiftEffect::time_shift); `None` when
    /// no effect shifts time.
    pub fn time_shift(&self, p: &[f64]) -> Option<f64> {
        let mut any = None;
        for (i, e) in self.effects.iter().enumerate() {
            if let Role::TimeShift(s) = e.role() {
                any = Some(any.unwrap_or(0.0) + s.time_shift(&p[self.range(i)]));
            }
        }
        any
    }

    /// Whether an effect of the model shifts time (one of [`Role::TimeShift`]).
    pub fn shifts_time(&self) -> bool {
        self.effects
            .iter()
            .any(|e| matches!(e.role(), Role::TimeShift(_)))
    }

    /// The effect names, in model order.
    pub fn effect_names(&self) -> Vec<&'static str> {
        self.effects.iter().map(|e| e.name()).collect()
    }

    /// Number of parameters.
    pub fn n_params(&self) -> usize {
        *self.offsets.last().unwrap_or(&0)
    }

    /// Full parameter names `effect.param`.
    pub fn param_names(&self) -> Vec<String> {
        self.effects
            .iter()
            .flat_map(|e| {
                e.params()
                    .iter()
                    .map(move |p| format!("{}.{}", e.name(), p.name))
            })
            .collect()
    }

    /// Parameter specifications, in parameter order.
    pub fn specs(&self) -> Vec<ParamSpec> {
        self.effects
            .iter()
            .flat_map(|e| e.params().iter().copied())
            .collect()
    }

    /// Nominal parameter vector.
    pub fn nominal(&self) -> Vec<f64> {
        self.specs().iter().map(|s| s.nominal).collect()
    }

    /// Index of a full parameter name.
    pub fn index(&self, full: &str) -> Option<usize> {
        // `effect.param` compared in its two parts, without forming every name: the models
        // look their parameters up by name at each evaluation
        let (effect, param) = full.split_once('.')?;
        let mut i = 0;
        for e in &self.effects {
            let ps = e.params();
            if e.name() == effect {
                return ps.iter().position(|p| p.name == param).map(|k| i + k);
            }
            i += ps.len();
        }
        None
    }

    /// Range of effect `i`'s parameters in the flat vector.
    pub fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }

    /// Whether the model contains the named effect.
    pub fn has(&self, name: &str) -> bool {
        self.effects.iter().any(|e| e.name() == name)
    }

    /// Indices of parameters made unidentifiable by another effect of the model (held fixed).
    pub fn superseded(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self
            .effects
            .iter()
            .flat_map(|e| e.supersedes().iter())
            .filter_map(|n| self.index(n))
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Value of a full parameter name in `p`, if the model has it.
    pub fn get(&self, p: &[f64], full: &str) -> Option<f64> {
        self.index(full).map(|i| p[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `index` finds each parameter where `param_names` lists it, and nothing for a name that
    /// is not the model's (another effect's, a misspelt or dotless one).
    #[test]
    fn index_is_the_position_in_the_names() {
        let m = Model::new(
            Scenario::TmmfRelease,
            &[
                "needle_contact",
                "tip_contact",
                "tip_adhesion",
                "needle_mass",
                "drift",
            ],
        )
        .unwrap();
        for (i, n) in m.param_names().iter().enumerate() {
            assert_eq!(m.index(n), Some(i), "{n}");
        }
        for n in [
            "needle_adhesion.A1",
            "tip_adhesion.a1",
            "tip_adhesion",
            "A1",
            "",
            ".",
            "tip_adhesion.A1.x",
        ] {
            assert_eq!(m.index(n), None, "{n}");
        }
    }

    #[test]
    fn builds_and_names_parameters() {
        let m = Model::new(
            Scenario::TmmfRelease,
            &["tip_adhesion", "needle_contact", "tip_contact"],
        )
        .unwrap();
        assert_eq!(
            m.effect_names(),
            ["needle_contact", "tip_contact", "tip_adhesion"]
        );
        assert_eq!(m.param_names()[4], "tip_adhesion.lambda");
        assert_eq!(m.n_params(), 5);
        assert!(matches!(
            Model::new(Scenario::TmmfRelease, &["piezo"]),
            Err(ModelError::WrongScenario { .. })
        ));
        assert!(matches!(
            Model::new(Scenario::TmmfRelease, &["glue"]),
            Err(ModelError::UnknownEffect { .. })
        ));
        assert!(matches!(
            Model::new(Scenario::TmmfRelease, &["tip_contact"]),
            Err(ModelError::MissingBase { .. })
        ));
        let nm = Model::new(
            Scenario::TmmfRelease,
            &["needle_contact", "tip_contact", "needle_mass"],
        )
        .unwrap();
        assert_eq!(nm.superseded(), vec![0]);
    }
}
