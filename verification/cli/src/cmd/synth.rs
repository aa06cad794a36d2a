//! `geodesic synth`: not yet implemented.

use crate::error::{CliError, CmdResult};

/// Flags of `geodesic synth`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(_args: Args) -> CmdResult {
    Err(CliError::bad("geodesic synth is not implemented yet"))
}
