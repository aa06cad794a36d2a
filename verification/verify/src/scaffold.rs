//! `geodesic new mission NAME --path DIR`: a project outside the framework's repository that
//! verifies its own system with geodesic: a descriptor, one requirement, one input file, one
//! check with a small model (a cantilever's tip deflection), a traced test, and a `main` that
//! is the harness ([`crate::harness::main`]). It builds and verifies as generated.

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
    /// The framework's repository (the folder holding `verification/core`), for the path
    /// dependencies.
    pub framework: PathBuf,
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
        Err(Error::bad(format!(
            "new mission {name}: a name of lower-case letters, digits and `-`, starting with a letter (e.g. `cubesat-hinge`)"
        )))
    }
}

/// The files of the project: `(path relative to the project, text)`.
pub fn files(name: &str, framework: &Path) -> Vec<(String, String)> {
    let krate = name.replace('-', "_");
    let id = format!("{}-DEFL", id_prefix(name));
    let fw = framework.display().to_string();
    let subst = |t: &str| {
        t.replace("@NAME@", name)
            .replace("@CRATE@", &krate)
            .replace("@ID@", &id)
            .replace("@FW@", &fw)
    };
    TEMPLATES
        .iter()
        .map(|(p, t)| (p.to_string(), subst(t)))
        .collect()
}

/// Writes the project (nothing is written when a file cannot be: the folder is created whole
/// in a sibling and renamed). Returns the files written.
pub fn write(n: &NewMission) -> Result<Vec<PathBuf>, Error> {
    check_name(&n.name)?;
    if !n.framework.join("verification/core/Cargo.toml").is_file() {
        return Err(Error::bad(format!(
            "--geodesic {}: not geodesic's repository (no verification/core/Cargo.toml); give the folder of a geodesic clone",
            n.framework.display()
        )));
    }
    let framework = n
        .framework
        .canonicalize()
        .map_err(|e| Error::bad(format!("{}: {e}", n.framework.display())))?;
    if n.path.exists()
        && std::fs::read_dir(&n.path)
            .map(|mut d| d.next().is_some())
            .unwrap_or(true)
    {
        return Err(Error::bad(format!(
            "--path {}: exists and is not empty; give a new folder",
            n.path.display()
        )));
    }
    let parent = n
        .path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(|e| Error::Io(format!("{}: {e}", parent.display())))?;
    let stage = parent.join(format!(
        ".{}.new-{}",
        n.path
            .file_name()
            .map_or("mission".into(), |f| f.to_string_lossy().into_owned()),
        std::process::id()
    ));
    let result = (|| -> Result<Vec<PathBuf>, Error> {
        let mut written = Vec::new();
        for (rel, text) in files(&n.name, &framework) {
            let p = stage.join(&rel);
            if let Some(d) = p.parent() {
                std::fs::create_dir_all(d)
                    .map_err(|e| Error::Io(format!("{}: {e}", d.display())))?;
            }
            std::fs::write(&p, text).map_err(|e| Error::Io(format!("{}: {e}", p.display())))?;
            written.push(n.path.join(rel));
        }
        // the framework's lock file: the project builds with the versions the framework was
        // tested with (and offline, from the same registry cache)
        let lock = framework.join("Cargo.lock");
        if lock.is_file() {
            std::fs::copy(&lock, stage.join("Cargo.lock"))
                .map_err(|e| Error::Io(format!("{}: {e}", lock.display())))?;
            written.push(n.path.join("Cargo.lock"));
        }
        if n.path.exists() {
            std::fs::remove_dir(&n.path)
                .map_err(|e| Error::Io(format!("{}: {e}", n.path.display())))?;
        }
        std::fs::rename(&stage, &n.path)
            .map_err(|e| Error::Io(format!("{}: {e}", n.path.display())))?;
        Ok(written)
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&stage);
    }
    result
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
geodesic-core = { path = "@FW@/verification/core" }
geodesic-verify = { path = "@FW@/verification/verify" }
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
        let d = Design::from_yaml(&f.text, &f.label).map_err(CheckError)?;
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
        r#"//! `cargo run -- verify --reports reports` (or no command): verifies @NAME@ against its
//! requirements; `--baseline OLD.json` gates; `export-reqif --out FILE` exports ReqIF.

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

Verified with [geodesic](@FW@): requirements in `requirements/`, inputs in `design.yaml`, the
check and its model in `src/lib.rs`, traced tests in `tests/traced.rs`.

```sh
cargo run -- verify --reports reports        # the matrix, the VCD, JUnit, index.html in reports/
cargo run -- verify --baseline reports/compliance.json --reports reports-new   # the gate
cargo run -- export-reqif --out reports/requirements.reqif --matrix reports/compliance.json
cargo test                                   # the traced tests
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
        for good in ["widget", "cubesat-hinge", "m2_arm"] {
            assert!(super::check_name(good).is_ok(), "{good}");
        }
    }

    #[test]
    fn every_placeholder_is_filled() {
        for (p, t) in super::files("my-widget", std::path::Path::new("/fw")) {
            assert!(
                !t.contains("@NAME@") && !t.contains("@ID@") && !t.contains("@CRATE@"),
                "{p}"
            );
        }
    }
}
