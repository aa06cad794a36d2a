//! `geodesic sensitivity --n N --seed S`: what drives the release velocity (issue 14 item 4;
//! interface.md). Variance-based first-order (Saltelli) and total (Jansen) indices of `|v_TM|`
//! for each uncertainty group of the budget, with bootstrap intervals, and the shift of the
//! 99.73 % point when each group is frozen at nominal. Thin: the estimators are in
//! `geodesic_release::sensitivity`.

use crate::error::{CliError, CmdResult};
use crate::threads::{check_threads, with_threads};
use geodesic_core::check::{InputFile, InputOrigin};
use geodesic_release::sensitivity::{release_groups, release_sensitivity};
use serde::Serialize;
use std::path::PathBuf;

/// Flags of `geodesic sensitivity`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  geodesic sensitivity --n 4000 --seed 1\n  geodesic sensitivity --n 20000 --seed 7 --budget my-budget.yaml --json\n\
Costs (groups + 2) x N + groups x N releases (9 and 7 groups x N: 16 N; N = 4000 takes a few\n\
seconds on 2 cores). first + ... should not exceed 1 (interactions make the rest); total >= first."
)]
pub struct Args {
    /// Draws per sample matrix.
    #[arg(long, default_value_t = 4000)]
    pub n: usize,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The release budget (`--budget`, the flag the descriptor's input declares: added by
    /// `Reading::reading` in `cmd/mod.rs`).
    #[arg(skip)]
    pub budget: Option<PathBuf>,
    /// Worker threads (results do not depend on it).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    check_threads(args.threads)?;
    if args.n < 100 || args.n > 1_000_000 {
        return Err(CliError::usage(format!(
            "--n {}: between 100 and 1 000 000 draws per sample matrix",
            args.n
        )));
    }
    let budget_file =
        crate::inputs::resolve(crate::inputs::ModelInput::budget(), args.budget.as_deref())?;
    crate::inputs::announce(args.json, crate::inputs::ModelInput::budget(), &budget_file);
    let (budget, _) =
        geodesic_checks::release::budget_from_file(&budget_file).map_err(CliError::from)?;
    let groups = release_groups().len() as u64;
    let task = crate::progress::Task::counter(
        args.json,
        "sensitivity: releases",
        (2 * groups + 4) * args.n as u64,
    );
    let go = || release_sensitivity(&budget, args.n, args.seed, &|k| task.inc(k));
    let r = with_threads(args.threads, go)?
        .map_err(|e| CliError::model(Some("sensitivity"), e.to_string()));
    task.finish();
    let r = r?;
    if args.json {
        let doc = SensitivityDoc {
            groups: r
                .groups
                .iter()
                .map(|(g, shift)| GroupDoc {
                    first: g.first,
                    first_ci: g.first_ci,
                    group: g.group.clone(),
                    p9973_shift_um_s: *shift,
                    total: g.total,
                    total_ci: g.total_ci,
                })
                .collect(),
            inputs: SensitivityInputs {
                budget: InputDoc::of(&budget_file),
            },
            n: r.n,
            output: "|v_TM| [um/s]".to_string(),
            p9973_um_s: r.p9973_um_s,
            seed: r.seed,
            sum_first: r.groups.iter().map(|(g, _)| g.first).sum::<f64>(),
            variance_um2_s2: r.variance_um2_s2,
        };
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).map_err(CliError::io)?
        );
        return Ok(0);
    }
    println!(
        "{}",
        crate::inputs::line(crate::inputs::ModelInput::budget(), &budget_file)
    );
    println!(
        "|v_TM| over {} x 2 draws (seed {}): 99.73 % point {:.3} um/s, variance {:.4} (um/s)^2",
        r.n, r.seed, r.p9973_um_s, r.variance_um2_s2
    );
    println!(
        "group                 first   95 % interval        total   95 % interval    99.73 % shift when frozen"
    );
    for (g, shift) in &r.groups {
        println!(
            "{:<20} {:>6.3}  [{:>6.3}, {:>6.3}]   {:>6.3}  [{:>6.3}, {:>6.3}]   {:+.3} um/s",
            g.group,
            g.first,
            g.first_ci[0],
            g.first_ci[1],
            g.total,
            g.total_ci[0],
            g.total_ci[1],
            shift
        );
    }
    println!(
        "sum of first-order indices {:.3} (the rest is interactions)",
        r.groups.iter().map(|(g, _)| g.first).sum::<f64>()
    );
    Ok(0)
}

/// The JSON document of `geodesic sensitivity --json` (interface.md). Fields are declared in
/// byte order of their keys, the order the document has always printed.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct SensitivityDoc {
    /// Sobol indices per input group.
    pub groups: Vec<GroupDoc>,
    /// The model inputs read.
    pub inputs: SensitivityInputs,
    /// Base sample size of the Sobol design.
    pub n: usize,
    /// The output analysed and its unit (`|v_TM| [um/s]`).
    pub output: String,
    /// 99.73rd percentile of the output [um/s].
    pub p9973_um_s: f64,
    /// Seed of the design.
    pub seed: u64,
    /// Sum of the first-order indices (dimensionless).
    pub sum_first: f64,
    /// Variance of the output [um^2/s^2].
    pub variance_um2_s2: f64,
}

/// One group of [`SensitivityDoc`], in byte order of its keys.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct GroupDoc {
    /// First-order Sobol index (dimensionless).
    pub first: f64,
    /// Its 95 % confidence interval: low, high.
    pub first_ci: [f64; 2],
    /// The group's name.
    pub group: String,
    /// Shift of the output's 99.73rd percentile when the group is frozen [um/s].
    pub p9973_shift_um_s: f64,
    /// Total Sobol index (dimensionless).
    pub total: f64,
    /// Its 95 % confidence interval: low, high.
    pub total_ci: [f64; 2],
}

/// The inputs of [`SensitivityDoc`].
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct SensitivityInputs {
    /// The release budget read.
    pub budget: InputDoc,
}

/// A model input file as the JSON documents name it, in byte order of its keys.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct InputDoc {
    /// Path as given (or `<built-in>/...` for the copy embedded in the binary).
    pub label: String,
    /// Where it was resolved from; absent for a file read otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub origin: Option<InputOrigin>,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
}

impl InputDoc {
    /// The document of input file `f`.
    pub fn of(f: &InputFile) -> InputDoc {
        InputDoc {
            label: f.label.clone(),
            origin: f.origin,
            sha256: f.sha256.clone(),
        }
    }
}
