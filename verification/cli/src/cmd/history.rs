//! `geodesic history DATASET`: RMS and reduced chi-square per model version of a dataset, as a
//! table and an SVG (`<stem>.history.svg` in `DIR/fits/`, `--reports DIR`).

use std::path::PathBuf;

use geodesic_fit::{history, plot};

use crate::error::{CliError, CmdResult};

/// Flags of `geodesic history`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Dataset YAML path or stem (`run-017.yaml` or `run-017`).
    pub dataset: PathBuf,
    /// Reports folder, as for `verify` and `fit`: the history is read from DIR/fits/ and its
    /// SVG written there.
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Not a flag of this command (`--out` names one output file everywhere in geodesic).
    #[arg(long, hide = true)]
    pub out: Option<PathBuf>,
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
    let fits = crate::fitting::fits_under(&args.reports, args.out.as_ref())?;
    let path = history::path_for(&fits, &stem);
    let entries =
        history::read(&path).map_err(|e| CliError::malformed(e.to_string()).in_file(&path, 0))?;
    if entries.is_empty() {
        return Err(CliError::evidence(format!(
            "{}: no fit history for `{stem}` (run `geodesic fit` first)",
            path.display()
        )));
    }
    let svg_path = fits.join(format!("{stem}.history.svg"));
    let svg = plot::history_svg(&entries).map_err(CliError::io)?;
    plot::write_svg(&svg_path, &svg).map_err(CliError::io)?;
    if args.json {
        let doc = history::HistoryDoc {
            dataset: stem,
            history: path.display().to_string(),
            entries: entries.into_iter().map(history::EntryDoc::from).collect(),
            svg: svg_path.display().to_string(),
        };
        let doc = serde_json::to_string(&doc).map_err(CliError::io)?;
        println!("{doc}");
    } else {
        print!("{}", history::table(&entries));
        println!("plot: {}", svg_path.display());
    }
    Ok(0)
}
