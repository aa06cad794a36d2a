//! `geodesic new mission NAME --path DIR`: a project outside the framework's repository that
//! verifies its own system with geodesic: a descriptor, one requirement, one input file, one
//! check with a small model (a cantilever's tip deflection), a traced test, and a `main` that
//! is the harness ([`crate::harness::main`]). It builds, records its traced tests (`cargo run
//! -- test`) and verifies as generated.
//!
//! Its `Cargo.toml` names no absolute path: it depends on geodesic by git (`git = URL, rev =
//! COMMIT`) when the generating checkout has a shareable remote (`git remote get-url origin` of
//! a network kind: `https://`, `ssh://`, `git://`, `git@`) or when `--geodesic-git URL` is given,
//! else by the relative path from the project to the checkout, with a note on standard error
//! ([`Dependency`]).

use crate::error::Error;
use std::path::{Path, PathBuf};

/// The JSON document of `geodesic new mission --json`. Fields are declared in byte order of
/// their keys, the order the document has always printed.
#[derive(
    Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct NewMissionDoc {
    /// The files written, in the order [`write`] returns them (paths under `path`).
    pub files: Vec<String>,
    /// The project's folder, as given (`--path`).
    pub path: String,
}

impl NewMissionDoc {
    /// The document of the project written into `path` as `files`.
    pub fn new(path: &Path, files: &[PathBuf]) -> NewMissionDoc {
        NewMissionDoc {
            files: files.iter().map(|f| f.display().to_string()).collect(),
            path: path.display().to_string(),
        }
    }
}

/// What to generate.
#[derive(Clone, Debug)]
pub struct NewMission {
    /// The mission's name: the package name and `mission.yaml`'s `name` (lower-case letters,
    /// digits, `-`, starting with a letter).
    pub name: String,
    /// The project's folder (must not exist, or be empty).
    pub path: PathBuf,
    /// The framework's repository (the folder holding `verification/core`): its remote and
    /// commit give the git dependency, or its relative path the path dependency.
    pub framework: PathBuf,
    /// The git URL to depend on (`--geodesic-git`) instead of the checkout's remote.
    pub git: Option<String>,
    /// The commit (or tag) of the git dependency (`--geodesic-rev`) instead of the checkout's
    /// `HEAD`.
    pub rev: Option<String>,
}

/// How the generated project depends on geodesic's framework crates.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Dependency {
    /// `{ git = url, rev = rev }`.
    Git {
        /// The repository's URL.
        url: String,
        /// The commit (or tag) pinned.
        rev: String,
    },
    /// `{ path = "<relative>/verification/core" }`, relative to the project's folder.
    Path(PathBuf),
}

impl Dependency {
    /// The TOML value of the dependency on the framework crate in `dir` (`verification/core`).
    pub fn toml(&self, dir: &str) -> String {
        match self {
            Dependency::Git { url, rev } => format!("{{ git = {url:?}, rev = {rev:?} }}"),
            Dependency::Path(p) => {
                let p = p.display().to_string().replace('\\', "/");
                format!("{{ path = {:?} }}", format!("{p}/{dir}"))
            }
        }
    }

    /// Where the README says geodesic is.
    fn where_(&self) -> String {
        match self {
            Dependency::Git { url, rev } => format!("[geodesic]({url}) at commit `{rev}`"),
            Dependency::Path(p) => format!(
                "geodesic (the checkout at `{}`, relative to this folder)",
                p.display()
            ),
        }
    }
}

/// Whether a remote URL can be fetched from another machine (not a local path or `file://`).
pub fn is_network_url(url: &str) -> bool {
    ["https://", "http://", "ssh://", "git://", "git@"]
        .iter()
        .any(|p| url.starts_with(p))
        // scp-like `user@host:path`
        || (url.contains('@') && url.contains(':') && !url.contains("://"))
}

/// `to` relative to `from` (both absolute): `../geodesic`.
pub fn relative(from: &Path, to: &Path) -> PathBuf {
    let f: Vec<_> = from.components().collect();
    let t: Vec<_> = to.components().collect();
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..f.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    out
}

fn git_out(dir: &Path, args: &[&str]) -> Option<String> {
    std::process::Command::new("git")
        .arg("-C")
        .arg(dir)
        .args(args)
        .stderr(std::process::Stdio::null())
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
}

/// The dependency of a project in `project` (absolute) on the checkout `framework` (absolute),
/// and the note to print when it is a path (why, and how to share the project).
pub fn dependency(
    n: &NewMission,
    framework: &Path,
    project: &Path,
) -> Result<(Dependency, Option<String>), Error> {
    let rev = || {
        n.rev
            .clone()
            .or_else(|| git_out(framework, &["rev-parse", "HEAD"]))
    };
    let remote = git_out(framework, &["remote", "get-url", "origin"]);
    if let Some(url) = n.git.clone() {
        let rev = rev().ok_or_else(|| {
            Error::usage(format!(
                "--geodesic-git {url}: {} is not a git checkout with a commit; give --geodesic-rev COMMIT",
                framework.display()
            ))
        })?;
        return Ok((Dependency::Git { url, rev }, None));
    }
    if let (Some(url), Some(rev)) = (remote.clone().filter(|u| is_network_url(u)), rev()) {
        return Ok((Dependency::Git { url, rev }, None));
    }
    let rel = relative(project, framework);
    let why = match remote {
        Some(u) => format!("its remote `origin` is {u}, not a network URL"),
        None => "no remote `origin`".to_string(),
    };
    let note = format!(
        "the project depends on geodesic by the relative path {} ({}: {why}): move them together, or give --geodesic-git URL (and --geodesic-rev COMMIT) to share it",
        rel.display(),
        framework.display()
    );
    Ok((Dependency::Path(rel), Some(note)))
}

/// The requirement ID prefix of a mission name (`my-widget` -> `MY-WIDGET`).
pub fn id_prefix(name: &str) -> String {
    name.to_uppercase().replace('_', "-")
}

fn check_name(name: &str) -> Result<(), Error> {
    let ok = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_')
        && name.len() <= 40
        && !name.ends_with('-');
    if ok {
        Ok(())
    } else {
        Err(Error::usage(format!(
            "new mission {name}: a name of lower-case letters, digits and `-`, starting with a letter (e.g. `solar-hinge`)"
        )))
    }
}

/// The files of the project: `(path relative to the project, text)`.
pub fn files(name: &str, dep: &Dependency) -> Vec<(String, String)> {
    let krate = name.replace('-', "_");
    let id = format!("{}-DEFL", id_prefix(name));
    let subst = |t: &str| {
        t.replace("@NAME@", name)
            .replace("@CRATE@", &krate)
            .replace("@ID@", &id)
            .replace("@CORE@", &dep.toml("verification/core"))
            .replace("@VERIFY@", &dep.toml("verification/verify"))
            .replace("@WHERE@", &dep.where_())
    };
    TEMPLATES
        .iter()
        .map(|(p, t)| (p.to_string(), subst(t)))
        .collect()
}

/// Writes the project (nothing is written when a file cannot be: the folder is created whole
/// in a sibling and renamed). Returns the files written, and the note to print on standard
/// error when the project depends on geodesic by a relative path ([`dependency`]).
pub fn write(n: &NewMission) -> Result<(Vec<PathBuf>, Option<String>), Error> {
    check_name(&n.name)?;
    if !n.framework.join("verification/core/Cargo.toml").is_file() {
        return Err(Error::usage(format!(
            "--geodesic {}: not geodesic's repository (no verification/core/Cargo.toml); give the folder of a geodesic clone",
            n.framework.display()
        )));
    }
    let framework = n.framework.canonicalize().map_err(|e| {
        Error::unreadable(format!("{}: {e}", n.framework.display())).in_file(&n.framework, 0)
    })?;
    if n.path.exists()
        && std::fs::read_dir(&n.path)
            .map(|mut d| d.next().is_some())
            .unwrap_or(true)
    {
        return Err(Error::usage(format!(
            "--path {}: exists and is not empty; give a new folder",
            n.path.display()
        )));
    }
    let parent = n
        .path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| Error::io_at(parent, e))?;
    let project = parent
        .canonicalize()
        .map_err(|e| Error::io_at(parent, e))?
        .join(n.path.file_name().unwrap_or(n.path.as_os_str()));
    let (dep, note) = dependency(n, &framework, &project)?;
    let stage = parent.join(format!(
        ".{}.new-{}",
        n.path
            .file_name()
            .map_or("mission".into(), |f| f.to_string_lossy().into_owned()),
        std::process::id()
    ));
    let result = (|| -> Result<Vec<PathBuf>, Error> {
        let mut written = Vec::new();
        for (rel, text) in files(&n.name, &dep) {
            let p = stage.join(&rel);
            if let Some(d) = p.parent() {
                std::fs::create_dir_all(d).map_err(|e| Error::io_at(d, e))?;
            }
            std::fs::write(&p, text).map_err(|e| Error::io_at(&p, e))?;
            written.push(n.path.join(rel));
        }
        // the framework's lock file: the project builds with the versions the framework was
        // tested with (and offline, from the same registry cache)
        let lock = framework.join("Cargo.lock");
        if lock.is_file() {
            std::fs::copy(&lock, stage.join("Cargo.lock")).map_err(|e| Error::io_at(&lock, e))?;
            written.push(n.path.join("Cargo.lock"));
        }
        if n.path.exists() {
            std::fs::remove_dir(&n.path).map_err(|e| Error::io_at(&n.path, e))?;
        }
        std::fs::rename(&stage, &n.path).map_err(|e| Error::io_at(&n.path, e))?;
        Ok(written)
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&stage);
    }
    result.map(|w| (w, note))
}

const TEMPLATES: &[(&str, &str)] = &[
    (
        "Cargo.toml",
        r#"[package]
name = "@NAME@"
version = "0.1.0"
edition = "2024"
publish = false

# A project of its own (not a member of an enclosing workspace).
[workspace]

[dependencies]
# geodesic's framework: requirements, checks, the matrix, the reports, the gate, ReqIF
# (a git dependency pinned to a commit, or a path relative to this folder: geodesic new
# mission chose; docs/guide-mission.md of geodesic says how to change it)
geodesic-core = @CORE@
geodesic-verify = @VERIFY@
serde = { version = "1", features = ["derive"] }
serde-saphyr = "2.1"

[profile.dev]
opt-level = 1

# as geodesic's own release profile: a build sharing geodesic's target folder reuses its crates
[profile.release]
debug = "line-tables-only"
"#,
    ),
    (
        "mission.yaml",
        r#"# The mission's descriptor: geodesic reads its requirement folder, its inputs, its document.
name: @NAME@
title: the @NAME@ cantilever
requirements: requirements
inputs:
  - name: design
    words: design inputs
    path: design.yaml
    about: "The cantilever's dimensions, material and load (units in the key names)"
document: document.yaml
# dispositions: dispositions.yaml      # known non-compliances (NCR, waiver, RFD)
# baseline: baseline/compliance.json   # what `verify --baseline` gates against
"#,
    ),
    (
        "document.yaml",
        r#"# Identification of the reports `verify` writes.
id: @ID@-VCD-001
issue: "1"
title: "@NAME@: compliance report and Verification Control Document"
project: "@NAME@"
"#,
    ),
    (
        "design.yaml",
        r#"# The cantilever's design inputs (SI units in the key names); the check reads this file.
length_m: 0.1
width_m: 0.02
thickness_m: 0.002
youngs_modulus_pa: 70.0e9
tip_load_n: 5.0
"#,
    ),
    (
        "requirements/structure.yaml",
        r#"family: structure
description: The cantilever's stiffness under its design load.
level: subsystem
stage: qualification
requirements:
  - id: @ID@
    title: Tip deflection under the design load
    text: "The cantilever's tip shall deflect by at most 2 mm under the design tip load."
    source: "@NAME@ specification"
    quantity: "tip deflection F L^3 / (3 E I), I = w t^3 / 12"
    dimension: length
    limit: "<= 2 mm"
    method: analysis
    activity: "Euler-Bernoulli cantilever model on the design inputs"
    check: tip-deflection
"#,
    ),
    (
        "src/lib.rs",
        r#"//! @NAME@: its model, its check and its mission, verified with geodesic.

use geodesic_core::check::{Basis, Check, CheckContext, CheckError, Evidence};
use geodesic_core::units::{Dim, Quantity};
use geodesic_verify::Mission;

/// The cantilever's design inputs (`design.yaml`).
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Design {
    /// Length [m].
    pub length_m: f64,
    /// Width [m].
    pub width_m: f64,
    /// Thickness [m].
    pub thickness_m: f64,
    /// Young's modulus [Pa].
    pub youngs_modulus_pa: f64,
    /// Tip load [N].
    pub tip_load_n: f64,
}

impl Design {
    /// Parses the design file; the error names the file.
    pub fn from_yaml(text: &str, label: &str) -> Result<Design, String> {
        let d: Design = serde_saphyr::from_str(text).map_err(|e| format!("{label}: {e}"))?;
        for (k, v) in [
            ("length_m", d.length_m),
            ("width_m", d.width_m),
            ("thickness_m", d.thickness_m),
            ("youngs_modulus_pa", d.youngs_modulus_pa),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{label}: {k} = {v}: must be a positive number"));
            }
        }
        if !d.tip_load_n.is_finite() {
            return Err(format!("{label}: tip_load_n is not a number"));
        }
        Ok(d)
    }

    /// Tip deflection F L^3 / (3 E I) with I = w t^3 / 12 [m].
    pub fn tip_deflection_m(&self) -> f64 {
        let i = self.width_m * self.thickness_m.powi(3) / 12.0;
        self.tip_load_n.abs() * self.length_m.powi(3) / (3.0 * self.youngs_modulus_pa * i)
    }
}

/// The check `tip-deflection`: the model on the run's design inputs.
pub struct TipDeflection;

impl Check for TipDeflection {
    fn name(&self) -> &'static str {
        "tip-deflection"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["@ID@"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        let f = ctx.inputs.file("design")?;
        let d = Design::from_yaml(&f.text, &f.label)
            .map_err(|e| CheckError::input(e).in_file(&f.label, 0))?;
        Ok(vec![
            Evidence::measured(
                "@ID@",
                Quantity::new(d.tip_deflection_m(), Dim::LENGTH),
                Basis::Model,
                "Euler-Bernoulli cantilever: F L^3 / (3 E I)",
            )
            .with_input("design", f.label.clone())
            .with_input("design_sha256", f.sha256.clone()),
        ])
    }
}

/// The mission: its descriptor and files (built in, so that the program verifies from any
/// folder) and its checks.
pub fn mission() -> Mission {
    Mission::with_checks(
        include_str!("../mission.yaml"),
        "mission.yaml",
        ".",
        || vec![Box::new(TipDeflection)],
    )
    .expect("mission.yaml is valid")
    .builtin("requirements/structure.yaml", include_str!("../requirements/structure.yaml"))
    .builtin("design.yaml", include_str!("../design.yaml"))
    .builtin("document.yaml", include_str!("../document.yaml"))
    .validate("design", |f| Design::from_yaml(&f.text, &f.label).map(|_| ()))
}
"#,
    ),
    (
        "src/main.rs",
        r#"//! `cargo run -- test` records the traced tests; `cargo run -- verify --reports reports` (or
//! no command) verifies @NAME@ against its requirements; `--baseline OLD.json` gates; `export
//! reqif --out FILE` exports ReqIF.

fn main() -> std::process::ExitCode {
    geodesic_verify::harness::main(@CRATE@::mission())
}
"#,
    ),
    (
        "tests/traced.rs",
        r#"//! Tests traced to the requirements: each names the requirement it verifies and asserts
//! its limit (read from requirements/) or an independent reference.

#[test]
fn the_design_meets_the_deflection_limit() {
    geodesic_core::verifies!("@ID@");
    let d = @CRATE@::Design::from_yaml(include_str!("../design.yaml"), "design.yaml").unwrap();
    geodesic_core::trace::assert_limit("@ID@", d.tip_deflection_m());
}

#[test]
fn the_model_matches_a_hand_calculation() {
    geodesic_core::verifies!("@ID@");
    // 1 m, 1 N, E = 1 Pa, w = 12 m, t = 1 m: I = 1 m^4, deflection 1/3 m
    let d = @CRATE@::Design {
        length_m: 1.0,
        width_m: 12.0,
        thickness_m: 1.0,
        youngs_modulus_pa: 1.0,
        tip_load_n: 1.0,
    };
    geodesic_core::trace::assert_reference("@ID@", "F L^3 / 3 E I by hand", d.tip_deflection_m(), 1.0 / 3.0, 1e-12);
}
"#,
    ),
    (".gitignore", "/target\n/reports\n"),
    (
        "README.md",
        r#"# @NAME@

Verified with @WHERE@: requirements in `requirements/`, inputs in `design.yaml`, the check
and its model in `src/lib.rs`, traced tests in `tests/traced.rs`.

The two commands:

```sh
cargo run -- test                                       # run the traced tests, record their run
cargo run -- verify --require-tests --reports reports   # verify: the matrix, the VCD, index.html
```

`test` runs `cargo test` (arguments after it are passed through) and writes
`target/geodesic/test-run.json`; `verify --require-tests` fails when that run is missing, stale
(a source, requirement or input changed since) or a traced test failed. More:

```sh
cargo run -- verify --baseline reports/compliance.json --reports reports-new   # the gate
cargo run -- export reqif --out reports/requirements.reqif --matrix reports/compliance.json
cargo run -- requirements list
```

Edit the limit in `requirements/structure.yaml` or a dimension in `design.yaml` and verify
again: the verdict moves.
"#,
    ),
];

#[cfg(test)]
mod tests {
    #[test]
    fn new_mission_doc_prints_its_keys_in_byte_order_and_reads_back() {
        let dir = std::path::Path::new("../widget");
        let doc = super::NewMissionDoc::new(dir, &[dir.join("Cargo.toml"), dir.join("src/lib.rs")]);
        let printed = serde_json::to_string_pretty(&doc).unwrap();
        let sorted = serde_json::to_string_pretty(&serde_json::to_value(&doc).unwrap()).unwrap();
        assert_eq!(printed, sorted);
        assert_eq!(doc.files[1], "../widget/src/lib.rs");
        assert_eq!(
            serde_json::from_str::<super::NewMissionDoc>(&printed).unwrap(),
            doc
        );
    }

    #[test]
    fn names_are_checked() {
        for bad in ["", "Widget", "9lives", "a b", "x-"] {
            assert!(super::check_name(bad).is_err(), "{bad}");
        }
        for good in ["widget", "solar-hinge", "m2_arm"] {
            assert!(super::check_name(good).is_ok(), "{good}");
        }
    }

    #[test]
    fn every_placeholder_is_filled() {
        let dep = super::Dependency::Path("../fw".into());
        for (p, t) in super::files("my-widget", &dep) {
            assert!(
                !t.contains("@NAME@")
                    && !t.contains("@ID@")
                    && !t.contains("@CRATE@")
                    && !t.contains("@CORE@")
                    && !t.contains("@VERIFY@")
                    && !t.contains("@WHERE@"),
                "{p}"
            );
        }
    }

    /// The git case: the manifest pins the URL and the commit, names no path.
    #[test]
    fn a_git_dependency_names_the_url_and_the_commit() {
        let dep = super::Dependency::Git {
            url: "https://example.org/geodesic.git".into(),
            rev: "0123abcd".into(),
        };
        let files = super::files("my-widget", &dep);
        let toml = &files.iter().find(|(p, _)| p == "Cargo.toml").unwrap().1;
        assert!(
            toml.contains(
                r#"geodesic-core = { git = "https://example.org/geodesic.git", rev = "0123abcd" }"#
            ),
            "{toml}"
        );
        assert!(
            toml.contains(r#"geodesic-verify = { git = "https://example.org/geodesic.git", rev = "0123abcd" }"#),
            "{toml}"
        );
        assert!(!toml.contains("path ="), "{toml}");
        let readme = &files.iter().find(|(p, _)| p == "README.md").unwrap().1;
        assert!(readme.contains("cargo run -- test") && readme.contains("verify --require-tests"));
    }

    #[test]
    fn a_path_dependency_is_relative() {
        let dep = super::Dependency::Path(super::relative(
            std::path::Path::new("/work/projects/widget"),
            std::path::Path::new("/work/geodesic"),
        ));
        assert_eq!(dep, super::Dependency::Path("../../geodesic".into()));
        let files = super::files("widget", &dep);
        let toml = &files.iter().find(|(p, _)| p == "Cargo.toml").unwrap().1;
        assert!(
            toml.contains(r#"geodesic-core = { path = "../../geodesic/verification/core" }"#),
            "{toml}"
        );
    }

    #[test]
    fn network_urls_are_told_from_local_ones() {
        for u in [
            "https://github.com/a/b.git",
            "ssh://git@host/b",
            "git@github.com:a/b.git",
            "git://host/b",
        ] {
            assert!(super::is_network_url(u), "{u}");
        }
        for u in ["/srv/git/geodesic", "../geodesic", "file:///srv/geodesic"] {
            assert!(!super::is_network_url(u), "{u}");
        }
    }
}
