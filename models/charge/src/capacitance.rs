//! Capacitance `C_RT` between the release-tip spherical cap and the TM face (thesis ch. 7,
//! "Electrification of the TM during the Release"; physics.md section 7):
//!
//! `C_RT = int_0^theta_f eps0 R^2 2 pi sin(t) / (d + R - R cos(t)) dt`,
//! `theta_f = atan(r_tip / R)`, with `R` the tip radius of curvature, `r_tip = 0.4 mm` the tip
//! radius and `d` the tip-TM gap (100 nm).
//!
//! Three evaluations: adaptive Simpson quadrature ([`c_rt_quadrature_f`], the reference), the
//! exact antiderivative (`u = cos t` gives `2 pi eps0 R ln(1 + R (1 - cos theta_f) / d)`,
//! [`c_rt_exact_f`]) and the small-angle closed form (`sin t ~ t`, `1 - cos t ~ t^2/2`:
//! `2 pi eps0 R ln(1 + R theta_f^2 / (2 d))`, [`c_rt_small_angle_f`]).

/// Vacuum permittivity (CODATA 2022) [F/m].
pub const EPS0_F_M: f64 = 8.854_187_818_8e-12;

/// Geometry of the release tip facing the TM.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TipGeometry {
    /// Radius of curvature of the tip `R_RT` [m] (thesis: 10 mm).
    pub radius_m: f64,
    /// Tip (cap) radius `r_tip` [m], `theta_f = atan(r_tip / R)` (thesis: 0.4e-3 m).
    pub cap_radius_m: f64,
    /// Gap between tip and TM `d` [m] (thesis: 100 nm).
    pub gap_m: f64,
}

impl TipGeometry {
    /// The thesis's values: R = 10 mm, r_tip = 0.4 mm, d = 100 nm.
    pub const THESIS: TipGeometry = TipGeometry {
        radius_m: 10e-3,
        cap_radius_m: 0.4e-3,
        gap_m: 100e-9,
    };

    /// Cap half-angle `theta_f = atan(r_tip / R)` [rad].
    pub fn theta_f_rad(&self) -> f64 {
        (self.cap_radius_m / self.radius_m).atan()
    }

    /// Integrand of the cap integral at polar angle `t` [rad] -> [F/rad].
    /// `1 - cos t` is written `2 sin^2(t/2)` to avoid cancellation near 0.
    pub fn integrand_f_per_rad(&self, t: f64) -> f64 {
        let r = self.radius_m;
        let s = (0.5 * t).sin();
        EPS0_F_M * r * r * 2.0 * std::f64::consts::PI * t.sin() / (self.gap_m + 2.0 * r * s * s)
    }
}

/// `C_RT` by adaptive Simpson quadrature of the cap integral, relative tolerance `rel_tol` [F].
///
/// ```
/// use geodesic_charge::{c_rt_quadrature_f, TipGeometry};
/// let c = c_rt_quadrature_f(&TipGeometry::THESIS, 1e-12);
/// assert!((c * 1e12 - 2.445).abs() < 0.01); // about 2.5 pF (thesis)
/// ```
pub fn c_rt_quadrature_f(g: &TipGeometry, rel_tol: f64) -> f64 {
    let f = |t: f64| g.integrand_f_per_rad(t);
    let b = g.theta_f_rad();
    // Scale of the result for an absolute tolerance: the small-angle value.
    let scale = c_rt_small_angle_f(g).abs().max(f64::MIN_POSITIVE);
    adaptive_simpson(&f, 0.0, b, rel_tol * scale, 60)
}

/// `C_RT` from the exact antiderivative: `2 pi eps0 R ln(1 + R (1 - cos theta_f) / d)` [F].
pub fn c_rt_exact_f(g: &TipGeometry) -> f64 {
    let r = g.radius_m;
    let s = (0.5 * g.theta_f_rad()).sin();
    2.0 * std::f64::consts::PI * EPS0_F_M * r * (2.0 * r * s * s / g.gap_m).ln_1p()
}

/// `C_RT` small-angle closed form: `2 pi eps0 R ln(1 + R theta_f^2 / (2 d))` [F].
pub fn c_rt_small_angle_f(g: &TipGeometry) -> f64 {
    let r = g.radius_m;
    let th = g.theta_f_rad();
    2.0 * std::f64::consts::PI * EPS0_F_M * r * (r * th * th / (2.0 * g.gap_m)).ln_1p()
}

/// Adaptive Simpson on `[a, b]` to absolute tolerance `tol`, at most `depth` halvings.
fn adaptive_simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, depth: u32) -> f64 {
    let fa = f(a);
    let fb = f(b);
    let m = 0.5 * (a + b);
    let fm = f(m);
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson_step(f, a, b, fa, fm, fb, whole, tol, depth)
}

#[allow(clippy::too_many_arguments)]
fn simpson_step(
    f: &dyn Fn(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fm: f64,
    fb: f64,
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let lm = 0.5 * (a + m);
    let rm = 0.5 * (m + b);
    let flm = f(lm);
    let frm = f(rm);
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * tol {
        // Richardson extrapolation
        left + right + delta / 15.0
    } else {
        simpson_step(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1)
            + simpson_step(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_matches_the_exact_antiderivative() {
        let g = TipGeometry::THESIS;
        let q = c_rt_quadrature_f(&g, 1e-12);
        let e = c_rt_exact_f(&g);
        assert!((q - e).abs() / e < 1e-10, "{q} vs {e}");
    }

    #[test]
    fn thesis_value_is_about_2_5_pf() {
        // 2 pi eps0 R ln(1 + 80) = 2.4446 pF; the thesis quotes 2.5 pF.
        let c = c_rt_exact_f(&TipGeometry::THESIS) * 1e12;
        assert!((c - 2.4446).abs() < 1e-3, "{c}");
    }

    #[test]
    fn small_angle_error_is_of_order_theta_squared() {
        let g = TipGeometry::THESIS;
        let th = g.theta_f_rad();
        let rel = (c_rt_small_angle_f(&g) - c_rt_exact_f(&g)).abs() / c_rt_exact_f(&g);
        assert!(rel < th * th, "{rel}");
        assert!(rel > 0.0);
    }

    #[test]
    fn quadrature_handles_a_sharp_peak() {
        // 1 nm gap: the integrand peaks within 1e-4 rad of 0.
        let g = TipGeometry {
            gap_m: 1e-9,
            ..TipGeometry::THESIS
        };
        let q = c_rt_quadrature_f(&g, 1e-12);
        let e = c_rt_exact_f(&g);
        assert!((q - e).abs() / e < 1e-9, "{q} vs {e}");
    }
}
