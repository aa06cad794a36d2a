//! `geodesic fit DATASET.yaml --effects a,b,c`: fits a model to a dataset (interface.md).
//!
//! Writes `<stem>.<effects>.svg` (data, model, residual, failure windows) and appends the fit to
//! `<stem>.history.jsonl` under `--reports DIR` in `DIR/fits/` (default `reports/fits/`).
//! Arguments -> [`geodesic_discover::session::Session::fit`] -> print.

use geodesic_discover::session::{FitRequest, PosteriorRequest};
use geodesic_fit::numeric::ensemble::EnsembleOptions;
use geodesic_fit::summary::summary;

use crate::error::{CliError, CmdResult};
use crate::fitting::{FitProgress, fits_dir, open, warn};

/// Flags of `geodesic fit` (shared with `geodesic diagnose`).
pub use crate::fitting::FitArgs as Args;

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let fits = fits_dir(&args)?;
    if !matches!(args.posterior_method.as_str(), "ensemble" | "laplace") {
        return Err(CliError::usage(format!(
            "--posterior-method {}: ensemble or laplace",
            args.posterior_method
        )));
    }
    if args
        .posterior_walkers
        .is_some_and(|w| !(4..=10_000).contains(&w))
    {
        return Err(CliError::usage(
            "--posterior-walkers: between 4 and 10 000 walkers".to_string(),
        ));
    }
    if !(100..=100_000).contains(&args.posterior_steps) {
        return Err(CliError::usage(format!(
            "--posterior-steps {}: between 100 and 100 000 steps per walker",
            args.posterior_steps
        )));
    }
    let opts = args.model.options()?;
    let effects = args.model.effects();
    let session = open(&args.dataset, args.strict, &effects, opts)?;
    let task = FitProgress::start(
        args.json,
        &format!(
            "fit: {} samples, model {}",
            session.prepared().dataset.t.len(),
            effects.join("+")
        ),
        "fit: ",
    );
    let method = match args.posterior_method.as_str() {
        "laplace" => PosteriorRequest::Laplace,
        _ => PosteriorRequest::Ensemble(EnsembleOptions {
            steps: args.posterior_steps,
            seed: args.posterior_seed,
            walkers: args.posterior_walkers,
        }),
    };
    let posterior = args.posterior.then_some(method);
    let report = session
        .with_observer(task.observer())
        .with_outputs(fits)
        .fit(&FitRequest { posterior })
        .map_err(crate::error::from_fit);
    task.finish();
    let report = report?;
    warn(&report);
    if args.json {
        println!("{}", serde_json::to_string(&report).map_err(CliError::io)?);
    } else {
        print!("{}", summary(&report));
    }
    Ok(0)
}
