//! The missions this repository verifies with geodesic's framework, each a descriptor
//! (`mission.yaml`) plus its code: [`lisa_pathfinder`] (the repository's root mission) and the
//! Drag-Free CubeSat (`missions/drag-free-cubesat/`, a crate of its own). The `geodesic` program
//! registers [`all`]; `geodesic verify --mission NAME` picks one.

mod cmd;
mod inputs;
pub mod lisa_pathfinder;
pub mod ranges;
mod threads;

use geodesic_verify::Mission;
// the paths the commands were written with
use geodesic_verify::{preflight, progress, quantity};

/// The commands' error type.
mod error {
    pub use geodesic_verify::error::{CmdResult, Error as CliError};
}

/// The root mission's requirement set, for its commands.
mod missions {
    use std::path::PathBuf;

    /// The root mission's requirement set (`dir` if given), with its source label and SHA-256.
    pub fn load_requirements(
        dir: Option<&PathBuf>,
    ) -> Result<(geodesic_core::Requirements, String, String), crate::error::CliError> {
        geodesic_verify::pipeline::load_requirements(&crate::lisa_pathfinder::mission(), dir)
    }
}

/// Every mission of the repository; the first is the root mission (`verify` without
/// `--mission`).
pub fn all() -> Vec<Mission> {
    vec![
        lisa_pathfinder::mission(),
        geodesic_mission_drag_free_cubesat::mission(),
    ]
}

/// The missions' own commands for the `geodesic` program (beside the framework's).
pub fn commands() -> Vec<geodesic_verify::plugin::PluginCommand> {
    cmd::commands()
}

/// The JSON Schema of each of those commands' `--json` document (`geodesic schema`).
pub fn schemas() -> Vec<geodesic_verify::schema::Entry> {
    cmd::schemas()
}
