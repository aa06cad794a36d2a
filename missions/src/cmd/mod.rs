//! The root mission's own commands (LISA Pathfinder's release: the Monte Carlo, the charge,
//! the capture criterion, the plungers, the tip radius, the sensitivity, a campaign of measured
//! releases), added to the `geodesic`
//! program beside the framework's commands.

use crate::inputs::ModelInput;
use clap::{Arg, ArgMatches};
use geodesic_verify::plugin::{PluginCommand, args};
use geodesic_verify::schema::Entry;
use std::path::PathBuf;

pub mod campaign;
pub mod capture;
pub mod charge;
pub mod merge;
pub mod montecarlo;
pub mod plunger;
pub mod sensitivity;
pub mod tipradius;

/// The schema of each command's `--json` document (`geodesic schema`), from the typed document
/// it prints.
pub fn schemas() -> Vec<Entry> {
    type Input = geodesic_core::check::InputFile;
    vec![
        Entry::of::<geodesic_capture::report::CaptureReport<Input>>("capture"),
        Entry::of::<geodesic_charge::report::ChargeReport<Input>>("charge"),
        Entry::of::<geodesic_release::report::McReport>("montecarlo"),
        Entry::of::<geodesic_release::report::McReport>("merge"),
        Entry::of::<geodesic_checks::plunger::PlungerReport>("plunger"),
        Entry::of::<geodesic_checks::tipradius::TradeOff>("tip-radius"),
        Entry::of::<sensitivity::SensitivityDoc>("sensitivity"),
        Entry::of::<geodesic_campaign::CampaignReport>("campaign"),
    ]
}

/// The commands, each with its help and examples.
pub fn commands() -> Vec<PluginCommand> {
    vec![
        PluginCommand::of::<capture::Args>(
            "capture",
            "Evaluate the DFACS quartic capture criterion for one TM state",
            Some("Examples:
  geodesic capture --vz 3um/s                        # exit 1 when the TM is not captured
  geodesic capture --vz 12um/s --x 20um --thz 1mrad --json
  geodesic capture --state state.yaml --vz-samples velocities.txt
Values may carry units; bare numbers are SI (m, m/s, rad, rad/s)."), |m| {
            let mut a: capture::Args = args(m)?;
            a.capture = given(m, ModelInput::capture());
            capture::run(a)
        }).reading(ModelInput::capture(), &["xlim"]),
        PluginCommand::of::<charge::Args>(
            "charge",
            "Charge left on the TM after release (contact electrification)",
            Some("Examples:
  geodesic charge
  geodesic charge --c-rt-pf 2.5 --json          # the thesis's rounded C_RT
  geodesic charge --dv-2sigma-v 0.5V --neutralise-e \"-1e8 e\""), |m| {
            let mut a: charge::Args = args(m)?;
            a.charge = given(m, ModelInput::charge());
            charge::run(a)
        }).reading(ModelInput::charge(), &[]),
        PluginCommand::of::<montecarlo::Args>(
            "montecarlo",
            "Run the in-flight release Monte Carlo",
            Some("Examples:
  geodesic montecarlo --n 100000 --seed 1
  geodesic montecarlo --n 100000 --case adhesion --budget my-budget.yaml --json
  geodesic montecarlo --n 1000000 --seed 1 --shard 2/8 --out parts/part-2.json   # then `geodesic merge`"), |m| {
            let mut a: montecarlo::Args = args(m)?;
            a.budget = given(m, ModelInput::budget());
            montecarlo::run(a)
        }).reading(ModelInput::budget(), &[]),
        PluginCommand::of::<merge::Args>(
            "merge",
            "Merge partial Monte Carlo results written with --shard",
            Some("Examples:
  geodesic merge parts/part-*.json
  geodesic merge parts/part-1.json parts/part-2.json --json"), |m| merge::run(args(m)?)),
        PluginCommand::of::<plunger::Args>(
            "plunger",
            "The plungers' attraction on the charged TM in the 25 s after the release",
            None, |m| plunger::run(args(m)?)),
        PluginCommand::of::<tipradius::Args>(
            "tip-radius",
            "The tip-radius trade-off: worst-case release velocity against tip radius",
            None, |m| {
            let mut a: tipradius::Args = args(m)?;
            a.budget = given(m, ModelInput::budget());
            tipradius::run(a)
        }).reading(ModelInput::budget(), &[]),
        PluginCommand::of::<campaign::Args>(
            "campaign",
            "Fit every release of a campaign, tabulate P_x, F_peak, dt and estimate the adhesion population",
            Some("Examples:
  geodesic synth --campaign 30 --out camp --seed 4
  geodesic campaign camp/campaign.yaml --effects needle_contact,tip_contact,tip_adhesion
  geodesic campaign camp --effects needle_contact,tip_contact,tip_adhesion --json > campaign.json
A release that cannot be fitted is listed with its file and cause (exit 2 after the table).
The page (table, population, releases, histograms, adhesion scatter) is written to DIR/campaign/ (--reports DIR, default reports)."), |m| campaign::run(args(m)?)),
        PluginCommand::of::<sensitivity::Args>(
            "sensitivity",
            "What drives the release velocity: Saltelli/Jansen indices per uncertainty group",
            None, |m| {
            let mut a: sensitivity::Args = args(m)?;
            a.budget = given(m, ModelInput::budget());
            sensitivity::run(a)
        }).reading(ModelInput::budget(), &[]),
    ]
}

/// A command that reads one of the root mission's declared inputs: its flag `--NAME FILE.yaml`
/// and its help come from the descriptor (`mission.yaml` `inputs:`), as `verify`'s do.
trait Reading {
    fn reading(self, input: ModelInput, aliases: &[&'static str]) -> PluginCommand;
}

impl Reading for PluginCommand {
    fn reading(mut self, input: ModelInput, aliases: &[&'static str]) -> PluginCommand {
        let arg = Arg::new(input.name())
            .long(input.name())
            .aliases(aliases.iter().copied())
            .value_name("FILE.yaml")
            .value_parser(clap::value_parser!(PathBuf))
            .help(format!(
                "{} [default: ./{} if present, else the built-in copy; as verify]",
                input.about(),
                input.repository_path()
            ));
        self.command = self.command.arg(arg);
        self
    }
}

/// The file given with an input's flag.
fn given(m: &ArgMatches, input: ModelInput) -> Option<PathBuf> {
    m.get_one::<PathBuf>(input.name()).cloned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_flags_derive_from_the_descriptor() {
        let cmds = commands();
        for (command, input) in [
            ("montecarlo", ModelInput::budget()),
            ("sensitivity", ModelInput::budget()),
            ("tip-radius", ModelInput::budget()),
            ("capture", ModelInput::capture()),
            ("charge", ModelInput::charge()),
        ] {
            let c = cmds.iter().find(|c| c.name() == command).unwrap();
            let m = c
                .command
                .clone()
                .try_get_matches_from([command, &input.flag(), "given.yaml"])
                .unwrap();
            assert_eq!(
                given(&m, input),
                Some(PathBuf::from("given.yaml")),
                "{command}"
            );
            let help = c.command.clone().render_long_help().to_string();
            assert!(help.contains(input.about()), "{command}: {help}");
            assert!(help.contains(input.repository_path()), "{command}: {help}");
        }
        // an alias of old
        let c = cmds.iter().find(|c| c.name() == "capture").unwrap();
        let m = c
            .command
            .clone()
            .try_get_matches_from(["capture", "--xlim", "x.yaml"])
            .unwrap();
        assert_eq!(
            given(&m, ModelInput::capture()),
            Some(PathBuf::from("x.yaml"))
        );
    }
}
