//! `geodesic capture`: not yet implemented.

use crate::error::{CliError, CmdResult};

/// Flags of `geodesic capture`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(_args: Args) -> CmdResult {
    Err(CliError::bad("geodesic capture is not implemented yet"))
}
