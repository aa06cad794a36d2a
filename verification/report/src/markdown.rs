//! `compliance.md`: the compliance matrix, a section per requirement with its evidence and
//! tests, and the trace views (check to requirements, orphan checks, requirements without
//! evidence).

use crate::{Report, fmt_limit, fmt_margin, fmt_value};
use geodesic_core::matrix::{Row, Status};
use geodesic_core::units::fmt_num;
use std::fmt::Write as _;

fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

fn badge(s: Status) -> &'static str {
    match s {
        Status::Compliant => "✅ compliant",
        Status::NonCompliant => "❌ non-compliant",
        Status::NotVerified => "⚠️ not-verified",
    }
}

/// Renders the whole Markdown report.
pub fn render(rep: &Report) -> String {
    let mut o = String::new();
    summary_table(&mut o, rep);
    fidelity_table(&mut o, rep);
    let _ = writeln!(o, "\n## Requirements\n");
    for r in &rep.matrix.requirements {
        requirement_section(&mut o, r);
    }
    trace_views(&mut o, rep);
    o
}

/// The heading, the run's lines, the summary with how to read it, and the matrix: one line
/// per requirement.
fn summary_table(o: &mut String, rep: &Report) {
    let m = &rep.matrix;
    let _ = writeln!(o, "# geodesic compliance matrix\n");
    for (k, v) in crate::run_lines(rep) {
        let _ = writeln!(o, "- {k}: {}", cell(&v));
    }
    let _ = writeln!(o);
    let _ = writeln!(
        o,
        "**{}.** Margin = (limit − value) / limit \
         (sign-adjusted for lower bounds; positive means met). A requirement without a value is `not-verified`, \
         never compliant. A sampled value is the confidence bound that decides, never the estimate. \
         The status reads as what the verdict rests on: plain `compliant` is a model or measurement \
         verdict with no finding; `flow-down`, `accepted`, `method validation`, `by construction`, \
         an assumed row that is not verified, a rejected model input or a test problem say so.\n",
        m.summary.line()
    );
    let _ = writeln!(
        o,
        "| ID | Title | Method | Status | Basis | Value | Limit | Margin | Evidence | Tests | Credibility |"
    );
    let _ = writeln!(o, "|---|---|---|---|---|---|---|---|---|---|---|");
    let run = m.test_run.is_some();
    for r in &m.requirements {
        let value = fmt_value(r);
        let ev: Vec<String> = r
            .evidence
            .iter()
            .map(|e| format!("`{}`", e.check))
            .collect();
        let _ = writeln!(
            o,
            "| [{id}](#{anchor}){dep} | {t} | {meth} | {st} | {basis} | {value} | {lim} | {mg} | {ev} | {nt} | {cr} |",
            id = r.id,
            dep = match &r.selection {
                Some(s) if s.role == "dependency" => format!(" (dependency: {})", cell(&s.why)),
                _ => String::new(),
            },
            anchor = r.id.to_lowercase(),
            t = cell(&r.title),
            meth = r.method,
            st = crate::verdict(r),
            basis = crate::basis_word(r),
            lim = geodesic_util::escape::text(&fmt_limit(r)),
            mg = fmt_margin(r.margin),
            ev = if ev.is_empty() {
                "—".into()
            } else {
                ev.join(", ")
            },
            nt = crate::tests_word(r, run),
            cr = crate::credibility_word(r)
        );
    }
}

/// The mission's figures against its reference (nothing when the run has none).
fn fidelity_table(o: &mut String, rep: &Report) {
    if rep.run.fidelity.is_empty() {
        return;
    }
    let _ = writeln!(o, "\n## {}\n", rep.run.reference.title);
    let _ = writeln!(
        o,
        "| Figure | geodesic | {} | Difference | Assumptions |",
        rep.run.reference.column
    );
    let _ = writeln!(o, "|---|---|---|---|---|");
    for f in &rep.run.fidelity {
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} |",
            cell(&f.figure),
            cell(&f.value),
            cell(&f.reference),
            f.difference,
            cell(&f.note)
        );
    }
}

/// One requirement's section: its statement and attributes, its verdict, its evidence and its
/// traced tests.
fn requirement_section(o: &mut String, r: &Row) {
    let _ = writeln!(o, "### {}\n", r.id);
    let _ = writeln!(o, "**{}** — {}\n", cell(&r.title), badge(r.status));
    let _ = writeln!(o, "> {}\n", r.text);
    let _ = writeln!(o, "- Source: {}", r.source);
    let unit = if r.unit.is_empty() { "-" } else { &r.unit };
    let _ = writeln!(o, "- Quantity: {} [{unit}]", r.quantity);
    let _ = writeln!(
        o,
        "- Limit: {}{}",
        fmt_limit(r),
        r.probability
            .as_ref()
            .map_or(String::new(), |p| format!(" at {p}"))
    );
    let _ = writeln!(
        o,
        "- Method: {} — level {}, stage {} — activity: {}",
        r.method, r.level, r.stage, r.activity
    );
    if let Some(n) = &r.note {
        let _ = writeln!(o, "- Remark: {}", cell(n));
    }
    if let Some(p) = &r.parent {
        let _ = writeln!(
            o,
            "- Parent: [{p}](#{}) (margin factor {})",
            p.to_lowercase(),
            r.parent_margin.unwrap_or(1.0)
        );
    }
    if !r.children.is_empty() {
        let c: Vec<String> = r
            .children
            .iter()
            .map(|c| format!("[{c}](#{})", c.to_lowercase()))
            .collect();
        let _ = writeln!(o, "- Children: {}", c.join(", "));
    }
    let _ = writeln!(o, "- Defined at: `{}`", r.defined_at);
    verdict_lines(o, r);
    credibility_list(o, r);
    evidence_list(o, r);
    traced_tests(o, r);
    let _ = writeln!(o);
}

/// A requirement's basis, findings, sample, disposition and status lines.
fn verdict_lines(o: &mut String, r: &Row) {
    let _ = writeln!(o, "- Basis of the verdict: {}", crate::basis_word(r));
    for f in &r.findings {
        let _ = writeln!(o, "- Finding: {}", cell(f));
    }
    if let Some(sm) = crate::sampling_text(r) {
        let _ = writeln!(
            o,
            "- Sample: {} ({})",
            cell(&sm),
            r.sampling.as_ref().map_or("", |s| s.method.as_str())
        );
    }
    if let Some(d) = &r.disposition {
        let _ = writeln!(
            o,
            "- Disposition: {} {} ({}; owner {}, raised {}{}{}) — {}",
            d.kind.as_str(),
            d.reference,
            d.defined_at,
            d.owner,
            d.date,
            d.expires
                .as_ref()
                .map_or(String::new(), |e| format!(", expires {e}")),
            if d.expired { ", EXPIRED" } else { "" },
            d.reason
        );
    }
    match r.status {
        Status::NotVerified => {
            let _ = writeln!(
                o,
                "- Status: not verified — {}",
                r.reason.as_deref().unwrap_or("no evidence")
            );
        }
        _ => {
            let _ = writeln!(
                o,
                "- Status: {} — value {} against {}, margin {}",
                r.verdict,
                fmt_value(r),
                fmt_limit(r),
                fmt_margin(r.margin)
            );
        }
    }
}

/// A row's credibility, factor by factor (nothing for a row not judged).
fn credibility_list(o: &mut String, r: &Row) {
    let lines = crate::credibility_lines(r);
    let Some((head, factors)) = lines.split_first() else {
        return;
    };
    let _ = writeln!(
        o,
        "\nCredibility (rubric: `docs/credibility.md`): {}\n",
        cell(head)
    );
    for l in factors {
        let _ = writeln!(o, "- {}", cell(l));
    }
}

/// A requirement's evidence, one item per check with its sample, assumptions, model inputs,
/// inputs and artifacts (nothing without evidence).
fn evidence_list(o: &mut String, r: &Row) {
    if r.evidence.is_empty() {
        return;
    }
    let _ = writeln!(o, "\nEvidence:\n");
    for e in &r.evidence {
        let what = match (e.value, &e.reason) {
            (Some(v), _) => format!("{} {}", fmt_num(v), r.unit),
            (None, Some(why)) => format!("not verified: {why}"),
            (None, None) => "—".into(),
        };
        let inputs: Vec<String> = e
            .inputs
            .iter()
            .map(|(k, v)| format!("{k} = {}", crate::vcd::fmt_input(v)))
            .collect();
        let basis = e.basis.map_or(String::new(), |b| format!(" [{b}]"));
        let _ = writeln!(o, "- `{}`{basis}: {} — {}", e.check, e.activity, what);
        if let Some(sm) = &e.sampling {
            let lim = r.limit.unwrap_or(f64::NAN);
            let _ = writeln!(
                o,
                "  - sample: {}",
                sm.describe(&|v| format!("{} {}", crate::units_near(v, lim), r.unit))
            );
        }
        if !e.assumes.is_empty() {
            let _ = writeln!(o, "  - takes as met: {}", e.assumes.join(", "));
        }
        if !e.model_inputs.is_empty() {
            let _ = writeln!(o, "  - model inputs: {}", e.model_inputs.join(", "));
        }
        if !inputs.is_empty() {
            let _ = writeln!(o, "  - inputs: {}", inputs.join(", "));
        }
        for a in &e.artifacts {
            let _ = writeln!(o, "  - artifact: [{a}]({a})");
        }
    }
}

/// A requirement's traced tests with their recorded results (nothing without one).
fn traced_tests(o: &mut String, r: &Row) {
    if r.tests.is_empty() {
        return;
    }
    let _ = writeln!(o, "\nTraced tests (recorded results):\n");
    for t in &r.tests {
        let _ = writeln!(
            o,
            "- `{}` ({}, `{}`): **{}**, {} case(s), asserts {}",
            t.test,
            t.kind,
            t.location,
            t.result.as_str(),
            t.cases,
            crate::assertions_text(t)
        );
    }
}

/// The trace views: checks to requirements, orphan checks, and the requirements without a
/// value, without a passing traced test, or with test problems.
fn trace_views(o: &mut String, rep: &Report) {
    let m = &rep.matrix;
    let _ = writeln!(o, "## Trace views\n");
    let _ = writeln!(o, "### Checks to requirements\n");
    let _ = writeln!(o, "| Check | Verifies |");
    let _ = writeln!(o, "|---|---|");
    for c in &rep.run.checks {
        let _ = writeln!(o, "| `{}` | {} |", c.name, c.verifies.join(", "));
    }
    let _ = writeln!(o, "\n### Orphan checks\n");
    if m.orphan_checks.is_empty() {
        let _ = writeln!(o, "None: every requirement a check names is loaded.");
    } else {
        for x in &m.orphan_checks {
            let _ = writeln!(
                o,
                "- `{}` names {}, which is not in the loaded requirements",
                x.check, x.requirement
            );
        }
    }
    let _ = writeln!(o, "\n### Requirements without a measured value\n");
    let _ = writeln!(o, "{}", crate::id_list(&m.without_value()));
    let _ = writeln!(
        o,
        "\n### Requirements without a passing traced test that asserts their limit or a reference\n"
    );
    let _ = writeln!(o, "{}", crate::id_list(&m.without_tests()));
    let _ = writeln!(
        o,
        "\n### Requirements whose traced tests failed, were ignored, did not run or are stale\n"
    );
    let _ = writeln!(o, "{}", crate::id_list(&m.with_test_problems()));
}
