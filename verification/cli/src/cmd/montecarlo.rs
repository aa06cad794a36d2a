//! `geodesic montecarlo`: the in-flight release Monte Carlo (physics.md §3, interface.md).
//!
//! Thin: parses flags, loads the budget (embedded default or `--budget FILE`), calls
//! `geodesic_release::montecarlo::run`, prints the summary (one JSON document with `--json`) or
//! writes a partial result with `--shard I/K --out PART.json` for `geodesic merge`.

use crate::error::{CliError, CmdResult};
use geodesic_release::budget::Budget;
use geodesic_release::montecarlo::{self, Case, McResult, Summary};
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
    /// Uncertainty budget YAML [default: ./models/release/budget.yaml if present, else the
    /// built-in copy; as verify].
    #[arg(long, value_name = "FILE")]
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

/// Largest `--threads`.
pub const MAX_THREADS: usize = 1024;

/// Checks `--threads`: 1..=[`MAX_THREADS`].
pub fn check_threads(t: Option<usize>) -> Result<(), CliError> {
    match t {
        Some(t) if t == 0 || t > MAX_THREADS => Err(CliError::bad(format!(
            "--threads {t}: must be 1 to {MAX_THREADS}"
        ))),
        _ => Ok(()),
    }
}

/// Runs `go` on a pool of `threads` workers (`--threads`), or on rayon's global pool. The
/// results do not depend on it (every draw has its own random stream).
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    go: impl FnOnce() -> R + Send,
) -> Result<R, CliError> {
    Ok(match threads {
        Some(t) => rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .map_err(|e| CliError::bad(format!("--threads: {e}")))?
            .install(go),
        None => go(),
    })
}

/// The JSON text of a partial result, sealed with its checksum (`geodesic_release::parts::sealed_json`).
pub fn sealed_json(r: &McResult) -> Result<Vec<u8>, CliError> {
    geodesic_release::parts::sealed_json(r).map_err(CliError::Io)
}

/// Parses `I/K`.
fn parse_shard(s: &str) -> Result<(usize, usize), CliError> {
    let bad = || {
        CliError::bad(format!(
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

/// The budget file: `--budget FILE`, else the repository's `models/release/budget.yaml` when
/// run from the repository's root, else the built-in copy ([`crate::inputs::resolve`], as
/// `verify` reads it).
pub fn budget_input(path: Option<&Path>) -> Result<geodesic_core::check::InputFile, CliError> {
    crate::inputs::resolve(crate::inputs::ModelInput::Budget, path)
}

/// Parses a resolved budget file, with its `adhesion_from` applied (the campaign's population;
/// path relative to the budget file).
pub fn load_budget(file: &geodesic_core::check::InputFile) -> Result<Budget, CliError> {
    Ok(load_budget_with_population(file)?.0)
}

/// [`load_budget`], also returning the campaign population the budget names, if any.
pub fn load_budget_with_population(
    file: &geodesic_core::check::InputFile,
) -> Result<
    (
        Budget,
        Option<geodesic_release::population::AdhesionPopulation>,
    ),
    CliError,
> {
    let b = Budget::from_yaml(&file.text, &file.label).map_err(|e| CliError::bad(e.to_string()))?;
    let on_disk = file.origin != Some(geodesic_core::check::InputOrigin::BuiltIn);
    geodesic_release::population::resolve(b, on_disk.then(|| Path::new(&file.label)))
        .map_err(CliError::bad)
}

/// Writes `bytes` to `path` whole or not at all (temporary file, then rename; nothing left
/// behind on failure or interruption).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CliError> {
    geodesic_core::output::write_atomic(path, bytes)
        .map(|_| ())
        .map_err(|e| CliError::Io(e.to_string()))
}

/// The JSON document of a summary plus wall time (interface.md keys first).
pub fn summary_json(s: &Summary, seconds: f64) -> serde_json::Value {
    let mut v = serde_json::to_value(s).expect("summary serialises");
    v["seconds"] = serde_json::json!(seconds);
    v
}

/// REL-GPRM-VEL's limit on |X'| [um/s], against which `probability_met` is judged.
pub const LIMIT_UM_S: f64 = 5.0;

/// Adds interface.md's `p9973_interval_um_s` (95 % distribution-free interval of the 99.73 %
/// point) and `probability_met` (probability that the 99.73 % point is at or below 5 um/s) to a
/// summary; both measure the Monte Carlo's sampling uncertainty only (the adhesion budget is
/// taken as known: the identification uncertainty of a campaign is not propagated yet).
pub fn add_uncertainty(v: &mut serde_json::Value, r: &McResult) {
    use geodesic_release::stats::{probability_quantile_below, quantile_interval_sorted};
    let mut abs = r.abs_um_s();
    abs.sort_by(f64::total_cmp);
    let exceed = abs.iter().filter(|x| **x > LIMIT_UM_S).count();
    v["p9973_interval_um_s"] = serde_json::json!(quantile_interval_sorted(&abs, 0.9973));
    v["probability_met"] = serde_json::json!(probability_quantile_below(abs.len(), exceed, 0.9973));
    v["limit_um_s"] = serde_json::json!(LIMIT_UM_S);
    v["uncertainty"] = serde_json::json!(
        "Monte Carlo sampling only (adhesion identification uncertainty not propagated)"
    );
}

/// Adds `inputs.budget` (`{label, sha256, origin}`, as every command says which budget it
/// read) from the budget source a run (or the partial results of one) carries.
pub fn add_inputs(v: &mut serde_json::Value, r: &McResult) {
    if let Some(s) = &r.budget_source {
        v["inputs"] = serde_json::json!({"budget": {
            "label": s.label,
            "sha256": r.budget_hash,
            "origin": s.origin,
        }});
    }
}

/// Prints a summary as text; `budget`: the budget file read (merge has only its hash).
pub fn print_text(s: &Summary, seconds: f64, budget: Option<&geodesic_core::check::InputFile>) {
    println!(
        "in-flight release Monte Carlo: case {}, N = {}, seed {}",
        s.case, s.n, s.seed
    );
    println!("  |X'| 99.73 %  {:.4} um/s", s.p9973_um_s);
    println!("  |X'| 99 %     {:.4} um/s", s.p99_um_s);
    println!("  |X'| median   {:.4} um/s", s.p50_um_s);
    println!("  |X'| mean     {:.4} um/s", s.mean_um_s);
    println!("  |X'| max      {:.4} um/s", s.max_um_s);
    println!(
        "  X' mean, sd   {:+.4}, {:.4} um/s",
        s.signed_mean_um_s, s.sd_um_s
    );
    println!("  fallback stops {}", s.fallback_stops);
    match budget {
        Some(f) => println!(
            "  {}: {}",
            crate::inputs::line(crate::inputs::ModelInput::Budget, f),
            s.budget
        ),
        None => println!("  budget sha256 {} ({})", s.budget_hash, s.budget),
    }
    println!("  {seconds:.2} s");
}

/// Writes the histogram SVG if asked.
pub fn write_histogram(r: &McResult, path: Option<&Path>) -> Result<(), CliError> {
    if let Some(p) = path {
        write_atomic(p, r.histogram_svg(Some(5.0)).as_bytes())?;
    }
    Ok(())
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let case: Case = args
        .case
        .parse()
        .map_err(|e: montecarlo::McError| CliError::bad(format!("--case: {e}")))?;
    if args.n == 0 || args.n > montecarlo::MAX_N {
        return Err(CliError::bad(format!(
            "--n {}: must be 1 to {}",
            args.n,
            montecarlo::MAX_N
        )));
    }
    check_threads(args.threads)?;
    if let Some(out) = &args.out {
        crate::preflight::out_file("--out", out)?;
    }
    let shard = args.shard.as_deref().map(parse_shard).transpose()?;
    if let Some((_, k)) = shard {
        montecarlo::check_size(args.n, Some(k))
            .map_err(|e| CliError::bad(format!("--shard: {e}")))?;
    }
    let budget_file = budget_input(args.budget.as_deref())?;
    crate::inputs::announce(args.json, crate::inputs::ModelInput::Budget, &budget_file);
    let (mut budget, mut population) = load_budget_with_population(&budget_file)?;
    if let Some(p) = &args.adhesion_from {
        let text =
            geodesic_core::fsio::read_text(p, geodesic_core::fsio::MAX_CSV_BYTES).map_err(|e| {
                CliError::bad(format!("--adhesion-from {}: {}", p.display(), e.cause()))
            })?;
        let pop = geodesic_release::population::AdhesionPopulation::from_campaign_json(
            &text,
            &p.display().to_string(),
        )
        .map_err(CliError::bad)?;
        budget = pop.apply(&budget).map_err(CliError::bad)?;
        population = Some(pop);
    }
    if population.is_some() && shard.is_some() {
        return Err(CliError::bad(
            "--shard with a campaign population: run the identification-uncertainty draws unsharded",
        ));
    }
    if population.is_some() && !(1..=1000).contains(&args.population_draws) {
        return Err(CliError::bad(format!(
            "--population-draws {}: between 1 and 1000",
            args.population_draws
        )));
    }
    let draws = match shard {
        Some((i, k)) => montecarlo::shard_range(args.n, i, k)
            .map_err(|e| CliError::bad(e.to_string()))?
            .len(),
        None => args.n,
    };
    let bar = crate::progress::Task::counter(args.json, "montecarlo: releases", draws as u64);
    let t0 = Instant::now();
    let go = || montecarlo::run(&budget, case, args.n, args.seed, shard, &|k| bar.inc(k));
    let mut result = with_threads(args.threads, go)?
        .map_err(|e| CliError::bad(format!("montecarlo ({}): {e}", budget_file.label)))?;
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
        write_atomic(out, &sealed_json(&result)?)?;
    }
    write_histogram(&result, args.histogram.as_deref())?;
    let summary = result.summary();
    // the identification uncertainty of a campaign population: repeated runs, each with a
    // population drawn from it (seeded from the run's seed; deterministic)
    let identification = match &population {
        Some(pop) => Some(identification_runs(pop, &budget, case, &args)?),
        None => None,
    };
    if args.json {
        let mut v = summary_json(&summary, seconds);
        add_uncertainty(&mut v, &result);
        add_inputs(&mut v, &result);
        if let (Some(pop), Some(id)) = (&population, &identification) {
            v["p9973_interval_um_s"] = serde_json::json!(id.interval_um_s);
            v["probability_met"] = serde_json::json!(id.probability_met(LIMIT_UM_S));
            v["uncertainty"] = serde_json::json!(format!(
                "adhesion identification (the campaign population's mean, spread and A1-lambda correlation drawn {} times from their uncertainty, N / 10 releases each) and Monte Carlo sampling",
                id.p9973_um_s.len()
            ));
            v["adhesion_from"] = serde_json::json!({
                "source": pop.source,
                "population": pop,
                "correlation_used": pop.rho.is_some(),
                "draws_p9973_um_s": id.p9973_um_s,
                "releases_per_draw": id.n_each,
            });
        }
        if let Some((i, k)) = shard {
            v["shard"] = serde_json::json!(format!("{i}/{k}"));
            v["draws"] = serde_json::json!(result.v_m_s.len());
        }
        if let Some(out) = &args.out {
            v["out"] = serde_json::json!(out.display().to_string());
        }
        println!("{v}");
    } else {
        if let Some((i, k)) = shard {
            println!(
                "shard {i}/{k}: {} of {} draws (statistics below are of this shard only)",
                result.v_m_s.len(),
                args.n
            );
        }
        print_text(&summary, seconds, Some(&budget_file));
        if let (Some(pop), Some(id)) = (&population, &identification) {
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
                "  99.73 % with identification uncertainty: 95 % interval [{:.4}, {:.4}] um/s over {} population draws; P(<= {LIMIT_UM_S} um/s) = {:.3}",
                id.interval_um_s[0],
                id.interval_um_s[1],
                id.p9973_um_s.len(),
                id.probability_met(LIMIT_UM_S)
            );
            match (pop.rho, pop.rho_ci95) {
                (Some(r), Some([lo, hi])) => println!(
                    "  A1-lambda correlation {r:+.2} (95 % [{lo:+.2}, {hi:+.2}]) used in the draws (Gaussian copula)"
                ),
                (Some(r), None) => println!(
                    "  A1-lambda correlation {r:+.2} used in the draws (Gaussian copula; Fisher 1/sqrt(n-3) uncertainty)"
                ),
                _ => {
                    println!("  the campaign states no A1-lambda correlation: drawn independently")
                }
            }
        }
        if let Some(out) = &args.out {
            println!("  partial result written to {}", out.display());
        }
    }
    Ok(0)
}

fn identification_runs(
    pop: &geodesic_release::population::AdhesionPopulation,
    budget: &Budget,
    case: Case,
    args: &Args,
) -> Result<geodesic_release::population::Identification, CliError> {
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
    let r = with_threads(args.threads, go)?.map_err(CliError::bad)?;
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
