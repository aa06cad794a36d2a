//! `geodesic history DATASET`: RMS and reduced chi-square per model version of a dataset, as a
//! table and an SVG (`<stem>.history.svg` under `--out`).

use std::path::PathBuf;

use geodesic_fit::{history, plot};

use crate::error::{CliError, CmdResult};

/// Flags of `geodesic history`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset YAML path or stem (`run-017.yaml` or `run-017`).
    pub dataset: PathBuf,
    /// Directory holding the fit outputs.
    #[arg(long, default_value = "reports/fits")]
    pub out: PathBuf,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let stem = args
        .dataset
        .file_stem()
        .map_or("dataset".into(), |s| s.to_string_lossy().to_string());
    let path = history::path_for(&args.out, &stem);
    let entries = history::read(&path).map_err(|e| CliError::bad(e.to_string()))?;
    if entries.is_empty() {
        return Err(CliError::bad(format!(
            "{}: no fit history for `{stem}` (run `geodesic fit` first)",
            path.display()
        )));
    }
    let svg_path = args.out.join(format!("{stem}.history.svg"));
    let svg = plot::history_svg(&entries).map_err(|e| CliError::Io(e.to_string()))?;
    plot::write_svg(&svg_path, &svg).map_err(|e| CliError::Io(e.to_string()))?;
    if args.json {
        let doc = serde_json::json!({
            "dataset": stem,
            "history": path.display().to_string(),
            "entries": entries,
            "svg": svg_path.display().to_string(),
        });
        println!("{doc}");
    } else {
        print!("{}", history::table(&entries));
        println!("plot: {}", svg_path.display());
    }
    Ok(0)
}
