//! `geodesic merge`: combines the partial results written by `geodesic montecarlo --shard I/K
//! --out PART.json` into the summary of the whole run, identical to an unsharded run with the
//! same N and seed (interface.md). Missing, duplicate or foreign shards are bad input (exit 2).

use crate::error::{CliError, CmdResult};
use geodesic_release::montecarlo::{self, McResult};
use geodesic_release::parts;
use geodesic_release::report::McReport;
use std::path::{Path, PathBuf};
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

/// Reads one partial result, refusing a non-regular or oversized file and anything that is not
/// exactly what `montecarlo --shard` wrote ([`parts::parse_part`]). Errors name the file.
fn read_part(p: &Path) -> Result<McResult, CliError> {
    let file = p.display().to_string();
    let text = geodesic_util::fsio::read_text(p, MAX_PART_BYTES)
        .map_err(|e| CliError::unreadable(format!("{file}: {e}")).in_file(p, e.line()))?;
    parts::parse_part(&file, &text).map_err(|e| CliError::malformed(e).in_file(p, 0))
}

/// Largest partial result read [bytes]: 20 digits per draw of the largest run, plus slack.
const MAX_PART_BYTES: u64 = 24 * montecarlo::MAX_N as u64 + (1 << 20);

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let t0 = Instant::now();
    let limit = limit_um_s()?;
    let mut parts: Vec<McResult> = Vec::with_capacity(args.parts.len().min(montecarlo::MAX_SHARDS));
    let mut names: Vec<String> = Vec::new();
    for p in &args.parts {
        let r = read_part(p)?;
        let file = p.display().to_string();
        if let (Some(first), Some(fname)) = (parts.first(), names.first()) {
            let same = r.n == first.n
                && r.seed == first.seed
                && r.case == first.case
                && r.budget_hash == first.budget_hash
                && r.shard.map(|s| s.1) == first.shard.map(|s| s.1);
            if !same {
                return Err(CliError::conflict(format!(
                    "{file}: from another run than {fname} (n {} vs {}, seed {} vs {}, case {} vs {}, budget {} vs {}, shards {} vs {})",
                    r.n,
                    first.n,
                    r.seed,
                    first.seed,
                    r.case,
                    first.case,
                    r.budget_hash,
                    first.budget_hash,
                    r.shard.map_or(1, |s| s.1),
                    first.shard.map_or(1, |s| s.1)
                )));
            }
        }
        if let Some(j) = parts.iter().position(|q| q.shard == r.shard) {
            let (i, k) = r.shard.unwrap_or((1, 1));
            return Err(CliError::conflict(format!(
                "{file}: shard {i}/{k} given twice (also {})",
                names[j]
            )));
        }
        parts.push(r);
        names.push(file);
    }
    let merged = montecarlo::merge(parts)
        .map_err(|e| CliError::conflict(format!("merge of {}: {e}", names.join(", "))))?;
    if let Some(p) = args.histogram.as_deref() {
        let svg = geodesic_checks::release::mc_histogram_svg(&merged, Some(limit));
        geodesic_util::output::write_atomic(p, svg.as_bytes())?;
    }
    let seconds = t0.elapsed().as_secs_f64();
    let summary = merged.summary();
    if args.json {
        let report = McReport::new(&merged, summary, seconds, limit);
        let v = serde_json::to_value(&report).map_err(CliError::io)?;
        println!("{v}");
    } else {
        for line in summary.text_lines() {
            println!("{line}");
        }
        println!(
            "  budget sha256 {} ({})",
            summary.budget_hash, summary.budget
        );
        println!("  {seconds:.2} s");
        if let Some(b) = &merged.budget_source {
            println!(
                "  release budget read by the parts: {} ({})",
                b.label, b.origin
            );
        }
    }
    Ok(0)
}

/// REL-GPRM-VEL's limit [um/s] from the requirements `verify` would load (`./requirements`
/// when run from the repository's root, else the built-in set).
fn limit_um_s() -> Result<f64, CliError> {
    let (reqs, _, _) = crate::missions::load_requirements(None)?;
    geodesic_checks::release::gprm_limit_um_s(&reqs).map_err(CliError::from)
}
