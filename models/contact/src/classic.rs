//! JKR and DMT adhesion theories for a sphere on a plane (thesis ch. 4, "Basic theories").
//!
//! Reference formulas used to compare with the thesis figures; the in-flight simulator uses the
//! semi-empirical exponential law ([`crate::ExponentialAdhesion`]).

use std::f64::consts::PI;

/// JKR pull-off force [N]: `1.5 pi gamma R` for surface energy `gamma_j_m2` [J/m^2] and sphere
/// radius `radius_m` [m] (thesis ch. 4; 0.132 N for 2.8 J/m^2 and 10 mm, the thesis prints 0.135 N).
pub fn jkr_pull_off_n(gamma_j_m2: f64, radius_m: f64) -> f64 {
    1.5 * PI * gamma_j_m2 * radius_m
}

/// DMT pull-off force [N]: `2 pi gamma R` (thesis ch. 4 eq. F_c = -2 pi gamma R).
pub fn dmt_pull_off_n(gamma_j_m2: f64, radius_m: f64) -> f64 {
    2.0 * PI * gamma_j_m2 * radius_m
}

/// JKR load [N] and penetration [m] at contact radius `a_m` [m] (thesis ch. 4, JKR):
/// `F = 4 E* a^3 / (3R) - sqrt(8 pi gamma E* a^3)`, `delta = a^2/R - sqrt(2 pi a gamma / E*)`.
/// Returns `(force_n, delta_m)`; the force is compressive when positive.
pub fn jkr_force_n(a_m: f64, gamma_j_m2: f64, e_star_pa: f64, radius_m: f64) -> (f64, f64) {
    let a3 = a_m * a_m * a_m;
    let f =
        4.0 * e_star_pa * a3 / (3.0 * radius_m) - (8.0 * PI * gamma_j_m2 * e_star_pa * a3).sqrt();
    let delta = a_m * a_m / radius_m - (2.0 * PI * a_m * gamma_j_m2 / e_star_pa).sqrt();
    (f, delta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jkr_curve_minimum_is_pull_off() {
        // minimum of F(a) over a is -1.5 pi gamma R (load-controlled pull-off)
        let (g, es, r) = (2.8, 59e9, 0.01);
        let fmin = (1..20_000)
            .map(|i| jkr_force_n(i as f64 * 1e-8, g, es, r).0)
            .fold(f64::INFINITY, f64::min);
        assert!(
            (fmin + jkr_pull_off_n(g, r)).abs() / jkr_pull_off_n(g, r) < 1e-4,
            "{fmin}"
        );
    }
}
