//! `index.html`: the whole verification as one self-contained page that works offline from the
//! file system: the matrix with status colours, the Verification Control Document, a section per
//! requirement with its evidence, tests and plots (SVG inlined, no external resource, no CDN),
//! the trace views and a gallery of every other plot found in the reports directory (fit
//! residuals with failure windows, error history per dataset).
//!
//! Rendered with `format!` and explicit escaping rather than a template engine: the page is one
//! fixed layout, and every dynamic string goes through [`crate::junit::esc`].

use crate::junit::esc;
use crate::{Report, fmt_margin, fmt_opt, vcd};
use geodesic_core::matrix::Status;
use std::fmt::Write as _;
use std::path::Path;

const STYLE: &str = r#"
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:0;color:#1d2330;background:#fafbfc}
header{background:#14213d;color:#fff;padding:1.2em 2em}
header h1{margin:0 0 .3em 0;font-size:1.5em}
main{padding:1em 2em;max-width:1400px}
table{border-collapse:collapse;width:100%;margin:.6em 0 1.4em 0;font-size:.9em;background:#fff}
th,td{border:1px solid #d8dde6;padding:.35em .5em;text-align:left;vertical-align:top}
td.ev{overflow-wrap:anywhere;font-size:.85em}
th{background:#eef1f6}
.compliant{background:#d7f5dd}.non-compliant{background:#fbd5d5}.not-verified{background:#fff3cd}
.badge{padding:.1em .5em;border-radius:.6em;font-weight:600;white-space:nowrap}
section.req{background:#fff;border:1px solid #d8dde6;border-radius:6px;padding:.6em 1.2em;margin:1em 0}
.plot svg{max-width:100%;height:auto;border:1px solid #e3e6ec;background:#fff}
.filters button{margin-right:.4em;padding:.3em .8em;border:1px solid #99a;border-radius:4px;background:#fff;cursor:pointer}
.filters button.on{background:#14213d;color:#fff}
code{background:#eef1f6;color:#1d2330;padding:0 .2em;border-radius:3px}
.muted{color:#667}
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

fn svgs_under(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if name.starts_with('.') {
                continue;
            }
            if p.is_dir() {
                svgs_under(&p, out);
            } else if name.ends_with(".svg") {
                out.push(p);
            }
        }
    }
}

/// Renders the page. `artifact_dirs` are searched, in order, for each artifact path (the staging
/// directory of this run first, then the final reports directory for plots of earlier commands
/// such as `geodesic fit`).
pub fn render(rep: &Report, artifact_dirs: &[&Path]) -> String {
    let m = &rep.matrix;
    let find = |rel: &str| {
        artifact_dirs
            .iter()
            .map(|d| d.join(rel))
            .find(|p| p.exists())
    };
    let mut inlined: Vec<std::path::PathBuf> = Vec::new();
    let mut o = String::new();
    let _ = write!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>geodesic verification report</title>\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><style>{STYLE}</style></head><body>"
    );
    let s = &m.summary;
    let _ = write!(
        o,
        "<header><h1>geodesic verification report — LISA Pathfinder test-mass release</h1>\
         <div>{} · \
         <b>{} requirements: {} compliant, {} non-compliant, {} not verified</b></div></header><main>",
        run_meta(rep),
        s.total,
        s.compliant,
        s.non_compliant,
        s.not_verified
    );
    // matrix
    let _ = write!(
        o,
        "<h2 id=\"matrix\">Compliance matrix</h2><div class=\"filters\">\
         <button data-filter=\"all\">all</button><button data-filter=\"compliant\">compliant</button>\
         <button data-filter=\"non-compliant\">non-compliant</button><button data-filter=\"not-verified\">not-verified</button></div>\
         <table><thead><tr><th>ID</th><th>Title</th><th>Method</th><th>Status</th><th>Basis</th><th>Value</th><th>Limit</th><th>Margin</th><th>Evidence</th><th>Tests</th></tr></thead><tbody>"
    );
    let run = m.test_run.is_some();
    for r in &m.requirements {
        let st = r.status.as_str();
        let checks: Vec<String> = r
            .evidence
            .iter()
            .map(|e| format!("<code>{}</code>", esc(&e.check)))
            .collect();
        let _ = write!(
            o,
            "<tr data-status=\"{st}\" class=\"{st}\"><td><a href=\"#{id}\">{id}</a></td><td>{t}</td><td>{meth}</td>\
             <td><span class=\"badge\">{verdict}</span></td><td>{basis}</td><td>{v}</td><td>{lim}</td><td>{mg}</td><td>{ev}</td><td>{nt}</td></tr>",
            verdict = esc(&crate::verdict(r)),
            basis = crate::basis_word(r),
            id = esc(&r.id),
            t = esc(&r.title),
            meth = esc(&r.method),
            v = r.value.map_or("—".into(), |_| format!(
                "{} {}",
                fmt_opt(r.value),
                esc(&r.unit)
            )),
            lim = esc(&r.limit_text),
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
    // VCD
    let _ = write!(
        o,
        "<h2 id=\"vcd\">Verification Control Document</h2><table><thead><tr><th>ID</th><th>Parent</th><th>Children</th>\
         <th>Method</th><th>Evidence</th><th>Compliance</th><th>Close-out</th></tr></thead><tbody>"
    );
    for l in vcd::lines(rep) {
        let _ = write!(
            o,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"ev\">{}</td><td>{}</td><td>{}: {}</td></tr>",
            esc(&l.id),
            esc(&l.parent),
            esc(&l.children.replace(';', ", ")),
            esc(&l.method),
            esc(&l.evidence),
            l.compliance,
            l.close_out,
            esc(&l.reason)
        );
    }
    let _ = write!(o, "</tbody></table>");
    if !rep.run.fidelity.is_empty() {
        let _ = write!(
            o,
            "<h2 id=\"fidelity\">Fidelity against the thesis</h2><table><thead><tr><th>Figure</th><th>geodesic</th>\
             <th>Thesis</th><th>Difference</th><th>Assumptions</th></tr></thead><tbody>"
        );
        for f in &rep.run.fidelity {
            let _ = write!(
                o,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(&f.figure),
                esc(&f.value),
                esc(&f.reference),
                esc(&f.difference),
                esc(&f.note)
            );
        }
        let _ = write!(o, "</tbody></table>");
    }
    // sections
    let _ = write!(o, "<h2 id=\"requirements\">Requirements</h2>");
    for r in &m.requirements {
        let st = r.status.as_str();
        let _ = write!(
            o,
            "<section class=\"req\" id=\"{id}\"><h3>{id} — {t} <span class=\"badge {st}\">{st}</span></h3>\
             <blockquote>{text}</blockquote><ul><li>Source: {src}</li><li>Quantity: {q}</li>\
             <li>Limit: <code>{lim}</code>{prob}</li><li>Method: {meth} — activity: {act}</li>",
            id = esc(&r.id),
            t = esc(&r.title),
            text = esc(&r.text),
            src = esc(&r.source),
            q = esc(&r.quantity),
            lim = esc(&r.limit_text),
            prob = r
                .probability
                .as_ref()
                .map_or(String::new(), |p| format!(" at {}", esc(p))),
            meth = esc(&r.method),
            act = esc(&r.activity)
        );
        if let Some(p) = &r.parent {
            let _ = write!(
                o,
                "<li>Parent: <a href=\"#{p}\">{p}</a> (margin factor {})</li>",
                r.parent_margin.unwrap_or(1.0)
            );
        }
        if !r.children.is_empty() {
            let c: Vec<String> = r
                .children
                .iter()
                .map(|c| format!("<a href=\"#{c}\">{c}</a>"))
                .collect();
            let _ = write!(o, "<li>Children: {}</li>", c.join(", "));
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
                    "<li>Value {} {} — margin {}</li>",
                    fmt_opt(r.value),
                    esc(&r.unit),
                    fmt_margin(r.margin)
                );
            }
        }
        let _ = write!(o, "</ul>");
        for e in &r.evidence {
            let inputs: Vec<String> = e.inputs.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            let _ = write!(
                o,
                "<p><b>Evidence</b> <code>{}</code>: {} {}<br><span class=\"muted\">{}</span></p>",
                esc(&e.check),
                esc(&e.activity),
                e.value.map_or_else(
                    || e.reason
                        .as_ref()
                        .map_or(String::new(), |w| format!("— not verified: {}", esc(w))),
                    |v| format!("— {} {}", geodesic_core::units::fmt_num(v), esc(&r.unit))
                ),
                esc(&inputs.join(", "))
            );
            for a in &e.artifacts {
                if let Some(p) = find(a)
                    && a.ends_with(".svg")
                    && let Some(svg) = inline_svg(&p)
                {
                    let _ = write!(
                        o,
                        "<div class=\"plot\"><p class=\"muted\">{}</p>{svg}</div>",
                        esc(a)
                    );
                    inlined.push(p);
                }
            }
        }
        if !r.tests.is_empty() {
            let _ = write!(o, "<p><b>Tests</b></p><ul>");
            for t in &r.tests {
                let asserted: Vec<&str> = t.assertions.iter().map(|a| a.as_str()).collect();
                let _ = write!(
                    o,
                    "<li><code>{}</code> ({}, {}): <b>{}</b>, asserts {}</li>",
                    esc(&t.test),
                    esc(&t.kind),
                    esc(&t.location),
                    t.result.as_str(),
                    esc(&asserted.join(", "))
                );
            }
            let _ = write!(o, "</ul>");
        }
        let _ = write!(o, "</section>");
    }
    // trace views
    let _ = write!(
        o,
        "<h2 id=\"trace\">Trace views</h2><h3>Checks to requirements</h3><table><thead><tr><th>Check</th><th>Verifies</th><th>Wall time [s]</th></tr></thead><tbody>"
    );
    for c in &rep.run.checks {
        let _ = write!(
            o,
            "<tr><td><code>{}</code></td><td>{}</td><td>{:.2}</td></tr>",
            esc(&c.name),
            esc(&c.verifies.join(", ")),
            c.seconds
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
    // gallery of the other plots
    let mut others = Vec::new();
    if let Some(last) = artifact_dirs.last() {
        svgs_under(last, &mut others);
    }
    others.sort();
    others.retain(|p| !inlined.iter().any(|q| q.file_name() == p.file_name()));
    if !others.is_empty() {
        let _ = write!(
            o,
            "<h2 id=\"plots\">Other plots (fits, residuals with failure windows, error history)</h2>"
        );
        for p in others {
            if let Some(svg) = inline_svg(&p) {
                let rel = p.strip_prefix(artifact_dirs.last().unwrap()).unwrap_or(&p);
                let _ = write!(
                    o,
                    "<div class=\"plot\"><p class=\"muted\">{}</p>{svg}</div>",
                    esc(&rel.display().to_string())
                );
            }
        }
    }
    let _ = writeln!(o, "</main><script>{SCRIPT}</script></body></html>");
    o
}

/// The run's identification (commit, date, inputs and their hashes) as one line of HTML.
fn run_meta(rep: &Report) -> String {
    crate::run_lines(rep)
        .iter()
        .map(|(k, v)| format!("{k} <code>{}</code>", esc(v)))
        .collect::<Vec<_>>()
        .join(" · ")
}

/// The Verification Control Document alone, as a self-contained HTML page.
pub fn render_vcd(rep: &Report) -> String {
    let mut o = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>geodesic VCD</title><style>{STYLE}</style></head>\
         <body><header><h1>Verification Control Document</h1><div>{}</div></header><main><table><thead><tr><th>ID</th><th>Requirement</th><th>Parent</th>\
         <th>Children</th><th>Method</th><th>Activity</th><th>Evidence</th><th>Value</th><th>Limit</th><th>Margin</th>\
         <th>Compliance</th><th>Close-out</th></tr></thead><tbody>",
        run_meta(rep)
    );
    for (l, r) in vcd::lines(rep).iter().zip(&rep.matrix.requirements) {
        let _ = write!(
            o,
            "<tr class=\"{}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"ev\">{}</td><td>{}</td><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}: {}</td></tr>",
            r.status.as_str(),
            esc(&l.id),
            esc(&l.text),
            esc(&l.parent),
            esc(&l.children.replace(';', ", ")),
            esc(&l.method),
            esc(&l.activity),
            esc(&l.evidence),
            esc(&l.value),
            esc(&l.limit),
            esc(&l.margin),
            l.compliance,
            l.close_out,
            esc(&l.reason)
        );
    }
    o.push_str("</tbody></table></main></body></html>\n");
    o
}
