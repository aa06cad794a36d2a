//! `geodesic surfaces BEFORE.yaml AFTER.yaml`: registration of two surface height maps of the
//! same spot before and after contact, the difference map and a two-sample Kolmogorov-Smirnov
//! test of the heights (interface.md). Thin: the
//! analysis is in `geodesic-images`.

use crate::error::{CliError, CmdResult, InputKind};
use geodesic_images::surfaces::{HeightMap, SurfacesDoc, register};
use geodesic_util::output::write_atomic;
use std::path::PathBuf;

/// Flags of `geodesic surfaces`.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Examples:\n  geodesic surfaces before.yaml after.yaml\n  geodesic surfaces before.yaml after.yaml --json\n\
Each YAML: `map:` a CSV grid of heights in m (empty cell or NaN = missing), `pixel_m`,\n\
`points: [[row, col], [row, col]]` (two matching features picked on that map), optional\n\
`valley_below_m` (default: BEFORE's 30th percentile of heights)."
)]
pub struct Args {
    /// The map before contact.
    #[arg(value_name = "BEFORE.yaml")]
    pub before: PathBuf,
    /// The map after contact.
    #[arg(value_name = "AFTER.yaml")]
    pub after: PathBuf,
    /// Folder of the difference-map plot and the JSON result (written to DIR/images/).
    #[arg(long, value_name = "DIR", default_value = "reports")]
    pub reports: PathBuf,
    /// Print exactly one JSON document on standard output.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> CmdResult {
    let dir = crate::preflight::images_dir(&args.reports)?;
    let b =
        HeightMap::load(&args.before).map_err(|e| CliError::input_from(InputKind::Invalid, e))?;
    let a =
        HeightMap::load(&args.after).map_err(|e| CliError::input_from(InputKind::Invalid, e))?;
    let r = register(&b, &a).map_err(|e| CliError::model(Some("surfaces"), e.to_string()))?;
    let doc = SurfacesDoc::new(&args.before, &args.after, b.pixel_m, &r);
    let text = serde_json::to_string_pretty(&doc).map_err(CliError::io)?;
    let stem = args
        .after
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "after".into());
    std::fs::create_dir_all(&dir).map_err(|e| CliError::io_at(&dir, e))?;
    let svg = geodesic_images::plot::difference_svg(
        &r,
        &format!(
            "AFTER - BEFORE, registered ({stem}); red above, blue below, 3 x the change threshold at full colour"
        ),
    );
    write_atomic(&dir.join(format!("{stem}.surfaces.svg")), svg.as_bytes())?;
    write_atomic(&dir.join(format!("{stem}.surfaces.json")), text.as_bytes())?;
    if args.json {
        println!("{text}");
    } else {
        let px = b.pixel_m;
        println!(
            "shift {:.3} x {:.3} pixels ({:.4e} m, {:.4e} m), rotation {:.3e} rad (start {:.3} x {:.3} pixels, {:.3e} rad)",
            r.shift_m[0] / px,
            r.shift_m[1] / px,
            r.shift_m[0],
            r.shift_m[1],
            r.rotation_rad,
            r.start_shift_m[0] / px,
            r.start_shift_m[1] / px,
            r.start_rotation_rad
        );
        println!(
            "valley RMS {:.3e} m over {} points below {:.3e} m; height offset {:.3e} m",
            r.rms_m, r.valley_points, r.valley_below_m, r.offset_m
        );
        println!(
            "changed area {:.3e} m^2 ({} of {} points beyond {:.3e} m = 5 x noise {:.3e} m)",
            r.changed_area_m2,
            (r.changed_area_m2 / (px * px)).round(),
            r.compared_points,
            r.change_threshold_m,
            r.noise_m
        );
        println!(
            "Kolmogorov-Smirnov: D = {:.4}, p = {:.3e}",
            r.ks_statistic, r.ks_p
        );
        println!("plot and JSON in {}", dir.display());
    }
    Ok(0)
}
