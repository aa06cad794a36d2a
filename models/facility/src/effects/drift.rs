//! `drift`: slow drift of the interferometer reading (physics.md section 4, examples README).

use super::{DistortionEffect, Effect, FitHints, GuessContext, ParamSpec, Role, Scenario};

/// `p0 + p1*t + p2*t^2` with `t` in s from the trigger, added to the measured `x` over the whole
/// record.
#[derive(Debug, Clone, Copy)]
pub struct Drift;

static PARAMS: [ParamSpec; 3] = [
    ParamSpec::lin("p0", "m", 0.0, 1e-9),
    ParamSpec::lin("p1", "m/s", 0.0, 1e-6),
    ParamSpec::lin("p2", "m/s^2", 0.0, 1e-4),
];

impl Effect for Drift {
    fn name(&self) -> &'static str {
        "drift"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn summary(&self) -> &'static str {
        "measurement drift p0 + p1*t + p2*t^2 added to x (physics.md s.4)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        &PARAMS
    }
    fn role(&self) -> Role<'_> {
        Role::Distortion(self)
    }
    fn hints(&self) -> &dyn FitHints {
        self
    }
}

impl DistortionEffect for Drift {
    fn distortion(&self, p: &[f64], t: f64, _x: f64) -> f64 {
        p[0] + p[1] * t + p[2] * t * t
    }
    fn distortion_gradient(&self, _p: &[f64], t: f64, _x: f64, d_p: &mut [f64]) -> Option<f64> {
        d_p.copy_from_slice(&[1.0, t, t * t]);
        Some(0.0)
    }
}

impl FitHints for Drift {
    fn null_params(&self) -> Option<Vec<f64>> {
        Some(vec![0.0; 3])
    }
    fn starts(&self, _g: &GuessContext) -> Vec<Vec<f64>> {
        vec![vec![0.0, 0.0, 0.0]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomial_in_time() {
        assert!((Drift.distortion(&[1.0, 2.0, 3.0], 2.0, 5.0) - 17.0).abs() < 1e-12);
    }
}
