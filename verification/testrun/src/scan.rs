//! The declared traces: every `verifies!("ID", ...)` call in the workspace's Rust code (not in
//! comments or strings), with the test it is in, so that a traced test that did not run (ignored,
//! filtered out, a dead function) still shows in the recorded run.

use std::path::{Path, PathBuf};

/// One `verifies!` call found in the sources.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Declared {
    /// Crate the file belongs to (`verification`, `geodesic_checks`).
    pub krate: String,
    /// Test name as libtest would print it (`hinge::torque_is_symmetric_in_sign`).
    pub test: String,
    /// The enclosing function's name.
    pub function: String,
    /// `file:line` of the call, the file relative to the workspace root (as `file!()` gives it).
    pub location: String,
    /// Requirement IDs.
    pub requirements: Vec<String>,
    /// Whether the enclosing function is a test (`#[test]`, in or out of `proptest!`).
    pub is_test: bool,
    /// Whether the call is inside a `proptest!` block.
    pub in_proptest: bool,
    /// Whether the function's body makes an insta `assert_*snapshot!`.
    pub snapshot: bool,
}

/// `text` with comments, string and character literals replaced by spaces (newlines kept), so
/// that byte offsets and line numbers stay those of `text`.
pub fn code_only(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = b.to_vec();
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for c in &mut out[from..to.min(b.len())] {
            if *c != b'\n' {
                *c = b' ';
            }
        }
    };
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                let end = text[i..].find('\n').map_or(b.len(), |e| i + e);
                blank(&mut out, i, end);
                i = end;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let (mut j, mut depth) = (i + 2, 1);
                while j < b.len() && depth > 0 {
                    if b[j] == b'/' && b.get(j + 1) == Some(&b'*') {
                        depth += 1;
                        j += 2;
                    } else if b[j] == b'*' && b.get(j + 1) == Some(&b'/') {
                        depth -= 1;
                        j += 2;
                    } else {
                        j += 1;
                    }
                }
                blank(&mut out, i, j);
                i = j;
            }
            b'r' if (i == 0
                || !ident(b[i - 1])
                || (b[i - 1] == b'b' && (i < 2 || !ident(b[i - 2]))))
                && matches!(b.get(i + 1), Some(b'"' | b'#')) =>
            {
                let mut j = i + 1;
                while b.get(j) == Some(&b'#') {
                    j += 1;
                }
                if b.get(j) != Some(&b'"') {
                    i += 1; // a raw identifier (`r#type`)
                    continue;
                }
                let hashes = j - i - 1;
                let close = format!("\"{}", "#".repeat(hashes));
                let end = text[j + 1..]
                    .find(&close)
                    .map_or(b.len(), |e| j + 1 + e + close.len());
                blank(&mut out, j, end);
                i = end;
            }
            b'"' => {
                let mut j = i + 1;
                while j < b.len() && b[j] != b'"' {
                    j += if b[j] == b'\\' { 2 } else { 1 };
                }
                blank(&mut out, i, j + 1);
                i = j + 1;
            }
            b'\'' => {
                // a character literal (`'a'`, `'\n'`, `'é'`) or a lifetime (`'a`)
                if b.get(i + 1) == Some(&b'\\') {
                    let mut j = i + 2;
                    while j < b.len() && b[j] != b'\'' {
                        j += 1;
                    }
                    blank(&mut out, i, j + 1);
                    i = j + 1;
                } else if let Some(c) = text[i + 1..].chars().next() {
                    let after = i + 1 + c.len_utf8();
                    if b.get(after) == Some(&b'\'') {
                        blank(&mut out, i, after + 1);
                        i = after + 1;
                    } else {
                        i += 1;
                    }
                } else {
                    i += 1;
                }
            }
            _ => i += 1,
        }
    }
    String::from_utf8(out).expect("only ASCII bytes replaced, whole characters")
}

/// Index of the bracket closing the one at `open` (in code-only text).
fn matching(code: &[u8], open: usize) -> Option<usize> {
    let (o, c) = match code[open] {
        b'(' => (b'(', b')'),
        b'[' => (b'[', b']'),
        b'{' => (b'{', b'}'),
        _ => return None,
    };
    let mut depth = 0usize;
    for (k, &x) in code.iter().enumerate().skip(open) {
        if x == o {
            depth += 1;
        } else if x == c {
            depth -= 1;
            if depth == 0 {
                return Some(k);
            }
        }
    }
    None
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// Offsets of `word` as a whole identifier-delimited word in `code`, followed (after optional
/// whitespace) by `then`; returns the word's offset and the offset just after `then`.
fn find_word(code: &str, word: &str, then: &str) -> Vec<(usize, usize)> {
    let b = code.as_bytes();
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(p) = code[from..].find(word) {
        let at = from + p;
        from = at + word.len();
        if at > 0 && is_ident(b[at - 1]) {
            continue;
        }
        let mut k = at + word.len();
        if then.is_empty() {
            if k < b.len() && is_ident(b[k]) {
                continue;
            }
            out.push((at, k));
            continue;
        }
        while k < b.len() && b[k].is_ascii_whitespace() {
            k += 1;
        }
        if code[k..].starts_with(then) {
            out.push((at, k + then.len()));
        }
    }
    out
}

/// The identifier starting at or after `at` (skipping whitespace).
fn ident_after(code: &str, at: usize) -> (String, usize) {
    let b = code.as_bytes();
    let mut k = at;
    while k < b.len() && b[k].is_ascii_whitespace() {
        k += 1;
    }
    let start = k;
    while k < b.len() && is_ident(b[k]) {
        k += 1;
    }
    (code[start..k].to_string(), k)
}

/// The attributes written before the item starting at `at` (`#[test]`, `#[ignore]`), skipping
/// visibility and qualifiers.
fn attributes_before(code: &str, at: usize) -> Vec<String> {
    let b = code.as_bytes();
    let mut k = at;
    let mut out = Vec::new();
    loop {
        while k > 0 && b[k - 1].is_ascii_whitespace() {
            k -= 1;
        }
        if k > 0 && b[k - 1] == b']' {
            // find the matching '['
            let mut depth = 0usize;
            let mut j = k;
            while j > 0 {
                j -= 1;
                match b[j] {
                    b']' => depth += 1,
                    b'[' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    _ => {}
                }
            }
            if j > 0 && b[j - 1] == b'#' {
                out.push(code[j + 1..k - 1].split_whitespace().collect::<String>());
                k = j - 1;
                continue;
            }
            return out;
        }
        let word_end = k;
        while k > 0 && is_ident(b[k - 1]) {
            k -= 1;
        }
        match &code[k..word_end] {
            "pub" | "async" | "unsafe" | "const" | "extern" => continue,
            _ => {
                // `pub(crate)`
                if word_end == k
                    && k > 0
                    && b[k - 1] == b')'
                    && let Some(open) = code[..k].rfind('(')
                    && code[..open].trim_end().ends_with("pub")
                {
                    k = open;
                    continue;
                }
                return out;
            }
        }
    }
}

/// The innermost enclosing block opened by `keyword` (`proptest!`, `mod NAME`) around `pos`:
/// for each occurrence whose following `{` closes after `pos`.
fn enclosing(code: &str, keyword: &str, then: &str, pos: usize) -> Vec<(usize, usize)> {
    let b = code.as_bytes();
    find_word(code, keyword, then)
        .into_iter()
        .filter(|&(at, _)| at < pos)
        .filter_map(|(at, after)| {
            let open = after + code[after..].find(['{', ';'])?;
            if b[open] != b'{' {
                return None;
            }
            let close = matching(b, open)?;
            (open < pos && pos < close).then_some((at, after))
        })
        .collect()
}

/// Whether `body` (code only) makes an insta `assert_*snapshot!`.
fn has_snapshot(body: &str) -> bool {
    let b = body.as_bytes();
    let mut from = 0;
    while let Some(p) = body[from..].find("assert_") {
        let s = from + p;
        let mut e = s;
        while e < b.len() && is_ident(b[e]) {
            e += 1;
        }
        if (s == 0 || !is_ident(b[s - 1]))
            && body[s..e].ends_with("snapshot")
            && b.get(e) == Some(&b'!')
        {
            return true;
        }
        from = e;
    }
    false
}

/// The crate and module path of a file, from its place in its package (`src/a/b.rs` is `a::b`
/// of the library, `tests/x/y.rs` is `y` of the test crate `x`).
pub fn crate_and_module(package: &str, rel: &Path) -> (String, Vec<String>) {
    let parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let lib = package.replace('-', "_");
    let strip = |s: &str| s.trim_end_matches(".rs").to_string();
    let module = |rest: &[String]| -> Vec<String> {
        let mut m: Vec<String> = rest.iter().map(|s| strip(s)).collect();
        if matches!(m.last().map(String::as_str), Some("mod" | "main" | "lib")) {
            m.pop();
        }
        m
    };
    match parts.first().map(String::as_str) {
        Some("src") if parts.get(1).map(String::as_str) == Some("bin") && parts.len() >= 3 => {
            (strip(&parts[2]).replace('-', "_"), module(&parts[3..]))
        }
        Some("src") => (lib, module(&parts[1..])),
        Some("tests" | "benches" | "examples") if parts.len() >= 2 => {
            if parts.len() == 2 {
                (strip(&parts[1]).replace('-', "_"), Vec::new())
            } else {
                (parts[1].replace('-', "_"), module(&parts[2..]))
            }
        }
        _ => (lib, module(&parts)),
    }
}

/// The declared traces of one file's text. `package` is its package's name, `rel_pkg` its path
/// in the package, `rel_root` its path from the workspace root.
pub fn scan_text(text: &str, package: &str, rel_pkg: &Path, rel_root: &str) -> Vec<Declared> {
    let code = code_only(text);
    let b = code.as_bytes();
    let (krate, file_module) = crate_and_module(package, rel_pkg);
    let mut out = Vec::new();
    for (at, after) in find_word(&code, "verifies", "!") {
        let mut k = after;
        while k < b.len() && b[k].is_ascii_whitespace() {
            k += 1;
        }
        if b.get(k) != Some(&b'(') {
            continue;
        }
        let Some(close) = matching(b, k) else {
            continue;
        };
        let raw: Vec<&str> = text[k + 1..close]
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        let literal = |s: &str| s.len() > 2 && s.starts_with('"') && s.ends_with('"');
        if raw.is_empty() || !raw.iter().all(|s| literal(s)) {
            continue; // not a call with requirement-ID literals (the macro's own definition)
        }
        let requirements: Vec<String> = raw.iter().map(|s| s[1..s.len() - 1].to_string()).collect();
        let line = text[..at].matches('\n').count() + 1;
        // the innermost function whose body contains the call
        let function = find_word(&code, "fn", "")
            .into_iter()
            .filter(|&(f, _)| f < at)
            .filter_map(|(f, end)| {
                let (name, _) = ident_after(&code, end);
                if name.is_empty() {
                    return None; // a function pointer type, `fn(T)`
                }
                let open = end + code[end..].find(['{', ';'])?;
                let body_end = if b[open] == b'{' {
                    matching(b, open)?
                } else {
                    return None;
                };
                (open < at && at < body_end).then_some((f, name, open, body_end))
            })
            .next_back();
        let (fn_at, name, body) = match &function {
            Some((f, name, open, end)) => (*f, name.clone(), &code[*open..*end]),
            None => (at, "?".to_string(), ""),
        };
        let attrs = attributes_before(&code, fn_at);
        let is_test = function.is_some()
            && attrs
                .iter()
                .any(|a| a == "test" || a.ends_with("::test") || a.starts_with("test("));
        let in_proptest = !enclosing(&code, "proptest", "!", at).is_empty();
        let snapshot = has_snapshot(body);
        let mut path = file_module.clone();
        for (_, after) in enclosing(&code, "mod", "", fn_at) {
            path.push(ident_after(&code, after).0);
        }
        path.push(name.clone());
        out.push(Declared {
            krate: krate.clone(),
            test: path.join("::"),
            function: name,
            location: format!("{rel_root}:{line}"),
            requirements,
            is_test,
            in_proptest,
            snapshot,
        });
    }
    out
}

fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if p.is_dir() {
            if name != "target" && !name.starts_with('.') {
                rs_files(&p, out);
            }
        } else if name.ends_with(".rs") {
            out.push(p);
        }
    }
}

/// The package of a file: the nearest `Cargo.toml` above it with a `[package]` name.
fn package_of(file: &Path, root: &Path) -> Option<(String, PathBuf)> {
    let mut dir = file.parent()?;
    loop {
        let manifest = dir.join("Cargo.toml");
        if let Ok(text) = std::fs::read_to_string(&manifest) {
            let mut in_package = false;
            for line in text.lines() {
                let t = line.trim();
                if t.starts_with('[') {
                    in_package = t == "[package]";
                } else if in_package
                    && let Some(v) = t.strip_prefix("name")
                    && let Some(v) = v.trim_start().strip_prefix('=')
                {
                    return Some((v.trim().trim_matches('"').to_string(), dir.into()));
                }
            }
        }
        if dir == root {
            return None;
        }
        dir = dir.parent()?;
    }
}

/// Every declared trace under the workspace `root`, in file and line order.
pub fn scan(root: &Path) -> Vec<Declared> {
    let mut files = Vec::new();
    rs_files(root, &mut files);
    files.sort();
    let mut out = Vec::new();
    for f in files {
        let Ok(text) = std::fs::read_to_string(&f) else {
            continue;
        };
        if !text.contains("verifies") {
            continue;
        }
        let Some((package, dir)) = package_of(&f, root) else {
            continue;
        };
        let rel_root = f
            .strip_prefix(root)
            .unwrap_or(&f)
            .to_string_lossy()
            .replace('\\', "/");
        let rel_pkg = f.strip_prefix(&dir).unwrap_or(&f);
        out.extend(scan_text(&text, &package, rel_pkg, &rel_root));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `verify` checks a recorded test against (issue 49): every `verifies!` call of the
    /// workspace, at the location a run records for it, reads back from the source as a call
    /// naming the same requirements; so a record of a real traced test is never rejected.
    #[test]
    fn every_traced_call_of_the_workspace_reads_back_from_its_location() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let declared = scan(&root);
        assert!(declared.len() > 20, "{}", declared.len());
        for d in &declared {
            let (file, line) = d.location.rsplit_once(':').unwrap();
            let text = std::fs::read_to_string(root.join(file)).unwrap();
            let read = geodesic_core::testrun::source_trace(&text, line.parse().unwrap());
            assert_eq!(
                read.map(|(ids, _)| ids),
                Some(d.requirements.clone()),
                "{}",
                d.location
            );
        }
    }

    const SOURCE: &str = r####"//! Tests. `verifies!("IN-DOC")` in a doc comment is no call.
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]
    /// A property.
    #[test]
    fn prop(x in 0.0f64..1.0) {
        geodesic_core::verifies!("CAP-QUARTIC");
        prop_assert!(x < 2.0);
    }
}

#[test]
#[ignore = "always fails"]
fn ignored_one() {
    geodesic_core::verifies!("CHG-Q", "CHG-V");
    panic!("{}", '"');
}

/* geodesic_core::verifies!("IN-BLOCK"); /* nested */ still comment */
// geodesic_core::verifies!("IN-LINE");

#[allow(dead_code)]
fn helper<'a>(s: &'a str) -> &'a str {
    geodesic_core::verifies!("REL-GPRM-VEL");
    let _ = r#"verifies!("IN-RAW")"#;
    s
}

#[cfg(test)]
mod tests {
    #[test]
    fn snap() {
        crate::verifies!("REL-DFACS-VEL",);
        insta::assert_json_snapshot!(1);
    }
}
"####;

    #[test]
    fn calls_outside_comments_and_strings() {
        let got = scan_text(
            SOURCE,
            "geodesic-checks",
            Path::new("tests/verification/capture.rs"),
            "verification/checks/tests/verification/capture.rs",
        );
        // test, line, requirements, is_test, in_proptest, snapshot
        type Brief<'a> = (&'a str, &'a str, Vec<&'a str>, bool, bool, bool);
        let brief: Vec<Brief> = got
            .iter()
            .map(|d| {
                (
                    d.test.as_str(),
                    d.location.rsplit(':').next().unwrap(),
                    d.requirements.iter().map(String::as_str).collect(),
                    d.is_test,
                    d.in_proptest,
                    d.snapshot,
                )
            })
            .collect();
        assert_eq!(
            brief,
            vec![
                ("capture::prop", "9", vec!["CAP-QUARTIC"], true, true, false),
                (
                    "capture::ignored_one",
                    "17",
                    vec!["CHG-Q", "CHG-V"],
                    true,
                    false,
                    false
                ),
                (
                    "capture::helper",
                    "26",
                    vec!["REL-GPRM-VEL"],
                    false,
                    false,
                    false
                ),
                (
                    "capture::tests::snap",
                    "35",
                    vec!["REL-DFACS-VEL"],
                    true,
                    false,
                    true
                ),
            ]
        );
        assert!(got.iter().all(|d| d.krate == "verification"));
        assert_eq!(got[1].function, "ignored_one");
    }

    #[test]
    fn crates_and_modules() {
        let cm = |p: &str| crate_and_module("geodesic-checks", Path::new(p));
        let v = |s: &[&str]| s.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(cm("src/lib.rs"), ("geodesic_checks".into(), v(&[])));
        assert_eq!(
            cm("src/capture.rs"),
            ("geodesic_checks".into(), v(&["capture"]))
        );
        assert_eq!(cm("src/a/mod.rs"), ("geodesic_checks".into(), v(&["a"])));
        assert_eq!(cm("src/bin/tool.rs"), ("tool".into(), v(&[])));
        assert_eq!(cm("tests/cli.rs"), ("cli".into(), v(&[])));
        assert_eq!(
            cm("tests/verification/main.rs"),
            ("verification".into(), v(&[]))
        );
        assert_eq!(
            cm("tests/verification/release.rs"),
            ("verification".into(), v(&["release"]))
        );
    }

    #[test]
    fn code_only_keeps_offsets() {
        let t = "let c = '\"'; let s = \"a // b\"; // c\nlet l: &'static str = r#\"x\"#;";
        let c = code_only(t);
        assert_eq!(c.len(), t.len());
        assert_eq!(c.matches('\n').count(), 1);
        assert!(!c.contains("//") && !c.contains('"'), "{c}");
        assert!(c.contains("&'static str"), "{c}");
    }
}
