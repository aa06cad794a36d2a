//! Traced tests of the charge family: the capacitance of the release-tip cap and the 2-sigma
//! charge and voltage bounds.

use geodesic_charge::{
    ChargeInputs, ELEMENTARY_CHARGE_C, TipGeometry, c_rt_exact_f, c_rt_quadrature_f,
    c_rt_small_angle_f, monte_carlo,
};
use geodesic_checks::charge::ChargeAnalysis;
use geodesic_core::Outcome;
use geodesic_core::trace::assert_reference;
use proptest::prelude::*;

fn any_inputs() -> impl Strategy<Value = ChargeInputs> {
    (
        1e-12f64..1e-10,
        1e-12f64..1e-10,
        1e-12f64..1e-10,
        1e-13f64..1e-11,
    )
        .prop_map(|(c_eh_f, c_pyr_f, c_cyl_f, c_rt_f)| ChargeInputs {
            c_eh_f,
            c_pyr_f,
            c_cyl_f,
            c_rt_f,
            dv_2sigma_v: 1.0,
        })
}

proptest! {
    /// Q and V_TM at 2 sigma scale linearly with the contact voltage spread.
    #[test]
    fn bounds_scale_linearly_with_voltage_spread(i in any_inputs(), k in 1e-3f64..1e3) {
        geodesic_core::verifies!("CHG-Q", "CHG-V");
        let j = ChargeInputs { dv_2sigma_v: k * i.dv_2sigma_v, ..i };
        let linear = "analytic: linear in dV (factor k)";
        assert_reference("CHG-Q", linear, j.q_2sigma_c() / i.q_2sigma_c(), k, 1e-12);
        assert_reference("CHG-V", linear, j.v_2sigma_v() / i.v_2sigma_v(), k, 1e-12);
        // and so does every Monte Carlo draw (same seed, same standard normals)
        let a = monte_carlo(&i, 50, 4);
        let b = monte_carlo(&j, 50, 4);
        assert_reference("CHG-Q", linear, b.q_p9545_e / a.q_p9545_e, k, 1e-9);
        assert_reference("CHG-V", linear, b.v_p9545_v / a.v_p9545_v, k, 1e-9);
    }

    /// The quadrature of the cap integral agrees with its exact antiderivative, and the
    /// small-angle closed form within theta_f^2 relative, over a range of geometries.
    #[test]
    fn quadrature_and_closed_forms_agree(
        radius_m in 1e-3f64..5e-2,
        cap_radius_m in 5e-5f64..1e-3,
        gap_m in 1e-9f64..1e-5,
    ) {
        geodesic_core::verifies!("CHG-Q", "CHG-V");
        let g = TipGeometry { radius_m, cap_radius_m, gap_m };
        let q = c_rt_quadrature_f(&g, 1e-12);
        let e = c_rt_exact_f(&g);
        // C_RT enters both bounds
        for id in ["CHG-Q", "CHG-V"] {
            assert_reference(id, "C_RT, exact antiderivative of the cap integral", q, e, 1e-9);
        }
        let th = g.theta_f_rad();
        let s = c_rt_small_angle_f(&g);
        prop_assert!((s / e - 1.0).abs() < th * th, "small-angle {} exact {}", s, e);
    }
}

/// The Monte Carlo 95.45 % quantiles agree with the analytic 2-sigma bounds.
#[test]
fn monte_carlo_confirms_the_analytic_bounds() {
    geodesic_core::verifies!("CHG-Q", "CHG-V");
    let i = ChargeInputs::thesis_with_c_rt(c_rt_exact_f(&TipGeometry::THESIS));
    let mc = monte_carlo(&i, 400_000, 21);
    // quantile standard error ~0.2 % at this N; 1 % allows 5 of them
    let analytic = "analytic 2-sigma bound";
    assert_reference("CHG-Q", analytic, mc.q_p9545_e, i.q_2sigma_e(), 0.01);
    assert_reference("CHG-V", analytic, mc.v_p9545_v, i.v_2sigma_v(), 0.01);
}

/// The charge-analysis evidence with the thesis's inputs, rounded: C_RT 2.444 pF,
/// |Q| 3.130e8 e (above the 3e8 e limit), |V_TM| 1.061 V; both against the thesis's equations
/// evaluated by hand with its capacitances (C_EH 34.4, C_Pyr 35, C_Cyl 10, C_RT 2.5 pF, dV 1 V).
#[test]
fn charge_analysis_snapshot() {
    geodesic_core::verifies!("CHG-Q", "CHG-V");
    let ev = ChargeAnalysis::evidence(&TipGeometry::THESIS, 10_000, 1);
    let thesis = "thesis equations with its capacitances, C_RT 2.5 pF, dV 1 V";
    let measured = |id: &str| match &ev.iter().find(|e| e.requirement == id).unwrap().outcome {
        Outcome::Measured(q) => q.value,
        Outcome::NotVerified(r) => panic!("{id}: {r}"),
    };
    // sqrt(34.4^2 + 35^2 + 10^2 + 2.5^2) pF x 1 V = 50.15 pC = 3.13e8 e (the check's value is in
    // coulomb); the thesis's 2.5 pF instead of the computed 2.444 pF changes it by 0.01 %
    let q_ref = (34.4f64.powi(2) + 35f64.powi(2) + 10f64.powi(2) + 2.5f64.powi(2)).sqrt() * 1e-12;
    assert_reference("CHG-Q", thesis, measured("CHG-Q"), q_ref, 1e-3);
    // sqrt(35^2 + 10^2 + 2.5^2) / 34.4 x 1 V
    let v_ref = (35f64.powi(2) + 10f64.powi(2) + 2.5f64.powi(2)).sqrt() / 34.4;
    assert_reference("CHG-V", thesis, measured("CHG-V"), v_ref, 1e-3);
    let rows: Vec<String> = ev
        .iter()
        .map(|e| match &e.outcome {
            Outcome::Measured(q) if e.requirement == "CHG-Q" => {
                format!("CHG-Q: {:.4e} e", q.value / ELEMENTARY_CHARGE_C)
            }
            Outcome::Measured(q) => format!("{}: {:.4} V", e.requirement, q.value),
            Outcome::NotVerified(r) => format!("{}: not verified ({r})", e.requirement),
        })
        .collect();
    let c_rt = format!("C_RT: {:.4} pF", ev[0].inputs["c_rt_pf"].as_f64().unwrap());
    insta::assert_yaml_snapshot!((c_rt, rows));
}
