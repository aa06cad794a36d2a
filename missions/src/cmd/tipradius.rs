//! `geodesic tip-radius`: the tip-radius trade-off of thesis ch. 6, "Lesson Learned" (issue 16,
//! item 2): the thesis's simple worst-case estimates against tip radius (bottom: 0.2 N,
//! 180 mm/s; upper: 0.4 N, 45 mm/s), their optimum, and the full release Monte Carlo at a
//! handful of radii as a cross-check. Thin: the model is `geodesic_release::tipradius`, the
//! document and the plot `geodesic_checks::tipradius` (as the `tip-radius-tradeoff` check's).

use crate::error::{CliError, CmdResult};
use geodesic_checks::tipradius::TradeOff;
use geodesic_release::tipradius::monte_carlo_at;
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
    /// The release budget (`--budget`, the flag the descriptor's input declares: added by
    /// `Reading::reading` in `cmd/mod.rs`).
    #[arg(skip)]
    pub budget: Option<PathBuf>,
    /// Also write the plot to FILE.svg.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    for r in &args.radii {
        if !(r.is_finite() && *r > 0.0 && *r <= 100.0) {
            return Err(CliError::usage(format!(
                "--radii: {r} mm is not a radius between 0 and 100 mm"
            )));
        }
    }
    if args.mc_n > geodesic_release::montecarlo::MAX_N {
        return Err(CliError::usage(format!(
            "--mc-n {}: at most {}",
            args.mc_n,
            geodesic_release::montecarlo::MAX_N
        )));
    }
    if let Some(p) = &args.plot {
        geodesic_util::output::check_target(p)
            .map_err(|e| CliError::usage(format!("--plot {e}")))?;
    }
    let budget_file =
        crate::inputs::resolve(crate::inputs::ModelInput::budget(), args.budget.as_deref())?;
    crate::inputs::announce(args.json, crate::inputs::ModelInput::budget(), &budget_file);
    let (budget, _) =
        geodesic_checks::release::budget_from_file(&budget_file).map_err(CliError::from)?;
    let mut mc = Vec::new();
    if args.mc_n > 0 {
        let task = crate::progress::Task::counter(
            args.json,
            "tip-radius: Monte Carlo radii",
            args.radii.len() as u64,
        );
        for r in &args.radii {
            mc.push(
                monte_carlo_at(&budget, r * 1e-3, args.mc_n, args.seed).map_err(|e| {
                    CliError::model(
                        Some("tip-radius Monte Carlo"),
                        format!("Monte Carlo at {r} mm: {e}"),
                    )
                })?,
            );
            task.inc(1);
        }
        task.finish();
    }
    let doc =
        TradeOff::new(&budget, &mc, args.mc_n, args.seed).with_input("budget", budget_file.clone());
    if let Some(p) = &args.plot {
        let svg = doc.svg().map_err(CliError::io)?;
        geodesic_util::output::write_atomic(p, svg.as_bytes())?;
    }
    if args.json {
        let v = serde_json::to_value(&doc).map_err(CliError::io)?;
        let text = serde_json::to_string_pretty(&v).map_err(CliError::io)?;
        println!("{text}");
    } else {
        print_text(&doc, &budget_file);
    }
    Ok(0)
}

/// Prints the trade-off as text.
fn print_text(doc: &TradeOff, budget_file: &geodesic_core::check::InputFile) {
    println!(
        "{}",
        crate::inputs::line(crate::inputs::ModelInput::budget(), budget_file)
    );
    println!(
        "initial tip jerk {:.3e} m/s^3 (mechanism model), E* {:.0} GPa, M {} kg, gold 120 MPa, bond 0.8 um",
        doc.jerk_m_s3,
        doc.e_star_pa * 1e-9,
        doc.mass_kg
    );
    for e in &doc.estimates {
        println!(
            "{:7} estimate: optimum radius {:.2} mm ({:.3} um/s); at {:.0} mm {:.3} um/s (push {:.3}, adhesion {:.3})",
            e.estimate,
            e.optimum_radius_mm,
            e.at_optimum_um_s,
            doc.budget_radius_mm,
            e.at_budget_radius_um_s,
            e.push_at_budget_radius_um_s,
            e.adhesion_at_budget_radius_um_s
        );
    }
    for p in &doc.monte_carlo {
        println!(
            "Monte Carlo R = {:6.2} mm (A1 x {:.3}): 99.73 % |X'| = {:.3} um/s",
            p.radius_mm, p.a1_scale, p.p9973_um_s
        );
    }
    println!("thesis: optimum near 1 mm against today's 10 mm");
}
