//! `plunger_compliance`: the compliant plunger of the release mechanism (physics.md section 1).

use super::{Effect, FitHints, GuessContext, MechanismEffect, ParamSpec, Role, Scenario};
use crate::retraction::RtConfig;

/// Plunger of mass `Mg` on the stiffness `Kg` (physics.md fixes the thesis's `Kg*l'` typo):
/// `Mg*l'' + Kg*l - b*(y' - l') - (k + T^2/Ca)*(y - l) + (T/Ca)*q = 0`. Bounded to physical
/// ranges (examples README pitfall).
#[derive(Debug, Clone, Copy)]
pub struct PlungerCompliance;

static PARAMS: [ParamSpec; 2] = [
    ParamSpec::log("Mg", "kg", 0.019, 1e-4, 1.0),
    ParamSpec::log("Kg", "N/m", 2.15e6, 1e4, 1e9),
];

impl Effect for PlungerCompliance {
    fn name(&self) -> &'static str {
        "plunger_compliance"
    }
    fn scenario(&self) -> Scenario {
        Scenario::RtRetraction
    }
    fn summary(&self) -> &'static str {
        "plunger mass Mg on stiffness Kg under the piezo stack (physics.md s.1)"
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

impl MechanismEffect for PlungerCompliance {
    fn configure_rt(&self, p: &[f64], rt: &mut RtConfig) {
        rt.plunger = Some((p[0], p[1]));
    }
}

impl FitHints for PlungerCompliance {
    fn null_params(&self) -> Option<Vec<f64>> {
        // a light, stiff plunger: l = 0
        Some(vec![PARAMS[0].lower, PARAMS[1].upper])
    }
    fn starts(&self, _g: &GuessContext) -> Vec<Vec<f64>> {
        let mut v = Vec::new();
        for mg in [0.005, 0.019, 0.08] {
            for kg in [5e5, 2.15e6, 1e7] {
                v.push(vec![mg, kg]);
            }
        }
        v
    }
}
