//! The detection thresholds of the candidates not in the final model ([`thresholds`]): for
//! each, the smallest amplitude of its main parameter that the record would show, at stated
//! values of its other parameters and along a curve of one of them (`DiscoverReport::thresholds`).

use std::collections::BTreeMap;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::diagnose::{DELTA_BIC_STRONG, with_candidate};
use crate::error::FitError;
use crate::estimate::FitOutcome;
use crate::prepare::Prepared;

/// The smallest amplitude of an undetected candidate's main parameter this record would detect.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Threshold {
    /// The effect.
    pub effect: String,
    /// Its main parameter (`effect.param`).
    pub parameter: String,
    /// Detectable above this value [SI].
    pub detectable_above: f64,
    /// Unit.
    pub unit: String,
    /// The values of the effect's other parameters that `detectable_above` assumes (their
    /// catalogue nominal values) [SI].
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub assumes: BTreeMap<String, f64>,
    /// For an effect with one other parameter spanning decades, the threshold at values of it
    /// (`{"effect.param": value, "detectable_above": a}`), so that the threshold for the
    /// record's own value can be read (log-log interpolation).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub curve: Vec<CurvePoint>,
    /// When the record's own fit of the candidate leaves it undetected with a 2-sigma upper
    /// bound above the first-order threshold, the threshold is raised to that bound (where the
    /// other parameter lies within its fitted 2-sigma interval) and this says so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raised: Option<String>,
}

/// One point of a threshold curve.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct CurvePoint {
    /// The other parameter's full name and value [SI].
    #[serde(flatten)]
    pub at: BTreeMap<String, f64>,
    /// The main parameter's threshold there [SI].
    pub detectable_above: f64,
}

/// Detection thresholds of the candidates not in the final model.
///
/// For each candidate, its main parameter `A` (the first amplitude: the first parameter whose
/// null value is zero or its lower bound, e.g. `tip_adhesion.A1`, `interferometer_cyclic.b1`,
/// `drift.p0`, `plunger_compliance.Mg`) is judged with the candidate's other parameters held at
/// stated values (at a vanishing amplitude they are not identified: the adhesion's range trades
/// against its strength) and every parameter of the final model free; `sigma_A` is its 1-sigma
/// from the Fisher information of the final model with the candidate added, whitened by the
/// noise model as every judgement of the residual. An amplitude `A` lowers chi-square by about
/// `(A / sigma_A)^2`, which beats the BIC penalty of the effect's `k` parameters and the
/// strong-evidence threshold when `A > sigma_A sqrt(k ln N - DELTA_BIC_STRONG)`: that is
/// `detectable_above`, at the values of the other parameters stated in `assumes` (their
/// catalogue nominal values).
///
/// The threshold of an effect of more than one parameter depends on the others (issue 33: a
/// tip adhesion of 80 000 N/m with a range of 0.2 um is not detectable on a record whose
/// threshold at the nominal 0.4 um is 15 702 N/m): when the effect has exactly one other
/// parameter spanning decades (the adhesions' `lambda`, the plunger's `Kg`), `curve` gives the
/// threshold at nine values of it from a thirtieth to ten times its nominal value, so that the
/// threshold for the record's own value can be read off (log-log interpolation).
///
/// `sigma_A`: when the effect vanishes at its null amplitude whatever its other parameters (the
/// adhesions, a drift, a cyclic error), from the linear response of the final model's
/// prediction to the amplitude, projected out of the final model's Jacobian (one prediction per
/// point of the curve). Otherwise (the plunger, whose stiffness alone changes the record; a
/// needle adhesion whose range holds it at the needles through the hold) there is no linear
/// response at the null: the threshold is the smallest amplitude whose signature, projected
/// the same way, reaches `sqrt(k ln N - DELTA_BIC_STRONG)` (a grid from the null to the far
/// end of the range and a bisection, one prediction per point: `Detection::crossing`); the
/// null itself when nothing in the range hides. An effect whose main parameter
/// vanishes elsewhere (`voltage_ramp`: a step is an infinite slope) or that has no null
/// (`needle_mass`) gets no threshold.
pub fn thresholds(
    prep: &Prepared,
    final_outcome: &FitOutcome,
    kept: &[&str],
) -> Result<Vec<Threshold>, FitError> {
    let basis = crate::kinds::Basis::new(prep, final_outcome);
    thresholds_with(prep, final_outcome, kept, &basis)
}

/// [`thresholds`] on the basis of `final_outcome` already made, the same bits.
pub fn thresholds_with(
    prep: &Prepared,
    final_outcome: &FitOutcome,
    kept: &[&str],
    basis: &crate::kinds::Basis,
) -> Result<Vec<Threshold>, FitError> {
    // each candidate's threshold is independent of the others': side by side on the thread
    // pool, collected in catalogue order
    let candidates: Vec<_> = geodesic_facility::effects::of_scenario(prep.dataset.scenario)
        .into_iter()
        .filter(|c| !kept.contains(&c.name()))
        .collect();
    let one = |cand: &&'static dyn geodesic_facility::effects::Effect| -> Result<Option<Threshold>, FitError> {
        Ok(Detection::new(prep, final_outcome, kept, *cand)?.and_then(|d| d.threshold(basis)))
    };
    let all: Vec<Result<Option<Threshold>, FitError>> = candidates.par_iter().map(one).collect();
    let mut out = Vec::new();
    for t in all {
        out.extend(t?);
    }
    Ok(out)
}

/// Points of `Detection::crossing`'s grid from the null amplitude to the far end of its range
/// (six decades for an adhesion's `A1`: one point every 0.375 decade).
const CROSSING_GRID: usize = 17;

/// Bisections of `Detection::crossing` between two grid points (a ratio of 2.37 narrowed to
/// 0.02 %).
const CROSSING_BISECTIONS: usize = 12;

/// One candidate's detection threshold ([`thresholds_with`]): the final model with the
/// candidate added, started where the final fit ended, and the candidate's main parameter.
struct Detection<'a> {
    prep: &'a Prepared,
    final_outcome: &'a FitOutcome,
    cand: &'static dyn geodesic_facility::effects::Effect,
    /// The candidate's parameters' null values.
    null: Vec<f64>,
    /// The index of its main parameter (its first amplitude).
    main: usize,
    /// The final model with the candidate added.
    model: geodesic_facility::model::Model,
    /// Its parameters: the final fit's, the candidate's nominal.
    start: Vec<f64>,
    /// The candidate's parameters in `model`'s vector.
    range: std::ops::Range<usize>,
    /// The final fit's prediction, normalised.
    base: Vec<f64>,
}

impl<'a> Detection<'a> {
    /// `None` when the candidate has no null or its main parameter vanishes elsewhere than at
    /// zero or its lower bound (no threshold).
    fn new(
        prep: &'a Prepared,
        final_outcome: &'a FitOutcome,
        kept: &[&str],
        cand: &'static dyn geodesic_facility::effects::Effect,
    ) -> Result<Option<Self>, FitError> {
        let params = cand.params();
        let Some(null) = cand.hints().null_params() else {
            return Ok(None);
        };
        let Some(main) = (0..params.len()).find(|&i| null[i] == 0.0 || null[i] == params[i].lower)
        else {
            return Ok(None);
        };
        let (model, start, range) = with_candidate(
            prep,
            kept,
            &final_outcome.model,
            &final_outcome.p,
            cand.name(),
        )?;
        let mut base = final_outcome.pred.clone();
        prep.normalise(&mut base, final_outcome.sigma);
        Ok(Some(Detection {
            prep,
            final_outcome,
            cand,
            null,
            main,
            model,
            start,
            range,
            base,
        }))
    }

    /// `effect.param` of the candidate's parameter `i`.
    fn full_name(&self, i: usize) -> String {
        format!("{}.{}", self.cand.name(), self.cand.params()[i].name)
    }

    /// The model's parameters with the candidate's main one at `a` and the others at `others`.
    fn with(&self, a: f64, others: &[f64]) -> Vec<f64> {
        let mut p = self.start.clone();
        let mut j = 0;
        for i in 0..self.cand.params().len() {
            p[self.range.start + i] = if i == self.main {
                a
            } else {
                j += 1;
                others[j - 1]
            };
        }
        p
    }

    /// The model's prediction at `p`, normalised.
    fn normalised(&self, p: &[f64]) -> Vec<f64> {
        let mut v = self
            .model
            .predict(p, &self.prep.dataset.t, &self.prep.inputs);
        self.prep.normalise(&mut v, self.final_outcome.sigma);
        v
    }

    /// The threshold amplitude at `others` (the candidate's other parameters): `sigma_A` from
    /// the linear response times `factor` when the effect vanishes at its null amplitude
    /// whatever `others` are ([`Self::sigma_linear`]), else the smallest amplitude whose
    /// signature the final model cannot absorb to first order ([`Self::crossing`]). `None`
    /// when the prediction is not finite.
    fn threshold_at(
        &self,
        others: &[f64],
        factor: f64,
        basis: &crate::kinds::Basis,
    ) -> Option<f64> {
        let at_null = self.normalised(&self.with(self.null[self.main], others));
        let off: f64 = at_null
            .iter()
            .zip(&self.base)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        if off < 0.1 {
            return self
                .sigma_linear(others, &at_null, basis)
                .map(|s| s * factor);
        }
        self.crossing(others, factor, basis)
    }

    /// sigma_A at `others` from the linear response of the prediction at the null amplitude
    /// (`at_null`, normalised), projected out of the final model's Jacobian.
    fn sigma_linear(
        &self,
        others: &[f64],
        at_null: &[f64],
        basis: &crate::kinds::Basis,
    ) -> Option<f64> {
        let spec = self.cand.params()[self.main];
        // the amplitude's step for the linear response: a hundredth of its nominal scale
        let step = if spec.log {
            1e-2 * spec.nominal
        } else {
            1e-2 * spec.scale
        };
        let at_step = self.normalised(&self.with(self.null[self.main] + step, others));
        let col: Vec<f64> = at_step
            .iter()
            .zip(at_null)
            .map(|(a, b)| (a - b) / step)
            .collect();
        basis.sigma_of_normalised(col)
    }

    /// The first-order chi-square the candidate at amplitude `a` (and `others`) leaves once the
    /// final model has absorbed what it can of it: the norm of its signature (prediction minus
    /// the final fit's, whitened and normalised) projected out of the final model's Jacobian.
    /// `None` when the prediction is not finite.
    fn signature(&self, a: f64, others: &[f64], basis: &crate::kinds::Basis) -> Option<f64> {
        let d: Vec<f64> = self
            .normalised(&self.with(a, others))
            .iter()
            .zip(&self.base)
            .map(|(m, b)| m - b)
            .collect();
        basis.projected_norm(d)
    }

    /// The threshold of an effect whose null amplitude does not make it vanish at `others`
    /// (an adhesion whose range holds it at the needles through the hold, the plunger's spring
    /// alone): the smallest amplitude `A` whose projected signature reaches `factor` (a
    /// chi-square of `factor^2`, the BIC price), found on [`CROSSING_GRID`] points from the
    /// null to the range's far end and refined by bisection. Each point is one prediction,
    /// judged as the linear response is (first order in the final model's freedom), where a
    /// fit of the amplitude with `others` held stopped where it started, on a bound, with a
    /// sigma of the whole range or of zero (issue 33: a needle adhesion "detectable above 0"
    /// or six times above its range on a 400 000-sample record). The null itself when its
    /// signature already reaches `factor` (nothing in the range hides at `others`); beyond
    /// the range, the linear extrapolation from its end.
    fn crossing(&self, others: &[f64], factor: f64, basis: &crate::kinds::Basis) -> Option<f64> {
        let spec = self.cand.params()[self.main];
        let a0 = self.null[self.main];
        let a1 = if a0 == spec.lower {
            spec.upper
        } else {
            spec.lower
        };
        // the amplitude at fraction `f` of the way from the null to the far end (log space
        // for a log parameter)
        let at = |f: f64| -> f64 {
            if spec.log && a0 > 0.0 && a1 > 0.0 {
                a0 * (a1 / a0).powf(f)
            } else {
                a0 + (a1 - a0) * f
            }
        };
        let n = CROSSING_GRID;
        let g: Vec<Option<f64>> = (0..n)
            .into_par_iter()
            .map(|j| self.signature(at(j as f64 / (n - 1) as f64), others, basis))
            .collect();
        let g: Vec<f64> = g.into_iter().collect::<Option<Vec<f64>>>()?;
        if g[0] >= factor {
            return Some(a0);
        }
        let Some(j) = g.iter().position(|&v| v >= factor) else {
            // not reached inside the range: extrapolate linearly from its end
            let last = g[n - 1];
            return (last > 0.0).then(|| a0 + (a1 - a0) * factor / last);
        };
        // bisection between grid points j - 1 (below) and j (at or above)
        let (mut f_lo, mut f_hi) = ((j - 1) as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
        for _ in 0..CROSSING_BISECTIONS {
            let f = 0.5 * (f_lo + f_hi);
            match self.signature(at(f), others, basis) {
                Some(v) if v >= factor => f_hi = f,
                Some(_) => f_lo = f,
                None => return None,
            }
        }
        Some(at(f_hi))
    }

    /// The threshold at the other parameters' nominal values, with its curve along one other
    /// parameter spanning decades; `None` when the threshold is not finite and positive.
    fn threshold(&self, basis: &crate::kinds::Basis) -> Option<Threshold> {
        let (params, main) = (self.cand.params(), self.main);
        let n = self.final_outcome.n as f64;
        let k = params.len() as f64;
        let factor = (k * n.ln() - DELTA_BIC_STRONG).sqrt();
        let nominal_others: Vec<f64> = (0..params.len())
            .filter(|&i| i != main)
            .map(|i| params[i].nominal)
            .collect();
        // the threshold at the nominal values and the curve are independent: side by side
        // (each point's arithmetic its own, so the same values)
        let (a, curve) = rayon::join(
            || self.threshold_at(&nominal_others, factor, basis),
            || self.curve(factor, basis),
        );
        let a = a?;
        if !(a.is_finite() && a > 0.0) {
            return None;
        }
        let assumes: BTreeMap<String, f64> = (0..params.len())
            .filter(|&i| i != main)
            .map(|i| (self.full_name(i), params[i].nominal))
            .collect();
        Some(Threshold {
            effect: self.cand.name().to_string(),
            parameter: self.full_name(main),
            detectable_above: a,
            unit: params[main].unit.to_string(),
            assumes,
            curve,
            raised: None,
        })
    }

    /// For an effect with exactly one other parameter spanning decades (a log range), the
    /// threshold at nine values of it from a thirtieth to ten times its nominal value; empty
    /// otherwise.
    fn curve(&self, factor: f64, basis: &crate::kinds::Basis) -> Vec<CurvePoint> {
        let params = self.cand.params();
        let mut curve = Vec::new();
        if params.len() != 2 {
            return curve;
        }
        let o = 1 - self.main;
        let os = params[o];
        if !os.log {
            return curve;
        }
        let (lo, hi) = (
            (os.nominal / 30.0).max(os.lower),
            (os.nominal * 10.0).min(os.upper),
        );
        // the nine points side by side on the thread pool (each a grid and a bisection of its
        // own: one after the other they were the end of a long record's `discover`, on one
        // core), kept in order
        let points: Vec<Option<CurvePoint>> = (0..9)
            .into_par_iter()
            .map(|j| {
                let v = lo * (hi / lo).powf(j as f64 / 8.0);
                self.threshold_at(&[v], factor, basis)
                    .filter(|a| a.is_finite())
                    .map(|a| CurvePoint {
                        at: BTreeMap::from([(self.full_name(o), v)]),
                        detectable_above: a,
                    })
            })
            .collect();
        curve.extend(points.into_iter().flatten());
        curve
    }
}
