//! `geodesic verify`: loads the requirements, runs every registered check that verifies one of
//! them, builds the compliance matrix and writes `compliance.md` and `compliance.json` into the
//! reports directory (whole or not at all). Exit 0 when nothing is non-compliant, 1 when
//! something is, 2 on bad input.

use crate::builtin;
use crate::error::{CliError, CmdResult};
use geodesic_core::Requirements;
use geodesic_core::matrix::Matrix;
use geodesic_report::{CheckRun, Report, RunInfo};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

/// Flags of `geodesic verify`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Directory of requirement YAML files [default: ./requirements if present, else the
    /// built-in set].
    #[arg(long, value_name = "DIR")]
    pub requirements: Option<PathBuf>,
    /// Directory the reports are written to.
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Monte Carlo sample count used by the checks that run one.
    #[arg(long = "mc-n", value_name = "N", default_value_t = 100_000)]
    pub mc_n: usize,
    /// Monte Carlo seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Also write the compliance checks as JUnit XML to FILE (for CI dashboards).
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// Compare with a baseline compliance.json: list status flips, margins moved beyond
    /// --margin-tolerance and suspect evidence; exit 1 on any regression.
    #[arg(long, value_name = "OLD.json")]
    pub baseline: Option<PathBuf>,
    /// Margin change (absolute, as a fraction of the limit) that counts as moved.
    #[arg(
        long = "margin-tolerance",
        value_name = "FRACTION",
        default_value_t = 0.01
    )]
    pub margin_tolerance: f64,
    /// Skip the fidelity table (figures against the thesis; runs two more Monte Carlo cases).
    #[arg(long = "no-fidelity")]
    pub no_fidelity: bool,
    /// Print only the JSON compliance matrix on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Loads the requirements named by `--requirements`, `./requirements`, or the built-in set.
pub fn load_requirements(dir: Option<&PathBuf>) -> Result<(Requirements, String), CliError> {
    match dir {
        Some(d) => Ok((
            Requirements::load_dir(d).map_err(|e| CliError::bad(e.to_string()))?,
            d.display().to_string(),
        )),
        None if PathBuf::from("requirements").is_dir() => {
            let d = PathBuf::from("requirements");
            Ok((
                Requirements::load_dir(&d).map_err(|e| CliError::bad(e.to_string()))?,
                "requirements".into(),
            ))
        }
        None => {
            let src: Vec<(PathBuf, String)> = builtin::REQUIREMENTS
                .iter()
                .map(|(n, t)| (PathBuf::from(format!("<built-in>/{n}")), t.to_string()))
                .collect();
            Ok((
                Requirements::from_sources(&src).map_err(|e| CliError::bad(e.to_string()))?,
                "built-in".into(),
            ))
        }
    }
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    if args.mc_n == 0 {
        return Err(CliError::bad("--mc-n must be at least 1"));
    }
    let (reqs, source) = load_requirements(args.requirements.as_ref())?;
    let mc = geodesic_checks::release::SharedMonteCarlo::new();
    let registry = geodesic_checks::registry_with(mc.clone());
    let names: Vec<&str> = registry.iter().map(|c| c.name()).collect();
    reqs.validate_checks(&names)
        .map_err(|e| CliError::bad(e.to_string()))?;

    let staging = geodesic_report::write::Staging::new(&args.reports)
        .map_err(|e| CliError::Io(e.to_string()))?;
    let ctx = geodesic_checks::context(
        reqs.clone(),
        geodesic_checks::builtin_inputs(),
        staging.path().to_path_buf(),
        args.mc_n,
        args.seed,
        args.json || !std::io::stderr().is_terminal(),
    );
    let mut evidence = Vec::new();
    let mut runs = Vec::new();
    for check in &registry {
        if !check.verifies().iter().any(|id| reqs.get(id).is_some()) {
            continue; // none of its requirements is loaded: listed as an orphan check below
        }
        if !ctx.quiet {
            eprintln!("geodesic: running check {} ...", check.name());
        }
        let t0 = Instant::now();
        let ev = check
            .run(&ctx)
            .map_err(|e| CliError::bad(format!("check {}: {e}", check.name())))?;
        runs.push(CheckRun {
            name: check.name().to_string(),
            verifies: check.verifies().iter().map(|s| s.to_string()).collect(),
            seconds: t0.elapsed().as_secs_f64(),
        });
        evidence.push((check.name().to_string(), ev));
    }
    let mut matrix = Matrix::build(&reqs, &evidence, None, &[]);
    for check in &registry {
        if !check.verifies().iter().any(|id| reqs.get(id).is_some()) {
            for id in check.verifies() {
                matrix.orphan_checks.push(geodesic_core::matrix::Orphan {
                    check: check.name().to_string(),
                    requirement: id.to_string(),
                });
            }
        }
    }
    let fidelity = if args.no_fidelity {
        Vec::new()
    } else {
        if !ctx.quiet {
            eprintln!(
                "geodesic: computing the fidelity table (Monte Carlo cases adhesion and mechanisms) ..."
            );
        }
        geodesic_checks::fidelity::table(&mc, &ctx)
            .map_err(|e| CliError::bad(format!("fidelity table: {e}")))?
    };
    let report = Report {
        matrix,
        run: RunInfo {
            geodesic_version: env!("CARGO_PKG_VERSION").to_string(),
            requirements: source,
            mc_n: args.mc_n,
            seed: args.seed,
            checks: runs,
            fidelity,
        },
    };
    if !(args.margin_tolerance.is_finite() && args.margin_tolerance >= 0.0) {
        return Err(CliError::bad(
            "--margin-tolerance must be a non-negative number",
        ));
    }
    let diff = match &args.baseline {
        Some(b) => Some(
            geodesic_report::baseline::diff(&report, b, args.margin_tolerance)
                .map_err(|e| CliError::bad(e.to_string()))?,
        ),
        None => None,
    };
    let mut doc = serde_json::to_value(&report).map_err(|e| CliError::Io(e.to_string()))?;
    if let Some(d) = &diff {
        doc["baseline_diff"] = serde_json::to_value(d).map_err(|e| CliError::Io(e.to_string()))?;
    }
    let json = serde_json::to_string_pretty(&doc).map_err(|e| CliError::Io(e.to_string()))?;
    let io = |e: geodesic_report::write::WriteError| CliError::Io(e.to_string());
    let md = geodesic_report::markdown::render(&report);
    staging
        .write("compliance.json", json.as_bytes())
        .map_err(io)?;
    staging.write("compliance.md", md.as_bytes()).map_err(io)?;
    let vcd = geodesic_report::vcd::markdown(&report);
    staging.write("vcd.md", vcd.as_bytes()).map_err(io)?;
    staging
        .write("vcd.csv", geodesic_report::vcd::csv(&report).as_bytes())
        .map_err(io)?;
    let vcd_html = geodesic_report::html::render_vcd(&report);
    staging.write("vcd.html", vcd_html.as_bytes()).map_err(io)?;
    let page = geodesic_report::html::render(&report, &[staging.path(), args.reports.as_path()]);
    staging.write("index.html", page.as_bytes()).map_err(io)?;
    if let Some(d) = &diff {
        let md = geodesic_report::baseline::markdown(d);
        staging
            .write("baseline-diff.md", md.as_bytes())
            .map_err(io)?;
    }
    let junit = geodesic_report::junit::render(&report);
    let written = staging.commit().map_err(io)?;
    if let Some(j) = &args.junit {
        write_whole(j, junit.as_bytes())?;
    }
    if args.json {
        println!("{json}");
    } else {
        let color = std::io::stdout().is_terminal();
        print!(
            "{}",
            geodesic_report::terminal::table(&report.matrix, color)
        );
        if let Some(d) = &diff {
            print!("{}", geodesic_report::baseline::markdown(d));
        }
        let names: Vec<String> = written
            .iter()
            .filter(|p| p.parent() == Some(args.reports.as_path()))
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        println!("wrote {}/{{{}}}", args.reports.display(), names.join(","));
    }
    let regressions = diff.as_ref().map_or(0, |d| d.regressions);
    Ok(report.matrix.exit_code().max(u8::from(regressions > 0)))
}

/// Writes a file whole or not at all (temporary file, then rename).
fn write_whole(path: &std::path::Path, bytes: &[u8]) -> Result<(), CliError> {
    let tmp = path.with_extension("tmp-geodesic");
    std::fs::write(&tmp, bytes).map_err(|e| CliError::Io(format!("{}: {e}", tmp.display())))?;
    std::fs::rename(&tmp, path).map_err(|e| CliError::Io(format!("{}: {e}", path.display())))
}
