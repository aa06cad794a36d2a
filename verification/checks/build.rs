//! Collects every `verifies!("ID", ...)` call of the workspace's Rust sources into a table of
//! test traces (test name, file, line, kind, requirement IDs) and fails the build if an ID is not
//! defined in `requirements/*.yaml`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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

fn requirement_ids(dir: &Path) -> Vec<String> {
    let mut ids = Vec::new();
    let Ok(rd) = std::fs::read_dir(dir) else {
        return ids;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.extension().and_then(|e| e.to_str()) != Some("yaml") {
            continue;
        }
        for line in std::fs::read_to_string(&p).unwrap_or_default().lines() {
            let indent = line.len() - line.trim_start().len();
            let t = line.trim_start().trim_start_matches("- ").trim_start();
            if let Some(rest) = t.strip_prefix("id:") {
                if indent <= 4 {
                    ids.push(rest.trim().trim_matches('"').to_string());
                }
            }
        }
    }
    ids
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let root = root.canonicalize().unwrap_or(root);
    for d in ["models", "verification", "requirements"] {
        println!("cargo:rerun-if-changed={}", root.join(d).display());
    }
    let ids = requirement_ids(&root.join("requirements"));
    let mut files = Vec::new();
    rs_files(&root.join("models"), &mut files);
    rs_files(&root.join("verification"), &mut files);
    files.sort();
    let needle = ["verifies", "!("].concat();
    let mut table = String::from("&[\n");
    let mut unknown = Vec::new();
    for f in files {
        let rel = f
            .strip_prefix(&root)
            .unwrap_or(&f)
            .to_string_lossy()
            .replace('\\', "/");
        if rel == "verification/core/src/trace.rs" {
            continue; // the macro's own definition and documentation
        }
        let text = std::fs::read_to_string(&f).unwrap_or_default();
        let mut from = 0;
        while let Some(pos) = text[from..].find(&needle) {
            let at = from + pos;
            from = at + needle.len();
            let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
            let line_text = &text[line_start..at];
            if line_text.trim_start().starts_with("//") {
                continue;
            }
            let close = text[from..].find(')').map_or(text.len(), |i| from + i);
            let args = &text[from..close];
            let raw: Vec<&str> = args
                .split(',')
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .collect();
            let literal = |s: &str| {
                s.len() > 2
                    && s.starts_with('"')
                    && s.ends_with('"')
                    && s[1..s.len() - 1]
                        .chars()
                        .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '-')
            };
            if raw.is_empty() || !raw.iter().all(|s| literal(s)) {
                continue; // not a call with requirement-ID literals (e.g. this file's own text)
            }
            let req: Vec<String> = raw
                .iter()
                .map(|s| s.trim_matches('"').to_string())
                .collect();
            let line = text[..at].matches('\n').count() + 1;
            let before = &text[..at];
            let fn_pos = before.rfind("fn ");
            let test = fn_pos
                .map(|p| {
                    before[p + 3..]
                        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                        .next()
                        .unwrap_or("?")
                        .to_string()
                })
                .unwrap_or_else(|| "?".into());
            let body_end = text[at..]
                .find("\n    fn ")
                .or_else(|| text[at..].find("\nfn "))
                .map_or(text.len(), |i| at + i);
            let body = &text[at..body_end];
            let kind = if body.contains("assert_snapshot!")
                || body.contains("assert_json_snapshot!")
                || body.contains("assert_yaml_snapshot!")
                || body.contains("assert_debug_snapshot!")
            {
                "snapshot"
            } else if before
                .rfind("proptest!")
                .is_some_and(|p| fn_pos.is_some_and(|f| f > p))
                && text[before.rfind("proptest!").unwrap_or(0)..at]
                    .matches('{')
                    .count()
                    > text[before.rfind("proptest!").unwrap_or(0)..at]
                        .matches('}')
                        .count()
            {
                "proptest"
            } else {
                "unit"
            };
            for r in &req {
                if !ids.contains(r) {
                    unknown.push(format!(
                        "{rel}:{line}: verifies!(\"{r}\") names an unknown requirement"
                    ));
                }
            }
            let module = rel.trim_end_matches(".rs").replace('/', "::");
            let reqs: Vec<String> = req.iter().map(|r| format!("{r:?}")).collect();
            writeln!(
                table,
                "    geodesic_core::trace::TestTrace {{ test: {:?}, file: {:?}, line: {line}, kind: {kind:?}, requirements: &[{}] }},",
                format!("{module}::{test}"),
                rel,
                reqs.join(", ")
            )
            .unwrap();
        }
    }
    table.push(']');
    if !unknown.is_empty() {
        for u in &unknown {
            println!("cargo:warning={u}");
        }
        panic!("{}", unknown.join("\n"));
    }
    let out = Path::new(&std::env::var("OUT_DIR").unwrap()).join("traces.rs");
    std::fs::write(out, table).unwrap();
}
