//! A credibility assessment beside every verdict (issue 49), after NASA-STD-7009A's
//! Credibility Assessment Scale: each judged row carries a level of 0 to 4 for each factor the
//! tool can judge from its own evidence, the weakest factor named, and the row's level is the
//! weakest factor's. The rubric, with an example from this repository for every level, is
//! `docs/credibility.md`; the words of each level are in [`assess`]'s helpers.
//!
//! | factor | what it reads |
//! | --- | --- |
//! | verification | the row's traced tests: passed, fresh, what they assert (limit, reference, change detection), property tests |
//! | validation | the model against a measurement or a reference covering its domain: a row that judges its model input (`judges_input` of its evidence) |
//! | input pedigree | the pedigree of every parameter of the row's model inputs ([`crate::pedigree`]): the weakest |
//! | results uncertainty | the sampled bound that decides (N, confidence), an analytic quantile, or a point value |
//! | results robustness | Sobol/Jansen sensitivity indices attached to the row (`total_*` inputs of its evidence), or to a row of the same check |
//!
//! A requirement may state the level its verdict needs (`credibility: 3`): a compliant row below
//! it is `not-verified`, with the reason, whatever its margin.

pub use crate::cas::{Credibility, Factor};
use crate::check::{Basis, Inputs};
use crate::matrix::{Matrix, Row, Status, TestsStatus};
use crate::pedigree::Kind;
use crate::requirement::Requirements;
use crate::testrun::{Assertion, TestResult};

fn f(level: u8, why: impl Into<String>) -> Factor {
    Factor {
        level,
        why: why.into(),
    }
}

/// Verification: the traced tests behind the row.
fn verification(r: &Row) -> Factor {
    match r.tests_status {
        TestsStatus::Stale => return f(0, "its traced test results are stale (another tree)"),
        TestsStatus::Failed => return f(0, "a traced test failed"),
        _ => {}
    }
    let passed: Vec<_> = r
        .tests
        .iter()
        .filter(|t| t.result == TestResult::Passed)
        .collect();
    if passed.is_empty() {
        return f(0, "no traced test passed in the recorded run");
    }
    let asserts = |a: Assertion| passed.iter().any(|t| t.assertions.contains(&a));
    let (limit, reference) = (asserts(Assertion::Limit), asserts(Assertion::Reference));
    let property = passed
        .iter()
        .any(|t| t.cases > 1 && t.assertions.contains(&Assertion::Reference));
    let numerical = r
        .evidence
        .iter()
        .any(|e| e.inputs.keys().any(|k| k.starts_with("numerical_error")));
    let n = passed.len();
    let mut v = if !limit && !reference {
        f(
            1,
            format!(
                "{n} traced test(s) passed, change detection only (snapshots): nothing asserts the limit or a reference"
            ),
        )
    } else if (limit && reference) || property {
        let what = match (limit && reference, property) {
            (true, true) => "the limit and an independent reference, one over many cases",
            (true, false) => "both the limit and an independent reference",
            _ => "an independent reference over many cases (a property test)",
        };
        if numerical {
            f(
                4,
                format!(
                    "{n} traced test(s) passed asserting {what}; the evidence estimates the model's numerical error"
                ),
            )
        } else {
            f(
                3,
                format!(
                    "{n} traced test(s) passed asserting {what}; no numerical-error estimate of the model"
                ),
            )
        }
    } else {
        f(
            2,
            format!(
                "{n} traced test(s) passed asserting {} only",
                if limit { "the limit" } else { "a reference" }
            ),
        )
    };
    if r.tests_status == TestsStatus::Incomplete && v.level > 1 {
        v = f(
            1,
            format!(
                "{}; but some traced tests were ignored or did not run",
                v.why
            ),
        );
    }
    v
}

/// Validation: the model against a measurement or a reference covering its domain.
fn validation(r: &Row, rows: &[Row]) -> Factor {
    if r.basis == Some(Basis::Measurement) {
        return f(4, "the value is a measurement of the system itself");
    }
    if let Some(i) = r.evidence.iter().find_map(|e| e.judges_input.as_deref()) {
        return f(
            3,
            format!(
                "it is the comparison of the {i}'s model with a measurement campaign (it judges that input)"
            ),
        );
    }
    for i in &r.model_inputs {
        let judge = rows.iter().find(|o| {
            o.id != r.id
                && o.evidence
                    .iter()
                    .any(|e| e.value.is_some() && e.judges_input.as_deref() == Some(i))
        });
        if let Some(j) = judge {
            return match j.status {
                Status::NonCompliant => f(
                    0,
                    format!(
                        "its {i} is rejected by {}: the model disagrees with the measurement that covers its domain",
                        j.id
                    ),
                ),
                Status::Compliant => f(3, format!("its {i} agrees with {}, a measurement", j.id)),
                Status::NotVerified => f(
                    1,
                    format!("its {i} is judged by {}, which is not verified", j.id),
                ),
            };
        }
    }
    match r.basis {
        Some(Basis::MethodValidation) => f(
            2,
            "the method is validated on synthetic scenes with known answers, not on flight data",
        ),
        Some(Basis::FlowDown) => f(
            1,
            "a flow-down of limits: no model to validate; it takes what it assumes as met",
        ),
        Some(Basis::Accepted) => f(
            1,
            "an accepted figure of another analysis: not validated here",
        ),
        _ if r.by_construction.is_some() => f(
            1,
            "it holds by construction: nothing independent compares it",
        ),
        _ => f(
            1,
            "no measurement or reference covering its domain is compared with this model",
        ),
    }
}

fn kind_level(k: Kind) -> u8 {
    match k {
        Kind::Measured => 4,
        Kind::Calibrated => 3,
        Kind::Cited | Kind::Design => 2,
        Kind::Assumed => 1,
    }
}

/// Input pedigree: the weakest stated pedigree of the row's model inputs' parameters.
fn input_pedigree(r: &Row, inputs: &Inputs) -> Factor {
    if r.model_inputs.is_empty() {
        return f(
            2,
            "no model input file: its inputs are requirement limits or fixed scenes in code",
        );
    }
    let mut weakest: Option<(u8, Vec<String>)> = None;
    let mut count = std::collections::BTreeMap::<&str, usize>::new();
    for name in &r.model_inputs {
        let Some(file) = inputs.get(name) else {
            continue;
        };
        if !file.parameters.is_empty() && file.pedigree.len() < file.parameters.len() {
            let missing: Vec<&str> = file
                .parameters
                .keys()
                .filter(|k| !file.pedigree.contains_key(*k))
                .map(String::as_str)
                .take(3)
                .collect();
            return f(
                0,
                format!("the {name} states no pedigree for {}", missing.join(", ")),
            );
        }
        for (p, k) in &file.pedigree {
            *count.entry(k.as_str()).or_default() += 1;
            let l = kind_level(*k);
            let entry = format!("{name} {p}");
            match &mut weakest {
                Some((w, ps)) if *w == l => ps.push(entry),
                Some((w, _)) if *w < l => {}
                _ => weakest = Some((l, vec![entry])),
            }
        }
    }
    let Some((level, ps)) = weakest else {
        return f(0, "its model inputs state no pedigree");
    };
    let counts: Vec<String> = count.iter().map(|(k, n)| format!("{n} {k}")).collect();
    let shown: Vec<&str> = ps.iter().take(3).map(String::as_str).collect();
    let more = if ps.len() > 3 {
        format!(" and {} more", ps.len() - 3)
    } else {
        String::new()
    };
    f(
        level,
        format!(
            "weakest: {}{more} ({}); parameters: {}",
            shown.join(", "),
            match level {
                4 => "measured",
                3 => "calibrated",
                2 => "cited or design values",
                _ => "assumed",
            },
            counts.join(", ")
        ),
    )
}

/// Results uncertainty: how the deciding value's uncertainty is stated.
fn results_uncertainty(r: &Row) -> Factor {
    if let Some(s) = &r.sampling {
        let pct = crate::units::fmt_pct(s.confidence);
        return if s.confidence >= 0.95 {
            f(
                4,
                format!("decided by its {pct} confidence bound over N = {}", s.n),
            )
        } else {
            f(
                3,
                format!(
                    "decided by a bound at only {pct} confidence over N = {}",
                    s.n
                ),
            )
        };
    }
    match &r.probability {
        Some(p) if r.basis == Some(Basis::Model) => f(
            2,
            format!("an analytic quantile ({p}) of the input spreads: no sampling bound"),
        ),
        _ => f(1, "a point value: its uncertainty is not characterised"),
    }
}

/// The largest `total_*` index of an evidence's inputs: (name, index).
fn dominant(e: &crate::matrix::EvidenceEntry) -> Option<(String, f64)> {
    e.inputs
        .iter()
        .filter_map(|(k, v)| {
            k.strip_prefix("total_")
                .and_then(|n| v.as_f64().map(|x| (n.replace('_', " "), x)))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// Results robustness: sensitivity indices attached to the row (or to a row of its check).
fn results_robustness(r: &Row, rows: &[Row]) -> Factor {
    if let Some((e, (name, x))) = r.evidence.iter().find_map(|e| dominant(e).map(|d| (e, d))) {
        return f(
            3,
            format!(
                "Sobol/Jansen total indices attached ({}): the largest, {name}, {}",
                e.check,
                crate::units::fmt_num(x)
            ),
        );
    }
    let checks: Vec<&str> = r
        .evidence
        .iter()
        .filter(|e| e.value.is_some())
        .map(|e| e.check.as_str())
        .collect();
    if let Some(o) = rows.iter().find(|o| {
        o.id != r.id
            && o.evidence.iter().any(|e| dominant(e).is_some())
            && o.evidence
                .iter()
                .any(|e| checks.contains(&e.check.as_str()))
    }) {
        return f(
            2,
            format!(
                "the sensitivity indices of {} cover the same model (same check), not this value",
                o.id
            ),
        );
    }
    f(1, "no sensitivity analysis of the deciding value")
}

/// The credibility of one row, `None` for a row with no verdict (not verified).
pub fn assess(r: &Row, rows: &[Row], inputs: &Inputs, required: Option<u8>) -> Option<Credibility> {
    if r.status == Status::NotVerified || r.value.is_none() {
        return None;
    }
    let mut c = Credibility {
        level: 0,
        weakest: String::new(),
        required,
        verification: verification(r),
        validation: validation(r, rows),
        input_pedigree: input_pedigree(r, inputs),
        results_uncertainty: results_uncertainty(r),
        results_robustness: results_robustness(r, rows),
    };
    let (name, level) = c
        .factors()
        .iter()
        .map(|(n, f)| (*n, f.level))
        .min_by_key(|(_, l)| *l)
        .expect("five factors");
    c.level = level;
    c.weakest = name.to_string();
    Some(c)
}

/// Assesses every judged row of `m` and applies the levels the requirements need: a compliant
/// row below its requirement's `credibility:` becomes not verified, with the reason and a
/// finding, and the summary is counted again.
pub fn apply(m: &mut Matrix, reqs: &Requirements, inputs: &Inputs) {
    let assessed: Vec<Option<Credibility>> = m
        .requirements
        .iter()
        .map(|r| {
            let need = reqs.get(&r.id).and_then(|q| q.credibility);
            assess(r, &m.requirements, inputs, need)
        })
        .collect();
    let mut demoted = false;
    for (r, c) in m.requirements.iter_mut().zip(assessed) {
        if let Some(c) = &c
            && c.below_required()
            && r.status == Status::Compliant
        {
            let why = format!(
                "credibility {} (weakest: {}: {}) is below the {} its requirement needs",
                c.level,
                c.weakest,
                c.factors()
                    .iter()
                    .find(|(n, _)| *n == c.weakest)
                    .map_or("", |(_, f)| f.why.as_str()),
                c.required.unwrap_or(0)
            );
            r.status = Status::NotVerified;
            r.verdict = format!(
                "not-verified (credibility {} below {})",
                c.level,
                c.required.unwrap_or(0)
            );
            r.findings.insert(0, why.clone());
            r.reason = Some(why);
            demoted = true;
        }
        r.credibility = c;
    }
    if demoted {
        m.retain_rows(|_| true);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{Evidence, InputFile};
    use crate::{Dim, Quantity};
    use std::path::PathBuf;

    const REQS: &str = "family: f
requirements:
  - id: W-VEL
    title: a
    text: shall
    source: s
    quantity: q
    dimension: velocity
    limit: <= 5 um/s
    method: analysis
    activity: mc
    credibility: CRED
  - id: W-CAL
    title: b
    text: shall
    source: s
    quantity: q
    dimension: dimensionless
    limit: <= 3
    method: analysis
    activity: cal
";

    /// W-VEL computed from `design`, which W-CAL judges (with the value `z`: above 3 rejects it).
    fn matrix(cred: u8, z: f64) -> Matrix {
        let reqs = Requirements::from_sources(&[(
            PathBuf::from("f.yaml"),
            REQS.replace("CRED", &cred.to_string()),
        )])
        .unwrap();
        let mut m = Matrix::build(
            &reqs,
            &[(
                "mc".into(),
                vec![
                    Evidence::measured(
                        "W-VEL",
                        Quantity::new(1e-6, Dim::VELOCITY),
                        Basis::Model,
                        "mc",
                    )
                    .from_inputs(&["design"])
                    .with_input("total_adhesion", 0.8)
                    .with_input("total_preload", 0.1),
                    Evidence::measured(
                        "W-CAL",
                        Quantity::new(z, Dim::DIMENSIONLESS),
                        Basis::Model,
                        "cal",
                    )
                    .judging_input("design"),
                ],
            )],
            None,
            &[],
        );
        let mut inputs = Inputs::default();
        let text = "m_kg: 1.96\nk: 3\npedigree:\n  m_kg: {kind: measured, ref: \"scale\"}\n  k: {kind: assumed, ref: \"guess\"}\n";
        inputs.insert(
            "design",
            "design",
            InputFile::new("d.yaml", text).with_parameters(),
        );
        apply(&mut m, &reqs, &inputs);
        m
    }

    #[test]
    fn each_factor_reads_the_rows_own_evidence_and_the_weakest_decides() {
        let m = matrix(0, 2.0);
        let c = m.requirements[0].credibility.as_ref().unwrap();
        assert_eq!(c.verification.level, 0, "no recorded test run");
        assert_eq!(c.validation.level, 3, "{}", c.validation.why);
        assert!(c.validation.why.contains("agrees with W-CAL"));
        assert_eq!(c.input_pedigree.level, 1, "{}", c.input_pedigree.why);
        assert!(c.input_pedigree.why.contains("design k"));
        assert_eq!(c.results_uncertainty.level, 1);
        assert_eq!(c.results_robustness.level, 3);
        assert!(
            c.results_robustness.why.contains("adhesion, 0.8"),
            "{}",
            c.results_robustness.why
        );
        assert_eq!((c.level, c.weakest.as_str()), (0, "verification"));
        assert_eq!(m.requirements[0].status, Status::Compliant, "needs 0");
        let judge = m.requirements[1].credibility.as_ref().unwrap();
        assert!(judge.validation.why.contains("judges that input"));
    }

    #[test]
    fn a_rejected_input_is_validation_0_and_a_needed_level_demotes_the_row() {
        let m = matrix(1, 5.0);
        let r = &m.requirements[0];
        let c = r.credibility.as_ref().unwrap();
        assert_eq!(c.validation.level, 0);
        assert!(c.validation.why.contains("rejected by W-CAL"));
        assert_eq!(c.required, Some(1));
        assert_eq!(r.status, Status::NotVerified, "below the level it needs");
        assert!(
            r.reason
                .as_deref()
                .unwrap()
                .contains("below the 1 its requirement needs")
        );
        assert_eq!(m.summary.compliant, 0);
        assert!(c.short().ends_with("needs 1)"), "{}", c.short());
    }
}
