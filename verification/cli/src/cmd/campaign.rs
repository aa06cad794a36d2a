//! `geodesic campaign DIR|CAMPAIGN.yaml --effects E`: fits every release of a campaign in
//! parallel, tabulates P_x, F_peak and dt as the thesis does (ch. 5), and estimates the adhesion
//! population with the measurement errors deconvolved (issue 14; interface.md). Thin: the work
//! is in `geodesic_fit::campaign`.

use crate::cmd::fit::{effect_list, options};
use crate::error::{CliError, CmdResult};
use std::path::PathBuf;

/// Flags of `geodesic campaign`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  geodesic synth --campaign 30 --out camp --seed 4\n  geodesic campaign camp/campaign.yaml --effects needle_contact,tip_contact,tip_adhesion\n  geodesic campaign camp --effects needle_contact,tip_contact,tip_adhesion --json > campaign.json\n\
A release that cannot be fitted is listed with its file and cause (exit 2 after the table)."
)]
pub struct Args {
    /// A folder of release datasets (every YAML with `scenario:`) or a campaign YAML with
    /// `releases: [file, ...]`.
    #[arg(value_name = "DIR_OR_LIST")]
    pub campaign: PathBuf,
    /// Effects of the model fitted to every release, comma separated.
    #[arg(long, value_delimiter = ',', required = true)]
    pub effects: Vec<String>,
    /// Hold a parameter fixed: effect.param=VALUE, repeatable.
    #[arg(long = "fix", value_name = "NAME=VALUE")]
    pub fix: Vec<String>,
    /// Bound a parameter: effect.param=LO:HI, repeatable.
    #[arg(long = "bound", value_name = "NAME=LO:HI")]
    pub bound: Vec<String>,
    /// Seed of the population's bootstrap.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let opts = options(&args.fix, &args.bound)?;
    let files =
        geodesic_fit::campaign::list(&args.campaign).map_err(|e| CliError::bad(e.to_string()))?;
    let effects = effect_list(&args.effects);
    let task =
        crate::progress::Task::counter(args.json, "campaign: releases fitted", files.len() as u64);
    let r = geodesic_fit::campaign::run(&files, &effects, &opts, args.seed, &|| task.inc(1));
    task.finish();
    for f in &r.failed {
        eprintln!(
            "geodesic: {}: not fitted: {}",
            f.file,
            geodesic_core::text::one_line(&f.cause)
        );
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&r).map_err(|e| CliError::Io(e.to_string()))?
        );
    } else {
        println!(
            "{} releases fitted, {} failed ({})",
            r.releases.len(),
            r.failed.len(),
            args.campaign.display()
        );
        println!(
            "quantity        source    mean         sd           sd of mean   min          max"
        );
        for (q, m) in &r.table {
            for (src, s) in m {
                match s {
                    Some(s) => println!(
                        "{q:<15} {src:<8} {:>12.4e} {:>12.4e} {:>12.4e} {:>12.4e} {:>12.4e}",
                        s.mean, s.sd, s.sd_mean, s.min, s.max
                    ),
                    None => println!(
                        "{q:<15} {src:<8} (not derived from the data: see docs/fitting.md)"
                    ),
                }
            }
        }
        if let Some(obj) = r.population.as_object() {
            for (k, v) in obj {
                if k == "correlation" {
                    println!("population correlation: {v}");
                } else {
                    println!(
                        "population {k}: mean {:.4e} +- {:.2e}, sd {:.4e} +- {:.2e} ({} releases)",
                        v["mean"].as_f64().unwrap_or(f64::NAN),
                        v["mean_sigma"].as_f64().unwrap_or(f64::NAN),
                        v["sd"].as_f64().unwrap_or(f64::NAN),
                        v["sd_sigma"].as_f64().unwrap_or(f64::NAN),
                        v["n"]
                    );
                }
            }
        }
    }
    Ok(if r.failed.is_empty() { 0 } else { 2 })
}
