//! `index.html`: the whole verification as one self-contained page that works offline from the
//! file system: the document identification, a table of contents, the matrix with status
//! colours, the Verification Control Document (ECSS-E-ST-10-02C Annex B columns, the full
//! evidence of each line one click away), the fidelity table, a section per requirement with
//! its evidence, tests and this run's plots (SVG inlined, no external resource, no CDN), and the
//! trace views. `vcd.html` is the VCD alone.
//!
//! Only the plots this run's evidence names are shown (found in the run's staging directory):
//! plots that earlier commands such as `geodesic fit` left in `reports/fits/` are not part of
//! this document.
//!
//! Rendered with `format!` and explicit escaping rather than a template engine: the page is one
//! fixed layout, and every dynamic string goes through [`crate::junit::esc`].

use crate::junit::esc;
use crate::{Report, fmt_limit, fmt_margin, fmt_value, vcd};
use geodesic_core::matrix::{EvidenceEntry, Row, Status};
use std::fmt::Write as _;
use std::path::Path;

const STYLE: &str = r#"
html{font-size:16px}
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:0;color:#1d2330;background:#fafbfc;line-height:1.4}
header{background:#14213d;color:#fff;padding:1em 2em}
header h1{margin:0 0 .2em 0;font-size:1.5em}
header .doc{font-size:1.05em}
nav.toc{position:fixed;top:0;left:0;bottom:0;width:15em;overflow-y:auto;background:#eef1f6;border-right:1px solid #d8dde6;padding:1em;box-sizing:border-box;font-size:.95em}
nav.toc a{color:#14213d;text-decoration:none}
nav.toc a:hover{text-decoration:underline}
nav.toc ol{padding-left:1.2em;margin:.3em 0}
nav.toc li{margin:.15em 0}
nav.toc .dot{display:inline-block;width:.7em;height:.7em;border-radius:50%;margin-right:.3em;border:1px solid #889}
.page{margin-left:15em}
main{padding:1em 2em;max-width:1500px}
h2{border-bottom:2px solid #14213d;padding-bottom:.2em;margin-top:1.6em}
h2 .up{font-size:.6em;font-weight:normal;margin-left:.8em}
h3 .up{font-size:.75em;font-weight:normal;margin-left:.8em}
table.vcd{table-layout:fixed}
table.vcd col.c-id{width:8%}table.vcd col.c-req{width:20%}table.vcd col.c-lvl{width:10%}
table.vcd col.c-ev{width:23%}table.vcd col.c-val{width:9%}table.vcd col.c-co{width:15%}
table.vcd col.c-rem{width:10%}table.vcd col.c-rv{width:5%}
table.vcd td{overflow-wrap:break-word}
table.matrix{table-layout:fixed}
table.matrix col.m-id{width:11%}table.matrix col.m-t{width:11%}table.matrix col.m-me{width:10%}
table.matrix col.m-st{width:12%}table.matrix col.m-b{width:9%}table.matrix col.m-v{width:10%}
table.matrix col.m-l{width:11%}table.matrix col.m-mg{width:7%}table.matrix col.m-ev{width:10%}
table.matrix col.m-te{width:9%}
table.matrix td{overflow-wrap:break-word}table.matrix td.num{white-space:normal;overflow-wrap:normal}
table{border-collapse:collapse;width:100%;margin:.6em 0 1.4em 0;font-size:.9em;background:#fff}
th,td{border:1px solid #d8dde6;padding:.35em .5em;text-align:left;vertical-align:top}
th{background:#eef1f6;position:sticky;top:0}
td.ev{overflow-wrap:anywhere;font-size:.85rem}
td.num{white-space:nowrap}
table.meta{width:auto}
table.meta th{position:static;white-space:nowrap}
.compliant{background:#d7f5dd}.non-compliant{background:#fbd5d5}.not-verified{background:#fff3cd}
.dot.compliant{background:#2e9e4f}.dot.non-compliant{background:#d03030}.dot.not-verified{background:#e0a800}
.badge{padding:.1em .5em;border-radius:.6em;font-weight:600}
h3 .badge{white-space:nowrap}
section.req{background:#fff;border:1px solid #d8dde6;border-radius:6px;padding:.6em 1.2em;margin:1em 0}
.plot{margin:.6em 0}
.plot svg{max-width:100%;height:auto;border:1px solid #e3e6ec;background:#fff}
.filters button{margin-right:.4em;padding:.3em .8em;border:1px solid #99a;border-radius:4px;background:#fff;cursor:pointer;font-size:.95em}
.filters button.on{background:#14213d;color:#fff}
code{background:#eef1f6;color:#1d2330;padding:0 .2em;border-radius:3px;font-size:.95em}
details summary{cursor:pointer;color:#1d4f91}
details ul{margin:.3em 0;padding-left:1.2em}
.muted{color:#556}
.small{font-size:.85rem}
@media print{nav.toc{display:none}.page{margin-left:0}}
"#;

const SCRIPT: &str = r#"
(function(){
  var buttons = document.querySelectorAll('.filters button');
  function show(status){
    document.querySelectorAll('tr[data-status]').forEach(function(tr){
      tr.style.display = (status === 'all' || tr.getAttribute('data-status') === status) ? '' : 'none';
    });
    buttons.forEach(function(b){ b.classList.toggle('on', b.getAttribute('data-filter') === status); });
  }
  buttons.forEach(function(b){ b.addEventListener('click', function(){ show(b.getAttribute('data-filter')); }); });
  show('all');
  document.body.setAttribute('data-js', 'ready');
})();
"#;

/// Reads an SVG file and returns its markup without the XML declaration, ready to inline.
fn inline_svg(path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(path).ok()?;
    let start = text.find("<svg")?;
    Some(text[start..].to_string())
}

/// `↑ contents` link placed after a heading.
const UP: &str = "<a class=\"up\" href=\"#contents\">↑ contents</a>";

/// The document identification and the run as a two-column table.
fn meta_table(rep: &Report) -> String {
    let mut o = String::from("<table class=\"meta\"><tbody>");
    for (k, v) in crate::run_lines(rep) {
        let _ = write!(o, "<tr><th>{}</th><td>{}</td></tr>", esc(k), esc(&v));
    }
    o.push_str("</tbody></table>");
    o
}

/// The VCD table (Annex B columns), shared by `index.html` and `vcd.html`. `link` is the prefix
/// of the links to the requirement sections (`""` inside `index.html`, `index.html` outside).
fn vcd_table(rep: &Report, link: &str) -> String {
    let mut o = String::from(
        "<table class=\"vcd\"><colgroup><col class=\"c-id\"><col class=\"c-req\"><col class=\"c-lvl\"><col class=\"c-ev\">\
         <col class=\"c-val\"><col class=\"c-co\"><col class=\"c-rem\"><col class=\"c-rv\"></colgroup><thead><tr><th>ID</th><th>Requirement, source, parent / children</th>\
         <th>Level, stage, method</th><th>Activity and evidence</th><th>Value, limit, margin</th>\
         <th>Compliance, close-out</th><th>Remarks</th><th>Re-verify</th></tr></thead><tbody>",
    );
    for (l, r) in vcd::lines(rep).iter().zip(&rep.matrix.requirements) {
        let st = r.status.as_str();
        let idlink = |id: &str| format!("<a href=\"{link}#{0}\">{0}</a>", esc(id));
        let children = if l.children.is_empty() {
            "—".to_string()
        } else {
            l.children
                .iter()
                .map(|c| idlink(c))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let detail: String = l
            .detail
            .iter()
            .map(|d| format!("<li>{}</li>", esc(d)))
            .collect();
        let refs: String = l
            .references
            .iter()
            .map(|d| format!("<li>{}</li>", esc(d)))
            .collect();
        let _ = write!(
            o,
            "<tr id=\"vcd-{id}\" data-status=\"{st}\" class=\"{st}\"><td><b>{idl}</b></td>\
             <td><b>{title}</b><br><span class=\"small\">{text}</span><br><span class=\"small muted\">Source: {src}<br>Parent: {parent}; children: {children}</span></td>\
             <td>{level}<br>{stage}<br>{method}</td>\
             <td class=\"ev\">{act}<br><b>{ev}</b> <a href=\"{link}#{id}\">§ evidence</a>\
             <details><summary>full evidence and references</summary><ul>{detail}</ul><b>References</b><ul>{refs}</ul></details></td>\
             <td>{value}<br>{limit}<br>margin {margin}<br><span class=\"small muted\">basis {basis}{sample}</span></td>\
             <td><span class=\"badge\">{comp}</span><br><span class=\"small\">credibility {cred}</span><br><b>{co}</b>: {cor}{cref}</td><td class=\"small\">{rem}</td><td>{rv}</td></tr>",
            id = esc(&l.id),
            idl = idlink(&l.id),
            title = esc(&l.title),
            text = esc(&l.text),
            src = esc(&l.source),
            parent = if l.parent.is_empty() {
                "—".to_string()
            } else {
                idlink(&l.parent)
            },
            level = esc(&l.level),
            stage = esc(&l.stage),
            method = esc(&l.method),
            act = esc(&l.activity),
            ev = esc(&l.evidence),
            value = esc(&l.value),
            limit = esc(&l.limit),
            margin = esc(&l.margin).replace(" %", "&nbsp;%"),
            basis = if l.basis.is_empty() { "—" } else { l.basis },
            sample = if l.sampling.is_empty() {
                String::new()
            } else {
                format!("<br>sample: {}", esc(&l.sampling))
            },
            comp = esc(&l.compliance),
            cred = esc(&l.credibility),
            co = l.close_out,
            cor = esc(&l.close_out_reason),
            cref = if l.close_out_reference.is_empty() {
                String::new()
            } else {
                format!(
                    "<br><span class=\"small muted\">{}</span>",
                    esc(&l.close_out_reference)
                )
            },
            rem = if l.remarks.is_empty() {
                "—".to_string()
            } else {
                format!(
                    "<details><summary>{}</summary>{}</details>",
                    esc(&short(&l.remarks, 90)),
                    esc(&l.remarks)
                )
            },
            rv = if l.reverify {
                format!(
                    "<details><summary><b>yes</b></summary>{}</details>",
                    esc(&l.reverify_reason)
                )
            } else {
                "no".into()
            },
        );
    }
    o.push_str("</tbody></table>");
    o
}

/// The first `n` characters of `s` at a word boundary, with `…` when cut.
fn short(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        return s.to_string();
    }
    let cut: String = s.chars().take(n).collect();
    let cut = cut.rsplit_once(' ').map_or(cut.as_str(), |(a, _)| a);
    format!("{cut} …")
}

/// Renders the page. Artifacts named by the evidence are searched in `artifact_dirs` in order
/// (the staging directory of this run); nothing else is inlined.
pub fn render(rep: &Report, artifact_dirs: &[&Path]) -> String {
    let m = &rep.matrix;
    let mut o = String::new();
    head_and_contents(&mut o, rep);
    page_header(&mut o, rep);
    let fid = !rep.run.fidelity.is_empty();
    let (n_req, n_trace) = if fid { (5, 6) } else { (4, 5) };
    let _ = write!(
        o,
        "<h2 id=\"identification\">1 Document identification{UP}</h2>{}",
        meta_table(rep)
    );
    matrix_table(&mut o, rep);
    let _ = write!(
        o,
        "<h2 id=\"vcd\">3 Verification Control Document{UP}</h2>\
         <p class=\"muted\">ECSS-E-ST-10-02C Annex B. Compliance: yes / yes (basis or finding) / no / partial (partly met) / not verified. \
         Each line links to the section holding its evidence; the full evidence is one click away. \
         Also as <a href=\"vcd.html\">vcd.html</a>, <a href=\"vcd.xlsx\">vcd.xlsx</a>, <a href=\"vcd.csv\">vcd.csv</a>, <a href=\"vcd.md\">vcd.md</a>.</p>{}",
        vcd_table(rep, "")
    );
    fidelity_table(&mut o, rep);
    let _ = write!(o, "<h2 id=\"requirements\">{n_req} Requirements{UP}</h2>");
    let run = m.test_run.is_some();
    for r in &m.requirements {
        requirement_section(&mut o, r, run, artifact_dirs);
    }
    trace_views(&mut o, rep, n_trace);
    let _ = writeln!(o, "</main></div><script>{SCRIPT}</script></body></html>");
    o
}

/// The document's head (title and style) and the table of contents, one entry per
/// requirement with its status colour.
fn head_and_contents(o: &mut String, rep: &Report) {
    let d = &rep.run.document;
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{id} issue {issue}: {title}</title>\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><style>{STYLE}</style></head><body>",
        id = esc(&d.id),
        issue = esc(&d.issue),
        title = esc(&d.title)
    );
    let _ = write!(
        o,
        "<nav class=\"toc\" id=\"contents\"><b>Contents</b><ol>\
         <li><a href=\"#identification\">Document identification</a></li>\
         <li><a href=\"#matrix\">Compliance matrix</a></li>\
         <li><a href=\"#vcd\">Verification Control Document</a></li>"
    );
    if !rep.run.fidelity.is_empty() {
        let _ = write!(
            o,
            "<li><a href=\"#fidelity\">{}</a></li>",
            esc(&rep.run.reference.title)
        );
    }
    let _ = write!(o, "<li><a href=\"#requirements\">Requirements</a><ol>");
    for r in &rep.matrix.requirements {
        let st = r.status.as_str();
        let _ = write!(
            o,
            "<li><a href=\"#{id}\"><span class=\"dot {st}\" title=\"{st}\"></span>{id}</a></li>",
            id = esc(&r.id)
        );
    }
    let _ = write!(
        o,
        "</ol></li><li><a href=\"#trace\">Trace views</a></li></ol></nav><div class=\"page\">"
    );
}

/// The banner: the document's title and identification, the summary, the run's date and
/// whether the test results are stale.
fn page_header(o: &mut String, rep: &Report) {
    let m = &rep.matrix;
    let d = &rep.run.document;
    let _ = write!(
        o,
        "<header><h1>{title}</h1><div class=\"doc\">{id} issue {issue} · {project}</div>\
         <div><b>{}</b> · run {date}{stale}</div></header><main>",
        esc(&m.summary.line()),
        stale = match &m.test_run {
            Some(t) if !t.fresh => format!(
                " · <b>test results STALE</b>: {}",
                esc(t.stale_reason.as_deref().unwrap_or(""))
            ),
            _ => String::new(),
        },
        title = esc(&d.title),
        id = esc(&d.id),
        issue = esc(&d.issue),
        project = esc(&d.project),
        date = esc(&rep.run.date),
    );
}

/// Section 2: the status filters and the compliance matrix, one row per requirement.
fn matrix_table(o: &mut String, rep: &Report) {
    let m = &rep.matrix;
    let _ = write!(
        o,
        "<h2 id=\"matrix\">2 Compliance matrix{UP}</h2><div class=\"filters\">\
         <button data-filter=\"all\">all</button><button data-filter=\"compliant\">compliant</button>\
         <button data-filter=\"non-compliant\">non-compliant</button><button data-filter=\"not-verified\">not-verified</button></div>\
         <table class=\"matrix\"><colgroup><col class=\"m-id\"><col class=\"m-t\"><col class=\"m-me\"><col class=\"m-st\"><col class=\"m-b\">\
         <col class=\"m-v\"><col class=\"m-l\"><col class=\"m-mg\"><col class=\"m-ev\"><col class=\"m-te\"><col class=\"m-cr\"></colgroup>\
         <thead><tr><th>ID</th><th>Title</th><th>Method</th><th>Status</th><th>Basis</th><th>Value</th><th>Limit</th><th>Margin</th><th>Evidence</th><th>Tests</th><th>Credibility</th></tr></thead><tbody>"
    );
    let run = m.test_run.is_some();
    for r in &m.requirements {
        let st = r.status.as_str();
        let mut checks: Vec<String> = r
            .evidence
            .iter()
            .map(|e| format!("<code>{}</code>", esc(&e.check)))
            .collect();
        checks.dedup();
        let _ = write!(
            o,
            "<tr id=\"matrix-{id}\" data-status=\"{st}\" class=\"{st}\"><td><a href=\"#{id}\">{id}</a></td><td>{t}</td><td>{meth}</td>\
             <td><span class=\"badge\">{verdict}</span></td><td>{basis}</td><td class=\"num\">{v}</td><td class=\"num\">{lim}</td><td class=\"num\">{mg}</td><td>{ev}</td><td>{nt}</td><td>{cr}</td></tr>",
            cr = esc(&crate::credibility_word(r)),
            verdict = esc(&crate::verdict(r)),
            basis = crate::basis_word(r),
            id = esc(&r.id),
            t = esc(&r.title),
            meth = esc(&r.method),
            v = esc(&fmt_value(r)),
            lim = esc(&fmt_limit(r)),
            mg = fmt_margin(r.margin),
            ev = if checks.is_empty() {
                "—".into()
            } else {
                checks.join(" ")
            },
            nt = esc(&crate::tests_word(r, run))
        );
    }
    let _ = write!(o, "</tbody></table>");
}

/// Section 4 when the run has one: the mission's figures against its reference.
fn fidelity_table(o: &mut String, rep: &Report) {
    if rep.run.fidelity.is_empty() {
        return;
    }
    let _ = write!(
        o,
        "<h2 id=\"fidelity\">4 {}{UP}</h2><table><thead><tr><th>Figure</th><th>geodesic</th>\
         <th>{}</th><th>Difference</th><th>Assumptions</th></tr></thead><tbody>",
        esc(&rep.run.reference.title),
        esc(&rep.run.reference.column)
    );
    for f in &rep.run.fidelity {
        let _ = write!(
            o,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"small\">{}</td></tr>",
            esc(&f.figure),
            esc(&f.value),
            esc(&f.reference),
            esc(&f.difference),
            esc(&f.note)
        );
    }
    let _ = write!(o, "</tbody></table>");
}

/// One requirement's section: its statement and attributes, its verdict, its evidence (with
/// the plots found in `artifact_dirs`) and its traced tests (`run`: a test run is recorded).
fn requirement_section(o: &mut String, r: &Row, run: bool, artifact_dirs: &[&Path]) {
    let st = r.status.as_str();
    let _ = write!(
        o,
        "<section class=\"req\" id=\"{id}\"><h3>{id} — {t} <span class=\"badge {st}\">{verdict}</span>\
         <a class=\"up\" href=\"#matrix-{id}\">matrix row</a><a class=\"up\" href=\"#vcd-{id}\">VCD line</a>{UP}</h3>\
         <blockquote>{text}</blockquote><ul><li>Source: {src}</li><li>Quantity: {q}</li>\
         <li>Limit: {lim}{prob}</li><li>Method: {meth}; level {level}, stage {stage}; activity: {act}</li>",
        id = esc(&r.id),
        t = esc(&r.title),
        verdict = esc(&crate::verdict(r)),
        text = esc(&r.text),
        src = esc(&r.source),
        q = esc(&r.quantity),
        lim = esc(&fmt_limit(r)),
        prob = r
            .probability
            .as_ref()
            .map_or(String::new(), |p| format!(" at {}", esc(p))),
        meth = esc(&r.method),
        level = esc(&r.level),
        stage = esc(&r.stage),
        act = esc(&r.activity)
    );
    if let Some(p) = &r.parent {
        let _ = write!(
            o,
            "<li>Parent: <a href=\"#{p}\">{p}</a> (margin factor {})</li>",
            r.parent_margin.unwrap_or(1.0),
            p = esc(p)
        );
    }
    if !r.children.is_empty() {
        let c: Vec<String> = r
            .children
            .iter()
            .map(|c| format!("<a href=\"#{0}\">{0}</a>", esc(c)))
            .collect();
        let _ = write!(o, "<li>Children: {}</li>", c.join(", "));
    }
    if let Some(n) = &r.note {
        let _ = write!(o, "<li>Remark: {}</li>", esc(n));
    }
    verdict_items(o, r);
    let _ = write!(o, "</ul>");
    for e in &r.evidence {
        evidence(o, r, e, artifact_dirs);
    }
    traced_tests(o, r, run);
    let _ = write!(o, "</section>");
}

/// A requirement's disposition, value or reason not verified, sample and findings, as items
/// of its list.
fn verdict_items(o: &mut String, r: &Row) {
    if let Some(d) = &r.disposition {
        let _ = write!(
            o,
            "<li>Disposition: <b>{} {}</b>{} (owner {}, raised {}{}): {}</li>",
            d.kind.as_str(),
            esc(&d.reference),
            if d.expired { " EXPIRED" } else { "" },
            esc(&d.owner),
            esc(&d.date),
            d.expires
                .as_ref()
                .map_or(String::new(), |e| format!(", expires {}", esc(e))),
            esc(&d.reason)
        );
    }
    match r.status {
        Status::NotVerified => {
            let _ = write!(
                o,
                "<li>Not verified: {}</li>",
                esc(r.reason.as_deref().unwrap_or("no evidence"))
            );
        }
        _ => {
            let _ = write!(
                o,
                "<li>Value <b>{}</b> against {} — margin {}</li>",
                esc(&fmt_value(r)),
                esc(&fmt_limit(r)),
                fmt_margin(r.margin)
            );
        }
    }
    if let Some(sm) = crate::sampling_text(r) {
        let _ = write!(
            o,
            "<li>Sample: {} ({})</li>",
            esc(&sm),
            esc(r.sampling.as_ref().map_or("", |s| s.method.as_str()))
        );
    }
    for f in &r.findings {
        let _ = write!(o, "<li>Finding: {}</li>", esc(f));
    }
    if let Some((head, factors)) = crate::credibility_lines(r).split_first() {
        let items: String = factors
            .iter()
            .map(|l| format!("<li>{}</li>", esc(l)))
            .collect();
        let _ = write!(
            o,
            "<li>Credibility {} (rubric: docs/credibility.md)<ul>{items}</ul></li>",
            esc(head)
        );
    }
}

/// One evidence entry of requirement `r`: its check, value or reason, inputs, and the SVG
/// plots it names that are found in `artifact_dirs` (inlined).
fn evidence(o: &mut String, r: &Row, e: &EvidenceEntry, artifact_dirs: &[&Path]) {
    let find = |rel: &str| {
        artifact_dirs
            .iter()
            .map(|d| d.join(rel))
            .find(|p| p.exists())
    };
    let inputs: String = e
        .inputs
        .iter()
        .map(|(k, v)| format!("<li>{} = {}</li>", esc(k), esc(&vcd::fmt_input(v))))
        .collect();
    let _ = write!(
        o,
        "<p><b>Evidence</b> <code>{}</code>{}: {} {}</p>{}",
        esc(&e.check),
        e.basis
            .map_or(String::new(), |b| format!(" [{}]", b.as_str())),
        esc(&e.activity),
        e.value.map_or_else(
            || e.reason
                .as_ref()
                .map_or(String::new(), |w| format!("— not verified: {}", esc(w))),
            |v| format!(
                "— <b>{} {}</b>{}",
                crate::units_near(v, r.limit.unwrap_or(f64::NAN)),
                esc(&r.unit),
                e.sampling.as_ref().map_or(String::new(), |sm| format!(
                    " ({})",
                    esc(&sm.describe(&|x| format!(
                        "{} {}",
                        crate::units_near(x, r.limit.unwrap_or(f64::NAN)),
                        r.unit
                    )))
                ))
            )
        ),
        if inputs.is_empty() {
            String::new()
        } else {
            format!("<details><summary>inputs</summary><ul class=\"small\">{inputs}</ul></details>")
        }
    );
    for a in &e.artifacts {
        if let Some(p) = find(a)
            && a.ends_with(".svg")
            && let Some(svg) = inline_svg(&p)
        {
            let _ = write!(
                o,
                "<div class=\"plot\"><p class=\"muted small\">{}</p>{svg}</div>",
                esc(a)
            );
        }
    }
}

/// A requirement's traced tests with their recorded results (nothing without one).
fn traced_tests(o: &mut String, r: &Row, run: bool) {
    if r.tests.is_empty() {
        return;
    }
    let _ = write!(
        o,
        "<p><b>Traced tests</b> ({})</p><ul>",
        esc(&crate::tests_word(r, run))
    );
    for t in &r.tests {
        let asserted: Vec<&str> = t.assertions.iter().map(|a| a.as_str()).collect();
        let _ = write!(
            o,
            "<li><code title=\"{full}\">{short}</code> ({kind}, {loc}): <b>{res}</b>, asserts {asserted}</li>",
            full = esc(&t.test),
            short = esc(&vcd::short_test(t)),
            kind = esc(&t.kind),
            loc = esc(&t.location),
            res = t.result.as_str(),
            asserted = esc(&asserted.join(", "))
        );
    }
    let _ = write!(o, "</ul>");
}

/// The last section, numbered `n`: checks to requirements, orphan checks, and the
/// requirements without a value or without a traced test.
fn trace_views(o: &mut String, rep: &Report, n: usize) {
    let m = &rep.matrix;
    let _ = write!(
        o,
        "<h2 id=\"trace\">{n} Trace views{UP}</h2><h3>Checks to requirements</h3><table><thead><tr><th>Check</th><th>Verifies</th></tr></thead><tbody>"
    );
    for c in &rep.run.checks {
        let ids: Vec<String> = c
            .verifies
            .iter()
            .map(|id| format!("<a href=\"#{0}\">{0}</a>", esc(id)))
            .collect();
        let _ = write!(
            o,
            "<tr><td><code>{}</code></td><td>{}</td></tr>",
            esc(&c.name),
            ids.join(", ")
        );
    }
    let _ = write!(o, "</tbody></table><h3>Orphan checks</h3>");
    if m.orphan_checks.is_empty() {
        let _ = write!(o, "<p>None.</p>");
    } else {
        let _ = write!(o, "<ul>");
        for x in &m.orphan_checks {
            let _ = write!(
                o,
                "<li><code>{}</code> names {}, not loaded</li>",
                esc(&x.check),
                esc(&x.requirement)
            );
        }
        let _ = write!(o, "</ul>");
    }
    let _ = write!(
        o,
        "<h3>Requirements without a measured value</h3><p>{}</p><h3>Requirements without a traced test</h3><p>{}</p>",
        esc(&crate::id_list(&m.without_value())),
        esc(&crate::id_list(&m.without_tests()))
    );
}

/// The Verification Control Document alone, as a self-contained HTML page (links to the
/// evidence go to `index.html` beside it).
pub fn render_vcd(rep: &Report) -> String {
    let d = &rep.run.document;
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{id} issue {issue}: Verification Control Document</title>\
         <style>{STYLE}</style></head><body><header><h1>Verification Control Document</h1>\
         <div class=\"doc\">{id} issue {issue}: {title} · {project}</div></header><main>{meta}\
         <p class=\"muted\">ECSS-E-ST-10-02C Annex B. Compliance: yes / yes (basis or finding) / no / partial (partly met) / not verified. \
         The evidence of each line is in <a href=\"index.html\">index.html</a> (the § evidence links).</p>{table}</main></body></html>\n",
        id = esc(&d.id),
        issue = esc(&d.issue),
        title = esc(&d.title),
        project = esc(&d.project),
        meta = meta_table(rep),
        table = vcd_table(rep, "index.html")
    )
}

#[cfg(test)]
mod tests {
    use crate::testutil::report;

    #[test]
    fn pages_have_contents_links_and_no_markdown() {
        let r = report(1.3, 6.0);
        for page in [super::render(&r, &[]), super::render_vcd(&r)] {
            assert!(!page.contains('`'), "a Markdown backtick in the HTML");
            assert!(page.contains("DOC-1 issue 2"));
            assert!(page.contains("&lt;= 5 um/s"));
        }
        let page = super::render(&r, &[]);
        for anchor in [
            "#identification",
            "#matrix",
            "#vcd",
            "#requirements",
            "#trace",
            "#F-A",
        ] {
            assert!(
                page.contains(&format!("href=\"{anchor}\"")),
                "no link to {anchor}"
            );
        }
        assert!(page.contains("id=\"vcd-F-B\"") && page.contains("<details>"));
    }

    #[test]
    fn only_the_plots_the_evidence_names_are_inlined() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(tmp.path().join("fits")).unwrap();
        let svg = |t: &str| format!("<?xml version=\"1.0\"?><svg><text>{t}</text></svg>");
        std::fs::write(tmp.path().join("fits/this-run.svg"), svg("THIS RUN")).unwrap();
        std::fs::write(tmp.path().join("fits/stray.svg"), svg("STRAY")).unwrap();
        let mut r = report(1.3, 6.0);
        r.matrix.requirements[0].evidence[0]
            .artifacts
            .push("fits/this-run.svg".into());
        let page = super::render(&r, &[tmp.path()]);
        assert!(page.contains("THIS RUN") && !page.contains("STRAY"));
    }
}
