//! Every number in every JSON document a command writes (standard output with `--json`, and
//! the JSON files it writes: compliance.json, Monte Carlo parts, truth files, fit histories)
//! is finite or explicitly absent, over the fuzz corpus (`fuzz/`: each target's seeds, its
//! regression inputs, and mutations of the seeds its parser accepts, drawn with a fixed seed)
//! and hostile flag values.
//!
//! JSON has no NaN nor infinity: serde_json writes them as `null`, so a non-finite value shows
//! as a `null`. A `null` is accepted only where it is a documented absence
//! ([`null_is_documented`], `docs/outputs.md`): a field without a value whose object says why
//! (`reason`, `status: not-verified`), or one of the optional fields listed there. Anything
//! else, and any text that is not JSON (`NaN`, `inf` written by hand), fails the test with the
//! command and the path. So does a free parameter (an object with a `value`, not `fixed`)
//! quoted with a `sigma` of exactly 0 (issue 48).

mod common;
use common::{scratch, workspace};

use geodesic_fuzz::{Ctx, Outcome};
use rand::SeedableRng;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Largest time one command may take here (debug build): beyond, a hang.
const TIMEOUT: Duration = Duration::from_secs(240);

/// Runs `geodesic ARGS` in `cwd`, killed after [`TIMEOUT`] (a failure: no hang).
fn run(args: &[String], cwd: &Path) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_geodesic"))
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run geodesic");
    // read the pipes on threads so that a large output cannot block the child
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut out, &mut v).ok();
        v
    });
    let t_err = std::thread::spawn(move || {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut err, &mut v).ok();
        v
    });
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            panic!("geodesic {args:?} did not finish in {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output {
        status,
        stdout: t_out.join().unwrap(),
        stderr: t_err.join().unwrap(),
    }
}

/// Whether a `null` at `key` of the object `obj` is a documented absence (docs/outputs.md).
fn null_is_documented(key: &str, obj: &serde_json::Map<String, Value>) -> bool {
    let says_why = obj.get("reason").is_some_and(|r| !r.is_null())
        || obj.get("status").and_then(Value::as_str) == Some("not-verified");
    match key {
        // optional texts and objects: there is none
        "basis" | "reason" | "disposition" | "parent" | "probability" | "limit" | "added"
        | "missing" | "expires" | "shard" | "svg" | "explained_reason" | "close_out"
        | "dispositions" | "test_run" | "baseline_diff" => true,
        // numbers without a value, where the object says why
        "value" => says_why,
        // a discover round without a runner-up candidate has no margin
        "margin" => says_why || obj.contains_key("added"),
        "parent_margin" => obj.get("parent").is_some_and(Value::is_null),
        // discover's round 0 adds nothing: no delta BIC
        "delta_bic" => obj.get("added").is_some_and(Value::is_null),
        // the Laplace evidence is undefined when a parameter's range is unbounded
        "delta_evidence" | "minus_2_log_evidence" | "log_evidence" => true,
        // discover's residual description: no term describes it
        "leading" => true,
        // plunger: the TM never touched a plunger
        "touched_at_s" => true,
        _ => false,
    }
}

/// Whether a `null` element `i` of the array `key` of the object `obj` is documented:
/// tiptrack's coordinates of a frame without a threshold crossing (interface.md); a baseline
/// change's `[before, after]` margin or value on a side that was not verified.
fn null_element_is_documented(
    key: &str,
    i: usize,
    obj: Option<&serde_json::Map<String, Value>>,
) -> bool {
    match key {
        "x_m" | "z_m" | "sigma_x_m" | "sigma_z_m" => true,
        // montecarlo's exact 99.73 % interval: a side the sample is too small to bound
        // (interface.md, issue 32)
        "p9973_interval_um_s" => true,
        "margin" | "value" => {
            obj.and_then(|o| o.get("status"))
                .and_then(|st| st.get(i))
                .and_then(Value::as_str)
                == Some("not-verified")
        }
        _ => false,
    }
}

/// Where a value sits: the key it is under, the object holding that key, and its index when
/// it is an element of an array.
#[derive(Clone, Copy)]
struct At<'a> {
    key: &'a str,
    obj: Option<&'a serde_json::Map<String, Value>>,
    index: Option<usize>,
}

fn walk(v: &Value, path: &str, at: At, bad: &mut Vec<String>) {
    match v {
        Value::Null => {
            let ok = match (at.index, at.obj) {
                (Some(i), o) => null_element_is_documented(at.key, i, o),
                (None, Some(o)) => null_is_documented(at.key, o),
                (None, None) => false,
            };
            if !ok {
                bad.push(format!(
                    "{path}: null (a non-finite number, or an undocumented absence)"
                ));
            }
        }
        Value::Number(n) if !n.as_f64().is_some_and(f64::is_finite) => {
            bad.push(format!("{path}: {n} is not finite"));
        }
        Value::Object(m) => {
            // a free parameter quoted with a sigma of exactly 0 claims infinite precision
            // (issue 48): it has a positive sigma or none (unresolved)
            if m.contains_key("value")
                && m.get("sigma").and_then(Value::as_f64) == Some(0.0)
                && m.get("fixed") != Some(&Value::Bool(true))
            {
                bad.push(format!("{path}: a free parameter with sigma 0"));
            }
            for (k, x) in m {
                let inner = At {
                    key: k,
                    obj: Some(m),
                    index: None,
                };
                walk(x, &format!("{path}.{k}"), inner, bad);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                let inner = At {
                    index: Some(i),
                    ..at
                };
                walk(x, &format!("{path}[{i}]"), inner, bad);
            }
        }
        _ => {}
    }
}

/// The violations of one JSON document (or JSON-lines file).
fn check_text(label: &str, text: &str, lines: bool) -> Vec<String> {
    let docs: Vec<Result<Value, serde_json::Error>> = if lines {
        text.lines()
            .filter(|l| !l.trim().is_empty())
            .map(serde_json::from_str)
            .collect()
    } else {
        vec![serde_json::from_str(text)]
    };
    let mut bad = Vec::new();
    for d in docs {
        match d {
            Ok(v) => walk(
                &v,
                "",
                At {
                    key: "",
                    obj: None,
                    index: None,
                },
                &mut bad,
            ),
            Err(e) => bad.push(format!("not JSON ({e})")),
        }
    }
    bad.into_iter().map(|b| format!("{label}: {b}")).collect()
}

/// What one command wrote: its standard output (when it succeeded or gave a verdict and was
/// asked for `--json`) and every JSON file under `dir`.
struct Checker {
    violations: Vec<String>,
    documents: usize,
    commands: usize,
    succeeded: usize,
    /// Files already checked, with their size and time: a file is checked once per version.
    seen: std::collections::HashSet<(PathBuf, u64, std::time::SystemTime)>,
}

impl Checker {
    fn new() -> Checker {
        Checker {
            violations: Vec::new(),
            documents: 0,
            commands: 0,
            succeeded: 0,
            seen: Default::default(),
        }
    }

    fn command(&mut self, args: &[String], dir: &Path) -> Option<Value> {
        let out = run(args, dir);
        self.commands += 1;
        let label = format!("geodesic {}", args.join(" "));
        let code = out.status.code();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(matches!(code, Some(0..=2)), "{label}: exit {code:?}: {err}");
        assert!(!err.contains("panicked"), "{label}: {err}");
        if code == Some(2) {
            // refused: one line, nothing reported as success
            assert!(out.stdout.is_empty(), "{label}: output with exit 2");
            return None;
        }
        self.succeeded += 1;
        let mut doc = None;
        if args.iter().any(|a| a == "--json") {
            let text = String::from_utf8_lossy(&out.stdout);
            self.violations.extend(check_text(&label, &text, false));
            self.documents += 1;
            doc = serde_json::from_str(&text).ok();
        }
        for f in json_files(dir) {
            let meta = std::fs::metadata(&f).unwrap();
            if !self
                .seen
                .insert((f.clone(), meta.len(), meta.modified().unwrap()))
            {
                continue;
            }
            let text = match std::fs::read(&f).map(String::from_utf8) {
                Ok(Ok(t)) => t,
                _ => {
                    self.violations
                        .push(format!("{label} -> {}: not UTF-8 text", f.display()));
                    continue;
                }
            };
            let lines = f.extension().is_some_and(|e| e == "jsonl");
            self.violations.extend(check_text(
                &format!("{label} -> {}", f.display()),
                &text,
                lines,
            ));
            self.documents += 1;
        }
        doc
    }
}

fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let p = e.path();
            // the report sets behind the stable links of `verify` (DIR/.geodesic/): the links
            // are checked
            if p.file_name().is_some_and(|n| n == ".geodesic") {
                continue;
            }
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "json" || x == "jsonl") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn s(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| x.to_string()).collect()
}

/// The seeds, the regression inputs and `mutants` accepted mutations of the seeds of a fuzz
/// target (a fixed stream: the same inputs every run).
fn corpus(target: &str, mutants: usize) -> Vec<Vec<u8>> {
    let root = workspace();
    let t = geodesic_fuzz::find(target).unwrap();
    let ctx = Ctx::new(&root).unwrap();
    let seeds = (t.seeds)(&root);
    let mut out = seeds.clone();
    let reg = root.join("fuzz/regressions").join(target);
    if let Ok(rd) = std::fs::read_dir(&reg) {
        let mut files: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
        files.sort();
        out.extend(files.iter().map(|f| std::fs::read(f).unwrap()));
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(35);
    let mut found = 0;
    for _ in 0..mutants * 400 {
        if found == mutants {
            break;
        }
        let base = &seeds[rand::RngExt::random_range(&mut rng, 0..seeds.len())];
        let m = geodesic_fuzz::mutate::mutate(&mut rng, base, &seeds, t.dict);
        if m != *base
            && matches!(
                geodesic_fuzz::run::run_one(t, &ctx, &m),
                Ok(Outcome::Accepted)
            )
        {
            out.push(m);
            found += 1;
        }
    }
    out
}

fn write(dir: &Path, name: &str, data: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, data).unwrap();
    p
}

fn copy(rel: &str, dir: &Path) -> PathBuf {
    let src = workspace().join(rel);
    let dst = dir.join(src.file_name().unwrap());
    if src.is_dir() {
        std::fs::create_dir_all(&dst).unwrap();
        for e in std::fs::read_dir(&src).unwrap().flatten() {
            std::fs::copy(e.path(), dst.join(e.file_name())).unwrap();
        }
    } else {
        std::fs::copy(&src, &dst).unwrap();
    }
    dst
}

fn finish(c: Checker, min_ok: usize) {
    eprintln!(
        "{} commands, {} succeeded, {} JSON documents checked",
        c.commands, c.succeeded, c.documents
    );
    assert!(
        c.violations.is_empty(),
        "{} non-finite or undocumented nulls in {} documents of {} commands:\n{}",
        c.violations.len(),
        c.documents,
        c.commands,
        c.violations.join("\n")
    );
    assert!(
        c.succeeded >= min_ok,
        "only {} of {} commands succeeded: the corpus reaches too little",
        c.succeeded,
        c.commands
    );
}

/// Records at the edges of what loads: time in milliseconds and one sample 1e30 off (issues
/// 35, 37), values 1e-200 of the example's, a constant and a zero record, a time axis 1e12
/// longer.
fn lab_variants(dir: &Path) -> Vec<PathBuf> {
    let root = workspace();
    let mut out = Vec::new();
    for (name, scale_t, scale_y, wild) in [
        ("rt-ms", 1e3, Some(1.0), false),
        ("rt-wild", 1.0, Some(1.0), true),
        ("rt-tiny", 1.0, Some(1e-200), false),
        ("rt-zero", 1.0, Some(0.0), false),
        ("rt-constant", 1.0, None, false),
        ("rt-long", 1e12, Some(1.0), false),
    ] {
        let csv = std::fs::read_to_string(root.join("data/examples/rt-plunger.csv")).unwrap();
        let mut lines = csv.lines();
        let mut text = format!("{}\n", lines.next().unwrap());
        for (i, l) in lines.enumerate() {
            let mut cells: Vec<String> = l.split(',').map(str::to_string).collect();
            let t: f64 = cells[0].parse().unwrap();
            cells[0] = format!("{:e}", t * scale_t);
            let y: f64 = cells[1].parse().unwrap();
            cells[1] = format!("{:e}", scale_y.map_or(1e-6, |k| y * k));
            if wild && i == 400 {
                cells[1] = "1e30".into();
            }
            text.push_str(&cells.join(","));
            text.push('\n');
        }
        std::fs::write(dir.join(format!("{name}.csv")), text).unwrap();
        let yaml = std::fs::read_to_string(root.join("data/examples/rt-plunger.yaml"))
            .unwrap()
            .replace("rt-plunger.csv", &format!("{name}.csv"));
        out.push(write(dir, &format!("{name}.yaml"), yaml.as_bytes()));
    }
    out
}

#[test]
fn fit_diagnose_discover_history_over_the_dataset_corpus() {
    let dir = scratch("finite-fit");
    copy("data/examples/rt-plunger.csv", &dir);
    copy("data/examples/tmmf-adhesion.csv", &dir);
    let mut c = Checker::new();
    let effects = |yaml: &[u8]| {
        if String::from_utf8_lossy(yaml).contains("tmmf-release") {
            "needle_contact,tip_contact,tip_adhesion"
        } else {
            "piezo"
        }
    };
    let mut datasets: Vec<(PathBuf, &str)> = Vec::new();
    for (i, y) in corpus("dataset-yaml", 4).iter().enumerate() {
        datasets.push((write(&dir, &format!("y{i}.yaml"), y), effects(y)));
    }
    // mutated CSVs under the example YAMLs
    let rt_yaml = std::fs::read(workspace().join("data/examples/rt-plunger.yaml")).unwrap();
    let tm_yaml = std::fs::read(workspace().join("data/examples/tmmf-adhesion.yaml")).unwrap();
    for (i, csv) in corpus("dataset-csv", 4).iter().enumerate() {
        let tmmf = String::from_utf8_lossy(csv)
            .lines()
            .next()
            .is_some_and(|h| h.contains('x'));
        let (yaml, from) = if tmmf {
            (&tm_yaml, "tmmf-adhesion.csv")
        } else {
            (&rt_yaml, "rt-plunger.csv")
        };
        write(&dir, &format!("c{i}.csv"), csv);
        let y = String::from_utf8_lossy(yaml).replace(from, &format!("c{i}.csv"));
        datasets.push((
            write(&dir, &format!("c{i}.yaml"), y.as_bytes()),
            effects(y.as_bytes()),
        ));
    }
    for p in lab_variants(&dir) {
        datasets.push((p, "piezo"));
    }
    for (k, (p, fx)) in datasets.iter().enumerate() {
        let reports = format!("r{k}");
        let ds = p.to_str().unwrap();
        c.command(
            &s(&["fit", ds, "--effects", fx, "--reports", &reports, "--json"]),
            &dir,
        );
        c.command(&s(&["history", ds, "--reports", &reports, "--json"]), &dir);
    }
    // a bound that excludes the nominal value (issue 35), fixed values, the posterior
    let rt = workspace().join("data/examples/rt-plunger.yaml");
    let rt = rt.to_str().unwrap();
    for extra in [
        &["--bound", "piezo.R=1e4:1e5"][..],
        &["--bound", "piezo.k=1e9:1e10", "--bound", "piezo.m=0.05:0.1"],
        &["--fix", "piezo.R=1e5"],
        &["--posterior"],
    ] {
        let mut a = s(&["fit", rt, "--effects", "piezo", "--reports", "rb", "--json"]);
        a.extend(s(extra));
        c.command(&a, &dir);
    }
    let tm = workspace().join("data/examples/tmmf-adhesion.yaml");
    let ms = dir.join("rt-ms.yaml");
    for ds in [rt, tm.to_str().unwrap(), ms.to_str().unwrap()] {
        c.command(
            &s(&[
                "diagnose",
                ds,
                "--effects",
                if ds.contains("tmmf") {
                    "needle_contact,tip_contact"
                } else {
                    "piezo"
                },
                "--reports",
                "rd",
                "--json",
            ]),
            &dir,
        );
    }
    c.command(
        &s(&[
            "discover",
            rt,
            "--effects",
            "piezo",
            "--max-rounds",
            "1",
            "--reports",
            "rs",
            "--json",
        ]),
        &dir,
    );
    finish(c, 20);
}

#[test]
fn monte_carlo_sensitivity_tip_radius_merge_over_their_corpus() {
    let dir = scratch("finite-mc");
    let mut c = Checker::new();
    for (i, b) in corpus("budget", 3).iter().enumerate() {
        let f = write(&dir, &format!("b{i}.yaml"), b);
        let f = f.to_str().unwrap();
        c.command(
            &s(&["montecarlo", "--n", "400", "--budget", f, "--json"]),
            &dir,
        );
        c.command(
            &s(&[
                "tip-radius",
                "--mc-n",
                "100",
                "--radii",
                "0.5,10",
                "--budget",
                f,
                "--json",
            ]),
            &dir,
        );
        if i < 2 {
            c.command(
                &s(&["sensitivity", "--n", "100", "--budget", f, "--json"]),
                &dir,
            );
        }
    }
    for (i, p) in corpus("campaign-json", 2).iter().enumerate() {
        let f = write(&dir, &format!("camp{i}.in"), p);
        let f = f.to_str().unwrap();
        let out = scratch(&format!("finite-mc-camp{i}"));
        c.command(
            &s(&[
                "montecarlo",
                "--n",
                "400",
                "--adhesion-from",
                f,
                "--population-draws",
                "3",
                "--json",
            ]),
            &out,
        );
    }
    // shards written and merged
    let parts = scratch("finite-mc-parts");
    for k in 1..=2 {
        c.command(
            &s(&[
                "montecarlo",
                "--n",
                "300",
                "--shard",
                &format!("{k}/2"),
                "--out",
                &format!("p{k}.json"),
                "--json",
            ]),
            &parts,
        );
    }
    c.command(&s(&["merge", "p1.json", "p2.json", "--json"]), &parts);
    for (i, p) in corpus("merge-part", 3).iter().enumerate() {
        let d = scratch(&format!("finite-merge{i}"));
        write(&d, "part.in", p);
        c.command(&s(&["merge", "part.in", "--json"]), &d);
    }
    // hostile but accepted flag values
    for args in [
        &[
            "montecarlo",
            "--n",
            "1",
            "--seed",
            "18446744073709551615",
            "--json",
        ][..],
        &["montecarlo", "--n", "200", "--case", "adhesion", "--json"],
        &["montecarlo", "--n", "200", "--case", "mechanisms", "--json"],
        &[
            "tip-radius",
            "--mc-n",
            "50",
            "--radii",
            "0.001,100",
            "--json",
        ],
    ] {
        c.command(&s(args), &dir);
    }
    finish(c, 12);
}

#[test]
fn capture_charge_plunger_effects_synth_over_their_corpus_and_hostile_values() {
    let dir = scratch("finite-small");
    let mut c = Checker::new();
    for (i, st) in corpus("capture-state", 4).iter().enumerate() {
        let f = write(&dir, &format!("s{i}.yaml"), st);
        c.command(
            &s(&["capture", "--state", f.to_str().unwrap(), "--json"]),
            &dir,
        );
    }
    for (i, ci) in corpus("capture-inputs", 3).iter().enumerate() {
        let f = write(&dir, &format!("ci{i}.yaml"), ci);
        c.command(
            &s(&[
                "capture",
                "--capture",
                f.to_str().unwrap(),
                "--vz",
                "3um/s",
                "--json",
            ]),
            &dir,
        );
    }
    for args in [
        &["capture", "--vz", "1e-300", "--json"][..],
        &[
            "capture", "--vz", "-12um/s", "--x", "1e3", "--wz", "1e6", "--json",
        ],
        &["charge", "--n", "1000", "--json"],
        &[
            "charge",
            "--n",
            "1000",
            "--c-eh-pf",
            "1e-30",
            "--c-pyr-pf",
            "1e6",
            "--json",
        ],
        &[
            "charge",
            "--n",
            "1000",
            "--neutralise-e",
            "-1e30",
            "--rate-e-s",
            "1e-300",
            "--json",
        ],
        &["plunger", "--json"],
        &[
            "plunger",
            "--voltage",
            "-3,0,1e3",
            "--v0",
            "-1mm/s",
            "--json",
        ],
        &[
            "plunger",
            "--retraction",
            "1:1e-9",
            "--capacitance",
            "sphere:1e-3",
            "--json",
        ],
        &["effects", "--json"],
        &["effects", "--scenario", "rt-retraction", "--json"],
        &["effects", "--scenario", "tmmf-release", "--json"],
    ] {
        c.command(&s(args), &dir);
    }
    // synthetic datasets at the edges of their flags, each fitted
    for (k, args) in [
        &[
            "--scenario",
            "rt-retraction",
            "--effects",
            "piezo",
            "--post",
            "2e-4",
        ][..],
        &[
            "--scenario",
            "rt-retraction",
            "--effects",
            "piezo,voltage_ramp",
            "--fs",
            "10kHz",
            "--post",
            "1e-3",
            "--noise",
            "y=1e-15",
        ],
        &[
            "--scenario",
            "tmmf-release",
            "--effects",
            "needle_contact,tip_contact,tip_adhesion",
            "--post",
            "2e-3",
            "--param",
            "tip_adhesion.A1=1e-3",
        ],
    ]
    .iter()
    .enumerate()
    {
        let d = scratch(&format!("finite-synth{k}"));
        let mut a = s(&["synth", "--out", "x.yaml", "--json"]);
        a.extend(s(args));
        c.command(&a, &d);
        let fx = args[3];
        c.command(&s(&["fit", "x.yaml", "--effects", fx, "--json"]), &d);
    }
    finish(c, 20);
}

#[test]
fn import_export_asd_tiptrack_surfaces_over_their_corpus() {
    let dir = scratch("finite-files");
    let mut c = Checker::new();
    let mut reqifs = corpus("reqif", 3);
    let tools = workspace().join("verification/exchange/tests/fixtures/tools");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&tools)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "reqif"))
        .collect();
    names.sort();
    reqifs.extend(names.iter().map(|p| std::fs::read(p).unwrap()));
    for (i, r) in reqifs.iter().enumerate() {
        let d = scratch(&format!("finite-reqif{i}"));
        write(&d, "in.reqif", r);
        c.command(
            &s(&["import", "reqif", "in.reqif", "--out", "o", "--json"]),
            &d,
        );
    }
    for (i, m) in corpus("compliance-status", 2).iter().enumerate() {
        let d = scratch(&format!("finite-export{i}"));
        write(&d, "m.txt", m);
        c.command(
            &s(&[
                "export", "reqif", "--matrix", "m.txt", "--out", "x.reqif", "--json",
            ]),
            &d,
        );
    }
    copy("data/spectra/lpf-da-example.csv", &dir);
    for (i, y) in corpus("series-yaml", 3).iter().enumerate() {
        let f = write(&dir, &format!("series{i}.yaml"), y);
        let f = f.to_str().unwrap();
        for req in ["LPF-DA-ASD", "LPF-IFO-ASD"] {
            c.command(&s(&["asd", f, "--requirement", req, "--json"]), &dir);
        }
    }
    let cam = scratch("finite-cam");
    copy("data/camera/frames", &cam);
    for (i, y) in corpus("frames-yaml", 2).iter().enumerate() {
        let f = write(&cam, &format!("frames{i}.yaml"), y);
        c.command(
            &s(&[
                "tiptrack",
                f.to_str().unwrap(),
                "--reports",
                &format!("r{i}"),
                "--json",
            ]),
            &cam,
        );
    }
    let surf = scratch("finite-surf");
    copy("data/surfaces/before.csv", &surf);
    copy("data/surfaces/after.csv", &surf);
    let after = copy("data/surfaces/after.yaml", &surf);
    for (i, y) in corpus("surface-yaml", 2).iter().enumerate() {
        let f = write(&surf, &format!("s{i}.yaml"), y);
        c.command(
            &s(&[
                "surfaces",
                f.to_str().unwrap(),
                after.to_str().unwrap(),
                "--reports",
                &format!("r{i}"),
                "--json",
            ]),
            &surf,
        );
    }
    finish(c, 20);
}

#[test]
fn verify_writes_finite_reports() {
    let dir = scratch("finite-verify");
    let mut c = Checker::new();
    let root = workspace();
    let baseline = root.join("verification/baseline/compliance.json");
    let series = root.join("data/spectra/lpf-da-example.yaml");
    let doc = c.command(
        &s(&[
            "verify",
            "--requirements",
            root.join("requirements").to_str().unwrap(),
            "--mc-n",
            "2000",
            "--no-fidelity",
            "--baseline",
            baseline.to_str().unwrap(),
            "--series",
            &format!("LPF-DA-ASD={}", series.display()),
            "--junit",
            "j.xml",
            "--json",
        ]),
        &dir,
    );
    let rows = doc.unwrap()["requirements"].as_array().unwrap().len();
    assert!(rows >= 28);
    finish(c, 1);
}
