//! The missions this program verifies, registered once at start-up by `main`
//! (`geodesic_missions::all()`); the first is the root mission (`verify` without `--mission`).

use crate::error::CliError;
use geodesic_verify::Mission;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

static MISSIONS: OnceLock<Vec<Mission>> = OnceLock::new();

/// Registers the missions (once, before the flags are parsed: `verify` has a flag per
/// declared input).
pub fn install(missions: Vec<Mission>) {
    let _ = MISSIONS.set(missions);
}

/// Every registered mission.
pub fn all() -> &'static [Mission] {
    MISSIONS.get().map_or(&[], Vec::as_slice)
}

/// The names of every registered mission's checks, each once, in the missions' order.
pub fn check_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for n in all().iter().flat_map(Mission::check_names) {
        if !names.contains(&n) {
            names.push(n);
        }
    }
    names
}

/// The root mission.
pub fn root() -> Result<&'static Mission, CliError> {
    all()
        .first()
        .ok_or_else(|| CliError::usage("no mission is registered"))
}

/// The mission `--mission NAME` names, or the one whose folder holds a given requirement folder
/// (`--requirements missions/NAME/requirements`: its `mission.yaml` beside it), else the root
/// mission.
pub fn select(name: Option<&str>, requirements: Option<&Path>) -> Result<Mission, CliError> {
    if let Some(n) = name {
        return all()
            .iter()
            .find(|m| m.spec.name == n)
            .cloned()
            .ok_or_else(|| {
                CliError::usage(format!(
                    "--mission {n}: no such mission (missions: {})",
                    all()
                        .iter()
                        .map(|m| m.spec.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            });
    }
    if let Some(dir) = requirements {
        let folder = dir.parent().unwrap_or(Path::new("."));
        let descriptor = folder.join("mission.yaml");
        if let Ok(text) = std::fs::read_to_string(&descriptor) {
            let spec =
                geodesic_verify::MissionSpec::from_yaml(&text, &descriptor.display().to_string())?;
            if let Some(m) = all().iter().find(|m| m.spec.name == spec.name) {
                return Ok(m.clone().at(folder));
            }
        }
    }
    root().cloned()
}

/// The root mission's requirement set (`dir` if given), with its source label and SHA-256:
/// for the commands that read requirements outside `verify`.
pub fn load_requirements(
    dir: Option<&PathBuf>,
) -> Result<(geodesic_core::Requirements, String, String), CliError> {
    let m = select(None, dir.map(PathBuf::as_path))?;
    geodesic_verify::pipeline::load_requirements(&m, dir)
}
