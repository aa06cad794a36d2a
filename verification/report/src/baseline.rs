//! Change impact: compares a compliance report with a baseline `compliance.json` from an
//! earlier run and lists every requirement whose status flipped or whose margin moved beyond a
//! stated tolerance, the requirements added or removed, and the checks whose evidence changed
//! (suspect evidence). A regression (a status that got worse, a margin that fell by more than
//! the tolerance, a requirement that disappeared) makes `geodesic verify --baseline` exit 1.

use crate::Report;
use geodesic_core::matrix::Status;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Deserialize)]
struct OldReport {
    requirements: Vec<OldRow>,
}

#[derive(Deserialize)]
struct OldRow {
    id: String,
    status: String,
    value: Option<f64>,
    margin: Option<f64>,
    #[serde(default)]
    unit: String,
    #[serde(default)]
    evidence: Vec<OldEvidence>,
}

#[derive(Deserialize)]
struct OldEvidence {
    check: String,
    value: Option<f64>,
    #[serde(default)]
    inputs: BTreeMap<String, serde_json::Value>,
}

/// A baseline file that cannot be read: one line with file:line:column.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BaselineError(pub String);

/// A requirement whose status changed.
#[derive(Clone, Debug, Serialize)]
pub struct Flip {
    /// Requirement ID.
    pub id: String,
    /// Status in the baseline.
    pub from: String,
    /// Status now.
    pub to: String,
    /// Whether it got worse.
    pub regression: bool,
}

/// A requirement whose margin moved by more than the tolerance.
#[derive(Clone, Debug, Serialize)]
pub struct Move {
    /// Requirement ID.
    pub id: String,
    /// Margin in the baseline (fraction).
    pub from: f64,
    /// Margin now (fraction).
    pub to: f64,
    /// Value in the baseline (requirement unit).
    pub value_from: Option<f64>,
    /// Value now (requirement unit).
    pub value_to: Option<f64>,
    /// Unit of the values.
    pub unit: String,
    /// Whether the margin fell.
    pub regression: bool,
}

/// Evidence of a check for a requirement whose value or inputs changed.
#[derive(Clone, Debug, Serialize)]
pub struct Suspect {
    /// Requirement ID.
    pub id: String,
    /// Check name.
    pub check: String,
    /// What changed.
    pub what: String,
}

/// The change impact of a run against a baseline.
#[derive(Clone, Debug, Serialize)]
pub struct Diff {
    /// Baseline file.
    pub baseline: String,
    /// Margin tolerance (absolute, as a fraction of the limit).
    pub tolerance: f64,
    /// Status flips.
    pub flipped: Vec<Flip>,
    /// Margins moved beyond the tolerance.
    pub margin_moved: Vec<Move>,
    /// Requirements new in this run.
    pub added: Vec<String>,
    /// Requirements of the baseline missing now.
    pub removed: Vec<String>,
    /// Checks whose evidence changed.
    pub suspect_evidence: Vec<Suspect>,
    /// Number of regressions.
    pub regressions: usize,
}

fn rank(s: &str) -> u8 {
    match s {
        "compliant" => 0,
        "not-verified" => 1,
        _ => 2,
    }
}

/// Reads a baseline file.
fn load(path: &Path) -> Result<OldReport, BaselineError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| BaselineError(format!("{}: {e}", path.display())))?;
    serde_json::from_str(&text).map_err(|e| {
        BaselineError(format!(
            "{}:{}:{}: not a geodesic compliance.json: {e}",
            path.display(),
            e.line(),
            e.column()
        ))
    })
}

/// Compares `now` with the baseline file.
pub fn diff(now: &Report, baseline: &Path, tolerance: f64) -> Result<Diff, BaselineError> {
    let old = load(baseline)?;
    let old_by: BTreeMap<&str, &OldRow> = old
        .requirements
        .iter()
        .map(|r| (r.id.as_str(), r))
        .collect();
    let mut d = Diff {
        baseline: baseline.display().to_string(),
        tolerance,
        flipped: vec![],
        margin_moved: vec![],
        added: vec![],
        removed: vec![],
        suspect_evidence: vec![],
        regressions: 0,
    };
    for r in &now.matrix.requirements {
        let Some(o) = old_by.get(r.id.as_str()) else {
            d.added.push(r.id.clone());
            continue;
        };
        let to = r.status.as_str();
        if o.status != to {
            let regression = rank(to) > rank(&o.status);
            d.flipped.push(Flip {
                id: r.id.clone(),
                from: o.status.clone(),
                to: to.into(),
                regression,
            });
        }
        if let (Some(a), Some(b)) = (o.margin, r.margin) {
            if (b - a).abs() > tolerance {
                d.margin_moved.push(Move {
                    id: r.id.clone(),
                    from: a,
                    to: b,
                    value_from: o.value,
                    value_to: r.value,
                    unit: if o.unit.is_empty() {
                        r.unit.clone()
                    } else {
                        o.unit.clone()
                    },
                    regression: b < a,
                });
            }
        }
        for e in &r.evidence {
            match o.evidence.iter().find(|x| x.check == e.check) {
                None => d.suspect_evidence.push(Suspect {
                    id: r.id.clone(),
                    check: e.check.clone(),
                    what: "new evidence".into(),
                }),
                Some(x) => {
                    let mut what = Vec::new();
                    if !opt_close(x.value, e.value) {
                        what.push(format!("value {:?} -> {:?}", x.value, e.value));
                    }
                    let keys: std::collections::BTreeSet<&String> =
                        x.inputs.keys().chain(e.inputs.keys()).collect();
                    for k in keys {
                        if !json_close(x.inputs.get(k), e.inputs.get(k)) {
                            what.push(format!("input {k} changed"));
                        }
                    }
                    if !what.is_empty() {
                        d.suspect_evidence.push(Suspect {
                            id: r.id.clone(),
                            check: e.check.clone(),
                            what: what.join(", "),
                        });
                    }
                }
            }
        }
    }
    let now_ids: Vec<&str> = now
        .matrix
        .requirements
        .iter()
        .map(|r| r.id.as_str())
        .collect();
    d.removed = old
        .requirements
        .iter()
        .filter(|o| !now_ids.contains(&o.id.as_str()))
        .map(|o| o.id.clone())
        .collect();
    d.regressions = d.flipped.iter().filter(|f| f.regression).count()
        + d.margin_moved.iter().filter(|m| m.regression).count()
        + d.removed.len();
    Ok(d)
}

/// Numbers equal to 1e-12 relative: a value re-read from JSON is the same evidence.
fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

fn opt_close(a: Option<f64>, b: Option<f64>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => close(a, b),
        (None, None) => true,
        _ => false,
    }
}

/// JSON values equal, numbers compared with [`close`].
fn json_close(a: Option<&serde_json::Value>, b: Option<&serde_json::Value>) -> bool {
    use serde_json::Value;
    match (a, b) {
        (None, None) => true,
        (Some(Value::Number(x)), Some(Value::Number(y))) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => close(x, y),
            _ => x == y,
        },
        (Some(Value::Array(x)), Some(Value::Array(y))) => {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| json_close(Some(p), Some(q)))
        }
        (Some(Value::Object(x)), Some(Value::Object(y))) => {
            x.len() == y.len() && x.iter().all(|(k, v)| json_close(Some(v), y.get(k)))
        }
        (Some(x), Some(y)) => x == y,
        _ => false,
    }
}

/// Markdown summary fit for a pull-request comment.
pub fn markdown(d: &Diff) -> String {
    let mut o = String::from("## geodesic: change impact against the baseline\n\n");
    o.push_str(&format!(
        "Baseline `{}` · margin tolerance {:.2} % of the limit · **{} regression(s)**\n\n",
        d.baseline,
        100.0 * d.tolerance,
        d.regressions
    ));
    if d.flipped.is_empty()
        && d.margin_moved.is_empty()
        && d.added.is_empty()
        && d.removed.is_empty()
    {
        o.push_str("No requirement changed status or moved its margin beyond the tolerance.\n");
    }
    if !d.flipped.is_empty() {
        o.push_str("| Requirement | Status before | Status now | |\n|---|---|---|---|\n");
        for f in &d.flipped {
            let tag = if f.regression {
                "⬇️ regression"
            } else {
                "⬆️ improvement"
            };
            o.push_str(&format!("| {} | {} | {} | {tag} |\n", f.id, f.from, f.to));
        }
        o.push('\n');
    }
    if !d.margin_moved.is_empty() {
        o.push_str("| Requirement | Margin before | Margin now | Value before | Value now | |\n|---|---|---|---|---|---|\n");
        for m in &d.margin_moved {
            let tag = if m.regression {
                "⬇️ regression"
            } else {
                "⬆️"
            };
            let v = |x: Option<f64>| {
                x.map_or("—".into(), |x| {
                    format!("{} {}", geodesic_core::units::fmt_num(x), m.unit)
                })
            };
            o.push_str(&format!(
                "| {} | {:.2} % | {:.2} % | {} | {} | {tag} |\n",
                m.id,
                100.0 * m.from,
                100.0 * m.to,
                v(m.value_from),
                v(m.value_to)
            ));
        }
        o.push('\n');
    }
    if !d.added.is_empty() {
        o.push_str(&format!("Added: {}\n\n", d.added.join(", ")));
    }
    if !d.removed.is_empty() {
        o.push_str(&format!(
            "Removed (regression): {}\n\n",
            d.removed.join(", ")
        ));
    }
    if !d.suspect_evidence.is_empty() {
        o.push_str("Suspect evidence (changed since the baseline):\n\n");
        for s in &d.suspect_evidence {
            o.push_str(&format!("- {} via `{}`: {}\n", s.id, s.check, s.what));
        }
    }
    o
}

/// Whether a status is a regression from another (used in tests and by callers).
pub fn worse(from: Status, to: Status) -> bool {
    rank(from.as_str()) < rank(to.as_str())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::report;

    fn diff_of(old: &Report, new: &Report, tol: f64) -> Diff {
        // each call its own file: tests run in parallel
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("baseline.json");
        std::fs::write(&p, serde_json::to_string(old).unwrap()).unwrap();
        diff(new, &p, tol).unwrap()
    }

    #[test]
    fn identical_runs_have_no_change() {
        let d = diff_of(&report(1.3, 2.0), &report(1.3, 2.0), 0.01);
        assert!(d.flipped.is_empty() && d.margin_moved.is_empty() && d.suspect_evidence.is_empty());
        assert_eq!(d.regressions, 0);
    }

    #[test]
    fn names_exactly_the_requirements_that_moved() {
        // F-A moves by 2 % of the limit (beyond 1 %), F-B by 0.2 % (within)
        let d = diff_of(&report(1.3, 2.0), &report(1.4, 2.01), 0.01);
        let moved: Vec<&str> = d.margin_moved.iter().map(|m| m.id.as_str()).collect();
        assert_eq!(moved, ["F-A"]);
        assert_eq!(d.regressions, 1);
        // both values changed: both are suspect evidence
        assert_eq!(d.suspect_evidence.len(), 2);
        assert!(markdown(&d).contains("F-A"));
    }

    #[test]
    fn a_flip_to_non_compliant_is_a_regression_and_back_is_not() {
        let d = diff_of(&report(1.3, 2.0), &report(6.0, 2.0), 0.01);
        assert_eq!(d.flipped.len(), 1);
        assert!(d.flipped[0].regression);
        let d = diff_of(&report(6.0, 2.0), &report(1.3, 2.0), 0.01);
        assert!(!d.flipped[0].regression);
        assert_eq!(d.regressions, 0);
    }

    #[test]
    fn a_malformed_baseline_names_file_and_line() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("baseline.json");
        std::fs::write(&p, "{\"requirements\": [\n  {\"id\": 3}\n]}").unwrap();
        let e = diff(&report(1.0, 1.0), &p, 0.01).unwrap_err().to_string();
        assert!(e.contains(":2:"), "{e}");
    }
}
