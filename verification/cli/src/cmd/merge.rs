//! `geodesic merge`: combines the partial results written by `geodesic montecarlo --shard I/K
//! --out PART.json` into the summary of the whole run, identical to an unsharded run with the
//! same N and seed (interface.md). Missing, duplicate or foreign shards are bad input (exit 2).

use crate::cmd::montecarlo::{print_text, summary_json, write_histogram};
use crate::error::{CliError, CmdResult};
use geodesic_release::montecarlo::{self, McResult};
use std::path::PathBuf;
use std::time::Instant;

/// Flags of `geodesic merge`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Partial results (JSON) of every shard of one run.
    #[arg(required = true, value_name = "PART.json")]
    pub parts: Vec<PathBuf>,
    /// Write an SVG histogram of |X'| to this file.
    #[arg(long, value_name = "FILE.svg")]
    pub histogram: Option<PathBuf>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let t0 = Instant::now();
    let mut parts = Vec::with_capacity(args.parts.len());
    for p in &args.parts {
        let text = std::fs::read_to_string(p)
            .map_err(|e| CliError::bad(format!("{}:0: {e}", p.display())))?;
        let r: McResult = serde_json::from_str(&text).map_err(|e| {
            CliError::bad(format!(
                "{}:{}: not a geodesic montecarlo partial result: {e}",
                p.display(),
                e.line()
            ))
        })?;
        parts.push(r);
    }
    let merged = montecarlo::merge(parts).map_err(|e| CliError::bad(format!("merge: {e}")))?;
    write_histogram(&merged, args.histogram.as_deref())?;
    let seconds = t0.elapsed().as_secs_f64();
    let summary = merged.summary();
    if args.json {
        println!("{}", summary_json(&summary, seconds));
    } else {
        print_text(&summary, seconds);
    }
    Ok(0)
}
