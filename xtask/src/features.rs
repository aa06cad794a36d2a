//! `cargo xtask features`: checks that `workspace-hack/Cargo.toml` makes every member's own build
//! (`cargo build -p NAME`, `cargo test -p NAME`) see each shared dependency with the features
//! the whole workspace's test build gives it, so that no build compiles a crate again for a
//! feature set of its own (issue 37, item 6). Reads `cargo tree`: the features of every package
//! in `cargo tree --workspace` (normal, build and dev edges) against those in `cargo tree -p
//! MEMBER` (normal and build edges), for the host's target. Prints what is missing as lines
//! for the hack's `Cargo.toml`; exit 1 when something is.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::{Command, ExitCode};

/// Package (name, version) -> features, from `cargo tree ... -f "{p} [{f}]"` lines.
pub type Features = BTreeMap<(String, String), BTreeSet<String>>;

/// Parses `cargo tree --prefix none -f "{p} [{f}]"` output (a package may appear on several
/// lines, for the host and the target: their features are merged).
pub fn parse_tree(text: &str) -> Features {
    let mut out = Features::new();
    for line in text.lines() {
        let line = line.trim().trim_end_matches(" (*)");
        let Some((head, feats)) = line.rsplit_once(" [") else {
            continue;
        };
        let feats = feats.trim_end_matches(']');
        let mut words = head.split_whitespace();
        let (Some(name), Some(version)) = (words.next(), words.next()) else {
            continue;
        };
        let Some(version) = version.strip_prefix('v') else {
            continue;
        };
        out.entry((name.to_string(), version.to_string()))
            .or_default()
            .extend(feats.split(',').filter(|f| !f.is_empty()).map(String::from));
    }
    out
}

/// What `member`'s own build lacks against the workspace's: package -> the workspace's features.
pub fn missing(workspace: &Features, member: &Features) -> Features {
    member
        .iter()
        .filter_map(|(k, f)| {
            let w = workspace.get(k)?;
            (!f.is_superset(w)).then(|| (k.clone(), w.clone()))
        })
        .collect()
}

/// A `Cargo.toml` dependency line asking for `features` of `name` `version`.
pub fn toml_line(name: &str, version: &str, features: &BTreeSet<String>) -> String {
    let major = match version.split('.').collect::<Vec<_>>().as_slice() {
        ["0", minor, ..] => format!("0.{minor}"),
        [major, ..] => major.to_string(),
        _ => version.to_string(),
    };
    let list: Vec<String> = features.iter().map(|f| format!("\"{f}\"")).collect();
    format!(
        "{name} = {{ version = \"{major}\", default-features = false, features = [{}] }}",
        list.join(", ")
    )
}

fn cargo_tree(root: &Path, target: &str, args: &[&str]) -> Result<Features, String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(root)
        .args([
            "tree",
            "--prefix",
            "none",
            "-f",
            "{p} [{f}]",
            "--target",
            target,
        ])
        .args(args)
        .output()
        .map_err(|e| format!("cargo tree: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "cargo tree {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(parse_tree(&String::from_utf8_lossy(&out.stdout)))
}

/// The workspace's members, from `cargo metadata`.
fn members(root: &Path) -> Result<Vec<String>, String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(root)
        .args(["metadata", "--no-deps", "--format-version", "1"])
        .output()
        .map_err(|e| format!("cargo metadata: {e}"))?;
    let doc: serde_json::Value =
        serde_json::from_slice(&out.stdout).map_err(|e| format!("cargo metadata: {e}"))?;
    Ok(doc["packages"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|p| p["name"].as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default())
}

/// The host's target triple (`rustc -vV`).
fn host() -> Result<String, String> {
    let out = Command::new("rustc")
        .arg("-vV")
        .output()
        .map_err(|e| format!("rustc -vV: {e}"))?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: ").map(String::from))
        .ok_or_else(|| "rustc -vV names no host".to_string())
}

/// Runs the check; `--check` only changes the wording of the closing line.
pub fn run(root: &Path) -> Result<ExitCode, String> {
    let target = host()?;
    let ws = cargo_tree(root, &target, &["--workspace", "-e", "normal,build,dev"])?;
    let mut all = Features::new();
    for m in members(root)? {
        let own = cargo_tree(root, &target, &["-p", &m, "-e", "normal,build"])?;
        let miss = missing(&ws, &own);
        if !miss.is_empty() {
            let names: Vec<String> = miss.keys().map(|(n, v)| format!("{n} {v}")).collect();
            println!("{m}: {}", names.join(", "));
        }
        all.extend(miss);
    }
    if all.is_empty() {
        println!(
            "xtask features: every member's own build sees the workspace's features \
             (workspace-hack/Cargo.toml is complete)"
        );
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "xtask features: add to workspace-hack/Cargo.toml ([dependencies]; proc-macro and \
         build-script crates such as syn under [build-dependencies]):"
    );
    for ((n, v), f) in &all {
        println!("{}", toml_line(n, v, f));
    }
    Ok(ExitCode::from(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_member_missing_a_feature_is_named_with_the_line_to_add() {
        let ws = parse_tree(
            "serde v1.0.229 [alloc,default,std]\nrand v0.10.3 [alloc,std,sys_rng]\n\
             geodesic-core v0.1.0 (/w/verification/core) []\nserde v1.0.229 [default] (*)\n",
        );
        assert_eq!(ws[&("serde".into(), "1.0.229".into())].len(), 3);
        let own = parse_tree("serde v1.0.229 [default,std]\nrand v0.10.3 [alloc,std,sys_rng]\n");
        let m = missing(&ws, &own);
        assert_eq!(m.len(), 1);
        let ((n, v), f) = m.iter().next().unwrap();
        assert_eq!(
            toml_line(n, v, f),
            "serde = { version = \"1\", default-features = false, features = [\"alloc\", \"default\", \"std\"] }"
        );
        assert_eq!(
            toml_line("rand", "0.10.3", &BTreeSet::new()),
            "rand = { version = \"0.10\", default-features = false, features = [] }"
        );
    }
}
