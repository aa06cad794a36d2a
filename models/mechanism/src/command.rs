//! The command voltage of the release (physics.md §1).

/// `E(t) = E0` for `t < 0`, `E(t) = max(0, E0 - em t)` for `t >= 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoltageCommand {
    /// Initial voltage `E0` [V] (120 V).
    pub e0_v: f64,
    /// Discharge slope `em` [V/s] (thesis: Normal(5e7, 1.02e7)); `f64::INFINITY` is the ideal step.
    pub slope_v_s: f64,
}

impl VoltageCommand {
    /// Nominal initial voltage [V].
    pub const E0_NOMINAL_V: f64 = 120.0;
    /// Nominal discharge slope [V/s].
    pub const SLOPE_NOMINAL_V_S: f64 = 5.0e7;

    /// A linear ramp from `e0_v` [V] down to 0 at `slope_v_s` [V/s].
    pub fn ramp(e0_v: f64, slope_v_s: f64) -> Self {
        Self { e0_v, slope_v_s }
    }

    /// The nominal command: 120 V, 5e7 V/s.
    pub fn nominal() -> Self {
        Self::ramp(Self::E0_NOMINAL_V, Self::SLOPE_NOMINAL_V_S)
    }

    /// Voltage [V] at time `t_s` [s].
    #[inline]
    pub fn voltage_v(&self, t_s: f64) -> f64 {
        if t_s < 0.0 {
            self.e0_v
        } else {
            (self.e0_v - self.slope_v_s * t_s).max(0.0)
        }
    }

    /// Time [s] at which the voltage reaches 0.
    pub fn ramp_end_s(&self) -> f64 {
        self.e0_v / self.slope_v_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_reaches_zero() {
        let c = VoltageCommand::nominal();
        assert_eq!(c.voltage_v(-1.0), 120.0);
        assert!((c.ramp_end_s() - 2.4e-6).abs() < 1e-18);
        assert_eq!(c.voltage_v(1e-5), 0.0);
        assert!((c.voltage_v(1.2e-6) - 60.0).abs() < 1e-9);
        let step = VoltageCommand::ramp(120.0, f64::INFINITY);
        assert_eq!(step.voltage_v(1e-12), 0.0);
        assert_eq!(step.ramp_end_s(), 0.0);
    }
}
