//! Commands a mission adds to a program: each a clap command and the function that runs it.
//! The `geodesic` program lists the commands of every registered mission beside its own.

use crate::error::CmdResult;
use clap::{ArgMatches, Command};

/// One command a mission adds.
pub struct PluginCommand {
    /// Its clap command (name, about, flags, examples).
    pub command: Command,
    /// Runs it on its parsed flags.
    pub run: fn(&ArgMatches) -> CmdResult,
}

impl PluginCommand {
    /// A command named `name` from a clap-derived `Args` type, its one-line `about`, its
    /// examples (`after_help`) and its `run` function.
    pub fn of<A: clap::Args + clap::FromArgMatches>(
        name: &'static str,
        about: &'static str,
        after_help: Option<&'static str>,
        run: fn(&ArgMatches) -> CmdResult,
    ) -> PluginCommand {
        let mut command = A::augment_args(Command::new(name)).about(about);
        if let Some(h) = after_help {
            command = command.after_help(h);
        }
        PluginCommand { command, run }
    }

    /// The command's name.
    pub fn name(&self) -> &str {
        self.command.get_name()
    }
}

/// Parses `A` from a plugin command's matches (a clap error becomes a usage error, exit 2).
pub fn args<A: clap::FromArgMatches>(m: &ArgMatches) -> Result<A, crate::Error> {
    A::from_arg_matches(m).map_err(|e| crate::Error::usage(e.to_string()))
}
