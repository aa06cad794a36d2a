//! The root mission's own commands (LISA Pathfinder's release: the Monte Carlo, the charge,
//! the capture criterion, the plungers, the tip radius, the sensitivity), added to the `geodesic`
//! program beside the framework's commands.

use geodesic_verify::plugin::{PluginCommand, args};
use geodesic_verify::schema::Entry;

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
Values may carry units; bare numbers are SI (m, m/s, rad, rad/s)."), |m| capture::run(args(m)?)),
        PluginCommand::of::<charge::Args>(
            "charge",
            "Charge left on the TM after release (contact electrification)",
            Some("Examples:
  geodesic charge
  geodesic charge --c-rt-pf 2.5 --json          # the thesis's rounded C_RT
  geodesic charge --dv-2sigma-v 0.5V --neutralise-e \"-1e8 e\""), |m| charge::run(args(m)?)),
        PluginCommand::of::<montecarlo::Args>(
            "montecarlo",
            "Run the in-flight release Monte Carlo",
            Some("Examples:
  geodesic montecarlo --n 100000 --seed 1
  geodesic montecarlo --n 100000 --case adhesion --budget my-budget.yaml --json
  geodesic montecarlo --n 1000000 --seed 1 --shard 2/8 --out parts/part-2.json   # then `geodesic merge`"), |m| montecarlo::run(args(m)?)),
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
            None, |m| tipradius::run(args(m)?)),
        PluginCommand::of::<sensitivity::Args>(
            "sensitivity",
            "What drives the release velocity: Saltelli/Jansen indices per uncertainty group",
            None, |m| sensitivity::run(args(m)?)),
    ]
}
