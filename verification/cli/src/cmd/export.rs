//! `geodesic export reqif`: the requirement set (and, given a compliance matrix, the VCD status
//! of each requirement) as a ReqIF 1.2 file for DOORS, Polarion, Jama, Capella and other tools;
//! `geodesic export needs`: the same as a sphinx-needs `needs.json`.

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
  geodesic export reqif --requirements missions/NAME/requirements --out NAME.reqif
  geodesic verify && geodesic export reqif --matrix reports/compliance.json --out status.reqif
  geodesic export reqif --json | jq .sha256
Deterministic: the same requirements give the same file apart from CREATION-TIME
(SOURCE_DATE_EPOCH fixes it). Valid against the OMG ReqIF 1.2 schema; see docs/exchange.md.")]
    Reqif(ReqifArgs),
    /// Write the requirement set as a sphinx-needs needs.json, with the VCD status when
    /// --matrix is given.
    #[command(after_help = "Examples:
  geodesic export needs --out needs.json
  geodesic verify && geodesic export needs --matrix reports/compliance.json --out docs/needs.json
One need per requirement (type req): status, verdict, links to its parent, limit, value,
margin; in Sphinx: needs_import with needs_extra_options (docs/exchange.md).")]
    Needs(NeedsArgs),
}

/// Flags of `geodesic export needs`.
#[derive(clap::Args, Debug)]
pub struct NeedsArgs {
    /// Directory of requirement YAML files [default: ./requirements if present, else the
    /// built-in set].
    #[arg(long, value_name = "DIR")]
    pub requirements: Option<PathBuf>,
    /// Compliance matrix written by `geodesic verify` (reports/compliance.json): the status,
    /// verdict, basis, value and margin of each requirement.
    #[arg(long, value_name = "compliance.json")]
    pub matrix: Option<PathBuf>,
    /// Output file.
    #[arg(long, value_name = "FILE.json", default_value = "reports/needs.json")]
    pub out: PathBuf,
    /// Print a JSON summary on standard output.
    #[arg(long)]
    pub json: bool,
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
        Format::Needs(a) => needs(a),
    }
}

/// The status of a compliance matrix `m`, checked against `reqs` (exit 2 when it was computed
/// for another requirement set).
fn matrix_status(
    m: Option<&PathBuf>,
    reqs: &geodesic_core::Requirements,
) -> Result<Option<StatusSet>, CliError> {
    let Some(m) = m else {
        return Ok(None);
    };
    let text = geodesic_util::fsio::read_text(m, geodesic_util::fsio::MAX_YAML_BYTES)
        .map_err(|e| CliError::unreadable(format!("{}: {e}", m.display())).in_file(m, e.line()))?;
    let s =
        StatusSet::parse(m, &text).map_err(|e| CliError::malformed(e.to_string()).in_file(m, 0))?;
    s.check_against(m, reqs)
        .map_err(|e| CliError::unknown_id(e.to_string()).in_file(m, 0))?;
    Ok(Some(s))
}

fn needs(a: NeedsArgs) -> CmdResult {
    crate::preflight::out_file_in_new_dir("--out", &a.out)?;
    let (reqs, source, _hash) = load_requirements(a.requirements.as_ref())?;
    let status = matrix_status(a.matrix.as_ref(), &reqs)?;
    let time = geodesic_verify::harness::creation_time()?;
    let version = env!("CARGO_PKG_VERSION");
    let doc = geodesic_exchange::needs::export(&reqs, status.as_ref(), &time, version);
    let mut text = serde_json::to_string_pretty(&doc).map_err(CliError::io)?;
    text.push('\n');
    geodesic_util::output::write_whole(&a.out, text.as_bytes())?;
    if a.json {
        let summary = geodesic_exchange::needs::Summary {
            out: a.out.display().to_string(),
            requirements: reqs.items.len(),
            source: source.to_string(),
            with_status: status.is_some(),
            version: version.to_string(),
        };
        println!("{}", serde_json::to_string(&summary).map_err(CliError::io)?);
    } else {
        println!(
            "wrote {} ({} needs from {source}{})",
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

fn reqif(a: ReqifArgs) -> CmdResult {
    crate::preflight::out_file_in_new_dir("--out", &a.out)?;
    let (reqs, source, _hash) = load_requirements(a.requirements.as_ref())?;
    let status = matrix_status(a.matrix.as_ref(), &reqs)?;
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
                .map_err(CliError::io)?
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
