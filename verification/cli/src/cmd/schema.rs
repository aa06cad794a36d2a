//! `geodesic schema [COMMAND]`: the JSON Schema (draft 2020-12) of a command's `--json`
//! document, generated from the typed struct the command prints
//! ([`geodesic_verify::schema`]); the registered missions add their commands' schemas.

use crate::error::{CliError, CmdResult};
use geodesic_verify::schema::{Entry, ListDoc, VerifyDoc};
use std::path::PathBuf;

/// Flags of `geodesic schema`.
#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:
  geodesic schema                                   # the commands that have a schema
  geodesic schema verify > verify.schema.json       # the contract of `geodesic verify --json`
  geodesic schema --all --out schemas/              # schemas/<command>.schema.json, one a command")]
pub struct Args {
    /// The command whose `--json` document's schema is printed.
    #[arg(value_name = "COMMAND", conflicts_with = "all")]
    pub command: Option<String>,
    /// Write every command's schema into --out DIR as <command>.schema.json.
    #[arg(long, requires = "out")]
    pub all: bool,
    /// Folder of --all.
    #[arg(long, value_name = "DIR", requires = "all")]
    pub out: Option<PathBuf>,
    /// Print exactly one JSON document on standard output (a schema is one already; without
    /// COMMAND: the list of commands).
    #[arg(long)]
    pub json: bool,
}

/// A schema-only view of `synth --json`: a record's document, or a campaign's with `--campaign`.
#[derive(schemars::JsonSchema)]
#[serde(untagged)]
#[allow(dead_code)]
enum SynthJson {
    /// `geodesic synth --out X.yaml --json`: the record written.
    Record(Box<geodesic_dataset::synth::SynthDoc>),
    /// `geodesic synth --campaign N --out DIR --json`: the campaign written.
    Campaign(geodesic_dataset::synth::SynthCampaignDoc),
}

/// A schema-only view of `export --json`: `export reqif`'s summary or `export needs`'.
#[derive(schemars::JsonSchema)]
#[serde(untagged)]
#[allow(dead_code)]
enum ExportJson {
    /// `geodesic export reqif --json`.
    Reqif(Box<geodesic_exchange::reqif::ExportDoc>),
    /// `geodesic export needs --json`.
    Needs(geodesic_exchange::needs::Summary),
}

/// Every command that has a `--json` document, with its schema: the framework's, then the
/// registered missions'.
pub fn entries() -> Vec<Entry> {
    let mut v = vec![
        Entry::of::<VerifyDoc>("verify"),
        Entry::of::<geodesic_fit::FitReport>("fit"),
        Entry::of::<geodesic_discover::diagnose::DiagnoseReport>("diagnose"),
        Entry::of::<geodesic_discover::discover::DiscoverDoc>("discover"),
        Entry::of::<SynthJson>("synth"),
        Entry::of::<geodesic_fit::history::HistoryDoc>("history"),
        Entry::of::<geodesic_verify::requirements::RequirementsDoc>("requirements"),
        Entry::of::<geodesic_facility::effects::EffectsDoc>("effects"),
        Entry::of::<geodesic_fit::spectral::AsdDoc>("asd"),
        Entry::of::<geodesic_images::tiptrack::TiptrackDoc>("tiptrack"),
        Entry::of::<geodesic_images::surfaces::SurfacesDoc>("surfaces"),
        Entry::of::<ExportJson>("export"),
        Entry::of::<geodesic_exchange::reqif::ImportDoc>("import"),
        Entry::of::<geodesic_verify::scaffold::NewMissionDoc>("new"),
    ];
    v.extend(geodesic_missions::schemas());
    v
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let entries = entries();
    let names: Vec<String> = entries.iter().map(|e| e.command.to_string()).collect();
    if let Some(c) = &args.command {
        let e = entries.iter().find(|e| e.command == c).ok_or_else(|| {
            CliError::usage(format!(
                "schema {c}: no such command with a --json document (commands: {})",
                names.join(", ")
            ))
        })?;
        print!("{}", e.text());
        return Ok(0);
    }
    let mut written = Vec::new();
    if let (true, Some(dir)) = (args.all, &args.out) {
        written = geodesic_verify::schema::write_all(&entries, dir)
            .map_err(|e| CliError::io(format!("--out: {e}")))?
            .iter()
            .map(|p| p.display().to_string())
            .collect();
    }
    if args.json {
        let doc = ListDoc {
            commands: names,
            written,
        };
        let text = serde_json::to_string(&doc).map_err(CliError::io)?;
        println!("{text}");
    } else if written.is_empty() {
        println!("commands with a --json schema (geodesic schema COMMAND):");
        for n in &names {
            println!("  {n}");
        }
    } else {
        println!(
            "wrote {} schemas into {}",
            written.len(),
            args.out
                .as_ref()
                .map_or(String::new(), |d| d.display().to_string())
        );
    }
    Ok(0)
}
