//! `interferometer_cyclic`: cyclic non-linearity of the interferometer (physics.md section 4).

use super::{Effect, EffectKind, GuessContext, ParamSpec, Scenario};

/// Laser wavelength of the TMMF interferometer [m].
pub const LASER_WAVELENGTH_M: f64 = 632.8e-9;

/// The measured `x` is distorted by `sum_n b_n*cos(2*pi*n*x/L) + c_n*sin(2*pi*n*x/L)` (two
/// harmonics), evaluated at the true `x`, with `L` near a sub-multiple of the laser wavelength
/// (thesis appendix "Post-Acquisition Removal of the Interferometer Noise").
#[derive(Debug, Clone, Copy)]
pub struct InterferometerCyclic;

static PARAMS: [ParamSpec; 5] = [
    ParamSpec::log("L", "m", LASER_WAVELENGTH_M / 2.0, 2e-8, 2e-6),
    ParamSpec::lin("b1", "m", 0.0, 1e-9),
    ParamSpec::lin("c1", "m", 0.0, 1e-9),
    ParamSpec::lin("b2", "m", 0.0, 1e-9),
    ParamSpec::lin("c2", "m", 0.0, 1e-9),
];

impl Effect for InterferometerCyclic {
    fn name(&self) -> &'static str {
        "interferometer_cyclic"
    }
    fn scenario(&self) -> Scenario {
        Scenario::TmmfRelease
    }
    fn kind(&self) -> EffectKind {
        EffectKind::Distortion
    }
    fn summary(&self) -> &'static str {
        "cyclic error sum b_n cos(2 pi n x/L) + c_n sin(2 pi n x/L), n = 1, 2 (thesis app.)"
    }
    fn null_params(&self) -> Option<Vec<f64>> {
        Some(vec![PARAMS[0].nominal, 0.0, 0.0, 0.0, 0.0])
    }
    fn params(&self) -> &'static [ParamSpec] {
        &PARAMS
    }
    fn distortion(&self, p: &[f64], _t: f64, x: f64) -> f64 {
        let ph = std::f64::consts::TAU * x / p[0];
        p[1] * ph.cos() + p[2] * ph.sin() + p[3] * (2.0 * ph).cos() + p[4] * (2.0 * ph).sin()
    }
    /// The period has many local minima: scan the sub-multiples `632.8 nm / n`, n = 1..8, with
    /// small in-phase and quadrature amplitudes, before refining.
    fn starts(&self, g: &GuessContext) -> Vec<Vec<f64>> {
        let a = (g.span_m * 1e-3).clamp(1e-11, 1e-9);
        (1..=8)
            .map(|n| vec![LASER_WAVELENGTH_M / n as f64, a, a, 0.0, 0.0])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodic_in_l() {
        let p = [316.4e-9, 1e-9, 2e-9, 3e-10, -4e-10];
        let a = InterferometerCyclic.distortion(&p, 0.0, 1e-7);
        let b = InterferometerCyclic.distortion(&p, 0.0, 1e-7 + 316.4e-9);
        assert!((a - b).abs() < 1e-20);
        assert!((InterferometerCyclic.distortion(&p, 0.0, 0.0) - 1.3e-9).abs() < 1e-20);
    }
}
