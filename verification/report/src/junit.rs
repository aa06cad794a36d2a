//! JUnit XML of the compliance checks, for CI dashboards: one test suite per requirement
//! family, one test case per requirement, and a suite `geodesic traced tests` with one test
//! case per traced test of the recorded test run.
//!
//! The file is valid against the Jenkins xUnit plugin's `junit-10.xsd` (CI takes the copy
//! pytest's source distribution ships, `.ci/clients.sh`) and is the JUnit 5 "legacy" format
//! GitLab, Jenkins' JUnit plugin, `junitparser` and `xunitparser` read:
//!
//! * A requirement's test case is named `ID title`; non-compliant is a failure, not verified is
//!   skipped with its reason, compliant is a pass. A compliant verdict that is not a plain model
//!   or measurement verdict (with a finding, a flow-down, an accepted value, an assumption...)
//!   is a pass whose `system-out` starts with `compliant with findings: ...`: a dashboard
//!   counts it with the passes, never with the not verified (skipped).
//! * What a case carries (requirement, verdict, basis, method, level, stage, compliance,
//!   sample, findings, value against limit and margin) is in its `system-out`, one `key: value`
//!   a line: `junit-10.xsd` allows no `<properties>` inside `<testcase>`. A traced test's case
//!   names each requirement it verifies on a `requirement: ID` line.
//! * The run's identification and summary counts are `<properties>` of the first suite only:
//!   `xunitparser` merges the properties of every suite and refuses a name given twice.
//! * Every suite has `errors` (0: a check that could not run is not verified, skipped);
//!   `<testsuites>` has `tests`, `failures` and `errors` (the sums), no `skipped`.
//!
//! Written by hand rather than with `quick-junit`: the format used here is a few elements with
//! escaped text, and the crate would add an XML writer and its dependencies to every build.

use crate::{Report, fmt_limit, fmt_margin, fmt_value};
use geodesic_core::matrix::Status;
use std::collections::BTreeMap;

/// Escapes text for XML attributes and content (`&`, `<`, `>`, `"`, `'`): geodesic's one
/// escaping, [`geodesic_util::escape::markup`].
pub use geodesic_util::escape::markup as esc;

/// The run's identification as JUnit properties (the first test suite carries them): document,
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

/// The `system-out` lines of requirement `r`: what it is, how it was judged and its value.
fn requirement_lines(r: &geodesic_core::matrix::Row) -> Vec<String> {
    let mut checks: Vec<&str> = r.evidence.iter().map(|e| e.check.as_str()).collect();
    checks.dedup();
    let mut lines = Vec::new();
    if r.status == Status::Compliant && !r.plainly_compliant() {
        lines.push(format!(
            "compliant with findings: {}",
            if r.findings.is_empty() {
                format!("{} (basis {})", r.verdict, crate::basis_word(r))
            } else {
                format!("{} ({})", r.verdict, r.findings.join("; "))
            }
        ));
    }
    lines.extend([
        format!("requirement: {}", r.id),
        format!("verdict: {}", r.verdict),
        format!("basis: {}", crate::basis_word(r)),
        format!("method: {}", r.method),
        format!("level: {}", r.level),
        format!("stage: {}", r.stage),
        format!("compliance: {}", crate::vcd::compliance(r)),
    ]);
    if let Some(p) = &r.probability {
        lines.push(format!("probability: {p}"));
    }
    if let (Some(sm), Some(text)) = (&r.sampling, crate::sampling_text(r)) {
        lines.push(format!("sample_n: {}", sm.n));
        lines.push(format!("confidence: {}", sm.confidence));
        lines.push(format!("sample: {text}"));
    }
    lines.extend(r.findings.iter().map(|f| format!("finding: {f}")));
    if let Some(c) = &r.credibility {
        lines.push(format!("credibility: {}", c.level));
        lines.push(format!("credibility_weakest: {}", c.weakest));
        if let Some(n) = c.required {
            lines.push(format!("credibility_required: {n}"));
        }
        for (n, f) in c.factors() {
            lines.push(format!(
                "credibility_{}: {}: {}",
                n.replace(' ', "_"),
                f.level,
                f.why
            ));
        }
    }
    lines.push(format!(
        "value {} against {}, margin {}; evidence: {}",
        fmt_value(r),
        fmt_limit(r),
        fmt_margin(r.margin),
        if checks.is_empty() {
            "none".to_string()
        } else {
            checks.join(", ")
        }
    ));
    lines
}

/// `<system-out>` of `lines`, one a line, escaped.
fn system_out(lines: &[String]) -> String {
    format!(
        "      <system-out>{}</system-out>\n",
        esc(&lines.join("\n"))
    )
}

/// Renders the JUnit XML document.
pub fn render(rep: &Report) -> String {
    let mut fam: BTreeMap<&str, Vec<&geodesic_core::matrix::Row>> = BTreeMap::new();
    for r in &rep.matrix.requirements {
        fam.entry(r.family.as_str()).or_default().push(r);
    }
    let s = &rep.matrix.summary;
    let traced = traced_tests(rep);
    let traced_failures = traced
        .values()
        .filter(|(t, _)| t.result == geodesic_core::testrun::TestResult::Failed)
        .count();
    let mut o = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    o.push_str(&format!(
        "<testsuites name=\"geodesic compliance\" tests=\"{}\" failures=\"{}\" errors=\"0\">\n",
        s.total + traced.len(),
        s.non_compliant + traced_failures
    ));
    // the run's properties, on the first suite only
    let mut props = Some(run_properties(rep));
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
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{fails}\" errors=\"0\" skipped=\"{skips}\">\n",
            esc(f),
            rows.len()
        ));
        o.push_str(&props.take().unwrap_or_default());
        for r in rows {
            o.push_str(&format!(
                "    <testcase classname=\"geodesic.{}\" name=\"{} {}\">\n",
                esc(f),
                esc(&r.id),
                esc(&r.title)
            ));
            match r.status {
                Status::Compliant => {}
                Status::NonCompliant => o.push_str(&format!(
                    "      <failure message=\"{}\" type=\"non-compliant\">{}</failure>\n",
                    esc(&format!("{} non-compliant", r.id)),
                    esc(&format!(
                        "value {} against {}, margin {}",
                        fmt_value(r),
                        fmt_limit(r),
                        fmt_margin(r.margin)
                    ))
                )),
                Status::NotVerified => o.push_str(&format!(
                    "      <skipped message=\"{}\" type=\"not-verified\"/>\n",
                    esc(&format!(
                        "not verified: {}",
                        r.reason.as_deref().unwrap_or("no evidence")
                    ))
                )),
            }
            o.push_str(&system_out(&requirement_lines(r)));
            o.push_str("    </testcase>\n");
        }
        o.push_str("  </testsuite>\n");
    }
    traced_suite(&traced, props, &mut o);
    o.push_str("</testsuites>\n");
    o
}

/// A traced test and the requirements it verifies.
type Traced<'a> = BTreeMap<&'a str, (&'a geodesic_core::matrix::TestRef, Vec<&'a str>)>;

/// The traced tests of the recorded run, by name, with the requirements each verifies.
fn traced_tests(rep: &Report) -> Traced<'_> {
    let mut tests: Traced<'_> = BTreeMap::new();
    for r in &rep.matrix.requirements {
        for t in &r.tests {
            tests
                .entry(t.test.as_str())
                .or_insert_with(|| (t, Vec::new()))
                .1
                .push(r.id.as_str());
        }
    }
    tests
}

/// The suite of traced tests: one test case per test of the recorded run, with its
/// requirements (and the run's properties when no suite came before).
fn traced_suite(tests: &Traced<'_>, props: Option<String>, o: &mut String) {
    use geodesic_core::testrun::TestResult;
    let fails = tests
        .values()
        .filter(|(t, _)| t.result == TestResult::Failed)
        .count();
    let skips = tests
        .values()
        .filter(|(t, _)| matches!(t.result, TestResult::Ignored | TestResult::NotRun))
        .count();
    o.push_str(&format!(
        "  <testsuite name=\"geodesic traced tests\" tests=\"{}\" failures=\"{fails}\" errors=\"0\" skipped=\"{skips}\">\n",
        tests.len()
    ));
    o.push_str(&props.unwrap_or_default());
    for (name, (t, ids)) in tests {
        let (class, short) = name.rsplit_once("::").unwrap_or(("", name));
        o.push_str(&format!(
            "    <testcase classname=\"{}\" name=\"{}\">\n",
            esc(class),
            esc(short)
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
        let mut lines: Vec<String> = ids.iter().map(|id| format!("requirement: {id}")).collect();
        lines.push(format!("kind: {}", t.kind));
        lines.push(format!(
            "file: {}",
            t.location.split(':').next().unwrap_or("")
        ));
        o.push_str(&system_out(&lines));
        o.push_str("    </testcase>\n");
    }
    o.push_str("  </testsuite>\n");
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesic_core::matrix::TestRef;
    use geodesic_core::testrun::TestResult;
    use std::collections::BTreeSet;

    /// The rules of `junit-10.xsd` (Jenkins xUnit plugin) this writer can break: the elements
    /// and attributes each element may have, the required attributes; and `xunitparser`'s: no
    /// property name twice in the file.
    fn check_junit_10(xml: &str) {
        let doc = roxmltree::Document::parse(xml).unwrap();
        let allowed = |tag: &str| -> (&[&str], &[&str], &[&str]) {
            match tag {
                "testsuites" => (
                    &["name", "time", "tests", "failures", "errors"],
                    &[],
                    &["testsuite"],
                ),
                "testsuite" => (
                    &[
                        "name",
                        "tests",
                        "failures",
                        "errors",
                        "group",
                        "time",
                        "skipped",
                        "timestamp",
                        "hostname",
                        "id",
                        "package",
                        "file",
                        "log",
                        "url",
                    ],
                    &["name", "tests", "failures", "errors"],
                    &[
                        "testsuite",
                        "properties",
                        "testcase",
                        "system-out",
                        "system-err",
                    ],
                ),
                "testcase" => (
                    &["name", "time", "classname", "group"],
                    &["name"],
                    &["skipped", "error", "failure", "system-out", "system-err"],
                ),
                "properties" => (&[], &[], &["property"]),
                "property" => (&["name", "value"], &["name", "value"], &[]),
                "failure" | "error" | "skipped" => (&["type", "message"], &[], &[]),
                "system-out" | "system-err" => (&[], &[], &[]),
                other => panic!("element <{other}> is not in junit-10.xsd"),
            }
        };
        let mut names = BTreeSet::new();
        for n in doc.descendants().filter(|n| n.is_element()) {
            let tag = n.tag_name().name();
            let (attrs, required, children) = allowed(tag);
            for a in n.attributes() {
                assert!(attrs.contains(&a.name()), "<{tag} {}=...>", a.name());
            }
            for r in required {
                assert!(n.has_attribute(*r), "<{tag}> lacks {r}");
            }
            for c in n.children().filter(|c| c.is_element()) {
                let ct = c.tag_name().name();
                assert!(children.contains(&ct), "<{ct}> inside <{tag}>");
            }
            if tag == "property" {
                let name = n.attribute("name").unwrap();
                assert!(names.insert(name.to_string()), "property {name} twice");
            }
            if tag == "testsuite" {
                let cases: Vec<_> = n
                    .children()
                    .filter(|c| c.has_tag_name("testcase"))
                    .collect();
                let count = |child: &str| {
                    cases
                        .iter()
                        .filter(|c| c.children().any(|x| x.has_tag_name(child)))
                        .count()
                        .to_string()
                };
                assert_eq!(n.attribute("tests"), Some(cases.len().to_string().as_str()));
                assert_eq!(n.attribute("failures"), Some(count("failure").as_str()));
                assert_eq!(n.attribute("skipped"), Some(count("skipped").as_str()));
                assert_eq!(n.attribute("errors"), Some("0"));
            }
        }
        let root = doc.root_element();
        let all = doc
            .descendants()
            .filter(|n| n.has_tag_name("testcase"))
            .count();
        assert_eq!(root.attribute("tests"), Some(all.to_string().as_str()));
    }

    #[test]
    fn the_file_follows_junit_10_and_tells_findings_from_not_verified() {
        let mut r = crate::testutil::report(1.3, 6.0);
        let t = |name: &str, result| TestRef {
            test: format!("geodesic_x::tests::{name}"),
            kind: "unit".into(),
            location: "x/src/lib.rs:10".into(),
            result,
            assertions: vec![],
            cases: 1,
            rejected: None,
            source_asserts_limit: false,
        };
        {
            let a = &mut r.matrix.requirements[0];
            a.basis = Some(geodesic_core::Basis::FlowDown);
            a.findings = vec!["takes F-B as met".into()];
            a.tests = vec![t("both", TestResult::Passed), t("gone", TestResult::NotRun)];
        }
        {
            let b = &mut r.matrix.requirements[1];
            b.status = Status::NotVerified;
            b.reason = Some("no evidence yet".into());
            b.tests = vec![t("both", TestResult::Passed)];
        }
        let xml = render(&r);
        check_junit_10(&xml);
        let doc = roxmltree::Document::parse(&xml).unwrap();
        let case = |name: &str| {
            doc.descendants()
                .find(|n| n.has_tag_name("testcase") && n.attribute("name") == Some(name))
                .unwrap_or_else(|| panic!("no case {name}: {xml}"))
        };
        let out = |n: roxmltree::Node| {
            n.children()
                .find(|c| c.has_tag_name("system-out"))
                .and_then(|c| c.text())
                .unwrap_or("")
                .to_string()
        };
        // compliant with findings: a pass that says so; not verified: skipped
        let a = case("F-A a");
        assert!(!a.children().any(|c| c.has_tag_name("skipped")));
        assert!(out(a).starts_with("compliant with findings:"), "{}", out(a));
        assert!(out(a).contains("requirement: F-A\n"));
        let b = case("F-B b");
        let skipped = b.children().find(|c| c.has_tag_name("skipped")).unwrap();
        assert_eq!(skipped.attribute("type"), Some("not-verified"));
        assert!(
            skipped
                .attribute("message")
                .unwrap()
                .contains("no evidence yet")
        );
        // a traced test names each requirement it verifies
        let both = out(case("both"));
        assert!(
            both.contains("requirement: F-A\nrequirement: F-B\n"),
            "{both}"
        );
        // the run's properties once
        assert_eq!(xml.matches("<property name=\"document\"").count(), 1);
    }
}
