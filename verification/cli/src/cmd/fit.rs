//! `geodesic fit DATASET.yaml --effects a,b,c`: fits a model to a dataset (interface.md).
//!
//! Writes `<stem>.<effects>.svg` (data, model, residual, failure windows) and appends the fit to
//! `<stem>.history.jsonl` under `--reports DIR` in `DIR/fits/` (default `reports/fits/`).

use geodesic_fit::report::{EnsembleMethod, LaplaceMethod, MethodName, PosteriorMethod};
use geodesic_fit::summary::summary;
use geodesic_fit::{FitOptions, FitReport};

use crate::error::{CliError, CmdResult};
use crate::fitting::{fits_dir, load, outputs, warn};

/// Flags of `geodesic fit` (shared with `geodesic diagnose`).
pub use crate::fitting::FitArgs as Args;

/// Every sampled parameter's chain is converged ([`geodesic_fit::numeric::ensemble::CONVERGED_TAUS`]).
fn report_converged(r: &geodesic_fit::fit::FitReport) -> bool {
    r.posterior
        .as_ref()
        .is_some_and(|p| p.values().all(|m| m.converged != Some(false)))
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let fits = fits_dir(&args)?;
    if !matches!(args.posterior_method.as_str(), "ensemble" | "laplace") {
        return Err(CliError::bad(format!(
            "--posterior-method {}: ensemble or laplace",
            args.posterior_method
        )));
    }
    if args
        .posterior_walkers
        .is_some_and(|w| !(4..=10_000).contains(&w))
    {
        return Err(CliError::bad(
            "--posterior-walkers: between 4 and 10 000 walkers".to_string(),
        ));
    }
    if !(100..=100_000).contains(&args.posterior_steps) {
        return Err(CliError::bad(format!(
            "--posterior-steps {}: between 100 and 100 000 steps per walker",
            args.posterior_steps
        )));
    }
    let opts = args.model.options()?;
    let prep = load(&args.dataset, args.strict)?;
    let effects = args.model.effects();
    let task = crate::fitting::FitProgress::start(
        args.json,
        &format!(
            "fit: {} samples, model {}",
            prep.dataset.t.len(),
            effects.join("+")
        ),
        "fit: ",
    );
    let opts = FitOptions {
        profile: true,
        observer: task.observer(),
        ..opts
    };
    let o = geodesic_fit::fit(&prep, &effects, &opts).map_err(|e| CliError::bad(e.to_string()));
    task.finish();
    let o = o?;
    let mut report = FitReport::new(&prep, &o);
    geodesic_fit::outliers::flag_user_bounds(&mut report, &opts.bounds);
    if args.posterior {
        match args.posterior_method.as_str() {
            "laplace" => {
                report.posterior = Some(geodesic_fit::fit::posterior_of_fit(&o, &opts.bounds));
                report.posterior_method = Some(PosteriorMethod::Laplace(LaplaceMethod {
                    method: MethodName::Laplace,
                }));
            }
            _ => {
                let eo = geodesic_fit::numeric::ensemble::EnsembleOptions {
                    steps: args.posterior_steps,
                    seed: args.posterior_seed,
                    walkers: args.posterior_walkers,
                };
                let task = crate::progress::Task::spinner(
                    args.json,
                    &format!("fit: sampling the posterior ({} steps)", eo.steps),
                );
                let r = geodesic_fit::fit::sample_posterior(&prep, &o, &opts, &eo);
                task.finish();
                let (marg, chain, names) = r.map_err(|e| CliError::bad(e.to_string()))?;
                let specs = o.model.specs();
                let backs: Vec<Box<dyn Fn(f64) -> f64>> = names
                    .iter()
                    .map(|n| {
                        let spec = specs[o.model.index(n).expect("a model parameter")];
                        Box::new(
                            move |u: f64| {
                                if spec.log { u.exp() } else { u * spec.scale }
                            },
                        ) as Box<dyn Fn(f64) -> f64>
                    })
                    .collect();
                let back_refs: Vec<&dyn Fn(f64) -> f64> =
                    backs.iter().map(|b| b.as_ref()).collect();
                let svg = geodesic_fit::plot::corner_svg(&names, &chain, &back_refs)
                    .map_err(|e| CliError::Io(e.to_string()))?;
                let path = fits.join(format!(
                    "{}.{}.corner.svg",
                    prep.dataset.stem(),
                    effects.join("+")
                ));
                geodesic_fit::plot::write_svg(&path, &svg)
                    .map_err(|e| CliError::Io(e.to_string()))?;
                report.posterior = Some(marg.into_iter().map(|(k, m)| (k, m.into())).collect());
                report.posterior_method = Some(PosteriorMethod::Ensemble(EnsembleMethod {
                    acceptance: chain.acceptance,
                    converged: report_converged(&report),
                    corner_svg: path.display().to_string(),
                    kept_steps_per_walker: chain.samples.len() / chain.walkers.max(1),
                    method: MethodName::Ensemble,
                    samples: chain.samples.len(),
                    seed: eo.seed,
                    steps: eo.steps,
                    walkers: chain.walkers,
                }));
            }
        }
    }
    outputs(&prep, &o.pred, &mut report, &fits)?;
    warn(&report);
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&report).map_err(|e| CliError::Io(e.to_string()))?
        );
    } else {
        print!("{}", summary(&report));
    }
    Ok(0)
}
