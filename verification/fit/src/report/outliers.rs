//! Outliers and stuck fits, said out loud (issue 37, item 2). Called once from
//! [`crate::report::FitReport::new`]; the residual's whitening and its judgement stay
//! `crate::numeric::residual`'s and `crate::numeric::noise`'s.
//!
//! * **Outliers.** A sample of the fitted channel whose residual (data - model) lies more than
//!   [`OUTLIER_ROBUST_SIGMA`] robust sigma from the median of its ten neighbours' residuals, and
//!   more than [`OUTLIER_SPREAD`] times their spread, is an outlier: a glitch, not a model
//!   failure (a missing effect bends the residual over many samples, which the neighbours'
//!   median follows). The robust sigma is 1.4826 times the median absolute deviation of those
//!   local differences (`crate::dataset::local_deviation`): one wild sample cannot inflate it,
//!   as it inflates chi-square and a standard deviation. Each is named by its CSV line. Samples
//!   the loader already excluded as wild (`crate::dataset::wild_samples`) are listed too, with
//!   `excluded: true`.
//! * **Whiteness.** `residual_white` is false when the Ljung-Box test fails (as before), when
//!   the record holds an outlier (a residual with a sample tens of sigma out is not Gaussian
//!   white noise, whatever its autocorrelation says: one spike has none), or when chi2_red
//!   exceeds [`CHI2_RED_ASTRONOMICAL`] (a residual 100 times the noise figure: the model does
//!   not describe the record, or a unit or the noise figure is wrong).
//! * **Stuck parameters.** A free parameter whose fitted value is its start value (the nominal
//!   value or one of its effect's data-driven starts) to 1e-9 in the fit's coordinates was not
//!   moved by the data; one on a bound of its range is held there by the bound. Both are named
//!   in the parameter's `flag` and in a warning.
//! * **Precision.** [`fmt_sig`]: four significant digits, scientific notation beyond 1e5 and
//!   below 1e-3: no 75-digit number.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::coords::to_u;
pub use crate::dataset::fmt_sig;
use crate::dataset::{local_deviation_at, robust_scale};
use crate::estimate::{FitOutcome, default_starts};
use crate::prepare::Prepared;
use crate::report::FitReport;

/// An outlier is this many robust sigma from its neighbours' median residual...
pub const OUTLIER_ROBUST_SIGMA: f64 = 8.0;
/// ...and this many times the spread of their residuals.
pub const OUTLIER_SPREAD: f64 = 3.0;
/// Above this reduced chi-square (a residual RMS 100 times the noise figure) the residual is
/// never reported white (defined with the fitting engine, whose profiles also read it).
pub use crate::estimate::CHI2_RED_ASTRONOMICAL;
/// A parameter within this of a start or a bound in the fit's coordinates (relative, at least
/// absolute for coordinates below 1) is at it.
const AT_TOLERANCE: f64 = 1e-9;

/// A sample far off the model (or far outside its neighbours, when the loader excluded it).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Outlier {
    /// Channel.
    pub channel: String,
    /// CSV line (1-based); null for a record not read from a CSV.
    pub line: Option<usize>,
    /// Time [s].
    pub t: f64,
    /// The sample's value [SI].
    pub value: f64,
    /// Its residual less the median of its neighbours' (or, excluded, its value less their
    /// median) [SI].
    pub deviation: f64,
    /// `|deviation|` over the robust sigma.
    pub robust_sigma: f64,
    /// Left out of the fit by the loader (a wild sample); false: in the fit, flagged.
    pub excluded: bool,
}

/// The outliers of the fitted channel's residual `resid` (data - model, SI), in time order.
pub(crate) fn residual_outliers(prep: &Prepared, resid: &[f64]) -> Vec<Outlier> {
    let dev = local_deviation_at(&prep.dataset.t, resid);
    if dev.is_empty() {
        return Vec::new();
    }
    // a floor for a residual that is mostly exact (a noiseless record): a thousandth of the noise
    let s = robust_scale(&dev).max(1e-3 * prep.marginal_sigma());
    let data = prep.data();
    dev.iter()
        .enumerate()
        .filter(|(_, (d, spread))| {
            d.abs() > OUTLIER_ROBUST_SIGMA * s && d.abs() > OUTLIER_SPREAD * spread
        })
        .map(|(i, (d, _))| Outlier {
            channel: prep.channel.to_string(),
            line: prep.dataset.line_of(i),
            t: prep.dataset.t[i],
            value: data[i],
            deviation: *d,
            robust_sigma: if s > 0.0 { d.abs() / s } else { f64::INFINITY },
            excluded: false,
        })
        .collect()
}

/// Whether `u` is within [`AT_TOLERANCE`] of `v` (both in the fit's coordinates).
fn at(u: f64, v: f64) -> bool {
    (u - v).abs() <= AT_TOLERANCE * v.abs().max(1.0)
}

/// The flag of each free parameter of `o` left at a start value or on a bound of its range:
/// `name -> "start" | "lower bound" | "upper bound"`.
pub(crate) fn stuck_parameters(prep: &Prepared, o: &FitOutcome) -> BTreeMap<String, &'static str> {
    let specs = o.model.specs();
    let names = o.model.param_names();
    let starts = default_starts(&o.model, &prep.guess, crate::estimate::MAX_STARTS);
    let mut out = BTreeMap::new();
    for (i, spec) in specs.iter().enumerate() {
        if !o.free[i] {
            continue;
        }
        let u = to_u(spec, o.p[i]);
        // an unbounded side (drift, cyclic-error amplitudes) has no bound to sit on
        let on = |b: f64| b.is_finite() && at(u, to_u(spec, b));
        let flag = if o.p[i] <= spec.lower || on(spec.lower) {
            Some("lower bound")
        } else if o.p[i] >= spec.upper || on(spec.upper) {
            Some("upper bound")
        } else if std::iter::once(spec.nominal)
            .chain(starts.iter().filter_map(|s| s.get(i).copied()))
            .any(|s| s.is_finite() && at(u, to_u(spec, s)))
        {
            Some("start")
        } else {
            None
        };
        if let Some(f) = flag {
            out.insert(names[i].clone(), f);
        }
    }
    out
}

/// What a flag means, for warnings.
fn flag_text(flag: &str) -> &'static str {
    match flag {
        "start" => "left at its start value: the data did not move it",
        "lower bound" => "on the lower bound of its range: the bound holds it",
        "upper bound" => "on the upper bound of its range: the bound holds it",
        _ => "flagged",
    }
}

/// Completes a fit report: outliers (the loader's excluded samples and the residual's),
/// stuck parameters, `residual_white` false when an outlier or an astronomical chi2_red makes
/// the whiteness test meaningless, and a one-line warning for each.
pub fn assess(prep: &Prepared, o: &FitOutcome, resid: &[f64], r: &mut FitReport) {
    let rows = &prep.dataset.rows;
    let mut outliers: Vec<Outlier> = rows
        .wild
        .iter()
        .map(|w| Outlier {
            channel: w.channel.clone(),
            line: Some(w.line),
            t: w.t,
            value: w.value,
            deviation: w.deviation,
            robust_sigma: w.robust_sigma,
            excluded: true,
        })
        .collect();
    let found = residual_outliers(prep, resid);
    let mut warnings: Vec<String> = rows.warnings.clone();
    if !found.is_empty() {
        let list: Vec<String> = found
            .iter()
            .take(5)
            .map(|w| {
                format!(
                    "{} (t = {} s, {} robust sigma)",
                    w.line
                        .map_or(format!("sample at t = {:e} s", w.t), |l| format!(
                            "line {l}"
                        )),
                    fmt_sig(w.t),
                    fmt_sig(w.robust_sigma)
                )
            })
            .collect();
        warnings.push(format!(
            "{}{}: {} sample{} of `{}` far off the model ({}{}): check {} in the data (leave a \
             cell empty to skip its row)",
            rows.file,
            found[0].line.map_or(String::new(), |l| format!(":{l}")),
            found.len(),
            if found.len() == 1 { "" } else { "s" },
            prep.channel,
            list.join(", "),
            if found.len() > 5 { ", ..." } else { "" },
            if found.len() == 1 {
                "that sample"
            } else {
                "those samples"
            }
        ));
    }
    outliers.extend(found);
    // samples the screen set aside before any decision (issue 50): out of the fit like the
    // loader's wild samples, but judged against the model's residual, so the residual's
    // whiteness is that of the cleaned record
    let white_before = outliers.is_empty();
    if !prep.set_aside.is_empty() {
        warnings.push(format!(
            "{}{}: {}",
            rows.file,
            prep.set_aside[0]
                .line
                .map_or(String::new(), |l| format!(":{l}")),
            crate::record::set_aside_text(&prep.set_aside)
        ));
    }
    outliers.extend(prep.set_aside.iter().map(|a| Outlier {
        channel: a.channel.clone(),
        line: a.line,
        t: a.t,
        value: a.value,
        deviation: a.deviation,
        robust_sigma: a.robust_sigma,
        excluded: true,
    }));
    for c in prep.noise_checks.iter().filter(|c| c.mismatch) {
        warnings.push(c.note.clone());
    }
    outliers.sort_by(|a, b| a.t.total_cmp(&b.t).then(a.channel.cmp(&b.channel)));
    let astronomical = r.chi2_red.is_nan() || r.chi2_red > CHI2_RED_ASTRONOMICAL;
    if astronomical {
        warnings.push(format!(
            "chi2_red {}: the residual's RMS is {} times the noise figure ({}, {}): the model \
             misses most of this record (or a unit or the noise figure is wrong); the residual \
             is not reported white",
            fmt_sig(r.chi2_red),
            fmt_sig(r.chi2_red.sqrt()),
            fmt_sig(o.sigma),
            o.sigma_source
        ));
    }
    if !white_before || astronomical {
        r.residual_white = false;
    }
    if let Some((chi2_red, bound)) = prep.profile.as_ref().and_then(|p| p.misfit()) {
        warnings.push(format!(
            "the tip channel is not described by its constant-jerk profile from t = 0 (chi2_red \
             {} above {}): the tip moves otherwise or starts later than the trigger (a trigger \
             delay); the model of the TM is driven by that profile (`explained` weighs it with \
             the TM channel in one chi-square)",
            fmt_sig(chi2_red),
            fmt_sig(bound)
        ));
    }
    for (name, flag) in stuck_parameters(prep, o) {
        if let Some(p) = r.params.get_mut(&name) {
            p.flag = Some(flag.to_string());
            warnings.push(format!(
                "{name} = {} {} is {}",
                fmt_sig(p.value),
                p.unit,
                flag_text(flag)
            ));
        }
    }
    r.outliers = outliers;
    r.warnings = warnings;
}

/// Flags the free parameters of `r` that sit on a bound the user gave (`--bound`:
/// `name -> (lower, upper)` [SI]), with a warning each.
pub fn flag_user_bounds(r: &mut FitReport, bounds: &BTreeMap<String, (f64, f64)>) {
    for (name, (lo, hi)) in bounds {
        let Some(p) = r.params.get_mut(name) else {
            continue;
        };
        if p.fixed || p.flag.is_some() {
            continue;
        }
        let near = |b: f64| {
            b.is_finite() && (p.value - b).abs() <= AT_TOLERANCE * b.abs().max(f64::MIN_POSITIVE)
        };
        let flag = if p.value <= *lo || near(*lo) {
            "lower bound"
        } else if p.value >= *hi || near(*hi) {
            "upper bound"
        } else {
            continue;
        };
        p.flag = Some(flag.to_string());
        r.warnings.push(format!(
            "{name} = {} {} is on the {flag} the user gave (--bound {name}={}:{}): the bound \
             holds it",
            fmt_sig(p.value),
            p.unit,
            fmt_sig(*lo),
            fmt_sig(*hi)
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::{FitOptions, fit};
    use crate::synth::{SynthSpec, generate};
    use geodesic_facility::Scenario;

    /// A short tip retraction with the plunger's compliance, white noise of 1 nm (stated).
    fn record() -> crate::dataset::Dataset {
        let mut spec =
            SynthSpec::defaults(Scenario::RtRetraction, &["piezo", "plunger_compliance"]);
        spec.post_s = 3e-4;
        spec.seed = 5;
        generate(&spec, "o.yaml").unwrap()
    }

    fn report(ds: crate::dataset::Dataset, effects: &[&str]) -> (FitReport, FitOutcome, Prepared) {
        let prep = Prepared::new(ds);
        let o = fit(&prep, effects, &FitOptions::default()).unwrap();
        (FitReport::new(&prep, &o), o, prep)
    }

    #[test]
    fn an_outlier_is_named_and_a_missing_effect_is_not_an_outlier() {
        let full = ["piezo", "plunger_compliance"];
        let (r, _, _) = report(record(), &full);
        assert!(
            r.outliers.is_empty() && r.residual_white,
            "{:?}",
            r.outliers
        );
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        // the baseline misses the plunger: its residual fails over many samples, which is a
        // model failure (failure windows), not an outlier
        let (b, _, _) = report(record(), &["piezo"]);
        assert!(
            !b.failures.is_empty() && b.outliers.is_empty(),
            "{:?}",
            b.outliers
        );
        // one sample 15 sigma off (below the loader's 20): in the fit, flagged by the model's
        // residual, the residual not white
        let mut ds = record();
        let k = 150;
        ds.channels.get_mut("y").unwrap()[k] += 15e-9;
        let (r, _, _) = report(ds, &full);
        assert_eq!(r.outliers.len(), 1, "{:?}", r.outliers);
        let o = &r.outliers[0];
        assert!(
            !o.excluded && o.line.is_none() && o.robust_sigma > 10.0,
            "{o:?}"
        );
        assert!(
            !r.residual_white && r.whiteness.white,
            "Ljung-Box alone misses one spike"
        );
        assert!(r.warnings.iter().any(|w| w.contains("far off the model")));
    }

    #[test]
    fn an_astronomical_chi2_is_never_white() {
        let full = ["piezo", "plunger_compliance"];
        // the noise stated 1000 times too small (a unit slip). A record long enough to test
        // the figure (320 samples: the third differences of all of them, its pre-trigger of 20
        // being too short) finds the slip and uses the record's figure (issue 50, item 2)
        let mut ds = record();
        for v in ds.noise.values_mut() {
            *v /= 1000.0;
        }
        let (r, _, prep) = report(ds, &full);
        let c = prep
            .noise_checks
            .iter()
            .find(|c| c.channel == "y")
            .expect("the figure tested");
        assert!(c.mismatch && (c.ratio / 1000.0 - 1.0).abs() < 0.2, "{c:?}");
        assert!(r.chi2_red < 1.5, "{}", r.chi2_red);
        // one too short to test it (120 samples): the residual is white noise, 1000 times the
        // figure, and an astronomical chi-square is never called white
        let mut spec = SynthSpec::defaults(Scenario::RtRetraction, &full);
        spec.post_s = 1e-4;
        spec.seed = 5;
        let mut ds = generate(&spec, "o.yaml").unwrap();
        for v in ds.noise.values_mut() {
            *v /= 1000.0;
        }
        let (r, _, prep) = report(ds, &full);
        assert!(prep.noise_checks.is_empty(), "{:?}", prep.noise_checks);
        assert!(r.chi2_red > CHI2_RED_ASTRONOMICAL, "{}", r.chi2_red);
        assert!(!r.residual_white);
        assert!(
            r.warnings
                .iter()
                .any(|w| w.contains("times the noise figure")),
            "{:?}",
            r.warnings
        );
    }

    #[test]
    fn parameters_at_a_start_or_on_a_bound_are_flagged() {
        let (_, mut o, prep) = report(record(), &["piezo", "plunger_compliance"]);
        assert!(stuck_parameters(&prep, &o).is_empty());
        let specs = o.model.specs();
        let i = o.model.index("piezo.b").unwrap();
        let j = o.model.index("plunger_compliance.Mg").unwrap();
        o.p[i] = specs[i].nominal;
        o.p[j] = specs[j].upper;
        let f = stuck_parameters(&prep, &o);
        assert_eq!(f.get("piezo.b"), Some(&"start"));
        assert_eq!(f.get("plunger_compliance.Mg"), Some(&"upper bound"));
        let r = FitReport::new(&prep, &o);
        assert_eq!(r.params["piezo.b"].flag.as_deref(), Some("start"));
        assert!(
            r.warnings
                .iter()
                .any(|w| w.contains("piezo.b") && w.contains("start value"))
        );
        // a bound the user gave
        let mut r = FitReport::new(&prep, &o);
        let k = r.params["piezo.k"].value;
        flag_user_bounds(
            &mut r,
            &BTreeMap::from([("piezo.k".to_string(), (k, 2.0 * k))]),
        );
        assert_eq!(r.params["piezo.k"].flag.as_deref(), Some("lower bound"));
    }

    #[test]
    fn numbers_keep_four_significant_digits() {
        assert_eq!(fmt_sig(8.7e74), "8.700e74");
        assert_eq!(fmt_sig(1.0083), "1.008");
        assert_eq!(fmt_sig(144.0), "144.0");
        assert_eq!(fmt_sig(-0.0123456), "-0.01235");
        assert_eq!(fmt_sig(1e-9), "1.000e-9");
        assert_eq!(fmt_sig(0.0), "0");
        assert!(fmt_sig(1e300).len() < 12);
    }
}
