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
    /// Release Monte Carlo budget [default: ./models/release/budget.yaml if present, else the
    /// built-in copy].
    #[arg(long, value_name = "FILE.yaml")]
    pub budget: Option<PathBuf>,
    /// Capture inputs: xlim, drift time, state sources [default: ./models/capture/capture.yaml
    /// if present, else the built-in copy].
    #[arg(long, value_name = "FILE.yaml")]
    pub capture: Option<PathBuf>,
    /// Charge inputs: capacitances, contact voltage spread, release-tip geometry [default:
    /// ./models/charge/charge.yaml if present, else the built-in copy].
    #[arg(long, value_name = "FILE.yaml")]
    pub charge: Option<PathBuf>,
    /// Dispositions of known non-compliances (NCR, waiver, RFD) [default:
    /// ./verification/dispositions.yaml if present, else none].
    #[arg(long, value_name = "FILE.yaml")]
    pub dispositions: Option<PathBuf>,
    /// Identification of the documents written (id, issue, title, project) [default:
    /// `document.yaml` beside the --requirements folder if present, else
    /// ./verification/document.yaml if present, else the built-in copy].
    #[arg(long, value_name = "FILE.yaml")]
    pub document: Option<PathBuf>,
    /// Recorded test run read for the traced tests' results [default:
    /// ./target/geodesic/test-run.json if present, else none: `cargo xtask test` writes it].
    #[arg(long, value_name = "FILE.json")]
    pub tests: Option<PathBuf>,
    /// Exit 1 when no test run is recorded, when the recorded run is stale (another commit,
    /// or the work tree changed since it ran), when a requirement's traced tests failed, were
    /// ignored or did not run, or when a model, measurement or method-validation verdict has no
    /// passing traced test that asserts its limit or a reference.
    #[arg(long = "require-tests")]
    pub require_tests: bool,
    /// Directory the reports are written to.
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Monte Carlo sample count used by the checks that run one.
    #[arg(long = "mc-n", value_name = "N", default_value_t = 100_000)]
    pub mc_n: usize,
    /// Monte Carlo seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Confidence of the bounds a sampled verdict (a Monte Carlo quantile, a probability from
    /// successes) is decided by, between 0 and 1.
    #[arg(long, value_name = "C", default_value_t = geodesic_checks::DEFAULT_CONFIDENCE)]
    pub confidence: f64,
    /// Also write the compliance checks as JUnit XML to FILE (for CI dashboards).
    #[arg(long, value_name = "FILE")]
    pub junit: Option<PathBuf>,
    /// Gate against a baseline compliance.json: exit 0 when nothing regressed, 1 on a
    /// regression (a new non-compliance, a margin lost beyond --margin-tolerance, evidence or a
    /// passing test lost, a disposition expired), each requirement counted once.
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
    /// A time series judged against a spectral requirement: `ID=FILE.yaml` (repeatable; the
    /// series format is in docs/spectra.md).
    #[arg(long = "series", value_name = "ID=FILE.yaml")]
    pub series: Vec<String>,
    /// A mission's design inputs read by its checks [default: `design.yaml` beside the
    /// requirements directory if present, else the checks' built-in copy].
    #[arg(long, value_name = "FILE.yaml")]
    pub design: Option<PathBuf>,
    /// Run only these requirements and what they depend on (their parents, the rows a
    /// flow-down assumes, the rows that judge their model inputs); the matrix holds those rows,
    /// marked chosen or dependency, and says the run was partial. Never with --baseline.
    #[arg(long, value_name = "ID[,ID...]", value_delimiter = ',')]
    pub only: Vec<String>,
    /// Print only the JSON compliance matrix on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Loads the requirements named by `--requirements`, `./requirements`, or the built-in set;
/// returns them with their source label and the SHA-256 over their files (names and bytes,
/// sorted by name).
pub fn load_requirements(
    dir: Option<&PathBuf>,
) -> Result<(Requirements, String, String), CliError> {
    let dir = match dir {
        Some(d) => Some(d.clone()),
        None if PathBuf::from("requirements").is_dir() => Some(PathBuf::from("requirements")),
        None => None,
    };
    match dir {
        Some(d) => {
            let reqs = Requirements::load_dir(&d).map_err(|e| CliError::bad(e.to_string()))?;
            let mut files: Vec<PathBuf> = std::fs::read_dir(&d)
                .map_err(|e| CliError::bad(format!("{}: {e}", d.display())))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "yml")))
                .collect();
            files.sort();
            let mut parts = Vec::new();
            for f in &files {
                let name = f
                    .file_name()
                    .map_or(String::new(), |n| n.to_string_lossy().into());
                let bytes =
                    std::fs::read(f).map_err(|e| CliError::bad(format!("{}: {e}", f.display())))?;
                parts.push((name, bytes));
            }
            let hash = geodesic_core::hash::sha256_parts(
                parts.iter().map(|(n, b)| (n.as_str(), b.as_slice())),
            );
            Ok((reqs, d.display().to_string(), hash))
        }
        None => {
            let src: Vec<(PathBuf, String)> = builtin::REQUIREMENTS
                .iter()
                .map(|(n, t)| (PathBuf::from(format!("<built-in>/{n}")), t.to_string()))
                .collect();
            let hash = geodesic_core::hash::sha256_parts(
                builtin::REQUIREMENTS
                    .iter()
                    .map(|(n, t)| (*n, t.as_bytes())),
            );
            Ok((
                Requirements::from_sources(&src).map_err(|e| CliError::bad(e.to_string()))?,
                "built-in".into(),
                hash,
            ))
        }
    }
}

/// Git commit and dirty flag of the current directory (`unknown`, false outside a repository).
pub fn git_state() -> (String, bool) {
    let run = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .stderr(std::process::Stdio::null())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match run(&["rev-parse", "HEAD"]) {
        Some(c) if !c.is_empty() => {
            let dirty = run(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            (c, dirty)
        }
        _ => ("unknown".into(), false),
    }
}

/// UTC date and time now, RFC 3339 (`2026-11-23T18:40:00Z`).
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    let day = secs.div_euclid(86_400);
    let s = secs.rem_euclid(86_400);
    format!(
        "{}T{:02}:{:02}:{:02}Z",
        geodesic_core::disposition::civil_from_days(day),
        s / 3600,
        (s / 60) % 60,
        s % 60
    )
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    if args.mc_n == 0 || args.mc_n > geodesic_release::montecarlo::MAX_N {
        return Err(CliError::bad(format!(
            "--mc-n {}: must be between 1 and {}",
            args.mc_n,
            geodesic_release::montecarlo::MAX_N
        )));
    }
    if !(args.confidence.is_finite() && args.confidence > 0.0 && args.confidence < 1.0) {
        return Err(CliError::bad(format!(
            "--confidence {}: must be between 0 and 1 (exclusive), e.g. 0.95",
            args.confidence
        )));
    }
    if !(args.margin_tolerance.is_finite() && args.margin_tolerance >= 0.0) {
        return Err(CliError::bad(
            "--margin-tolerance must be a non-negative number",
        ));
    }
    preflight_outputs(&args)?;
    crate::only::refuse_partial_gate(&args.only, args.baseline.as_deref())?;
    let (reqs, source, requirements_hash) = load_requirements(args.requirements.as_ref())?;
    let mut selection = crate::only::Selection::parse(&args.only, &reqs)?;
    let mc = geodesic_checks::release::SharedMonteCarlo::new();
    let registry = geodesic_checks::registry_with(mc.clone());
    let names: Vec<&str> = registry.iter().map(|c| c.name()).collect();
    reqs.validate_checks(&names)
        .map_err(|e| CliError::bad(e.to_string()))?;

    // model inputs, read and checked before anything runs
    let mut series = std::collections::BTreeMap::new();
    for s in &args.series {
        let Some((id, file)) = s.split_once('=') else {
            return Err(CliError::bad(format!(
                "--series {s}: write ID=FILE.yaml (e.g. --series LPF-DA-ASD=data/spectra/da.yaml)"
            )));
        };
        let Some(r) = reqs.get(id.trim()) else {
            return Err(CliError::bad(format!(
                "--series {s}: no requirement {id} is loaded"
            )));
        };
        if r.spectrum.is_none() {
            return Err(CliError::bad(format!(
                "--series {s}: {id} is not a spectral requirement (it has no `spectrum`)"
            )));
        }
        let f = geodesic_core::check::InputFile::read(std::path::Path::new(file.trim()))
            .map_err(|e| CliError::bad(format!("--series {e}")))?;
        // read and checked before anything runs: a bad series is exit 2 with its file and line
        geodesic_fit::spectral::Series::load(std::path::Path::new(file.trim()))
            .map_err(|e| CliError::bad(e.to_string()))?;
        if series.insert(r.id.to_string(), f).is_some() {
            return Err(CliError::bad(format!("--series: {id} given twice")));
        }
    }
    let design = match &args.design {
        Some(p) => Some(geodesic_core::check::InputFile::read(p).map_err(CliError::bad)?),
        None => args
            .requirements
            .as_ref()
            .and_then(|d| {
                let p = d
                    .parent()
                    .unwrap_or(std::path::Path::new("."))
                    .join("design.yaml");
                p.is_file().then_some(p)
            })
            .map(|p| geodesic_core::check::InputFile::read(&p).map_err(CliError::bad))
            .transpose()?,
    };
    if let Some(f) = &design {
        // read and checked before anything runs (exit 2, nothing written)
        geodesic_housing::Design::from_yaml(&f.text, &f.label).map_err(CliError::bad)?;
    }
    let inputs = geodesic_core::check::ModelInputs {
        budget: budget_file(args.budget.as_ref())?,
        capture: capture_file(args.capture.as_ref())?,
        charge: charge_file(args.charge.as_ref())?,
        design,
        series,
    };
    announce_inputs(args.json, &inputs);
    geodesic_charge::ChargeFile::from_yaml_str(&inputs.charge.text, &inputs.charge.label)
        .map_err(|e| CliError::bad(e.to_string()))?;
    let b = geodesic_release::budget::Budget::from_yaml(&inputs.budget.text, &inputs.budget.label)
        .map_err(|e| CliError::bad(e.to_string()))?;
    if !inputs.budget.label.starts_with("<built-in>") {
        // its adhesion_from (a campaign result) must load before anything runs
        geodesic_release::population::resolve(b, Some(std::path::Path::new(&inputs.budget.label)))
            .map_err(CliError::bad)?;
    }
    geodesic_capture::CaptureInputs::from_yaml_str(&inputs.capture.text, &inputs.capture.label)
        .map_err(|e| CliError::bad(e.to_string()))?;
    // a mission folder (`missions/<name>/requirements/` given with --requirements) may carry
    // its own document identification beside its requirements
    let mission_document = args.requirements.as_ref().and_then(|d| {
        let p = d
            .parent()
            .unwrap_or(std::path::Path::new("."))
            .join("document.yaml");
        p.is_file().then_some(p)
    });
    let document_file = input_file(
        args.document.as_ref().or(mission_document.as_ref()),
        "verification/document.yaml",
        DEFAULT_DOCUMENT_YAML,
    )?;
    let document = geodesic_core::document::Document::from_yaml(
        &document_file.text,
        std::path::Path::new(&document_file.label),
    )
    .map_err(|e| CliError::bad(e.to_string()))?;
    let today = geodesic_core::disposition::today();
    // the repository's default file applies to whatever subset of requirements is loaded; a file
    // given with --dispositions must name loaded requirements only
    let strict = args.dispositions.is_some();
    let disp_path = args.dispositions.clone().or_else(|| {
        let p = PathBuf::from("verification/dispositions.yaml");
        p.is_file().then_some(p)
    });
    let (dispositions, disp_file) = match &disp_path {
        Some(p) => (
            geodesic_core::disposition::load(p, &reqs, today, strict)
                .map_err(|e| CliError::bad(e.to_string()))?,
            Some(geodesic_core::check::InputFile::read(p).map_err(CliError::bad)?),
        ),
        None => (Vec::new(), None),
    };
    let tests_path = args.tests.clone().or_else(|| {
        let p = PathBuf::from("target/geodesic/test-run.json");
        p.is_file().then_some(p)
    });
    let test_run = match &tests_path {
        Some(p) => Some(geodesic_core::testrun::TestRun::load(p).map_err(CliError::bad)?),
        None => None,
    };
    // the recorded run counts only for the tree it ran on: same commit, same content
    let freshness = test_run.as_ref().map(|t| {
        t.freshness(&geodesic_core::testrun::tree_state(std::path::Path::new(
            ".",
        )))
    });

    let staging = geodesic_report::write::Staging::new(&args.reports)
        .map_err(|e| CliError::Io(e.to_string()))?;
    let ctx = geodesic_checks::context(
        reqs.clone(),
        inputs.clone(),
        staging.path().to_path_buf(),
        args.mc_n,
        args.seed,
        args.confidence,
        !crate::progress::enabled(args.json),
    );
    let wanted = |check: &dyn geodesic_core::Check, sel: Option<&crate::only::Selection>| {
        geodesic_checks::is_wanted(check, &reqs) && sel.is_none_or(|s| s.wants(check, &reqs))
    };
    let to_run = registry
        .iter()
        .filter(|c| wanted(c.as_ref(), selection.as_ref()))
        .count()
        + usize::from(
            selection.is_none()
                && !args.no_fidelity
                && reqs.items.iter().any(|r| r.family == "release"),
        );
    let mut task = crate::progress::Task::counter(args.json, "verify", to_run as u64);
    let mut evidence = Vec::new();
    let mut runs = Vec::new();
    let mut timings = Vec::new();
    let run_t0 = Instant::now();
    let mut done = vec![false; registry.len()];
    loop {
        for (i, check) in registry.iter().enumerate() {
            if done[i] || !wanted(check.as_ref(), selection.as_ref()) {
                continue; // none of its requirements is loaded (an orphan check, listed below)
            }
            done[i] = true;
            task.set_label(&format!("verify: check {}", check.name()));
            let t0 = Instant::now();
            let ev = check
                .run(&ctx)
                .map_err(|e| CliError::bad(format!("check {}: {e}", check.name())))?;
            // wall time is not controlled content: the run information's `timings`, which no
            // comparison reads (standard error stays quiet unless --progress or a terminal)
            timings.push(geodesic_report::CheckTiming {
                check: check.name().to_string(),
                wall_s: t0.elapsed().as_secs_f64(),
            });
            task.note(&format!(
                "check {} took {:.1} s",
                check.name(),
                t0.elapsed().as_secs_f64()
            ));
            let mut verifies: Vec<String> =
                check.verifies().iter().map(|s| s.to_string()).collect();
            for e in &ev {
                if !verifies.contains(&e.requirement) {
                    verifies.push(e.requirement.clone());
                }
            }
            runs.push(CheckRun {
                name: check.name().to_string(),
                verifies,
            });
            evidence.push((check.name().to_string(), ev));
            task.inc(1);
        }
        // --only: what the evidence so far shows the chosen rows depend on runs too
        let grew = selection
            .as_mut()
            .is_some_and(|s| s.grow(&evidence, &registry, &reqs));
        if !grew {
            break;
        }
    }
    let tests_label = tests_path.as_ref().map(|p| p.display().to_string());
    let mut matrix = Matrix::build_with(
        &reqs,
        &evidence,
        match (&tests_label, &test_run, &freshness) {
            (Some(file), Some(run), Some(freshness)) => Some(geodesic_core::matrix::TestEvidence {
                file,
                run,
                freshness,
            }),
            _ => None,
        },
        &dispositions,
    );
    // a requirement bound to a check (`check:`) that gave it no evidence: say which check and
    // what it evaluates, not only that no check did
    for row in &mut matrix.requirements {
        let named = reqs.get(&row.id).and_then(|r| r.check.clone());
        if row.status == geodesic_core::matrix::Status::NotVerified
            && row.evidence.is_empty()
            && let Some(name) = named
            && let Some(run) = runs.iter().find(|r| r.name == name)
        {
            row.reason = Some(format!(
                "its check `{name}` ran and gave no evidence for {}: `{name}` evaluates {} (a requirement bound to it must be one of these, or the check taught to evaluate it)",
                row.id,
                run.verifies.join(", ")
            ));
        }
    }
    if let Some(s) = &selection {
        s.apply(&mut matrix);
    }
    for check in &registry {
        if !geodesic_checks::is_wanted(check.as_ref(), &reqs) {
            for id in check.verifies() {
                matrix.orphan_checks.push(geodesic_core::matrix::Orphan {
                    check: check.name().to_string(),
                    requirement: id.to_string(),
                });
            }
        }
    }
    // the fidelity table compares the LISA Pathfinder release with the thesis: only for a
    // requirement set that has the release family
    let lpf = reqs.items.iter().any(|r| r.family == "release");
    // a partial run (--only) leaves the fidelity table out: it is not about the chosen rows
    let mut fidelity = if args.no_fidelity || !lpf || selection.is_some() {
        Vec::new()
    } else {
        task.set_label("verify: fidelity table (Monte Carlo cases adhesion and mechanisms)");
        let t0 = Instant::now();
        let t = geodesic_checks::fidelity::table(&mc, &ctx)
            .map_err(|e| CliError::bad(format!("fidelity table: {e}")))?;
        timings.push(geodesic_report::CheckTiming {
            check: "fidelity table".to_string(),
            wall_s: t0.elapsed().as_secs_f64(),
        });
        task.inc(1);
        t
    };
    // the Drag-Free CubeSat housing's figures, when its requirements are loaded
    if !args.no_fidelity && selection.is_none() && reqs.items.iter().any(|r| r.family == "housing")
    {
        fidelity.extend(
            geodesic_checks::fidelity::dfc_table(&ctx)
                .map_err(|e| CliError::bad(format!("fidelity table: {e}")))?,
        );
    }
    task.finish();
    let timings = geodesic_report::Timings {
        total_s: run_t0.elapsed().as_secs_f64(),
        checks: timings,
    };
    let (commit, dirty) = git_state();
    let report = Report {
        matrix,
        run: RunInfo {
            document,
            document_file,
            geodesic_version: env!("CARGO_PKG_VERSION").to_string(),
            tool_version: env!("CARGO_PKG_VERSION").to_string(),
            commit,
            dirty,
            date: utc_now(),
            command: std::env::args().collect::<Vec<_>>().join(" "),
            requirements: source,
            requirements_hash,
            inputs,
            dispositions: disp_file,
            mc_n: args.mc_n,
            seed: args.seed,
            confidence: args.confidence,
            checks: runs,
            fidelity,
            partial: selection.as_ref().map(|s| s.partial(&reqs)),
            timings,
        },
        reverify: Default::default(),
    };
    let diff = match &args.baseline {
        Some(b) => Some(
            geodesic_report::baseline::diff(&report, b, args.margin_tolerance)
                .map_err(|e| CliError::bad(e.to_string()))?,
        ),
        None => None,
    };
    let mut report = report;
    if let Some(d) = &diff {
        report.reverify = geodesic_report::vcd::reverify_from(d);
    }
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
    let xlsx = geodesic_report::xlsx::render(&report)
        .map_err(|e| CliError::Io(format!("vcd.xlsx: {e}")))?;
    staging.write("vcd.xlsx", &xlsx).map_err(io)?;
    let vcd_html = geodesic_report::html::render_vcd(&report);
    staging.write("vcd.html", vcd_html.as_bytes()).map_err(io)?;
    let page = geodesic_report::html::render(&report, &[staging.path()]);
    staging.write("index.html", page.as_bytes()).map_err(io)?;
    if let Some(d) = &diff {
        let md = geodesic_report::baseline::markdown(d);
        staging
            .write("baseline-diff.md", md.as_bytes())
            .map_err(io)?;
    }
    let junit = geodesic_report::junit::render(&report);
    // the JUnit file is written beside its target first: a bad target fails before the report
    // set is switched, and nothing is left behind
    let junit_pending = match &args.junit {
        Some(j) => Some(
            geodesic_core::output::PendingFile::prepare(j, junit.as_bytes())
                .map_err(|e| CliError::Io(format!("--junit {e}")))?,
        ),
        None => None,
    };
    let written = staging.commit().map_err(io)?;
    if let Some(j) = junit_pending {
        j.commit()
            .map_err(|e| CliError::Io(format!("--junit {e}")))?;
    }
    if args.json {
        println!("{json}");
    } else {
        let color = std::io::stdout().is_terminal();
        print!(
            "{}",
            geodesic_report::terminal::table(&report.matrix, color)
        );
        let names: Vec<String> = written
            .iter()
            .filter(|p| p.parent() == Some(args.reports.as_path()))
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        for l in input_lines(&report.run.inputs) {
            println!("{l}");
        }
        if let Some(p) = &report.run.partial {
            println!("partial run: {}", p.note);
        }
        println!("wrote {}/{{{}}}", args.reports.display(), names.join(","));
    }
    if let Some(d) = &diff {
        for l in geodesic_report::baseline::summary_lines(d) {
            eprintln!("geodesic: {l}");
        }
        if d.regressions == 0 {
            eprintln!(
                "geodesic: no regression against {} ({} requirement(s) changed without regressing)",
                d.baseline,
                d.changes.len()
            );
        }
        if !d.added.is_empty() {
            // named on the gate's output, not only in baseline-diff.md: a new requirement that is
            // not verified passes the gate, one that is non-compliant without disposition fails
            let added: Vec<String> = d
                .added
                .iter()
                .map(|id| {
                    let st = report
                        .matrix
                        .requirements
                        .iter()
                        .find(|r| &r.id == id)
                        .map_or("?", |r| r.status.as_str());
                    format!("{id} ({st})")
                })
                .collect();
            eprintln!("geodesic: added since {}: {}", d.baseline, added.join(", "));
        }
    }
    let mut tests_fail = false;
    if args.require_tests {
        let m = &report.matrix;
        match &m.test_run {
            None => {
                tests_fail = true;
                eprintln!(
                    "geodesic: --require-tests: no recorded test run (run `cargo xtask test`)"
                );
            }
            Some(t) if !t.fresh => {
                tests_fail = true;
                eprintln!(
                    "geodesic: --require-tests: the recorded test run {} is STALE: {}",
                    t.file,
                    t.stale_reason.as_deref().unwrap_or("")
                );
            }
            Some(_) => {}
        }
        for r in &m.requirements {
            let why = match r.tests_status {
                geodesic_core::matrix::TestsStatus::Stale => {
                    Some("its traced test results are stale".to_string())
                }
                geodesic_core::matrix::TestsStatus::Failed
                | geodesic_core::matrix::TestsStatus::Incomplete => {
                    let bad: Vec<String> = r
                        .tests
                        .iter()
                        .filter(|t| t.result != geodesic_core::testrun::TestResult::Passed)
                        .map(|t| format!("{} {}", t.test, t.result.as_str()))
                        .collect();
                    Some(format!("traced test {}", bad.join(", ")))
                }
                _ => None,
            };
            if let Some(why) = why {
                tests_fail = true;
                eprintln!("geodesic: --require-tests: {}: {why}", r.id);
            }
        }
        if m.test_run.as_ref().is_some_and(|t| t.fresh) {
            for id in m.without_test_evidence() {
                tests_fail = true;
                eprintln!(
                    "geodesic: --require-tests: {id}: its verdict ({}) has no passing traced test that asserts its limit or a reference",
                    m.requirements
                        .iter()
                        .find(|r| r.id == id)
                        .map_or("", |r| r.verdict.as_str())
                );
            }
        }
    }
    // With a baseline the gate is the regression count; without one, the verdict.
    let code = match &diff {
        Some(d) => u8::from(d.regressions > 0),
        None => report.matrix.exit_code(),
    };
    Ok(code.max(u8::from(tests_fail)))
}

/// The outputs and the inputs that are read after the checks, checked before any check runs
/// (issue 35): the reports folder (a folder, writable), the JUnit file, the baseline (read and
/// parsed: a missing or malformed one is exit 2 at once, with its line).
fn preflight_outputs(args: &Args) -> Result<(), CliError> {
    if args.reports.exists() && !args.reports.is_dir() {
        return Err(CliError::bad(format!(
            "--reports {}: is not a directory; give a folder for the reports",
            args.reports.display()
        )));
    }
    crate::preflight::out_dir("--reports", &args.reports)?;
    if let Some(j) = &args.junit {
        crate::preflight::out_file("--junit", j)?;
    }
    if let Some(b) = &args.baseline {
        crate::preflight::in_file("--baseline", b)?;
        geodesic_report::baseline::check(b).map_err(|e| CliError::bad(e.to_string()))?;
    }
    if let Some(t) = &args.tests {
        crate::preflight::in_file("--tests", t)?;
    }
    for (flag, f) in [
        ("--budget", &args.budget),
        ("--capture", &args.capture),
        ("--charge", &args.charge),
        ("--dispositions", &args.dispositions),
        ("--document", &args.document),
        ("--design", &args.design),
    ] {
        if let Some(f) = f {
            crate::preflight::in_file(flag, f)?;
        }
    }
    Ok(())
}

/// The repository's `verification/document.yaml`, built into the binary.
pub const DEFAULT_DOCUMENT_YAML: &str = include_str!("../../../document.yaml");

/// An input file that is not a model input (the document identification): `path` if given,
/// else the repository's copy at `default_rel` (relative to the current directory) if present,
/// else the copy built into the binary. Model inputs: [`crate::inputs::resolve`].
pub fn input_file(
    path: Option<&PathBuf>,
    default_rel: &str,
    builtin: &str,
) -> Result<geodesic_core::check::InputFile, CliError> {
    match path {
        Some(p) => geodesic_core::check::InputFile::read(p).map_err(CliError::bad),
        None if std::path::Path::new(default_rel).is_file() => {
            geodesic_core::check::InputFile::read(std::path::Path::new(default_rel))
                .map_err(CliError::bad)
        }
        None => Ok(geodesic_core::check::InputFile::new(
            format!("<built-in>/{default_rel}"),
            builtin,
        )),
    }
}

/// The model inputs of a run, each with where it was resolved from and its SHA-256.
fn input_lines(inputs: &geodesic_core::check::ModelInputs) -> Vec<String> {
    use crate::inputs::{ModelInput, line};
    vec![
        line(ModelInput::Budget, &inputs.budget),
        line(ModelInput::Capture, &inputs.capture),
        line(ModelInput::Charge, &inputs.charge),
    ]
}

/// With `--json --progress`, the model inputs on standard error ([`crate::inputs::announce`]).
fn announce_inputs(json: bool, inputs: &geodesic_core::check::ModelInputs) {
    use crate::inputs::{ModelInput, announce};
    announce(json, ModelInput::Budget, &inputs.budget);
    announce(json, ModelInput::Capture, &inputs.capture);
    announce(json, ModelInput::Charge, &inputs.charge);
}

/// The release budget file, resolved as every command resolves it ([`crate::inputs::resolve`]).
pub fn budget_file(path: Option<&PathBuf>) -> Result<geodesic_core::check::InputFile, CliError> {
    crate::inputs::resolve(
        crate::inputs::ModelInput::Budget,
        path.map(PathBuf::as_path),
    )
}

/// The charge inputs file ([`crate::inputs::resolve`]).
pub fn charge_file(path: Option<&PathBuf>) -> Result<geodesic_core::check::InputFile, CliError> {
    crate::inputs::resolve(
        crate::inputs::ModelInput::Charge,
        path.map(PathBuf::as_path),
    )
}

/// The capture inputs file ([`crate::inputs::resolve`]).
pub fn capture_file(path: Option<&PathBuf>) -> Result<geodesic_core::check::InputFile, CliError> {
    crate::inputs::resolve(
        crate::inputs::ModelInput::Capture,
        path.map(PathBuf::as_path),
    )
}
