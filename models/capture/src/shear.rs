//! The shear illustration at the end of thesis ch. 6 (physics.md section 6): the angular and
//! linear velocity a tangential pull at the contact patch would give the TM.
//!
//! Thesis formulas: `dw = dt F a / (2 I)` and `dv = dt F / (2 M)`, with `dt = 1e-4 s`,
//! `F = 0.05 N` (the adhesion peak), `a = 0.046 m`, `I = 7.06e-4 kg m^2`, `M = 1.96 kg`.
//! The thesis prints 330 urad/s and 2.5 um/s, which match the formulas *without* the factor
//! 1/2 (326 urad/s, 2.55 um/s); with it they give 163 urad/s and 1.28 um/s. The factor 1/2 is
//! the impulse of a triangular force pulse of peak `F` (the same as the thesis's rough
//! estimate `P = F_peak dt / 2` in ch. 6); without it the pulse is rectangular, an upper bound.
//! Both are computed; [`PulseShape::USED`] says which one the verification uses and why.

/// Shape of the tangential force pulse, fixing the impulse `J = factor * F * dt`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PulseShape {
    /// Triangular pulse of peak `F`: factor 1/2 (the thesis's formula as printed).
    Triangular,
    /// Rectangular pulse of height `F`: factor 1 (matches the thesis's printed numbers).
    Rectangular,
}

impl PulseShape {
    /// The shape the verification uses: rectangular (no factor 1/2). It is the upper bound of
    /// the two, it reproduces the numbers the thesis prints (330 urad/s, 2.5 um/s), and both
    /// shapes give the same verdicts against the TM state requirement (rate above 100 urad/s,
    /// velocity below 5 um/s).
    pub const USED: PulseShape = PulseShape::Rectangular;

    /// Impulse factor (1/2 or 1) [-].
    pub const fn factor(self) -> f64 {
        match self {
            PulseShape::Triangular => 0.5,
            PulseShape::Rectangular => 1.0,
        }
    }

    /// Short name for reports (`triangular`, `rectangular`).
    pub const fn as_str(self) -> &'static str {
        match self {
            PulseShape::Triangular => "triangular (factor 1/2)",
            PulseShape::Rectangular => "rectangular (no factor 1/2)",
        }
    }
}

/// Inputs of the shear illustration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShearInputs {
    /// Pulse duration `dt` [s].
    pub dt_s: f64,
    /// Tangential force `F` [N].
    pub force_n: f64,
    /// Lever arm `a` [m] (the thesis uses 0.046 m, the TM side).
    pub arm_m: f64,
    /// TM moment of inertia `I` [kg m^2].
    pub inertia_kg_m2: f64,
    /// TM mass `M` [kg].
    pub mass_kg: f64,
}

impl ShearInputs {
    /// The thesis's values (end of ch. 6).
    pub const THESIS: ShearInputs = ShearInputs {
        dt_s: 1e-4,
        force_n: 0.05,
        arm_m: 0.046,
        inertia_kg_m2: 7.06e-4,
        mass_kg: 1.96,
    };

    /// Angular rate after the pulse, `dw = factor dt F a / I` [rad/s].
    pub fn angular_rate_rad_s(&self, shape: PulseShape) -> f64 {
        shape.factor() * self.dt_s * self.force_n * self.arm_m / self.inertia_kg_m2
    }

    /// Linear velocity after the pulse, `dv = factor dt F / M` [m/s].
    pub fn velocity_m_s(&self, shape: PulseShape) -> f64 {
        shape.factor() * self.dt_s * self.force_n / self.mass_kg
    }
}

/// The numbers the thesis prints for the illustration: 330 urad/s [rad/s].
pub const THESIS_PRINTED_RATE_RAD_S: f64 = 330e-6;
/// The numbers the thesis prints for the illustration: 2.5 um/s [m/s].
pub const THESIS_PRINTED_VELOCITY_M_S: f64 = 2.5e-6;

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn with_factor_half() {
        let s = ShearInputs::THESIS;
        // 1e-4 * 0.05 * 0.046 / (2 * 7.06e-4) = 1.6289e-4 rad/s
        assert_relative_eq!(
            s.angular_rate_rad_s(PulseShape::Triangular),
            1.628_895e-4,
            max_relative = 1e-6
        );
        // 1e-4 * 0.05 / (2 * 1.96) = 1.2755e-6 m/s
        assert_relative_eq!(
            s.velocity_m_s(PulseShape::Triangular),
            1.275_510e-6,
            max_relative = 1e-6
        );
    }

    #[test]
    fn printed_numbers_match_the_formula_without_the_half() {
        let s = ShearInputs::THESIS;
        let w = s.angular_rate_rad_s(PulseShape::Rectangular);
        let v = s.velocity_m_s(PulseShape::Rectangular);
        // the thesis rounds to 2 significant figures
        assert!(
            (w - THESIS_PRINTED_RATE_RAD_S).abs() / THESIS_PRINTED_RATE_RAD_S < 0.02,
            "{w}"
        );
        assert!(
            (v - THESIS_PRINTED_VELOCITY_M_S).abs() / THESIS_PRINTED_VELOCITY_M_S < 0.03,
            "{v}"
        );
        // and do not match the formula with it
        let w2 = s.angular_rate_rad_s(PulseShape::Triangular);
        assert!((w2 - THESIS_PRINTED_RATE_RAD_S).abs() / THESIS_PRINTED_RATE_RAD_S > 0.4);
    }
}
