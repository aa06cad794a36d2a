//! The verification status of each requirement, read from the `compliance.json` that
//! `geodesic verify` writes (the contract of `docs/spec/interface.md`: rows with `id`,
//! `status`, `basis`, `value`, `limit`, `margin`, `disposition`; the `run` object). Only the
//! fields the ReqIF export carries are read; fields added later are ignored.

use geodesic_core::Requirements;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// Why a compliance matrix was refused. Display is one line naming the file.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{file}: {cause}")]
pub struct StatusError {
    /// The matrix file.
    pub file: String,
    /// One-line cause.
    pub cause: String,
}

/// The VCD status of one requirement.
#[derive(Clone, Debug, PartialEq)]
pub struct RowStatus {
    /// `compliant`, `non-compliant` or `not-verified`.
    pub status: String,
    /// `model`, `flow-down`, `measurement`, `method-validation`, `accepted`, `illustration`;
    /// `None` when not verified.
    pub basis: Option<String>,
    /// The status as it must be read (`compliant (flow-down; assumes not-verified TMS-X-VEL)`),
    /// when the matrix states it.
    pub verdict: Option<String>,
    /// For a sampled value, the sample in words: the quantile or probability, N, the
    /// confidence bounds.
    pub sample: Option<String>,
    /// Value in the requirement's unit ([`RowStatus::unit`]).
    pub value: Option<f64>,
    /// The requirement's unit (empty for a dimensionless quantity).
    pub unit: String,
    /// Margin as a fraction of the limit (positive: met).
    pub margin: Option<f64>,
    /// `closed` (compliant) or `open` (non-compliant or not verified), or the matrix's own
    /// `close_out` when it states one.
    pub close_out: String,
    /// Disposition of a known non-compliance: `NCR NCR-GEO-001`.
    pub disposition: Option<String>,
    /// Why the requirement is not verified.
    pub reason: Option<String>,
    /// The limit as written in the matrix (checked against the requirement set).
    pub limit_text: String,
    /// The verdict's credibility (issue 49): `level 0 (weakest: validation); verification 3:
    /// ...; validation 0: ...`, when the matrix states it.
    pub credibility: Option<String>,
}

/// The status of every row of a compliance matrix, and where it comes from.
#[derive(Clone, Debug, Default)]
pub struct StatusSet {
    /// Rows by requirement ID.
    pub rows: BTreeMap<String, RowStatus>,
    /// One line naming the verify run: commit, dirty flag, date, tool version.
    pub provenance: String,
}

impl StatusSet {
    /// Parses a `compliance.json` text (`file` names it in errors).
    pub fn parse(file: &Path, text: &str) -> Result<StatusSet, StatusError> {
        let err = |cause: String| StatusError {
            file: file.display().to_string(),
            cause,
        };
        let v: Value = serde_json::from_str(text).map_err(|e| {
            err(format!(
                "line {}: not a JSON compliance matrix: {}",
                e.line(),
                geodesic_util::text::clip(&e.to_string(), 300)
            ))
        })?;
        let rows = v
            .get("requirements")
            .and_then(Value::as_array)
            .ok_or_else(|| {
                err("no `requirements` array: not a compliance.json of geodesic verify".into())
            })?;
        let mut out = StatusSet::default();
        for (i, r) in rows.iter().enumerate() {
            let s = |k: &str| r.get(k).and_then(Value::as_str).map(str::to_string);
            let n = |k: &str| r.get(k).and_then(Value::as_f64);
            let id = s("id").ok_or_else(|| err(format!("requirements[{i}] has no `id`")))?;
            let status = s("status").ok_or_else(|| err(format!("{id}: no `status`")))?;
            if !matches!(
                status.as_str(),
                "compliant" | "non-compliant" | "not-verified"
            ) {
                return Err(err(format!("{id}: unknown status `{status}`")));
            }
            let basis = s("basis");
            if let Some(b) = &basis
                && !matches!(
                    b.as_str(),
                    "model"
                        | "flow-down"
                        | "measurement"
                        | "method-validation"
                        | "accepted"
                        | "illustration"
                )
            {
                return Err(err(format!("{id}: unknown basis `{b}`")));
            }
            // the matrix's own close-out when it states one ("closed", "open", or a phrase
            // starting with either), else from the status
            let close_out = match s("close_out") {
                Some(c) if c.starts_with("closed") => "closed".to_string(),
                Some(c) if c.starts_with("open") => "open".to_string(),
                _ if status == "compliant" => "closed".to_string(),
                _ => "open".to_string(),
            };
            let disposition = r.get("disposition").and_then(|d| {
                let kind = d.get("kind").and_then(Value::as_str)?;
                let reference = d.get("reference").and_then(Value::as_str)?;
                Some(format!("{kind} {reference}"))
            });
            let sample = r.get("sampling").filter(|v| v.is_object()).map(|sm| {
                let f = |k: &str| sm.get(k).and_then(Value::as_f64);
                let num =
                    |v: Option<f64>| v.map_or("none".to_string(), geodesic_core::units::fmt_num);
                let pct = |v: Option<f64>| v.map_or("?".to_string(), geodesic_core::units::fmt_pct);
                let unit = s("unit").unwrap_or_default();
                format!(
                    "{} {} of N = {}: estimate {} {unit}, {} bounds [{}, {}] {unit}",
                    sm.get("statistic")
                        .and_then(Value::as_str)
                        .unwrap_or("sample"),
                    pct(f("probability")),
                    sm.get("n").and_then(Value::as_u64).unwrap_or(0),
                    num(f("estimate")),
                    pct(f("confidence")),
                    num(f("lower")),
                    num(f("upper")),
                )
            });
            let row = RowStatus {
                status,
                basis,
                verdict: s("verdict"),
                sample,
                value: n("value"),
                unit: s("unit").unwrap_or_default(),
                margin: n("margin"),
                close_out,
                disposition,
                reason: s("reason"),
                limit_text: s("limit_text").unwrap_or_default(),
                credibility: r
                    .get("credibility")
                    .filter(|c| c.is_object())
                    .map(credibility_text),
            };
            if out.rows.insert(id.clone(), row).is_some() {
                return Err(err(format!("requirement {id} appears twice")));
            }
        }
        let run = v.get("run");
        let rs = |k: &str| {
            run.and_then(|r| r.get(k))
                .and_then(Value::as_str)
                .unwrap_or("unknown")
                .to_string()
        };
        let dirty = run
            .and_then(|r| r.get("dirty"))
            .and_then(Value::as_bool)
            .map_or("", |d| if d { " (dirty tree)" } else { "" });
        out.provenance = format!(
            "verification status from geodesic verify of commit {}{dirty}, run {}, tool {}",
            rs("commit"),
            rs("date"),
            rs("tool_version")
        );
        Ok(out)
    }

    /// Checks that the matrix was computed for this requirement set: the same IDs, and the
    /// same limit for each (a status exported beside a different limit would be a false
    /// record).
    pub fn check_against(&self, file: &Path, reqs: &Requirements) -> Result<(), StatusError> {
        let err = |cause: String| StatusError {
            file: file.display().to_string(),
            cause,
        };
        for r in &reqs.items {
            let Some(row) = self.rows.get(r.id.as_str()) else {
                return Err(err(format!(
                    "has no row for requirement {}: the matrix was computed for another requirement set (run geodesic verify again)",
                    r.id
                )));
            };
            let limit_text = r
                .limit
                .as_ref()
                .map_or(geodesic_core::matrix::QUALITATIVE_LIMIT_TEXT, |l| {
                    l.text.as_str()
                });
            if !row.limit_text.is_empty() && row.limit_text != limit_text {
                return Err(err(format!(
                    "{}: the matrix judged limit `{}` but the requirement set says `{}` (run geodesic verify again)",
                    r.id, row.limit_text, limit_text
                )));
            }
        }
        if let Some(id) = self.rows.keys().find(|id| reqs.get(id).is_none()) {
            return Err(err(format!(
                "row {id} is not in the requirement set: the matrix was computed for another requirement set (run geodesic verify again)"
            )));
        }
        Ok(())
    }
}

/// A row's `credibility` object in one line: `level 0 (weakest: validation); verification 3:
/// why; ...`.
fn credibility_text(c: &Value) -> String {
    let level = |v: &Value| v.get("level").and_then(Value::as_u64).unwrap_or(0);
    let mut parts = vec![format!(
        "level {} (weakest: {})",
        level(c),
        c.get("weakest").and_then(Value::as_str).unwrap_or("?")
    )];
    for (key, name) in [
        ("verification", "verification"),
        ("validation", "validation"),
        ("input_pedigree", "input pedigree"),
        ("results_uncertainty", "results uncertainty"),
        ("results_robustness", "results robustness"),
    ] {
        if let Some(f) = c.get(key) {
            parts.push(format!(
                "{name} {}: {}",
                level(f),
                f.get("why").and_then(Value::as_str).unwrap_or("")
            ));
        }
    }
    parts.join("; ")
}
