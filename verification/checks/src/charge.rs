//! Checks of the `charge` family (thesis ch. 7, "Electrification of the TM during the
//! Release"; physics.md section 7):
//!
//! - `charge-analysis`: CHG-Q and CHG-V, the analytic 2-sigma bounds of `|Q|` and `|V_TM|` with
//!   `C_RT` from the spherical-cap integral (quadrature), cross-checked by a seeded Monte Carlo
//!   whose estimates go into the evidence inputs. The values are reported whatever their margin:
//!   with the thesis's own capacitances `|Q|` at 2 sigma is 3.13e8 e, above the 3e8 e the thesis
//!   rounds to.

use geodesic_charge::{
    ChargeInputs, ELEMENTARY_CHARGE_C, TipGeometry, c_rt_exact_f, c_rt_quadrature_f,
    c_rt_small_angle_f, monte_carlo,
};
use geodesic_core::{Check, CheckContext, CheckError, Dim, Evidence, Quantity};

/// Relative tolerance of the `C_RT` quadrature [-].
const QUAD_REL_TOL: f64 = 1e-12;

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    vec![Box::new(ChargeAnalysis)]
}

/// `charge-analysis`: CHG-Q and CHG-V with the thesis's inputs.
pub struct ChargeAnalysis;

impl ChargeAnalysis {
    /// The evidence for a tip geometry and the thesis's other capacitances and voltage spread,
    /// with a Monte Carlo of `n` draws and `seed`.
    pub fn evidence(geometry: &TipGeometry, n: usize, seed: u64) -> Vec<Evidence> {
        let c_rt = c_rt_quadrature_f(geometry, QUAD_REL_TOL);
        let inputs = ChargeInputs::thesis_with_c_rt(c_rt);
        let mc = monte_carlo(&inputs, n.max(2), seed);
        let common = |e: Evidence| {
            e.with_input("c_eh_pf", inputs.c_eh_f * 1e12)
                .with_input("c_pyr_pf", inputs.c_pyr_f * 1e12)
                .with_input("c_cyl_pf", inputs.c_cyl_f * 1e12)
                .with_input("c_rt_pf", c_rt * 1e12)
                .with_input("c_rt_exact_pf", c_rt_exact_f(geometry) * 1e12)
                .with_input("c_rt_small_angle_pf", c_rt_small_angle_f(geometry) * 1e12)
                .with_input("r_m", geometry.radius_m)
                .with_input("cap_radius_m", geometry.cap_radius_m)
                .with_input("d_m", geometry.gap_m)
                .with_input("dv_2sigma_v", inputs.dv_2sigma_v)
                .with_input("mc_n", mc.n)
                .with_input("mc_seed", mc.seed)
        };
        let q = common(Evidence::measured(
            "CHG-Q",
            Quantity::new(inputs.q_2sigma_c(), Dim::CHARGE),
            geodesic_core::Basis::Model,
            "Analytic 2-sigma bound sqrt(C_EH^2+C_Pyr^2+C_Cyl^2+C_RT^2) dV with C_RT from the \
             spherical-cap integral (quadrature); confirmed by Monte Carlo (inputs).",
        ))
        .with_input("q_2sigma_e", inputs.q_2sigma_e())
        .with_input("mc_q_p9545_e", mc.q_p9545_e)
        .with_input("mc_q_2sd_e", mc.q_2sd_e)
        .with_input("elementary_charge_c", ELEMENTARY_CHARGE_C);
        let v = common(Evidence::measured(
            "CHG-V",
            Quantity::new(inputs.v_2sigma_v(), Dim::VOLTAGE),
            geodesic_core::Basis::Model,
            "Analytic 2-sigma bound sqrt(C_Pyr^2+C_Cyl^2+C_RT^2)/C_EH dV with C_RT from the \
             spherical-cap integral (quadrature); confirmed by Monte Carlo (inputs).",
        ))
        .with_input("mc_v_p9545_v", mc.v_p9545_v)
        .with_input("mc_v_2sd_v", mc.v_2sd_v);
        vec![q, v]
    }
}

impl Check for ChargeAnalysis {
    fn name(&self) -> &'static str {
        "charge-analysis"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["CHG-Q", "CHG-V"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        Ok(ChargeAnalysis::evidence(
            &TipGeometry::THESIS,
            ctx.mc_n,
            ctx.seed,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesic_core::Outcome;

    #[test]
    fn thesis_inputs_give_the_printed_orders() {
        let ev = ChargeAnalysis::evidence(&TipGeometry::THESIS, 20_000, 1);
        let Outcome::Measured(q) = &ev[0].outcome else {
            panic!()
        };
        let Outcome::Measured(v) = &ev[1].outcome else {
            panic!()
        };
        let q_e = q.value / ELEMENTARY_CHARGE_C;
        assert!((q_e - 3.1297e8).abs() < 1e5, "{q_e}");
        assert!((v.value - 1.0605).abs() < 1e-3, "{}", v.value);
    }
}
