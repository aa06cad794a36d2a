//! The identification session (issue 51): a dataset, a model and options in; `fit`, `diagnose`
//! and `discover` run on them; typed results out. It holds what a front end would otherwise
//! orchestrate: the dataset's loading and preparation, the model (the dataset's scenario, its
//! `ScenarioSpec`, with the named effects), the stages of each command (screening, the fit, the
//! posterior, the candidates, the rounds) and their outputs (each fit's plot and its line in
//! the fit history, when the session is given a folder). Progress and debug lines go to the
//! observer of the options ([`FitOptions::observer`]); the session prints nothing.
//!
//! ```no_run
//! use geodesic_discover::session::{FitRequest, Session};
//! use geodesic_fit::FitOptions;
//! use geodesic_dataset::dataset::LoadOptions;
//! let s = Session::open(
//!     std::path::Path::new("data/examples/tmmf-adhesion.yaml"),
//!     LoadOptions::default(),
//!     &["needle_contact", "tip_contact"],
//!     FitOptions::default(),
//! )?;
//! let report = s.fit(&FitRequest::default())?;
//! println!("chi2_red {}", report.chi2_red);
//! # Ok::<(), geodesic_fit::FitError>(())
//! ```

use std::path::{Path, PathBuf};

use crate::dataset::{Dataset, LoadOptions};
use crate::diagnose::DiagnoseReport;
use crate::discover::{DiscoverOptions, DiscoverReport};
use crate::error::FitError;
use crate::estimate::{FitOptions, FitOutcome};
use crate::numeric::ensemble::EnsembleOptions;
use crate::numeric::observe::SharedObserver;
use crate::prepare::Prepared;
use crate::report::{EnsembleMethod, FitReport, LaplaceMethod, MethodName, PosteriorMethod};

/// How `fit` adds each free parameter's marginal posterior.
#[derive(Debug, Clone)]
pub enum PosteriorRequest {
    /// The Laplace approximation at the best fit (instant).
    Laplace,
    /// Sampled by the affine-invariant ensemble, with its corner plot among the outputs (its
    /// path in the method's `corner_svg`, empty when the session writes no outputs).
    Ensemble(EnsembleOptions),
}

/// What [`Session::fit`] does besides the fit: the posterior, if any.
#[derive(Debug, Clone, Default)]
pub struct FitRequest {
    /// The marginal posteriors to add (`None`: none).
    pub posterior: Option<PosteriorRequest>,
}

/// The outcome of [`Session::discover`]: the report and the record it was made on (screened
/// for wild samples), which a caller needs to act on it (`--scaffold`).
#[derive(Debug)]
pub struct Discovered {
    /// The report (interface.md), its final fit with its plot when the session has outputs.
    pub report: DiscoverReport,
    /// The prepared record the loop ran on.
    pub prepared: Prepared,
}

/// A dataset, a model and the options of its fits.
#[derive(Debug)]
pub struct Session {
    prep: Prepared,
    effects: Vec<String>,
    opts: FitOptions,
    outputs: Option<PathBuf>,
}

impl Session {
    /// Loads the dataset at `path` (YAML with its CSV beside it; bad input refused with its
    /// file and line) and prepares it (noise per channel, guesses) for the model of its
    /// scenario with `effects`.
    pub fn open(
        path: &Path,
        load: LoadOptions,
        effects: &[&str],
        opts: FitOptions,
    ) -> Result<Session, FitError> {
        let ds = Dataset::load_with(path, load)?;
        Ok(Session::new(Prepared::new(ds), effects, opts))
    }

    /// A session on a record already prepared.
    pub fn new(prep: Prepared, effects: &[&str], opts: FitOptions) -> Session {
        Session {
            prep,
            effects: effects.iter().map(|e| e.to_string()).collect(),
            opts,
            outputs: None,
        }
    }

    /// Writes each fit's plot (`<stem>.<effects>.svg`, `<stem>.discover.svg`, the posterior's
    /// corner plot) into `dir` and appends each fit to `dir/<stem>.history.jsonl`.
    pub fn with_outputs(mut self, dir: impl Into<PathBuf>) -> Session {
        self.outputs = Some(dir.into());
        self
    }

    /// Sends the progress and debug lines of every stage to `observer` (it replaces the
    /// options' [`FitOptions::observer`]).
    pub fn with_observer(mut self, observer: SharedObserver) -> Session {
        self.opts.observer = observer;
        self
    }

    /// The prepared record.
    pub fn prepared(&self) -> &Prepared {
        &self.prep
    }

    /// The options of the fits.
    pub fn options(&self) -> &FitOptions {
        &self.opts
    }

    fn effects(&self) -> Vec<&str> {
        self.effects.iter().map(String::as_str).collect()
    }

    /// Fits the model (with the profile likelihood along each parameter), adds the posterior
    /// `req` asks for, flags the parameters at a user's bound, writes the outputs.
    pub fn fit(&self, req: &FitRequest) -> Result<FitReport, FitError> {
        let opts = FitOptions {
            profile: true,
            ..self.opts.clone()
        };
        let o = crate::estimate::fit(&self.prep, &self.effects(), &opts)?;
        let mut report = FitReport::new(&self.prep, &o);
        crate::report::outliers::flag_user_bounds(&mut report, &opts.bounds);
        match &req.posterior {
            None => {}
            Some(PosteriorRequest::Laplace) => {
                report.posterior = Some(crate::estimate::posterior_of_fit(&o, &opts.bounds));
                report.posterior_method = Some(PosteriorMethod::Laplace(LaplaceMethod {
                    method: MethodName::Laplace,
                }));
            }
            Some(PosteriorRequest::Ensemble(eo)) => self.sample(&o, &opts, eo, &mut report)?,
        }
        self.record(&o.pred, &mut report)?;
        Ok(report)
    }

    /// The ensemble posterior of the fit `o` into `report`, its corner plot among the outputs.
    fn sample(
        &self,
        o: &FitOutcome,
        opts: &FitOptions,
        eo: &EnsembleOptions,
        report: &mut FitReport,
    ) -> Result<(), FitError> {
        opts.observer.progress(
            &format!("sampling the posterior ({} steps)", eo.steps),
            true,
        );
        let (marg, chain, names) = crate::estimate::sample_posterior(&self.prep, o, opts, eo)?;
        let specs = o.model.specs();
        let backs: Vec<Box<dyn Fn(f64) -> f64>> = names
            .iter()
            .map(|n| {
                let spec = specs[o.model.index(n).expect("a model parameter")];
                Box::new(move |u: f64| if spec.log { u.exp() } else { u * spec.scale })
                    as Box<dyn Fn(f64) -> f64>
            })
            .collect();
        let corner = match &self.outputs {
            Some(dir) => {
                let back_refs: Vec<&dyn Fn(f64) -> f64> =
                    backs.iter().map(|b| b.as_ref()).collect();
                let svg = crate::plot::corner_svg(&names, &chain, &back_refs)?;
                let path = dir.join(format!(
                    "{}.{}.corner.svg",
                    self.prep.dataset.stem(),
                    self.effects.join("+")
                ));
                crate::plot::write_svg(&path, &svg)?;
                path.display().to_string()
            }
            None => String::new(),
        };
        report.posterior = Some(marg.into_iter().map(|(k, m)| (k, m.into())).collect());
        let converged = report
            .posterior
            .as_ref()
            .is_some_and(|p| p.values().all(|m| m.converged != Some(false)));
        report.posterior_method = Some(PosteriorMethod::Ensemble(EnsembleMethod {
            acceptance: chain.acceptance,
            converged,
            corner_svg: corner,
            kept_steps_per_walker: chain.samples.len() / chain.walkers.max(1),
            method: MethodName::Ensemble,
            samples: chain.samples.len(),
            seed: eo.seed,
            steps: eo.steps,
            walkers: chain.walkers,
        }));
        Ok(())
    }

    /// Screens the record for wild samples against the model, fits it, then every candidate
    /// effect of the scenario it lacks, ranked by delta BIC; the model's fit, flagged at a
    /// user's bound, written to the outputs, is the report's `fit`.
    pub fn diagnose(self) -> Result<DiagnoseReport, FitError> {
        let Session {
            prep,
            effects: names,
            opts,
            outputs,
        } = self;
        let effects: Vec<&str> = names.iter().map(String::as_str).collect();
        let obs = opts.observer.clone();
        let prep = crate::screen::screen(prep, &effects, &opts, &mut |m| obs.stage(m))?;
        let (mut report, base) = crate::diagnose::diagnose(&prep, &effects, &opts)?;
        crate::report::outliers::flag_user_bounds(&mut report.fit, &opts.bounds);
        record_to(outputs.as_deref(), &prep, &base.pred, &mut report.fit)?;
        Ok(report)
    }

    /// The discovery loop from the model (at most `max_rounds` rounds that add an effect) on
    /// the record screened for wild samples: every round's fit written to the outputs, the
    /// final fit flagged at a user's bound with its plot `<stem>.discover.svg`.
    pub fn discover(self, max_rounds: usize) -> Result<Discovered, FitError> {
        let Session {
            prep,
            effects: names,
            opts,
            outputs,
        } = self;
        let effects: Vec<&str> = names.iter().map(String::as_str).collect();
        let obs = opts.observer.clone();
        let opts = DiscoverOptions {
            fit: opts,
            max_rounds,
        };
        let (prep, mut report, last, all) =
            crate::discover::discover_screened(prep, &effects, &opts, |m| obs.stage(m))?;
        if let Some(dir) = &outputs {
            // every round's fit into the history and its plot, in order
            for o in &all {
                let mut fr = FitReport::new(&prep, o);
                record_to(Some(dir), &prep, &o.pred, &mut fr)?;
            }
        }
        let mut fr = report.final_fit.clone();
        crate::report::outliers::flag_user_bounds(&mut fr, &opts.fit.bounds);
        if let Some(dir) = &outputs {
            let svg = crate::plot::fit_svg(&prep, &last.pred, &fr)?;
            let path = dir.join(format!("{}.discover.svg", prep.dataset.stem()));
            crate::plot::write_svg(&path, &svg)?;
            fr.svg = Some(path.display().to_string());
        }
        report.final_fit = fr;
        Ok(Discovered {
            report,
            prepared: prep,
        })
    }

    fn record(&self, pred: &[f64], report: &mut FitReport) -> Result<(), FitError> {
        record_to(self.outputs.as_deref(), &self.prep, pred, report)
    }
}

/// Writes the plot of a fit into `dir` (its path into the report) and appends the fit to the
/// history there; nothing without a folder.
fn record_to(
    dir: Option<&Path>,
    prep: &Prepared,
    pred: &[f64],
    report: &mut FitReport,
) -> Result<(), FitError> {
    let Some(dir) = dir else { return Ok(()) };
    let svg = crate::plot::fit_svg(prep, pred, report)?;
    let path = dir.join(format!(
        "{}.{}.svg",
        prep.dataset.stem(),
        report.effects.join("+")
    ));
    crate::plot::write_svg(&path, &svg)?;
    report.svg = Some(path.display().to_string());
    crate::history::append(dir, &prep.dataset.stem(), report)?;
    Ok(())
}

/// The dimension of an effect parameter (`tip_adhesion.A1`) from the catalogue's unit, if the
/// parameter is known and its unit parses: what a front end needs to read `--fix` and `--bound`
/// values with units.
pub fn param_dim(name: &str) -> Option<geodesic_core::units::Dim> {
    let (effect, param) = name.split_once('.')?;
    let e = geodesic_facility::effects::catalogue()
        .iter()
        .find(|e| e.name() == effect)?;
    let p = e.params().iter().find(|p| p.name == param)?;
    geodesic_core::units::parse_unit(p.unit).ok().map(|u| u.dim)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::{SynthSpec, generate};
    use geodesic_facility::Scenario;

    fn retraction() -> Prepared {
        let mut spec = SynthSpec::defaults(Scenario::RtRetraction, &["piezo", "voltage_ramp"]);
        spec.post_s = 3e-4;
        spec.seed = 71;
        spec.noise_in_yaml = false;
        Prepared::new(generate(&spec, "t.yaml").expect("synth"))
    }

    /// A session's fit is the engine's fit with the profiles, its report flagged at the user's
    /// bounds, its plot written and its line appended to the history of the outputs folder; a
    /// second fit of the same model, with the Laplace posterior asked for, has the posterior
    /// and replaces the model's row of the history.
    #[test]
    fn a_session_fits_and_writes_its_plot_and_history() {
        let dir = tempfile::tempdir().expect("tempdir");
        let effects = ["piezo", "voltage_ramp"];
        let prep = retraction();
        let direct = crate::estimate::fit(
            &prep,
            &effects,
            &FitOptions {
                profile: true,
                ..FitOptions::default()
            },
        )
        .expect("fit");
        let direct = FitReport::new(&prep, &direct);
        let s = Session::new(prep, &effects, FitOptions::default()).with_outputs(dir.path());
        let mut r = s.fit(&FitRequest::default()).expect("session fit");
        let svg = r.svg.take().expect("the plot's path");
        assert_eq!(
            svg,
            dir.path()
                .join("t.piezo+voltage_ramp.svg")
                .display()
                .to_string()
        );
        assert!(std::fs::read_to_string(&svg).expect("svg").contains("<svg"));
        assert_eq!(
            serde_json::to_string(&r).expect("json"),
            serde_json::to_string(&direct).expect("json")
        );
        let history = || {
            std::fs::read_to_string(dir.path().join("t.history.jsonl"))
                .expect("history")
                .lines()
                .count()
        };
        assert_eq!(history(), 1);
        let r2 = s
            .fit(&FitRequest {
                posterior: Some(PosteriorRequest::Laplace),
            })
            .expect("session fit");
        // the same model version: its row replaced, not a second one
        assert_eq!(history(), 1);
        assert!(matches!(
            r2.posterior_method,
            Some(PosteriorMethod::Laplace(_))
        ));
        assert!(r2.posterior.is_some_and(|p| !p.is_empty()));
    }
}
