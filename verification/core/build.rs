//! Embeds the requirement IDs of `requirements/*.yaml` so that `verifies!` can reject unknown IDs
//! at test run time.
use std::path::Path;

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../requirements");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut ids = Vec::new();
    let mut sources = Vec::new();
    if let Ok(rd) = std::fs::read_dir(&dir) {
        let mut files: Vec<_> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
        files.sort();
        for f in files {
            if f.extension().and_then(|e| e.to_str()) != Some("yaml") {
                continue;
            }
            let text = std::fs::read_to_string(&f).unwrap_or_default();
            let name = f.file_name().unwrap().to_string_lossy().into_owned();
            let abs = f.canonicalize().unwrap_or(f.clone());
            sources.push(format!(
                "({:?}, include_str!({:?}))",
                format!("requirements/{name}"),
                abs.display().to_string()
            ));
            for line in text.lines() {
                let t = line.trim_start().trim_start_matches("- ").trim_start();
                // entries are `- id: X` at the requirement level (4 spaces of indent at most)
                if let Some(rest) = t.strip_prefix("id:") {
                    let indent = line.len() - line.trim_start().len();
                    if indent <= 4 {
                        ids.push(rest.trim().trim_matches('"').to_string());
                    }
                }
            }
        }
    }
    let out = Path::new(&std::env::var("OUT_DIR").unwrap()).join("requirement_ids.rs");
    let body: Vec<String> = ids.iter().map(|i| format!("{i:?}")).collect();
    std::fs::write(out, format!("&[{}]", body.join(", "))).unwrap();
    let out = Path::new(&std::env::var("OUT_DIR").unwrap()).join("requirement_sources.rs");
    std::fs::write(out, format!("&[{}]", sources.join(", "))).unwrap();
}
