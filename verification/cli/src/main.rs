//! `geodesic`: verifies the LISA Pathfinder test-mass release against its requirements and
//! confronts its physics models with measurements.
//!
//! The binary stays thin: it parses flags (clap), calls the library crates and prints. Every
//! command accepts `--json` (exactly one JSON document on standard output). Exit status: 0
//! success, 1 a verdict of non-compliance (`verify`), 2 bad input or usage with a one-line cause
//! on standard error.

mod builtin;
mod cmd;
mod error;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "geodesic",
    version,
    about = "Verify the LISA Pathfinder test-mass release against its requirements"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Check every requirement and write the compliance matrix (reports/compliance.{md,json}).
    Verify(cmd::verify::Args),
    /// Run the in-flight release Monte Carlo.
    Montecarlo(cmd::montecarlo::Args),
    /// Merge partial Monte Carlo results written with --shard.
    Merge(cmd::merge::Args),
    /// Fit a model (a list of effects) to a measurement dataset.
    Fit(cmd::fit::Args),
    /// Fit a model, then every candidate effect it lacks, and name the missing one.
    Diagnose(cmd::diagnose::Args),
    /// Write a synthetic dataset from a truth model built from the effect catalogue.
    Synth(cmd::synth::Args),
    /// Show the fit history (RMS and chi-square per model version) of a dataset.
    History(cmd::history::Args),
    /// Charge left on the TM after release (contact electrification).
    Charge(cmd::charge::Args),
    /// Evaluate the DFACS quartic capture criterion for one TM state.
    Capture(cmd::capture::Args),
    /// List the effect catalogue: effects, scenarios, parameters with units and ranges.
    Effects(cmd::effects::Args),
    /// Export the requirement set to another tool's format (reqif).
    Export(cmd::export::Args),
    /// Import requirements from another tool's format (reqif) into requirement YAML.
    Import(cmd::import::Args),
}

/// Restores the default action of SIGPIPE so that `geodesic ... | head` ends quietly, as Unix
/// tools do, instead of panicking on a closed standard output (Rust ignores SIGPIPE by default).
fn reset_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called once at start-up, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// A clap usage error as one line: `geodesic: usage: <first line of the cause> (see --help)`.
fn usage_line(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let first = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("invalid usage");
    let first = first.strip_prefix("error: ").unwrap_or(first);
    format!("geodesic: usage: {first} (see geodesic --help)")
}

fn main() -> ExitCode {
    reset_sigpipe();
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            let code = match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => 0,
                _ => 2,
            };
            if code == 0 {
                let _ = e.print();
            } else {
                eprintln!("{}", usage_line(&e));
            }
            return ExitCode::from(code);
        }
    };
    let result = match cli.command {
        Command::Verify(a) => cmd::verify::run(a),
        Command::Montecarlo(a) => cmd::montecarlo::run(a),
        Command::Merge(a) => cmd::merge::run(a),
        Command::Fit(a) => cmd::fit::run(a),
        Command::Diagnose(a) => cmd::diagnose::run(a),
        Command::Synth(a) => cmd::synth::run(a),
        Command::History(a) => cmd::history::run(a),
        Command::Charge(a) => cmd::charge::run(a),
        Command::Capture(a) => cmd::capture::run(a),
        Command::Effects(a) => cmd::effects::run(a),
        Command::Export(a) => cmd::export::run(a),
        Command::Import(a) => cmd::import::run(a),
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("geodesic: {e}");
            ExitCode::from(2)
        }
    }
}
