//! Free drift of the TM between release and the start of control (thesis ch. 7, release
//! timeline: "t = 15 s: start of observation and control"): the offset reached by a TM that
//! leaves the release with a constant velocity and no force acting on it.
//!
//! Neglected (stated in the evidence): the plunger attraction, which the thesis bounds at less
//! than 0.1 um/s of extra velocity with the increased plunger retraction, and any offset of the
//! holding position itself (no model gives it).

/// Time from release to the start of observation and control (thesis ch. 7) [s].
pub const DRIFT_TIME_S: f64 = 15.0;

/// Offset after free drift, `|x0 + v t|` [m], from the initial offset `x0_m` [m], the velocity
/// `v_m_s` [m/s] and the drift time `t_s` [s].
///
/// ```
/// use geodesic_capture::{drift_offset_m, DRIFT_TIME_S};
/// // 5 um/s for 15 s: 75 um
/// assert!((drift_offset_m(0.0, 5e-6, DRIFT_TIME_S) - 75e-6).abs() < 1e-15);
/// ```
pub fn drift_offset_m(x0_m: f64, v_m_s: f64, t_s: f64) -> f64 {
    (x0_m + v_m_s * t_s).abs()
}

/// Angle after free drift, `|th0 + w t|` [rad], from `th0_rad` [rad], `w_rad_s` [rad/s] and
/// `t_s` [s].
pub fn drift_angle_rad(th0_rad: f64, w_rad_s: f64, t_s: f64) -> f64 {
    (th0_rad + w_rad_s * t_s).abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drift_is_linear_and_signless() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-9);
        assert!(close(drift_offset_m(0.0, -2e-6, 10.0), 2e-5));
        assert!(drift_offset_m(1e-5, -1e-6, 10.0) < 1e-20);
        assert!(close(drift_angle_rad(0.0, 100e-6, 15.0), 1.5e-3));
    }
}
