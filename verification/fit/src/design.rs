//! What to measure next (issue 13, item 5): when two candidate effects explain a record about
//! equally well, which change of the measurement separates them best, with the delta BIC it is
//! expected to give.
//!
//! For candidates `A` and `B` (each the given model plus one effect, fitted to the record), the
//! expected delta BIC of a measurement variant is computed without noise, the standard
//! expected-evidence argument (Fisher information at the fitted models): take `A`'s fitted
//! prediction on the variant's time grid as the data, fit `B` to it (from `B`'s fitted values),
//! and `chi2_B` is the expected chi-square by which `B` falls behind when `A` is true (the noise
//! adds the same expected `N - k` to both); the expected delta BIC is
//! `chi2_B + (k_B - k_A) ln N`. The same with the roles swapped; a variant's separation is the
//! smaller of the two (the one that must be overcome whichever is true). Variants:
//!
//! * `as measured`: the record's own grid and noise (what this record could show at best);
//! * `noise halved`: chi-square four times larger at the same optimum (exact for a fixed
//!   noise figure; no refit needed);
//! * `sampling rate x2`: the same span at half the sample spacing;
//! * `duration x2`: the record after the trigger twice as long;
//! * `pre-trigger x2`: twice as many samples before the trigger.
//!
//! A second channel is not offered: the catalogue's models predict the fitted channel only.

use serde::{Deserialize, Serialize};

use crate::error::FitError;
use crate::estimate::{FitOptions, FitOutcome, fit_model};
use crate::prepare::Prepared;

/// One measurement variant and the delta BIC it is expected to give between the candidates.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct DesignOption {
    /// The change of the measurement.
    pub change: String,
    /// Samples of the fitted channel.
    pub samples: usize,
    /// Expected `BIC(B) - BIC(A)` when `A` is true (positive: the data favour `A`).
    pub if_first_true: f64,
    /// Expected `BIC(A) - BIC(B)` when `B` is true.
    pub if_second_true: f64,
    /// `min` of the two: the separation whichever is true.
    pub separation: f64,
}

/// Advice for two close candidates.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct DesignAdvice {
    /// The first candidate (the better by delta BIC on this record).
    pub first: String,
    /// The runner-up.
    pub second: String,
    /// Their delta BIC difference on this record (`BIC(second) - BIC(first)`).
    pub observed_gap: f64,
    /// Every variant, best separation first.
    pub options: Vec<DesignOption>,
    /// The variant that separates them best, and whether it reaches strong evidence (10).
    pub best: String,
}

/// Separation threshold: strong evidence on the Kass-Raftery scale.
pub const STRONG: f64 = 10.0;

/// `prep` with the fitted channel replaced by `truth` on the grid `t` (white noise `sigma`, no
/// coloured-noise model), the tip channel by the fitted profile.
fn on_grid(prep: &Prepared, t: Vec<f64>, truth: Vec<f64>, sigma: f64) -> Prepared {
    let mut p = prep.clone();
    let ch = prep.channel.to_string();
    if let Some(y) = p.dataset.channels.get_mut("y")
        && ch != "y"
    {
        *y = t.iter().map(|ti| prep.inputs.profile.y(*ti)).collect();
    }
    p.dataset.channels.insert(ch, truth);
    p.dataset.t = t;
    p.sigma = sigma;
    p.ar = None;
    p
}

/// Expected chi-square of `b`'s model fitted to `a`'s noise-free prediction on `t` (noise
/// `sigma`), started from `b`'s fitted values.
fn expected_chi2(
    prep: &Prepared,
    a: &FitOutcome,
    b: &FitOutcome,
    t: &[f64],
    sigma: f64,
    opts: &FitOptions,
) -> Result<f64, FitError> {
    let truth = a.model.predict(&a.p, t, &prep.inputs);
    let p = on_grid(prep, t.to_vec(), truth, sigma);
    let mut o = opts.clone();
    o.sigma = Some(sigma);
    o.max_starts = Some(1);
    o.profile = false;
    let fitted = fit_model(&p, &b.model, &o, std::slice::from_ref(&b.p))?;
    Ok(fitted.chi2)
}

/// The measurement variants' time grids: (name, grid).
fn grids(t: &[f64]) -> Vec<(String, Vec<f64>)> {
    let n = t.len();
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    let dt = d.get(d.len() / 2).copied().unwrap_or(0.0);
    let (t0, t1) = (t[0], t[n - 1]);
    let mut out = vec![("as measured".to_string(), t.to_vec())];
    if dt > 0.0 {
        let span = |a: f64, b: f64, h: f64| -> Vec<f64> {
            let k = ((b - a) / h).round() as usize;
            (0..=k).map(|i| a + i as f64 * h).collect()
        };
        out.push(("sampling rate x2".into(), span(t0, t1, dt / 2.0)));
        if t1 > 0.0 {
            out.push(("duration x2".into(), span(t0, 2.0 * t1, dt)));
        }
        if t0 < 0.0 {
            out.push(("pre-trigger x2".into(), span(2.0 * t0, t1, dt)));
        }
    }
    out
}

/// The advice for candidates `a` (better) and `b` fitted to `prep` at noise `sigma` (their
/// common noise figure); `observed_gap = BIC(b) - BIC(a)` on the record.
pub fn advise(
    prep: &Prepared,
    a: (&str, &FitOutcome),
    b: (&str, &FitOutcome),
    observed_gap: f64,
    opts: &FitOptions,
) -> Result<DesignAdvice, FitError> {
    let sigma = prep.marginal_sigma();
    let (ka, kb) = (a.1.n_free as f64, b.1.n_free as f64);
    let mut options = Vec::new();
    for (name, t) in grids(&prep.dataset.t) {
        let ln_n = (t.len() as f64).ln();
        let cb = expected_chi2(prep, a.1, b.1, &t, sigma, opts)?;
        let ca = expected_chi2(prep, b.1, a.1, &t, sigma, opts)?;
        let push = |options: &mut Vec<DesignOption>, change: String, ca: f64, cb: f64| {
            let if_a = cb + (kb - ka) * ln_n;
            let if_b = ca + (ka - kb) * ln_n;
            options.push(DesignOption {
                change,
                samples: t.len(),
                if_first_true: if_a,
                if_second_true: if_b,
                separation: if_a.min(if_b),
            });
        };
        if name == "as measured" {
            push(&mut options, "noise halved".into(), 4.0 * ca, 4.0 * cb);
        }
        push(&mut options, name, ca, cb);
    }
    options.sort_by(|x, y| y.separation.total_cmp(&x.separation));
    let best = options.first().map_or(String::new(), |o| {
        format!(
            "{}: expected delta BIC {:.1} if {} is true, {:.1} if {} is true ({})",
            o.change,
            o.if_first_true,
            a.0,
            o.if_second_true,
            b.0,
            if o.separation >= STRONG {
                "strong evidence whichever is true"
            } else {
                "below strong evidence (10) for one of them: combine changes or repeat the test"
            }
        )
    });
    Ok(DesignAdvice {
        first: a.0.to_string(),
        second: b.0.to_string(),
        observed_gap,
        options,
        best,
    })
}
