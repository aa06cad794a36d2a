//! geodesic developer tasks.
//!
//! `cargo xtask test [-- CARGO-TEST-ARGS]` runs `cargo test --workspace --release` (with the
//! extra arguments) and records the traced tests' results into `target/geodesic/test-run.json`
//! (the framework's library [`geodesic_testrun`], which a project verified with geodesic calls
//! from its own `cargo run -- test`), and exits with cargo's status.

mod features;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// How long a fresh clone's first build takes on the 2-core machine (README, measured).
const FRESH_BUILD: &str = "6 minutes";

const USAGE: &str = "usage: cargo xtask test [-- CARGO-TEST-ARGS] | cargo xtask features

  test   run `cargo test --workspace --release [CARGO-TEST-ARGS]` and record the traced tests'
         results in target/geodesic/test-run.json
  features
         check that workspace-hack/Cargo.toml gives every member's own build the workspace's
         features of each shared dependency (exit 1 with the lines to add when not)";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("test") => {
            let mut extra = args[1..].to_vec();
            if extra.first().map(String::as_str) == Some("--") {
                extra.remove(0);
            }
            match geodesic_testrun::record(&recording(extra)) {
                Ok(code) => ExitCode::from(code),
                Err(e) => {
                    eprintln!("xtask test: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Some("features") => match features::run(&root()) {
            Ok(code) => code,
            Err(e) => {
                eprintln!("xtask features: {e}");
                ExitCode::from(2)
            }
        },
        Some("-h" | "--help" | "help") => {
            println!("{USAGE}");
            ExitCode::SUCCESS
        }
        _ => {
            eprintln!("{USAGE}");
            ExitCode::from(2)
        }
    }
}

/// The workspace root (this crate is `xtask/` in it).
fn root() -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    p.canonicalize().unwrap_or(p)
}

/// The recorded run of `cargo xtask test [-- extra]`: the whole workspace, release profile.
fn recording(extra: Vec<String>) -> geodesic_testrun::Recording {
    let mut command = String::from("cargo xtask test");
    if !extra.is_empty() {
        command.push_str(" -- ");
        command.push_str(&extra.join(" "));
    }
    let root = root();
    geodesic_testrun::Recording {
        out_dir: geodesic_testrun::target_dir(&root).join("geodesic"),
        root,
        cargo_args: vec!["--workspace".into(), "--release".into()],
        extra,
        command,
        prefix: "xtask test".into(),
        fresh_build: Some(FRESH_BUILD.into()),
    }
}
