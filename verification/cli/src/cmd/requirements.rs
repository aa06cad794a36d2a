//! `geodesic requirements check | list | show ID` ([`geodesic_verify::requirements`]) for the
//! mission whose requirement folder is named (the root mission without `--requirements`).

use crate::error::CmdResult;
pub use geodesic_verify::requirements::Args;

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let mission = crate::missions::select(None, args.requirements_dir())?;
    geodesic_verify::requirements::run(&mission, args)
}
