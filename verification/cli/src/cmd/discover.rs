//! `geodesic discover DATASET.yaml --effects BASELINE`: the discovery loop (issue 13,
//! interface.md): round after round, diagnose, add the effect the evidence supports, refit, test
//! removing earlier additions; stop when the residual is noise or nothing is justified; then say
//! whether the model explains the data and describe what is left. Thin: the loop is in
//! `geodesic_discover::discover`, its text in `geodesic_discover::discover::text` and
//! `--scaffold` in `geodesic_discover::discover::new_effect`: arguments ->
//! [`geodesic_discover::session::Session::discover`] -> `--scaffold` -> print.

use crate::error::{CliError, CmdResult};
use crate::fitting::{FitProgress, fits_under, open, warn};
use geodesic_discover::discover::new_effect;
use geodesic_discover::session::Discovered;
use std::path::{Path, PathBuf};

/// Flags of `geodesic discover`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  geodesic discover data/examples/tmmf-adhesion.yaml --effects needle_contact,tip_contact\n  geodesic discover data/examples/rt-plunger.yaml --effects piezo --json\n\
Each round's fit goes into the fit history (geodesic history) and its plot into DIR/fits/.\n\
explained: true when the final residual is consistent with the noise (chi2_red within\n\
1 + 5 sqrt(2/nu) and a white residual); otherwise no catalogue effect is named and the\n\
residual is described (windows, spectral peaks, correlations with the model's states, terms)."
)]
pub struct Args {
    /// Dataset YAML.
    pub dataset: PathBuf,
    /// The baseline model: --effects, --fix, --bound.
    #[command(flatten)]
    pub model: crate::fitting::ModelArgs,
    /// Most rounds that add an effect.
    #[arg(long, default_value_t = 4)]
    pub max_rounds: usize,
    /// Reports folder: plots and the history go into DIR/fits/.
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Refuse a record with a missing value (an empty cell) or a wild sample instead of
    /// skipping that row with a warning.
    #[arg(long)]
    pub strict: bool,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
    /// Write a new effect NAME (snake_case) from the leading term outside the catalogue into
    /// the catalogue: its file under models/facility/src/effects/, its registration, its hiding
    /// test and guard-list entry (run from the repository's root; rebuild, then discover again).
    #[arg(long, value_name = "NAME")]
    pub scaffold: Option<String>,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    // --scaffold: the name and the repository (the working directory) checked before any
    // computation
    let root = Path::new(".");
    if let Some(name) = &args.scaffold {
        new_effect::preflight(name, root).map_err(CliError::usage)?;
    }
    let fits = fits_under(&args.reports, None)?;
    let fit = args.model.options()?;
    let effects = args.model.effects();
    let session = open(&args.dataset, args.strict, &effects, fit)?;
    let task = FitProgress::start(
        args.json,
        &format!(
            "discover: {} samples from {}",
            session.prepared().dataset.t.len(),
            effects.join("+")
        ),
        "discover: ",
    );
    // wild samples set aside before any decision (the same prepared record for the outputs);
    // every round's fit into the history and its plot, in order
    let r = session
        .with_observer(task.observer())
        .with_outputs(fits)
        .discover(args.max_rounds)
        .map_err(crate::error::from_fit);
    task.finish();
    let Discovered {
        report,
        prepared: prep,
    } = r?;
    warn(&report.final_fit);
    let scaffolded = match &args.scaffold {
        Some(name) => Some(
            new_effect::scaffold(name, root, &args.dataset, &prep, &report)
                .map_err(|e| CliError::usage(format!("--scaffold {name}: {e}")))?,
        ),
        None => None,
    };
    if args.json {
        // through serde_json::Value: keys in alphabetical order, as the document always had
        let v = serde_json::to_value(geodesic_discover::discover::DiscoverDoc {
            report: &report,
            scaffold: scaffolded.as_ref().map(|s| &s.json),
        })
        .map_err(CliError::io)?;
        println!("{}", serde_json::to_string(&v).map_err(CliError::io)?);
        return Ok(0);
    }
    print!("{}", geodesic_discover::discover::text::text(&report));
    if let Some(s) = &scaffolded {
        print!("{}", s.text);
    }
    Ok(0)
}
