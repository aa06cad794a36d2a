//! The release tip's trajectory from high-speed camera frames (thesis appendix "Mitigation of
//! Non Linear Motion of the Ground Release Tip" and its MATLAB script).
//!
//! The camera sees the tip's shadow (dark) against a strong constant light (bright), the tip
//! entering the frame from the right. Per frame and per gray level `L`:
//!
//! 1. along the bottom row, scanning from the left, the first pixel darker than `L`; the
//!    crossing is interpolated linearly between its centre and the previous pixel's: `x`;
//! 2. along the column at `x + offset_px` (the thesis's `Delta`, where the tip's boundary is
//!    horizontal; gray levels interpolated linearly between the two neighbouring columns),
//!    scanning from the top, the first pixel darker than `L`, interpolated the same way: the
//!    tip's upper boundary, reported as its height `z` above the bottom edge of the frame.
//!
//! Conventions (interface.md): column `i` spans `[i, i+1)` pixels from the left edge, its centre
//! at `i + 1/2`; row `r` counted from the bottom spans `[r, r+1)` pixels up from the bottom
//! edge. Both coordinates in m (`pixel_m` per pixel); `t = k / fps` for frame `k`.
//!
//! Over the thresholds, `x` and `z` are the means of the crossings found and `sigma_x`,
//! `sigma_z` their sample standard deviations (n - 1; 0 with one threshold): the spread across
//! gray levels is the uncertainty the thesis takes (it reflects the edge's blur and the noise).
//! A frame where no threshold gives a crossing has `null` coordinates and is named in the
//! warnings.

use crate::frames::{Frame, Sequence, load_sequence};
use crate::{ImageError, positive, yaml_error};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The YAML of a frame sequence (interface.md, `geodesic tiptrack FRAMES.yaml`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConfig {
    frames: String,
    fps: f64,
    pixel_m: f64,
    thresholds: Vec<f64>,
    offset_px: f64,
    #[serde(default)]
    validity: Option<RawValidity>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawValidity {
    window_s: f64,
    max_shear_m: f64,
}

/// A test-validity criterion on the tip's shear motion: `|z(t) - z(0)|` must stay below
/// `max_shear_m` for `t <= window_s` (the thesis's tests were invalid when the tip moved
/// vertically in the first instants of the retraction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Validity {
    /// Window from the first frame [s].
    pub window_s: f64,
    /// Largest accepted shear (z) excursion [m].
    pub max_shear_m: f64,
}

/// A checked frame-sequence configuration.
#[derive(Debug, Clone)]
pub struct Config {
    /// The YAML file.
    pub file: PathBuf,
    /// The frames (folder or multi-frame file), resolved from the YAML's folder.
    pub frames: PathBuf,
    /// Frame rate [Hz].
    pub fps: f64,
    /// Pixel size [m].
    pub pixel_m: f64,
    /// Gray levels of the threshold crossings.
    pub thresholds: Vec<f64>,
    /// Offset of the vertical line from `x` [pixels] (the thesis's Delta).
    pub offset_px: f64,
    /// The optional validity criterion.
    pub validity: Option<Validity>,
}

impl Config {
    /// Reads and checks `FRAMES.yaml`.
    pub fn load(file: &Path) -> Result<Config, ImageError> {
        let text = std::fs::read_to_string(file)
            .map_err(|e| ImageError::new(file, 0, format!("cannot read: {e}")))?;
        let raw: RawConfig = serde_saphyr::from_str(&text).map_err(|e| yaml_error(file, &e))?;
        let fps = positive(file, "fps", raw.fps)?;
        let pixel_m = positive(file, "pixel_m", raw.pixel_m)?;
        if !raw.offset_px.is_finite() {
            return Err(ImageError::new(
                file,
                0,
                "`offset_px` must be a finite number of pixels",
            ));
        }
        if raw.thresholds.is_empty() {
            return Err(ImageError::new(
                file,
                0,
                "`thresholds` is empty: give at least one gray level",
            ));
        }
        if let Some(t) = raw.thresholds.iter().find(|t| !t.is_finite()) {
            return Err(ImageError::new(
                file,
                0,
                format!("threshold {t} is not a finite gray level"),
            ));
        }
        let validity = match raw.validity {
            Some(v) => Some(Validity {
                window_s: positive(file, "validity.window_s", v.window_s)?,
                max_shear_m: positive(file, "validity.max_shear_m", v.max_shear_m)?,
            }),
            None => None,
        };
        let base = file.parent().unwrap_or(Path::new("."));
        Ok(Config {
            file: file.to_path_buf(),
            frames: base.join(&raw.frames),
            fps,
            pixel_m,
            thresholds: raw.thresholds,
            offset_px: raw.offset_px,
            validity,
        })
    }
}

/// The trajectory: one entry per frame (`None` where no threshold gave a crossing).
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Time of each frame [s].
    pub t_s: Vec<f64>,
    /// Tip x from the left edge [m].
    pub x_m: Vec<Option<f64>>,
    /// Tip z (upper boundary) above the bottom edge [m].
    pub z_m: Vec<Option<f64>>,
    /// Spread of x across thresholds [m].
    pub sigma_x_m: Vec<Option<f64>>,
    /// Spread of z across thresholds [m].
    pub sigma_z_m: Vec<Option<f64>>,
    /// Frames (index) without any crossing, and why.
    pub warnings: Vec<String>,
}

/// The verdict of a [`Validity`] criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidityResult {
    /// The criterion.
    pub criterion: Validity,
    /// Largest `|z(t) - z(0)|` within the window [m].
    pub shear_m: f64,
    /// Where it occurs [s].
    pub at_s: f64,
    /// Frames with a z inside the window.
    pub frames: usize,
    /// Whether the test is valid (`shear_m <= max_shear_m`).
    pub valid: bool,
}

/// Crossing of `level` along `g` (values at pixel centres `i + 1/2`), scanning from index 0:
/// the first sample below `level` after a sample at or above it, interpolated linearly.
fn crossing(g: impl Iterator<Item = f64>, level: f64) -> Option<f64> {
    let mut prev: Option<f64> = None;
    for (i, v) in g.enumerate() {
        if v < level {
            let p = prev?;
            // p >= level > v
            return Some(i as f64 - 0.5 + (p - level) / (p - v));
        }
        prev = Some(v);
    }
    None
}

/// `(x, z)` in pixels of one frame at one gray level (see the module's conventions).
pub fn crossing_px(f: &Frame, level: f64, offset_px: f64) -> (Option<f64>, Option<f64>) {
    let bottom = f.height - 1;
    let Some(x) = crossing((0..f.width).map(|c| f.at(c, bottom)), level) else {
        return (None, None);
    };
    // the column at x + offset: between the centres of columns j0 and j0 + 1
    let xc = x + offset_px - 0.5;
    let j0 = xc.floor();
    if !(j0 >= 0.0 && j0 <= (f.width - 1) as f64) {
        return (Some(x), None);
    }
    let j0 = j0 as usize;
    let a = xc - j0 as f64;
    let j1 = (j0 + 1).min(f.width - 1);
    let col = (0..f.height).map(|r| (1.0 - a) * f.at(j0, r) + a * f.at(j1, r));
    let z = crossing(col, level).map(|y_top| f.height as f64 - y_top);
    (Some(x), z)
}

fn mean_sd(v: &[f64]) -> Option<(f64, f64)> {
    if v.is_empty() {
        return None;
    }
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let sd = if v.len() > 1 {
        (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    Some((m, sd))
}

/// The trajectory of a frame sequence.
pub fn track(seq: &Sequence, cfg: &Config) -> Result<Trajectory, ImageError> {
    let maxval = f64::from(seq.frames[0].maxval);
    if let Some(t) = cfg.thresholds.iter().find(|&&t| !(t > 0.0 && t <= maxval)) {
        return Err(ImageError::new(
            &cfg.file,
            0,
            format!("threshold {t} is outside the frames' gray range (0, {maxval}]"),
        ));
    }
    let mut out = Trajectory {
        t_s: Vec::new(),
        x_m: Vec::new(),
        z_m: Vec::new(),
        sigma_x_m: Vec::new(),
        sigma_z_m: Vec::new(),
        warnings: Vec::new(),
    };
    let p = cfg.pixel_m;
    for (k, f) in seq.frames.iter().enumerate() {
        let mut xs = Vec::new();
        let mut zs = Vec::new();
        for &l in &cfg.thresholds {
            let (x, z) = crossing_px(f, l, cfg.offset_px);
            xs.extend(x);
            zs.extend(z);
        }
        let x = mean_sd(&xs);
        let z = mean_sd(&zs);
        if x.is_none() {
            out.warnings.push(format!(
                "frame {k} ({}): no dark-after-bright crossing along the bottom row at any threshold",
                seq.sources[k].display()
            ));
        } else if z.is_none() {
            out.warnings.push(format!(
                "frame {k} ({}): no crossing along the column at x + {} px (outside the frame or no tip edge)",
                seq.sources[k].display(),
                cfg.offset_px
            ));
        }
        out.t_s.push(k as f64 / cfg.fps);
        out.x_m.push(x.map(|(m, _)| m * p));
        out.sigma_x_m.push(x.map(|(_, s)| s * p));
        out.z_m.push(z.map(|(m, _)| m * p));
        out.sigma_z_m.push(z.map(|(_, s)| s * p));
    }
    if out.x_m.iter().all(|x| x.is_none()) {
        return Err(ImageError::new(
            &cfg.frames,
            0,
            "no frame shows a dark tip after bright background along the bottom row at the thresholds given",
        ));
    }
    Ok(out)
}

/// Judges `v` on a trajectory: the largest `|z(t) - z(first)|` for `t <= window_s`.
pub fn judge(tr: &Trajectory, v: Validity) -> Option<ValidityResult> {
    let mut z0 = None;
    let mut worst = (0.0f64, 0.0f64);
    let mut frames = 0;
    for (t, z) in tr.t_s.iter().zip(&tr.z_m) {
        if *t > v.window_s * (1.0 + 1e-12) {
            break;
        }
        let Some(z) = z else { continue };
        frames += 1;
        let z0 = *z0.get_or_insert(*z);
        let d = (z - z0).abs();
        if d > worst.0 {
            worst = (d, *t);
        }
    }
    (frames > 0).then_some(ValidityResult {
        criterion: v,
        shear_m: worst.0,
        at_s: worst.1,
        frames,
        valid: worst.0 <= v.max_shear_m,
    })
}

/// Loads the configuration and its frames and tracks the tip.
pub fn run(file: &Path) -> Result<(Config, Trajectory), ImageError> {
    let cfg = Config::load(file)?;
    let seq = load_sequence(&cfg.frames)?;
    let tr = track(&seq, &cfg)?;
    Ok((cfg, tr))
}

/// The JSON document of `geodesic tiptrack --json`, also written to
/// `DIR/images/STEM.tiptrack.json` (docs/spec/interface.md). Fields are declared in byte order
/// of their keys, the order the document has always printed; a frame where a coordinate was
/// not found has `null` there.
#[derive(Debug, Clone, PartialEq, serde::Serialize, Deserialize, schemars::JsonSchema)]
pub struct TiptrackDoc {
    /// Frame rate [Hz].
    pub fps: f64,
    /// The frame sequence's YAML, as given on the command line.
    pub frames_yaml: String,
    /// Offset of the vertical line from `x` [pixels] (the thesis's Delta).
    pub offset_px: f64,
    /// Pixel size [m].
    pub pixel_m: f64,
    /// Spread of x across thresholds, per frame [m].
    pub sigma_x_m: Vec<Option<f64>>,
    /// Spread of z across thresholds, per frame [m].
    pub sigma_z_m: Vec<Option<f64>>,
    /// Time of each frame [s].
    pub t_s: Vec<f64>,
    /// Gray levels of the threshold crossings.
    pub thresholds: Vec<f64>,
    /// The validity criterion's verdict; `null` when the YAML states no criterion.
    pub validity: Option<ValidityDoc>,
    /// Frames (index) without any crossing, and why.
    pub warnings: Vec<String>,
    /// Tip x from the left edge, per frame [m].
    pub x_m: Vec<Option<f64>>,
    /// Tip z (upper boundary) above the bottom edge, per frame [m].
    pub z_m: Vec<Option<f64>>,
}

/// The verdict of [`TiptrackDoc::validity`], in byte order of its keys.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, Deserialize, schemars::JsonSchema)]
pub struct ValidityDoc {
    /// Where the largest shear occurs [s].
    pub at_s: f64,
    /// Frames with a z inside the window.
    pub frames: usize,
    /// Largest accepted shear (z) excursion [m].
    pub max_shear_m: f64,
    /// Largest `|z(t) - z(0)|` within the window [m].
    pub shear_m: f64,
    /// Whether the test is valid (`shear_m <= max_shear_m`).
    pub valid: bool,
    /// Window from the first frame [s].
    pub window_s: f64,
}

impl From<ValidityResult> for ValidityDoc {
    fn from(r: ValidityResult) -> ValidityDoc {
        ValidityDoc {
            at_s: r.at_s,
            frames: r.frames,
            max_shear_m: r.criterion.max_shear_m,
            shear_m: r.shear_m,
            valid: r.valid,
            window_s: r.criterion.window_s,
        }
    }
}

impl TiptrackDoc {
    /// The document of trajectory `tr` tracked from `frames_yaml` with `cfg`, and the
    /// validity `verdict` ([`judge`]) when the YAML states a criterion.
    pub fn new(
        frames_yaml: &Path,
        cfg: &Config,
        tr: &Trajectory,
        verdict: Option<ValidityResult>,
    ) -> TiptrackDoc {
        TiptrackDoc {
            fps: cfg.fps,
            frames_yaml: frames_yaml.display().to_string(),
            offset_px: cfg.offset_px,
            pixel_m: cfg.pixel_m,
            sigma_x_m: tr.sigma_x_m.clone(),
            sigma_z_m: tr.sigma_z_m.clone(),
            t_s: tr.t_s.clone(),
            thresholds: cfg.thresholds.clone(),
            validity: verdict.map(ValidityDoc::from),
            warnings: tr.warnings.clone(),
            x_m: tr.x_m.clone(),
            z_m: tr.z_m.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_interpolates_between_centres() {
        // bright 200 up to pixel 2, dark 0 from pixel 3: level 100 crosses half-way between
        // the centres 2.5 and 3.5
        let g = [200.0, 200.0, 200.0, 0.0, 0.0];
        assert_eq!(crossing(g.into_iter(), 100.0), Some(3.0));
        assert_eq!(crossing(g.into_iter(), 150.0), Some(2.75));
        assert_eq!(crossing([0.0, 200.0].into_iter(), 100.0), None);
        assert_eq!(crossing([200.0, 200.0].into_iter(), 100.0), None);
    }
}
