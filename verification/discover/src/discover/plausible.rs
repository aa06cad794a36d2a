//! Plausibility and resolution of what `discover` adds (issue 50, item 4): a candidate is added
//! only with each free parameter resolved (a finite, positive sigma, off its bounds, not
//! filling its range) and with the relations its effect declares to the record
//! ([`geodesic_facility::effects::FitHints::plausible`]) holding. A candidate refused is named
//! with the parameter, its value and sigma, and the bound ([`Refusal`]).

use geodesic_facility::effects::RecordStats;
use serde::{Deserialize, Serialize};

use crate::diagnose::Candidate;
use crate::prepare::Prepared;

/// A candidate the evidence supported but `discover` did not add.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
pub struct Refusal {
    /// The round whose candidate it was.
    pub round: usize,
    /// The effect.
    pub effect: String,
    /// Its delta BIC on that round.
    pub delta_bic: f64,
    /// Why, in one sentence: the parameter, its value and sigma, the bound.
    pub why: String,
}

/// What the record shows that the effects' relations need: the peak-to-peak of `pred` (the
/// fitted channel's model prediction [m]) and the record's duration [s].
pub(crate) fn record_stats(prep: &Prepared, pred: &[f64]) -> RecordStats {
    let (lo, hi) = pred
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let t = &prep.dataset.t;
    RecordStats {
        motion_pp_m: if hi >= lo { hi - lo } else { 0.0 },
        span_s: t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0),
    }
}

/// `Ok` when candidate `c` may be added on a record showing `stats`; else why not.
pub(crate) fn vet(c: &Candidate, stats: &RecordStats) -> Result<(), String> {
    let effect = geodesic_facility::by_name(&c.effect)
        .ok_or_else(|| format!("{} is not in the catalogue", c.effect))?;
    let mut values = Vec::with_capacity(effect.params().len());
    for spec in effect.params() {
        let name = format!("{}.{}", c.effect, spec.name);
        let Some(p) = c.params.get(&name) else {
            values.push(spec.nominal);
            continue;
        };
        values.push(p.value);
        if p.fixed {
            continue;
        }
        let unit = spec.unit;
        let sigma = p.sigma.filter(|s| p.resolved && s.is_finite() && *s > 0.0);
        let Some(sigma) = sigma else {
            return Err(format!(
                "{name} = {:.4e} {unit} has no finite sigma (the record does not resolve it)",
                p.value
            ));
        };
        if let Some(flag) = p.flag.as_deref().filter(|f| f.ends_with("bound")) {
            let bound = if flag.starts_with("lower") {
                spec.lower
            } else {
                spec.upper
            };
            return Err(format!(
                "{name} = {:.4e} +- {sigma:.2e} {unit} sits on its {flag} {bound:.4e} {unit}",
                p.value
            ));
        }
        let fills = if spec.log {
            2.0 * sigma / p.value.abs() >= (spec.upper / spec.lower).ln()
        } else {
            (spec.upper - spec.lower).is_finite() && 2.0 * sigma >= spec.upper - spec.lower
        };
        if fills {
            return Err(format!(
                "{name} = {:.4e} +- {sigma:.2e} {unit} fills its range {:.4e}..{:.4e} {unit}",
                p.value, spec.lower, spec.upper
            ));
        }
    }
    effect
        .hints()
        .plausible(&values, stats)
        .map_err(|e| format!("{}: {e}", c.effect))
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::report::ParamOut;

    fn cyclic(c1: f64, sigma: Option<f64>) -> Candidate {
        let p = |v: f64, s: Option<f64>| ParamOut {
            value: v,
            sigma: s,
            resolved: s.is_some(),
            unit: "m".into(),
            fixed: false,
            flag: None,
        };
        let mut params = BTreeMap::new();
        params.insert("interferometer_cyclic.L".into(), p(316.4e-9, Some(1e-9)));
        params.insert("interferometer_cyclic.b1".into(), p(1e-10, Some(1e-11)));
        params.insert("interferometer_cyclic.c1".into(), p(c1, sigma));
        params.insert("interferometer_cyclic.b2".into(), p(0.0, Some(1e-11)));
        params.insert("interferometer_cyclic.c2".into(), p(0.0, Some(1e-11)));
        Candidate {
            effect: "interferometer_cyclic".into(),
            rms: BTreeMap::new(),
            chi2_red: 1.0,
            delta_bic: -100.0,
            delta_evidence: None,
            residual_white: true,
            params,
        }
    }

    const MOTION: RecordStats = RecordStats {
        motion_pp_m: 374e-9,
        span_s: 0.02,
    };

    #[test]
    fn an_unresolved_amplitude_is_refused_with_its_name() {
        let e = vet(&cyclic(205e-9, None), &MOTION).unwrap_err();
        assert!(
            e.contains("interferometer_cyclic.c1") && e.contains("no finite sigma"),
            "{e}"
        );
    }

    #[test]
    fn a_resolved_but_implausible_amplitude_is_refused_by_the_effects_relation() {
        let e = vet(&cyclic(205e-9, Some(3e-9)), &MOTION).unwrap_err();
        assert!(
            e.starts_with("interferometer_cyclic: ") && e.contains("folds"),
            "{e}"
        );
        assert!(vet(&cyclic(2e-9, Some(1e-10)), &MOTION).is_ok());
    }

    #[test]
    fn a_parameter_on_its_bound_or_filling_its_range_is_refused() {
        let mut c = cyclic(2e-9, Some(1e-10));
        let l = c.params.get_mut("interferometer_cyclic.L").unwrap();
        l.flag = Some("upper bound".into());
        let e = vet(&c, &MOTION).unwrap_err();
        assert!(e.contains("upper bound 2.0000e-6"), "{e}");
        let l = c.params.get_mut("interferometer_cyclic.L").unwrap();
        l.flag = None;
        // ln(2e-6 / 2e-8) = 4.6: a relative sigma of 2.5 spans it
        l.sigma = Some(2.5 * 316.4e-9);
        let e = vet(&c, &MOTION).unwrap_err();
        assert!(e.contains("fills its range"), "{e}");
    }
}
