//! Helpers shared by the CLI test binaries: run the `geodesic` binary in a directory, find the
//! workspace, and give each test a scratch directory of its own that is removed when the test's
//! thread ends (tests run in parallel and never share a path; nothing is left behind).
#![allow(dead_code)] // each test binary uses a subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `geodesic ARGS` in `cwd`.
pub fn geodesic(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geodesic"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run geodesic")
}

/// The workspace root.
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// The temporary directory of the test running on this thread.
pub fn test_dir() -> PathBuf {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::Builder::new()
            .prefix("geodesic-cli-")
            .tempdir()
            .expect("a temporary directory");
    }
    DIR.with(|d| d.path().to_path_buf())
}

/// A fresh scratch directory `name` inside this test's own temporary directory.
pub fn scratch(name: &str) -> PathBuf {
    let d = test_dir().join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
