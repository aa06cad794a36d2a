//! `voltage_ramp`: the finite slope of the command-voltage drop (physics.md section 1).

use super::{Effect, FitHints, GuessContext, MechanismEffect, ParamSpec, Role, Scenario};
use crate::retraction::RtConfig;

/// Replaces the ideal step by `E(t) = max(0, E0 - em*t)` for `t >= 0` (thesis:
/// `em ~ Normal(5e7, 1.02e7)` V/s).
#[derive(Debug, Clone, Copy)]
pub struct VoltageRamp;

static PARAMS: [ParamSpec; 1] = [ParamSpec::log("em", "V/s", 5e7, 1e5, 1e11)];

impl Effect for VoltageRamp {
    fn name(&self) -> &'static str {
        "voltage_ramp"
    }
    fn scenario(&self) -> Scenario {
        Scenario::RtRetraction
    }
    fn summary(&self) -> &'static str {
        "command voltage E(t) = max(0, E0 - em*t) instead of the ideal step (physics.md s.1)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        &PARAMS
    }
    fn role(&self) -> Role<'_> {
        Role::Mechanism(self)
    }
    fn hints(&self) -> &dyn FitHints {
        self
    }
}

impl MechanismEffect for VoltageRamp {
    fn configure_rt(&self, p: &[f64], rt: &mut RtConfig) {
        rt.em_v_s = Some(p[0]);
    }
}

impl FitHints for VoltageRamp {
    fn null_params(&self) -> Option<Vec<f64>> {
        // a ramp of 1.2 ns from 120 V: the ideal step
        Some(vec![PARAMS[0].upper])
    }
    fn starts(&self, g: &GuessContext) -> Vec<Vec<f64>> {
        let _ = g;
        vec![vec![1e7], vec![5e7], vec![3e8]]
    }
}
