//! `geodesic effects`: the effect catalogue (every effect a model can be built from), with each
//! parameter's unit, nominal value and physical range, read from the one registry that `fit`,
//! `diagnose` and `synth` use (`geodesic_facility::effects::catalogue`).

use crate::error::{CliError, CmdResult};
use geodesic_facility::effects::{EffectDoc, EffectKind, EffectsDoc, Scenario, catalogue};

/// Flags of `geodesic effects`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  geodesic effects\n  geodesic effects --scenario rt-retraction --json"
)]
pub struct Args {
    /// Only the effects of this scenario (`tmmf-release`, `rt-retraction`).
    #[arg(long, value_name = "S")]
    pub scenario: Option<String>,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

fn kind(k: EffectKind) -> &'static str {
    k.name()
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let only = match &args.scenario {
        Some(s) => Some(Scenario::from_name(s).ok_or_else(|| {
            CliError::usage(format!(
                "--scenario {s}: unknown scenario (tmmf-release or rt-retraction)"
            ))
        })?),
        None => None,
    };
    let effects: Vec<_> = catalogue()
        .iter()
        .filter(|e| only.is_none_or(|s| e.scenario() == s))
        .collect();
    if args.json {
        let doc = EffectsDoc {
            effects: effects.iter().map(|e| EffectDoc::of(**e)).collect(),
        };
        let text = serde_json::to_string(&doc).map_err(CliError::io)?;
        println!("{text}");
        return Ok(0);
    }
    for e in effects {
        println!(
            "{} ({}, {}): {}",
            e.name(),
            e.scenario().name(),
            kind(e.kind()),
            e.summary()
        );
        for p in e.params() {
            println!(
                "  {}.{:<8} [{}]  nominal {:e}  range [{:e}, {:e}]",
                e.name(),
                p.name,
                p.unit,
                p.nominal,
                p.lower,
                p.upper
            );
        }
    }
    Ok(0)
}
