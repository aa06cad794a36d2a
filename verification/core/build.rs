//! Embeds the requirement IDs of `requirements/*.yaml` and of every mission's
//! `missions/*/requirements/*.yaml` so that `verifies!` can reject unknown IDs at test run time,
//! and their texts so that a traced test can assert a requirement's own limit.
use std::path::{Path, PathBuf};

fn yaml_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|f| f.extension().and_then(|e| e.to_str()) == Some("yaml"));
    files.sort();
    files
}

fn collect(
    files: &[PathBuf],
    label: &dyn Fn(&str) -> String,
    ids: &mut Vec<String>,
) -> Vec<String> {
    let mut sources = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(f).unwrap_or_default();
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let abs = f.canonicalize().unwrap_or(f.clone());
        sources.push(format!(
            "({:?}, include_str!({:?}))",
            label(&name),
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
    sources
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = root.join("requirements");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut ids = Vec::new();
    let sources = collect(
        &yaml_files(&dir),
        &|n| format!("requirements/{n}"),
        &mut ids,
    );
    // the missions beside the LISA Pathfinder set: missions/<name>/requirements/*.yaml
    let missions = root.join("missions");
    println!("cargo:rerun-if-changed={}", missions.display());
    let mut mission_sources = Vec::new();
    let mut names: Vec<PathBuf> = std::fs::read_dir(&missions)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    names.sort();
    for m in names {
        let rdir = m.join("requirements");
        if !rdir.is_dir() {
            continue;
        }
        println!("cargo:rerun-if-changed={}", rdir.display());
        let mname = m.file_name().unwrap().to_string_lossy().into_owned();
        let srcs = collect(
            &yaml_files(&rdir),
            &|n| format!("missions/{mname}/requirements/{n}"),
            &mut ids,
        );
        mission_sources.push(format!("({mname:?}, &[{}])", srcs.join(", ")));
    }
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    let body: Vec<String> = ids.iter().map(|i| format!("{i:?}")).collect();
    std::fs::write(
        out_dir.join("requirement_ids.rs"),
        format!("&[{}]", body.join(", ")),
    )
    .unwrap();
    std::fs::write(
        out_dir.join("requirement_sources.rs"),
        format!("&[{}]", sources.join(", ")),
    )
    .unwrap();
    std::fs::write(
        out_dir.join("mission_sources.rs"),
        format!("&[{}]", mission_sources.join(", ")),
    )
    .unwrap();
}
