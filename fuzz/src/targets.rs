//! One fuzz target per parser of untrusted input, each with its seeds, its dictionary and its
//! contract check.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use geodesic_core::requirement::Requirements;
use geodesic_core::units::{Dim, parse_quantity, parse_si, parse_unit};

/// What one input did to a parser.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Accepted (and the result passed the checks).
    Accepted,
    /// Refused with this one-line error.
    Refused(String),
    /// The parser broke its contract (a multi-line error, an error not naming the file, a
    /// success holding NaN or infinity): the cause.
    Violation(String),
}

/// Scratch space and shared inputs of one fuzz run (one directory per run, not per input).
pub struct Ctx {
    dir: tempfile::TempDir,
    root: PathBuf,
    reqs: OnceLock<Requirements>,
    report: OnceLock<geodesic_report::Report>,
}

impl Ctx {
    /// A fresh scratch directory; `root` is the repository (seeds and real requirements).
    pub fn new(root: &Path) -> std::io::Result<Ctx> {
        // a RAM file system when there is one: the file-based targets write every input
        let shm = Path::new("/dev/shm");
        let mut b = tempfile::Builder::new();
        b.prefix("geodesic-fuzz-");
        let dir = if shm.is_dir() {
            b.tempdir_in(shm).or_else(|_| b.tempdir())?
        } else {
            b.tempdir()?
        };
        Ok(Ctx {
            dir,
            root: root.to_path_buf(),
            reqs: OnceLock::new(),
            report: OnceLock::new(),
        })
    }

    /// The scratch directory.
    pub fn dir(&self) -> &Path {
        self.dir.path()
    }

    /// A subdirectory of the scratch directory (created).
    fn sub(&self, name: &str) -> PathBuf {
        let d = self.dir.path().join(name);
        if !d.is_dir() {
            std::fs::create_dir_all(&d).expect("create scratch subdirectory");
        }
        d
    }

    /// The repository's requirement set.
    fn reqs(&self) -> &Requirements {
        self.reqs.get_or_init(|| {
            Requirements::load_dir(&self.root.join("requirements"))
                .expect("the repository's requirements load")
        })
    }

    /// A report over the repository's requirements with no evidence (every row not verified).
    fn report(&self) -> &geodesic_report::Report {
        use geodesic_core::check::{InputFile, Inputs};
        self.report.get_or_init(|| geodesic_report::Report {
            matrix: geodesic_core::matrix::Matrix::build(self.reqs(), &[], None, &[]),
            run: geodesic_report::RunInfo {
                document: {
                    let p = self.root.join("verification/document.yaml");
                    let text =
                        std::fs::read_to_string(&p).expect("the document identification reads");
                    geodesic_core::document::Document::from_yaml(&text, &p)
                        .expect("the document identification loads")
                },
                document_file: InputFile::new("verification/document.yaml", ""),
                geodesic_version: "fuzz".into(),
                tool_version: "fuzz".into(),
                commit: "0".into(),
                dirty: false,
                date: "2026-01-01T00:00:00Z".into(),
                command: "geodesic-fuzz".into(),
                requirements: "requirements".into(),
                requirements_hash: "0".into(),
                inputs: {
                    let mut i = Inputs::default();
                    for n in ["budget", "capture", "charge"] {
                        i.insert(n, n, InputFile::new(format!("{n}.yaml"), ""));
                    }
                    i
                },
                dispositions: None,
                options: Default::default(),
                confidence: 0.95,
                checks: vec![],
                fidelity: vec![],
                reference: Default::default(),
                partial: None,
                timings: Default::default(),
                build_commit: None,
                build_note: None,
                unmatched_dispositions: Vec::new(),
            },
            reverify: Default::default(),
        })
    }
}

/// A fuzz target.
pub struct Target {
    /// Name on the command line and in crash files.
    pub name: &'static str,
    /// The parser fuzzed.
    pub about: &'static str,
    /// Seed inputs from the repository's real files (`root`: the repository).
    pub seeds: fn(&Path) -> Vec<Vec<u8>>,
    /// Tokens of the format, tried besides [`crate::mutate::COMMON`].
    pub dict: &'static [&'static str],
    /// Feeds one input to the parser and checks its contract.
    pub run: fn(&Ctx, &[u8]) -> Outcome,
}

/// Every target.
pub static TARGETS: &[Target] = &[
    Target {
        name: "requirements",
        about: "requirement YAML set (geodesic_core::requirement::Requirements::load_dir)",
        seeds: seeds_requirements,
        dict: YAML_REQ,
        run: run_requirements,
    },
    Target {
        name: "units",
        about: "units and quantities (geodesic_core::units: parse_unit, parse_quantity, parse_si)",
        seeds: seeds_units,
        dict: UNITS,
        run: run_units,
    },
    Target {
        name: "dispositions",
        about: "dispositions YAML (geodesic_core::disposition::from_str_with)",
        seeds: |r| files(r, &["verification/dispositions.yaml"]),
        dict: YAML_DISP,
        run: run_dispositions,
    },
    Target {
        name: "testrun",
        about: "recorded test run JSON (geodesic_core::testrun::TestRun::load)",
        seeds: seeds_testrun,
        dict: JSON,
        run: run_testrun,
    },
    Target {
        name: "baseline",
        about: "baseline compliance JSON (geodesic_report::baseline::diff_text)",
        seeds: |r| files(r, &["verification/baseline/compliance.json"]),
        dict: JSON_COMPLIANCE,
        run: run_baseline,
    },
    Target {
        name: "compliance-status",
        about: "compliance JSON read by the ReqIF export (geodesic_exchange::status::StatusSet::parse)",
        seeds: |r| files(r, &["verification/baseline/compliance.json"]),
        dict: JSON_COMPLIANCE,
        run: run_status,
    },
    Target {
        name: "dataset-yaml",
        about: "dataset YAML (geodesic_dataset::dataset::Dataset::load) with the real CSVs beside it",
        seeds: |r| {
            files(
                r,
                &[
                    "data/examples/rt-plunger.yaml",
                    "data/examples/tmmf-adhesion.yaml",
                ],
            )
        },
        dict: YAML_DATASET,
        run: run_dataset_yaml,
    },
    Target {
        name: "dataset-csv",
        about: "dataset CSV (geodesic_dataset::dataset::Dataset::load) under both example YAMLs",
        seeds: seeds_csv,
        dict: CSV,
        run: run_dataset_csv,
    },
    Target {
        name: "history",
        about: "fit history JSONL (geodesic_fit::history::read)",
        seeds: seeds_history,
        dict: JSON,
        run: run_history,
    },
    Target {
        name: "budget",
        about: "release budget YAML (geodesic_release::budget::Budget::from_yaml)",
        seeds: |r| files(r, &["models/release/budget.yaml"]),
        dict: YAML_BUDGET,
        run: run_budget,
    },
    Target {
        name: "capture-inputs",
        about: "capture inputs YAML (geodesic_capture::CaptureInputs::from_yaml_str)",
        seeds: |r| files(r, &["models/capture/capture.yaml"]),
        dict: YAML_CAPTURE,
        run: run_capture_inputs,
    },
    Target {
        name: "capture-state",
        about: "TM state YAML (geodesic_capture::TmState::from_yaml_str)",
        seeds: seeds_state,
        dict: YAML_STATE,
        run: run_capture_state,
    },
    Target {
        name: "merge-part",
        about: "Monte Carlo partial result of `geodesic merge` (geodesic_release::parts::parse_part)",
        seeds: seeds_parts,
        dict: JSON_PART,
        run: run_merge_part,
    },
    Target {
        name: "reqif",
        about: "ReqIF importer (geodesic_exchange::reqif::import) and the YAML it writes",
        seeds: seeds_reqif,
        dict: XML,
        run: run_reqif,
    },
    Target {
        name: "campaign-json",
        about: "campaign result read by `--adhesion-from` and `adhesion_from` \
                (geodesic_release::population::AdhesionPopulation::from_campaign_json, then apply)",
        seeds: |_| vec![CAMPAIGN_SEED.as_bytes().to_vec()],
        dict: JSON_CAMPAIGN,
        run: run_campaign_json,
    },
    Target {
        name: "pgm",
        about: "PGM frames of the tip camera (geodesic_images::frames::read_pgm)",
        seeds: |r| {
            files_in(r, "data/camera/frames", "pgm")
                .into_iter()
                .take(3)
                .collect()
        },
        dict: PGM,
        run: run_pgm,
    },
    Target {
        name: "frames-yaml",
        about: "tip camera FRAMES.yaml (geodesic_images::tiptrack::Config::load) with the real \
                frames beside it",
        seeds: |r| files(r, &["data/camera/frames.yaml"]),
        dict: YAML_IMAGES,
        run: run_frames_yaml,
    },
    Target {
        name: "surface-yaml",
        about: "surface map YAML (geodesic_images::surfaces::HeightMap::load) with the real CSV \
                beside it",
        seeds: |r| {
            files(
                r,
                &["data/surfaces/before.yaml", "data/surfaces/after.yaml"],
            )
        },
        dict: YAML_IMAGES,
        run: run_surface_yaml,
    },
    Target {
        name: "surface-csv",
        about: "surface map CSV grid (geodesic_images::surfaces::HeightMap::load)",
        seeds: |r| files(r, &["data/surfaces/before.csv"]),
        dict: CSV,
        run: run_surface_csv,
    },
    Target {
        name: "series-yaml",
        about: "time-series YAML of `verify --series` and `geodesic asd` \
                (geodesic_fit::spectral::Series::load) with the real CSV beside it",
        seeds: |r| files(r, &["data/spectra/lpf-da-example.yaml"]),
        dict: YAML_DATASET,
        run: run_series_yaml,
    },
];

/// A campaign result (`geodesic campaign --json`, cut to what `--adhesion-from` reads).
const CAMPAIGN_SEED: &str = r#"{"releases": [], "failed": [], "table": {},
"population": {"tip_adhesion.A1": {"mean": 100069.2, "mean_sigma": 4870.7, "sd": 26378.5, "sd_sigma": 3500.3, "n": 30},
"tip_adhesion.lambda": {"mean": 5.83e-7, "mean_sigma": 1.42e-8, "sd": 7.75e-8, "sd_sigma": 9.27e-9, "n": 30},
"correlation": {"tip_adhesion.A1~tip_adhesion.lambda": -0.14}},
"correlation_ci95": {"tip_adhesion.A1~tip_adhesion.lambda": [-0.61, 0.25]}}"#;

const JSON_CAMPAIGN: &[&str] = &[
    "\"population\"",
    "\"tip_adhesion.A1\"",
    "\"tip_adhesion.lambda\"",
    "\"mean\"",
    "\"mean_sigma\"",
    "\"sd\"",
    "\"sd_sigma\"",
    "\"correlation\"",
    "\"correlation_ci95\"",
    "\"tip_adhesion.A1~tip_adhesion.lambda\"",
    "-1.0000001",
    "1e308",
    "-0.0",
];

const PGM: &[&str] = &["P5", "P2", "\n", " ", "255", "65535", "60 80", "#", "0"];

const YAML_IMAGES: &[&str] = &[
    "frames:",
    "fps:",
    "pixel_m:",
    "thresholds:",
    "offset_px:",
    "validity:",
    "window_s:",
    "max_shear_m:",
    "map:",
    "points:",
    "valley_below_m:",
    "[[0, 0], [1, 1]]",
    ".nan",
    ".inf",
    "-1e-300",
];

/// The target named `name`.
pub fn find(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

// ---------------------------------------------------------------- dictionaries

const YAML_REQ: &[&str] = &[
    "id: ",
    "title: ",
    "text: ",
    "source: ",
    "quantity: ",
    "dimension: ",
    "limit: ",
    "method: ",
    "activity: ",
    "derived_from: ",
    "factor: ",
    "family: ",
    "requirements:",
    "check: ",
    "<= 5 um/s",
    ">= 1e-3",
    "< 0",
    "velocity",
    "length",
    "analysis",
    "test",
    "inspection",
    "REL-",
    "um/s",
    "µrad/s",
    "m/s^2",
    "e",
    "V",
    "N",
];
const UNITS: &[&str] = &[
    "m",
    "s",
    "kg",
    "um",
    "µm",
    "nm",
    "mm",
    "km",
    "rad",
    "µrad",
    "deg",
    "V",
    "N",
    "nN",
    "J",
    "Hz",
    "e",
    "C",
    "pF",
    "F",
    "K",
    "W",
    "A",
    "g",
    "%",
    "m/s",
    "um/s",
    "m/s^2",
    "N/m",
    "^2",
    "^-2",
    "^127",
    "^-128",
    "^99999999999",
    "/",
    "*",
    " ",
    "·",
    ".",
    "1/",
    "1e308",
    "1e-308",
    "-",
    "_",
];
const YAML_DISP: &[&str] = &[
    "dispositions:",
    "requirement: ",
    "kind: ",
    "NCR",
    "waiver",
    "RFD",
    "reference: ",
    "reason: ",
    "owner: ",
    "date: ",
    "expires: ",
    "2026-02-29",
    "2026-13-01",
    "0000-00-00",
    "9999-12-31",
    "-2026-01-01",
    "CHG-Q",
    "FAC-ADH-CAL",
];
const JSON: &[&str] = &[
    "{}",
    "[]",
    "null",
    "\"\"",
    "1e400",
    "-1",
    "1.5",
    "true",
    ",",
    ":",
    "\"commit\":",
    "\"tests\":",
    "\"result\":",
    "\"passed\"",
    "\"not-run\"",
    "\"assertions\":",
    "\"limit\"",
    "\"version\":",
    "\"rms\":",
    "\"effects\":",
];
const JSON_COMPLIANCE: &[&str] = &[
    "\"requirements\":",
    "\"id\":",
    "\"status\":",
    "\"compliant\"",
    "\"non-compliant\"",
    "\"not-verified\"",
    "\"value\":",
    "\"margin\":",
    "\"limit\":",
    "\"basis\":",
    "\"model\"",
    "\"flow-down\"",
    "\"accepted\"",
    "\"unit\":",
    "\"evidence\":",
    "\"run\":",
    "null",
    "1e400",
    "-1e400",
    "{}",
    "[]",
];
const YAML_DATASET: &[&str] = &[
    "scenario: ",
    "tmmf-release",
    "rt-retraction",
    "data: ",
    "time_column: ",
    "channels:",
    "known:",
    "noise:",
    "x: ",
    "y: ",
    "E: ",
    "m: ",
    "E0: ",
    "t",
    "/dev/zero",
    "/proc/self/mem",
    "..",
    "rt-plunger.csv",
    "tmmf-adhesion.csv",
    "um",
    "V",
    "kg",
];
const CSV: &[&str] = &[
    ",", "\n", "t", "x", "y", "E", "\"", "\"\"", "NaN", "inf", "1e308", "-1e308", ",,", ";",
    "\r\n", "t,t", "0", "-0",
];
const YAML_BUDGET: &[&str] = &[
    "dist: ",
    "uniform",
    "normal",
    "fixed",
    "lognormal",
    "min: ",
    "max: ",
    "mean: ",
    "sd: ",
    "sigma: ",
    "value: ",
    "lo: ",
    "hi: ",
    "A1",
    "lambda",
    "description: ",
    "[0, 0]",
    "[1, 0]",
];
const YAML_CAPTURE: &[&str] = &[
    "value: ", "unit: ", "sigma: ", "min: ", "max: ", "states:", "limits:", "x", "y", "z", "vx",
    "vy", "vz", "phi", "theta", "eta", "wx", "wy", "wz", "m", "m/s", "rad", "rad/s",
];
const YAML_STATE: &[&str] = &[
    "x: ", "y: ", "z: ", "vx: ", "vy: ", "vz: ", "phi: ", "theta: ", "eta: ", "wx: ", "wy: ",
    "wz: ", "1e-6", "-3e-6",
];
const JSON_PART: &[&str] = &[
    "\"n\":",
    "\"seed\":",
    "\"case\":",
    "\"shard\":",
    "\"start\":",
    "\"v_m_s\":",
    "\"sha256\":",
    "\"all\"",
    "\"adhesion\"",
    "\"mechanisms\"",
    "[1,1]",
    "[0,0]",
    "[2,1]",
    "[1,100000]",
    "18446744073709551615",
    "9218868437227405312",
    "9221120237041090560",
    "10000000",
    "10000001",
    "0",
    "null",
];
const XML: &[&str] = &[
    "<REQ-IF>",
    "</REQ-IF>",
    "<SPEC-OBJECT ",
    "</SPEC-OBJECT>",
    "IDENTIFIER=\"",
    "LONG-NAME=\"",
    "<ATTRIBUTE-VALUE-STRING THE-VALUE=\"",
    "<ATTRIBUTE-VALUE-XHTML>",
    "<xhtml:div>",
    "</xhtml:div>",
    "<xhtml:br/>",
    "<xhtml:p>",
    "<DEFINITION>",
    "<SPEC-RELATION ",
    "<SPEC-HIERARCHY ",
    "<CHILDREN>",
    "<OBJECT>",
    "<SPEC-OBJECT-REF>",
    "xmlns=\"",
    "&lt;",
    "&#10;",
    "&#xD800;",
    "<!ENTITY x SYSTEM \"file:///etc/passwd\">",
    "&x;",
    "<!DOCTYPE",
    "<?xml version=\"1.1\"?>",
    "<![CDATA[x]]>",
    "\"/>",
    "><",
    "=\"\"",
];

// ---------------------------------------------------------------- seeds

/// The bytes of the repository's files `paths` (relative to `root`) that exist.
fn files(root: &Path, paths: &[&str]) -> Vec<Vec<u8>> {
    paths
        .iter()
        .filter_map(|p| std::fs::read(root.join(p)).ok())
        .collect()
}

/// Every file of `dir` (relative to `root`) with the extension `ext`, sorted by name.
fn files_in(root: &Path, dir: &str, ext: &str) -> Vec<Vec<u8>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root.join(dir))
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    paths.retain(|p| p.extension().and_then(|e| e.to_str()) == Some(ext));
    paths.sort();
    paths.iter().filter_map(|p| std::fs::read(p).ok()).collect()
}

/// The repository's requirement files that load on their own: the target loads the fuzzed
/// file as a set of one, and a file whose requirements derive from another file's (a parent
/// in `tm-state.yaml`, say) is refused alone. The grammar is the same in every file.
fn seeds_requirements(root: &Path) -> Vec<Vec<u8>> {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    files_in(root, "requirements", "yaml")
        .into_iter()
        .filter(|f| {
            let _ = std::fs::remove_file(scratch.path().join("seed.yaml"));
            std::fs::write(scratch.path().join("seed.yaml"), f).is_ok()
                && Requirements::load_dir(scratch.path()).is_ok()
        })
        .collect()
}

fn seeds_units(root: &Path) -> Vec<Vec<u8>> {
    let mut out: Vec<Vec<u8>> = [
        "um/s",
        "3 um/s",
        "3um/s",
        "200µm",
        "3e8 e",
        "1.5e5 N/m",
        "µrad/s",
        "m/s^2",
        "N m",
        "kg·m/s",
        "5e-6",
        "0.7 um",
        "120 V",
        "1e-3 rad",
        "10 pF",
        "1 mm",
    ]
    .iter()
    .map(|s| s.as_bytes().to_vec())
    .collect();
    for f in files_in(root, "requirements", "yaml") {
        let text = String::from_utf8_lossy(&f).into_owned();
        for l in text.lines() {
            if let Some(v) = l.trim().strip_prefix("limit:") {
                let v = v.trim().trim_matches(['"', '\'']);
                let v = v.trim_start_matches(['<', '>', '=']).trim();
                out.push(v.as_bytes().to_vec());
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

fn seeds_testrun(root: &Path) -> Vec<Vec<u8>> {
    let mut out = files(root, &["target/geodesic/test-run.json"]);
    out.push(
        br#"{"commit":"0123abc","dirty":false,"date":"2026-11-23T10:00:00Z","command":"cargo xtask test","tests":[{"krate":"geodesic-release","test":"tests::mc_within_limit","result":"passed","location":"models/release/src/montecarlo.rs:10","requirements":["REL-V"],"cases":1,"assertions":["limit"],"kind":"unit","asserted":{"REL-V":["limit"]}},{"krate":"geodesic-capture","test":"tests::capture","result":"not-run","requirements":["CAP-X"],"cases":0,"assertions":["reference","change-detection"],"kind":"integration"}]}"#
            .to_vec(),
    );
    out
}

fn seeds_csv(root: &Path) -> Vec<Vec<u8>> {
    // the first 300 lines of each example CSV: enough for the loader's checks, fast to parse
    files(
        root,
        &[
            "data/examples/rt-plunger.csv",
            "data/examples/tmmf-adhesion.csv",
        ],
    )
    .into_iter()
    .map(|f| {
        let text = String::from_utf8_lossy(&f);
        let mut s: String = text.lines().take(300).collect::<Vec<_>>().join("\n");
        s.push('\n');
        s.into_bytes()
    })
    .collect()
}

fn seeds_history(_root: &Path) -> Vec<Vec<u8>> {
    // the format `geodesic fit` appends (history::append), as written by a real fit
    vec![
        br#"{"version":1,"dataset":"tmmf-adhesion.yaml","effects":["needle_contact","tip_contact"],"n_free":3,"rms":7.0298621093160975e-9,"chi2_red":77.67820776726727,"bic":34818.171481754245}
{"version":2,"dataset":"tmmf-adhesion.yaml","effects":["needle_contact","tip_contact","tip_adhesion"],"n_free":5,"rms":8.066558697952731e-10,"chi2_red":1.0273663477924677,"bic":488.762727812954}
"#
        .to_vec(),
    ]
}

fn seeds_state(_root: &Path) -> Vec<Vec<u8>> {
    use geodesic_capture::StateName;
    let all: String = StateName::ALL
        .iter()
        .enumerate()
        .map(|(i, s)| format!("{}: {:e}\n", s.as_str(), (i as f64 - 5.0) * 1e-6))
        .collect();
    vec![
        all.into_bytes(),
        b"# TM state after release, SI units\nvz: -3.0e-6\nwx: 1.0e-5\n".to_vec(),
    ]
}

fn seeds_parts(_root: &Path) -> Vec<Vec<u8>> {
    use geodesic_release::montecarlo::{Case, McResult};
    let part = |shard: Option<(usize, usize)>, start: usize, v: Vec<f64>| McResult {
        n: 4,
        seed: 42,
        case: Case::All,
        budget_hash: "5d2f".into(),
        budget_description: "fuzz seed".into(),
        budget_source: None,
        shard,
        start,
        v_m_s: v,
        fallback_stops: 0,
        rhs_evals: 1234,
    };
    [
        part(None, 0, vec![1e-6, -2e-6, 3.5e-6, 0.0]),
        part(Some((1, 2)), 0, vec![1e-6, -2e-6]),
        part(Some((2, 2)), 2, vec![3.5e-6, 0.0]),
    ]
    .iter()
    .map(|p| geodesic_release::parts::sealed_json(p).expect("seal a seed part"))
    .collect()
}

fn seeds_reqif(root: &Path) -> Vec<Vec<u8>> {
    // geodesic's own test files and the small real exports of other tools (Enterprise
    // Architect, DOORS Next, RMF, Capella, ...: dangling references, missing types)
    let mut v = files_in(root, "verification/exchange/tests/fixtures", "reqif");
    v.extend(
        files_in(root, "verification/exchange/tests/fixtures/tools", "reqif")
            .into_iter()
            .filter(|f| f.len() < 50_000),
    );
    // and .reqifz archives of them
    v.extend(files_in(
        root,
        "verification/exchange/tests/fixtures/tools",
        "reqifz",
    ));
    v
}

// ---------------------------------------------------------------- checks

/// Whether the `Debug` text of a value shows a NaN or an infinite float outside string and
/// character literals (`NaN`, `inf`, `-inf` as whole tokens).
pub fn non_finite(debug: &str) -> bool {
    let mut chars = debug.chars().peekable();
    let mut word = String::new();
    let bad = |w: &str| w == "NaN" || w == "inf";
    while let Some(c) = chars.next() {
        if c == '"' || c == '\'' {
            if bad(&word) {
                return true;
            }
            word.clear();
            let quote = c;
            while let Some(d) = chars.next() {
                if d == '\\' {
                    chars.next();
                } else if d == quote {
                    break;
                }
            }
        } else if c.is_alphanumeric() || c == '_' {
            word.push(c);
        } else {
            if bad(&word) {
                return true;
            }
            word.clear();
        }
    }
    bad(&word)
}

/// The outcome of an error message: refused if it is one line (naming `file` when given).
fn refused(msg: String, file: Option<&str>) -> Outcome {
    if msg.contains('\n') {
        return Outcome::Violation(format!("error message is not one line: {msg:?}"));
    }
    if let Some(f) = file
        && !msg.contains(f)
    {
        return Outcome::Violation(format!("error message does not name the file {f}: {msg:?}"));
    }
    Outcome::Refused(msg)
}

/// The outcome of a result: accepted if its `Debug` shows only finite floats.
fn checked<T: std::fmt::Debug, E: std::fmt::Display>(
    r: Result<T, E>,
    file: Option<&str>,
) -> Outcome {
    match r {
        Ok(v) => {
            let d = format!("{v:?}");
            if non_finite(&d) {
                let mut d = d;
                d.truncate(2000);
                Outcome::Violation(format!("accepted with a non-finite value: {d}"))
            } else {
                Outcome::Accepted
            }
        }
        Err(e) => refused(e.to_string(), file),
    }
}

fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

fn write(path: &Path, data: &[u8]) {
    std::fs::write(path, data).expect("write a fuzz input to the scratch directory");
}

// ---------------------------------------------------------------- targets

fn run_requirements(ctx: &Ctx, data: &[u8]) -> Outcome {
    let dir = ctx.sub("requirements");
    write(&dir.join("fuzz.yaml"), data);
    checked(
        Requirements::load_dir(&dir),
        Some(&dir.display().to_string()),
    )
}

fn run_units(_ctx: &Ctx, data: &[u8]) -> Outcome {
    let t = text(data);
    let u = checked(parse_unit(&t), None);
    if let Outcome::Violation(_) = u {
        return u;
    }
    let q = checked(parse_quantity(&t), None);
    if let Outcome::Violation(_) = q {
        return q;
    }
    let s = checked(parse_si(&t, Dim::VELOCITY), None);
    match (&u, &q, &s) {
        (_, _, Outcome::Violation(_)) => s,
        (Outcome::Accepted, _, _) | (_, Outcome::Accepted, _) => Outcome::Accepted,
        _ => s,
    }
}

fn run_dispositions(ctx: &Ctx, data: &[u8]) -> Outcome {
    let file = Path::new("fuzz-dispositions.yaml");
    let strict = data.len().is_multiple_of(2);
    // a fixed day (2026-11-23) so that outcomes do not depend on the date of the run
    let today = 20_415;
    checked(
        geodesic_core::disposition::from_str_with(&text(data), file, ctx.reqs(), today, strict),
        Some("fuzz-dispositions.yaml"),
    )
}

fn run_testrun(ctx: &Ctx, data: &[u8]) -> Outcome {
    let p = ctx.sub("testrun").join("test-run.json");
    write(&p, data);
    checked(
        geodesic_core::testrun::TestRun::load(&p),
        Some(&p.display().to_string()),
    )
}

fn run_baseline(ctx: &Ctx, data: &[u8]) -> Outcome {
    let r = geodesic_report::baseline::diff_text(
        ctx.report(),
        &text(data),
        "fuzz-compliance.json",
        0.01,
    );
    match r {
        Ok(d) => {
            // the diff is rendered in every report: render it too
            let _ = geodesic_report::baseline::summary_lines(&d);
            let _ = geodesic_report::baseline::markdown(&d);
            checked(Ok::<_, String>(d), None)
        }
        Err(e) => refused(e.to_string(), Some("fuzz-compliance.json")),
    }
}

fn run_status(ctx: &Ctx, data: &[u8]) -> Outcome {
    let file = Path::new("fuzz-compliance.json");
    match geodesic_exchange::status::StatusSet::parse(file, &text(data)) {
        Ok(s) => match s.check_against(file, ctx.reqs()) {
            Ok(()) => checked(Ok::<_, String>(s), None),
            Err(e) => refused(e.to_string(), Some("fuzz-compliance.json")),
        },
        Err(e) => refused(e.to_string(), Some("fuzz-compliance.json")),
    }
}

fn run_dataset_yaml(ctx: &Ctx, data: &[u8]) -> Outcome {
    let dir = ctx.sub("dataset-yaml");
    for csv in ["rt-plunger.csv", "tmmf-adhesion.csv"] {
        let p = dir.join(csv);
        if !p.exists() {
            let src = ctx.root.join("data/examples").join(csv);
            std::fs::copy(&src, &p).expect("copy an example CSV to the scratch directory");
        }
    }
    let y = dir.join("fuzz.yaml");
    write(&y, data);
    match geodesic_dataset::dataset::Dataset::load(&y) {
        // the CSV named by `data:` may be any file: its errors name it instead of the YAML
        Err(e) if e.to_string().contains(": data file: ") => refused(e.to_string(), None),
        r => checked(r, Some(&dir.display().to_string())),
    }
}

fn run_dataset_csv(ctx: &Ctx, data: &[u8]) -> Outcome {
    let dir = ctx.sub("dataset-csv");
    write(&dir.join("data.csv"), data);
    let mut last: Option<Outcome> = None;
    for yaml in ["rt-plunger.yaml", "tmmf-adhesion.yaml"] {
        let y = dir.join(yaml);
        if !y.exists() {
            let src = std::fs::read_to_string(ctx.root.join("data/examples").join(yaml))
                .expect("read an example dataset YAML");
            let s: String = src
                .lines()
                .map(|l| {
                    if l.starts_with("data:") {
                        "data: data.csv"
                    } else {
                        l
                    }
                })
                .collect::<Vec<_>>()
                .join("\n");
            write(&y, s.as_bytes());
        }
        let o = checked(
            geodesic_dataset::dataset::Dataset::load(&y),
            Some(&dir.display().to_string()),
        );
        if let Outcome::Violation(_) = o {
            return o;
        }
        if last != Some(Outcome::Accepted) {
            last = Some(o);
        }
    }
    last.unwrap_or(Outcome::Accepted)
}

fn run_history(ctx: &Ctx, data: &[u8]) -> Outcome {
    let p = ctx.sub("history").join("fuzz.history.jsonl");
    write(&p, data);
    checked(
        geodesic_fit::history::read(&p),
        Some(&p.display().to_string()),
    )
}

fn run_budget(_ctx: &Ctx, data: &[u8]) -> Outcome {
    checked(
        geodesic_release::budget::Budget::from_yaml(&text(data), "fuzz-budget.yaml"),
        Some("fuzz-budget.yaml"),
    )
}

fn run_capture_inputs(_ctx: &Ctx, data: &[u8]) -> Outcome {
    checked(
        geodesic_capture::CaptureInputs::from_yaml_str(&text(data), "fuzz-capture.yaml"),
        Some("fuzz-capture.yaml"),
    )
}

fn run_capture_state(_ctx: &Ctx, data: &[u8]) -> Outcome {
    checked(
        geodesic_capture::TmState::from_yaml_str(&text(data), "fuzz-state.yaml"),
        Some("fuzz-state.yaml"),
    )
}

fn run_merge_part(_ctx: &Ctx, data: &[u8]) -> Outcome {
    use geodesic_release::parts::CHECKSUM_KEY;
    let t = text(data);
    let raw = part_and_merge(&t);
    if let Outcome::Violation(_) = raw {
        return raw;
    }
    // re-seal the mutated JSON so that the checks behind the checksum are reached too
    let Ok(mut v) = serde_json::from_str::<serde_json::Value>(&t) else {
        return raw;
    };
    let Some(obj) = v.as_object_mut() else {
        return raw;
    };
    obj.remove(CHECKSUM_KEY);
    let Ok(body) = serde_json::to_vec(&v) else {
        return raw;
    };
    v[CHECKSUM_KEY] = serde_json::json!(geodesic_util::hash::sha256_hex(&body));
    part_and_merge(&v.to_string())
}

fn part_and_merge(t: &str) -> Outcome {
    use geodesic_release::montecarlo;
    match geodesic_release::parts::parse_part("fuzz-part.json", t) {
        Ok(r) => {
            // one shard of several is complete on its own only as a parse: merging it alone
            // is refused by design (a missing shard), so only a whole run is merged
            if r.shard.is_some_and(|(_, k)| k > 1) {
                let finite = r.v_m_s.iter().all(|v| v.is_finite());
                return checked(
                    if finite {
                        Ok(())
                    } else {
                        Err("non-finite velocity accepted".to_string())
                    },
                    None,
                );
            }
            let merged = montecarlo::merge(vec![r.clone()]);
            match merged {
                Ok(m) => checked(Ok::<_, String>((r, m.summary())), None),
                Err(e) => refused(format!("merge: {e}"), None),
            }
        }
        Err(e) => refused(e, Some("fuzz-part.json")),
    }
}

fn run_reqif(_ctx: &Ctx, data: &[u8]) -> Outcome {
    // every path of the importer on every input: strict (refuses at the first problem), the
    // default (imports what is meaningful with a warning per problem) and `--skip-incomplete`;
    // the outcome is the strict one unless a path broke the contract
    let strict = reqif_with(data, true, false);
    if matches!(strict, Outcome::Violation(_)) {
        return strict;
    }
    for skip_incomplete in [false, true] {
        let o = reqif_with(data, false, skip_incomplete);
        if matches!(o, Outcome::Violation(_)) {
            return o;
        }
    }
    strict
}

fn reqif_with(data: &[u8], strict: bool, skip_incomplete: bool) -> Outcome {
    use geodesic_exchange::reqif::{ImportOptions, import_file};
    let file = Path::new("fuzz.reqif");
    let opts = ImportOptions {
        skip_incomplete,
        strict,
        ..ImportOptions::default()
    };
    // as `geodesic import reqif` reads it: the bytes, a .reqif or a .reqifz archive
    match import_file(file, data, &opts) {
        Ok(imp) => {
            // each warning is one line at a line of the file (of the document, in an archive)
            let lines = if geodesic_exchange::reqif::is_archive(data) {
                u32::MAX - 1
            } else {
                text(data).lines().count().max(1) as u32
            };
            if let Some(w) = imp
                .warnings
                .iter()
                .find(|w| w.cause.contains(['\n', '\r']) || w.line == 0 || w.line > lines + 1)
            {
                return Outcome::Violation(format!("warning not one line in the file: {w:?}"));
            }
            if strict && !imp.warnings.is_empty() {
                return Outcome::Violation("--strict accepted a file with warnings".into());
            }
            // every SPEC-OBJECT is accounted for
            let accounted =
                imp.count() + imp.headings + imp.other_objects + imp.duplicates + imp.skipped.len();
            if accounted != imp.spec_objects {
                return Outcome::Violation(format!(
                    "{accounted} objects accounted for of {} SPEC-OBJECTs",
                    imp.spec_objects
                ));
            }
            // `geodesic import reqif` loads the YAML it writes: that must not panic either
            let sources: Vec<(PathBuf, String)> = imp
                .families
                .iter()
                .map(|f| (PathBuf::from("out").join(&f.file_name), f.yaml.clone()))
                .collect();
            match Requirements::from_sources(&sources) {
                Ok(_) => checked(Ok::<_, String>(imp), None),
                Err(e) => Outcome::Violation(format!("the imported YAML does not load: {e}")),
            }
        }
        Err(e) => refused(e.to_string(), Some("fuzz.reqif")),
    }
}

fn run_campaign_json(_ctx: &Ctx, data: &[u8]) -> Outcome {
    use geodesic_release::population::AdhesionPopulation;
    let r =
        AdhesionPopulation::from_campaign_json(&text(data), "fuzz-campaign.json").and_then(|p| {
            // a population that loads must also make a valid budget, and its draws stay finite
            let b = p.apply(&geodesic_release::budget::Budget::default_budget())?;
            use rand::SeedableRng;
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
            let d = p.draw(&mut rng);
            let pair = b.adhesion.sample(&mut rng);
            Ok((p, d, pair))
        });
    checked(r, Some("fuzz-campaign.json"))
}

fn run_pgm(_ctx: &Ctx, data: &[u8]) -> Outcome {
    checked(
        geodesic_images::frames::read_pgm(Path::new("fuzz.pgm"), data).map(|f| f.len()),
        Some("fuzz.pgm"),
    )
}

fn copy_once(ctx: &Ctx, dir: &Path, rel: &str, name: &str) {
    let p = dir.join(name);
    if !p.exists() {
        let src = ctx.root.join(rel);
        if src.is_dir() {
            std::fs::create_dir_all(&p).expect("scratch folder");
            for e in std::fs::read_dir(&src).expect("read the real folder") {
                let e = e.expect("folder entry");
                std::fs::copy(e.path(), p.join(e.file_name())).expect("copy a real file");
            }
        } else {
            std::fs::copy(&src, &p).expect("copy a real file to the scratch directory");
        }
    }
}

fn run_frames_yaml(ctx: &Ctx, data: &[u8]) -> Outcome {
    let dir = ctx.sub("frames-yaml");
    copy_once(ctx, &dir, "data/camera/frames", "frames");
    let y = dir.join("fuzz.yaml");
    write(&y, data);
    match geodesic_images::tiptrack::Config::load(&y) {
        Ok(c) => {
            // the frames it names load or are refused in one line (`frames:` may be any text,
            // a path too long to quote whole)
            match geodesic_images::frames::load_sequence(&c.frames) {
                Ok(seq) => checked(Ok::<_, String>((c, seq.frames.len())), None),
                Err(e) => refused(e.to_string(), None),
            }
        }
        Err(e) => refused(e.to_string(), Some(&y.display().to_string())),
    }
}

fn run_surface_yaml(ctx: &Ctx, data: &[u8]) -> Outcome {
    let dir = ctx.sub("surface-yaml");
    copy_once(ctx, &dir, "data/surfaces/before.csv", "before.csv");
    copy_once(ctx, &dir, "data/surfaces/after.csv", "after.csv");
    let y = dir.join("fuzz.yaml");
    write(&y, data);
    match geodesic_images::surfaces::HeightMap::load(&y) {
        // the CSV named by `map:` may be any file: its errors name it instead of the YAML
        Err(e) if !e.to_string().contains("fuzz.yaml") => refused(e.to_string(), None),
        r => checked(
            r.map(|m| (m.pixel_m, m.points, m.rows, m.cols)),
            Some(&y.display().to_string()),
        ),
    }
}

fn run_surface_csv(ctx: &Ctx, data: &[u8]) -> Outcome {
    let dir = ctx.sub("surface-csv");
    let y = dir.join("map.yaml");
    if !y.exists() {
        write(
            &y,
            b"map: map.csv\npixel_m: 1.10365e-7\npoints: [[35, 36], [60, 84]]\n",
        );
    }
    let c = dir.join("map.csv");
    write(&c, data);
    match geodesic_images::surfaces::HeightMap::load(&y) {
        // a map's heights may be missing (NaN) by design, but never infinite
        Ok(m) if m.h.iter().any(|v| v.is_infinite()) => {
            Outcome::Violation("surface map accepted with an infinite height".into())
        }
        // the CSV's own faults name it; a point outside the map names the YAML that holds it
        r => checked(
            r.map(|m| (m.pixel_m, m.points, m.rows, m.cols)),
            Some(&dir.display().to_string()),
        ),
    }
}

fn run_series_yaml(ctx: &Ctx, data: &[u8]) -> Outcome {
    let dir = ctx.sub("series-yaml");
    copy_once(
        ctx,
        &dir,
        "data/spectra/lpf-da-example.csv",
        "lpf-da-example.csv",
    );
    let y = dir.join("fuzz.yaml");
    write(&y, data);
    match geodesic_fit::spectral::Series::load(&y) {
        Err(e) if !e.to_string().contains("fuzz.yaml") => refused(e.to_string(), None),
        Ok(s) if s.values.iter().any(|v| !v.is_finite()) => {
            Outcome::Violation("series accepted with a non-finite sample".into())
        }
        r => checked(r.map(|s| s.dt_s), Some(&y.display().to_string())),
    }
}

#[cfg(test)]
mod tests {
    use super::non_finite;

    #[test]
    fn non_finite_sees_floats_not_strings() {
        assert!(non_finite("Foo { a: NaN, b: 1.0 }"));
        assert!(non_finite("[1.0, -inf]"));
        assert!(non_finite("inf"));
        assert!(!non_finite("Foo { a: \"NaN inf\", c: 'i', b: 1e300 }"));
        assert!(!non_finite("Foo { info: 1.0, inflate: Nan }"));
        assert!(!non_finite("\"escaped \\\" NaN\""));
    }
}
