//! `geodesic verify`: runs the verify pipeline ([`geodesic_verify::pipeline`]) for a mission and
//! prints its outcome. Exit 0 when nothing is non-compliant, 1 when something is, 2 on bad
//! input.

use crate::error::CmdResult;
use clap::{Arg, ArgMatches, Command};
use geodesic_verify::pipeline::Options;

/// Flags of `geodesic verify`: the pipeline's options ([`geodesic_verify::harness::verify_args`],
/// with a `--NAME FILE` flag per input a registered mission declares) and `--mission`.
#[derive(Debug)]
pub struct Args {
    /// The pipeline's options.
    pub options: Options,
    /// `--mission NAME`.
    pub mission: Option<String>,
}

impl clap::FromArgMatches for Args {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let mut options = geodesic_verify::harness::options(m);
        options.build_commit = Some(env!("GEODESIC_BUILD_COMMIT").to_string());
        Ok(Args {
            options,
            mission: m.get_one::<String>("mission").cloned(),
        })
    }
    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}

impl clap::Args for Args {
    fn augment_args(cmd: Command) -> Command {
        let missions: Vec<&geodesic_verify::Mission> = crate::missions::all().iter().collect();
        let names: Vec<&str> = missions.iter().map(|m| m.spec.name.as_str()).collect();
        geodesic_verify::harness::verify_args(cmd, &missions).arg(
            Arg::new("mission")
                .long("mission")
                .value_name("NAME")
                .help(format!(
                    "The mission verified: {} [default: the root mission, or the mission whose folder holds --requirements]",
                    names.join(", ")
                )),
        )
    }
    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let mission = crate::missions::select(
        args.mission.as_deref(),
        args.options.requirements.as_deref(),
    )?;
    let out = geodesic_verify::pipeline::run(&mission, &args.options)?;
    Ok(geodesic_verify::harness::print(
        "geodesic",
        &args.options,
        &out,
    ))
}
