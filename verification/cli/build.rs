//! Records the commit the binary is built from (`GEODESIC_BUILD_COMMIT`): `git rev-parse HEAD`
//! of the source tree when git and a repository are there, else `unknown` (a source archive).
//! `verify` writes it in its run information and says when it is not the commit of the tree
//! it judges.

use std::path::PathBuf;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
}

fn main() {
    let commit = git(&["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=GEODESIC_BUILD_COMMIT={commit}");
    // rebuilt when HEAD moves: the HEAD file, the branch it names, the packed refs
    if let Some(dir) = git(&["rev-parse", "--absolute-git-dir"]) {
        let dir = PathBuf::from(dir);
        let mut watch = vec![dir.join("HEAD")];
        if let Some(common) = git(&["rev-parse", "--git-common-dir"]) {
            let common = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(common);
            watch.push(common.join("packed-refs"));
            if let Some(head_ref) = git(&["symbolic-ref", "-q", "HEAD"]) {
                watch.push(common.join(head_ref));
            }
        }
        // a path that does not exist would rerun the script on every build
        for p in watch.iter().filter(|p| p.exists()) {
            println!("cargo:rerun-if-changed={}", p.display());
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
