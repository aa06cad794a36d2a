//! JUnit XML of the compliance checks, for CI dashboards: one test suite per requirement
//! family, one test case per requirement (non-compliant is a failure, not-verified is skipped
//! with its reason, and a compliant verdict that is not a plain model or measurement verdict
//! with no finding (a flow-down, an accepted value, a method validation, an assumed row not
//! verified, a rejected model input, a test problem) is skipped with its verdict: never a plain
//! pass), each with its verdict, basis, findings and sample as properties, and a suite `geodesic traced tests` with one test case per traced test of
//! the recorded test run, each naming the requirements it verifies in
//! `<property name="requirement" value="ID"/>` (the convention Polarion, StrictDoc and
//! sphinx-test-reports import): failed is a failure, ignored or not run is skipped.
//!
//! Written by hand rather than with `quick-junit`: the format used here is three elements with
//! escaped text, and the crate would add an XML writer and its dependencies to every build.

use crate::{Report, fmt_limit, fmt_margin, fmt_value};
use geodesic_core::matrix::Status;
use std::collections::BTreeMap;

/// Escapes text for XML attributes and content (`&`, `<`, `>`, `"`, `'`): geodesic's one
/// escaping, [`geodesic_util::escape::markup`].
pub use geodesic_util::escape::markup as esc;

/// The run's identification as JUnit properties (every test suite carries them): document,
/// issue, title and project, tool version, commit and dirty flag, date, command line and the
/// SHA-256 of the requirement set and of each input file.
fn run_properties(rep: &Report) -> String {
    let r = &rep.run;
    let mut p: Vec<(&str, String)> = vec![
        ("document", r.document.id.clone()),
        ("issue", r.document.issue.clone()),
        ("title", r.document.title.clone()),
        ("project", r.document.project.clone()),
        ("tool_version", r.tool_version.clone()),
        ("commit", r.commit.clone()),
        ("dirty", r.dirty.to_string()),
        ("date", r.date.clone()),
        ("command", r.command.clone()),
        ("requirements", r.requirements.clone()),
        ("requirements_sha256", r.requirements_hash.clone()),
    ];
    let inputs: Vec<(String, String, String)> = r
        .inputs
        .iter()
        .map(|(n, _, f)| (n.to_string(), format!("{n}_sha256"), f.label.clone()))
        .collect();
    for ((n, nsha, label), (_, _, f)) in inputs.iter().zip(r.inputs.iter()) {
        p.push((n.as_str(), label.clone()));
        p.push((nsha.as_str(), f.sha256.clone()));
    }
    p.extend([
        ("confidence", r.confidence.to_string()),
        ("summary", rep.matrix.summary.line()),
        (
            "plainly_compliant",
            rep.matrix.summary.plainly_compliant.to_string(),
        ),
        (
            "compliant_with_findings",
            rep.matrix.summary.compliant_with_findings.to_string(),
        ),
        ("test_results", rep.matrix.summary.tests.clone()),
    ]);
    let by_basis: Vec<(String, String)> = rep
        .matrix
        .summary
        .compliant_by_basis
        .iter()
        .map(|(b, n)| (format!("compliant_{}", b.replace('-', "_")), n.to_string()))
        .collect();
    p.extend(by_basis.iter().map(|(k, v)| (k.as_str(), v.clone())));
    if let Some(d) = &r.dispositions {
        p.push(("dispositions", d.label.clone()));
        p.push(("dispositions_sha256", d.sha256.clone()));
    }
    let mut o = String::from("    <properties>\n");
    for (k, v) in p {
        o.push_str(&format!(
            "      <property name=\"{k}\" value=\"{}\"/>\n",
            esc(&v)
        ));
    }
    o.push_str("    </properties>\n");
    o
}

/// Renders the JUnit XML document.
pub fn render(rep: &Report) -> String {
    let mut fam: BTreeMap<&str, Vec<&geodesic_core::matrix::Row>> = BTreeMap::new();
    for r in &rep.matrix.requirements {
        fam.entry(r.family.as_str()).or_default().push(r);
    }
    let s = &rep.matrix.summary;
    let qualified = rep
        .matrix
        .requirements
        .iter()
        .filter(|r| r.status == Status::Compliant && !r.plainly_compliant())
        .count();
    let mut o = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    o.push_str(&format!(
        "<testsuites name=\"geodesic compliance\" tests=\"{}\" failures=\"{}\" skipped=\"{}\">\n",
        s.total,
        s.non_compliant,
        s.not_verified + qualified
    ));
    for (f, rows) in fam {
        let fails = rows
            .iter()
            .filter(|r| r.status == Status::NonCompliant)
            .count();
        let skips = rows
            .iter()
            .filter(|r| {
                r.status == Status::NotVerified
                    || (r.status == Status::Compliant && !r.plainly_compliant())
            })
            .count();
        o.push_str(&format!(
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{fails}\" skipped=\"{skips}\">\n",
            esc(f),
            rows.len()
        ));
        o.push_str(&run_properties(rep));
        for r in rows {
            let mut checks: Vec<&str> = r.evidence.iter().map(|e| e.check.as_str()).collect();
            checks.dedup();
            o.push_str(&format!(
                "    <testcase classname=\"geodesic.{}\" name=\"{} {}\">\n",
                esc(f),
                esc(&r.id),
                esc(&r.title)
            ));
            o.push_str(&format!(
                "      <properties><property name=\"requirement\" value=\"{}\"/><property name=\"basis\" value=\"{}\"/><property name=\"verdict\" value=\"{}\"/><property name=\"method\" value=\"{}\"/><property name=\"level\" value=\"{}\"/><property name=\"stage\" value=\"{}\"/><property name=\"compliance\" value=\"{}\"/>",
                esc(&r.id),
                crate::basis_word(r),
                esc(&r.verdict),
                esc(&r.method),
                esc(&r.level),
                esc(&r.stage),
                esc(&crate::vcd::compliance(r))
            ));
            if let Some(p) = &r.probability {
                o.push_str(&format!(
                    "<property name=\"probability\" value=\"{}\"/>",
                    esc(p)
                ));
            }
            if let (Some(sm), Some(text)) = (&r.sampling, crate::sampling_text(r)) {
                o.push_str(&format!(
                    "<property name=\"sample_n\" value=\"{}\"/><property name=\"confidence\" value=\"{}\"/><property name=\"sample\" value=\"{}\"/>",
                    sm.n,
                    sm.confidence,
                    esc(&text)
                ));
            }
            for f in &r.findings {
                o.push_str(&format!(
                    "<property name=\"finding\" value=\"{}\"/>",
                    esc(f)
                ));
            }
            if let Some(c) = &r.credibility {
                o.push_str(&format!(
                    "<property name=\"credibility\" value=\"{}\"/><property name=\"credibility_weakest\" value=\"{}\"/>",
                    c.level,
                    esc(&c.weakest)
                ));
                if let Some(n) = c.required {
                    o.push_str(&format!(
                        "<property name=\"credibility_required\" value=\"{n}\"/>"
                    ));
                }
                for (n, f) in c.factors() {
                    o.push_str(&format!(
                        "<property name=\"credibility_{}\" value=\"{}: {}\"/>",
                        n.replace(' ', "_"),
                        f.level,
                        esc(&f.why)
                    ));
                }
            }
            o.push_str("</properties>\n");
            let detail = format!(
                "value {} against {}, margin {}; evidence: {}",
                fmt_value(r),
                fmt_limit(r),
                fmt_margin(r.margin),
                if checks.is_empty() {
                    "none".to_string()
                } else {
                    checks.join(", ")
                }
            );
            match r.status {
                Status::Compliant if r.plainly_compliant() => o.push_str(&format!(
                    "      <system-out>{}</system-out>\n",
                    esc(&detail)
                )),
                Status::Compliant => o.push_str(&format!(
                    "      <skipped message=\"{}\"/>\n      <system-out>{}</system-out>\n",
                    esc(&format!(
                        "{}: not a plain model verdict ({})",
                        r.verdict,
                        if r.findings.is_empty() {
                            format!("basis {}", crate::basis_word(r))
                        } else {
                            r.findings.join("; ")
                        }
                    )),
                    esc(&detail)
                )),
                Status::NonCompliant => o.push_str(&format!(
                    "      <failure message=\"{}\" type=\"non-compliant\">{}</failure>\n",
                    esc(&format!("{} non-compliant", r.id)),
                    esc(&detail)
                )),
                Status::NotVerified => o.push_str(&format!(
                    "      <skipped message=\"{}\"/>\n",
                    esc(&format!(
                        "not verified: {}",
                        r.reason.as_deref().unwrap_or("no evidence")
                    ))
                )),
            }
            o.push_str("    </testcase>\n");
        }
        o.push_str("  </testsuite>\n");
    }
    traced_suite(rep, &mut o);
    o.push_str("</testsuites>\n");
    o
}

/// The suite of traced tests: one test case per test of the recorded run, with its requirements.
fn traced_suite(rep: &Report, o: &mut String) {
    use geodesic_core::testrun::TestResult;
    let mut tests: BTreeMap<&str, (&geodesic_core::matrix::TestRef, Vec<&str>)> = BTreeMap::new();
    for r in &rep.matrix.requirements {
        for t in &r.tests {
            tests
                .entry(t.test.as_str())
                .or_insert_with(|| (t, Vec::new()))
                .1
                .push(r.id.as_str());
        }
    }
    let fails = tests
        .values()
        .filter(|(t, _)| t.result == TestResult::Failed)
        .count();
    let skips = tests
        .values()
        .filter(|(t, _)| matches!(t.result, TestResult::Ignored | TestResult::NotRun))
        .count();
    o.push_str(&format!(
        "  <testsuite name=\"geodesic traced tests\" tests=\"{}\" failures=\"{fails}\" skipped=\"{skips}\">\n",
        tests.len()
    ));
    o.push_str(&run_properties(rep));
    for (name, (t, ids)) in &tests {
        let (class, short) = name.rsplit_once("::").unwrap_or(("", name));
        o.push_str(&format!(
            "    <testcase classname=\"{}\" name=\"{}\" file=\"{}\">\n      <properties>",
            esc(class),
            esc(short),
            esc(t.location.split(':').next().unwrap_or(""))
        ));
        for id in ids {
            o.push_str(&format!(
                "<property name=\"requirement\" value=\"{}\"/>",
                esc(id)
            ));
        }
        o.push_str(&format!(
            "<property name=\"kind\" value=\"{}\"/></properties>\n",
            esc(&t.kind)
        ));
        match t.result {
            TestResult::Failed => {
                o.push_str("      <failure message=\"failed in the recorded test run\"/>\n")
            }
            TestResult::Ignored => {
                o.push_str("      <skipped message=\"ignored in the recorded test run\"/>\n")
            }
            TestResult::NotRun => {
                o.push_str("      <skipped message=\"did not run in the recorded test run\"/>\n")
            }
            TestResult::Passed => {}
        }
        o.push_str("    </testcase>\n");
    }
    o.push_str("  </testsuite>\n");
}
