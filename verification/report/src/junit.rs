//! JUnit XML of the compliance checks, for CI dashboards: one test suite per requirement
//! family, one test case per requirement (non-compliant is a failure, not-verified is skipped
//! with its reason), and a suite `geodesic traced tests` with one test case per traced test of
//! the recorded test run, each naming the requirements it verifies in
//! `<property name="requirement" value="ID"/>` (the convention Polarion, StrictDoc and
//! sphinx-test-reports import): failed is a failure, ignored or not run is skipped.
//!
//! Written by hand rather than with `quick-junit`: the format used here is three elements with
//! escaped text, and the crate would add an XML writer and its dependencies to every build.

use crate::{Report, fmt_margin, fmt_opt};
use geodesic_core::matrix::Status;
use std::collections::BTreeMap;

/// Escapes text for XML attributes and content.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

/// Renders the JUnit XML document.
pub fn render(rep: &Report) -> String {
    let mut fam: BTreeMap<&str, Vec<&geodesic_core::matrix::Row>> = BTreeMap::new();
    for r in &rep.matrix.requirements {
        fam.entry(r.family.as_str()).or_default().push(r);
    }
    let s = &rep.matrix.summary;
    let mut o = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    o.push_str(&format!(
        "<testsuites name=\"geodesic compliance\" tests=\"{}\" failures=\"{}\" skipped=\"{}\">\n",
        s.total, s.non_compliant, s.not_verified
    ));
    for (f, rows) in fam {
        let fails = rows
            .iter()
            .filter(|r| r.status == Status::NonCompliant)
            .count();
        let skips = rows
            .iter()
            .filter(|r| r.status == Status::NotVerified)
            .count();
        o.push_str(&format!(
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{fails}\" skipped=\"{skips}\">\n",
            esc(f),
            rows.len()
        ));
        for r in rows {
            let checks: Vec<&str> = r.evidence.iter().map(|e| e.check.as_str()).collect();
            o.push_str(&format!(
                "    <testcase classname=\"geodesic.{}\" name=\"{} {}\">\n",
                esc(f),
                esc(&r.id),
                esc(&r.title)
            ));
            o.push_str(&format!(
                "      <properties><property name=\"requirement\" value=\"{}\"/><property name=\"basis\" value=\"{}\"/><property name=\"method\" value=\"{}\"/></properties>\n",
                esc(&r.id),
                crate::basis_word(r),
                esc(&r.method)
            ));
            let detail = format!(
                "value {} {} against `{}`, margin {}; evidence: {}",
                fmt_opt(r.value),
                r.unit,
                r.limit_text,
                fmt_margin(r.margin),
                if checks.is_empty() {
                    "none".to_string()
                } else {
                    checks.join(", ")
                }
            );
            match r.status {
                Status::Compliant => o.push_str(&format!(
                    "      <system-out>{}</system-out>\n",
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
