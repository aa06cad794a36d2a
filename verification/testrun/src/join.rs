//! Joins the three sources of a recorded run: what libtest printed (results), what the
//! `verifies!` calls recorded while running (requirements, cases, assertions) and what the
//! sources declare (traces that did not run).

use crate::output::Listed;
use crate::scan::Declared;
use geodesic_core::testrun::{Assertion, RecordedTest, TestResult, TraceRecord};
use std::collections::{BTreeMap, BTreeSet};

/// The recorded tests, sorted by crate and name, and warnings about the traces.
pub fn join(
    listed: &[Listed],
    records: &[TraceRecord],
    declared: &[Declared],
) -> (Vec<RecordedTest>, Vec<String>) {
    let mut warnings = Vec::new();
    let result_of = |krate: &str, test: &str| {
        listed
            .iter()
            .rev()
            .find(|l| l.krate == krate && l.test == test)
            .map(|l| l.result)
    };
    let mut tests = Vec::new();
    let mut executed: BTreeSet<&str> = BTreeSet::new();
    for rec in records {
        if rec.calls.is_empty() {
            if !rec.asserted.is_empty() {
                warnings.push(format!(
                    "{}: asserts {} without a verifies! call: not recorded",
                    rec.test, rec.asserted[0].requirement
                ));
            }
            continue;
        }
        let krate = if rec.krate.is_empty() {
            crate::output::crate_of_binary(&rec.binary)
        } else {
            rec.krate.clone()
        };
        let mut requirements: Vec<String> = Vec::new();
        for c in &rec.calls {
            executed.insert(c.location.as_str());
            for r in &c.requirements {
                if !requirements.contains(r) {
                    requirements.push(r.clone());
                }
            }
        }
        let mut asserted: BTreeMap<String, Vec<Assertion>> = BTreeMap::new();
        for a in &rec.asserted {
            if !requirements.contains(&a.requirement) {
                warnings.push(format!(
                    "{krate}::{}: asserts {} but does not declare it in verifies!",
                    rec.test, a.requirement
                ));
            }
            let v = asserted.entry(a.requirement.clone()).or_default();
            if !v.contains(&a.assertion) {
                v.push(a.assertion);
                v.sort();
            }
        }
        let mut assertions: Vec<Assertion> = asserted.values().flatten().copied().collect();
        assertions.sort();
        assertions.dedup();
        if assertions.is_empty() {
            assertions.push(Assertion::ChangeDetection);
        }
        let cases = rec.calls.iter().map(|c| c.count).max().unwrap_or(0);
        let location = rec
            .calls
            .iter()
            .map(|c| c.location.as_str())
            .collect::<Vec<_>>()
            .join(", ");
        let snapshot = rec.calls.iter().any(|c| {
            declared
                .iter()
                .any(|d| d.location == c.location && d.snapshot)
        });
        let kind = if cases > 1 {
            "proptest"
        } else if snapshot {
            "snapshot"
        } else {
            "unit"
        };
        // The verifies! call ran; a test that has no result line crashed its binary.
        let result = result_of(&krate, &rec.test).unwrap_or(TestResult::Failed);
        tests.push(RecordedTest {
            krate,
            test: rec.test.clone(),
            result,
            location,
            requirements,
            cases,
            assertions,
            kind: kind.to_string(),
            asserted,
            rejected: BTreeMap::new(),
            source_asserts_limit: BTreeSet::new(),
        });
    }
    for d in declared {
        if executed.contains(d.location.as_str()) {
            continue;
        }
        if !d.is_test {
            warnings.push(format!(
                "{}: verifies! in `{}`, which is not a test: it traces nothing",
                d.location, d.function
            ));
        }
        let ignored = |l: &&Listed| l.result == TestResult::Ignored;
        let exact = listed
            .iter()
            .filter(ignored)
            .any(|l| l.krate == d.krate && l.test == d.test);
        let by_function = |same_crate: bool| {
            listed.iter().filter(ignored).any(|l| {
                (!same_crate || l.krate == d.krate)
                    && l.test.rsplit("::").next() == Some(d.function.as_str())
            })
        };
        let result = if d.is_test && (exact || by_function(true) || by_function(false)) {
            TestResult::Ignored
        } else {
            TestResult::NotRun
        };
        let kind = if d.in_proptest {
            "proptest"
        } else if d.snapshot {
            "snapshot"
        } else {
            "unit"
        };
        tests.push(RecordedTest {
            krate: d.krate.clone(),
            test: d.test.clone(),
            result,
            location: d.location.clone(),
            requirements: d.requirements.clone(),
            cases: 0,
            assertions: vec![Assertion::ChangeDetection],
            kind: kind.to_string(),
            asserted: BTreeMap::new(),
            rejected: BTreeMap::new(),
            source_asserts_limit: BTreeSet::new(),
        });
    }
    tests.sort_by(|a, b| (&a.krate, &a.test, &a.location).cmp(&(&b.krate, &b.test, &b.location)));
    (tests, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::parse;
    use crate::scan::scan_text;
    use geodesic_core::testrun::{TraceAssertion, TraceCall};
    use std::path::Path;

    /// A test file with a proptest, an ignored always-failing test, a dead function, a commented
    /// call, a failing test and a snapshot.
    const SOURCE: &str = r#"
proptest! {
    #[test]
    fn prop(x in 0.0f64..1.0) {
        geodesic_core::verifies!("CAP-QUARTIC");
    }
}

#[test]
#[ignore]
fn ignored_one() {
    geodesic_core::verifies!("CHG-Q");
    panic!();
}

#[allow(dead_code)]
fn dead() {
    geodesic_core::verifies!("TMS-Z-POS");
}

/* geodesic_core::verifies!("TMS-X-POS"); */

#[test]
fn fails_late() {
    geodesic_core::verifies!("REL-GPRM-VEL");
    geodesic_core::trace::assert_limit("REL-GPRM-VEL", 1e-6);
    panic!("later");
}

#[test]
fn snap() {
    geodesic_core::verifies!("REL-DFACS-VEL", "TMS-Z-VEL");
    geodesic_core::trace::assert_reference("REL-DFACS-VEL", "x", 1.0, 1.0, 0.0);
    insta::assert_json_snapshot!(1);
}
"#;

    const OUTPUT: &str = "
     Running tests/verification/main.rs (target/debug/deps/verification-0123456789abcdef)

running 4 tests
test capture::ignored_one ... ignored
test capture::snap ... ok
test capture::fails_late ... FAILED
test capture::prop ... ok
";

    fn record(test: &str, line: u32, reqs: &[&str], count: u64) -> TraceRecord {
        TraceRecord {
            krate: "verification".into(),
            test: test.into(),
            binary: "verification-0123456789abcdef".into(),
            calls: vec![TraceCall {
                location: format!("verification/checks/tests/verification/capture.rs:{line}"),
                requirements: reqs.iter().map(|s| s.to_string()).collect(),
                count,
            }],
            asserted: Vec::new(),
        }
    }

    #[test]
    fn ignored_dead_commented_proptest_failing_snapshot() {
        let declared = scan_text(
            SOURCE,
            "geodesic-checks",
            Path::new("tests/verification/capture.rs"),
            "verification/checks/tests/verification/capture.rs",
        );
        assert_eq!(declared.len(), 5, "{declared:#?}");
        let mut fails = record("capture::fails_late", 25, &["REL-GPRM-VEL"], 1);
        fails.asserted.push(TraceAssertion {
            requirement: "REL-GPRM-VEL".into(),
            assertion: Assertion::Limit,
        });
        let mut snap = record("capture::snap", 32, &["REL-DFACS-VEL", "TMS-Z-VEL"], 1);
        snap.asserted.push(TraceAssertion {
            requirement: "REL-DFACS-VEL".into(),
            assertion: Assertion::Reference,
        });
        let records = vec![
            record("capture::prop", 5, &["CAP-QUARTIC"], 256),
            fails,
            snap,
        ];
        let (tests, warnings) = join(&parse(OUTPUT), &records, &declared);
        let brief: Vec<(&str, TestResult, &str, u64, Vec<Assertion>)> = tests
            .iter()
            .map(|t| {
                (
                    t.test.as_str(),
                    t.result,
                    t.kind.as_str(),
                    t.cases,
                    t.assertions.clone(),
                )
            })
            .collect();
        use Assertion::*;
        use TestResult::*;
        assert_eq!(
            brief,
            vec![
                ("capture::dead", NotRun, "unit", 0, vec![ChangeDetection]),
                ("capture::fails_late", Failed, "unit", 1, vec![Limit]),
                (
                    "capture::ignored_one",
                    Ignored,
                    "unit",
                    0,
                    vec![ChangeDetection]
                ),
                (
                    "capture::prop",
                    Passed,
                    "proptest",
                    256,
                    vec![ChangeDetection]
                ),
                ("capture::snap", Passed, "snapshot", 1, vec![Reference]),
            ]
        );
        let snap = &tests[4];
        assert_eq!(snap.assertions_for("REL-DFACS-VEL"), vec![Reference]);
        assert_eq!(snap.assertions_for("TMS-Z-VEL"), vec![ChangeDetection]);
        assert_eq!(tests[1].requirements, vec!["REL-GPRM-VEL"]);
        assert_eq!(tests[2].requirements, vec!["CHG-Q"]);
        assert!(
            tests
                .iter()
                .all(|t| t.krate == "verification" && !t.requirements.contains(&"TMS-X-POS".into()))
        );
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("`dead`, which is not a test"));
    }

    #[test]
    fn a_test_that_ran_without_a_result_line_failed() {
        let records = vec![record("capture::prop", 5, &["CAP-QUARTIC"], 3)];
        let (tests, _) = join(&[], &records, &[]);
        assert_eq!(tests[0].result, TestResult::Failed);
        assert_eq!(tests[0].kind, "proptest");
    }
}
