//! `geodesic charge`: the TM charge and voltage left by contact electrification at release
//! (thesis ch. 7; physics.md section 7): `C_RT` from the cap integral, the 2-sigma bounds of
//! `Q` and `V_TM` analytically and by Monte Carlo, and the time cosmic-ray charging takes to
//! neutralise a negative charge. Thin: the physics is in `geodesic-charge`.

use geodesic_charge::report::{CRt, ChargeReport};
use geodesic_charge::{
    ChargeInputs, DAY_S, THESIS_RATE_E_S, TipGeometry, c_rt_exact_f, c_rt_quadrature_f,
    c_rt_small_angle_f, monte_carlo, time_to_neutralise_s,
};

use crate::error::{CliError, CmdResult};

/// Relative tolerance of the `C_RT` quadrature [-].
const QUAD_REL_TOL: f64 = 1e-12;

/// Largest `--n` (Monte Carlo draws).
pub const MAX_N: usize = 10_000_000;

/// Flags of `geodesic charge` (defaults: the charge inputs file, resolved as `verify` resolves
/// it: `--charge FILE`, else ./models/charge/charge.yaml, else the built-in copy; a flag
/// replaces one of its values).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// TM - electrode housing capacitance C_EH [pF].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::in_unit(geodesic_core::units::Dim::CAPACITANCE, 1e-12))]
    pub c_eh_pf: Option<f64>,
    /// TM - pyramidal plunger capacitance C_Pyr [pF].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::in_unit(geodesic_core::units::Dim::CAPACITANCE, 1e-12))]
    pub c_pyr_pf: Option<f64>,
    /// TM - cylindrical plunger capacitance C_Cyl [pF].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::in_unit(geodesic_core::units::Dim::CAPACITANCE, 1e-12))]
    pub c_cyl_pf: Option<f64>,
    /// Use this C_RT [pF] instead of the cap integral (e.g. the thesis's rounded 2.5).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::in_unit(geodesic_core::units::Dim::CAPACITANCE, 1e-12))]
    pub c_rt_pf: Option<f64>,
    /// Release-tip radius of curvature R [m].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::length())]
    pub r_m: Option<f64>,
    /// Release-tip cap radius [m]: theta_f = atan(cap / R).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::length())]
    pub cap_radius_m: Option<f64>,
    /// Tip - TM gap d [m].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::length())]
    pub d_m: Option<f64>,
    /// 2-sigma contact voltage difference of each contact [V].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::quantity::voltage())]
    pub dv_2sigma_v: Option<f64>,
    /// Cosmic-ray charging rate [e/s] (default 3e8 e / 50 days = 69.4 e/s, back-derived from
    /// the thesis's "about 50 days to neutralise -3e8 e").
    #[arg(long, default_value_t = THESIS_RATE_E_S, allow_hyphen_values = true, value_parser = crate::quantity::in_unit(geodesic_core::units::Dim([0, 0, 0, 1, 0, 0]), geodesic_core::units::ELEMENTARY_CHARGE_C))]
    pub rate_e_s: f64,
    /// Charge whose neutralisation time is reported [e] (negative: cosmic rays charge positively).
    #[arg(long, default_value_t = -3e8, allow_hyphen_values = true, value_parser = crate::quantity::in_unit(geodesic_core::units::Dim::CHARGE, geodesic_core::units::ELEMENTARY_CHARGE_C))]
    pub neutralise_e: f64,
    /// The charge inputs (`--charge`, the flag the descriptor's input declares: added by
    /// `Reading::reading` in `cmd/mod.rs`).
    #[arg(skip)]
    pub charge: Option<std::path::PathBuf>,
    /// Monte Carlo draws.
    #[arg(long, default_value_t = 100_000)]
    pub n: usize,
    /// Monte Carlo seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

fn positive(flag: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(CliError::usage(format!(
            "--{flag} {v}: must be finite and positive"
        )))
    }
}

/// Runs the command.
/// A capacitance [F]: the flag's value [pF] when given, else the charge file's [F].
fn capacitance(flag: &str, given_pf: Option<f64>, file_f: f64) -> Result<f64, CliError> {
    match given_pf {
        Some(v) => Ok(positive(flag, v)? * 1e-12),
        None => positive(flag, file_f),
    }
}

pub fn run(args: Args) -> CmdResult {
    use crate::inputs::ModelInput;
    let charge_file = crate::inputs::resolve(ModelInput::charge(), args.charge.as_deref())?;
    crate::inputs::announce(args.json, ModelInput::charge(), &charge_file);
    let file = geodesic_charge::ChargeFile::from_yaml_str(&charge_file.text, &charge_file.label)
        .map_err(|e| CliError::malformed(e.to_string()).in_file(&charge_file.label, 0))?;
    let geometry = TipGeometry {
        radius_m: positive("r-m", args.r_m.unwrap_or(file.tip.radius_m))?,
        cap_radius_m: positive(
            "cap-radius-m",
            args.cap_radius_m.unwrap_or(file.tip.cap_radius_m),
        )?,
        gap_m: positive("d-m", args.d_m.unwrap_or(file.tip.gap_m))?,
    };
    let c_rt_quad = c_rt_quadrature_f(&geometry, QUAD_REL_TOL);
    let c_rt_exact = c_rt_exact_f(&geometry);
    let c_rt_small = c_rt_small_angle_f(&geometry);
    let c_rt_used = match args.c_rt_pf {
        Some(v) => positive("c-rt-pf", v)? * 1e-12,
        None => c_rt_quad,
    };
    let inputs = ChargeInputs {
        c_eh_f: capacitance("c-eh-pf", args.c_eh_pf, file.inputs.c_eh_f)?,
        c_pyr_f: capacitance("c-pyr-pf", args.c_pyr_pf, file.inputs.c_pyr_f)?,
        c_cyl_f: capacitance("c-cyl-pf", args.c_cyl_pf, file.inputs.c_cyl_f)?,
        c_rt_f: c_rt_used,
        dv_2sigma_v: positive(
            "dv-2sigma-v",
            args.dv_2sigma_v.unwrap_or(file.inputs.dv_2sigma_v),
        )?,
    };
    let rate = positive("rate-e-s", args.rate_e_s)?;
    if args.n < 2 || args.n > MAX_N {
        return Err(CliError::usage(format!(
            "--n {}: must be 2 to {MAX_N} draws",
            args.n
        )));
    }
    if !args.neutralise_e.is_finite() || args.neutralise_e.abs() > 1e30 {
        return Err(CliError::usage(format!(
            "--neutralise-e {}: must be a finite charge of at most 1e30 e",
            args.neutralise_e
        )));
    }
    let task =
        crate::progress::Task::spinner(args.json, &format!("charge: {} Monte Carlo draws", args.n));
    let mc = monte_carlo(&inputs, args.n, args.seed);
    task.finish();
    let q2 = inputs.q_2sigma_e();
    let t_given = time_to_neutralise_s(args.neutralise_e, rate);
    let t_q2 = time_to_neutralise_s(-q2, rate);
    let days = |t: Option<f64>| t.map(|s| s / DAY_S);
    let figures = [
        ("C_RT", c_rt_used),
        ("C_RT quadrature", c_rt_quad),
        ("C_RT exact", c_rt_exact),
        ("C_RT small-angle", c_rt_small),
        ("Q 2-sigma", q2),
        ("V_TM 2-sigma", inputs.v_2sigma_v()),
        ("Monte Carlo Q", mc.q_p9545_e),
        ("Monte Carlo V", mc.v_p9545_v),
        ("Monte Carlo Q 2 sd", mc.q_2sd_e),
        ("Monte Carlo V 2 sd", mc.v_2sd_v),
        ("neutralisation time", t_given.unwrap_or(0.0)),
        ("neutralisation time of Q", t_q2.unwrap_or(0.0)),
    ];
    if let Some((name, v)) = figures.iter().find(|(_, v)| !v.is_finite()) {
        return Err(CliError::not_finite(format!(
            "charge: {name} is {v}: the inputs overflow the arithmetic (use physical values)"
        )));
    }

    let doc = ChargeReport::new(
        &geometry,
        &inputs,
        CRt {
            quadrature_f: c_rt_quad,
            exact_f: c_rt_exact,
            small_angle_f: c_rt_small,
            given: args.c_rt_pf.is_some(),
        },
        &mc,
        (rate, args.neutralise_e),
        &charge_file,
    );
    let doc = serde_json::to_value(&doc).map_err(CliError::io)?;
    if args.json {
        println!("{doc}");
        return Ok(0);
    }
    println!(
        "{}",
        crate::inputs::line(ModelInput::charge(), &charge_file)
    );
    println!(
        "C_RT = {:.4} pF (quadrature; exact {:.4} pF, small-angle {:.4} pF; thesis 2.5 pF)",
        c_rt_quad * 1e12,
        c_rt_exact * 1e12,
        c_rt_small * 1e12
    );
    if args.c_rt_pf.is_some() {
        println!("using C_RT = {:.4} pF (--c-rt-pf)", c_rt_used * 1e12);
    }
    println!(
        "|Q| at 2 sigma: {:.4e} e analytic, {:.4e} e Monte Carlo 95.45 % (2 sd {:.4e} e; N = {}, seed {}); thesis ~3e8 e",
        q2, mc.q_p9545_e, mc.q_2sd_e, mc.n, mc.seed
    );
    println!(
        "|V_TM| at 2 sigma: {:.4} V analytic, {:.4} V Monte Carlo 95.45 % (2 sd {:.4} V); thesis ~1.1 V",
        inputs.v_2sigma_v(),
        mc.v_p9545_v,
        mc.v_2sd_v
    );
    match days(t_given) {
        Some(d) => println!(
            "time to neutralise {:.3e} e at {:.2} e/s: {:.1} days",
            args.neutralise_e, rate, d
        ),
        None => println!(
            "{:.3e} e is not neutralised by positive charging at {:.2} e/s",
            args.neutralise_e, rate
        ),
    }
    Ok(0)
}
