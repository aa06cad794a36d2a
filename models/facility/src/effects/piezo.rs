//! `piezo`: the release tip on a rigid plunger driven by an ideal voltage step (physics.md s.1).

use super::{Effect, FitHints, GuessContext, MechanismEffect, ParamSpec, Role, Scenario};
use crate::retraction::RtConfig;

/// Piezo stack (charge `q`) and tip (position `y`) of physics.md section 1 with `l = 0`:
/// `R*Ca*q' + q - T*y = Ca*E`, `m*y'' + b*y' + (k + T^2/Ca)*y - (T/Ca)*q = 0`. Starts from the
/// thesis table "Example of estimated model parameters".
#[derive(Debug, Clone, Copy)]
pub struct Piezo;

static PARAMS: [ParamSpec; 6] = [
    ParamSpec::log("R", "ohm", 371.2, 1.0, 1e5),
    ParamSpec::log("m", "kg", 9e-4, 1e-6, 1e-1),
    ParamSpec::log("Ca", "F", 2.3e-7, 1e-10, 1e-4),
    ParamSpec::log("k", "N/m", 4.91e7, 1e5, 1e10),
    ParamSpec::log("b", "N s/m", 9.77, 1e-3, 1e5),
    ParamSpec::log("T", "C/m", 5.73, 1e-2, 1e3),
];

impl Effect for Piezo {
    fn name(&self) -> &'static str {
        "piezo"
    }
    fn scenario(&self) -> Scenario {
        Scenario::RtRetraction
    }
    fn summary(&self) -> &'static str {
        "piezo stack and tip on a rigid plunger, ideal voltage step (physics.md s.1, l = 0)"
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

impl MechanismEffect for Piezo {
    fn configure_rt(&self, p: &[f64], rt: &mut RtConfig) {
        rt.r_ohm = p[0];
        rt.m_kg = p[1];
        rt.ca_f = p[2];
        rt.k_n_m = p[3];
        rt.b_ns_m = p[4];
        rt.t_c_m = p[5];
    }
}

impl FitHints for Piezo {
    /// The thesis table, and the same scaled so that the static stroke `T*E0/k` and the
    /// electrical time `R*(Ca + T^2/k)` stay fixed while the mechanical ones move.
    fn starts(&self, _g: &GuessContext) -> Vec<Vec<f64>> {
        let nominal: Vec<f64> = PARAMS.iter().map(|p| p.nominal).collect();
        let mut v = vec![nominal.clone()];
        for s in [0.7, 1.4] {
            let mut q = nominal.clone();
            q[1] *= s;
            q[4] *= s;
            v.push(q);
        }
        v
    }
}
