//! `geodesic`: verifies the registered missions against their requirements and
//! confronts its physics models with measurements.
//!
//! The binary stays thin: it parses flags (clap), calls the library crates and prints. Every
//! command accepts `--json` (exactly one JSON document on standard output). Exit status: 0
//! success, 1 a verdict of non-compliance (`verify`), 2 bad input or usage with a one-line cause
//! on standard error.

#![warn(missing_docs)]
mod cmd;
mod error;
mod fitting;
mod missions;
mod quantity;

use geodesic_verify::{preflight, progress, usage};

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "geodesic",
    version,
    about = "Verify a system against its requirements and confront its physics models with measurements",
    after_help = "Examples:
  geodesic verify                                   # every requirement; reports/compliance.{md,json}, the VCD
  geodesic verify --mission NAME                    # another mission of this repository
  geodesic new mission my-arm --path ../my-arm       # a project of your own, verified the same way
  geodesic fit data/examples/tmmf-adhesion.yaml --effects needle_contact,tip_contact,tip_adhesion
  geodesic import reqif from-doors.reqif --out imported/ && geodesic verify --requirements imported/
  geodesic COMMAND --help                           # a command's options and examples

Exit status: 0 success, 1 a verdict (verify: a non-compliance; tiptrack, asd and a mission's
own commands: not met), 2 bad input or usage (one line on standard error), 128 + N when interrupted by signal N.
`geodesic` alone prints this list of commands on standard error and exits 2."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Show progress on standard error even with --json or when it is not a terminal.
    #[arg(long, global = true, conflicts_with = "quiet")]
    progress: bool,
    /// Never show progress (errors are still printed).
    #[arg(long, short = 'q', global = true)]
    quiet: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Check every requirement and write the compliance matrix (reports/compliance.{md,json}).
    #[command(after_help = "Examples:
  geodesic verify                                   # every requirement, built-in models; reports/ 
  geodesic verify --mc-n 20000 --no-fidelity        # a quicker look
  geodesic verify --mission NAME --design my-design.yaml --reports out/
  geodesic verify --baseline verification/baseline/compliance.json --require-tests --junit reports/junit.xml
  geodesic verify --json | jq '.requirements[] | select(.status != \"compliant\") | .id'
  geodesic verify --only CHG-V,TMS-X-POS            # those rows and what they depend on (a partial run)

Exit status: 0 nothing non-compliant (with --baseline: nothing regressed), 1 a non-compliance
or a regression, 2 bad input.")]
    Verify(cmd::verify::Args),
    /// Fit a model (a list of effects) to a measurement dataset.
    #[command(after_help = "Examples:
  geodesic effects --scenario tmmf-release                 # the effects you can fit
  geodesic fit data/examples/tmmf-adhesion.yaml --effects needle_contact,tip_contact,tip_adhesion
  geodesic fit data/examples/rt-plunger.yaml --effects piezo --fix piezo.R=371ohm --bound \"piezo.Ca=10nF:10uF\" --json
Values may carry units (--fix tip_adhesion.lambda=400nm); bare numbers are SI.
Writes reports/fits/<dataset>.<effects>.svg and appends reports/fits/<dataset>.history.jsonl.")]
    Fit(cmd::fit::Args),
    /// Fit a model, then every candidate effect it lacks, and name the missing one.
    #[command(after_help = "Examples:
  geodesic diagnose data/examples/tmmf-adhesion.yaml --effects needle_contact,tip_contact
  geodesic diagnose data/examples/rt-plunger.yaml --effects piezo --json | jq .missing")]
    Diagnose(cmd::diagnose::Args),
    /// Write a synthetic dataset from a truth model built from the effect catalogue.
    #[command(after_help = "Examples:
  geodesic synth --scenario tmmf-release --effects needle_contact,tip_contact,tip_adhesion \
      --param tip_adhesion.A1=2e5 --noise x=2nm --seed 3 --out data/mine.yaml
  geodesic synth --scenario rt-retraction --effects piezo,plunger_compliance --fs 1MHz --out rt.yaml
Writes X.yaml, X.csv and X.truth.json (the truth parameters) beside each other.")]
    Synth(cmd::synth::Args),
    /// Show the fit history (RMS and chi-square per model version) of a dataset.
    #[command(after_help = "Examples:
  geodesic history data/examples/tmmf-adhesion.yaml
  geodesic history tmmf-adhesion --json")]
    History(cmd::history::Args),
    /// List the effect catalogue: effects, scenarios, parameters with units and ranges.
    #[command(after_help = "Examples:
  geodesic effects
  geodesic effects --scenario rt-retraction --json")]
    Effects(cmd::effects::Args),
    /// Export the requirement set to another tool's format (reqif).
    #[command(after_help = "Examples:
  geodesic export reqif                                              # reports/requirements.reqif
  geodesic export reqif --matrix reports/compliance.json --out reqs.reqif   # with the VCD status
See docs/exchange.md.")]
    Export(cmd::export::Args),
    /// Import requirements from another tool's format (reqif) into requirement YAML.
    #[command(after_help = "Examples:
  geodesic import reqif from-doors.reqif --out imported/ --report
  geodesic import reqif polarion.reqif --out imported/ --attribute limit=\"Max Value\" --strict
See docs/exchange.md.")]
    Import(cmd::import::Args),
    /// The discovery loop: diagnose, add the supported effect, refit, until the residual is noise
    Discover(cmd::discover::Args),
    /// The release tip's trajectory from high-speed camera frames (threshold crossings)
    Tiptrack(cmd::tiptrack::Args),
    /// Register two surface height maps (before and after contact) and compare them
    Surfaces(cmd::surfaces::Args),
    /// Amplitude spectral density of a time series judged against a spectral requirement
    Asd(cmd::asd::Args),
    /// Validate, list and show the requirements (status and evidence from the last run)
    #[command(after_help = "Examples:
  geodesic requirements check                       # validate requirements/ only (exit 2: file:line:column)
  geodesic requirements list                        # every requirement with its status from reports/
  geodesic requirements show REL-GPRM-VEL           # source, limit, flow-down, traced tests, evidence")]
    Requirements(cmd::requirements::Args),
    /// Scaffold a project outside this repository that verifies its own system with geodesic
    #[command(after_help = "Examples:
  geodesic new mission solar-hinge --path ../solar-hinge
  cd ../solar-hinge && cargo run -- test && cargo run -- verify --require-tests
See docs/guide-mission.md.")]
    New(cmd::new::Args),
    /// Print the JSON Schema (draft 2020-12) of a command's --json document, the machine-readable contract
    Schema(cmd::schema::Args),
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

/// Keeps the memory of freed large blocks in the process for the next allocation instead of
/// returning it to the system. A long record's fit allocates and frees vectors of a few
/// megabytes (a residual, a Jacobian column) at every iteration; with glibc's default
/// thresholds each came back as fresh pages, and the kernel's zeroing of those pages was 7 % of
/// a 400 000-sample `discover`'s time (7.8 s of system time in 107 s of CPU; 0.6 s with these
/// thresholds, peak memory unchanged, 2026-11-28). Blocks up to 64 MiB come from the heap, and
/// the heap is trimmed only when 256 MiB lie free at its top. The arithmetic does not change.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: called once at start-up, before any other thread exists; mallopt only sets
    // glibc's allocation thresholds.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 64 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
    }
}

/// Handles SIGINT, SIGTERM and SIGHUP on a thread of their own: it removes the temporary files
/// and staged report sets the run registered (`geodesic_util::output`), waiting for a commit in
/// progress to finish, then exits with 128 + the signal number, as a shell reports it. The
/// signals are blocked in every other thread (the mask is inherited by the threads spawned
/// later, rayon's included), so only this thread receives them.
fn handle_interrupts() {
    #[cfg(unix)]
    // SAFETY: called once at start-up, before any other thread exists; the sigset is
    // initialised by sigemptyset before use and lives on this stack frame while it is used.
    unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for s in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::sigaddset(&mut set, s);
        }
        if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
            return;
        }
        std::thread::Builder::new()
            .name("geodesic-signals".into())
            .spawn(move || {
                let mut sig: libc::c_int = 0;
                // SAFETY: `set` is a valid, initialised signal set owned by this closure.
                while libc::sigwait(&set, &mut sig) != 0 {}
                geodesic_util::output::remove_registered();
                eprintln!("geodesic: interrupted (signal {sig}); no partial output left");
                std::process::exit(128 + sig);
            })
            .ok();
    }
}

fn main() -> ExitCode {
    reset_sigpipe();
    keep_freed_memory();
    handle_interrupts();
    // the missions this repository verifies (the root mission first): `verify` has a flag per
    // input they declare
    missions::install(geodesic_missions::all());
    // the missions' own commands beside the framework's
    let plugins = geodesic_missions::commands();
    let cmd = plugins
        .iter()
        .fold(Cli::command(), |c, p| c.subcommand(p.command.clone()));
    // usage errors: one line naming the argument (geodesic_verify::usage); negative numbers are
    // values
    let matches = match usage::parse_matches(cmd) {
        Ok(m) => m,
        Err(code) => return ExitCode::from(code),
    };
    progress::set_mode(if matches.get_flag("quiet") {
        progress::Mode::Never
    } else if matches.get_flag("progress") {
        progress::Mode::Always
    } else {
        progress::Mode::Auto
    });
    let plugin = matches
        .subcommand()
        .and_then(|(name, sub)| plugins.iter().find(|p| p.name() == name).map(|p| (p, sub)));
    let result = match plugin {
        Some((p, sub)) => (p.run)(sub),
        None => match Cli::from_arg_matches(&matches) {
            Ok(cli) => run(cli.command),
            Err(e) => return ExitCode::from(usage::report(&e, "geodesic", "geodesic")),
        },
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("geodesic: {e}");
            ExitCode::from(2)
        }
    }
}

/// Runs a framework command.
fn run(command: Command) -> error::CmdResult {
    match command {
        Command::Verify(a) => cmd::verify::run(a),
        Command::Fit(a) => cmd::fit::run(a),
        Command::Diagnose(a) => cmd::diagnose::run(a),
        Command::Synth(a) => cmd::synth::run(a),
        Command::History(a) => cmd::history::run(a),
        Command::Effects(a) => cmd::effects::run(a),
        Command::Export(a) => cmd::export::run(a),
        Command::Import(a) => cmd::import::run(a),
        Command::Discover(a) => cmd::discover::run(a),
        Command::Tiptrack(a) => cmd::tiptrack::run(a),
        Command::Asd(a) => cmd::asd::run(a),
        Command::Surfaces(a) => cmd::surfaces::run(a),
        Command::Requirements(a) => cmd::requirements::run(a),
        Command::New(a) => cmd::new::run(a),
        Command::Schema(a) => cmd::schema::run(a),
    }
}
