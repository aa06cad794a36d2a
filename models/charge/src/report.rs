//! The document of `geodesic charge --json`: the right-tip capacitance three ways, the charge
//! and voltage at 2 sigma (analytic and Monte Carlo), the neutralisation time, the inputs used
//! and the thesis's values beside them. Typed here, where it is computed; the command prints it
//! through `serde_json::Value` (keys in alphabetical order, as it always has).

use crate::{
    ChargeInputs, ChargeMonteCarlo, DAY_S, ELEMENTARY_CHARGE_C, THESIS_RATE_E_S, TipGeometry,
    time_to_neutralise_s,
};
use serde::Serialize;

/// The right-tip capacitance `C_RT` three ways [F] and the one used.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CRt {
    /// Cap integral by quadrature [F].
    pub quadrature_f: f64,
    /// Exact series [F].
    pub exact_f: f64,
    /// Small-angle approximation [F].
    pub small_angle_f: f64,
    /// Given with `--c-rt-pf` (else the quadrature is used).
    pub given: bool,
}

/// `geodesic charge`'s document; `F` is how the charge inputs file is named (its label,
/// SHA-256 and origin).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct ChargeReport<F: Serialize> {
    /// `C_RT` used [pF].
    pub c_rt_pf: f64,
    /// `C_RT` by quadrature [pF].
    pub c_rt_quadrature_pf: f64,
    /// `C_RT` exact [pF].
    pub c_rt_exact_pf: f64,
    /// `C_RT` small-angle [pF].
    pub c_rt_small_angle_pf: f64,
    /// Relative difference quadrature - exact [-].
    pub c_rt_quadrature_vs_exact_rel: f64,
    /// Relative difference small-angle - exact [-].
    pub c_rt_small_angle_vs_exact_rel: f64,
    /// Where the `C_RT` used comes from.
    pub c_rt_source: &'static str,
    /// Charge at 2 sigma [e].
    pub q_2sigma_e: f64,
    /// Charge at 2 sigma [C].
    pub q_2sigma_c: f64,
    /// Voltage at 2 sigma [V].
    pub v_2sigma_v: f64,
    /// The Monte Carlo's figures.
    pub monte_carlo: McFigures,
    /// Time to neutralise a charge.
    pub neutralise: Neutralise,
    /// The inputs used.
    pub inputs: UsedInputs<F>,
    /// The thesis's values.
    pub thesis: Thesis,
}

/// The charge Monte Carlo's figures.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct McFigures {
    /// Draws.
    pub n: usize,
    /// Seed.
    pub seed: u64,
    /// Twice the sample sd of Q [e].
    pub q_2sd_e: f64,
    /// 95.45 % point of |Q| [e].
    pub q_p9545_e: f64,
    /// Twice the sample sd of V_TM [V].
    pub v_2sd_v: f64,
    /// 95.45 % point of |V_TM| [V].
    pub v_p9545_v: f64,
}

/// Time to neutralise a charge by positive charging.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct Neutralise {
    /// Charging rate [e/s].
    pub rate_e_s: f64,
    /// Where the rate comes from.
    pub rate_source: &'static str,
    /// Charge to neutralise [e].
    pub q_e: f64,
    /// Time [s] (none: not neutralised by positive charging).
    pub seconds: Option<f64>,
    /// Time [days].
    pub days: Option<f64>,
    /// Time to neutralise the negative 2-sigma charge [days].
    pub q_2sigma_negative_days: Option<f64>,
}

/// The inputs used.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct UsedInputs<F: Serialize> {
    /// Capacitance TM-electrode housing [pF].
    pub c_eh_pf: f64,
    /// Pyramidal plunger capacitance [pF].
    pub c_pyr_pf: f64,
    /// Cylindrical capacitance [pF].
    pub c_cyl_pf: f64,
    /// Right-tip capacitance [pF].
    pub c_rt_pf: f64,
    /// Gap [m].
    pub d_m: f64,
    /// Tip radius [m].
    pub r_m: f64,
    /// Cap radius [m].
    pub cap_radius_m: f64,
    /// Cap half-angle [rad].
    pub theta_f_rad: f64,
    /// Contact potential difference at 2 sigma [V].
    pub dv_2sigma_v: f64,
    /// Elementary charge [C].
    pub elementary_charge_c: f64,
    /// The charge inputs file.
    pub charge: F,
}

/// The thesis's values (ch. 7).
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct Thesis {
    /// `C_RT` [pF].
    pub c_rt_pf: f64,
    /// Charge at 2 sigma [e].
    pub q_2sigma_e: f64,
    /// Voltage at 2 sigma [V].
    pub v_2sigma_v: f64,
    /// Neutralisation time [days].
    pub neutralise_days: f64,
}

impl<F: Serialize> ChargeReport<F> {
    /// The document of `inputs` (with `c_rt`, the tip `geometry`), the Monte Carlo `mc`, and the
    /// neutralisation of `q_e` [e] at `rate_e_s` [e/s]; `file` names the inputs file.
    pub fn new(
        geometry: &TipGeometry,
        inputs: &ChargeInputs,
        c_rt: CRt,
        mc: &ChargeMonteCarlo,
        (rate_e_s, q_e): (f64, f64),
        file: F,
    ) -> Self {
        let q2 = inputs.q_2sigma_e();
        let t_given = time_to_neutralise_s(q_e, rate_e_s);
        let t_q2 = time_to_neutralise_s(-q2, rate_e_s);
        let days = |t: Option<f64>| t.map(|s| s / DAY_S);
        ChargeReport {
            c_rt_pf: inputs.c_rt_f * 1e12,
            c_rt_quadrature_pf: c_rt.quadrature_f * 1e12,
            c_rt_exact_pf: c_rt.exact_f * 1e12,
            c_rt_small_angle_pf: c_rt.small_angle_f * 1e12,
            c_rt_quadrature_vs_exact_rel: (c_rt.quadrature_f - c_rt.exact_f).abs() / c_rt.exact_f,
            c_rt_small_angle_vs_exact_rel: (c_rt.small_angle_f - c_rt.exact_f).abs() / c_rt.exact_f,
            c_rt_source: if c_rt.given {
                "--c-rt-pf"
            } else {
                "cap integral (quadrature)"
            },
            q_2sigma_e: q2,
            q_2sigma_c: inputs.q_2sigma_c(),
            v_2sigma_v: inputs.v_2sigma_v(),
            monte_carlo: McFigures {
                n: mc.n,
                seed: mc.seed,
                q_2sd_e: mc.q_2sd_e,
                q_p9545_e: mc.q_p9545_e,
                v_2sd_v: mc.v_2sd_v,
                v_p9545_v: mc.v_p9545_v,
            },
            neutralise: Neutralise {
                rate_e_s,
                rate_source: if (rate_e_s - THESIS_RATE_E_S).abs() < 1e-12 * THESIS_RATE_E_S {
                    "default: 3e8 e / 50 days, back-derived from the thesis (ch. 7)"
                } else {
                    "--rate-e-s"
                },
                q_e,
                seconds: t_given,
                days: days(t_given),
                q_2sigma_negative_days: days(t_q2),
            },
            inputs: UsedInputs {
                c_eh_pf: inputs.c_eh_f * 1e12,
                c_pyr_pf: inputs.c_pyr_f * 1e12,
                c_cyl_pf: inputs.c_cyl_f * 1e12,
                c_rt_pf: inputs.c_rt_f * 1e12,
                d_m: geometry.gap_m,
                r_m: geometry.radius_m,
                cap_radius_m: geometry.cap_radius_m,
                theta_f_rad: geometry.theta_f_rad(),
                dv_2sigma_v: inputs.dv_2sigma_v,
                elementary_charge_c: ELEMENTARY_CHARGE_C,
                charge: file,
            },
            thesis: Thesis {
                c_rt_pf: 2.5,
                q_2sigma_e: 3e8,
                v_2sigma_v: 1.1,
                neutralise_days: 50.0,
            },
        }
    }
}
