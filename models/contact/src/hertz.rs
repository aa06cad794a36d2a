//! Hertz contact of a sphere on a plane (thesis ch. 6 "Lesson learned", physics.md §2).

/// Hertz sphere-on-plane contact.
///
/// `F = (4/3) * Es * sqrt(R) * d^(3/2)` for an indentation `d >= 0` [m], contact radius
/// `a = (3 F R / (4 Es))^(1/3)` (thesis, Maugis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    /// Effective elastic modulus `E*` [Pa] (thesis JKR example: 59 GPa).
    pub e_star_pa: f64,
    /// Tip radius of curvature [m] (nominal 10 mm).
    pub radius_m: f64,
}

impl Hertz {
    /// Effective modulus of the thesis JKR example [Pa].
    pub const E_STAR_NOMINAL_PA: f64 = 59.0e9;
    /// Nominal tip radius [m].
    pub const RADIUS_NOMINAL_M: f64 = 0.010;

    /// A Hertz contact with modulus `e_star_pa` [Pa] and radius `radius_m` [m].
    pub fn new(e_star_pa: f64, radius_m: f64) -> Self {
        Self {
            e_star_pa,
            radius_m,
        }
    }

    /// Nominal contact: 59 GPa, 10 mm.
    pub fn nominal() -> Self {
        Self::new(Self::E_STAR_NOMINAL_PA, Self::RADIUS_NOMINAL_M)
    }

    /// Stiffness coefficient `(4/3) Es sqrt(R)` [N/m^1.5].
    #[inline]
    pub fn coefficient(&self) -> f64 {
        4.0 / 3.0 * self.e_star_pa * self.radius_m.sqrt()
    }

    /// Compressive force [N] at indentation `d_m` [m] (0 for `d_m <= 0`).
    #[inline]
    pub fn force_n(&self, d_m: f64) -> f64 {
        if d_m <= 0.0 {
            0.0
        } else {
            self.coefficient() * d_m * d_m.sqrt()
        }
    }

    /// Indentation [m] under a compressive force `f_n` [N].
    pub fn indentation_m(&self, f_n: f64) -> f64 {
        if f_n <= 0.0 {
            0.0
        } else {
            (f_n / self.coefficient()).powf(2.0 / 3.0)
        }
    }

    /// Contact radius [m] under force `f_n` [N]: `a = (3 F R / (4 Es))^(1/3)`.
    pub fn contact_radius_m(&self, f_n: f64) -> f64 {
        (3.0 * f_n.max(0.0) * self.radius_m / (4.0 * self.e_star_pa)).cbrt()
    }

    /// Contact stiffness `dF/dd` [N/m] under force `f_n` [N]: `2 Es a`.
    pub fn stiffness_n_m(&self, f_n: f64) -> f64 {
        2.0 * self.e_star_pa * self.contact_radius_m(f_n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn indentation_inverts_force() {
        let h = Hertz::nominal();
        let d = h.indentation_m(0.3);
        assert_relative_eq!(h.force_n(d), 0.3, max_relative = 1e-12);
        // 0.3 N on 10 mm, 59 GPa: about 113 nm
        assert!(d > 1.1e-7 && d < 1.15e-7, "{d}");
    }

    #[test]
    fn contact_radius_matches_indentation() {
        // Hertz: a^2 = R d
        let h = Hertz::nominal();
        let d = h.indentation_m(0.3);
        assert_relative_eq!(
            h.contact_radius_m(0.3).powi(2),
            h.radius_m * d,
            max_relative = 1e-12
        );
    }

    #[test]
    fn stiffness_is_derivative() {
        let h = Hertz::nominal();
        let d = h.indentation_m(0.3);
        let dd = d * 1e-6;
        let num = (h.force_n(d + dd) - h.force_n(d - dd)) / (2.0 * dd);
        assert_relative_eq!(num, h.stiffness_n_m(0.3), max_relative = 1e-6);
        // about 4e6 N/m, the figure quoted in the project brief
        assert!(num > 3.5e6 && num < 4.5e6, "{num}");
    }
}
