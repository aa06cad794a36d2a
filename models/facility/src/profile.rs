//! The smooth tip-retraction profile of the TMMF release (examples README, physics.md section 4).
//!
//! The measured tip displacement `y` is noisy; driving the contact forces with it turns tip noise
//! times `k_c` into a random force of several mN. The model is therefore driven by a smooth
//! profile fitted to `y` first: constant jerk `j` from rest up to the speed `v` (reached at
//! `t1 = sqrt(2 v / j)`), then constant speed. `y = 0` for `t <= 0`.

/// Constant-jerk-then-constant-speed tip retraction.
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct TipProfile {
    /// Jerk of the first phase [m/s^3].
    pub jerk_m_s3: f64,
    /// Final constant speed [m/s].
    pub v_m_s: f64,
}

impl TipProfile {
    /// End of the constant-jerk phase `t1 = sqrt(2 v / j)` [s].
    pub fn t1_s(&self) -> f64 {
        (2.0 * self.v_m_s / self.jerk_m_s3).sqrt()
    }

    /// Tip speed `y'(t)` [m/s] at time `t` [s] from the trigger (never decreasing for `t > 0`).
    pub fn speed(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        if t < self.t1_s() {
            0.5 * self.jerk_m_s3 * t * t
        } else {
            self.v_m_s
        }
    }

    /// Tip displacement `y(t)` [m] at time `t` [s] from the trigger.
    pub fn y(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        let t1 = self.t1_s();
        if t < t1 {
            self.jerk_m_s3 * t * t * t / 6.0
        } else {
            self.jerk_m_s3 * t1 * t1 * t1 / 6.0 + self.v_m_s * (t - t1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_is_continuous_at_t1() {
        let p = TipProfile {
            jerk_m_s3: 6000.0,
            v_m_s: 3e-3,
        };
        let t1 = p.t1_s();
        assert!((t1 - 1e-3).abs() < 1e-12);
        let a = p.y(t1 * (1.0 - 1e-9));
        let b = p.y(t1 * (1.0 + 1e-9));
        assert!((a - b).abs() < 1e-14, "{a} {b}");
        assert_eq!(p.y(-1.0), 0.0);
    }
}
