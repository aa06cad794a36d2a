//! Contact laws between a release tip and the test mass (TM), thesis ch. 4 and physics.md §2.
//!
//! A contact law maps the elongation `e` of one tip/TM contact [m] to the force on the TM [N]
//! (positive when it pulls the TM towards that tip). The in-flight release simulator
//! (`geodesic-release`) only sees the [`ContactLaw`] trait, so a new law is one new type here,
//! not an edit of the simulator.
//!
//! Sign convention (physics.md §2): `e < 0` is an indentation (compressive Hertz force, negative),
//! `e > 0` a stretched adhesive bond (pulling force, positive).
//!
//! ```
//! use geodesic_contact::{ContactLaw, Hertz, ExponentialAdhesion, HertzAdhesion};
//! let law = HertzAdhesion::new(Hertz::nominal(), ExponentialAdhesion::new(1.0e5, 5.0e-7));
//! let e0 = law.preload_elongation_m(0.3);            // indentation under 0.3 N preload
//! assert!((law.force_n(e0) + 0.3).abs() < 1e-12);     // Hertz pushes back with 0.3 N
//! assert!(law.force_n(5.0e-7) > 0.0);                 // the bond pulls
//! ```

mod adhesion;
mod classic;
pub mod figures;
mod hertz;

pub use adhesion::ExponentialAdhesion;
pub use classic::{dmt_pull_off_n, jkr_force_n, jkr_pull_off_n};
pub use hertz::Hertz;

/// Threshold elongation [m] used to declare a non-adhesive contact open (physics.md §3: "a few
/// nm (5 nm) without adhesion").
pub const OPEN_WITHOUT_ADHESION_M: f64 = 5.0e-9;

/// Multiple of the adhesion length `lambda` beyond which a bond counts as broken for good
/// (physics.md §3: less than 1e-4 of the bond energy remains).
pub const BROKEN_LAMBDA_MULTIPLE: f64 = 12.0;

/// A force law for one tip/TM contact.
pub trait ContactLaw: Send + Sync {
    /// Force on the TM [N] at elongation `e_m` [m]; positive pulls the TM towards the tip.
    fn force_n(&self, e_m: f64) -> f64;

    /// Elongation [m] of the contact in static equilibrium under a compressive load `load_n` [N]
    /// (negative: an indentation).
    fn preload_elongation_m(&self, load_n: f64) -> f64;

    /// Elongation [m] beyond which the contact is released for good (stopping rule, physics.md §3).
    fn open_elongation_m(&self) -> f64;

    /// Fraction of the bond energy still to be released when the contact is at `e_m` [m]
    /// (0 for a law without adhesion, 1 while compressed).
    fn remaining_bond_fraction(&self, e_m: f64) -> f64;
}

/// The contact law of physics.md §2: Hertz sphere-on-plane for `e <= 0` and the exponential
/// adhesion law (thesis eq. F_adh) for `e > 0`. The force is continuous at `e = 0`, its slope is
/// not (0 on the Hertz side, `A1` on the adhesion side): the integrator treats `e = 0` as a
/// switching event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzAdhesion {
    /// Compressive branch.
    pub hertz: Hertz,
    /// Tensile (adhesive) branch.
    pub adhesion: ExponentialAdhesion,
}

impl HertzAdhesion {
    /// Combines a Hertz branch and an adhesion branch.
    pub fn new(hertz: Hertz, adhesion: ExponentialAdhesion) -> Self {
        Self { hertz, adhesion }
    }
}

impl ContactLaw for HertzAdhesion {
    #[inline]
    fn force_n(&self, e_m: f64) -> f64 {
        if e_m <= 0.0 {
            -self.hertz.force_n(-e_m)
        } else {
            self.adhesion.force_n(e_m)
        }
    }

    fn preload_elongation_m(&self, load_n: f64) -> f64 {
        -self.hertz.indentation_m(load_n)
    }

    fn open_elongation_m(&self) -> f64 {
        if self.adhesion.is_active() {
            (BROKEN_LAMBDA_MULTIPLE * self.adhesion.lambda_m).max(OPEN_WITHOUT_ADHESION_M)
        } else {
            OPEN_WITHOUT_ADHESION_M
        }
    }

    fn remaining_bond_fraction(&self, e_m: f64) -> f64 {
        if e_m <= 0.0 {
            1.0
        } else {
            self.adhesion.remaining_fraction(e_m)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_is_continuous_at_contact() {
        let law = HertzAdhesion::new(Hertz::nominal(), ExponentialAdhesion::new(1.5e5, 8e-7));
        assert!(law.force_n(-1e-15).abs() < 1e-12);
        assert!(law.force_n(1e-15).abs() < 1e-9);
    }

    #[test]
    fn open_threshold_follows_lambda_or_5nm() {
        let adh = HertzAdhesion::new(Hertz::nominal(), ExponentialAdhesion::new(1e5, 4e-7));
        assert!((adh.open_elongation_m() - 4.8e-6).abs() < 1e-15);
        let none = HertzAdhesion::new(Hertz::nominal(), ExponentialAdhesion::none());
        assert_eq!(none.open_elongation_m(), 5e-9);
        assert_eq!(none.remaining_bond_fraction(1e-9), 0.0);
    }

    #[test]
    fn preload_elongation_balances_load() {
        let law = HertzAdhesion::new(Hertz::new(59e9, 0.0095), ExponentialAdhesion::none());
        let e0 = law.preload_elongation_m(0.32);
        assert!(e0 < 0.0);
        assert!((law.force_n(e0) + 0.32).abs() < 1e-12);
    }
}
