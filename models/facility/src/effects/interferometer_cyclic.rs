//! `interferometer_cyclic`: cyclic non-linearity of the interferometer (physics.md section 4).

use super::{
    DistortionEffect, Effect, FitHints, GuessContext, ParamSpec, RecordStats, Role, Scenario,
};

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
    /// A cyclic error is a small distortion of the reading: the reading stays monotone in the
    /// true position (its slope `1 + (2 pi / L) (a1 cos + 2 a2 cos)` positive, i.e.
    /// `a1 + 2 a2 < L / (2 pi)`, 50 nm at `L` = 316 nm: a larger one would fold the fringe
    /// count), and it is smaller than the motion it distorts (`a1 + a2` below half the
    /// peak-to-peak of the fitted reading). `a_n = hypot(b_n, c_n)` [m].
    fn plausible(&self, p: &[f64], r: &RecordStats) -> Result<(), String> {
        let a1 = p[1].hypot(p[2]);
        let a2 = p[3].hypot(p[4]);
        let fold = p[0] / std::f64::consts::TAU;
        if a1 + 2.0 * a2 >= fold {
            return Err(format!(
                "its amplitudes a1 {a1:.3e} m + 2 a2 {a2:.3e} m reach L / (2 pi) = {fold:.3e} m \
                 (L {:.3e} m): a reading that folds back on itself, not a cyclic error",
                p[0]
            ));
        }
        if a1 + a2 >= 0.5 * r.motion_pp_m {
            return Err(format!(
                "its amplitudes a1 {a1:.3e} m + a2 {a2:.3e} m reach half the motion it distorts \
                 (the fitted reading spans {:.3e} m peak to peak)",
                r.motion_pp_m
            ));
        }
        Ok(())
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
    fn a_cyclic_error_larger_than_the_fringe_or_the_motion_is_implausible() {
        let r = RecordStats {
            motion_pp_m: 374e-9,
            span_s: 0.02,
        };
        // issue 50: c1 = 205 nm on a TM that moves 374 nm, L = 316 nm
        let e = InterferometerCyclic
            .plausible(&[316.4e-9, 0.0, 205e-9, 0.0, 0.0], &r)
            .unwrap_err();
        assert!(e.contains("folds"), "{e}");
        // 30 nm is below L / (2 pi) = 50 nm but above half of a 50 nm motion
        let small = RecordStats {
            motion_pp_m: 50e-9,
            ..r
        };
        let e = InterferometerCyclic
            .plausible(&[316.4e-9, 30e-9, 0.0, 0.0, 0.0], &small)
            .unwrap_err();
        assert!(e.contains("half the motion"), "{e}");
        // a 1.5 nm error on a micron of motion is what the thesis measures
        let ok = RecordStats {
            motion_pp_m: 2e-6,
            ..r
        };
        assert!(
            InterferometerCyclic
                .plausible(&[316.4e-9, 1.5e-9, 0.8e-9, 0.0, 0.0], &ok)
                .is_ok()
        );
    }

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
