//! The Verification Control Document (ECSS-E-ST-10-02C, annex on the VCD): for every
//! requirement, its ID and text, parent and children, verification method, the activity and its
//! evidence (check, Monte Carlo N and seed, dataset, test names, snapshots), value, limit,
//! margin, the basis of the verdict, compliance (yes / yes (accepted) / no / not verified) and
//! close-out status with its reason. Exported as
//! Markdown and CSV here, and as a section of the HTML report.

use crate::{Report, fmt_margin, fmt_opt};
use geodesic_core::matrix::{Row, Status};
use serde::Serialize;

/// One VCD line.
#[derive(Clone, Debug, Serialize)]
pub struct VcdLine {
    /// Requirement ID.
    pub id: String,
    /// Shall statement.
    pub text: String,
    /// Parent ID.
    pub parent: String,
    /// Children IDs, `;`-separated.
    pub children: String,
    /// Verification method.
    pub method: String,
    /// Verification activity.
    pub activity: String,
    /// Evidence: checks with their inputs, then tests.
    pub evidence: String,
    /// Value in the requirement's unit.
    pub value: String,
    /// Limit as written.
    pub limit: String,
    /// Margin.
    pub margin: String,
    /// What the verdict rests on: model, flow-down, accepted (empty when not verified).
    pub basis: &'static str,
    /// yes / yes (accepted) / no / not verified.
    pub compliance: &'static str,
    /// closed / open.
    pub close_out: &'static str,
    /// Why.
    pub reason: String,
}

/// Compliance as the VCD states it (ECSS-E-ST-10-02C Annex B): `yes` (compliant on a model or
/// flow-down), `yes (accepted)` (compliant on a cited external result), `no` (non-compliant),
/// `not verified` (no evidence gives a value: in ECSS "partial" means partly met, which a
/// missing verification is not).
pub fn compliance(r: &Row) -> &'static str {
    match (r.status, r.basis) {
        (Status::Compliant, Some(geodesic_core::Basis::Accepted)) => "yes (accepted)",
        (Status::Compliant, _) => "yes",
        (Status::NonCompliant, _) => "no",
        (Status::NotVerified, _) => "not verified",
    }
}

/// Builds the VCD lines from a report.
pub fn lines(rep: &Report) -> Vec<VcdLine> {
    rep.matrix
        .requirements
        .iter()
        .map(|r| {
            let mut ev: Vec<String> = r
                .evidence
                .iter()
                .map(|e| {
                    let inputs: Vec<String> =
                        e.inputs.iter().map(|(k, v)| format!("{k}={v}")).collect();
                    if inputs.is_empty() {
                        format!("check {}", e.check)
                    } else {
                        format!("check {} ({})", e.check, inputs.join(", "))
                    }
                })
                .collect();
            ev.extend(
                r.tests
                    .iter()
                    .map(|t| format!("{} test {} ({})", t.kind, t.test, t.result.as_str())),
            );
            if let Some(d) = &r.disposition {
                ev.push(format!("{} {}", d.kind.as_str(), d.reference));
            }
            let basis = r.basis.map_or("", |b| b.as_str());
            let tests = crate::tests_word(r, rep.matrix.test_run.is_some());
            let (close_out, reason) = match r.status {
                Status::Compliant => (
                    "closed",
                    format!("value within limit ({basis}); traced tests: {tests}"),
                ),
                Status::NonCompliant => (
                    "open",
                    format!(
                        "value {} {} violates `{}`{}",
                        fmt_opt(r.value),
                        r.unit,
                        r.limit_text,
                        r.disposition.as_ref().map_or(String::new(), |d| format!(
                            "; {} {}{}: {}",
                            d.kind.as_str(),
                            d.reference,
                            if d.expired { " (EXPIRED)" } else { "" },
                            d.reason
                        ))
                    ),
                ),
                Status::NotVerified => (
                    "open",
                    r.reason.clone().unwrap_or_else(|| "no evidence".into()),
                ),
            };
            VcdLine {
                id: r.id.clone(),
                text: r.text.clone(),
                parent: r.parent.clone().unwrap_or_default(),
                children: r.children.join(";"),
                method: r.method.clone(),
                activity: r.activity.clone(),
                evidence: ev.join("; "),
                value: r.value.map_or(String::new(), |_| {
                    format!("{} {}", fmt_opt(r.value), r.unit)
                }),
                limit: r.limit_text.clone(),
                margin: fmt_margin(r.margin),
                basis: r.basis.map_or("", |b| b.as_str()),
                compliance: compliance(r),
                close_out,
                reason,
            }
        })
        .collect()
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The VCD as CSV (RFC 4180 quoting), one header row.
pub fn csv(rep: &Report) -> String {
    let mut o = String::from(
        "id,text,parent,children,method,activity,evidence,value,limit,margin,basis,compliance,close_out,reason\n",
    );
    for l in lines(rep) {
        let f = [
            &l.id,
            &l.text,
            &l.parent,
            &l.children,
            &l.method,
            &l.activity,
            &l.evidence,
            &l.value,
            &l.limit,
            &l.margin,
            l.basis,
            l.compliance,
            l.close_out,
            &l.reason,
        ];
        let row: Vec<String> = f.iter().map(|s| csv_field(s)).collect();
        o.push_str(&row.join(","));
        o.push('\n');
    }
    o
}

/// The VCD as Markdown.
pub fn markdown(rep: &Report) -> String {
    let mut o = String::from("# Verification Control Document\n\n");
    for (k, v) in crate::run_lines(rep) {
        o.push_str(&format!("- {k}: {}\n", v.replace('|', "\\|")));
    }
    o.push('\n');
    o.push_str("| ID | Requirement | Parent | Children | Method | Activity / evidence | Value | Limit | Margin | Basis | Compliance | Close-out |\n");
    o.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    let c = |s: &str| s.replace('|', "\\|");
    for l in lines(rep) {
        o.push_str(&format!(
            "| {} | {} | {} | {} | {} | {}<br>{} | {} | `{}` | {} | {} | {} | {}: {} |\n",
            l.id,
            c(&l.text),
            l.parent,
            l.children.replace(';', ", "),
            l.method,
            c(&l.activity),
            c(&l.evidence),
            l.value,
            l.limit,
            l.margin,
            l.basis,
            l.compliance,
            l.close_out,
            c(&l.reason)
        ));
    }
    o
}
