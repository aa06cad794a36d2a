//! The missions this repository verifies with geodesic's framework, each a descriptor
//! (`mission.yaml`) plus its code: [`lisa_pathfinder`] (the repository's root mission) and
//! [`drag_free_cubesat`] (`missions/drag-free-cubesat/`). The `geodesic` program registers
//! [`all`]; `geodesic verify --mission NAME` picks one.

pub mod drag_free_cubesat;
pub mod lisa_pathfinder;

use geodesic_verify::Mission;

/// Every mission of the repository; the first is the root mission (`verify` without
/// `--mission`).
pub fn all() -> Vec<Mission> {
    vec![lisa_pathfinder::mission(), drag_free_cubesat::mission()]
}

/// The missions' own commands for the `geodesic` program (beside the framework's).
pub fn commands() -> Vec<geodesic_verify::plugin::PluginCommand> {
    Vec::new()
}

/// Checks a time series (the spectral check's input) before anything runs.
pub(crate) fn series(p: &std::path::Path) -> Result<(), String> {
    geodesic_fit::spectral::Series::load(p)
        .map(|_| ())
        .map_err(|e| e.to_string())
}
