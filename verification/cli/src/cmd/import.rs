//! `geodesic import reqif FILE`: a ReqIF file (written by geodesic, DOORS, Polarion, ...) into
//! requirement YAML that `geodesic verify --requirements DIR` loads.

use crate::error::{CliError, CmdResult};
use geodesic_core::Requirements;
use geodesic_exchange::reqif::{Field, ImportOptions, import};
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
    Reqif(ReqifArgs),
}

/// Flags of `geodesic import reqif`.
#[derive(clap::Args, Debug)]
pub struct ReqifArgs {
    /// The ReqIF file.
    pub file: PathBuf,
    /// Directory the YAML files are written to (created; must hold no YAML file yet).
    #[arg(long, value_name = "DIR", default_value = "imported-requirements")]
    pub out: PathBuf,
    /// Import only complete quantitative requirements: leave out those with a limit but no
    /// verification method (or one that cannot be read) instead of failing, and the qualitative
    /// ones (no limit; imported by default, method review-of-design unless the file states
    /// one). Each is listed on standard error.
    #[arg(long = "skip-incomplete")]
    pub skip_incomplete: bool,
    /// The attribute (its LONG-NAME) that holds a field, e.g. `limit=Max Value` or
    /// `method=V-Method`; repeatable. Fields: id, title, text, source, quantity, dimension,
    /// limit, probability, method, activity, check, note.
    #[arg(long = "attribute", value_name = "FIELD=NAME")]
    pub attribute: Vec<String>,
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
    let mut opts = ImportOptions {
        skip_incomplete: a.skip_incomplete,
        ..ImportOptions::default()
    };
    for m in &a.attribute {
        let (f, name) = m
            .split_once('=')
            .ok_or_else(|| CliError::bad(format!("--attribute `{m}`: write FIELD=NAME")))?;
        let field = Field::parse(f.trim()).ok_or_else(|| {
            let all: Vec<&str> = Field::ALL.iter().map(|f| f.name()).collect();
            CliError::bad(format!(
                "--attribute `{m}`: unknown field `{f}` (fields: {})",
                all.join(", ")
            ))
        })?;
        opts.attribute.insert(field, name.trim().to_string());
    }
    let text = geodesic_core::fsio::read_text(&a.file, MAX_REQIF_BYTES).map_err(|e| {
        CliError::bad(format!(
            "{}:{}: {}",
            a.file.display(),
            e.line().max(1),
            e.cause()
        ))
    })?;
    let imported = import(&a.file, &text, &opts).map_err(|e| CliError::bad(e.to_string()))?;
    // the check names must be registered ones, as verify requires
    let sources: Vec<(PathBuf, String)> = imported
        .families
        .iter()
        .map(|f| (a.out.join(&f.file_name), f.yaml.clone()))
        .collect();
    let reqs = Requirements::from_sources(&sources).map_err(|e| CliError::bad(e.to_string()))?;
    let names = geodesic_checks::check_names();
    if let Err(e) = reqs.validate_checks(&names) {
        let id = reqs
            .items
            .iter()
            .find(|r| r.check_origin.as_ref() == Some(&e.origin))
            .map(|r| r.id.to_string());
        let line = id
            .as_ref()
            .and_then(|id| {
                imported
                    .families
                    .iter()
                    .flat_map(|f| &f.requirements)
                    .find(|r| &r.id == id)
            })
            .map_or(1, |r| r.line);
        return Err(CliError::bad(format!(
            "{}:{line}: {}",
            a.file.display(),
            e.cause
        )));
    }

    // write whole or not at all: stage in DIR/.staging-PID, then move the files into DIR
    if a.out.is_dir() {
        let existing = std::fs::read_dir(&a.out)
            .map_err(|e| CliError::Io(format!("{}: {e}", a.out.display())))?
            .filter_map(|e| e.ok())
            .any(|e| {
                matches!(
                    e.path().extension().and_then(|x| x.to_str()),
                    Some("yaml" | "yml")
                )
            });
        if existing {
            return Err(CliError::bad(format!(
                "{}: already holds requirement YAML files; import into an empty or new directory",
                a.out.display()
            )));
        }
    }
    let stage = a.out.join(format!(".staging-{}", std::process::id()));
    let io = |e: std::io::Error| CliError::Io(format!("{}: {e}", a.out.display()));
    std::fs::create_dir_all(&stage).map_err(io)?;
    let staged = (|| -> std::io::Result<()> {
        for f in &imported.families {
            std::fs::write(stage.join(&f.file_name), &f.yaml)?;
        }
        for f in &imported.families {
            std::fs::rename(stage.join(&f.file_name), a.out.join(&f.file_name))?;
        }
        Ok(())
    })();
    let _ = std::fs::remove_dir_all(&stage);
    staged.map_err(io)?;

    for s in &imported.skipped {
        eprintln!(
            "geodesic: {}:{}: skipped requirement {}: {}",
            a.file.display(),
            s.line,
            s.id,
            s.missing.join("; ")
        );
    }
    let files: Vec<String> = imported
        .families
        .iter()
        .map(|f| f.file_name.clone())
        .collect();
    if a.json {
        let v = serde_json::json!({
            "file": a.file.display().to_string(),
            "out": a.out.display().to_string(),
            "source_tool": imported.source_tool,
            "requirements": imported.count(),
            "families": imported.families.iter().map(|f| serde_json::json!({
                "family": f.family, "file": f.file_name, "requirements": f.requirements.len()
            })).collect::<Vec<_>>(),
            "skipped": imported.skipped.iter().map(|s| serde_json::json!({
                "id": s.id, "line": s.line, "missing": s.missing
            })).collect::<Vec<_>>(),
            "headings": imported.headings,
            "other_objects": imported.other_objects,
            "relations": imported.relations,
            "qualitative": imported.qualitative,
        });
        println!("{v}");
    } else {
        println!(
            "imported {} requirements ({} qualitative, {} headings, {} relations{}) into {}/{{{}}}",
            imported.count(),
            imported.qualitative,
            imported.headings,
            imported.relations,
            if imported.skipped.is_empty() {
                String::new()
            } else {
                format!(", {} skipped", imported.skipped.len())
            },
            a.out.display(),
            files.join(",")
        );
    }
    Ok(0)
}
