//! The Verification Control Document with the fields of ECSS-E-ST-10-02C Annex B: for every
//! requirement its ID, title, text and source; parent and children; verification level and
//! stage; method; the activity and the report section that holds the evidence; the evidence and
//! its references (report, tests, NCR, waiver, RFD); value, limit, margin and the basis of the
//! verdict; compliance (yes / no / partial / not verified); close-out (open / closed) with its
//! reason and reference; remarks; and the re-verification flag a baseline comparison sets.
//!
//! Evidence is written as an engineer writes it (rounded numbers with units, short test names);
//! the full detail (every input of every check, the full test names and what they asserted) is
//! in [`VcdLine::detail`], one click away in the HTML (`<details>`), and in `compliance.json`.
//! Exported as Markdown, CSV and XLSX here, and as HTML by [`crate::html`].

use crate::{Report, fmt_limit, fmt_margin, fmt_value};
use geodesic_core::disposition::DispositionKind;
use geodesic_core::matrix::{EvidenceEntry, Row, Status, TestRef};
use geodesic_core::units::fmt_num;
use serde::Serialize;

/// One VCD line (one requirement).
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct VcdLine {
    /// Requirement ID.
    pub id: String,
    /// Title.
    pub title: String,
    /// Shall statement.
    pub text: String,
    /// Where the requirement comes from.
    pub source: String,
    /// Parent ID (empty when none).
    pub parent: String,
    /// Children IDs.
    pub children: Vec<String>,
    /// Verification level (equipment, subsystem, element, system).
    pub level: String,
    /// Verification stage (qualification, acceptance, pre-launch, in-orbit, post-landing).
    pub stage: String,
    /// Verification method (test, analysis, review-of-design, inspection).
    pub method: String,
    /// The verification activity.
    pub activity: String,
    /// The report section holding the evidence (`index.html#REL-GPRM-VEL`).
    pub section: String,
    /// The evidence in a few words (`release-montecarlo: 1.329 um/s, N = 100 000, seed 1`).
    pub evidence: String,
    /// The evidence in full: each check with every input, each test with its full name, kind,
    /// location, result and assertions; one item per line.
    pub detail: Vec<String>,
    /// Evidence references: the report and its section, the traced tests (short names), the
    /// NCR, waiver or RFD.
    pub references: Vec<String>,
    /// Value in the requirement's unit (`—` when none).
    pub value: String,
    /// Limit (`<= 5 um/s`).
    pub limit: String,
    /// Margin (`73.4 %`, `—`).
    pub margin: String,
    /// The value as a number in [`VcdLine::unit`] (`None`: none, or not finite).
    pub value_number: Option<f64>,
    /// The limit as a number in [`VcdLine::unit`] (`None`: a qualitative requirement).
    pub limit_number: Option<f64>,
    /// The unit of the value and limit (`um/s`; empty for a pure number).
    pub unit: String,
    /// The margin as a fraction of the limit (0.734 for 73.4 %; `None` when none).
    pub margin_fraction: Option<f64>,
    /// What the verdict rests on: model, flow-down, accepted (empty when not verified).
    pub basis: &'static str,
    /// The sample behind a sampled value: the quantile or probability, N, the bounds at their
    /// confidence (empty when the value is not sampled).
    pub sampling: String,
    /// yes / yes (with the verdict's qualifiers: `yes (flow-down; assumes not-verified
    /// TMS-X-VEL)`) / no / partial / not verified.
    pub compliance: String,
    /// The verdict's credibility: level and weakest factor (`0 (validation)`, `—` when not
    /// judged; the factors in [`VcdLine::detail`]).
    pub credibility: String,
    /// open / closed.
    pub close_out: &'static str,
    /// Why open or closed.
    pub close_out_reason: String,
    /// For a closed line: the document, issue, section and date that close it.
    pub close_out_reference: String,
    /// Remarks: the requirement's note, the disposition's reason, illustrations.
    pub remarks: String,
    /// Whether the line must be re-verified: a baseline comparison showed that it changed.
    pub reverify: bool,
    /// Why (empty when not flagged).
    pub reverify_reason: String,
}

/// Whether `value op limit` holds for the row's comparison.
fn holds(r: &Row, value: f64) -> bool {
    let Some(limit) = r.limit else {
        return false; // a qualitative requirement: no value decides it
    };
    match r.op.as_str() {
        "<=" => value <= limit,
        "<" => value < limit,
        ">=" => value >= limit,
        ">" => value > limit,
        _ => false,
    }
}

/// Compliance as the VCD states it (ECSS-E-ST-10-02C Annex B): `yes` (compliant on a model or
/// a measurement with no finding), `yes (...)` with the verdict's qualifiers (`yes (accepted)`,
/// `yes (flow-down; assumes not-verified TMS-X-VEL)`, `yes (design rejected by WID-CAL)`),
/// `no` (non-compliant), `partial` (partly met: non-compliant, yet another deciding piece of
/// evidence for the same requirement meets the limit), `not verified` (no evidence gives a
/// value; in ECSS "partial" means partly met, which a missing verification is not).
pub fn compliance(r: &Row) -> String {
    match r.status {
        Status::Compliant => match r.verdict.strip_prefix("compliant") {
            Some(q) if !q.trim().is_empty() => format!("yes{q}"),
            _ => "yes".into(),
        },
        Status::NonCompliant => {
            let deciding: Vec<f64> = r
                .evidence
                .iter()
                .filter(|e| e.basis.is_some_and(|b| b.decides()))
                .filter_map(|e| e.value)
                .collect();
            if deciding.len() > 1 && deciding.iter().any(|v| holds(r, *v)) {
                "partial".into()
            } else {
                "no".into()
            }
        }
        Status::NotVerified => "not verified".into(),
    }
}

/// A test's name without its crate and test-binary path (`release::energy_relation_holds`).
pub fn short_test(t: &TestRef) -> String {
    let parts: Vec<&str> = t.test.split("::").collect();
    if parts.len() >= 2 {
        parts[parts.len() - 2..].join("::")
    } else {
        t.test.clone()
    }
}

/// A JSON input as an engineer writes it: numbers to at most 4 significant digits, lists
/// shortened, long hashes cut to 12 characters.
pub fn fmt_input(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) => group(i),
            (None, Some(f)) => fmt_num(f),
            _ => n.to_string(),
        },
        serde_json::Value::String(s) => {
            if s.len() == 64 && s.chars().all(|c| c.is_ascii_hexdigit()) {
                format!("{}…", &s[..12])
            } else {
                s.clone()
            }
        }
        serde_json::Value::Array(a) => {
            let items: Vec<String> = a.iter().take(6).map(fmt_input).collect();
            if a.len() > 6 {
                format!("[{}, … ({} values)]", items.join(", "), a.len())
            } else {
                format!("[{}]", items.join(", "))
            }
        }
        other => other.to_string(),
    }
}

/// An integer with thin groups of three digits (`100 000`).
fn group(i: i64) -> String {
    let s = i.unsigned_abs().to_string();
    let mut out = String::new();
    for (k, c) in s.chars().enumerate() {
        if k > 0 && (s.len() - k).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    if i < 0 { format!("-{out}") } else { out }
}

/// One check's evidence in a few words: `release-montecarlo: 1.334 um/s (upper 95 % bound of
/// the 99.73 % quantile, estimate 1.329 um/s; N = 100 000, seed 1)`.
fn short_evidence(r: &Row, e: &EvidenceEntry) -> String {
    let lim = r.limit.unwrap_or(f64::NAN);
    let num = |v: f64| {
        format!("{} {}", geodesic_core::units::fmt_num_near(v, lim), r.unit)
            .trim_end()
            .to_string()
    };
    let what = match (e.value, &e.reason, &e.sampling) {
        (Some(v), _, Some(s)) => {
            let side = if Some(v) == s.upper { "upper" } else { "lower" };
            format!(
                "{} ({side} {} bound of {}, estimate {})",
                num(v),
                geodesic_core::units::fmt_pct(s.confidence),
                match s.statistic {
                    geodesic_core::check::SampleStatistic::Quantile => format!(
                        "the {} quantile",
                        geodesic_core::units::fmt_pct(s.probability)
                    ),
                    geodesic_core::check::SampleStatistic::Proportion =>
                        format!("{} of {}", s.successes.unwrap_or(0), s.n),
                },
                num(s.estimate)
            )
        }
        (Some(v), _, None) => num(v),
        (None, Some(_), Some(s)) => format!(
            "no verdict from N = {} (estimate {}; N >= {} can show {})",
            s.n,
            num(s.estimate),
            s.n_required,
            geodesic_core::units::fmt_pct(s.probability)
        ),
        (None, Some(_), None) => "no value".into(),
        (None, None, _) => "—".into(),
    };
    let mut key = Vec::new();
    if let Some(s) = &e.sampling
        && !e.inputs.contains_key("n")
    {
        key.push(format!("N = {}", fmt_input(&serde_json::json!(s.n))));
    }
    for (k, label) in [("n", "N"), ("seed", "seed"), ("dataset", "dataset")] {
        if let Some(v) = e.inputs.get(k) {
            key.push(if label == "N" {
                format!("N = {}", fmt_input(v))
            } else {
                format!("{label} {}", fmt_input(v))
            });
        }
    }
    let basis = match e.basis {
        Some(b) if !b.decides() => " (illustration)",
        _ => "",
    };
    if key.is_empty() {
        format!("{}: {what}{basis}", e.check)
    } else {
        format!("{}: {what}{basis} ({})", e.check, key.join(", "))
    }
}

/// The report section of a requirement in `index.html`.
pub fn section_of(id: &str) -> String {
    format!("index.html#{id}")
}

/// The rows of the VCD whose re-verification a baseline comparison asks for, with why: a row
/// that changed (status, margin, tests, disposition), or whose evidence changed.
pub fn reverify_from(d: &crate::baseline::Diff) -> std::collections::BTreeMap<String, String> {
    let mut m = std::collections::BTreeMap::new();
    for c in &d.changes {
        let why: Vec<&str> = c
            .regressions
            .iter()
            .chain(&c.notes)
            .map(String::as_str)
            .collect();
        m.insert(c.id.clone(), why.join("; "));
    }
    for s in &d.suspect_evidence {
        let e = m.entry(s.id.clone()).or_insert_with(String::new);
        if !e.is_empty() {
            e.push_str("; ");
        }
        e.push_str(&format!("evidence of {} changed: {}", s.check, s.what));
    }
    for id in &d.added {
        m.insert(id.clone(), "new since the baseline".into());
    }
    m
}

/// Builds the VCD lines from a report.
pub fn lines(rep: &Report) -> Vec<VcdLine> {
    let date = rep.run.date.get(..10).unwrap_or(&rep.run.date);
    rep.matrix
        .requirements
        .iter()
        .map(|r| line(rep, r, date))
        .collect()
}

/// The VCD line of requirement `r` (`date`: the run's day, which closes a closed line).
fn line(rep: &Report, r: &Row, date: &str) -> VcdLine {
    let doc = &rep.run.document;
    let run = rep.matrix.test_run.is_some();
    let mut evidence: Vec<String> = r.evidence.iter().map(|e| short_evidence(r, e)).collect();
    let tests = crate::tests_word(r, run);
    if !r.tests.is_empty() || run {
        evidence.push(format!("tests: {tests}"));
    }
    let mut references = vec![format!("{} issue {} §{}", doc.id, doc.issue, r.id)];
    references.extend(r.tests.iter().map(|t| format!("test {}", short_test(t))));
    if let Some(d) = &r.disposition {
        references.push(format!("{} {}", d.kind.as_str(), d.reference));
    }
    let (close_out, close_out_reason) = close_out(r, &tests);
    let close_out_reference = if close_out == "closed" {
        format!("{} issue {} §{}, {date}", doc.id, doc.issue, r.id)
    } else {
        String::new()
    };
    let reverify_reason = rep.reverify.get(&r.id).cloned().unwrap_or_default();
    VcdLine {
        id: r.id.clone(),
        title: r.title.clone(),
        text: r.text.clone(),
        source: r.source.clone(),
        parent: r.parent.clone().unwrap_or_default(),
        children: r.children.clone(),
        level: r.level.clone(),
        stage: r.stage.clone(),
        method: r.method.clone(),
        activity: r.activity.clone(),
        section: section_of(&r.id),
        evidence: evidence.join("; "),
        detail: detail(r),
        references,
        value: fmt_value(r),
        limit: fmt_limit(r),
        margin: fmt_margin(r.margin),
        value_number: r.value.filter(|v| v.is_finite()),
        limit_number: r.limit.filter(|v| v.is_finite()),
        unit: r.unit.clone(),
        margin_fraction: r.margin.filter(|v| v.is_finite()),
        basis: r.basis.map_or("", |b| b.as_str()),
        sampling: crate::sampling_text(r).unwrap_or_default(),
        compliance: compliance(r),
        credibility: crate::credibility_word(r),
        close_out,
        close_out_reason,
        close_out_reference,
        remarks: remarks(r),
        reverify: rep.reverify.contains_key(&r.id),
        reverify_reason,
    }
}

/// The full evidence of a line ([`VcdLine::detail`]): each check with every input, then each
/// traced test with its full name, kind, location, result and assertions.
fn detail(r: &Row) -> Vec<String> {
    let mut detail: Vec<String> = crate::credibility_lines(r)
        .into_iter()
        .map(|l| format!("credibility: {l}"))
        .collect();
    for e in &r.evidence {
        let inputs: Vec<String> = e
            .inputs
            .iter()
            .map(|(k, v)| format!("{k} = {}", fmt_input(v)))
            .collect();
        let what = match (e.value, &e.reason) {
            (Some(v), _) => format!("{} {}", fmt_num(v), r.unit).trim_end().to_string(),
            (None, Some(w)) => format!("no value: {w}"),
            (None, None) => "—".into(),
        };
        let sample = e.sampling.as_ref().map_or(String::new(), |s| {
            let lim = r.limit.unwrap_or(f64::NAN);
            format!(
                " Sample: {} ({}).",
                s.describe(&|v| format!(
                    "{} {}",
                    geodesic_core::units::fmt_num_near(v, lim),
                    r.unit
                )),
                s.method
            )
        });
        detail.push(format!(
            "check {} [{}]: {what}.{sample} {}{}{}",
            e.check,
            e.basis.map_or("no basis", |b| b.as_str()),
            e.activity,
            if inputs.is_empty() {
                String::new()
            } else {
                format!(" Inputs: {}.", inputs.join(", "))
            },
            if e.artifacts.is_empty() {
                String::new()
            } else {
                format!(" Plots: {}.", e.artifacts.join(", "))
            }
        ));
    }
    for t in &r.tests {
        detail.push(format!(
            "test {} ({}, {}): {}, {} case(s), asserts {}",
            t.test,
            t.kind,
            t.location,
            t.result.as_str(),
            t.cases,
            crate::assertions_text(t)
        ));
    }
    detail
}

/// Close-out (`open` or `closed`) and why: a compliant line and a non-compliance accepted by
/// a waiver in force are closed; `tests` is the traced tests' word.
fn close_out(r: &Row, tests: &str) -> (&'static str, String) {
    let accepted_by_waiver = r.disposition.as_ref().filter(|d| {
        r.status == Status::NonCompliant && d.kind == DispositionKind::Waiver && !d.expired
    });
    match (r.status, accepted_by_waiver) {
        (Status::Compliant, _) => (
            "closed",
            format!(
                "{} {} meets {} ({}); traced tests: {tests}",
                if r.basis == Some(geodesic_core::Basis::Accepted) {
                    "accepted value"
                } else {
                    "value"
                },
                fmt_value(r),
                fmt_limit(r),
                r.verdict
            ),
        ),
        (Status::NonCompliant, Some(d)) => (
            "closed",
            format!(
                "value {} does not meet {}; non-compliance accepted by waiver {}",
                fmt_value(r),
                fmt_limit(r),
                d.reference
            ),
        ),
        (Status::NonCompliant, None) => (
            "open",
            format!(
                "value {} does not meet {}{}",
                fmt_value(r),
                fmt_limit(r),
                r.disposition
                    .as_ref()
                    .map_or("; no disposition".to_string(), |d| format!(
                        "; {} {}{}",
                        d.kind.as_str(),
                        d.reference,
                        if d.expired { " (EXPIRED)" } else { " open" }
                    ))
            ),
        ),
        (Status::NotVerified, _) => (
            "open",
            format!(
                "not verified: {}",
                r.reason.as_deref().unwrap_or("no evidence")
            ),
        ),
    }
}

/// The remarks of a line: the requirement's note, the disposition, an accepted value's
/// origin, the findings.
fn remarks(r: &Row) -> String {
    let mut remarks = Vec::new();
    if let Some(n) = &r.note {
        remarks.push(n.trim().to_string());
    }
    if let Some(d) = &r.disposition {
        remarks.push(format!(
            "{} {} (owner {}, raised {}{}): {}",
            d.kind.as_str(),
            d.reference,
            d.owner,
            d.date,
            d.expires
                .as_ref()
                .map_or(String::new(), |e| format!(", expires {e}")),
            d.reason
        ));
    }
    if r.status == Status::Compliant && r.basis == Some(geodesic_core::Basis::Accepted) {
        remarks.push("value taken from the cited source, not computed".into());
    }
    for f in &r.findings {
        remarks.push(format!("Finding: {f}."));
    }
    remarks.join(" ")
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The column names of the CSV and XLSX exports, in order. `value` and `limit` are numbers in
/// `unit`, `margin` a number, the fraction of the limit (0.734 for 73.4 %); each empty when
/// there is none; `value_text`, `limit_text` and `margin_text` are the same as the reports write
/// them (`1.329 um/s`, `<= 5 um/s`, `73.4 %`). `evidence_references` are the documents and tests
/// the evidence is in (not `references`: Doorstop's import takes a column of that name for its
/// own file references). `credibility` is the verdict's level and weakest factor
/// (docs/credibility.md).
pub const COLUMNS: [&str; 32] = [
    "id",
    "title",
    "text",
    "source",
    "parent",
    "children",
    "level",
    "stage",
    "method",
    "activity",
    "section",
    "evidence",
    "evidence_detail",
    "evidence_references",
    "value",
    "limit",
    "unit",
    "margin",
    "value_text",
    "limit_text",
    "margin_text",
    "basis",
    "sampling",
    "compliance",
    "close_out",
    "close_out_reason",
    "close_out_reference",
    "remarks",
    "reverify",
    "reverify_reason",
    "document",
    "credibility",
];

/// The cells of a line in [`COLUMNS`] order.
pub fn cells(rep: &Report, l: &VcdLine) -> Vec<String> {
    vec![
        l.id.clone(),
        l.title.clone(),
        l.text.clone(),
        l.source.clone(),
        l.parent.clone(),
        l.children.join("; "),
        l.level.clone(),
        l.stage.clone(),
        l.method.clone(),
        l.activity.clone(),
        l.section.clone(),
        l.evidence.clone(),
        l.detail.join("\n"),
        l.references.join("; "),
        number(l.value_number),
        number(l.limit_number),
        l.unit.clone(),
        number(l.margin_fraction),
        l.value.clone(),
        l.limit.clone(),
        l.margin.clone(),
        l.basis.to_string(),
        l.sampling.clone(),
        l.compliance.clone(),
        l.close_out.to_string(),
        l.close_out_reason.clone(),
        l.close_out_reference.clone(),
        l.remarks.clone(),
        if l.reverify { "yes" } else { "no" }.to_string(),
        l.reverify_reason.clone(),
        format!("{} issue {}", rep.run.document.id, rep.run.document.issue),
        l.credibility.clone(),
    ]
}

/// A number cell: the shortest text that reads back to the same number, empty for none.
fn number(v: Option<f64>) -> String {
    match v {
        None => String::new(),
        Some(v) if v == 0.0 || (1e-4..1e15).contains(&v.abs()) => format!("{v}"),
        Some(v) => format!("{v:e}"),
    }
}

/// The VCD as CSV (RFC 4180 quoting), UTF-8 with a byte-order mark (so that spreadsheet
/// programs do not read `±` as `Â±`), one header row; the run's identification is in the
/// `document` column and in the other exports' headers.
pub fn csv(rep: &Report) -> String {
    let mut o = String::from("\u{FEFF}");
    o.push_str(&COLUMNS.join(","));
    o.push('\n');
    for l in lines(rep) {
        let row: Vec<String> = cells(rep, &l).iter().map(|s| csv_field(s)).collect();
        o.push_str(&row.join(","));
        o.push('\n');
    }
    o
}

/// The VCD as Markdown: the run's identification, then one table row per requirement, then the
/// full evidence per requirement.
pub fn markdown(rep: &Report) -> String {
    let c = |s: &str| s.replace('|', "\\|").replace('\n', " ");
    let mut o = String::from("# Verification Control Document\n\n");
    for (k, v) in crate::run_lines(rep) {
        o.push_str(&format!("- {k}: {}\n", c(&v)));
    }
    o.push_str("\nColumns follow ECSS-E-ST-10-02C Annex B. Compliance: yes (a model or measurement verdict with no finding) / yes (qualified: its basis, what it assumes, a rejected input, a test problem) / no / partial (partly met) / not verified. A sampled value is the confidence bound that decides (Sample column). Full evidence per requirement below the table.\n\n");
    o.push_str("| ID | Requirement | Source | Parent / children | Level / stage | Method | Activity / evidence | Value | Limit | Margin | Basis | Sample | Compliance | Credibility | Close-out | Remarks | Re-verify |\n");
    o.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    let lines = lines(rep);
    for l in &lines {
        o.push_str(&format!(
            "| [{id}](#{a}) | **{title}**: {text} | {src} | {par} / {ch} | {lev} / {st} | {meth} | {act}<br>{ev}<br>refs: {refs} | {val} | {lim} | {mg} | {basis} | {smp} | {comp} | {cred} | {co}: {cor}{cref} | {rem} | {rv} |\n",
            id = l.id,
            a = l.id.to_lowercase(),
            title = c(&l.title),
            text = c(&l.text),
            src = c(&l.source),
            par = if l.parent.is_empty() { "—" } else { &l.parent },
            ch = if l.children.is_empty() {
                "—".to_string()
            } else {
                l.children.join(", ")
            },
            lev = l.level,
            st = l.stage,
            meth = l.method,
            act = c(&l.activity),
            ev = c(&l.evidence),
            refs = c(&l.references.join("; ")),
            val = l.value,
            lim = c(&l.limit),
            mg = l.margin,
            basis = if l.basis.is_empty() { "—" } else { l.basis },
            smp = if l.sampling.is_empty() {
                "—".to_string()
            } else {
                c(&l.sampling)
            },
            comp = l.compliance,
            cred = l.credibility,
            co = l.close_out,
            cor = c(&l.close_out_reason),
            cref = if l.close_out_reference.is_empty() {
                String::new()
            } else {
                format!(" ({})", c(&l.close_out_reference))
            },
            rem = if l.remarks.is_empty() {
                "—".to_string()
            } else {
                c(&l.remarks)
            },
            rv = if l.reverify {
                format!("yes: {}", c(&l.reverify_reason))
            } else {
                "no".into()
            },
        ));
    }
    o.push_str("\n## Evidence in full\n");
    for l in &lines {
        o.push_str(&format!("\n### {}\n\n", l.id));
        if l.detail.is_empty() {
            o.push_str("- none\n");
        }
        for d in &l.detail {
            o.push_str(&format!("- {d}\n"));
        }
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::report;

    #[test]
    fn inputs_read_as_an_engineer_writes_them() {
        assert_eq!(fmt_input(&serde_json::json!(1.3999999682597337)), "1.4");
        assert_eq!(fmt_input(&serde_json::json!(100000)), "100 000");
        assert_eq!(fmt_input(&serde_json::json!(3.13e8)), "3.13e8");
        assert_eq!(
            fmt_input(&serde_json::json!("a".repeat(64))),
            "aaaaaaaaaaaa…"
        );
        assert_eq!(
            fmt_input(&serde_json::json!([1, 2, 3, 4, 5, 6, 7])),
            "[1, 2, 3, 4, 5, 6, … (7 values)]"
        );
    }

    #[test]
    fn compliance_partial_means_partly_met_and_not_verified_is_not_partial() {
        let mut r = report(1.0, 6.0);
        assert_eq!(compliance(&r.matrix.requirements[0]), "yes");
        assert_eq!(compliance(&r.matrix.requirements[1]), "no");
        // a second deciding piece of evidence for F-B that meets the limit: partly met
        let mut met = r.matrix.requirements[1].evidence[0].clone();
        met.value = Some(2.0);
        met.check = "other".into();
        r.matrix.requirements[1].evidence.push(met);
        assert_eq!(compliance(&r.matrix.requirements[1]), "partial");
        let row = &mut r.matrix.requirements[0];
        row.status = Status::NotVerified;
        row.value = None;
        assert_eq!(compliance(row), "not verified");
    }

    #[test]
    fn every_line_carries_the_annex_b_fields() {
        let mut r = report(1.3, 6.0);
        r.reverify.insert("F-B".into(), "margin moved".into());
        let ls = lines(&r);
        assert_eq!(ls.len(), 2);
        let a = &ls[0];
        assert_eq!(
            (a.level.as_str(), a.stage.as_str()),
            ("system", "qualification")
        );
        assert_eq!(a.section, "index.html#F-A");
        assert_eq!(a.close_out, "closed");
        assert_eq!(a.close_out_reference, "DOC-1 issue 2 §F-A, 2026-01-01");
        assert_eq!(a.limit, "<= 5 um/s");
        assert!(a.evidence.starts_with("mc: 1.3 um/s"), "{}", a.evidence);
        assert!(!a.reverify);
        let b = &ls[1];
        assert_eq!((b.compliance.as_str(), b.close_out), ("no", "open"));
        assert!(
            b.close_out_reason
                .contains("6 um/s does not meet <= 5 um/s")
        );
        assert!(b.reverify && b.reverify_reason == "margin moved");
        let csv = csv(&r);
        assert_eq!(
            csv.lines().next().unwrap(),
            format!("\u{FEFF}{}", COLUMNS.join(","))
        );
        assert_eq!(csv.lines().count(), 3);
        let md = markdown(&r);
        assert!(md.contains("document: DOC-1 issue 2: T") && !md.contains("`<="));
    }

    /// What a spreadsheet program or pandas reads: value, limit and margin as numbers that read
    /// back to the matrix's, the unit beside them, the text as the reports write it.
    #[test]
    fn the_csv_has_numbers_a_unit_and_a_byte_order_mark() {
        let mut r = report(1.3, 6.0);
        r.matrix.requirements[1].value = Some(1.234_567_890_123e-9);
        let text = csv(&r);
        let body = text
            .strip_prefix('\u{FEFF}')
            .expect("a byte-order mark first");
        let mut rdr = ::csv::Reader::from_reader(body.as_bytes());
        let header: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
        assert_eq!(header, COLUMNS.map(String::from).to_vec());
        let col = |name: &str| header.iter().position(|c| c == name).unwrap();
        let rows: Vec<::csv::StringRecord> = rdr.records().map(|r| r.unwrap()).collect();
        assert_eq!(rows.len(), 2);
        for (cells, m) in rows.iter().zip(&r.matrix.requirements) {
            let num = |name: &str| cells[col(name)].parse::<f64>().unwrap();
            assert_eq!(num("value"), m.value.unwrap());
            assert_eq!(num("limit"), m.limit.unwrap());
            assert_eq!(num("margin"), m.margin.unwrap());
            assert_eq!(&cells[col("unit")], "um/s");
            assert_eq!(cells[col("value_text")], *crate::fmt_value(m));
            assert_eq!(cells[col("margin_text")], *crate::fmt_margin(m.margin));
        }
        assert!(body.contains(",1.234567890123e-9,5,um/s,"), "{body}");
        // none: an empty cell, not a dash
        r.matrix.requirements[0].value = None;
        r.matrix.requirements[0].margin = None;
        let l = &lines(&r)[0];
        let c = cells(&r, l);
        assert_eq!(c[COLUMNS.iter().position(|n| *n == "value").unwrap()], "");
        assert_eq!(c[COLUMNS.iter().position(|n| *n == "margin").unwrap()], "");
    }
}
