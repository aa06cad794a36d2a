//! What the fit commands (`fit`, `diagnose`, `discover`, `history`) share, so that
//! no command imports another: the flags of `fit` and `diagnose`, the parsing of `--effects`,
//! `--fix` and `--bound`, the opening of the identification session (which loads the dataset,
//! runs the stages and writes each fit's plot and history entry), the fits folder
//! (`--reports DIR` + `fits`), a fit's warnings and the observer that shows a fit's progress.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use geodesic_fit::numeric::observe::{Observer, SharedObserver};

use geodesic_dataset::dataset::LoadOptions;
use geodesic_discover::session::Session;
use geodesic_fit::{FitOptions, FitReport};

use crate::error::CliError;

/// The model flags of `fit`, `diagnose` and `discover`: one declaration, one help
/// text (flattened into each command's flags).
#[derive(clap::Args, Debug)]
pub struct ModelArgs {
    /// Effects of the model, comma separated (e.g. needle_contact,tip_contact; `geodesic
    /// effects` lists them).
    #[arg(long, value_delimiter = ',', required = true)]
    pub effects: Vec<String>,
    /// Hold a parameter fixed: effect.param=VALUE (SI or with a unit), repeatable.
    #[arg(long = "fix", value_name = "NAME=VALUE")]
    pub fix: Vec<String>,
    /// Bound a parameter: effect.param=LO:HI (SI or with a unit), repeatable.
    #[arg(long = "bound", value_name = "NAME=LO:HI")]
    pub bound: Vec<String>,
}

impl ModelArgs {
    /// The effect names of `--effects` ([`effect_list`]).
    pub fn effects(&self) -> Vec<&str> {
        effect_list(&self.effects)
    }

    /// The fit options of `--fix` and `--bound` ([`options`]).
    pub fn options(&self) -> Result<FitOptions, CliError> {
        options(&self.fix, &self.bound)
    }
}

/// Flags of `geodesic fit` and `geodesic diagnose` (the model to start from).
#[derive(clap::Args, Debug)]
pub struct FitArgs {
    /// Dataset YAML: `channels`, `known`, `scenario` and a CSV beside it (docs/spec/interface.md in the repository).
    pub dataset: PathBuf,
    /// The model: --effects, --fix, --bound.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Reports folder, as for `verify`: the SVG and the history go into DIR/fits/.
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Not a flag of this command (`--out` names one output file everywhere in geodesic).
    #[arg(long, hide = true)]
    pub out: Option<PathBuf>,
    /// Add each free parameter's marginal posterior (median, 68 % and 95 % intervals), flat
    /// priors over the parameter's range: the Laplace approximation at the best fit (instant),
    /// or with `--posterior-method ensemble` sampled by an affine-invariant ensemble (flags
    /// `prior_limited` and `multimodal`, each chain's autocorrelation time and `converged` when
    /// the kept steps are at least 50 of them, a corner plot in DIR/fits/).
    #[arg(long)]
    pub posterior: bool,
    /// How to get the posterior: laplace (default) or ensemble.
    #[arg(long, value_name = "METHOD", default_value = "laplace")]
    pub posterior_method: String,
    /// Walkers of the ensemble sampler (default max(8 x free parameters, 32)), 4-10000.
    #[arg(long, value_name = "N")]
    pub posterior_walkers: Option<usize>,
    /// Steps per walker of the ensemble sampler (a third discarded as burn-in), 100-100000.
    #[arg(long, value_name = "N", default_value_t = 1500)]
    pub posterior_steps: usize,
    /// Seed of the ensemble sampler.
    #[arg(long, value_name = "SEED", default_value_t = 1)]
    pub posterior_seed: u64,
    /// Refuse a record with a missing value (an empty cell) or a wild sample instead of
    /// skipping that row with a warning.
    #[arg(long)]
    pub strict: bool,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// The folder of the fit outputs: `--reports DIR` + `fits`. Refuses the old `--out DIR`.
pub fn fits_dir(args: &FitArgs) -> Result<PathBuf, CliError> {
    fits_under(&args.reports, args.out.as_ref())
}

/// `reports/fits`, or the cause when `--out` was given to a command that writes a folder.
pub fn fits_under(reports: &Path, out: Option<&PathBuf>) -> Result<PathBuf, CliError> {
    if let Some(o) = out {
        return Err(CliError::usage(format!(
            "--out {}: in geodesic --out names one output file; fit plots and histories go \
             under --reports DIR (into DIR/fits/)",
            o.display()
        )));
    }
    if reports.exists() && !reports.is_dir() {
        return Err(CliError::usage(format!(
            "--reports {}: is not a directory",
            reports.display()
        )));
    }
    // checked before the record is read or fitted: a folder that cannot be written is exit 2
    // at once, not after the fit
    crate::preflight::out_dir("--reports", &reports.join("fits"))?;
    Ok(reports.join("fits"))
}

/// Parses `--fix` and `--bound` into fit options.
pub fn options(fix: &[String], bound: &[String]) -> Result<FitOptions, CliError> {
    use crate::quantity::{pair, param_dim};
    let mut fixed = BTreeMap::new();
    for f in fix {
        let (k, v) = pair(f, "fix", param_dim)?;
        fixed.insert(k, v);
    }
    let mut bounds = BTreeMap::new();
    for b in bound {
        let (k, r) = crate::quantity::bound(b, param_dim)?;
        bounds.insert(k, r);
    }
    Ok(FitOptions {
        fixed,
        bounds,
        max_starts: None,
        profile: false,
        sigma: None,
        sigma_source: None,
        observer: SharedObserver::default(),
    })
}

/// The environment variable that turns on the fit library's debug lines on standard error
/// (the multi-start stages, the runs stopped, the null-space tests): read here, by the binary,
/// never by a library.
pub const DEBUG_VAR: &str = "GEODESIC_FIT_DEBUG";

/// What the fit commands show while the library works: a spinner task (under the quiet rule of
/// `crate::progress`) that the library's progress lines and stages update, and the library's
/// debug lines on standard error when [`DEBUG_VAR`] is set.
pub struct FitProgress {
    task: Mutex<Option<crate::progress::Task>>,
    hook: Option<crate::progress::LineHook>,
    prefix: String,
    debug: bool,
}

impl FitProgress {
    /// Starts the spinner `label`; a stage the library reports replaces the label by
    /// `prefix` and the stage.
    pub fn start(json: bool, label: &str, prefix: &str) -> Arc<FitProgress> {
        let task = crate::progress::Task::spinner(json, label);
        Arc::new(FitProgress {
            hook: task.fit_hook(),
            task: Mutex::new(Some(task)),
            prefix: prefix.to_string(),
            debug: std::env::var_os(DEBUG_VAR).is_some(),
        })
    }

    /// The observer to pass in the fit options.
    pub fn observer(self: &Arc<Self>) -> SharedObserver {
        SharedObserver::from_arc(self.clone())
    }

    /// Ends the spinner.
    pub fn finish(&self) {
        if let Some(t) = self.task.lock().ok().and_then(|mut t| t.take()) {
            t.finish();
        }
    }
}

impl Observer for FitProgress {
    fn progress(&self, line: &str, milestone: bool) {
        if let Some(h) = &self.hook {
            h(line, milestone);
        }
    }

    fn stage(&self, label: &str) {
        if let Ok(mut t) = self.task.lock()
            && let Some(t) = t.as_mut()
        {
            t.set_label(&format!("{}{label}", self.prefix));
        }
    }

    fn debugging(&self) -> bool {
        self.debug
    }

    fn debug(&self, line: &dyn Fn() -> String) {
        if self.debug {
            eprintln!("{}", line());
        }
    }
}

/// Opens the identification session of a command: loads and prepares the dataset (`strict`:
/// a missing value or a wild sample refused instead of skipped) for the model of `effects`,
/// mapping errors to exit 2.
pub fn open(
    path: &Path,
    strict: bool,
    effects: &[&str],
    opts: FitOptions,
) -> Result<Session, CliError> {
    Session::open(path, LoadOptions { strict }, effects, opts).map_err(crate::error::from_fit)
}

/// Prints a fit report's warnings on standard error, one line each.
pub fn warn(r: &FitReport) {
    for w in &r.warnings {
        eprintln!("geodesic: warning: {w}");
    }
}

/// The effect names of `--effects`, trimmed, empty items dropped.
pub fn effect_list(effects: &[String]) -> Vec<&str> {
    effects
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect()
}
