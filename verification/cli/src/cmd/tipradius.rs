//! `geodesic tip-radius`: the tip-radius trade-off of thesis ch. 6, "Lesson Learned" (issue 16,
//! item 2): the thesis's simple worst-case estimates against tip radius (bottom: 0.2 N,
//! 180 mm/s; upper: 0.4 N, 45 mm/s), their optimum, and the full release Monte Carlo at a
//! handful of radii as a cross-check. Thin: the model is `geodesic_release::tipradius`.

use crate::cmd::montecarlo::{budget_input, load_budget, write_atomic};
use crate::error::{CliError, CmdResult};
use geodesic_release::tipradius::{
    ESTIMATES, SimpleInputs, initial_jerk_m_s3, monte_carlo_at, optimum_radius_m, worst_velocity,
};
use serde_json::json;
use std::path::PathBuf;

/// Flags of `geodesic tip-radius`.
#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:
  geodesic tip-radius
  geodesic tip-radius --radii 0.5,1,2,5,10,20 --mc-n 20000 --plot tip-radius.svg --json
Simple model: push = F t_exit / M (Hertz indentation undone at the mechanism's initial jerk),
adhesion = 120 MPa x Hertz area x 0.8 um / v_RT / M; the Monte Carlo scales A1 with the contact
area (R / R0)^(2/3). See docs/release.md.")]
pub struct Args {
    /// Radii of the Monte Carlo cross-check, in mm, comma-separated.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true, default_values_t = [0.5, 1.0, 2.0, 5.0, 10.0, 20.0])]
    pub radii: Vec<f64>,
    /// Monte Carlo draws per radius (0: no cross-check).
    #[arg(long = "mc-n", default_value_t = 20_000)]
    pub mc_n: usize,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Uncertainty budget YAML [default: ./models/release/budget.yaml if present, else the
    /// built-in copy; as verify].
    #[arg(long, value_name = "FILE.yaml")]
    pub budget: Option<PathBuf>,
    /// Also write the plot to FILE.svg.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Log-spaced radii from 0.05 mm to 50 mm [m].
pub fn grid() -> Vec<f64> {
    (0..=120)
        .map(|i| 0.05e-3 * 1000f64.powf(i as f64 / 120.0))
        .collect()
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    for r in &args.radii {
        if !(r.is_finite() && *r > 0.0 && *r <= 100.0) {
            return Err(CliError::bad(format!(
                "--radii: {r} mm is not a radius between 0 and 100 mm"
            )));
        }
    }
    if args.mc_n > geodesic_release::montecarlo::MAX_N {
        return Err(CliError::bad(format!(
            "--mc-n {}: at most {}",
            args.mc_n,
            geodesic_release::montecarlo::MAX_N
        )));
    }
    if let Some(p) = &args.plot {
        geodesic_core::output::check_target(p).map_err(|e| CliError::bad(format!("--plot {e}")))?;
    }
    let budget_file = budget_input(args.budget.as_deref())?;
    crate::inputs::announce(args.json, crate::inputs::ModelInput::Budget, &budget_file);
    let budget = load_budget(&budget_file)?;
    let inputs = SimpleInputs {
        e_star_pa: budget.e_star_pa.mean(),
        mass_kg: budget.tm_mass_kg.mean(),
        jerk_m_s3: initial_jerk_m_s3(
            budget.mechanism.mean(),
            geodesic_mechanism::VoltageCommand::ramp(budget.e0_v.mean(), budget.em_v_s.mean()),
        ),
        rupture_pa: 120e6,
        elongation_m: 0.8e-6,
    };
    let r0 = budget.tip_radius_m.mean();
    let mut curves = Vec::new();
    let mut est_json = Vec::new();
    for e in &ESTIMATES {
        let w: Vec<_> = grid()
            .into_iter()
            .map(|r| worst_velocity(&inputs, e, r))
            .collect();
        let opt = optimum_radius_m(&inputs, e);
        let at_opt = worst_velocity(&inputs, e, opt);
        let at_r0 = worst_velocity(&inputs, e, r0);
        est_json.push(json!({
            "estimate": e.name,
            "force_n": e.force_n,
            "v_rt_m_s": e.v_rt_m_s,
            "optimum_radius_mm": opt * 1e3,
            "at_optimum_um_s": at_opt.total_m_s * 1e6,
            "at_budget_radius_um_s": at_r0.total_m_s * 1e6,
            "push_at_budget_radius_um_s": at_r0.push_m_s * 1e6,
            "adhesion_at_budget_radius_um_s": at_r0.adhesion_m_s * 1e6,
            "curve": w.iter().map(|p| json!({"radius_mm": p.radius_m * 1e3, "push_um_s": p.push_m_s * 1e6, "adhesion_um_s": p.adhesion_m_s * 1e6, "total_um_s": p.total_m_s * 1e6})).collect::<Vec<_>>(),
        }));
        curves.push((
            format!("{} ({} N, {} mm/s)", e.name, e.force_n, e.v_rt_m_s * 1e3),
            w,
        ));
    }
    let mut mc = Vec::new();
    if args.mc_n > 0 {
        let task = crate::progress::Task::counter(
            args.json,
            "tip-radius: Monte Carlo radii",
            args.radii.len() as u64,
        );
        for r in &args.radii {
            mc.push(
                monte_carlo_at(&budget, r * 1e-3, args.mc_n, args.seed)
                    .map_err(|e| CliError::bad(format!("Monte Carlo at {r} mm: {e}")))?,
            );
            task.inc(1);
        }
        task.finish();
    }
    let doc = json!({
        "budget_radius_mm": r0 * 1e3,
        "jerk_m_s3": inputs.jerk_m_s3,
        "e_star_pa": inputs.e_star_pa,
        "mass_kg": inputs.mass_kg,
        "rupture_pa": inputs.rupture_pa,
        "elongation_m": inputs.elongation_m,
        "estimates": est_json,
        "monte_carlo": mc.iter().map(|p| json!({"radius_mm": p.radius_m * 1e3, "p9973_um_s": p.p9973_um_s, "a1_scale": p.a1_scale})).collect::<Vec<_>>(),
        "mc_n": args.mc_n,
        "seed": args.seed,
        "inputs": {"budget": crate::inputs::json(&budget_file)},
    });
    if let Some(p) = &args.plot {
        let svg = geodesic_checks::plots::tip_radius_svg(&curves, &mc, r0)
            .map_err(|e| CliError::Io(e.0))?;
        write_atomic(p, svg.as_bytes())?;
    }
    if args.json {
        let text = serde_json::to_string_pretty(&doc).map_err(|e| CliError::Io(e.to_string()))?;
        println!("{text}");
    } else {
        println!(
            "{}",
            crate::inputs::line(crate::inputs::ModelInput::Budget, &budget_file)
        );
        println!(
            "initial tip jerk {:.3e} m/s^3 (mechanism model), E* {:.0} GPa, M {} kg, gold 120 MPa, bond 0.8 um",
            inputs.jerk_m_s3,
            inputs.e_star_pa * 1e-9,
            inputs.mass_kg
        );
        for e in doc["estimates"].as_array().into_iter().flatten() {
            println!(
                "{:7} estimate: optimum radius {:.2} mm ({:.3} um/s); at {:.0} mm {:.3} um/s (push {:.3}, adhesion {:.3})",
                e["estimate"].as_str().unwrap_or(""),
                e["optimum_radius_mm"].as_f64().unwrap_or(f64::NAN),
                e["at_optimum_um_s"].as_f64().unwrap_or(f64::NAN),
                r0 * 1e3,
                e["at_budget_radius_um_s"].as_f64().unwrap_or(f64::NAN),
                e["push_at_budget_radius_um_s"].as_f64().unwrap_or(f64::NAN),
                e["adhesion_at_budget_radius_um_s"]
                    .as_f64()
                    .unwrap_or(f64::NAN)
            );
        }
        for p in &mc {
            println!(
                "Monte Carlo R = {:6.2} mm (A1 x {:.3}): 99.73 % |X'| = {:.3} um/s",
                p.radius_m * 1e3,
                p.a1_scale,
                p.p9973_um_s
            );
        }
        println!("thesis: optimum near 1 mm against today's 10 mm");
    }
    Ok(0)
}
