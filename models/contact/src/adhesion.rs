//! The exponential adhesion law of thesis ch. 5 (eq. F_adh), physics.md §2.

/// `F = A1 * e * exp(-e / lambda)` for `e > 0` [N].
///
/// Peak pull-off `A1 * lambda / e_Euler` at `e = lambda`; bond energy `dU = A1 * lambda^2`
/// (thesis ch. 6). Experimental bounds (thesis): `A1` in [0, 1.5e5] N/m, `lambda` in [0, 8e-7] m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExponentialAdhesion {
    /// Bond stiffness `A1` [N/m].
    pub a1_n_m: f64,
    /// Bond elongation scale `lambda` [m].
    pub lambda_m: f64,
}

impl ExponentialAdhesion {
    /// Upper experimental bound of `A1` [N/m].
    pub const A1_MAX_N_M: f64 = 1.5e5;
    /// Upper experimental bound of `lambda` [m].
    pub const LAMBDA_MAX_M: f64 = 8.0e-7;

    /// A bond of stiffness `a1_n_m` [N/m] and length `lambda_m` [m].
    pub fn new(a1_n_m: f64, lambda_m: f64) -> Self {
        Self { a1_n_m, lambda_m }
    }

    /// No adhesion.
    pub fn none() -> Self {
        Self::new(0.0, 0.0)
    }

    /// Whether the bond exerts any force.
    pub fn is_active(&self) -> bool {
        self.a1_n_m > 0.0 && self.lambda_m > 0.0
    }

    /// Pulling force [N] at elongation `e_m > 0` [m].
    #[inline]
    pub fn force_n(&self, e_m: f64) -> f64 {
        if e_m <= 0.0 || self.lambda_m <= 0.0 {
            0.0
        } else {
            self.a1_n_m * e_m * (-e_m / self.lambda_m).exp()
        }
    }

    /// Peak pull-off force [N]: `A1 lambda / e_Euler`, reached at `e = lambda`.
    pub fn peak_pull_off_n(&self) -> f64 {
        self.a1_n_m * self.lambda_m / std::f64::consts::E
    }

    /// Bond energy [J]: `dU = A1 lambda^2` (thesis ch. 6).
    pub fn bond_energy_j(&self) -> f64 {
        self.a1_n_m * self.lambda_m * self.lambda_m
    }

    /// Momentum [N s] the bond gives a body pulled by a tip retracting at constant `v_tip_m_s`
    /// [m/s] from a stiff contact: `int F dt = dU / v_tip` (TMMF estimate, thesis ch. 5).
    pub fn momentum_at_tip_speed_ns(&self, v_tip_m_s: f64) -> f64 {
        self.bond_energy_j() / v_tip_m_s
    }

    /// Fraction of the bond energy left beyond `e_m` [m]: `(1 + e/lambda) exp(-e/lambda)`.
    pub fn remaining_fraction(&self, e_m: f64) -> f64 {
        if !self.is_active() {
            return 0.0;
        }
        if e_m <= 0.0 {
            return 1.0;
        }
        let x = e_m / self.lambda_m;
        (1.0 + x) * (-x).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn peak_is_at_lambda() {
        let a = ExponentialAdhesion::new(1.5e5, 8e-7);
        assert_relative_eq!(a.force_n(8e-7), a.peak_pull_off_n(), max_relative = 1e-12);
        assert!(a.force_n(7.9e-7) < a.peak_pull_off_n());
        assert!(a.force_n(8.1e-7) < a.peak_pull_off_n());
        // the experimental corner: 44 mN
        assert_relative_eq!(a.peak_pull_off_n(), 0.04415, max_relative = 1e-3);
    }

    #[test]
    fn bond_energy_is_the_integral() {
        let a = ExponentialAdhesion::new(1.0e5, 5e-7);
        let n = 200_000;
        let de = 40.0 * a.lambda_m / n as f64;
        let num: f64 = (0..n).map(|i| a.force_n((i as f64 + 0.5) * de) * de).sum();
        assert_relative_eq!(num, a.bond_energy_j(), max_relative = 1e-6);
    }

    #[test]
    fn twelve_lambda_leaves_less_than_1e4() {
        let a = ExponentialAdhesion::new(1.0e5, 5e-7);
        let f = a.remaining_fraction(12.0 * a.lambda_m);
        assert!(f < 1e-4 && f > 5e-5, "{f}");
        assert_eq!(a.remaining_fraction(-1.0), 1.0);
    }
}
