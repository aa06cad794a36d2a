//! `geodesic montecarlo`: the in-flight release Monte Carlo (physics.md §3, interface.md).
//!
//! Thin: parses flags, loads the budget (embedded default or `--budget FILE`), calls
//! `geodesic_release::montecarlo::run`, prints the summary (one JSON document with `--json`) or
//! writes a partial result with `--shard I/K --out PART.json` for `geodesic merge`.

use crate::error::{CliError, CmdResult};
use geodesic_release::budget::Budget;
use geodesic_release::montecarlo::{self, Case, McResult};
use geodesic_release::population::{AdhesionPopulation, Identification};
use geodesic_release::report::McReport;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Flags of `geodesic montecarlo`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Number of releases of the whole run.
    #[arg(long, default_value_t = montecarlo::DEFAULT_N)]
    pub n: usize,
    /// Seed of the run (draw i uses stream i of ChaCha8 seeded with it).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Uncertainties sampled: all | adhesion | mechanisms.
    #[arg(long, default_value = "all")]
    pub case: String,
    /// The release budget (`--budget`, the flag the descriptor's input declares: added by
    /// `Reading::reading` in `cmd/mod.rs`).
    #[arg(skip)]
    pub budget: Option<PathBuf>,
    /// Run only shard I of K (1-based) and write it with --out.
    #[arg(long, value_name = "I/K", requires = "out")]
    pub shard: Option<String>,
    /// Write the (partial) result to this JSON file for `geodesic merge`.
    #[arg(long, value_name = "PART.json")]
    pub out: Option<PathBuf>,
    /// Take the adhesion from a campaign result (`geodesic campaign --json`): its population of
    /// A1 and lambda replaces the budget's adhesion, and `p9973_interval_um_s` and
    /// `probability_met` then include the population's identification uncertainty.
    #[arg(long = "adhesion-from", value_name = "CAMPAIGN.json")]
    pub adhesion_from: Option<PathBuf>,
    /// Runs drawn from the population's identification uncertainty (with --adhesion-from or a
    /// budget's adhesion_from), each of N / 10 releases.
    #[arg(long = "population-draws", default_value_t = 20)]
    pub population_draws: usize,
    /// Write an SVG histogram of |X'| to this file.
    #[arg(long, value_name = "FILE.svg")]
    pub histogram: Option<PathBuf>,
    /// Worker threads (default: all cores); results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// The JSON text of a partial result, sealed with its checksum (`geodesic_release::parts::sealed_json`).
pub fn sealed_json(r: &McResult) -> Result<Vec<u8>, CliError> {
    geodesic_release::parts::sealed_json(r).map_err(CliError::io)
}

/// Parses `I/K`.
fn parse_shard(s: &str) -> Result<(usize, usize), CliError> {
    let bad = || {
        CliError::usage(format!(
            "--shard {s}: expected I/K with 1 <= I <= K, e.g. 3/8"
        ))
    };
    let (i, k) = s.split_once('/').ok_or_else(bad)?;
    let (i, k): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        k.trim().parse().map_err(|_| bad())?,
    );
    if i == 0 || k == 0 || i > k {
        return Err(bad());
    }
    Ok((i, k))
}

/// REL-GPRM-VEL's limit [um/s] from the requirements `verify` would load (`./requirements`
/// when run from the repository's root, else the built-in set): the limit against which
/// `probability_met` is judged and the histogram's red line.
fn limit_um_s() -> Result<f64, CliError> {
    let (reqs, _, _) = crate::missions::load_requirements(None)?;
    geodesic_checks::release::gprm_limit_um_s(&reqs).map_err(CliError::from)
}

/// Writes the histogram SVG of |X'| with the limit `limit_um_s` [um/s] if asked.
fn write_histogram(r: &McResult, limit_um_s: f64, path: Option<&Path>) -> Result<(), CliError> {
    if let Some(p) = path {
        let svg = geodesic_checks::release::mc_histogram_svg(r, Some(limit_um_s));
        geodesic_util::output::write_atomic(p, svg.as_bytes())?;
    }
    Ok(())
}

/// Checks the flags before any work: the case, N, threads, the output and the shard.
fn checked(args: &Args) -> Result<(Case, Option<(usize, usize)>), CliError> {
    let case: Case = args
        .case
        .parse()
        .map_err(|e: montecarlo::McError| CliError::usage(format!("--case: {e}")))?;
    if args.n == 0 || args.n > montecarlo::MAX_N {
        return Err(CliError::usage(format!(
            "--n {}: must be 1 to {}",
            args.n,
            montecarlo::MAX_N
        )));
    }
    crate::threads::check_threads(args.threads)?;
    if let Some(out) = &args.out {
        crate::preflight::out_file("--out", out)?;
    }
    let shard = args.shard.as_deref().map(parse_shard).transpose()?;
    if let Some((_, k)) = shard {
        montecarlo::check_size(args.n, Some(k))
            .map_err(|e| CliError::usage(format!("--shard: {e}")))?;
    }
    Ok((case, shard))
}

/// The budget with `--adhesion-from` (or the budget's own `adhesion_from`) applied, and that
/// campaign's population.
fn budget_and_population(
    args: &Args,
    budget_file: &geodesic_core::check::InputFile,
) -> Result<(Budget, Option<AdhesionPopulation>), CliError> {
    let (mut budget, mut population) =
        geodesic_checks::release::budget_from_file(budget_file).map_err(CliError::from)?;
    if let Some(p) = &args.adhesion_from {
        let text =
            geodesic_util::fsio::read_text(p, geodesic_util::fsio::MAX_CSV_BYTES).map_err(|e| {
                CliError::usage(format!("--adhesion-from {}: {}", p.display(), e.cause()))
            })?;
        let pop = AdhesionPopulation::from_campaign_json(&text, &p.display().to_string())
            .map_err(|e| CliError::malformed(e).in_file(p, 0))?;
        budget = pop.apply(&budget).map_err(CliError::invalid)?;
        population = Some(pop);
    }
    Ok((budget, population))
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let (case, shard) = checked(&args)?;
    let limit = limit_um_s()?;
    let budget_file =
        crate::inputs::resolve(crate::inputs::ModelInput::budget(), args.budget.as_deref())?;
    crate::inputs::announce(args.json, crate::inputs::ModelInput::budget(), &budget_file);
    let (budget, population) = budget_and_population(&args, &budget_file)?;
    if population.is_some() && shard.is_some() {
        return Err(CliError::usage(
            "--shard with a campaign population: run the identification-uncertainty draws unsharded",
        ));
    }
    if population.is_some() && !(1..=1000).contains(&args.population_draws) {
        return Err(CliError::usage(format!(
            "--population-draws {}: between 1 and 1000",
            args.population_draws
        )));
    }
    let draws = match shard {
        Some((i, k)) => montecarlo::shard_range(args.n, i, k)
            .map_err(|e| CliError::usage(e.to_string()))?
            .len(),
        None => args.n,
    };
    let bar = crate::progress::Task::counter(args.json, "montecarlo: releases", draws as u64);
    let t0 = Instant::now();
    let go = || montecarlo::run(&budget, case, args.n, args.seed, shard, &|k| bar.inc(k));
    let mut result = crate::threads::with_threads(args.threads, go)?.map_err(|e| {
        CliError::model(
            Some("montecarlo"),
            format!("montecarlo ({}): {e}", budget_file.label),
        )
    })?;
    // the budget is identified as every command identifies it: the SHA-256 of the file's bytes
    // (partial results of one run carry it, and `merge` refuses parts of different budgets)
    result.budget_hash = budget_file.sha256.clone();
    result.budget_source = Some(geodesic_release::montecarlo::BudgetSource {
        label: budget_file.label.clone(),
        origin: serde_json::to_value(budget_file.origin)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_else(|| "given".into()),
    });
    bar.finish();
    let seconds = t0.elapsed().as_secs_f64();
    if let Some(out) = &args.out {
        geodesic_util::output::write_atomic(out, &sealed_json(&result)?)?;
    }
    write_histogram(&result, limit, args.histogram.as_deref())?;
    // the identification uncertainty of a campaign population: repeated runs, each with a
    // population drawn from it (seeded from the run's seed; deterministic)
    let identification = match &population {
        Some(pop) => Some(identification_runs(pop, &budget, case, &args)?),
        None => None,
    };
    let mut report = McReport::new(&result, result.summary(), seconds, limit);
    if let (Some(pop), Some(id)) = (&population, &identification) {
        report = report.with_identification(pop, id);
    }
    if let Some((i, k)) = shard {
        report.shard = Some(format!("{i}/{k}"));
        report.draws = Some(result.v_m_s.len());
    }
    report.out = args.out.as_ref().map(|o| o.display().to_string());
    if args.json {
        print_json(&report)?;
    } else {
        print_text(
            &args,
            &report,
            &budget_file,
            population.as_ref().zip(identification.as_ref()),
        );
    }
    Ok(0)
}

/// Prints a report as one JSON document (through `serde_json::Value`: keys in alphabetical
/// order, as interface.md's consumers have always read them).
fn print_json(report: &McReport) -> Result<(), CliError> {
    let v = serde_json::to_value(report).map_err(CliError::io)?;
    println!("{v}");
    Ok(())
}

/// Prints a run's report as text.
fn print_text(
    args: &Args,
    report: &McReport,
    budget_file: &geodesic_core::check::InputFile,
    identification: Option<(&AdhesionPopulation, &Identification)>,
) {
    let s = &report.summary;
    if let (Some(shard), Some(draws)) = (&report.shard, report.draws) {
        println!(
            "shard {shard}: {draws} of {} draws (statistics below are of this shard only)",
            args.n
        );
    }
    for line in s.text_lines() {
        println!("{line}");
    }
    println!(
        "  {}: {}",
        crate::inputs::line(crate::inputs::ModelInput::budget(), budget_file),
        s.budget
    );
    println!("  {:.2} s", report.seconds);
    if let Some((pop, id)) = identification {
        print_identification(pop, id, report.limit_um_s);
    }
    if let Some(out) = &args.out {
        println!("  partial result written to {}", out.display());
    }
}

/// Prints the campaign population and the identification uncertainty of the 99.73 % point.
fn print_identification(pop: &AdhesionPopulation, id: &Identification, limit_um_s: f64) {
    println!(
        "  adhesion from {}: A1 {:.4e} +- {:.2e} (spread {:.3e}), lambda {:.4e} +- {:.2e} (spread {:.3e})",
        pop.source,
        pop.a1.mean,
        pop.a1.mean_sigma,
        pop.a1.sd,
        pop.lambda.mean,
        pop.lambda.mean_sigma,
        pop.lambda.sd
    );
    println!(
        "  99.73 % with identification uncertainty: 95 % interval [{:.4}, {:.4}] um/s over {} population draws; P(<= {limit_um_s} um/s) = {:.3}",
        id.interval_um_s[0],
        id.interval_um_s[1],
        id.p9973_um_s.len(),
        id.probability_met(limit_um_s)
    );
    match (pop.rho, pop.rho_ci95) {
        (Some(r), Some([lo, hi])) => println!(
            "  A1-lambda correlation {r:+.2} (95 % [{lo:+.2}, {hi:+.2}]) used in the draws (Gaussian copula)"
        ),
        (Some(r), None) => println!(
            "  A1-lambda correlation {r:+.2} used in the draws (Gaussian copula; Fisher 1/sqrt(n-3) uncertainty)"
        ),
        _ => println!("  the campaign states no A1-lambda correlation: drawn independently"),
    }
}

fn identification_runs(
    pop: &AdhesionPopulation,
    budget: &Budget,
    case: Case,
    args: &Args,
) -> Result<Identification, CliError> {
    let n_each = (args.n / 10).max(1000);
    let bar = crate::progress::Task::counter(
        args.json,
        "montecarlo: population draws",
        (args.population_draws * n_each) as u64,
    );
    let go = || {
        geodesic_release::population::identification(
            pop,
            budget,
            case,
            n_each,
            args.population_draws,
            args.seed,
            &|d| bar.inc(d),
        )
    };
    let r = crate::threads::with_threads(args.threads, go)?
        .map_err(|e| CliError::model(Some("population identification"), e))?;
    bar.finish();
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_syntax() {
        assert_eq!(parse_shard("2/5").unwrap(), (2, 5));
        assert!(parse_shard("0/5").is_err());
        assert!(parse_shard("6/5").is_err());
        assert!(parse_shard("x").is_err());
    }
}
