//! Reads `cargo test`'s human output: which test binary is running (`Running ... (path)`,
//! `Doc-tests NAME`) and the result of each test (`test NAME ... ok|FAILED|ignored`).

use geodesic_core::testrun::TestResult;

/// One test result as libtest printed it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Listed {
    /// Crate of the test binary (`geodesic_checks`, `verification`).
    pub krate: String,
    /// Test name (`hinge::tests::torque`), without libtest's ` - should panic` mode.
    pub test: String,
    /// `passed`, `failed` or `ignored`.
    pub result: TestResult,
}

/// Removes ANSI escape sequences (`ESC [ ... letter`) and carriage returns.
pub(crate) fn strip_ansi(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\u{1b}' => {
                if chars.peek() == Some(&'[') {
                    chars.next();
                    for c in chars.by_ref() {
                        if c.is_ascii_alphabetic() {
                            break;
                        }
                    }
                }
            }
            '\r' => {}
            c => out.push(c),
        }
    }
    out
}

/// The crate of a test binary from its path: `target/debug/deps/geodesic_checks-0123abcd` gives
/// `geodesic_checks`.
pub fn crate_of_binary(path: &str) -> String {
    let name = path.rsplit(['/', '\\']).next().unwrap_or(path);
    let name = name.strip_suffix(".exe").unwrap_or(name);
    let name = match name.rsplit_once('-') {
        Some((stem, hash)) if hash.len() >= 8 && hash.chars().all(|c| c.is_ascii_hexdigit()) => {
            stem
        }
        _ => name,
    };
    name.replace('-', "_")
}

/// The result word after ` ... `, if it is one.
fn result_word(rest: &str) -> Option<TestResult> {
    let rest = rest.trim();
    let word = rest
        .split(|c: char| !c.is_ascii_alphabetic())
        .next()
        .unwrap_or("");
    match word {
        "ok" => Some(TestResult::Passed),
        "FAILED" => Some(TestResult::Failed),
        "ignored" => Some(TestResult::Ignored),
        _ => None,
    }
}

/// The crate named by a `Running` or `Doc-tests` line.
fn binary_line(line: &str) -> Option<String> {
    let t = line.trim();
    if let Some(rest) = t.strip_prefix("Doc-tests ") {
        return Some(rest.trim().replace('-', "_"));
    }
    let rest = t.strip_prefix("Running ")?;
    let path = match (rest.rfind('('), rest.ends_with(')')) {
        (Some(open), true) => &rest[open + 1..rest.len() - 1],
        _ => rest.split_whitespace().last()?,
    };
    Some(crate_of_binary(path.trim_matches('`')))
}

/// Every test result in `text`, in order, with the crate of the binary that printed it.
/// Tolerates output of the tests themselves (`--nocapture`) before a result line and between
/// `test NAME ... ` and its result.
pub fn parse(text: &str) -> Vec<Listed> {
    let mut out = Vec::new();
    let mut krate = String::new();
    let mut pending: Option<String> = None;
    for raw in text.lines() {
        let line = strip_ansi(raw);
        if let Some(k) = binary_line(&line) {
            krate = k;
            pending = None;
            continue;
        }
        if let Some(dots) = line.find(" ... ") {
            let head = &line[..dots];
            // a result line starts with `test `; after a test's own output without a newline
            // (`--nocapture`), the last `test ` of the line starts it
            let at = if head.starts_with("test ") {
                Some(0)
            } else {
                head.rfind("test ")
            };
            if let Some(at) = at {
                let mut name = head[at + 5..].trim();
                name = name.strip_suffix(" - should panic").unwrap_or(name);
                if !name.is_empty() && !name.starts_with("result:") {
                    match result_word(&line[dots + 5..]) {
                        Some(result) => {
                            out.push(Listed {
                                krate: krate.clone(),
                                test: name.to_string(),
                                result,
                            });
                            pending = None;
                        }
                        None => pending = Some(name.to_string()),
                    }
                    continue;
                }
            }
        }
        if let Some(name) = &pending {
            let t = line.trim();
            if t == "ok" || t == "FAILED" || t == "ignored" || t.starts_with("ignored, ") {
                out.push(Listed {
                    krate: krate.clone(),
                    test: name.clone(),
                    result: result_word(t).expect("a result word"),
                });
                pending = None;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const CAPTURED: &str = "\
   Compiling geodesic-core v0.1.0 (/work/geodesic/verification/core)
    Finished `test` profile [optimized + debuginfo] target(s) in 9.01s
     Running unittests src/lib.rs (target/debug/deps/geodesic_checks-0123456789abcdef)

running 3 tests
test capture::tests::criterion_evidence ... ok
test tests::check_names_are_unique ... FAILED
test tm_state::tests::slow ... ignored, needs the campaign data

test result: FAILED. 1 passed; 1 failed; 1 ignored; 0 measured; 0 filtered out; finished in 0.20s

     Running tests/verification/main.rs (target/debug/deps/verification-fedcba9876543210)

running 4 tests
test capture::criterion_is_symmetric_in_sign ... ok
test charge::charge_analysis_snapshot ... ignored
test trace::tests::unknown_id_fails - should panic ... ok
printed by a test without a newlinetest release::momentum_balance_holds ... ok

test result: ok. 3 passed; 0 failed; 1 ignored; 0 measured; 0 filtered out; finished in 1.00s

   Doc-tests geodesic_core

running 1 test
test verification/core/src/trace.rs - trace (line 17) - compile fail ... ok
";

    fn t(krate: &str, test: &str, result: TestResult) -> Listed {
        Listed {
            krate: krate.into(),
            test: test.into(),
            result,
        }
    }

    #[test]
    fn results_of_several_binaries() {
        let got = parse(CAPTURED);
        assert_eq!(
            got,
            vec![
                t(
                    "geodesic_checks",
                    "capture::tests::criterion_evidence",
                    TestResult::Passed
                ),
                t(
                    "geodesic_checks",
                    "tests::check_names_are_unique",
                    TestResult::Failed
                ),
                t(
                    "geodesic_checks",
                    "tm_state::tests::slow",
                    TestResult::Ignored
                ),
                t(
                    "verification",
                    "capture::criterion_is_symmetric_in_sign",
                    TestResult::Passed
                ),
                t(
                    "verification",
                    "charge::charge_analysis_snapshot",
                    TestResult::Ignored
                ),
                t(
                    "verification",
                    "trace::tests::unknown_id_fails",
                    TestResult::Passed
                ),
                t(
                    "verification",
                    "release::momentum_balance_holds",
                    TestResult::Passed
                ),
                t(
                    "geodesic_core",
                    "verification/core/src/trace.rs - trace (line 17) - compile fail",
                    TestResult::Passed
                ),
            ]
        );
    }

    #[test]
    fn interleaved_output_and_colours() {
        // one test thread (`--test-threads=1 --nocapture`): the test prints between the name
        // and its result; colours from a terminal
        let text = "\
\u{1b}[1m\u{1b}[32m     Running\u{1b}[0m tests/cli.rs (target/debug/deps/cli-00112233aabbccdd)
test prints_a_lot ... some output
more output
FAILED
test coloured ... \u{1b}[32mok\u{1b}[0m
test waits ... 
ignored, slow
";
        assert_eq!(
            parse(text),
            vec![
                t("cli", "prints_a_lot", TestResult::Failed),
                t("cli", "coloured", TestResult::Passed),
                t("cli", "waits", TestResult::Ignored),
            ]
        );
    }

    #[test]
    fn binary_names() {
        assert_eq!(
            crate_of_binary("target/debug/deps/geodesic_checks-0123456789abcdef"),
            "geodesic_checks"
        );
        assert_eq!(
            crate_of_binary(r"target\debug\deps\capture_charge-0123456789abcdef.exe"),
            "capture_charge"
        );
        assert_eq!(crate_of_binary("target/debug/deps/plain"), "plain");
        assert_eq!(
            binary_line("     Running `/abs/target/debug/deps/montecarlo-0123456789abcdef`"),
            Some("montecarlo".to_string())
        );
        assert_eq!(binary_line("running 3 tests"), None);
    }
}
