//! Fitting a model to a dataset: noise, tip profile, data-driven starts, multi-start
//! Levenberg-Marquardt, covariance and the JSON report of interface.md.
//!
//! Parameters are fitted in internal coordinates: `ln(p)` for positive parameters spanning
//! decades, `p/scale` for signed ones. The residual is `(model - data)/sigma` over every sample
//! of the fitted channel. Covariance `C = (J^T Sigma^-1 J)^-1` (physics.md section 5) with
//! `Sigma = sigma^2 I`, inflated by `chi2_red` when that exceeds 1 (an incomplete model must not
//! report optimistic errors); 1-sigma per parameter is `sqrt(C_kk)`, mapped to physical units.

use std::collections::BTreeMap;

use geodesic_facility::effects::{GuessContext, of_scenario};
use geodesic_facility::{Model, Scenario};
use nalgebra::DMatrix;

use crate::coords::{from_u, to_u};
use crate::error::FitError;
use crate::numeric::residual::noise_from_differences;
use crate::prepare::Prepared;

mod held;
mod problem;
mod search;
mod solve;
use problem::{Problem, hi_of, lo_of};
use solve::fit_model_on;

/// User constraints of a fit.
#[derive(Debug, Clone, Default)]
pub struct FitOptions {
    /// Parameters held at a value (`effect.param` -> value, SI).
    pub fixed: BTreeMap<String, f64>,
    /// Bounds overriding the physical ones (`effect.param` -> (lower, upper), SI).
    pub bounds: BTreeMap<String, (f64, f64)>,
    /// Upper limit on the number of starting points.
    pub max_starts: Option<usize>,
    /// Widen each parameter's 1-sigma by profiling chi-square along it (slower; `fit` does).
    pub profile: bool,
    /// Noise of the fitted channel to use [SI], overriding the dataset's (diagnose passes the
    /// baseline's estimate to every candidate so that their BICs compare).
    pub sigma: Option<f64>,
    /// Where [`FitOptions::sigma`] comes from, said in the fit's `noise_source` (`None`:
    /// `given`). `discover` holds round 0's figure for every round and passes its source on, so
    /// that a figure estimated from the record is not reported as given.
    pub sigma_source: Option<String>,
    /// Receives the fit's progress (its stages, the iterations on long records) and debug
    /// lines (default: silent); it never changes a result.
    pub observer: crate::numeric::observe::SharedObserver,
}

/// The raw outcome of a fit.
#[derive(Debug, Clone)]
pub struct FitOutcome {
    /// The model.
    pub model: Model,
    /// Best parameters [SI].
    pub p: Vec<f64>,
    /// Which parameters were free.
    pub free: Vec<bool>,
    /// 1-sigma per parameter [SI] (0 for fixed ones), inflated by `chi2_red` when above 1.
    pub sigma_p: Vec<f64>,
    /// 1-sigma per parameter from the covariance alone, before inflation [SI].
    pub sigma_cov: Vec<f64>,
    /// Correlation matrix of the free parameters (in free order).
    pub corr: DMatrix<f64>,
    /// Model prediction of the fitted channel.
    pub pred: Vec<f64>,
    /// `sum ((model - data)/sigma)^2`.
    pub chi2: f64,
    /// Number of samples.
    pub n: usize,
    /// Number of free parameters.
    pub n_free: usize,
    /// Number of starting points tried.
    pub starts: usize,
    /// 1-sigma noise of the fitted channel used for chi-square and covariance [SI].
    pub sigma: f64,
    /// Where `sigma` came from.
    pub sigma_source: String,
    /// `1/2 ln det(2 pi C)` of the covariance `C` in the fit's coordinates (log for the
    /// parameters fitted in log space), at `sigma`; `None` when a direction is unconstrained.
    pub half_log_det_2pi_cov: Option<f64>,
    /// `ln` of the prior volume: the product of the free parameters' ranges in the fit's
    /// coordinates; `None` when a range is unbounded (drift, cyclic-error amplitudes).
    pub log_prior_volume: Option<f64>,
    /// Per parameter, the covariance 1-sigma from differences over half the steps divided by
    /// the one reported (1 for a fixed parameter). Near 1 when the data resolve the parameter;
    /// near 2 when its sigma is made by the differences' truncation error (a direction the
    /// data do not constrain: the sigma grows like 1/step). See [`STEP_RATIO_TOLERANCE`].
    pub step_ratio: Vec<f64>,
    /// Per parameter, whether the data resolve it (true for a fixed one): false when it moves
    /// along one of `symmetries` or fails the step test; its `sigma_p` is then not a sigma
    /// (the report gives none).
    pub resolved: Vec<bool>,
    /// The directions the data do not resolve (`crate::identify::symmetries`).
    pub symmetries: Vec<crate::identify::Symmetry>,
    /// The parameters held at stated values for the retraction's exact symmetries
    /// (`crate::identify::holds`), their uncertainties propagated into `sigma_p`.
    pub held: Vec<crate::identify::Held>,
    /// The identifiable combinations (retraction fits).
    pub combinations: BTreeMap<String, crate::identify::Combination>,
}

/// Largest departure of [`FitOutcome::step_ratio`] from 1 for which a covariance sigma counts
/// as resolved by the data. Resolved parameters of the examples move by at most 0.2 %; ones the
/// data do not constrain by 15 % to 100 % (docs/fitting.md, "Sigmas the data do not resolve").
pub const STEP_RATIO_TOLERANCE: f64 = 0.1;

impl FitOutcome {
    /// The free parameters whose covariance sigma is not resolved by the data (its
    /// [`FitOutcome::step_ratio`] departs from 1 by more than [`STEP_RATIO_TOLERANCE`]), as
    /// (index, ratio).
    pub fn unresolved(&self) -> Vec<(usize, f64)> {
        self.step_ratio
            .iter()
            .enumerate()
            .filter(|&(i, r)| {
                self.free[i] && (r.is_nan() || (r - 1.0).abs() > STEP_RATIO_TOLERANCE)
            })
            .map(|(i, r)| (i, *r))
            .collect()
    }
}

impl FitOutcome {
    /// Re-expresses chi-square and parameter errors for another noise figure `sigma` [SI] (the
    /// best-fit parameters do not depend on a constant noise figure).
    ///
    /// The same noise figure changes nothing (the sigmas are kept as the fit left them, with
    /// the held values' spread folded in and any profile widening). A held value's sigma is
    /// its stated spread, which no noise figure moves; a free parameter keeps the variance the
    /// held values add to it (`sigma_p^2 - (sigma_cov inflate)^2` before) on top of its data
    /// part at the new noise figure. (Before, the held values' sigmas came out 0 and the free
    /// parameters lost the held part when a fit with held values was rescaled.)
    pub fn rescale(&mut self, sigma: f64, source: &str) {
        self.sigma_source = source.to_string();
        if sigma == self.sigma {
            return;
        }
        let r = self.sigma / sigma;
        let inflate_old = self.chi2_red().max(1.0).sqrt();
        self.chi2 *= r * r;
        self.sigma = sigma;
        let inflate = self.chi2_red().max(1.0).sqrt();
        let held: Vec<usize> = self
            .held
            .iter()
            .filter_map(|h| self.model.index(&h.param))
            .collect();
        for (i, (sp, sc)) in self
            .sigma_p
            .iter_mut()
            .zip(self.sigma_cov.iter_mut())
            .enumerate()
        {
            let data_old = *sc * inflate_old;
            *sc /= r;
            if held.contains(&i) {
                continue;
            }
            let extra = if held.is_empty() {
                0.0
            } else {
                (*sp * *sp - data_old * data_old).max(0.0)
            };
            let data = *sc * inflate;
            *sp = (data * data + extra).sqrt();
        }
        // C scales with sigma^2: ln det C moves by -2 k ln r
        if let Some(h) = self.half_log_det_2pi_cov.as_mut() {
            *h -= self.n_free as f64 * r.ln();
        }
    }

    /// Laplace approximation of the log evidence `ln Z` (up to a constant shared by every model
    /// of the same record and noise): `-chi2/2 + ln(Occam factor)`, the Occam factor
    /// `sqrt(det(2 pi C)) / prior volume` for flat priors over the parameters' ranges in the
    /// fit's coordinates, capped at 1 (a posterior wider than its prior is the prior). `None`
    /// when a range is unbounded or a direction unconstrained: the evidence needs proper priors.
    /// `-2 ln Z` is on BIC's scale.
    pub fn log_evidence(&self) -> Option<f64> {
        let occam = self.half_log_det_2pi_cov? - self.log_prior_volume?;
        Some(-0.5 * self.chi2 + occam.min(0.0))
    }

    /// Residual sum of squares `sum (data - model)^2` [SI^2].
    pub fn rss(&self) -> f64 {
        self.chi2 * self.sigma * self.sigma
    }

    /// Reduced chi-square `chi2/(N - k)`.
    pub fn chi2_red(&self) -> f64 {
        self.chi2 / (self.n.saturating_sub(self.n_free)).max(1) as f64
    }
    /// Bayesian information criterion `chi2 + k ln N` (Gaussian noise of known sigma).
    pub fn bic(&self) -> f64 {
        self.chi2 + self.n_free as f64 * (self.n as f64).ln()
    }
}

/// Every combination of the effects' own starting points (at most `cap`, evenly strided).
pub fn default_starts(model: &Model, g: &GuessContext, cap: usize) -> Vec<Vec<f64>> {
    let lists: Vec<Vec<Vec<f64>>> = model.effects.iter().map(|e| e.hints().starts(g)).collect();
    let total: usize = lists.iter().map(|l| l.len()).product();
    let cap = cap.clamp(1, total.max(1));
    let mut out = Vec::with_capacity(cap);
    for k in 0..cap {
        // evenly spread over the combinations (not a fixed stride, which would alias with the
        // mixed-radix counter and skip whole rows of a list)
        let mut rem = k * total / cap;
        let mut p = Vec::with_capacity(model.n_params());
        for l in &lists {
            p.extend_from_slice(&l[rem % l.len()]);
            rem /= l.len();
        }
        out.push(p);
    }
    out
}

/// Fits `model` to `prep` from the given starting points (full parameter vectors, SI): a short
/// run from every start, then the best three refined; returns the best.
pub fn fit_model(
    prep: &Prepared,
    model: &Model,
    opts: &FitOptions,
    starts: &[Vec<f64>],
) -> Result<FitOutcome, FitError> {
    // the retraction's exact symmetries: held by stated values unless the user holds them
    let held = crate::identify::holds(model, &opts.fixed, &opts.bounds);
    let held_opts;
    let opts = if held.is_empty() {
        opts
    } else {
        let mut o = opts.clone();
        for h in &held {
            o.fixed.insert(h.param.clone(), h.value);
        }
        held_opts = o;
        &held_opts
    };
    let mut o = fit_model_held(prep, model, opts, starts)?;
    held::propagate_held(prep, &mut o, &held);
    o.held = held;
    Ok(o)
}

/// [`fit_model`] once the scale is held.
fn fit_model_held(
    prep: &Prepared,
    model: &Model,
    opts: &FitOptions,
    starts: &[Vec<f64>],
) -> Result<FitOutcome, FitError> {
    if let Some(sub) = prep.reduced(SEARCH_SAMPLES) {
        // a long record: search on the reduced record (every sample of the start, the rest
        // thinned), then refine the best point on the whole record
        let search = FitOptions {
            profile: false,
            ..opts.clone()
        };
        let found = fit_model_on(&sub, model, &search, starts, false, 0)?;
        let mut o = fit_model_on(prep, model, opts, std::slice::from_ref(&found.p), true, 0)?;
        o.starts = found.starts;
        return Ok(o);
    }
    fit_model_on(prep, model, opts, starts, false, 0)
}

/// Above this reduced chi-square (a residual RMS 100 times the noise figure) the record
/// rejects the model outright: its report says the model misses most of the record and never
/// calls the residual white (`crate::report::outliers`), and its profile refits are cut
/// shorter (`solve`).
pub const CHI2_RED_ASTRONOMICAL: f64 = 1e4;

/// Records longer than this many samples are searched on a reduced record of about this size
/// ([`Prepared::reduced`]) before the refinement on the whole record: the search's cost then
/// stops growing with the record, and the refinement, which starts next to the minimum, takes
/// a few Levenberg-Marquardt iterations whose cost is linear in the record.
pub const SEARCH_SAMPLES: usize = 4_000;

/// Each free parameter's marginal, the chain, and the free parameters' names.
pub type SampledPosterior = (
    BTreeMap<String, crate::numeric::ensemble::Marginal>,
    crate::numeric::ensemble::Chain,
    Vec<String>,
);

/// Samples the posterior of the free parameters of the fit `o` (made with `opts` on `prep`):
/// `crate::numeric::ensemble` on `-chi2/2` at the fit's noise figure, flat priors over the ranges in the
/// fit's coordinates. Returns each free parameter's marginal (physical units), the chain, and
/// the free parameters' names.
pub fn sample_posterior(
    prep: &Prepared,
    o: &FitOutcome,
    opts: &FitOptions,
    eo: &crate::numeric::ensemble::EnsembleOptions,
) -> Result<SampledPosterior, FitError> {
    let pb = Problem::new(prep, &o.model, opts)?;
    let r2 = (prep.sigma / o.sigma).powi(2);
    let start = o.p.clone();
    let ln_p = |u: &[f64]| -> f64 {
        let c: f64 = pb.resid(u, &start).iter().map(|v| v * v).sum();
        if c.is_finite() {
            -0.5 * c * r2
        } else {
            f64::NEG_INFINITY
        }
    };
    let u0: Vec<f64> = pb
        .fidx
        .iter()
        .map(|&i| {
            to_u(&pb.specs[i], o.p[i]).clamp(lo_of(&pb.lo, i, &pb.fidx), hi_of(&pb.hi, i, &pb.fidx))
        })
        .collect();
    let scale: Vec<f64> = pb
        .fidx
        .iter()
        .map(|&i| {
            if pb.specs[i].log {
                o.sigma_cov[i] / o.p[i].abs().max(1e-300)
            } else {
                o.sigma_cov[i] / pb.specs[i].scale
            }
        })
        .collect();
    let chain = crate::numeric::ensemble::sample(&ln_p, &u0, &scale, &pb.lo, &pb.hi, eo);
    let mut out = BTreeMap::new();
    let mut names = Vec::new();
    for (k, &i) in pb.fidx.iter().enumerate() {
        let spec = &pb.specs[i];
        let back = |u: f64| from_u(spec, u);
        out.insert(
            pb.names[i].clone(),
            crate::numeric::ensemble::marginal(&chain, k, pb.lo[k], pb.hi[k], &back),
        );
        names.push(pb.names[i].clone());
    }
    Ok((out, chain, names))
}

/// Noise of the fitted channel for a fit whose residual (data - model) is `raw`.
///
/// From the YAML when given. Otherwise the pre-trigger estimate is pooled with the noise seen in
/// the first differences of the residual after the trigger (`var(diff)/2`, which a smooth misfit
/// hardly reaches), weighted by sample counts: a short pre-trigger record (20 samples in the
/// retraction tests) alone would leave chi-square uncertain by +-30 %.
pub fn effective_sigma(prep: &Prepared, raw: &[f64]) -> (f64, String) {
    let src = prep
        .noise_source
        .get(prep.channel)
        .map_or("yaml", String::as_str);
    if src == "yaml" || prep.ar.is_some() {
        // a stated figure, or the innovations of a coloured-noise model (which the residual's
        // differences would misjudge)
        return (prep.sigma, src.to_string());
    }
    let t = &prep.dataset.t;
    let post: Vec<f64> = t
        .iter()
        .zip(raw)
        .filter(|(t, _)| **t >= 0.0)
        .map(|(_, r)| *r)
        .collect();
    let n_pre = t.iter().filter(|t| **t < 0.0).count();
    let Some(sd) = noise_from_differences(&post) else {
        return (prep.sigma, src.to_string());
    };
    if src == "pre-trigger" {
        let (a, b) = (
            n_pre.saturating_sub(1) as f64,
            post.len().saturating_sub(1) as f64,
        );
        let pooled = ((a * prep.sigma * prep.sigma + b * sd * sd) / (a + b)).sqrt();
        (pooled, "pre-trigger+residual-differences".to_string())
    } else {
        (sd, "residual-differences".to_string())
    }
}

/// Builds the model of `effects` for the dataset's scenario.
pub fn model_for(prep: &Prepared, effects: &[&str]) -> Result<Model, FitError> {
    Model::new(prep.dataset.scenario, effects)
        .map_err(|e| FitError::input(&prep.dataset.name, 0, e.to_string()))
}

/// Largest number of starting points screened by default.
pub const MAX_STARTS: usize = 512;

/// Fits `effects` to the prepared dataset from data-driven starts (at most [`MAX_STARTS`]).
pub fn fit(prep: &Prepared, effects: &[&str], opts: &FitOptions) -> Result<FitOutcome, FitError> {
    let model = model_for(prep, effects)?;
    let starts = default_starts(&model, &prep.guess, opts.max_starts.unwrap_or(MAX_STARTS));
    fit_model(prep, &model, opts, &starts)
}

/// The effect names of a scenario, for messages.
pub fn scenario_effects(s: Scenario) -> Vec<&'static str> {
    of_scenario(s).iter().map(|e| e.name()).collect()
}

/// The posterior summary of every free parameter of a fit outcome, `bounds` the user's
/// `--bound` ranges (the catalogue's range otherwise).
pub fn posterior_of_fit(
    o: &FitOutcome,
    bounds: &std::collections::BTreeMap<String, (f64, f64)>,
) -> BTreeMap<String, crate::numeric::posterior::Posterior> {
    let names = o.model.param_names();
    let specs = o.model.specs();
    let mut out = std::collections::BTreeMap::new();
    for (i, n) in names.iter().enumerate() {
        if !o.free[i] {
            continue;
        }
        let s = &specs[i];
        let (lo, hi) = bounds.get(n).copied().unwrap_or((s.lower, s.upper));
        let p = o.p[i];
        let sp = o.sigma_p[i];
        let post = if s.log {
            // u = ln p, sigma_u = sigma_p / p (delta method)
            crate::numeric::posterior::truncated_normal(
                p.max(1e-300).ln(),
                sp / p.abs().max(1e-300),
                lo.max(1e-300).ln(),
                hi.ln(),
                &f64::exp,
            )
        } else {
            crate::numeric::posterior::truncated_normal(p, sp, lo, hi, &|u| u)
        };
        out.insert(n.clone(), post);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::{SynthSpec, generate};

    /// Every parameter of `model` held at its nominal value but `free`.
    fn all_fixed_but(model: &Model, free: &[&str]) -> BTreeMap<String, f64> {
        model
            .param_names()
            .into_iter()
            .zip(model.nominal())
            .filter(|(n, _)| !free.contains(&n.as_str()))
            .collect()
    }

    fn retraction() -> Prepared {
        let mut spec = SynthSpec::defaults(Scenario::RtRetraction, &["piezo", "voltage_ramp"]);
        spec.post_s = 3e-4;
        spec.seed = 71;
        spec.noise_in_yaml = false;
        Prepared::new(generate(&spec, "t.yaml").expect("synth"))
    }

    /// An observer that records every line and asks for the debug lines (so that the fit takes
    /// its debug branches too).
    #[derive(Default)]
    struct Recorder {
        progress: std::sync::Mutex<Vec<(String, bool)>>,
        debug: std::sync::Mutex<Vec<String>>,
    }

    impl crate::numeric::observe::Observer for Recorder {
        fn progress(&self, line: &str, milestone: bool) {
            self.progress
                .lock()
                .unwrap()
                .push((line.to_string(), milestone));
        }
        fn debugging(&self) -> bool {
            true
        }
        fn debug(&self, line: &dyn Fn() -> String) {
            self.debug.lock().unwrap().push(line());
        }
    }

    /// Rescaling a fit whose model holds values (the retraction's scale, issue 50's restart and
    /// noise figures) keeps the held values' stated spread: at the same noise figure nothing
    /// moves, at another the held values' sigmas are unchanged (they were 0 before this test)
    /// and each free parameter keeps at least the held part of its variance.
    #[test]
    fn rescaling_keeps_the_held_values_spread() {
        let prep = retraction();
        let o = fit(&prep, &["piezo"], &FitOptions::default()).expect("fit");
        assert!(!o.held.is_empty(), "the retraction holds its scale");
        let held: Vec<usize> = o
            .held
            .iter()
            .filter_map(|h| o.model.index(&h.param))
            .collect();
        for &i in &held {
            assert!(o.sigma_p[i] > 0.0, "held {} has sigma {}", i, o.sigma_p[i]);
        }
        let mut same = o.clone();
        same.rescale(o.sigma, &o.sigma_source);
        assert_eq!(format!("{:?}", same.sigma_p), format!("{:?}", o.sigma_p));
        let mut twice = o.clone();
        twice.rescale(2.0 * o.sigma, "given");
        for &i in &held {
            assert_eq!(twice.sigma_p[i].to_bits(), o.sigma_p[i].to_bits());
        }
        for i in (0..o.p.len()).filter(|&i| o.free[i]) {
            let data_old = o.sigma_cov[i] * o.chi2_red().max(1.0).sqrt();
            let held_part = (o.sigma_p[i].powi(2) - data_old.powi(2)).max(0.0).sqrt();
            assert!(
                twice.sigma_p[i] >= held_part * (1.0 - 1e-12),
                "{}: {} below the held part {}",
                i,
                twice.sigma_p[i],
                held_part
            );
            assert!(twice.sigma_p[i].is_finite() && twice.sigma_p[i] > 0.0);
        }
    }

    /// The observer sees the fit's stages and its debug lines, and never changes a result: the
    /// report of a fit observed (debug branches taken) is bit for bit that of a fit with none.
    #[test]
    fn an_observer_sees_the_milestones_and_changes_no_result() {
        let prep = retraction();
        let effects = ["piezo", "voltage_ramp"];
        let plain = FitOptions {
            profile: true,
            ..FitOptions::default()
        };
        let rec = std::sync::Arc::new(Recorder::default());
        let observed = FitOptions {
            observer: crate::numeric::observe::SharedObserver::from_arc(rec.clone()),
            ..plain.clone()
        };
        let a = fit(&prep, &effects, &plain).expect("fit");
        let b = fit(&prep, &effects, &observed).expect("fit");
        // every field (Debug writes each f64 in its shortest form that reads back to its bits)
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        assert_eq!(
            a.p.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            b.p.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        let lines = rec.progress.lock().unwrap();
        for stage in [
            "search",
            "long Levenberg-Marquardt runs",
            "covariance",
            "profiles",
        ] {
            assert!(
                lines
                    .iter()
                    .any(|(l, m)| *m && l.contains(stage) && l.contains("piezo+voltage_ramp")),
                "no milestone for {stage}: {lines:?}"
            );
        }
        assert!(!rec.debug.lock().unwrap().is_empty(), "no debug line");
    }

    /// A parameter the data cannot constrain (adhesion held where it vanishes: A1 within
    /// [10, 20] N/m, lambda within [1, 1.1] nm, on a record without adhesion) reports its
    /// allowed range as its 1-sigma instead of an infinite or meaningless figure, and the fit
    /// succeeds (it used to fail as "non-finite values", which failed a whole `diagnose`).
    #[test]
    fn an_unconstrained_parameter_reports_its_range() {
        let mut spec =
            SynthSpec::defaults(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]);
        spec.fs_hz = 1e5;
        spec.pre_s = 5e-4;
        spec.post_s = 4e-3;
        spec.seed = 5;
        let prep = Prepared::new(generate(&spec, "u.yaml").expect("synth"));
        let effects = ["needle_contact", "tip_contact", "tip_adhesion"];
        let bounds: BTreeMap<String, (f64, f64)> = [
            ("tip_adhesion.A1".to_string(), (10.0, 20.0)),
            ("tip_adhesion.lambda".to_string(), (1e-9, 1.1e-9)),
        ]
        .into_iter()
        .collect();
        let o = fit(
            &prep,
            &effects,
            &FitOptions {
                bounds,
                ..Default::default()
            },
        )
        .expect("an unconstrained parameter does not fail the fit");
        let i = o.model.index("tip_adhesion.A1").unwrap();
        assert!(
            o.sigma_p[i] > 0.0 && o.sigma_p[i] <= 10.0,
            "{}",
            o.sigma_p[i]
        );
        let k = o.model.index("needle_contact.F_pre").unwrap();
        assert!(o.sigma_p[k] < 0.5 * o.p[k], "{} {}", o.sigma_p[k], o.p[k]);
    }

    /// A profiled fit gives the same bits on one thread and on two: the Jacobian's columns and
    /// the profile's sides run in parallel, each with its own fixed arithmetic, and a restart
    /// from a point below the best fit is chosen once every side has run (not by whichever
    /// thread met one first).
    #[test]
    fn a_profiled_fit_does_not_depend_on_the_thread_count() {
        let prep = retraction();
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    fit(
                        &prep,
                        &["piezo", "voltage_ramp"],
                        &FitOptions {
                            profile: true,
                            ..Default::default()
                        },
                    )
                    .unwrap()
                })
        };
        let (a, b) = (run(1), run(2));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.p), bits(&b.p));
        assert_eq!(bits(&a.sigma_p), bits(&b.sigma_p));
        assert_eq!(a.chi2.to_bits(), b.chi2.to_bits());
    }

    /// The step test of the covariance tells the parameters the data resolve from the ones
    /// they do not. The rigid-plunger retraction's output depends on the six `piezo`
    /// parameters only through four combinations of them (its transfer function
    /// `T E / (m R Ca s^3 + (m + b R Ca) s^2 + (b + (k + T^2/Ca) R Ca) s + k)`): with `R`, `m`
    /// and `b` fixed, `Ca`, `k` and `T` are resolved (three combinations), and with all six
    /// free the covariance of the degenerate directions is made by the differences'
    /// truncation error, its sigmas growing as the steps are halved.
    #[test]
    fn the_step_test_flags_the_parameters_the_data_do_not_resolve() {
        let prep = retraction();
        let free3 = ["piezo.Ca", "piezo.k", "piezo.T"];
        let model = model_for(&prep, &["piezo"]).unwrap();
        let opts = |free: &[&str]| FitOptions {
            fixed: all_fixed_but(&model, free),
            ..Default::default()
        };
        let o = fit(&prep, &["piezo"], &opts(&free3)).unwrap();
        assert!(o.unresolved().is_empty(), "{:?}", o.step_ratio);
        for n in free3 {
            let r = o.step_ratio[o.model.index(n).unwrap()];
            assert!((r - 1.0).abs() < 0.02, "{n}: {r}");
        }
        let all = model.param_names();
        let all: Vec<&str> = all.iter().map(|s| s.as_str()).collect();
        // with all six free the fit holds Ca and R (the model's two exact symmetries, issue 33):
        // the other four are then resolved, their sigmas widened by the held values' 11.5 %
        let o = fit(&prep, &["piezo"], &opts(&all)).unwrap();
        let held: Vec<&str> = o.held.iter().map(|h| h.param.as_str()).collect();
        assert_eq!(held, ["piezo.Ca", "piezo.R"]);
        assert!(o.unresolved().is_empty(), "{:?}", o.step_ratio);
        assert!(o.resolved.iter().all(|r| *r), "{:?}", o.symmetries);
        // with only Ca and R fixed by the user and m free beside k, b, T nothing is held: the
        // same four are free
        let o2 = fit(
            &prep,
            &["piezo"],
            &opts(&["piezo.m", "piezo.k", "piezo.b", "piezo.T"]),
        )
        .unwrap();
        assert!(o2.held.is_empty());
        assert_eq!(o2.n_free, 4);
        // the user holding only Ca leaves the second symmetry to the null-space check: found,
        // its parameters without a sigma
        let o3 = fit(
            &prep,
            &["piezo"],
            &opts(&["piezo.R", "piezo.m", "piezo.k", "piezo.b", "piezo.T"]),
        )
        .unwrap();
        assert!(o3.held.is_empty());
        assert!(
            o3.symmetries.iter().any(|s| s.kind == "exact"),
            "{:?} {:?}",
            o3.symmetries,
            o3.step_ratio
        );
        assert!(o3.resolved.iter().any(|r| !r));
    }

    /// The Laplace evidence against an independent reference: with one free parameter
    /// (`voltage_ramp.em`, fitted in log space, flat prior over ln em in [ln 1e5, ln 1e11]),
    /// `ln Z = ln( integral exp(-chi2(u)/2) du / W )` by quadrature over +-10 sigma of the
    /// optimum (401 points, Simpson) agrees with `FitOutcome::log_evidence` within 0.05 (the
    /// likelihood is near Gaussian in u), and a prior range 10 times narrower raises ln Z by
    /// ln 10 (the Occam factor follows the prior).
    #[test]
    fn laplace_evidence_matches_quadrature_in_one_dimension() {
        let prep = retraction();
        let effects = ["piezo", "voltage_ramp"];
        let model = model_for(&prep, &effects).unwrap();
        let fixed = all_fixed_but(&model, &["voltage_ramp.em"]);
        let o = fit(
            &prep,
            &effects,
            &FitOptions {
                fixed: fixed.clone(),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(o.n_free, 1);
        let lz = o.log_evidence().expect("bounded range");
        let i = model.index("voltage_ramp.em").unwrap();
        let u0 = o.p[i].ln();
        let su = o.sigma_cov[i] / o.p[i];
        let chi2 = |u: f64| -> f64 {
            let mut p = o.p.clone();
            p[i] = u.exp();
            let pred = model.predict(&p, &prep.dataset.t, &prep.inputs);
            pred.iter()
                .zip(prep.data())
                .map(|(m, d)| ((m - d) / o.sigma).powi(2))
                .sum()
        };
        assert!((chi2(u0) - o.chi2).abs() < 1e-6 * o.chi2);
        let (k, h) = (400, 20.0 * su / 400.0);
        let mut sum = 0.0;
        for j in 0..=k {
            let w = if j == 0 || j == k {
                1.0
            } else if j % 2 == 1 {
                4.0
            } else {
                2.0
            };
            let u = u0 - 10.0 * su + j as f64 * h;
            sum += w * (-(chi2(u) - o.chi2) / 2.0).exp();
        }
        let integral = sum * h / 3.0;
        let width = (1e11f64).ln() - (1e5f64).ln();
        let reference = -o.chi2 / 2.0 + integral.ln() - width.ln();
        assert!(
            (lz - reference).abs() < 0.05,
            "Laplace {lz} vs quadrature {reference}"
        );
        // the evidence moves with the prior: a range 10 times narrower (in ln em) adds ln 10
        let narrow = fit(
            &prep,
            &effects,
            &FitOptions {
                fixed,
                bounds: [(
                    "voltage_ramp.em".to_string(),
                    (o.p[i] * (-0.69f64).exp(), o.p[i] * (0.69f64).exp()),
                )]
                .into(),
                ..Default::default()
            },
        )
        .unwrap();
        let gain = narrow.log_evidence().unwrap() - lz;
        let want = (width / 1.38).ln();
        assert!((gain - want).abs() < 0.05, "{gain} vs {want}");
    }

    /// The reported sigmas against the sampled posterior (issue 13, item 4): on a retraction
    /// record with two free parameters (`piezo.R`, `voltage_ramp.em`), the ensemble's 68 %
    /// half-widths agree with the fit's 1-sigma within 15 % and its medians lie within half a
    /// sigma of the best fit (a near-Gaussian likelihood, where both must agree).
    #[test]
    fn reported_sigmas_agree_with_the_sampled_posterior() {
        let prep = retraction();
        let effects = ["piezo", "voltage_ramp"];
        let model = model_for(&prep, &effects).unwrap();
        let fixed = all_fixed_but(&model, &["voltage_ramp.em", "piezo.R"]);
        let opts = FitOptions {
            fixed,
            ..Default::default()
        };
        let o = fit(&prep, &effects, &opts).unwrap();
        assert_eq!(o.n_free, 2);
        let eo = crate::numeric::ensemble::EnsembleOptions {
            steps: 1200,
            seed: 3,
            walkers: None,
        };
        let (marg, chain, names) = sample_posterior(&prep, &o, &opts, &eo).unwrap();
        assert_eq!(names.len(), 2);
        assert!(chain.acceptance > 0.2, "{}", chain.acceptance);
        for n in &names {
            let i = model.index(n).unwrap();
            let m = &marg[n];
            let half = 0.5 * (m.hi68 - m.lo68);
            assert!(
                (half / o.sigma_p[i] - 1.0).abs() < 0.15,
                "{n}: sampled {half:e} vs reported {:e}",
                o.sigma_p[i]
            );
            assert!((m.median - o.p[i]).abs() < 0.5 * o.sigma_p[i], "{n}: {m:?}");
            assert!(!m.prior_limited && !m.multimodal, "{n}: {m:?}");
        }
    }

    #[test]
    fn estimates_the_noise_and_fits_to_it() {
        let prep = retraction();
        assert_eq!(prep.noise_source["y"], "pre-trigger");
        let o = fit(&prep, &["piezo", "voltage_ramp"], &FitOptions::default()).unwrap();
        assert!((o.sigma / 1e-9 - 1.0).abs() < 0.1, "sigma {}", o.sigma);
        assert!(
            (o.chi2_red() - 1.0).abs() < 0.2,
            "chi2_red {}",
            o.chi2_red()
        );
        let i = o.model.index("voltage_ramp.em").unwrap();
        assert!(
            (o.p[i] - 5e7).abs() < 3.0 * o.sigma_p[i],
            "em {} +- {}",
            o.p[i],
            o.sigma_p[i]
        );
    }

    #[test]
    fn profiling_only_widens_the_errors_and_fixing_holds() {
        let prep = retraction();
        let effects = ["piezo", "voltage_ramp"];
        let plain = fit(&prep, &effects, &FitOptions::default()).unwrap();
        let prof = fit(
            &prep,
            &effects,
            &FitOptions {
                profile: true,
                ..Default::default()
            },
        )
        .unwrap();
        for (a, b) in plain.sigma_p.iter().zip(&prof.sigma_p) {
            assert!(b >= a, "{b} < {a}");
        }
        let fixed = FitOptions {
            fixed: [("piezo.R".to_string(), 380.0)].into(),
            ..Default::default()
        };
        let f = fit(&prep, &effects, &fixed).unwrap();
        assert_eq!(f.p[f.model.index("piezo.R").unwrap()], 380.0);
        assert_eq!(f.n_free, 6);
        let bad = FitOptions {
            fixed: [("piezo.Q".to_string(), 1.0)].into(),
            ..Default::default()
        };
        assert!(
            fit(&prep, &effects, &bad)
                .unwrap_err()
                .to_string()
                .contains("piezo.Q")
        );
    }

    #[test]
    fn user_bounds_replace_the_built_in_range_and_bad_constraints_are_refused() {
        let prep = retraction();
        let effects = ["piezo", "voltage_ramp"];
        let m = model_for(&prep, &effects).unwrap();
        let i = m.index("piezo.R").unwrap();
        let spec = m.specs()[i];
        // a bound entirely outside the built-in range used to panic in clamp
        let (lo, hi) = (spec.upper * 2.0, spec.upper * 4.0);
        let o = fit(
            &prep,
            &effects,
            &FitOptions {
                bounds: [("piezo.R".to_string(), (lo, hi))].into(),
                max_starts: Some(2),
                ..Default::default()
            },
        )
        .unwrap();
        assert!(
            o.p[i] >= lo * (1.0 - 1e-9) && o.p[i] <= hi * (1.0 + 1e-9),
            "{}",
            o.p[i]
        );
        for (fixed, bounds, want) in [
            (Some(f64::NAN), None, "finite"),
            (Some(f64::INFINITY), None, "finite"),
            (Some(-380.0), None, "piezo.R"),
            (None, Some((5.0, 1.0)), "lower bound not below"),
            (None, Some((f64::NAN, 1.0)), "finite"),
            (None, Some((-1.0, 1e3)), "above 0"),
        ] {
            let opts = FitOptions {
                fixed: fixed
                    .map(|v| ("piezo.R".to_string(), v))
                    .into_iter()
                    .collect(),
                bounds: bounds
                    .map(|b| ("piezo.R".to_string(), b))
                    .into_iter()
                    .collect(),
                ..Default::default()
            };
            let e = fit(&prep, &effects, &opts).unwrap_err().to_string();
            assert!(e.contains(want) && e.contains("piezo.R"), "{want}: {e}");
        }
    }

    #[test]
    fn default_starts_cover_every_list_entry() {
        let m = Model::new(Scenario::TmmfRelease, &["needle_contact", "tip_contact"]).unwrap();
        let g = GuessContext {
            m_kg: 0.089,
            ..Default::default()
        };
        let all = default_starts(&m, &g, 10_000);
        let few = default_starts(&m, &g, 7);
        assert_eq!(few.len(), 7);
        // every needle stiffness of the grid appears even in a capped list of 20
        let capped = default_starts(&m, &g, 20);
        for k in [3e5, 6.5e5, 1.5e6, 4e6] {
            assert!(capped.iter().any(|s| s[0] == k), "k_nd {k} missing");
        }
        assert!(all.len() >= capped.len());
    }
}
