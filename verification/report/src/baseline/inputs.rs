//! The gate treats a changed model input like a changed requirement (issue 49): every
//! parameter of a declared input file whose value differs from the baseline's
//! (`run.inputs.NAME.parameters`) is "input changed, needs review", with the parameter, its old
//! and new value and the rows it moved, whichever way they moved (a margin that rose is no more
//! a free pass than one that fell: an input edit can close a known non-compliance). A baseline
//! written before the parameters were recorded is compared by the file's SHA-256.

use super::{Change, Diff, OldRow, opt_close};
use crate::Report;
use geodesic_core::matrix::Row;
use serde::Serialize;
use std::collections::BTreeMap;

/// One changed parameter of a model input.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct InputChange {
    /// The input's name (`charge`).
    pub input: String,
    /// The file read now.
    pub label: String,
    /// The parameter's path (`contact_voltage_2sigma_v`); `(file)` when the baseline has only
    /// the file's SHA-256.
    pub parameter: String,
    /// Its value in the baseline (`absent` when the baseline has no such parameter).
    pub old: String,
    /// Its value now (`absent` when it was removed).
    pub new: String,
    /// The rows computed from this input that moved (status, value or margin), with how.
    pub rows: Vec<String>,
}

impl InputChange {
    /// In words: `input changed, needs review: charge contact_voltage_2sigma_v 1.0 -> 0.95
    /// (models/charge/charge.yaml)`.
    pub fn words(&self) -> String {
        format!(
            "input changed, needs review: {} {} {} -> {} ({})",
            self.input, self.parameter, self.old, self.new, self.label
        )
    }
}

/// How a row moved from the baseline's (status, value, margin), in words (`None`: it did not).
fn moved(r: &Row, o: &OldRow) -> Option<String> {
    let mut how = Vec::new();
    if r.status.as_str() != o.status {
        how.push(format!("status {} -> {}", o.status, r.status.as_str()));
    }
    if !opt_close(o.value, r.value) {
        how.push(format!(
            "value {} -> {}",
            super::val(o.value, &r.unit),
            super::val(r.value, &r.unit)
        ));
    }
    if !opt_close(o.margin, r.margin) {
        how.push(format!(
            "margin {} -> {}",
            super::pct(o.margin),
            super::pct(r.margin)
        ));
    }
    // the verdict's words alone are not compared: a stale test run qualifies every row
    (!how.is_empty()).then(|| how.join(", "))
}

/// The parameters of the baseline's input `name`, or its SHA-256 when it recorded none.
fn old_params(v: &serde_json::Value) -> (BTreeMap<String, String>, Option<String>) {
    let params = v
        .get("parameters")
        .and_then(|p| p.as_object())
        .map(|m| {
            m.iter()
                .filter_map(|(k, v)| v.as_str().map(|s| (k.clone(), s.to_string())))
                .collect()
        })
        .unwrap_or_default();
    let sha = v.get("sha256").and_then(|s| s.as_str()).map(str::to_string);
    (params, sha)
}

/// Compares the run's model inputs with the baseline's and marks every row each changed
/// parameter moved; a change that moved no row is a regression of its own (counted in
/// [`Diff::regressions`]).
pub(super) fn gate(
    now: &Report,
    old_inputs: &BTreeMap<String, serde_json::Value>,
    old_by: &BTreeMap<&str, &OldRow>,
    d: &mut Diff,
) {
    for (name, f) in &now.run.inputs.files {
        let Some(ov) = old_inputs.get(name) else {
            continue;
        };
        let (old, old_sha) = old_params(ov);
        let mut changed: Vec<(String, String, String)> = Vec::new();
        if old.is_empty() {
            if let Some(s) = old_sha
                && s != f.sha256
            {
                changed.push((
                    "(file)".into(),
                    format!("sha256 {s}"),
                    format!("sha256 {}", f.sha256),
                ));
            }
        } else {
            let keys: std::collections::BTreeSet<&String> =
                old.keys().chain(f.parameters.keys()).collect();
            for k in keys {
                let (a, b) = (old.get(k), f.parameters.get(k));
                if a != b {
                    let s = |x: Option<&String>| x.cloned().unwrap_or_else(|| "absent".into());
                    changed.push((k.clone(), s(a), s(b)));
                }
            }
        }
        if changed.is_empty() {
            continue;
        }
        let rows: Vec<(&Row, String)> = now
            .matrix
            .requirements
            .iter()
            .filter(|r| r.model_inputs.iter().any(|m| m == name))
            .filter_map(|r| {
                old_by
                    .get(r.id.as_str())
                    .and_then(|o| moved(r, o))
                    .map(|how| (r, how))
            })
            .collect();
        for (parameter, old, new) in changed {
            let c = InputChange {
                input: name.clone(),
                label: f.label.clone(),
                parameter,
                old,
                new,
                rows: rows
                    .iter()
                    .map(|(r, how)| format!("{} ({how})", r.id))
                    .collect(),
            };
            for (r, how) in &rows {
                let line = format!("{}; it moved: {how}", c.words());
                match d.changes.iter_mut().find(|x| x.id == r.id) {
                    Some(x) => {
                        x.regression = true;
                        x.regressions.push(line);
                    }
                    None => d.changes.push(Change {
                        id: r.id.clone(),
                        regression: true,
                        regressions: vec![line],
                        notes: vec![],
                        status: (
                            old_by
                                .get(r.id.as_str())
                                .map_or("absent".into(), |o| o.status.clone()),
                            r.status.as_str().to_string(),
                        ),
                        margin: (old_by.get(r.id.as_str()).and_then(|o| o.margin), r.margin),
                    }),
                }
            }
            d.inputs_changed.push(c);
        }
    }
}
