//! `interferometer_cyclic`: cyclic non-linearity of the interferometer (physics.md section 4).

use super::{DistortionEffect, Effect, FitHints, GuessContext, ParamSpec, Role, Scenario};

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
    fn summary(&self) -> &'static str {
        "cyclic error sum b_n cos(2 pi n x/L) + c_n sin(2 pi n x/L), n = 1, 2 (thesis app.)"
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

impl DistortionEffect for InterferometerCyclic {
    fn distortion(&self, p: &[f64], _t: f64, x: f64) -> f64 {
        let ph = std::f64::consts::TAU * x / p[0];
        p[1] * ph.cos() + p[2] * ph.sin() + p[3] * (2.0 * ph).cos() + p[4] * (2.0 * ph).sin()
    }
    /// A fit that carries the error on the second harmonic (first harmonic below half of it) is
    /// the same function with period `L/2` on the first: prefer that form (the period is then
    /// the true cyclic period, the one compared with the laser sub-multiples).
    fn distortion_gradient(&self, p: &[f64], _t: f64, x: f64, d_p: &mut [f64]) -> Option<f64> {
        let k = std::f64::consts::TAU / p[0];
        let ph = k * x;
        let (s1, c1) = ph.sin_cos();
        let (s2, c2) = (2.0 * ph).sin_cos();
        // d distortion / d phase; the phase is 2 pi x / L
        let d_ph = -p[1] * s1 + p[2] * c1 - 2.0 * p[3] * s2 + 2.0 * p[4] * c2;
        d_p.copy_from_slice(&[-d_ph * ph / p[0], c1, s1, c2, s2]);
        Some(d_ph * k)
    }
}

impl FitHints for InterferometerCyclic {
    fn null_params(&self) -> Option<Vec<f64>> {
        Some(vec![PARAMS[0].nominal, 0.0, 0.0, 0.0, 0.0])
    }
    fn alternatives(&self, p: &[f64]) -> Vec<Vec<f64>> {
        let a1 = p[1].hypot(p[2]);
        let a2 = p[3].hypot(p[4]);
        if a2 > 2.0 * a1 && p[0] / 2.0 >= PARAMS[0].lower {
            vec![vec![p[0] / 2.0, p[3], p[4], 0.0, 0.0]]
        } else {
            Vec::new()
        }
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
    fn second_harmonic_form_is_re_expressed_with_half_the_period() {
        let p = [316.4e-9, 1e-12, 0.0, 2e-9, -1e-9];
        let alt = &InterferometerCyclic.alternatives(&p)[0];
        for x in [0.0, 3e-8, 1.7e-7, 4.4e-7] {
            let a = InterferometerCyclic.distortion(&p, 0.0, x)
                - 1e-12 * (std::f64::consts::TAU * x / p[0]).cos();
            let b = InterferometerCyclic.distortion(alt, 0.0, x);
            assert!((a - b).abs() < 1e-21, "{a} {b}");
        }
        assert!(
            InterferometerCyclic
                .alternatives(&[316.4e-9, 2e-9, 0.0, 1e-10, 0.0])
                .is_empty()
        );
    }

    #[test]
    fn periodic_in_l() {
        let p = [316.4e-9, 1e-9, 2e-9, 3e-10, -4e-10];
        let a = InterferometerCyclic.distortion(&p, 0.0, 1e-7);
        let b = InterferometerCyclic.distortion(&p, 0.0, 1e-7 + 316.4e-9);
        assert!((a - b).abs() < 1e-20);
        assert!((InterferometerCyclic.distortion(&p, 0.0, 0.0) - 1.3e-9).abs() < 1e-20);
    }
}
