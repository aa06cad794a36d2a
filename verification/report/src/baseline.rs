//! The CI gate: compares a compliance report with a baseline `compliance.json` and lists, once
//! per requirement, what changed, in plain words, each line naming its requirement.
//! `geodesic verify --baseline OLD.json` exits 1 only on a **regression**:
//!
//! - a new non-compliance (the requirement was compliant or not verified in the baseline);
//! - a non-compliance without a disposition (NCR, waiver, RFD), whether it is new, was in the
//!   baseline, or belongs to a requirement the baseline does not have; a disposition that
//!   expired or was withdrawn;
//! - a requirement whose limit, probability, method, quantity or text changed ("requirement
//!   changed, needs review", in either direction: a loosened limit is not an improvement);
//! - a margin lost beyond what the run can resolve: for a sampled value (a Monte Carlo
//!   quantile, a probability from successes), beyond what the two runs' sampling explains
//!   ([`sampling_tolerance`]); otherwise beyond the tolerance (absolute, a fraction of the
//!   limit);
//! - a smaller sample or a lower confidence than the baseline's behind a sampled verdict;
//! - evidence lost (a value in the baseline, none now) or a weaker basis (model -> flow-down);
//! - a traced test that passed in the baseline and does not pass now, or vanished (compared
//!   only when this run's recorded test run is fresh);
//! - a requirement that disappeared;
//! - a model input parameter that changed ("input changed, needs review", with the rows it
//!   moved, whichever way: [`InputChange`]);
//! - a credibility level that fell, or a row no longer compliant because its credibility is
//!   below the level its requirement needs.
//!
//! A known non-compliance with its disposition is not a regression; an improvement is listed but
//! never fails the gate. Checks whose value or inputs changed (a seed, say) are listed as
//! suspect evidence: a change of seed alone moves sampled values within their sampling
//! uncertainty and fails nothing.

use crate::Report;
use geodesic_core::matrix::{Row, Status};
use geodesic_core::units::fmt_num;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

mod credibility;
mod inputs;
pub use inputs::InputChange;

#[derive(Deserialize)]
struct OldReport {
    requirements: Vec<OldRow>,
    #[serde(default)]
    run: Option<OldRun>,
}

#[derive(Deserialize)]
struct OldRun {
    /// The model inputs by name (`parameters`, `sha256`), and the time series under `series`.
    #[serde(default)]
    inputs: BTreeMap<String, serde_json::Value>,
}

#[derive(Deserialize)]
struct OldRow {
    id: String,
    status: String,
    value: Option<f64>,
    margin: Option<f64>,
    #[serde(default)]
    limit: Option<f64>,
    #[serde(default)]
    unit: String,
    #[serde(default)]
    limit_text: Option<String>,
    #[serde(default)]
    probability: Option<String>,
    #[serde(default)]
    method: Option<String>,
    #[serde(default)]
    check: Option<String>,
    #[serde(default)]
    text: Option<String>,
    #[serde(default)]
    quantity: Option<String>,
    #[serde(default)]
    sampling: Option<geodesic_core::check::Sampling>,
    #[serde(default)]
    verdict: Option<String>,
    #[serde(default)]
    basis: Option<String>,
    #[serde(default)]
    evidence: Vec<OldEvidence>,
    #[serde(default)]
    tests: Vec<OldTest>,
    #[serde(default)]
    disposition: Option<OldDisposition>,
    #[serde(default)]
    credibility: Option<serde_json::Value>,
}

#[derive(Deserialize)]
struct OldEvidence {
    check: String,
    value: Option<f64>,
    #[serde(default)]
    inputs: BTreeMap<String, serde_json::Value>,
}

#[derive(Deserialize)]
struct OldTest {
    test: String,
    #[serde(default)]
    result: Option<String>,
}

#[derive(Deserialize)]
struct OldDisposition {
    reference: String,
}

/// A baseline file that cannot be read: one line with file:line:column.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BaselineError(pub String);

/// What changed for one requirement.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Change {
    /// Requirement ID.
    pub id: String,
    /// Whether any of the changes is a regression (counted once per requirement).
    pub regression: bool,
    /// The regressions, in plain words.
    pub regressions: Vec<String>,
    /// The other changes (improvements, information), in plain words.
    pub notes: Vec<String>,
    /// Status in the baseline and now.
    pub status: (String, String),
    /// Margin in the baseline and now (fraction of the limit).
    pub margin: (Option<f64>, Option<f64>),
}

/// Evidence of a check for a requirement whose value or inputs changed.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Suspect {
    /// Requirement ID.
    pub id: String,
    /// Check name.
    pub check: String,
    /// What changed.
    pub what: String,
}

/// The change impact of a run against a baseline.
#[derive(Clone, Debug, Serialize, schemars::JsonSchema)]
pub struct Diff {
    /// Baseline file.
    pub baseline: String,
    /// Margin tolerance of a value that is not sampled (absolute, as a fraction of the limit).
    pub tolerance: f64,
    /// Whether test results were compared (this run's recorded test run is fresh).
    pub tests_compared: bool,
    /// Why not, when they were not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tests_not_compared: Option<String>,
    /// Requirements that changed, one entry each.
    pub changes: Vec<Change>,
    /// Requirements new in this run.
    pub added: Vec<String>,
    /// Requirements of the baseline missing now (each a regression).
    pub removed: Vec<String>,
    /// Checks whose evidence changed.
    pub suspect_evidence: Vec<Suspect>,
    /// Model input parameters that changed since the baseline, each with the rows it moved
    /// (each a regression: on every row it moved, or of its own when it moved none).
    pub inputs_changed: Vec<InputChange>,
    /// Number of requirements with a regression (each counted once).
    pub regressions: usize,
}

fn rank(s: &str) -> u8 {
    match s {
        "compliant" => 0,
        "not-verified" => 1,
        _ => 2,
    }
}

fn basis_rank(b: Option<&str>) -> u8 {
    match b {
        Some("model") | Some("measurement") => 0,
        Some("method-validation") => 1,
        Some("flow-down") => 2,
        Some("accepted") => 3,
        _ => 4,
    }
}

/// One-sided normal quantile of the gate's test that a sampled margin fell (99.9 %): a change
/// of seed alone moves a sampled value by more than this many of its standard deviations once
/// in a thousand comparisons.
pub const SAMPLING_Z: f64 = 3.090_232_306_167_813;

/// The margin drop (a fraction of the limit) that a sampled value's two runs can explain:
/// each run's sampling standard deviation is taken as its deciding bound's distance from its
/// estimate over the one-sided normal quantile of its confidence, and the drop of the
/// difference of two independent runs is significant beyond [`SAMPLING_Z`] of their combined
/// deviation. It replaces a fixed tolerance, which a margin smaller than it (CAP-RELEASE-PROB:
/// 0.27 %) could never exceed and which a Monte Carlo of 10^5 draws resolves 20 times finer.
pub fn sampling_tolerance(
    old: &geodesic_core::check::Sampling,
    old_limit: f64,
    new: &geodesic_core::check::Sampling,
    new_limit: f64,
) -> f64 {
    let sd = |s: &geodesic_core::check::Sampling, limit: f64| {
        let z = geodesic_util::normal::normal_quantile(s.confidence);
        let w = [s.lower, s.upper]
            .iter()
            .flatten()
            .map(|b| (b - s.estimate).abs())
            .fold(0.0, f64::max);
        w / z / limit.abs()
    };
    let (a, b) = (sd(old, old_limit), sd(new, new_limit));
    SAMPLING_Z * (a * a + b * b).sqrt()
}

/// Compares `now` with the baseline file.
pub fn diff(now: &Report, baseline: &Path, tolerance: f64) -> Result<Diff, BaselineError> {
    let text = std::fs::read_to_string(baseline)
        .map_err(|e| BaselineError(format!("{}: {e}", baseline.display())))?;
    diff_text(now, &text, &baseline.display().to_string(), tolerance)
}

fn pct(m: Option<f64>) -> String {
    m.map_or("—".into(), |m| format!("{:.1} %", 100.0 * m))
}

/// A small fraction as a percentage with the digits it needs (`0.0042 %`).
fn pct_fine(m: f64) -> String {
    format!("{} %", fmt_num(100.0 * m))
}

fn val(v: Option<f64>, unit: &str) -> String {
    v.map_or("no value".into(), |v| {
        format!("{} {unit}", fmt_num(v)).trim().to_string()
    })
}

/// Reads and parses a baseline `compliance.json` without comparing anything: `verify
/// --baseline` calls it before any check runs, so that a missing or malformed baseline is
/// exit 2 at once (with its line and column), not after the whole run.
pub fn check(baseline: &Path) -> Result<(), BaselineError> {
    let text = std::fs::read_to_string(baseline)
        .map_err(|e| BaselineError(format!("{}: {e}", baseline.display())))?;
    parse_old(&text, &baseline.display().to_string()).map(|_| ())
}

fn parse_old(text: &str, label: &str) -> Result<OldReport, BaselineError> {
    serde_json::from_str(text).map_err(|e| {
        BaselineError(format!(
            "{}:{}:{}: not a geodesic compliance.json: {}",
            geodesic_util::text::one_line(label),
            e.line(),
            e.column(),
            geodesic_util::text::clip(&e.to_string(), 300)
        ))
    })
}

/// Compares `now` with a baseline's JSON text (`label` names it in messages).
pub fn diff_text(
    now: &Report,
    text: &str,
    label: &str,
    tolerance: f64,
) -> Result<Diff, BaselineError> {
    let old = parse_old(text, label)?;
    let old_by: BTreeMap<&str, &OldRow> = old
        .requirements
        .iter()
        .map(|r| (r.id.as_str(), r))
        .collect();
    let tests_compared = now.matrix.test_run.as_ref().is_some_and(|t| t.fresh);
    let tests_not_compared = match &now.matrix.test_run {
        None => Some("no recorded test run".to_string()),
        Some(t) if !t.fresh => Some(format!(
            "the recorded test run is stale ({})",
            t.stale_reason.as_deref().unwrap_or("")
        )),
        Some(_) => None,
    };
    let mut d = Diff {
        baseline: label.to_string(),
        tolerance,
        tests_compared,
        tests_not_compared,
        changes: vec![],
        added: vec![],
        removed: vec![],
        suspect_evidence: vec![],
        inputs_changed: vec![],
        regressions: 0,
    };
    for r in &now.matrix.requirements {
        let Some(o) = old_by.get(r.id.as_str()) else {
            d.added.push(r.id.clone());
            // a new requirement that is non-compliant with no disposition is a regression
            let why: Vec<String> = undisposed(r)
                .into_iter()
                .chain(rejected_tests(r))
                .map(|w| format!("new requirement, {w}"))
                .collect();
            if !why.is_empty() {
                d.changes.push(Change {
                    id: r.id.clone(),
                    regression: true,
                    regressions: why,
                    notes: vec![],
                    status: ("absent".into(), r.status.as_str().to_string()),
                    margin: (None, r.margin),
                });
            }
            continue;
        };
        let c = compare(r, o, tolerance, tests_compared);
        if !c.regressions.is_empty() || !c.notes.is_empty() {
            d.changes.push(c);
        }
        suspects(r, o, &mut d.suspect_evidence);
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
    if let Some(run) = &old.run {
        inputs::gate(now, &run.inputs, &old_by, &mut d);
    }
    d.regressions = d.changes.iter().filter(|c| c.regression).count()
        + d.removed.len()
        + d.inputs_changed
            .iter()
            .filter(|c| c.rows.is_empty())
            .count();
    Ok(d)
}

/// Why a non-compliant row without a disposition is a regression (`None` otherwise).
fn undisposed(r: &Row) -> Option<String> {
    (r.status == Status::NonCompliant && r.disposition.is_none()).then(|| {
        format!(
            "non-compliant with no disposition (NCR, waiver or RFD): value {} against {}",
            val(r.value, &r.unit),
            r.limit_text
        )
    })
}

/// How row `r` moved from the baseline's row `o`: the regressions (the gate fails on any)
/// and the notes (reviewed, not failing), in the order the report lists them.
fn compare(r: &Row, o: &OldRow, tolerance: f64, tests_compared: bool) -> Change {
    let mut reg = Vec::new();
    let mut notes = Vec::new();
    let now = r.status.as_str();
    let unit = if r.unit.is_empty() { &o.unit } else { &r.unit };
    reg.extend(requirement_edits(r, o));
    status_change(r, o, unit, &mut reg, &mut notes);
    margin_change(r, o, unit, tolerance, &mut reg, &mut notes);
    let now_basis = r.basis.map(|b| b.as_str());
    if o.value.is_some()
        && r.value.is_some()
        && basis_rank(now_basis) > basis_rank(o.basis.as_deref())
    {
        reg.push(format!(
            "its verdict now rests on a weaker basis: {} -> {}",
            o.basis.as_deref().unwrap_or("none"),
            now_basis.unwrap_or("none")
        ));
    }
    if tests_compared {
        tests_lost(r, o, &mut reg);
    }
    reg.extend(rejected_tests(r));
    reg.extend(credibility::regressions(r, o, tests_compared));
    if r.status == Status::NonCompliant {
        match (&r.disposition, &o.disposition) {
            (Some(dn), _) if dn.expired => reg.push(format!(
                "its {} {} expired on {}",
                dn.kind.as_str(),
                dn.reference,
                dn.expires.as_deref().unwrap_or("?")
            )),
            (None, Some(od)) => reg.push(format!(
                "its disposition {} was withdrawn while it is still non-compliant",
                od.reference
            )),
            (None, None) => reg.extend(undisposed(r)),
            _ => {}
        }
    }
    if let Some(ov) = &o.verdict
        && *ov != r.verdict
    {
        notes.push(format!("verdict `{ov}` -> `{}`", r.verdict));
    }
    Change {
        id: r.id.clone(),
        regression: !reg.is_empty(),
        regressions: reg,
        notes,
        status: (o.status.clone(), now.to_string()),
        margin: (o.margin, r.margin),
    }
}

/// The requirement itself: any edit of what it asks (limit, probability, method, quantity,
/// text) is reviewed, whichever direction (`None` when nothing was edited).
fn requirement_edits(r: &Row, o: &OldRow) -> Option<String> {
    let q = |s: &str| format!("`{}`", geodesic_util::text::clip(s, 120));
    let edits: Vec<String> = [
        (
            "limit",
            o.limit_text.as_deref(),
            Some(r.limit_text.as_str()),
        ),
        (
            "probability",
            o.probability.as_deref(),
            r.probability.as_deref(),
        ),
        ("method", o.method.as_deref(), Some(r.method.as_str())),
        ("check", o.check.as_deref(), Some(r.check.as_str())),
        ("quantity", o.quantity.as_deref(), Some(r.quantity.as_str())),
        ("text", o.text.as_deref(), Some(r.text.as_str())),
    ]
    .iter()
    .filter(|(name, old, new)| {
        // a baseline written before a field existed says nothing about it, except the
        // probability, which a row always states (null when none)
        (old.is_some() || *name == "probability") && old != new
    })
    .map(|(name, old, new)| {
        format!(
            "{name} {} -> {}",
            old.map_or("none".into(), q),
            new.map_or("none".into(), q)
        )
    })
    .collect();
    (!edits.is_empty()).then(|| format!("requirement changed, needs review: {}", edits.join("; ")))
}

/// A change of status: becoming non-compliant or losing the evidence is a regression, an
/// improvement or another move a note (`unit`: the values' unit).
fn status_change(r: &Row, o: &OldRow, unit: &str, reg: &mut Vec<String>, notes: &mut Vec<String>) {
    let now = r.status.as_str();
    if now == o.status {
        return;
    }
    let msg = format!("status {} -> {}", o.status, now);
    if r.status == Status::NonCompliant {
        reg.push(format!(
            "became non-compliant (was {}): value {} against {} {}",
            o.status,
            val(r.value, unit),
            r.op,
            val(r.limit, unit)
        ));
    } else if o.value.is_some() && r.value.is_none() {
        reg.push(format!(
            "lost its evidence: now not verified ({})",
            r.reason.as_deref().unwrap_or("no reason given")
        ));
    } else if rank(now) < rank(&o.status) {
        notes.push(format!("improved: {msg}"));
    } else {
        notes.push(msg);
    }
}

/// The margin's move: a fall beyond the tolerance is a regression, a rise beyond it a note. A
/// sampled value is compared with what its sampling resolves, never a fixed tolerance, and a
/// smaller sample or a lower confidence than the baseline's is a regression.
fn margin_change(
    r: &Row,
    o: &OldRow,
    unit: &str,
    tolerance: f64,
    reg: &mut Vec<String>,
    notes: &mut Vec<String>,
) {
    let (tol, tol_why) = match (&o.sampling, &r.sampling, o.limit, r.limit) {
        (Some(os), Some(ns), Some(ol), Some(nl)) => {
            let t = sampling_tolerance(os, ol, ns, nl);
            (
                t,
                format!(
                    "beyond the {} of the limit the two runs' sampling explains (N {} and {})",
                    pct_fine(t),
                    os.n,
                    ns.n
                ),
            )
        }
        _ => (tolerance, format!("tolerance {:.1} %", 100.0 * tolerance)),
    };
    if let (Some(os), Some(ns)) = (&o.sampling, &r.sampling) {
        if ns.n < os.n {
            reg.push(format!(
                "its sampled verdict rests on N = {}, the baseline's on N = {}",
                ns.n, os.n
            ));
        }
        if ns.confidence < os.confidence {
            reg.push(format!(
                "its bound is at {} confidence, the baseline's at {}",
                geodesic_core::units::fmt_pct(ns.confidence),
                geodesic_core::units::fmt_pct(os.confidence)
            ));
        }
    }
    if let (Some(a), Some(b)) = (o.margin, r.margin) {
        if b < a - tol {
            reg.push(format!(
                "margin fell from {} to {} of the limit (value {} -> {}; {tol_why})",
                pct(Some(a)),
                pct(Some(b)),
                val(o.value, unit),
                val(r.value, unit),
            ));
        } else if b > a + tol {
            notes.push(format!(
                "margin rose from {} to {} (value {} -> {})",
                pct(Some(a)),
                pct(Some(b)),
                val(o.value, unit),
                val(r.value, unit)
            ));
        }
    }
}

/// The traced test records of row `r` that do not check against the tree (a forged or
/// foreign record): a regression whatever the baseline says.
fn rejected_tests(r: &Row) -> Option<String> {
    let bad: Vec<String> = r
        .tests
        .iter()
        .filter_map(|t| t.rejected.as_ref().map(|w| format!("{} ({w})", t.test)))
        .collect();
    (!bad.is_empty()).then(|| {
        format!(
            "traced test record rejected against the tree: {}",
            bad.join(", ")
        )
    })
}

/// Traced tests that passed in the baseline and no longer pass: all vanished at once, or
/// each one that now fails, is ignored or is absent.
fn tests_lost(r: &Row, o: &OldRow, reg: &mut Vec<String>) {
    let passed: Vec<&OldTest> = o
        .tests
        .iter()
        .filter(|t| t.result.as_deref() == Some("passed"))
        .collect();
    let vanished = passed
        .iter()
        .filter(|t| !r.tests.iter().any(|n| n.test == t.test))
        .count();
    if vanished > 0 && vanished == passed.len() && r.tests.is_empty() {
        reg.push(format!(
            "its {vanished} traced test(s) vanished (passed in the baseline, absent from this run)"
        ));
    } else {
        for t in passed {
            let res = r
                .tests
                .iter()
                .find(|n| n.test == t.test)
                .map_or("absent", |n| n.result.as_str());
            if res != "passed" {
                reg.push(format!("test {} passed in the baseline, now {res}", t.test));
            }
        }
    }
}

fn suspects(r: &Row, o: &OldRow, out: &mut Vec<Suspect>) {
    for (i, e) in r.evidence.iter().enumerate() {
        // a check may give several pieces of evidence for one requirement (a value and an
        // illustration): compare the k-th of this check with the k-th of the baseline
        let k = r.evidence[..i]
            .iter()
            .filter(|x| x.check == e.check)
            .count();
        match o.evidence.iter().filter(|x| x.check == e.check).nth(k) {
            None => out.push(Suspect {
                id: r.id.clone(),
                check: e.check.clone(),
                what: "new evidence".into(),
            }),
            Some(x) => {
                let mut what = Vec::new();
                if !opt_close(x.value, e.value) {
                    what.push(format!(
                        "value {} -> {}",
                        val(x.value, &r.unit),
                        val(e.value, &r.unit)
                    ));
                }
                let keys: std::collections::BTreeSet<&String> =
                    x.inputs.keys().chain(e.inputs.keys()).collect();
                let changed: Vec<&str> = keys
                    .into_iter()
                    .filter(|k| !json_close(x.inputs.get(*k), e.inputs.get(*k)))
                    .map(String::as_str)
                    .collect();
                if !changed.is_empty() {
                    what.push(format!("inputs changed: {}", changed.join(", ")));
                }
                if !what.is_empty() {
                    out.push(Suspect {
                        id: r.id.clone(),
                        check: e.check.clone(),
                        what: what.join("; "),
                    });
                }
            }
        }
    }
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

/// Plain-text lines for a terminal or a CI log: one line per regression.
pub fn summary_lines(d: &Diff) -> Vec<String> {
    let mut out = Vec::new();
    for c in d.changes.iter().filter(|c| c.regression) {
        out.push(format!("REGRESSION {}: {}", c.id, c.regressions.join("; ")));
    }
    for id in &d.removed {
        out.push(format!(
            "REGRESSION {id}: removed (it is in the baseline, not in this run)"
        ));
    }
    for c in d.inputs_changed.iter().filter(|c| c.rows.is_empty()) {
        out.push(format!("REGRESSION {}; it moved no row", c.words()));
    }
    out
}

/// Markdown summary fit for a pull-request comment.
pub fn markdown(d: &Diff) -> String {
    let mut o = String::from("## geodesic: change impact against the baseline\n\n");
    o.push_str(&format!(
        "Baseline `{}` · margin tolerance {:.1} % of the limit (sampled values: their sampling uncertainty) · **{} requirement(s) regressed**\n\n",
        d.baseline,
        100.0 * d.tolerance,
        d.regressions
    ));
    if !d.tests_compared {
        o.push_str(&format!(
            "Test results were not compared: {} (`cargo xtask test` records a run of this tree).\n\n",
            d.tests_not_compared.as_deref().unwrap_or("no fresh test run")
        ));
    }
    if d.changes.is_empty()
        && d.added.is_empty()
        && d.removed.is_empty()
        && d.inputs_changed.is_empty()
    {
        o.push_str("No requirement changed status, margin, basis, tests or disposition.\n\n");
    }
    if !d.changes.is_empty() {
        o.push_str("| Requirement | | Status | Margin | What changed |\n|---|---|---|---|---|\n");
        for c in &d.changes {
            let tag = if c.regression { "regression" } else { "change" };
            let mut what = c.regressions.clone();
            what.extend(c.notes.iter().cloned());
            o.push_str(&format!(
                "| {} | {tag} | {} -> {} | {} -> {} | {} |\n",
                c.id,
                c.status.0,
                c.status.1,
                pct(c.margin.0),
                pct(c.margin.1),
                what.join("; ").replace('|', "\\|")
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
    if !d.inputs_changed.is_empty() {
        o.push_str("Model inputs changed since the baseline (each needs review):\n\n");
        for c in &d.inputs_changed {
            let rows = if c.rows.is_empty() {
                "it moved no row (regression)".to_string()
            } else {
                format!("rows it moved: {}", c.rows.join("; "))
            };
            o.push_str(&format!(
                "- `{}` {} `{}` -> `{}` ({}): {}\n",
                c.input,
                c.parameter,
                c.old.replace('`', "'"),
                c.new.replace('`', "'"),
                c.label,
                rows.replace('|', "\\|")
            ));
        }
        o.push('\n');
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

    /// No files: the baseline is the old report's JSON text.
    fn diff_of(old: &Report, new: &Report, tol: f64) -> Diff {
        diff_text(new, &serde_json::to_string(old).unwrap(), "old.json", tol).unwrap()
    }

    #[test]
    fn identical_runs_have_no_change() {
        let d = diff_of(&report(1.3, 2.0), &report(1.3, 2.0), 0.01);
        assert!(d.changes.is_empty() && d.suspect_evidence.is_empty());
        assert_eq!(d.regressions, 0);
    }

    #[test]
    fn two_pieces_of_evidence_of_one_check_are_compared_in_order() {
        // a check that gives a value and an illustration for one requirement: unchanged runs
        // flag nothing (each is compared with its own counterpart, not with the first)
        let mut r = report(1.3, 2.0);
        let mut second = r.matrix.requirements[0].evidence[0].clone();
        second.value = Some(4.0);
        second.inputs.insert("other".into(), serde_json::json!(1));
        r.matrix.requirements[0].evidence.push(second);
        let d = diff_of(&r, &r, 0.01);
        assert!(d.suspect_evidence.is_empty(), "{:?}", d.suspect_evidence);
        assert!(crate::vcd::reverify_from(&d).is_empty());
    }

    #[test]
    fn names_exactly_the_requirements_that_moved_once_each() {
        // F-A loses 2 % of the limit (beyond 1 %), F-B 0.2 % (within)
        let d = diff_of(&report(1.3, 2.0), &report(1.4, 2.01), 0.01);
        let moved: Vec<&str> = d.changes.iter().map(|m| m.id.as_str()).collect();
        assert_eq!(moved, ["F-A"]);
        assert_eq!(d.regressions, 1);
        assert!(d.changes[0].regressions[0].starts_with("margin fell from 74.0 % to 72.0 %"));
        // both values changed: both are suspect evidence
        assert_eq!(d.suspect_evidence.len(), 2);
        assert!(markdown(&d).contains("F-A"));
        assert!(!d.changes[0].regressions[0].contains("Some("));
    }

    /// Gives row `id` an NCR.
    fn ncr(mut r: Report, id: &str) -> Report {
        let row = r
            .matrix
            .requirements
            .iter_mut()
            .find(|x| x.id == id)
            .unwrap();
        row.disposition = Some(geodesic_core::disposition::Disposition {
            requirement: id.into(),
            kind: geodesic_core::disposition::DispositionKind::Ncr,
            reference: "NCR-1".into(),
            reason: "known".into(),
            owner: "o".into(),
            date: "2026-01-01".into(),
            expires: None,
            expired: false,
            defined_at: "d.yaml:1".into(),
        });
        r
    }

    #[test]
    fn a_new_non_compliance_is_one_regression_and_back_is_none() {
        // flips, loses margin and has no disposition: still one requirement, one count
        let d = diff_of(&report(1.3, 2.0), &report(6.0, 2.0), 0.01);
        assert_eq!(d.changes.len(), 1);
        assert_eq!(d.regressions, 1);
        assert_eq!(d.changes[0].regressions.len(), 3, "{:?}", d.changes[0]);
        assert_eq!(summary_lines(&d).len(), 1);
        assert!(summary_lines(&d)[0].starts_with("REGRESSION F-A: "));
        let d = diff_of(&report(6.0, 2.0), &report(1.3, 2.0), 0.01);
        assert!(!d.changes[0].regression);
        assert_eq!(d.regressions, 0);
    }

    #[test]
    fn a_known_non_compliance_passes_only_with_its_disposition() {
        let known = ncr(report(1.3, 6.0), "F-B");
        let d = diff_of(&known, &known, 0.01);
        assert_eq!(d.regressions, 0);
        // the same non-compliance with no disposition, in the baseline and now: a regression
        let d = diff_of(&report(1.3, 6.0), &report(1.3, 6.0), 0.01);
        assert_eq!(d.regressions, 1);
        assert!(summary_lines(&d)[0].contains("F-B: non-compliant with no disposition"));
        // the disposition dropped since the baseline
        let d = diff_of(&known, &report(1.3, 6.0), 0.01);
        assert_eq!(d.regressions, 1);
        assert!(summary_lines(&d)[0].contains("NCR-1 was withdrawn"));
    }

    #[test]
    fn a_requirement_edit_needs_review_in_either_direction() {
        let old = report(1.3, 2.0);
        for (text, limit) in [("<= 5.5 um/s", 5.5), ("<= 4.5 um/s", 4.5)] {
            let mut new = report(1.3, 2.0);
            let row = &mut new.matrix.requirements[1];
            row.limit_text = text.into();
            row.limit = Some(limit);
            let d = diff_of(&old, &new, 0.01);
            assert_eq!(d.regressions, 1, "{text}");
            let line = &summary_lines(&d)[0];
            assert!(
                line.starts_with(
                    "REGRESSION F-B: requirement changed, needs review: limit `<= 5 um/s` -> `"
                ) && line.contains(text),
                "{line}"
            );
        }
        let mut new = report(1.3, 2.0);
        new.matrix.requirements[0].text = "shall, more loosely".into();
        new.matrix.requirements[0].probability = Some("50 %".into());
        let d = diff_of(&old, &new, 0.01);
        let line = &summary_lines(&d)[0];
        assert!(
            line.contains("probability none -> `50 %`") && line.contains("text `shall` -> "),
            "{line}"
        );
    }

    #[test]
    fn a_new_non_compliant_requirement_without_disposition_fails() {
        let mut old = report(1.3, 2.0);
        old.matrix.requirements.pop();
        let d = diff_of(&old, &report(1.3, 6.0), 0.01);
        assert_eq!(d.added, ["F-B"]);
        assert_eq!(d.regressions, 1);
        assert!(
            summary_lines(&d)[0]
                .starts_with("REGRESSION F-B: new requirement, non-compliant with no disposition")
        );
        // with its disposition it is listed, not failed
        let d = diff_of(&old, &ncr(report(1.3, 6.0), "F-B"), 0.01);
        assert_eq!(d.regressions, 0);
    }

    /// A sampled row of `n` draws whose 99.73 % estimate is `est` um/s and upper bound `up`.
    fn sampled(mut r: Report, n: u64, est: f64, up: f64) -> Report {
        let row = &mut r.matrix.requirements[0];
        row.value = Some(up);
        row.margin = Some((5.0 - up) / 5.0);
        row.sampling = Some(geodesic_core::check::Sampling {
            statistic: geodesic_core::check::SampleStatistic::Quantile,
            probability: 0.9973,
            confidence: 0.95,
            n,
            successes: None,
            estimate: est,
            lower: Some(2.0 * est - up),
            upper: Some(up),
            lower_rank: None,
            upper_rank: None,
            n_required: 1109,
            method: "test".into(),
        });
        r
    }

    #[test]
    fn a_sampled_margin_is_judged_by_its_sampling_and_its_sample_size() {
        // estimate 1.329 +- about 0.003 (bound 1.334): a move within sampling passes, ...
        let old = sampled(report(1.3, 2.0), 100_000, 1.329, 1.334);
        let d = diff_of(
            &old,
            &sampled(report(1.3, 2.0), 100_000, 1.331, 1.336),
            0.01,
        );
        assert_eq!(d.regressions, 0, "{:?}", d.changes);
        // ... 0.03 um/s (0.6 % of the limit, below the fixed 1 % tolerance) is beyond it
        let d = diff_of(
            &old,
            &sampled(report(1.3, 2.0), 100_000, 1.359, 1.364),
            0.01,
        );
        assert_eq!(d.regressions, 1);
        assert!(
            summary_lines(&d)[0].contains("sampling explains"),
            "{:?}",
            summary_lines(&d)
        );
        // a smaller sample than the baseline's fails even when its bound looks good
        let d = diff_of(&old, &sampled(report(1.3, 2.0), 2_000, 1.2, 1.3), 0.01);
        assert!(summary_lines(&d)[0].contains("N = 2000, the baseline's on N = 100000"));
        // so does a lower confidence
        let mut lower = sampled(report(1.3, 2.0), 100_000, 1.329, 1.333);
        lower.matrix.requirements[0]
            .sampling
            .as_mut()
            .unwrap()
            .confidence = 0.9;
        let d = diff_of(&old, &lower, 0.01);
        assert_eq!(d.regressions, 1);
        assert!(
            summary_lines(&d)[0]
                .contains("its bound is at 90 % confidence, the baseline's at 95 %"),
            "{:?}",
            summary_lines(&d)
        );
    }

    #[test]
    fn a_malformed_baseline_names_file_and_line() {
        let e = diff_text(
            &report(1.0, 1.0),
            "{\"requirements\": [\n  {\"id\": 3}\n]}",
            "old.json",
            0.01,
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("old.json:2:"), "{e}");
    }
}
