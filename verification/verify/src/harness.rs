//! The test-oracle harness: a project that verifies its own system with geodesic writes
//!
//! ```no_run
//! # fn mission() -> geodesic_verify::Mission { unimplemented!() }
//! fn main() -> std::process::ExitCode {
//!     geodesic_verify::harness::main(mission())
//! }
//! ```
//!
//! and its program runs the verification (`verify`, or no command at all) with the flags
//! `geodesic verify` has (`--reports DIR`, `--json`, `--baseline OLD.json`, `--require-tests`,
//! `--junit FILE`, `--only`, `--NAME FILE` for each declared input, `--NAME VALUE` for each
//! declared run option, e.g. `--mc-n N`), lists,
//! checks and shows its requirements (`requirements check|list|show ID`), exports them as ReqIF
//! (`export reqif --out FILE [--matrix compliance.json]`, as `geodesic export reqif`; the older
//! `export-reqif` still works), and records its traced tests (`test [ARGS]`: `cargo test ARGS`
//! in the project, in the profile the program was built with, recorded by [`geodesic_testrun::record`] into
//! `target/geodesic/test-run.json`, which `verify --require-tests` reads). `verify` names the
//! project's own command (`cargo run -- test`) when the run is missing or stale.

use crate::error::Error;
use crate::mission::Mission;
use crate::pipeline::{self, Options};
use clap::{Arg, ArgAction, ArgMatches, Command};
use std::path::PathBuf;
use std::process::ExitCode;

/// The `verify` flags every program shares (`geodesic verify` and a project's harness), with
/// one `--NAME FILE` flag per declared input of `missions`.
pub fn verify_args(cmd: Command, missions: &[&Mission]) -> Command {
    let mut cmd = cmd
        .arg(Arg::new("requirements").long("requirements").value_name("DIR").value_parser(clap::value_parser!(PathBuf))
            .help("Directory of requirement YAML files [default: the mission's folder if present, else its built-in copy]"))
        .arg(Arg::new("dispositions").long("dispositions").value_name("FILE.yaml").value_parser(clap::value_parser!(PathBuf))
            .help("Dispositions of known non-compliances (NCR, waiver, RFD) [default: the mission's if present, else none]"))
        .arg(Arg::new("document").long("document").value_name("FILE.yaml").value_parser(clap::value_parser!(PathBuf))
            .help("Identification of the documents written (id, issue, title, project) [default: `document.yaml` beside the --requirements folder if present, else the mission's]"))
        .arg(Arg::new("tests").long("tests").value_name("FILE.json").value_parser(clap::value_parser!(PathBuf))
            .help("Recorded test run read for the traced tests' results [default: ./target/geodesic/test-run.json if present]"))
        .arg(Arg::new("require-tests").long("require-tests").action(ArgAction::SetTrue)
            .help("Exit 1 when no test run is recorded, when it is stale, when a requirement's traced tests failed, were ignored or did not run, or when a verdict has no passing traced test that asserts its limit or a reference"))
        .arg(Arg::new("reports").long("reports").value_name("DIR").default_value("reports").value_parser(clap::value_parser!(PathBuf))
            .help("Directory the reports are written to"))
        .arg(Arg::new("confidence").long("confidence").value_name("C").default_value("0.95").value_parser(clap::value_parser!(f64))
            .help("Confidence of the bounds a sampled verdict (a Monte Carlo quantile, a probability from successes) is decided by, between 0 and 1"))
        .arg(Arg::new("junit").long("junit").value_name("FILE").value_parser(clap::value_parser!(PathBuf))
            .help("Also write the compliance checks as JUnit XML to FILE (for CI dashboards)"))
        .arg(Arg::new("baseline").long("baseline").value_name("OLD.json").value_parser(clap::value_parser!(PathBuf))
            .help("Gate against a baseline compliance.json: exit 0 when nothing regressed, 1 on a regression (a new non-compliance, a margin lost beyond --margin-tolerance, evidence or a passing test lost, a disposition expired), each requirement counted once"))
        .arg(Arg::new("margin-tolerance").long("margin-tolerance").value_name("FRACTION").default_value("0.01").value_parser(clap::value_parser!(f64))
            .help("Margin change (absolute, as a fraction of the limit) that counts as moved"))
        .arg(Arg::new("no-fidelity").long("no-fidelity").action(ArgAction::SetTrue)
            .help("Skip the fidelity table (the mission's figures against its reference)"))
        .arg(Arg::new("series").long("series").value_name("ID=FILE.yaml").action(ArgAction::Append)
            .help("A time series judged against a spectral requirement: `ID=FILE.yaml` (repeatable)"))
        .arg(Arg::new("only").long("only").value_name("ID[,ID...]").value_delimiter(',').action(ArgAction::Append)
            .help("Run only these requirements and what they depend on (their parents, the rows a flow-down assumes, the rows that judge their model inputs); the matrix holds those rows, marked chosen or dependency, and says the run was partial. Never with --baseline"))
        .arg(Arg::new("json").long("json").action(ArgAction::SetTrue)
            .help("Print only the JSON compliance matrix on standard output"));
    let mut seen: Vec<String> = Vec::new();
    // the run options the missions declare: `--NAME VALUE`, a whole number
    for m in missions {
        for o in &m.spec.options {
            if seen.contains(&o.name) {
                continue;
            }
            seen.push(o.name.clone());
            let defaults: Vec<String> = missions
                .iter()
                .filter_map(|m| {
                    let d = m.spec.options.iter().find(|d| d.name == o.name)?.default;
                    Some((m.spec.name.as_str(), d))
                })
                .map(|(name, d)| {
                    if missions.len() == 1 {
                        d.to_string()
                    } else {
                        format!("{d} (mission {name})")
                    }
                })
                .collect();
            cmd = cmd.arg(
                Arg::new(leak(format!("option:{}", o.name)))
                    .long(leak(o.name.clone()))
                    .value_name(leak(o.words.to_uppercase().replace(' ', "_")))
                    .value_parser(clap::value_parser!(u64))
                    .help(format!("{} [default: {}]", o.about, defaults.join(", "))),
            );
        }
    }
    for m in missions {
        for i in &m.spec.inputs {
            if seen.contains(&i.name) {
                continue;
            }
            seen.push(i.name.clone());
            let about = if i.about.is_empty() {
                i.words.clone()
            } else {
                i.about.clone()
            };
            cmd = cmd.arg(
                Arg::new(leak(format!("input:{}", i.name)))
                    .long(leak(i.name.clone()))
                    .value_name("FILE.yaml")
                    .value_parser(clap::value_parser!(PathBuf))
                    .help(format!(
                        "{about} [default: {} of mission {} if present, else its built-in copy]",
                        m.path(&i.path).display(),
                        m.spec.name
                    )),
            );
        }
    }
    cmd
}

/// A name clap keeps for the program's life (the flags are built once per process).
fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

/// The [`Options`] of parsed `verify` flags.
pub fn options(m: &ArgMatches) -> Options {
    let path = |id: &str| m.get_one::<PathBuf>(id).cloned();
    let mut inputs = std::collections::BTreeMap::new();
    for id in m.ids() {
        if let Some(name) = id.as_str().strip_prefix("input:")
            && let Some(p) = m.get_one::<PathBuf>(id.as_str())
        {
            inputs.insert(name.to_string(), p.clone());
        }
    }
    let mut options = std::collections::BTreeMap::new();
    for id in m.ids() {
        if let Some(name) = id.as_str().strip_prefix("option:")
            && let Some(v) = m.get_one::<u64>(id.as_str())
        {
            options.insert(name.to_string(), *v);
        }
    }
    Options {
        requirements: path("requirements"),
        inputs,
        dispositions: path("dispositions"),
        document: path("document"),
        tests: path("tests"),
        require_tests: m.get_flag("require-tests"),
        reports: path("reports").unwrap_or_else(|| PathBuf::from("reports")),
        options,
        confidence: *m.get_one::<f64>("confidence").unwrap_or(&0.95),
        junit: path("junit"),
        baseline: path("baseline"),
        margin_tolerance: *m.get_one::<f64>("margin-tolerance").unwrap_or(&0.01),
        no_fidelity: m.get_flag("no-fidelity"),
        series: m
            .get_many::<String>("series")
            .map(|v| v.cloned().collect())
            .unwrap_or_default(),
        only: m
            .get_many::<String>("only")
            .map(|v| v.cloned().collect())
            .unwrap_or_default(),
        json: m.get_flag("json"),
        ..Options::default()
    }
}

/// Prints a run's outcome the way `geodesic verify` does: the JSON document (`--json`), or the
/// terminal matrix, the input lines and the files written; the gate's lines on standard error
/// (prefixed with `program`). Returns the exit status.
pub fn print(program: &str, opts: &Options, out: &crate::Outcome) -> u8 {
    use std::io::IsTerminal;
    if opts.json {
        println!("{}", out.json);
    } else {
        let color = std::io::stdout().is_terminal();
        print!(
            "{}",
            geodesic_report::terminal::table_for(&out.report.matrix, color, &opts.test_command)
        );
        let names: Vec<String> = out
            .written
            .iter()
            .filter(|p| p.parent() == Some(opts.reports.as_path()))
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        let run_options: Vec<String> = out
            .report
            .run
            .options
            .lines()
            .iter()
            .map(|(label, text)| format!("{label}: {text}"))
            .collect();
        println!(
            "sampled verdicts: decided by their {} confidence bounds{}",
            geodesic_core::units::fmt_pct(out.report.run.confidence),
            if run_options.is_empty() {
                String::new()
            } else {
                format!(" ({})", run_options.join("; "))
            }
        );
        for l in pipeline::input_lines(&out.report.run.inputs) {
            println!("{l}");
        }
        if let Some(p) = &out.report.run.partial {
            println!("partial run: {}", p.note);
        }
        println!("wrote {}/{{{}}}", opts.reports.display(), names.join(","));
    }
    for l in &out.messages {
        eprintln!("{program}: {l}");
    }
    out.code
}

/// UTC time as xsd:dateTime: now, or `SOURCE_DATE_EPOCH` (seconds) when set, as reproducible
/// builds do.
pub fn creation_time() -> Result<String, Error> {
    let secs = match std::env::var("SOURCE_DATE_EPOCH") {
        Ok(s) => s.trim().parse::<i64>().map_err(|_| {
            Error::usage(format!(
                "SOURCE_DATE_EPOCH `{s}` is not a number of seconds since 1970-01-01"
            ))
        })?,
        Err(_) => std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs() as i64),
    };
    let (day, s) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    Ok(format!(
        "{}T{:02}:{:02}:{:02}Z",
        geodesic_core::disposition::civil_from_days(day),
        s / 3600,
        (s / 60) % 60,
        s % 60
    ))
}

fn export_reqif(mission: &Mission, m: &ArgMatches) -> Result<u8, Error> {
    use geodesic_exchange::reqif::{ExportOptions, export};
    let out = m
        .get_one::<PathBuf>("out")
        .cloned()
        .unwrap_or_else(|| PathBuf::from("reports/requirements.reqif"));
    crate::preflight::out_file_in_new_dir("--out", &out)?;
    let (reqs, _, _) = pipeline::load_requirements(mission, m.get_one::<PathBuf>("requirements"))?;
    let status = match m.get_one::<PathBuf>("matrix") {
        Some(p) => {
            let text = geodesic_util::fsio::read_text(p, geodesic_util::fsio::MAX_YAML_BYTES)
                .map_err(|e| {
                    Error::unreadable(format!("{}: {e}", p.display())).in_file(p, e.line())
                })?;
            let s = geodesic_exchange::status::StatusSet::parse(p, &text)
                .map_err(|e| Error::malformed(e.to_string()).in_file(p, 0))?;
            s.check_against(p, &reqs)
                .map_err(|e| Error::unknown_id(e.to_string()).in_file(p, 0))?;
            Some(s)
        }
        None => None,
    };
    let time = creation_time()?;
    let tool = format!("geodesic {}", env!("CARGO_PKG_VERSION"));
    let doc = export(
        &reqs,
        &ExportOptions {
            creation_time: &time,
            tool_version: &tool,
            status: status.as_ref(),
        },
    );
    geodesic_util::output::write_atomic(&out, doc.as_bytes())
        .map_err(|e| Error::io(format!("--out {e}")))?;
    println!(
        "wrote {} ({} requirements)",
        out.display(),
        reqs.items.len()
    );
    Ok(0)
}

/// The program of a project verified with geodesic: `verify` (the default), `test`,
/// `requirements list|check|show`, `export reqif`. Exit status: 0 compliant (with `--baseline`: nothing
/// regressed), 1 non-compliant or regressed, 2 bad input with a one-line cause.
pub fn main(mission: Mission) -> ExitCode {
    let program = std::env::args()
        .next()
        .and_then(|a| {
            std::path::Path::new(&a)
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| mission.spec.name.clone());
    let req_arg = || {
        Arg::new("requirements")
            .long("requirements")
            .value_name("DIR")
            .value_parser(clap::value_parser!(PathBuf))
    };
    let cmd = verify_args(
        Command::new(leak(program.clone()))
            .about(format!(
                "Verify {} against its requirements",
                mission.spec.title
            ))
            .after_help(format!(
                "Without a command: verify. Reports written by verify:\n{}",
                geodesic_report::formats::help()
            ))
            .args_conflicts_with_subcommands(true)
            .subcommand(verify_args(
                Command::new("verify").about("Check every requirement and write the reports"),
                &[&mission],
            ))
            .subcommand(
                <crate::requirements::Args as clap::Args>::augment_args(Command::new("requirements"))
                    .about("Validate, list and show the requirements (status and evidence from the last run)"),
            )
            .subcommand(
                Command::new("test")
                    .about("Run the traced tests (`cargo test` in the project, in this program's profile, ARGS passed through) and record their run in target/geodesic/test-run.json for `verify`")
                    .arg(
                        Arg::new("args")
                            .value_name("ARGS")
                            .num_args(0..)
                            .trailing_var_arg(true)
                            .allow_hyphen_values(true),
                    ),
            )
            .subcommand(
                Command::new("export")
                    .about("Export the requirements to an exchange format")
                    .subcommand_required(true)
                    .subcommand(reqif_args(Command::new("reqif"), req_arg())),
            )
            // the name of earlier generated projects' scripts
            .subcommand(reqif_args(Command::new("export-reqif"), req_arg()).hide(true)),
        &[&mission],
    );
    let m = match cmd.try_get_matches() {
        Ok(m) => m,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let res = match m.subcommand() {
        Some(("requirements", sub)) => {
            match <crate::requirements::Args as clap::FromArgMatches>::from_arg_matches(sub) {
                Ok(a) => crate::requirements::run_for(&mission, a, &test_command(&program)),
                Err(e) => Err(Error::usage(e.to_string())),
            }
        }
        Some(("export-reqif", sub)) => export_reqif(&mission, sub),
        Some(("export", sub)) => match sub.subcommand() {
            Some(("reqif", sub)) => export_reqif(&mission, sub),
            _ => Err(Error::usage("export: give a format (`export reqif`)")),
        },
        Some(("test", sub)) => record_tests(&program, sub),
        Some((_, sub)) => run_verify(&program, &mission, sub),
        None => run_verify(&program, &mission, &m),
    };
    match res {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("{program}: {e}");
            ExitCode::from(2)
        }
    }
}

/// `export reqif` (and its older spelling `export-reqif`): the flags.
fn reqif_args(cmd: Command, requirements: Arg) -> Command {
    cmd.about("Export the requirements (and the VCD status) as ReqIF 1.2")
        .arg(requirements)
        .arg(
            Arg::new("out")
                .long("out")
                .value_name("FILE.reqif")
                .value_parser(clap::value_parser!(PathBuf)),
        )
        .arg(
            Arg::new("matrix")
                .long("matrix")
                .value_name("compliance.json")
                .value_parser(clap::value_parser!(PathBuf)),
        )
}

/// The command that records a project's traced tests: `cargo run -- test` when cargo runs the
/// program (it sets `CARGO`), else the program itself.
fn test_command(program: &str) -> String {
    if std::env::var_os("CARGO").is_some() {
        "cargo run -- test".into()
    } else {
        format!("{program} test")
    }
}

/// The project's root: the folder of `cargo locate-project --workspace` from here, else the
/// current folder.
fn project_root() -> PathBuf {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    std::process::Command::new(cargo)
        .args(["locate-project", "--workspace", "--message-format", "plain"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| {
            PathBuf::from(String::from_utf8_lossy(&o.stdout).trim())
                .parent()
                .map(PathBuf::from)
        })
        .unwrap_or_else(|| PathBuf::from("."))
}

/// `test [ARGS]`: `cargo test ARGS` in the project (`--release` when this program was built in
/// the release profile), recorded as `cargo xtask test` records this repository's
/// ([`geodesic_testrun::record`]). Exit status: cargo's.
fn record_tests(program: &str, m: &ArgMatches) -> Result<u8, Error> {
    let extra: Vec<String> = m
        .get_many::<String>("args")
        .map(|v| v.cloned().collect())
        .unwrap_or_default();
    let mut command = test_command(program);
    for a in &extra {
        command.push(' ');
        command.push_str(a);
    }
    let root = project_root();
    let r = geodesic_testrun::Recording {
        // where `verify` reads it (`./target/geodesic/test-run.json`), whatever
        // CARGO_TARGET_DIR says: a project built in a shared target folder keeps its own run
        out_dir: root.join("target/geodesic"),
        root,
        // the profile this program was built with: `cargo run -- test` builds the tests in the
        // dev profile and `cargo run --release -- test` in release, each sharing every compiled
        // crate with the program's own build (the first build compiles the framework once)
        cargo_args: if cfg!(debug_assertions) {
            Vec::new()
        } else {
            vec!["--release".into()]
        },
        extra,
        command,
        prefix: format!("{program} test"),
        fresh_build: None,
    };
    geodesic_testrun::record(&r).map_err(Error::io)
}

fn run_verify(program: &str, mission: &Mission, m: &ArgMatches) -> Result<u8, Error> {
    let mut opts = options(m);
    opts.test_command = test_command(program);
    crate::progress::set_mode(crate::progress::Mode::Auto);
    let out = pipeline::run(mission, &opts)?;
    Ok(print(program, &opts, &out))
}
