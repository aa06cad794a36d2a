//! `geodesic import reqif FILE`: a ReqIF file (written by geodesic, DOORS, Polarion, ...) into
//! requirement YAML that `geodesic verify --requirements DIR` loads.

use crate::error::{CliError, CmdResult};
use geodesic_core::Requirements;
use geodesic_exchange::reqif::{Field, ImportDoc, ImportOptions, import_file};
use std::path::PathBuf;

/// Largest ReqIF file read [bytes] (256 MiB).
const MAX_REQIF_BYTES: u64 = 256 << 20;

/// Flags of `geodesic import`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    format: Format,
}

#[derive(clap::Subcommand, Debug)]
enum Format {
    /// Read a ReqIF file into requirement YAML (one file per family).
    #[command(after_help = "Examples:
  geodesic import reqif from-doors.reqif --out imported/            # then: geodesic verify --requirements imported/
  geodesic import reqif from-doors.reqif --out imported/ --report   # which attribute went to which field
  geodesic import reqif polarion.reqifz --out imported/ --attribute limit=\"Max Value\" --attribute method=\"V&V Method\"
  geodesic import reqif supplier.reqif --out imported/ --strict     # refuse at the first problem (exit 2)
  geodesic import reqif supplier.reqif --out imported/ --json | jq '.warnings | length'
What other tools get wrong (dangling references, duplicated IDs, missing types) is imported with a
warning per problem (file:line) on standard error; see docs/exchange.md.")]
    Reqif(ReqifArgs),
}

/// Flags of `geodesic import reqif`.
#[derive(clap::Args, Debug)]
pub struct ReqifArgs {
    /// The ReqIF file (.reqif, or a .reqifz archive of one).
    pub file: PathBuf,
    /// Directory the YAML files are written to (created; must hold no YAML file yet).
    #[arg(long, value_name = "DIR", default_value = "imported-requirements")]
    pub out: PathBuf,
    /// Import only complete quantitative requirements: leave out the qualitative ones too (no
    /// limit; imported by default, method review-of-design unless the file states one). Each
    /// is listed on standard error.
    #[arg(long = "skip-incomplete")]
    pub skip_incomplete: bool,
    /// Refuse the file at its first problem (a dangling reference, a duplicated ID, a value
    /// that cannot be read, ...), exit 2, instead of importing what is meaningful with a
    /// warning per problem.
    #[arg(long)]
    pub strict: bool,
    /// Print which ReqIF attribute was taken for each field (and the attributes no field
    /// took), to correct with --attribute.
    #[arg(long)]
    pub report: bool,
    /// The attribute (its LONG-NAME) that holds a field, e.g. `limit=Max Value` or
    /// `method=V-Method`; repeatable. Fields: id, title, text, source, quantity, dimension,
    /// limit, probability, spectrum-band, spectrum-shape, level, stage, method, activity,
    /// check, note.
    #[arg(long = "attribute", value_name = "FIELD=NAME")]
    pub attribute: Vec<String>,
    /// Print a JSON summary on standard output (with the warnings and the mapping).
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    match args.format {
        Format::Reqif(a) => reqif(a),
    }
}

/// Warnings printed on standard error before the rest are only counted (all are in `--json`).
const MAX_PRINTED_WARNINGS: usize = 100;

fn reqif(a: ReqifArgs) -> CmdResult {
    crate::preflight::out_dir("--out", &a.out)?;
    let opts = options(&a)?;
    let bytes = geodesic_util::fsio::read_bytes(&a.file, MAX_REQIF_BYTES).map_err(|e| {
        CliError::unreadable(format!(
            "{}:{}: {}",
            a.file.display(),
            e.line().max(1),
            e.cause()
        ))
        .in_file(&a.file, e.line().max(1))
    })?;
    // a .reqif file, or a .reqifz archive of one
    let imported = import_file(&a.file, &bytes, &opts)
        .map_err(|e| CliError::malformed(e.to_string()).in_file(&a.file, 0))?;
    // what is written loads, with registered checks only (the import left the others out)
    let sources: Vec<(PathBuf, String)> = imported
        .families
        .iter()
        .map(|f| (a.out.join(&f.file_name), f.yaml.clone()))
        .collect();
    let reqs = Requirements::from_sources(&sources)?;
    let names = crate::missions::check_names();
    reqs.validate_checks(&names).map_err(|e| {
        CliError::unknown_name(format!("{}: {}", a.file.display(), e.cause)).in_file(&a.file, 0)
    })?;

    geodesic_exchange::reqif::write_families(&a.out, &imported.families).map_err(|e| match e {
        geodesic_exchange::reqif::WriteFamilies::Occupied(m) => CliError::usage(m),
        geodesic_exchange::reqif::WriteFamilies::Io(m) => CliError::io(m),
    })?;

    for l in geodesic_exchange::reqif::warning_lines(&imported, MAX_PRINTED_WARNINGS) {
        eprintln!("geodesic: {l}");
    }
    let files: Vec<String> = imported
        .families
        .iter()
        .map(|f| f.file_name.clone())
        .collect();
    if a.json {
        let doc = ImportDoc::new(&imported, &a.file, &a.out);
        let v = serde_json::to_string(&doc).map_err(CliError::io)?;
        println!("{v}");
        return Ok(0);
    }
    if a.report {
        print!("{}", geodesic_exchange::reqif::mapping_text(&imported));
    }
    println!(
        "imported {} requirement{} ({} qualitative) of {} SPEC-OBJECTs ({} headings, {} without text, {} duplicates, {} skipped), {} relations, {} warnings, into {}/{{{}}}",
        imported.count(),
        if imported.count() == 1 { "" } else { "s" },
        imported.qualitative,
        imported.spec_objects,
        imported.headings,
        imported.other_objects,
        imported.duplicates,
        imported.skipped.len(),
        imported.relations,
        imported.warnings.len(),
        a.out.display(),
        files.join(",")
    );
    Ok(0)
}

/// The import options of the flags: skip, strict, the registered checks and `--attribute`s.
fn options(a: &ReqifArgs) -> Result<ImportOptions, CliError> {
    let mut opts = ImportOptions {
        skip_incomplete: a.skip_incomplete,
        strict: a.strict,
        checks: Some(
            crate::missions::check_names()
                .into_iter()
                .map(str::to_string)
                .collect(),
        ),
        ..ImportOptions::default()
    };
    for m in &a.attribute {
        let (f, name) = m
            .split_once('=')
            .ok_or_else(|| CliError::usage(format!("--attribute `{m}`: write FIELD=NAME")))?;
        let field = Field::parse(f.trim()).ok_or_else(|| {
            let all: Vec<&str> = Field::ALL.iter().map(|f| f.name()).collect();
            CliError::usage(format!(
                "--attribute `{m}`: unknown field `{f}` (fields: {})",
                all.join(", ")
            ))
        })?;
        if name.trim().is_empty() {
            return Err(CliError::usage(format!(
                "--attribute `{m}`: the attribute name is empty"
            )));
        }
        opts.attribute.insert(field, name.trim().to_string());
    }
    Ok(opts)
}
