//! `geodesic tiptrack FRAMES.yaml`: the release tip's trajectory from high-speed camera frames
//! (threshold crossings; interface.md).
//! Thin: the analysis is in `geodesic-images`.

use crate::error::{CliError, CmdResult, InputKind};
use geodesic_images::tiptrack;
use geodesic_util::output::write_atomic;
use std::path::PathBuf;

/// Flags of `geodesic tiptrack`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  geodesic tiptrack data/camera/frames.yaml\n  geodesic tiptrack frames.yaml --json > trajectory.json\n\
FRAMES.yaml: `frames:` a folder of PGM/PNG frames (sorted by name) or one multi-frame PGM, `fps`,\n\
`pixel_m`, `thresholds: [gray levels]`, `offset_px`; optional `validity: {window_s, max_shear_m}`\n\
judges the tip's shear (z) motion in the first window_s seconds (exit 1 when it is exceeded)."
)]
pub struct Args {
    /// The frame sequence's YAML.
    #[arg(value_name = "FRAMES.yaml")]
    pub frames: PathBuf,
    /// Folder of the plot and the JSON result (written to DIR/images/).
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let dir = crate::preflight::images_dir(&args.reports)?;
    let (cfg, tr) =
        tiptrack::run(&args.frames).map_err(|e| CliError::input_from(InputKind::Invalid, e))?;
    let verdict = cfg.validity.and_then(|v| tiptrack::judge(&tr, v));
    if cfg.validity.is_some() && verdict.is_none() {
        return Err(CliError::evidence(format!(
            "{}: no frame inside the validity window has a z: the criterion cannot be judged",
            args.frames.display()
        )));
    }
    let doc = tiptrack::TiptrackDoc::new(&args.frames, &cfg, &tr, verdict);
    let text = serde_json::to_string_pretty(&doc).map_err(CliError::io)?;
    let stem = args
        .frames
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frames".into());
    std::fs::create_dir_all(&dir).map_err(|e| CliError::io_at(&dir, e))?;
    let svg =
        geodesic_images::plot::trajectory_svg(&tr, &format!("Release tip trajectory: {stem}"));
    write_atomic(&dir.join(format!("{stem}.tiptrack.svg")), svg.as_bytes())?;
    write_atomic(&dir.join(format!("{stem}.tiptrack.json")), text.as_bytes())?;
    for w in &tr.warnings {
        eprintln!("geodesic: warning: {w}");
    }
    if args.json {
        println!("{text}");
    } else {
        let found = tr.x_m.iter().filter(|x| x.is_some()).count();
        println!(
            "{} frames at {} Hz, {} thresholds: x found in {found}, z in {}",
            tr.t_s.len(),
            cfg.fps,
            cfg.thresholds.len(),
            tr.z_m.iter().filter(|z| z.is_some()).count()
        );
        let span = |v: &[Option<f64>]| {
            let f: Vec<f64> = v.iter().flatten().copied().collect();
            let lo = f.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = f.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (lo * 1e6, hi * 1e6)
        };
        let (xl, xh) = span(&tr.x_m);
        let (zl, zh) = span(&tr.z_m);
        println!("x {xl:.3} .. {xh:.3} um, z {zl:.3} .. {zh:.3} um");
        if let Some(r) = verdict {
            println!(
                "validity: shear {:.3} um at {:.1} us within the first {:.1} us, limit {:.3} um: {}",
                r.shear_m * 1e6,
                r.at_s * 1e6,
                r.criterion.window_s * 1e6,
                r.criterion.max_shear_m * 1e6,
                if r.valid { "valid" } else { "INVALID" }
            );
        }
        println!("plot and JSON in {}", dir.display());
    }
    Ok(if verdict.is_some_and(|r| !r.valid) {
        1
    } else {
        0
    })
}
