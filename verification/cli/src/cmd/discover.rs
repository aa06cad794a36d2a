//! `geodesic discover DATASET.yaml --effects BASELINE`: the discovery loop (issue 13,
//! interface.md): round after round, diagnose, add the effect the evidence supports, refit, test
//! removing earlier additions; stop when the residual is noise or nothing is justified; then say
//! whether the model explains the data and describe what is left. Thin: the loop is in
//! `geodesic_fit::discover`, its text in `geodesic_fit::discover::text` and `--scaffold` in
//! `geodesic_fit::discover::new_effect`.

use crate::error::{CliError, CmdResult};
use crate::fitting::{fits_under, load, outputs, warn};
use geodesic_fit::discover::{DiscoverOptions, discover_screened, new_effect};
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
        new_effect::preflight(name, root).map_err(CliError::bad)?;
    }
    let fits = fits_under(&args.reports, None)?;
    let fit = args.model.options()?;
    let prep = load(&args.dataset, args.strict)?;
    let effects = args.model.effects();
    let mut task = crate::progress::Task::spinner(
        args.json,
        &format!(
            "discover: {} samples from {}",
            prep.dataset.t.len(),
            effects.join("+")
        ),
    );
    let opts = DiscoverOptions {
        fit,
        max_rounds: args.max_rounds,
    };
    geodesic_fit::progress::set_hook(task.fit_hook());
    // wild samples set aside before any decision (the same prepared record for the outputs)
    let r = discover_screened(prep, &effects, &opts, |m| {
        task.set_label(&format!("discover: {m}"))
    })
    .map_err(|e| CliError::bad(e.to_string()));
    geodesic_fit::progress::set_hook(None);
    task.finish();
    let (prep, mut report, last, all) = r?;
    // every round's fit into the history and its plot, in order
    for o in &all {
        let mut fr = geodesic_fit::FitReport::new(&prep, o);
        outputs(&prep, &o.pred, &mut fr, &fits)?;
    }
    let mut fr = report.final_fit.clone();
    geodesic_fit::outliers::flag_user_bounds(&mut fr, &opts.fit.bounds);
    warn(&fr);
    let svg = geodesic_fit::plot::fit_svg(&prep, &last.pred, &fr)
        .map_err(|e| CliError::Io(e.to_string()))?;
    let path = fits.join(format!("{}.discover.svg", prep.dataset.stem()));
    geodesic_fit::plot::write_svg(&path, &svg).map_err(|e| CliError::Io(e.to_string()))?;
    fr.svg = Some(path.display().to_string());
    report.final_fit = fr;
    let scaffolded = match &args.scaffold {
        Some(name) => Some(
            new_effect::scaffold(name, root, &args.dataset, &prep, &report)
                .map_err(|e| CliError::bad(format!("--scaffold {name}: {e}")))?,
        ),
        None => None,
    };
    if args.json {
        // through serde_json::Value: keys in alphabetical order, as the document always had
        let v = serde_json::to_value(geodesic_fit::discover::DiscoverDoc {
            report: &report,
            scaffold: scaffolded.as_ref().map(|s| &s.json),
        })
        .map_err(|e| CliError::Io(e.to_string()))?;
        println!(
            "{}",
            serde_json::to_string(&v).map_err(|e| CliError::Io(e.to_string()))?
        );
        return Ok(0);
    }
    print!("{}", geodesic_fit::discover::text::text(&report));
    if let Some(s) = &scaffolded {
        print!("{}", s.text);
    }
    Ok(0)
}
