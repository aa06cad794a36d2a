//! The verify pipeline: resolve a mission's inputs -> run its checks -> build the compliance
//! matrix -> compare with a baseline -> write every report format, whole or not at all.
//!
//! [`run`] returns a typed [`Outcome`]; the caller (the `geodesic` command line or a project's
//! own harness) prints it. Exit status: 0 nothing non-compliant (with a baseline: nothing
//! regressed), 1 a non-compliance or a regression (or a failed `require_tests`), and an
//! [`Error`] (exit 2) on bad input, with nothing written.

use crate::error::{Error, InputKind};
use crate::mission::Mission;
use crate::only::Selection;
use crate::progress::Task;
use geodesic_core::Requirements;
use geodesic_core::check::{Check, InputFile, InputOrigin, Inputs, is_wanted};
use geodesic_core::matrix::Matrix;
use geodesic_report::{CheckRun, Report, RunInfo};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How to run: the flags of `verify`, typed.
#[derive(Clone, Debug)]
pub struct Options {
    /// Requirement folder instead of the mission's.
    pub requirements: Option<PathBuf>,
    /// Input files instead of the mission's defaults, by input name.
    pub inputs: BTreeMap<String, PathBuf>,
    /// Dispositions file instead of the mission's (then every entry must name a loaded
    /// requirement).
    pub dispositions: Option<PathBuf>,
    /// Document identification instead of the mission's.
    pub document: Option<PathBuf>,
    /// The recorded test run [default: target/geodesic/test-run.json if present].
    pub tests: Option<PathBuf>,
    /// Exit 1 unless every verdict has fresh passing traced tests.
    pub require_tests: bool,
    /// The reports folder.
    pub reports: PathBuf,
    /// Values of the run options the mission declares (`mission.yaml` `options:`), by name
    /// (`mc-n`); a declared option not given takes its default.
    pub options: BTreeMap<String, u64>,
    /// Confidence of the bounds a sampled verdict is decided by [-].
    pub confidence: f64,
    /// Also write JUnit XML to this file.
    pub junit: Option<PathBuf>,
    /// Gate against this compliance.json.
    pub baseline: Option<PathBuf>,
    /// Margin change that counts as moved (fraction of the limit) [-].
    pub margin_tolerance: f64,
    /// Skip the reference (fidelity) table.
    pub no_fidelity: bool,
    /// Time series by requirement ID (`ID=FILE.yaml`).
    pub series: Vec<String>,
    /// Run only these requirements and what they depend on.
    pub only: Vec<String>,
    /// The caller prints JSON (progress is then off unless asked for).
    pub json: bool,
    /// The version written in the reports.
    pub tool_version: String,
    /// The command line written in the reports.
    pub command: String,
    /// The commit the running binary was built from (the command line's `build.rs`), when
    /// known; the run says when it is not the commit of the tree it judges.
    pub build_commit: Option<String>,
    /// The command that records the traced tests' run, named when there is none or it is stale
    /// (`cargo xtask test` here; a project's harness: `cargo run -- test`).
    pub test_command: String,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            requirements: None,
            inputs: BTreeMap::new(),
            dispositions: None,
            document: None,
            tests: None,
            require_tests: false,
            reports: PathBuf::from("reports"),
            options: BTreeMap::new(),
            confidence: DEFAULT_CONFIDENCE,
            junit: None,
            baseline: None,
            margin_tolerance: 0.01,
            no_fidelity: false,
            series: Vec::new(),
            only: Vec::new(),
            json: false,
            tool_version: env!("CARGO_PKG_VERSION").to_string(),
            command: std::env::args().collect::<Vec<_>>().join(" "),
            build_commit: None,
            test_command: geodesic_core::testrun::RECORD_COMMAND.to_string(),
        }
    }
}

/// The confidence of the bounds a sampled verdict is decided by, unless told otherwise [-].
pub const DEFAULT_CONFIDENCE: f64 = 0.95;

/// The lowest `--confidence` accepted [-]: below it a one-sided bound falls on the wrong side of
/// its estimate.
pub const MIN_CONFIDENCE: f64 = 0.5;

/// What a run produced.
pub struct Outcome {
    /// The report (matrix and run information).
    pub report: Report,
    /// The comparison with the baseline, when gated.
    pub diff: Option<geodesic_report::baseline::Diff>,
    /// `compliance.json`'s text.
    pub json: String,
    /// The files written (paths under the reports folder, and the JUnit file).
    pub written: Vec<PathBuf>,
    /// Lines for standard error (the gate's summary, --require-tests findings), without the
    /// program's prefix.
    pub messages: Vec<String>,
    /// The exit status: 0 or 1.
    pub code: u8,
}

/// The requirement set: `dir` if given, else the mission's folder if present, else its
/// built-in copy; with its source label and the SHA-256 over its files (names and bytes,
/// sorted by name).
pub fn load_requirements(
    mission: &Mission,
    dir: Option<&PathBuf>,
) -> Result<(Requirements, String, String), Error> {
    let own = mission.path(&mission.spec.requirements);
    let dir = match dir {
        Some(d) => Some(d.clone()),
        None if own.is_dir() => Some(own),
        None => None,
    };
    match dir {
        Some(d) => {
            let reqs = Requirements::load_dir(&d)?;
            let mut files: Vec<PathBuf> = std::fs::read_dir(&d)
                .map_err(|e| Error::unreadable(format!("{}: {e}", d.display())).in_file(&d, 0))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "yml")))
                .collect();
            files.sort();
            let mut parts = Vec::new();
            for f in &files {
                let name = f
                    .file_name()
                    .map_or(String::new(), |n| n.to_string_lossy().into());
                let bytes = std::fs::read(f).map_err(|e| {
                    Error::unreadable(format!("{}: {e}", f.display())).in_file(f, 0)
                })?;
                parts.push((name, bytes));
            }
            let hash = geodesic_util::hash::sha256_parts(
                parts.iter().map(|(n, b)| (n.as_str(), b.as_slice())),
            );
            Ok((reqs, d.display().to_string(), hash))
        }
        None => {
            let builtin = mission.builtin_requirements();
            if builtin.is_empty() {
                return Err(Error::unreadable(format!(
                    "{}: no requirement folder (mission {} declares `requirements: {}`)",
                    mission.path(&mission.spec.requirements).display(),
                    mission.spec.name,
                    mission.spec.requirements
                )));
            }
            let src: Vec<(PathBuf, String)> = builtin
                .iter()
                .map(|(n, t)| (PathBuf::from(format!("<built-in>/{n}")), t.to_string()))
                .collect();
            let hash =
                geodesic_util::hash::sha256_parts(builtin.iter().map(|(n, t)| (*n, t.as_bytes())));
            Ok((Requirements::from_sources(&src)?, "built-in".into(), hash))
        }
    }
}

/// Resolves one of the mission's files: `given` if set, else its path on disk if present, else
/// the built-in copy (`None` when there is none).
pub fn resolve_file(
    mission: &Mission,
    rel: &str,
    given: Option<&Path>,
    flag: &str,
) -> Result<Option<InputFile>, Error> {
    let read = |p: &Path, origin: InputOrigin| -> Result<InputFile, Error> {
        let text = geodesic_util::fsio::read_text(p, geodesic_util::fsio::MAX_YAML_BYTES).map_err(
            |e| {
                let at = match e.line() {
                    0 => String::new(),
                    l => format!(":{l}"),
                };
                let by = match origin {
                    InputOrigin::Given => format!("{flag} "),
                    _ => String::new(),
                };
                Error::unreadable(format!("{by}{}{at}: {}", p.display(), e.cause()))
                    .in_file(p, e.line())
            },
        )?;
        Ok(InputFile::new(p.display().to_string(), text).with_origin(origin))
    };
    if let Some(p) = given {
        return read(p, InputOrigin::Given).map(Some);
    }
    let on_disk = mission.path(rel);
    if on_disk.is_file() {
        return read(&on_disk, InputOrigin::Repository).map(Some);
    }
    Ok(mission.builtin.get(rel).map(|t| {
        InputFile::new(format!("<built-in>/{}", on_disk.display()), *t)
            .with_origin(InputOrigin::BuiltIn)
    }))
}

/// The mission's declared inputs, each given, found on disk or built in; validated by the
/// mission before anything runs.
pub fn resolve_inputs(mission: &Mission, opts: &Options) -> Result<Inputs, Error> {
    for name in opts.inputs.keys() {
        if !mission.spec.inputs.iter().any(|i| &i.name == name) {
            return Err(Error::usage(format!(
                "--{name}: mission {} declares no input `{name}` (its inputs: {})",
                mission.spec.name,
                mission
                    .spec
                    .inputs
                    .iter()
                    .map(|i| i.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    let mut inputs = Inputs::default();
    for spec in &mission.spec.inputs {
        let flag = format!("--{}", spec.name);
        let f = resolve_file(
            mission,
            &spec.path,
            opts.inputs.get(&spec.name).map(PathBuf::as_path),
            &flag,
        )?;
        let Some(f) = f else {
            return Err(Error::unreadable(format!(
                "{}: not found (input `{}` of mission {}; give it with {flag} FILE)",
                mission.path(&spec.path).display(),
                spec.name,
                mission.spec.name
            ))
            .in_file(mission.path(&spec.path), 0));
        };
        mission
            .validate_input(&spec.name, &f)
            .map_err(Error::invalid)?;
        inputs.insert(&spec.name, &spec.words, f.with_parameters());
    }
    Ok(inputs)
}

fn series_inputs(
    mission: &Mission,
    reqs: &Requirements,
    series: &[String],
) -> Result<BTreeMap<String, InputFile>, Error> {
    let mut out = BTreeMap::new();
    for s in series {
        let Some((id, file)) = s.split_once('=') else {
            return Err(Error::usage(format!(
                "--series {s}: write ID=FILE.yaml (e.g. --series ACC-ASD=data/spectra/acc.yaml)"
            )));
        };
        let Some(r) = reqs.get(id.trim()) else {
            return Err(Error::unknown_id(format!(
                "--series {s}: no requirement {id} is loaded"
            )));
        };
        if r.spectrum.is_none() {
            return Err(Error::usage(format!(
                "--series {s}: {id} is not a spectral requirement (it has no `spectrum`)"
            )));
        }
        let f = InputFile::read(Path::new(file.trim()))
            .map_err(|e| Error::unreadable(format!("--series {e}")))?;
        // read and checked before anything runs: a bad series is exit 2 with its file and line
        mission
            .validate_series(Path::new(file.trim()))
            .map_err(Error::malformed)?;
        if out.insert(r.id.to_string(), f).is_some() {
            return Err(Error::conflict(format!("--series: {id} given twice")));
        }
    }
    Ok(out)
}

/// The outputs and the inputs read after the checks, checked before any check runs: the
/// reports folder, the JUnit file, the baseline (read and parsed), the given files.
fn preflight(opts: &Options) -> Result<(), Error> {
    if opts.reports.exists() && !opts.reports.is_dir() {
        return Err(Error::usage(format!(
            "--reports {}: is not a directory; give a folder for the reports",
            opts.reports.display()
        )));
    }
    crate::preflight::out_dir("--reports", &opts.reports)?;
    if let Some(j) = &opts.junit {
        crate::preflight::out_file("--junit", j)?;
    }
    if let Some(b) = &opts.baseline {
        crate::preflight::in_file("--baseline", b)?;
        geodesic_report::baseline::check(b)
            .map_err(|e| Error::input_from(InputKind::Evidence, e).in_file(b, 0))?;
    }
    if let Some(t) = &opts.tests {
        crate::preflight::in_file("--tests", t)?;
    }
    for (name, f) in &opts.inputs {
        crate::preflight::in_file(&format!("--{name}"), f)?;
    }
    for (flag, f) in [
        ("--dispositions", &opts.dispositions),
        ("--document", &opts.document),
    ] {
        if let Some(f) = f {
            crate::preflight::in_file(flag, f)?;
        }
    }
    Ok(())
}

/// Checks the options and returns the mission's run options for this run.
fn check_options(
    mission: &Mission,
    opts: &Options,
) -> Result<geodesic_core::check::RunOptions, Error> {
    let run_options = mission
        .spec
        .run_options(&opts.options)
        .map_err(Error::usage)?;
    // below 0.5 a one-sided bound lies on the wrong side of its estimate: an upper bound
    // below the median would pass what the estimate fails
    if !(opts.confidence.is_finite() && (MIN_CONFIDENCE..1.0).contains(&opts.confidence)) {
        return Err(Error::usage(format!(
            "--confidence {}: must be at least {MIN_CONFIDENCE} and below 1, e.g. 0.95 (a bound at a lower confidence is weaker than the estimate it bounds)",
            opts.confidence
        )));
    }
    if !(opts.margin_tolerance.is_finite() && opts.margin_tolerance >= 0.0) {
        return Err(Error::usage(
            "--margin-tolerance must be a non-negative number",
        ));
    }
    Ok(run_options)
}

/// The document identification: `--document`, else `document.yaml` beside a given requirement
/// folder (a mission folder), else the mission's, else its built-in copy.
fn document_file(mission: &Mission, opts: &Options) -> Result<InputFile, Error> {
    let beside = opts.requirements.as_ref().and_then(|d| {
        let p = d.parent().unwrap_or(Path::new(".")).join("document.yaml");
        p.is_file().then_some(p)
    });
    if let Some(p) = opts.document.as_ref().or(beside.as_ref()) {
        return InputFile::read(p).map_err(Error::unreadable);
    }
    let rel = mission.spec.document.as_deref().unwrap_or("document.yaml");
    let on_disk = mission.path(rel);
    if on_disk.is_file() {
        return InputFile::read(&on_disk).map_err(Error::unreadable);
    }
    match mission.builtin.get(rel) {
        Some(t) => Ok(InputFile::new(
            format!("<built-in>/{}", on_disk.display()),
            *t,
        )),
        None => Err(Error::unreadable(format!(
            "{}: not found (the document identification of mission {}: id, issue, title, project)",
            on_disk.display(),
            mission.spec.name
        ))),
    }
}

/// Everything read before a check runs.
struct Loaded {
    reqs: Requirements,
    source: String,
    requirements_hash: String,
    inputs: Inputs,
    document: geodesic_core::document::Document,
    document_file: InputFile,
    dispositions: Vec<geodesic_core::disposition::Disposition>,
    disp_file: Option<InputFile>,
    tests_path: Option<PathBuf>,
    test_run: Option<geodesic_core::testrun::TestRun>,
    freshness: Option<geodesic_core::testrun::Freshness>,
    unmatched_dispositions: Vec<String>,
}

fn load(mission: &Mission, opts: &Options, names: &[&str]) -> Result<Loaded, Error> {
    let (reqs, source, requirements_hash) = load_requirements(mission, opts.requirements.as_ref())?;
    reqs.validate_checks(names)?;
    let mut inputs = resolve_inputs(mission, opts)?;
    inputs.series = series_inputs(mission, &reqs, &opts.series)?;
    let document_file = document_file(mission, opts)?;
    let document = geodesic_core::document::Document::from_yaml(
        &document_file.text,
        Path::new(&document_file.label),
    )?;
    let today = geodesic_core::disposition::today();
    // the mission's own file applies to whatever subset of requirements is loaded; a file
    // given with --dispositions must name loaded requirements only
    let strict = opts.dispositions.is_some();
    let disp_path = opts.dispositions.clone().or_else(|| {
        let p = mission.path(mission.spec.dispositions.as_deref()?);
        p.is_file().then_some(p)
    });
    let (dispositions, disp_file) = match &disp_path {
        Some(p) => (
            geodesic_core::disposition::load(p, &reqs, today, strict)?,
            Some(InputFile::read(p).map_err(Error::unreadable)?),
        ),
        None => (Vec::new(), None),
    };
    // a disposition whose requirement is not loaded (renamed, removed) is said, not dropped
    let unmatched_dispositions = match &disp_file {
        Some(f) => geodesic_core::disposition::unmatched(&f.text, Path::new(&f.label), &reqs),
        None => Vec::new(),
    };
    let tests_path = opts.tests.clone().or_else(|| {
        let p = PathBuf::from("target/geodesic/test-run.json");
        p.is_file().then_some(p)
    });
    let mut test_run = match &tests_path {
        Some(p) => Some(
            geodesic_core::testrun::TestRun::load(p)
                .map_err(|e| Error::evidence(e).in_file(p, 0))?,
        ),
        None => None,
    };
    // the recorded run counts only for the tree it ran on (same commit, same content), each
    // record only where that tree holds its call, and only if what verify reads is in it
    let tree = geodesic_core::testrun::tree_state_any(Path::new("."));
    let freshness = test_run.as_mut().map(|t| {
        let f = t.freshness_for(&tree, &opts.test_command);
        let Ok(tree) = &tree else { return f };
        geodesic_core::testrun::check_records(t, tree);
        let hidden = geodesic_core::testrun::uncovered(tree, &read_files(&source, &inputs, &disp_path, &document_file));
        match (f, hidden.is_empty()) {
            (geodesic_core::testrun::Freshness::Fresh, false) => {
                geodesic_core::testrun::Freshness::Stale {
                    reason: format!(
                        "verify reads {}, which the tree fingerprint does not cover (ignored or hidden from git, or outside the work tree): the tests did not run on it",
                        hidden.join(", ")
                    ),
                }
            }
            (f, _) => f,
        }
    });
    Ok(Loaded {
        reqs,
        source,
        requirements_hash,
        inputs,
        document,
        document_file,
        dispositions,
        disp_file,
        tests_path,
        test_run,
        freshness,
        unmatched_dispositions,
    })
}

/// The files a run reads from disk: the requirement files, the input files given or found on
/// disk (not the built-in copies), the dispositions and the document, the series.
fn read_files(
    requirements: &str,
    inputs: &Inputs,
    dispositions: &Option<PathBuf>,
    document: &InputFile,
) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = Vec::new();
    if let Ok(rd) = std::fs::read_dir(requirements) {
        let mut files: Vec<PathBuf> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "yml")))
            .collect();
        files.sort();
        out.extend(files);
    }
    for (_, _, f) in inputs.iter() {
        if f.origin != Some(InputOrigin::BuiltIn) {
            out.push(PathBuf::from(&f.label));
        }
    }
    out.extend(inputs.series.values().map(|f| PathBuf::from(&f.label)));
    out.extend(dispositions.iter().cloned());
    if !document.label.starts_with("<built-in>") {
        out.push(PathBuf::from(&document.label));
    }
    out
}

/// The evidence of the checks that ran.
struct Ran {
    evidence: Vec<(String, Vec<geodesic_core::Evidence>)>,
    runs: Vec<CheckRun>,
    timings: Vec<geodesic_report::CheckTiming>,
}

fn run_checks(
    checks: &[Box<dyn Check>],
    ctx: &geodesic_core::CheckContext,
    reqs: &Requirements,
    selection: &mut Option<Selection>,
    task: &mut Task,
) -> Result<Ran, Error> {
    let wanted = |check: &dyn Check, sel: Option<&Selection>| {
        is_wanted(check, reqs) && sel.is_none_or(|s| s.wants(check, reqs))
    };
    let mut ran = Ran {
        evidence: Vec::new(),
        runs: Vec::new(),
        timings: Vec::new(),
    };
    let mut done = vec![false; checks.len()];
    loop {
        for (i, check) in checks.iter().enumerate() {
            if done[i] || !wanted(check.as_ref(), selection.as_ref()) {
                continue; // none of its requirements is loaded (an orphan check, listed below)
            }
            done[i] = true;
            task.set_label(&format!("verify: check {}", check.name()));
            let t0 = Instant::now();
            let ev = check.run(ctx).map_err(|e| Error::check(check.name(), e))?;
            // wall time is not controlled content: the run information's `timings`, which no
            // comparison reads (standard error stays quiet unless --progress or a terminal)
            ran.timings.push(geodesic_report::CheckTiming {
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
            ran.runs.push(CheckRun {
                name: check.name().to_string(),
                verifies,
            });
            ran.evidence.push((check.name().to_string(), ev));
            task.inc(1);
        }
        // --only: what the evidence so far shows the chosen rows depend on runs too
        let grew = selection
            .as_mut()
            .is_some_and(|s| s.grow(&ran.evidence, checks, reqs));
        if !grew {
            return Ok(ran);
        }
    }
}

fn build_matrix(
    l: &Loaded,
    ran: &Ran,
    checks: &[Box<dyn Check>],
    selection: Option<&Selection>,
) -> Matrix {
    let tests_label = l.tests_path.as_ref().map(|p| p.display().to_string());
    let mut matrix = Matrix::build_with(
        &l.reqs,
        &ran.evidence,
        match (&tests_label, &l.test_run, &l.freshness) {
            (Some(file), Some(run), Some(freshness)) => Some(geodesic_core::matrix::TestEvidence {
                file,
                run,
                freshness,
            }),
            _ => None,
        },
        &l.dispositions,
    );
    // a requirement bound to a check (`check:`) that gave it no evidence: say which check and
    // what it evaluates, not only that no check did
    for row in &mut matrix.requirements {
        let named = l.reqs.get(&row.id).and_then(|r| r.check.clone());
        if row.status == geodesic_core::matrix::Status::NotVerified
            && row.evidence.is_empty()
            && let Some(name) = named
            && let Some(run) = ran.runs.iter().find(|r| r.name == name)
        {
            row.reason = Some(format!(
                "its check `{name}` ran and gave no evidence for {}: `{name}` evaluates {} (a requirement bound to it must be one of these, or the check taught to evaluate it)",
                row.id,
                run.verifies.join(", ")
            ));
        }
    }
    geodesic_core::credibility::apply(&mut matrix, &l.reqs, &l.inputs);
    if let Some(s) = selection {
        s.apply(&mut matrix);
    }
    for check in checks {
        if !is_wanted(check.as_ref(), &l.reqs) {
            for id in check.verifies() {
                matrix.orphan_checks.push(geodesic_core::matrix::Orphan {
                    check: check.name().to_string(),
                    requirement: id.to_string(),
                });
            }
        }
    }
    matrix
}

/// Runs the pipeline for `mission` and writes the report set (whole or not at all).
pub fn run(mission: &Mission, opts: &Options) -> Result<Outcome, Error> {
    let run_options = check_options(mission, opts)?;
    preflight(opts)?;
    crate::only::refuse_partial_gate(&opts.only, opts.baseline.as_deref())?;
    let session = mission.session();
    let names: Vec<&str> = session.checks.iter().map(|c| c.name()).collect();
    let l = load(mission, opts, &names)?;
    let mut selection = Selection::parse(&opts.only, &l.reqs)?;
    announce_inputs(opts.json, &l.inputs);

    let staging = geodesic_report::write::Staging::new(&opts.reports).map_err(Error::io)?;
    let ctx = geodesic_core::CheckContext {
        requirements: std::sync::Arc::new(l.reqs.clone()),
        inputs: std::sync::Arc::new(l.inputs.clone()),
        reports_dir: staging.path().to_path_buf(),
        options: run_options.clone(),
        confidence: opts.confidence,
        quiet: !crate::progress::enabled(opts.json),
    };
    let with_reference = session.reference.is_some() && !opts.no_fidelity && selection.is_none();
    let to_run = session
        .checks
        .iter()
        .filter(|c| is_wanted(c.as_ref(), &l.reqs))
        .filter(|c| {
            selection
                .as_ref()
                .is_none_or(|s| s.wants(c.as_ref(), &l.reqs))
        })
        .count()
        + usize::from(with_reference);
    let mut task = Task::counter(opts.json, "verify", to_run as u64);
    let run_t0 = Instant::now();
    let mut ran = run_checks(&session.checks, &ctx, &l.reqs, &mut selection, &mut task)?;
    let matrix = build_matrix(&l, &ran, &session.checks, selection.as_ref());
    // the reference table (a partial run leaves it out: it is not about the chosen rows)
    let fidelity = match (&session.reference, with_reference) {
        (Some(table), true) => {
            task.set_label("verify: reference table");
            let t0 = Instant::now();
            let t = table(&ctx).map_err(|e| Error::model_from("fidelity table", e))?;
            if !t.is_empty() {
                ran.timings.push(geodesic_report::CheckTiming {
                    check: "fidelity table".to_string(),
                    wall_s: t0.elapsed().as_secs_f64(),
                });
            }
            task.inc(1);
            t
        }
        _ => Vec::new(),
    };
    task.finish();
    let timings = geodesic_report::Timings {
        total_s: run_t0.elapsed().as_secs_f64(),
        checks: ran.timings,
    };
    let (commit, dirty) = git_state();
    let build_note = build_note(opts.build_commit.as_deref(), &commit);
    let partial = selection.as_ref().map(|s| s.partial(&l.reqs));
    let report = Report {
        matrix,
        run: RunInfo {
            document: l.document,
            document_file: l.document_file,
            geodesic_version: env!("CARGO_PKG_VERSION").to_string(),
            tool_version: opts.tool_version.clone(),
            commit,
            dirty,
            date: utc_now(),
            command: opts.command.clone(),
            requirements: l.source,
            requirements_hash: l.requirements_hash,
            inputs: l.inputs,
            dispositions: l.disp_file,
            options: run_options,
            confidence: opts.confidence,
            checks: ran.runs,
            fidelity,
            reference: mission
                .spec
                .reference
                .as_ref()
                .map(|r| geodesic_report::ReferenceHeading {
                    title: r.title.clone(),
                    column: r.column.clone(),
                })
                .unwrap_or_default(),
            partial,
            timings,
            build_note,
            build_commit: opts.build_commit.clone(),
            unmatched_dispositions: l.unmatched_dispositions,
        },
        reverify: Default::default(),
    };
    finish(report, opts, staging)
}

/// Compares with the baseline, writes the report set and says the verdict.
fn finish(
    mut report: Report,
    opts: &Options,
    staging: geodesic_report::write::Staging,
) -> Result<Outcome, Error> {
    let diff = match &opts.baseline {
        Some(b) => Some(
            geodesic_report::baseline::diff(&report, b, opts.margin_tolerance)
                .map_err(|e| Error::evidence(e.to_string()).in_file(b, 0))?,
        ),
        None => None,
    };
    if let Some(d) = &diff {
        report.reverify = geodesic_report::vcd::reverify_from(d);
    }
    // through serde_json::Value: keys in alphabetical order, as the reports have always had them
    let doc = serde_json::to_value(crate::schema::VerifyDoc {
        report: &report,
        baseline_diff: diff.as_ref(),
    })
    .map_err(Error::io)?;
    let json = serde_json::to_string_pretty(&doc).map_err(Error::io)?;
    let io = |e: geodesic_report::write::WriteError| Error::io(e);
    let input = geodesic_report::formats::RenderInput {
        report: &report,
        diff: diff.as_ref(),
        json: &json,
        dir: staging.path(),
    };
    for f in geodesic_report::formats::formats() {
        if let Some(bytes) = f.render(&input).map_err(Error::io)? {
            staging.write(f.file(), &bytes).map_err(io)?;
        }
    }
    let junit = geodesic_report::junit::render(&report);
    // the JUnit file is written beside its target first: a bad target fails before the report
    // set is switched, and nothing is left behind
    let junit_pending = match &opts.junit {
        Some(j) => Some(
            geodesic_util::output::PendingFile::prepare(j, junit.as_bytes())
                .map_err(|e| Error::io(format!("--junit {e}")))?,
        ),
        None => None,
    };
    let mut written = staging.commit().map_err(io)?;
    if let Some(j) = junit_pending {
        j.commit().map_err(|e| Error::io(format!("--junit {e}")))?;
        written.extend(opts.junit.clone());
    }
    let mut messages = Vec::new();
    messages.extend(report.run.build_note.iter().map(|n| format!("note: {n}")));
    messages.extend(
        report
            .run
            .unmatched_dispositions
            .iter()
            .map(|n| format!("dispositions: {n}")),
    );
    if let Some(d) = &diff {
        gate_messages(d, &report, &mut messages);
    }
    let tests_fail =
        opts.require_tests && require_tests(&report.matrix, &opts.test_command, &mut messages);
    // With a baseline the gate is the regression count; without one, the verdict.
    let code = match &diff {
        Some(d) => u8::from(d.regressions > 0),
        None => report.matrix.exit_code(),
    };
    Ok(Outcome {
        report,
        diff,
        json,
        written,
        messages,
        code: code.max(u8::from(tests_fail)),
    })
}

fn gate_messages(d: &geodesic_report::baseline::Diff, report: &Report, out: &mut Vec<String>) {
    out.extend(geodesic_report::baseline::summary_lines(d));
    if d.regressions == 0 {
        out.push(format!(
            "no regression against {} ({} requirement(s) changed without regressing)",
            d.baseline,
            d.changes.len()
        ));
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
        out.push(format!("added since {}: {}", d.baseline, added.join(", ")));
    }
}

/// `--require-tests`: whether the test evidence fails the run, with why.
fn require_tests(m: &Matrix, test_command: &str, out: &mut Vec<String>) -> bool {
    let mut fail = false;
    match &m.test_run {
        None => {
            fail = true;
            out.push(format!(
                "--require-tests: no recorded test run (run `{test_command}`)"
            ));
        }
        Some(t) if !t.fresh => {
            fail = true;
            out.push(format!(
                "--require-tests: the recorded test run {} is STALE: {}",
                t.file,
                t.stale_reason.as_deref().unwrap_or("")
            ));
        }
        Some(_) => {}
    }
    for r in &m.requirements {
        let why = match r.tests_status {
            geodesic_core::matrix::TestsStatus::Stale => {
                Some("its traced test results are stale".to_string())
            }
            geodesic_core::matrix::TestsStatus::Rejected => {
                let bad: Vec<String> = r
                    .tests
                    .iter()
                    .filter_map(|t| t.rejected.as_ref().map(|w| format!("{} ({w})", t.test)))
                    .collect();
                Some(format!(
                    "traced test record rejected against the tree: {}",
                    bad.join(", ")
                ))
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
            fail = true;
            out.push(format!("--require-tests: {}: {why}", r.id));
        }
    }
    if m.test_run.as_ref().is_some_and(|t| t.fresh) {
        for id in m.without_test_evidence() {
            fail = true;
            out.push(format!(
                "--require-tests: {id}: its verdict ({}) has no passing traced test that asserts its limit or a reference",
                m.requirements
                    .iter()
                    .find(|r| r.id == id)
                    .map_or("", |r| r.verdict.as_str())
            ));
        }
    }
    fail
}

/// One line per input file: `design inputs: design.yaml (the repository's copy), sha256 ...`
/// (the whole hash).
pub fn input_lines(inputs: &Inputs) -> Vec<String> {
    inputs
        .iter()
        .map(|(_, words, f)| {
            format!(
                "{words}: {} ({}), sha256 {}",
                f.label,
                f.origin.map_or("given", InputOrigin::words),
                f.sha256
            )
        })
        .collect()
}

/// With `--json --progress`, the input lines on standard error.
fn announce_inputs(json: bool, inputs: &Inputs) {
    if json && crate::progress::enabled(json) {
        for l in input_lines(inputs) {
            eprintln!("geodesic: {l}");
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

/// What a run says when the binary was built from another commit than the tree's `commit`
/// (`None` when they agree, or when either is unknown).
pub fn build_note(build: Option<&str>, commit: &str) -> Option<String> {
    let build = build?;
    let short = |c: &str| c.chars().take(12).collect::<String>();
    (build != commit && build != "unknown" && commit != "unknown").then(|| {
        format!(
            "this binary was built from commit {}, the work tree is at {}: the checks that ran are those of the build (rebuild to judge the tree with its own code)",
            short(build),
            short(commit)
        )
    })
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
