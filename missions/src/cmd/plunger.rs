//! `geodesic plunger`: the plungers' attraction on the charged TM in the 25 s after the release
//! (thesis ch. 7; issue 16, item 1), for any TM voltage, release velocity, retraction and
//! capacitance model. Thin: the model is `geodesic_charge::plunger`, the plot
//! `geodesic_checks::plunger`. Prints the extra velocity, the smallest TM-plunger gap, whether it
//! touches, and the force against the DFACS authority.

use crate::error::{CliError, CmdResult};
use geodesic_charge::plunger::{
    FlatDisc, PlungerCapacitance, Retraction, SpherePlane, default_model, simulate,
};
use geodesic_checks::plunger::{CaseRow, PlungerReport, case, plunger_svg};
use geodesic_util::output::write_atomic;
use std::path::PathBuf;

/// Flags of `geodesic plunger`.
#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:
  geodesic plunger                                  # 0.5, 1, 1.06 and 2 V, baseline and revised
  geodesic plunger --voltage 1.5 --retraction 2400:15 --v0 7.5um/s --json
  geodesic plunger --capacitance sphere:10 --plot plunger.svg
--retraction: baseline (15 um -> 500 um in 15 s), revised (-> 1800 um in 15 s) or END_UM:RAMP_S.
--capacitance: disc (the flat disc calibrated to 35 pF at 15 um), disc:RADIUS_MM or sphere:RADIUS_MM.")]
pub struct Args {
    /// TM voltages [V] (plungers at 0 V), comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [0.5, 1.0, 1.06, 2.0], allow_hyphen_values = true)]
    pub voltage: Vec<f64>,
    /// Retraction procedures, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = ["baseline".to_string(), "revised".to_string()])]
    pub retraction: Vec<String>,
    /// Release velocity towards one plunger (a unit may be given).
    #[arg(long, default_value = "5um/s", allow_hyphen_values = true, value_parser = crate::quantity::in_unit(geodesic_core::units::Dim::VELOCITY, 1.0))]
    pub v0: f64,
    /// Capacitance model.
    #[arg(long, default_value = "disc")]
    pub capacitance: String,
    /// Also write the plot of |F| / authority over time to FILE.svg.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

fn retraction(s: &str) -> Result<(String, Retraction), CliError> {
    match s.trim() {
        "baseline" => Ok(("baseline".into(), Retraction::BASELINE)),
        "revised" => Ok(("revised".into(), Retraction::REVISED)),
        other => {
            let bad = || {
                CliError::usage(format!(
                    "--retraction {other}: baseline, revised or END_UM:RAMP_S (e.g. 2400:15)"
                ))
            };
            let (e, r) = other.split_once(':').ok_or_else(bad)?;
            let (e, r): (f64, f64) = (
                e.trim().parse().map_err(|_| bad())?,
                r.trim().parse().map_err(|_| bad())?,
            );
            if !(e.is_finite() && r.is_finite() && e > 15.0 && e <= 1e5 && r > 0.0 && r <= 25.0) {
                return Err(CliError::usage(format!(
                    "--retraction {other}: the end must be above the 15 um start (at most 1e5 um) and the ramp within (0, 25] s"
                )));
            }
            Ok((
                format!("{e}um:{r}s"),
                Retraction {
                    g0_m: 15e-6,
                    g_end_m: e * 1e-6,
                    ramp_s: r,
                },
            ))
        }
    }
}

fn capacitance(s: &str) -> Result<Box<dyn PlungerCapacitance>, CliError> {
    let bad = || {
        CliError::usage(format!(
            "--capacitance {s}: disc, disc:RADIUS_MM or sphere:RADIUS_MM"
        ))
    };
    let radius = |r: &str| -> Result<f64, CliError> {
        let v: f64 = r.trim().parse().map_err(|_| bad())?;
        if v.is_finite() && v > 0.0 && v <= 100.0 {
            Ok(v * 1e-3)
        } else {
            Err(bad())
        }
    };
    match s.trim().split_once(':') {
        None if s.trim() == "disc" => Ok(Box::new(default_model())),
        Some(("disc", r)) => Ok(Box::new(FlatDisc {
            radius_m: radius(r)?,
        })),
        Some(("sphere", r)) => Ok(Box::new(SpherePlane {
            radius_m: radius(r)?,
            rel_tol: 1e-10,
        })),
        _ => Err(bad()),
    }
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    if let Some(v) = args
        .voltage
        .iter()
        .find(|v| !(v.is_finite() && v.abs() <= 1e3))
    {
        return Err(CliError::usage(format!(
            "--voltage {v}: a finite TM voltage within +-1000 V"
        )));
    }
    if args.v0.is_nan() || args.v0.abs() > 1e-3 {
        return Err(CliError::usage(format!(
            "--v0 {}: a release velocity within +-1 mm/s",
            args.v0
        )));
    }
    if let Some(p) = &args.plot {
        geodesic_util::output::check_target(p)
            .map_err(|e| CliError::usage(format!("--plot {e}")))?;
    }
    let cap = capacitance(&args.capacitance)?;
    let procs: Vec<(String, Retraction)> = args
        .retraction
        .iter()
        .map(|s| retraction(s))
        .collect::<Result<_, _>>()?;
    let mut cases = Vec::new();
    let mut rows = Vec::new();
    for (name, r) in &procs {
        for &v in &args.voltage {
            let run = simulate(cap.as_ref(), &case(v, args.v0, *r));
            let row = CaseRow::new(name, v, &run);
            rows.push(row);
            // the plot's legend names the procedure; the check's plot takes static names
            let label: &'static str = match name.as_str() {
                "baseline" => "baseline",
                "revised" => "revised",
                _ => "custom",
            };
            cases.push((label, v, run));
        }
    }
    if let Some(p) = &args.plot {
        let svg = plunger_svg(&cases).map_err(CliError::io)?;
        write_atomic(p, svg.as_bytes())?;
    }
    if args.json {
        let doc = PlungerReport {
            capacitance: cap.describe(),
            v0_um_s: args.v0 * 1e6,
            authority_n: geodesic_checks::plunger::AUTHORITY_N,
            duration_s: geodesic_checks::plunger::DURATION_S,
            cases: rows,
        };
        let doc = serde_json::to_value(&doc).map_err(CliError::io)?;
        let text = serde_json::to_string_pretty(&doc).map_err(CliError::io)?;
        println!("{text}");
    } else {
        println!(
            "{}; v0 {:.3} um/s towards plunger 1; {} s; authority {:e} N",
            cap.describe(),
            args.v0 * 1e6,
            geodesic_checks::plunger::DURATION_S,
            geodesic_checks::plunger::AUTHORITY_N
        );
        for r in &rows {
            let head = format!("{:>14} {:5.2} V:", r.retraction, r.v_tm_v);
            let nan = f64::NAN;
            match r.touched_at_s {
                Some(t) => println!(
                    "{head} TOUCHES a plunger at {t:.3} s (velocity change before it {:.4} um/s, growing without bound at contact)",
                    r.extra_velocity_um_s.unwrap_or(nan)
                ),
                None => println!(
                    "{head} extra {:.4} um/s, smallest gap {:.2} um, F/u_max at 4.3 s {}, >= 1 % until {:.2} s",
                    r.extra_velocity_um_s.unwrap_or(nan),
                    r.min_gap_um.unwrap_or(nan),
                    r.force_ratio_at_4_3_s
                        .map_or("-".to_string(), |x| format!("{x:.2e}")),
                    r.force_above_1pct_until_s.unwrap_or(nan)
                ),
            }
        }
    }
    Ok(0)
}
