//! `geodesic export reqif`: the requirement set (and, given a compliance matrix, the VCD status
//! of each requirement) as a ReqIF 1.2 file for DOORS, Polarion, Jama, Capella and other tools.

use crate::error::{CliError, CmdResult};
use crate::missions::load_requirements;
use geodesic_exchange::reqif::{ExportDoc, ExportOptions, export};
use geodesic_exchange::status::StatusSet;
use std::path::PathBuf;

/// Flags of `geodesic export`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    format: Format,
}

#[derive(clap::Subcommand, Debug)]
enum Format {
    /// Write the requirement set as ReqIF 1.2 (OMG), with the VCD status when --matrix is given.
    #[command(after_help = "Examples:
  geodesic export reqif                                  # ./requirements (or the built-in set) -> reports/requirements.reqif
  geodesic export reqif --requirements missions/drag-free-cubesat/requirements --out cubesat.reqif
  geodesic verify && geodesic export reqif --matrix reports/compliance.json --out status.reqif
  geodesic export reqif --json | jq .sha256
Deterministic: the same requirements give the same file apart from CREATION-TIME
(SOURCE_DATE_EPOCH fixes it). Valid against the OMG ReqIF 1.2 schema; see docs/exchange.md.")]
    Reqif(ReqifArgs),
}

/// Flags of `geodesic export reqif`.
#[derive(clap::Args, Debug)]
pub struct ReqifArgs {
    /// Directory of requirement YAML files [default: ./requirements if present, else the
    /// built-in set].
    #[arg(long, value_name = "DIR")]
    pub requirements: Option<PathBuf>,
    /// Compliance matrix written by `geodesic verify` (reports/compliance.json): adds status,
    /// basis, value, margin, close-out, disposition and remarks to each requirement.
    #[arg(long, value_name = "compliance.json")]
    pub matrix: Option<PathBuf>,
    /// Output file.
    #[arg(
        long,
        value_name = "FILE.reqif",
        default_value = "reports/requirements.reqif"
    )]
    pub out: PathBuf,
    /// Print a JSON summary on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    match args.format {
        Format::Reqif(a) => reqif(a),
    }
}

fn reqif(a: ReqifArgs) -> CmdResult {
    crate::preflight::out_file_in_new_dir("--out", &a.out)?;
    let (reqs, source, _hash) = load_requirements(a.requirements.as_ref())?;
    let status = match &a.matrix {
        Some(m) => {
            let text = geodesic_core::fsio::read_text(m, geodesic_core::fsio::MAX_YAML_BYTES)
                .map_err(|e| CliError::bad(format!("{}: {e}", m.display())))?;
            let s = StatusSet::parse(m, &text).map_err(|e| CliError::bad(e.to_string()))?;
            s.check_against(m, &reqs)
                .map_err(|e| CliError::bad(e.to_string()))?;
            Some(s)
        }
        None => None,
    };
    let time = geodesic_verify::harness::creation_time()?;
    let tool = format!("geodesic {}", env!("CARGO_PKG_VERSION"));
    let opts = ExportOptions {
        creation_time: &time,
        tool_version: &tool,
        status: status.as_ref(),
    };
    let doc = export(&reqs, &opts);
    geodesic_util::output::write_whole(&a.out, doc.as_bytes())?;
    let relations = reqs.items.iter().filter(|r| r.parent.is_some()).count();
    if a.json {
        println!(
            "{}",
            serde_json::to_string(&ExportDoc::new(&reqs, &doc, &a.out, &source, &opts))
                .map_err(|e| CliError::Io(e.to_string()))?
        );
    } else {
        println!(
            "wrote {} ({} requirements from {source}, {relations} derivations{})",
            a.out.display(),
            reqs.items.len(),
            if status.is_some() {
                ", with the verification status"
            } else {
                ""
            }
        );
    }
    Ok(0)
}
