//! Checks of the `charge` family (thesis ch. 7, "Electrification of the TM during the
//! Release"; physics.md section 7):
//!
//! - `charge-analysis`: CHG-Q and CHG-V from the run's charge inputs file
//!   (`models/charge/charge.yaml`, or `verify --charge FILE`): the capacitances, the 2-sigma
//!   contact voltage difference and the release tip's geometry (`C_RT` from the spherical-cap
//!   integral, quadrature). `Q` and `V_TM` are zero-mean normals, so their `|.|` quantile at
//!   the requirement's `probability` is exact: `k` sigma for a probability written `(k sigma)`,
//!   else the two-sided normal point. A seeded Monte Carlo cross-checks the 2-sigma values (its
//!   estimates go into the evidence inputs). The values are reported whatever their margin:
//!   with the thesis's own capacitances `|Q|` at 2 sigma is 3.13e8 e, above the 3e8 e the thesis
//!   rounds to.

use geodesic_charge::{
    ChargeFile, ChargeInputs, ELEMENTARY_CHARGE_C, TipGeometry, c_rt_exact_f, c_rt_small_angle_f,
    monte_carlo,
};
use geodesic_core::{Check, CheckContext, CheckError, Dim, Evidence, Quantity};

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    vec![Box::new(ChargeAnalysis)]
}

/// `charge-analysis`: CHG-Q and CHG-V from the charge inputs file.
pub struct ChargeAnalysis;

/// The charge inputs of a run: its charge file parsed (errors name the file and line).
pub fn charge_of(ctx: &CheckContext) -> Result<ChargeFile, CheckError> {
    let f = &ctx.inputs.file("charge")?;
    ChargeFile::from_yaml_str(&f.text, &f.label)
        .map_err(|e| CheckError::input(e.to_string()).in_file(&f.label, 0))
}

/// The two-sided coverage `k` of a probability written with its sigma level, else the normal
/// point `Phi^-1((1 + p) / 2)`: `|X|` of a zero-mean normal is below `k` sigma with
/// probability `p`.
pub fn sigmas_for(probability: f64, sigma: Option<f64>) -> f64 {
    sigma.unwrap_or_else(|| geodesic_util::normal::normal_quantile(0.5 * (1.0 + probability)))
}

impl ChargeAnalysis {
    /// The evidence for charge inputs (`file`: the label and SHA-256 of their file), with the
    /// quantile of each requirement at `k_q` and `k_v` sigmas (`None`: the requirement states
    /// no probability) and a Monte Carlo of `n` draws and `seed`.
    pub fn evidence_for(
        charge: &ChargeFile,
        file: (&str, &str),
        k_q: Option<f64>,
        k_v: Option<f64>,
        n: usize,
        seed: u64,
    ) -> Vec<Evidence> {
        let inputs = &charge.inputs;
        let geometry = &charge.tip;
        let mc = monte_carlo(inputs, n.max(2), seed);
        let common = |e: Evidence| {
            e.with_input("c_eh_pf", inputs.c_eh_f * 1e12)
                .with_input("c_pyr_pf", inputs.c_pyr_f * 1e12)
                .with_input("c_cyl_pf", inputs.c_cyl_f * 1e12)
                .with_input("c_rt_pf", inputs.c_rt_f * 1e12)
                .with_input("c_rt_exact_pf", c_rt_exact_f(geometry) * 1e12)
                .with_input("c_rt_small_angle_pf", c_rt_small_angle_f(geometry) * 1e12)
                .with_input("r_m", geometry.radius_m)
                .with_input("cap_radius_m", geometry.cap_radius_m)
                .with_input("d_m", geometry.gap_m)
                .with_input("dv_2sigma_v", inputs.dv_2sigma_v)
                .with_input("charge_file", file.0)
                .with_input("charge_sha256", file.1)
                .with_input("mc_n", mc.n)
                .with_input("mc_seed", mc.seed)
                .from_inputs(&["charge"])
        };
        let no_probability = |id: &str| {
            common(Evidence::not_verified(
                id,
                format!(
                    "{id} states no `probability`: |Q| and |V_TM| are normal, and the requirement's probability says which quantile to judge"
                ),
                "Analytic propagation of the contact voltages.",
            ))
        };
        let q = match k_q {
            Some(k) => common(Evidence::measured(
                "CHG-Q",
                Quantity::new(inputs.q_2sigma_c() * k / 2.0, Dim::CHARGE),
                geodesic_core::Basis::Model,
                format!(
                    "Analytic {} sigma bound sqrt(C_EH^2+C_Pyr^2+C_Cyl^2+C_RT^2) x dV with the charge inputs' capacitances and C_RT from the spherical-cap integral (quadrature); confirmed by Monte Carlo (inputs).",
                    geodesic_core::units::fmt_num(k)
                ),
            ))
            .with_input("sigmas", k)
            .with_input("q_2sigma_e", inputs.q_2sigma_e())
            .with_input("mc_q_p9545_e", mc.q_p9545_e)
            .with_input("mc_q_2sd_e", mc.q_2sd_e)
            .with_input("elementary_charge_c", ELEMENTARY_CHARGE_C),
            None => no_probability("CHG-Q"),
        };
        let v = match k_v {
            Some(k) => common(Evidence::measured(
                "CHG-V",
                Quantity::new(inputs.v_2sigma_v() * k / 2.0, Dim::VOLTAGE),
                geodesic_core::Basis::Model,
                format!(
                    "Analytic {} sigma bound sqrt(C_Pyr^2+C_Cyl^2+C_RT^2)/C_EH x dV with the charge inputs' capacitances and C_RT from the spherical-cap integral (quadrature); confirmed by Monte Carlo (inputs).",
                    geodesic_core::units::fmt_num(k)
                ),
            ))
            .with_input("sigmas", k)
            .with_input("mc_v_p9545_v", mc.v_p9545_v)
            .with_input("mc_v_2sd_v", mc.v_2sd_v),
            None => no_probability("CHG-V"),
        };
        vec![q, v]
    }

    /// The evidence for a tip geometry and the thesis's other capacitances and voltage spread
    /// at 2 sigma, with a Monte Carlo of `n` draws and `seed`.
    pub fn evidence(geometry: &TipGeometry, n: usize, seed: u64) -> Vec<Evidence> {
        let charge = ChargeFile {
            inputs: ChargeInputs::thesis_with_c_rt(geodesic_charge::c_rt_quadrature_f(
                geometry,
                geodesic_charge::inputs::QUAD_REL_TOL,
            )),
            tip: *geometry,
            file: "<thesis>".into(),
        };
        Self::evidence_for(&charge, ("<thesis>", ""), Some(2.0), Some(2.0), n, seed)
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
        let charge = charge_of(ctx)?;
        let k = |id: &str| {
            ctx.requirements.get(id).and_then(|r| {
                r.probability_value
                    .map(|p| sigmas_for(p, r.probability_sigma))
            })
        };
        Ok(ChargeAnalysis::evidence_for(
            &charge,
            (
                &ctx.inputs.file("charge")?.label,
                &ctx.inputs.file("charge")?.sha256,
            ),
            k("CHG-Q"),
            k("CHG-V"),
            ctx.option::<usize>("mc_n")?,
            ctx.option::<u64>("seed")?,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesic_core::Outcome;

    fn value(e: &Evidence) -> f64 {
        match &e.outcome {
            Outcome::Measured(q) => q.value,
            Outcome::NotVerified(r) => panic!("{r}"),
        }
    }

    #[test]
    fn thesis_inputs_give_the_printed_orders() {
        let ev = ChargeAnalysis::evidence(&TipGeometry::THESIS, 20_000, 1);
        let q_e = value(&ev[0]) / ELEMENTARY_CHARGE_C;
        assert!((q_e - 3.1297e8).abs() < 1e5, "{q_e}");
        assert!((value(&ev[1]) - 1.0605).abs() < 1e-3, "{}", value(&ev[1]));
    }

    #[test]
    fn the_charge_file_and_the_probability_move_the_rows() {
        let mut ctx = crate::builtin_context(crate::scratch_dir(), 1000, 1);
        let base = ChargeAnalysis.run(&ctx).unwrap();
        // the repository's file holds the thesis's inputs: the same values
        let thesis = ChargeAnalysis::evidence(&TipGeometry::THESIS, 1000, 1);
        assert_eq!(value(&base[0]), value(&thesis[0]));
        assert_eq!(base[0].model_inputs, ["charge"]);
        // an edited capacitance moves CHG-Q
        let mut inputs = (*ctx.inputs).clone();
        inputs.insert(
            "charge",
            "charge inputs",
            geodesic_core::check::InputFile::new(
                "edited.yaml",
                geodesic_charge::DEFAULT_CHARGE_YAML.replace("c_eh_f: 34.4e-12", "c_eh_f: 20e-12"),
            ),
        );
        ctx.inputs = std::sync::Arc::new(inputs);
        let edited = ChargeAnalysis.run(&ctx).unwrap();
        assert!(value(&edited[0]) < 0.9 * value(&base[0]));
        assert_eq!(edited[0].inputs["charge_file"], "edited.yaml");
        // 3 sigma instead of 2: 1.5 times the value
        let mut reqs = (*ctx.requirements).clone();
        let r = reqs
            .items
            .iter_mut()
            .find(|r| r.id.as_str() == "CHG-Q")
            .unwrap();
        r.probability_value = Some(0.9973);
        r.probability_sigma = Some(3.0);
        ctx.requirements = std::sync::Arc::new(reqs);
        let three = ChargeAnalysis.run(&ctx).unwrap();
        assert!((value(&three[0]) / value(&edited[0]) - 1.5).abs() < 1e-12);
    }

    #[test]
    fn sigma_levels_of_probabilities() {
        assert_eq!(sigmas_for(0.9545, Some(2.0)), 2.0);
        assert!((sigmas_for(0.9973002039367398, None) - 3.0).abs() < 1e-5);
        assert!((sigmas_for(0.5, None) - 0.6744897501960817).abs() < 1e-5);
    }
}
