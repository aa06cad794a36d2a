//! Registration of two surface height maps of the same spot, before and after contact (thesis
//! ch. 5 "Surface Analysis Before and After the Tests" and appendix "Surfaces matching").
//!
//! The thesis's procedure: keep the valleys (points below a threshold), start from two points
//! the user picked on each map, and minimise the RMS difference between the valleys over the
//! relative translation and rotation, excluding missing points; then compare the height
//! distributions with a two-sample Kolmogorov-Smirnov test.
//!
//! Here, with positions in pixels `(x, y) = (column, row)` and `c` the centre of BEFORE, the
//! content of BEFORE at `p` lies in AFTER at `T(p) = R(theta) (p - c) + c + d`, `d = (dx, dy)`
//! (interface.md: `shift_m` = `d` times the pixel size, dx along columns, dy along rows).
//!
//! * Start: `theta0` from the directions of the two point pairs, `d0` from their midpoints.
//! * Cost of `(d, theta)`: over BEFORE's valley points whose image `T(p)` falls inside AFTER
//!   with its four neighbours present, `e = A(T(p)) - B(p)` with `A` interpolated bilinearly;
//!   the RMS of `e` about its mean (the mean, a height offset between the two measurements, is
//!   free: a profilometer does not keep its height reference between sessions). At least half
//!   of the valley points must overlap.
//! * Search: a grid of rotations over the range picks off by [`PICK_ERROR_PX`] can turn the
//!   pairs' directions (steps of one pixel at the map's edge, at most 24 each way), each with
//!   the whole-pixel translations within 4 pixels of where it maps the picked midpoint, judged
//!   on at most 4 000 valley points; then Nelder-Mead in `(dx, dy, theta L)` (`L`, half the
//!   diagonal, puts rotation in pixels at the map's edge) from the three best.
//! * Difference map: `A(T(p)) - B(p) - offset` over every BEFORE point, `offset` the median
//!   difference; its noise `sigma` is the MAD of the differences times 1.4826 (robust to the
//!   changed patch); a point has changed when
//!   `|difference| > 5 sigma` (at most 3e-7 false detections per point for Gaussian noise);
//!   `changed_area_m2` counts them times the pixel area.
//! * Kolmogorov-Smirnov: BEFORE's heights against AFTER's registered heights (offset removed)
//!   on the same points; the p-value from the asymptotic Kolmogorov distribution with the
//!   effective size `n1 n2 / (n1 + n2)` and Stephens' correction (Numerical Recipes `probks`).
//!   Neighbouring heights of a map are correlated, so the p-value overstates the evidence: it is
//!   reported as the thesis reports it, a statement about the two distributions' difference.

use crate::{ImageError, positive, yaml_error};
use geodesic_util::stats::median;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A height map and its user-picked points.
#[derive(Debug, Clone)]
pub struct HeightMap {
    /// The YAML file.
    pub file: PathBuf,
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Heights [m], row-major; NaN = missing.
    pub h: Vec<f64>,
    /// Pixel size [m].
    pub pixel_m: f64,
    /// Two matching points `[row, col]`.
    pub points: [[f64; 2]; 2],
    /// The valley threshold [m], if given.
    pub valley_below_m: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMap {
    map: String,
    pixel_m: f64,
    points: Vec<Vec<f64>>,
    #[serde(default)]
    valley_below_m: Option<f64>,
}

/// Largest accepted map side [points].
pub const MAX_SIDE: usize = 8192;

/// Largest error [pixel] per coordinate of a picked point that the registration's start
/// search covers (docs/images.md: the stated accuracy holds for picks off by up to this).
pub const PICK_ERROR_PX: f64 = 3.0;

/// Most rotation steps each way of the registration's start grid.
const ROTATION_STEPS: usize = 24;

/// Most valley points the registration's start grid is judged on.
const GRID_POINTS: usize = 4000;

/// Valley points whose difference lies beyond this many robust sigmas (1.4826 x the MAD) of
/// the median are left out of the registration's robust refinement.
pub const TRIM_SIGMAS: f64 = 3.0;

/// Most rounds of the robust refinement.
const TRIM_ROUNDS: usize = 3;

impl HeightMap {
    /// Reads `MAP.yaml` and its CSV grid.
    pub fn load(file: &Path) -> Result<HeightMap, ImageError> {
        let text = std::fs::read_to_string(file)
            .map_err(|e| ImageError::new(file, 0, format!("cannot read: {e}")))?;
        let raw: RawMap = serde_saphyr::from_str(&text).map_err(|e| yaml_error(file, &e))?;
        let pixel_m = positive(file, "pixel_m", raw.pixel_m)?;
        if raw.points.len() != 2 || raw.points.iter().any(|p| p.len() != 2) {
            return Err(ImageError::new(
                file,
                0,
                "`points` must be two [row, col] pairs: [[r1, c1], [r2, c2]]",
            ));
        }
        if let Some(v) = raw.points.iter().flatten().find(|v| !v.is_finite()) {
            return Err(ImageError::new(
                file,
                0,
                format!("point coordinate {v} is not finite"),
            ));
        }
        if let Some(v) = raw.valley_below_m
            && !v.is_finite()
        {
            return Err(ImageError::new(
                file,
                0,
                format!("`valley_below_m` {v} is not finite"),
            ));
        }
        let csv = file.parent().unwrap_or(Path::new(".")).join(&raw.map);
        let (rows, cols, h) = read_grid(&csv)?;
        let points = [
            [raw.points[0][0], raw.points[0][1]],
            [raw.points[1][0], raw.points[1][1]],
        ];
        for p in &points {
            if !(p[0] >= 0.0
                && p[0] <= (rows - 1) as f64
                && p[1] >= 0.0
                && p[1] <= (cols - 1) as f64)
            {
                return Err(ImageError::new(
                    file,
                    0,
                    format!(
                        "point [{}, {}] is outside the {rows} x {cols} map",
                        p[0], p[1]
                    ),
                ));
            }
        }
        if points[0] == points[1] {
            return Err(ImageError::new(
                file,
                0,
                "the two points coincide: pick two distinct features",
            ));
        }
        Ok(HeightMap {
            file: file.to_path_buf(),
            rows,
            cols,
            h,
            pixel_m,
            points,
            valley_below_m: raw.valley_below_m,
        })
    }

    fn at(&self, r: usize, c: usize) -> f64 {
        self.h[r * self.cols + c]
    }

    /// Bilinear interpolation at `(x, y) = (col, row)`; `None` outside or next to a missing point.
    pub fn sample(&self, x: f64, y: f64) -> Option<f64> {
        if !(x >= 0.0 && y >= 0.0 && x <= (self.cols - 1) as f64 && y <= (self.rows - 1) as f64) {
            return None;
        }
        let (c0, r0) = (x.floor() as usize, y.floor() as usize);
        let (c1, r1) = ((c0 + 1).min(self.cols - 1), (r0 + 1).min(self.rows - 1));
        let (a, b) = (x - c0 as f64, y - r0 as f64);
        let v = (1.0 - a) * (1.0 - b) * self.at(r0, c0)
            + a * (1.0 - b) * self.at(r0, c1)
            + (1.0 - a) * b * self.at(r1, c0)
            + a * b * self.at(r1, c1);
        v.is_finite().then_some(v)
    }
}

/// Reads a CSV grid of heights: no header, comma separated, empty cell or NaN = missing.
fn read_grid(csv: &Path) -> Result<(usize, usize, Vec<f64>), ImageError> {
    let text = std::fs::read_to_string(csv)
        .map_err(|e| ImageError::new(csv, 0, format!("map file: cannot read: {e}")))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let mut h = Vec::new();
    let mut cols = 0usize;
    let mut rows = 0usize;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim_end_matches('\r');
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(',').collect();
        if rows == 0 {
            cols = cells.len();
            if cols > MAX_SIDE {
                return Err(ImageError::new(
                    csv,
                    i + 1,
                    format!("{cols} columns, at most {MAX_SIDE}"),
                ));
            }
        } else if cells.len() != cols {
            return Err(ImageError::new(
                csv,
                i + 1,
                format!("{} cells, the first row has {cols}", cells.len()),
            ));
        }
        for (j, cell) in cells.iter().enumerate() {
            let s = cell.trim();
            let v = if s.is_empty() || s.eq_ignore_ascii_case("nan") {
                f64::NAN
            } else {
                let v: f64 = s.parse().map_err(|_| {
                    ImageError::new(
                        csv,
                        i + 1,
                        format!(
                            "column {}: `{}` is not a height in m",
                            j + 1,
                            geodesic_util::text::clip(s, 40)
                        ),
                    )
                })?;
                if !v.is_finite() {
                    return Err(ImageError::new(
                        csv,
                        i + 1,
                        format!(
                            "column {}: `{s}` is not a finite height (write NaN or leave the cell empty for a missing point)",
                            j + 1
                        ),
                    ));
                }
                v
            };
            h.push(v);
        }
        rows += 1;
        if rows > MAX_SIDE {
            return Err(ImageError::new(
                csv,
                i + 1,
                format!("more than {MAX_SIDE} rows"),
            ));
        }
    }
    if rows < 2 || cols < 2 {
        return Err(ImageError::new(
            csv,
            0,
            format!("a {rows} x {cols} grid: at least 2 x 2 heights are needed"),
        ));
    }
    if h.iter().all(|v| v.is_nan()) {
        return Err(ImageError::new(csv, 0, "every height is missing"));
    }
    Ok((rows, cols, h))
}

/// The result of a registration.
#[derive(Debug, Clone)]
pub struct Registration {
    /// Where AFTER's content lies relative to BEFORE [m]: along columns, along rows.
    pub shift_m: [f64; 2],
    /// Rotation of AFTER's content about BEFORE's centre [rad] (counter-clockwise in (col, row)).
    pub rotation_rad: f64,
    /// RMS of the valley differences about their mean at the optimum [m].
    pub rms_m: f64,
    /// Height offset AFTER - BEFORE removed [m] (the median difference).
    pub offset_m: f64,
    /// The valley threshold used [m].
    pub valley_below_m: f64,
    /// Valley points in the cost at the optimum.
    pub valley_points: usize,
    /// Valley points left out of the robust refinement: their difference lay beyond
    /// [`TRIM_SIGMAS`] robust sigmas of the median (a changed patch).
    pub trimmed_points: usize,
    /// Start of the search from the picked points: shift [m], rotation [rad].
    pub start_shift_m: [f64; 2],
    /// Start rotation [rad].
    pub start_rotation_rad: f64,
    /// Robust noise of the difference map [m].
    pub noise_m: f64,
    /// Threshold of a changed point [m] (5 noise).
    pub change_threshold_m: f64,
    /// Changed area [m^2].
    pub changed_area_m2: f64,
    /// Points compared in the difference map.
    pub compared_points: usize,
    /// Two-sample Kolmogorov-Smirnov statistic.
    pub ks_statistic: f64,
    /// Its asymptotic p-value.
    pub ks_p: f64,
    /// The difference map (BEFORE's grid; NaN where not compared) [m].
    pub difference: Vec<f64>,
    /// Rows and columns of the difference map.
    pub shape: [usize; 2],
}

/// The JSON document of `geodesic surfaces` (interface.md): the registration of AFTER on BEFORE.
/// Fields are declared in byte order of their keys, the order the document has always printed.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SurfacesDoc {
    /// The AFTER map's YAML, as given on the command line.
    pub after: String,
    /// The BEFORE map's YAML, as given on the command line.
    pub before: String,
    /// Threshold of a changed point [m] (5 noise).
    pub change_threshold_m: f64,
    /// Changed area [m^2].
    pub changed_area_m2: f64,
    /// Points compared in the difference map.
    pub compared_points: usize,
    /// Asymptotic p-value of the two-sample Kolmogorov-Smirnov test (dimensionless).
    pub ks_p: f64,
    /// Two-sample Kolmogorov-Smirnov statistic (dimensionless).
    pub ks_statistic: f64,
    /// Robust noise of the difference map [m].
    pub noise_m: f64,
    /// Height offset AFTER - BEFORE removed [m].
    pub offset_m: f64,
    /// BEFORE's pixel size [m].
    pub pixel_m: f64,
    /// RMS of the valley differences about their mean at the optimum [m].
    pub rms_m: f64,
    /// Rotation of AFTER's content about BEFORE's centre [rad].
    pub rotation_rad: f64,
    /// Where AFTER's content lies relative to BEFORE [m]: along columns, along rows.
    pub shift_m: [f64; 2],
    /// Start rotation of the search [rad].
    pub start_rotation_rad: f64,
    /// Start shift of the search from the picked points [m]: along columns, along rows.
    pub start_shift_m: [f64; 2],
    /// The valley threshold used [m].
    pub valley_below_m: f64,
    /// Valley points in the cost at the optimum.
    pub valley_points: usize,
}

impl SurfacesDoc {
    /// The document of registration `r` of maps `before` -> `after` (their YAML paths as
    /// given), BEFORE's pixel size `pixel_m` [m].
    pub fn new(before: &Path, after: &Path, pixel_m: f64, r: &Registration) -> SurfacesDoc {
        SurfacesDoc {
            after: after.display().to_string(),
            before: before.display().to_string(),
            change_threshold_m: r.change_threshold_m,
            changed_area_m2: r.changed_area_m2,
            compared_points: r.compared_points,
            ks_p: r.ks_p,
            ks_statistic: r.ks_statistic,
            noise_m: r.noise_m,
            offset_m: r.offset_m,
            pixel_m,
            rms_m: r.rms_m,
            rotation_rad: r.rotation_rad,
            shift_m: r.shift_m,
            start_rotation_rad: r.start_rotation_rad,
            start_shift_m: r.start_shift_m,
            valley_below_m: r.valley_below_m,
            valley_points: r.valley_points,
        }
    }
}

struct Problem<'a> {
    after: &'a HeightMap,
    valley: Vec<(f64, f64, f64)>,
    centre: (f64, f64),
    min_overlap: usize,
}

impl Problem<'_> {
    fn map(&self, x: f64, y: f64, d: (f64, f64), th: f64) -> (f64, f64) {
        let (cx, cy) = self.centre;
        let (s, c) = th.sin_cos();
        let (px, py) = (x - cx, y - cy);
        (c * px - s * py + cx + d.0, s * px + c * py + cy + d.1)
    }

    /// RMS about the mean, the mean and the count.
    fn cost(&self, d: (f64, f64), th: f64) -> (f64, f64, usize) {
        let (mut s, mut s2, mut n) = (0.0, 0.0, 0usize);
        for &(x, y, b) in &self.valley {
            let (u, v) = self.map(x, y, d, th);
            if let Some(a) = self.after.sample(u, v) {
                let e = a - b;
                s += e;
                s2 += e * e;
                n += 1;
            }
        }
        if n < self.min_overlap || n == 0 {
            return (f64::INFINITY, 0.0, n);
        }
        let m = s / n as f64;
        (((s2 / n as f64) - m * m).max(0.0).sqrt(), m, n)
    }

    /// The valley points whose difference at `(d, th)` lies within [`TRIM_SIGMAS`] robust
    /// sigmas of the median difference (points that do not overlap are left out).
    fn inliers(&self, d: (f64, f64), th: f64) -> Vec<(f64, f64, f64)> {
        let e: Vec<(usize, f64)> = self
            .valley
            .iter()
            .enumerate()
            .filter_map(|(i, &(x, y, b))| {
                let (u, v) = self.map(x, y, d, th);
                self.after.sample(u, v).map(|a| (i, a - b))
            })
            .collect();
        let mut vals: Vec<f64> = e.iter().map(|p| p.1).collect();
        let med = median(&mut vals);
        let mut dev: Vec<f64> = e.iter().map(|p| (p.1 - med).abs()).collect();
        let sigma = 1.4826 * median(&mut dev);
        e.iter()
            .filter(|p| (p.1 - med).abs() <= TRIM_SIGMAS * sigma)
            .map(|p| self.valley[p.0])
            .collect()
    }
}

/// Nelder-Mead on `f` from `x0` with initial steps `step`.
#[allow(clippy::needless_range_loop)] // three coordinates indexed together reads best
fn nelder_mead(
    f: &dyn Fn(&[f64; 3]) -> f64,
    x0: [f64; 3],
    step: [f64; 3],
    iters: usize,
) -> ([f64; 3], f64) {
    let mut pts: Vec<([f64; 3], f64)> = Vec::with_capacity(4);
    pts.push((x0, f(&x0)));
    for k in 0..3 {
        let mut p = x0;
        p[k] += step[k];
        pts.push((p, f(&p)));
    }
    for _ in 0..iters {
        pts.sort_by(|a, b| a.1.total_cmp(&b.1));
        let spread = (0..3)
            .map(|k| {
                pts.iter()
                    .map(|p| (p.0[k] - pts[0].0[k]).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        if spread < 1e-4 {
            break;
        }
        let mut cen = [0.0; 3];
        for p in &pts[..3] {
            for k in 0..3 {
                cen[k] += p.0[k] / 3.0;
            }
        }
        let worst = pts[3];
        let along = |t: f64| {
            let mut q = [0.0; 3];
            for k in 0..3 {
                q[k] = cen[k] + t * (worst.0[k] - cen[k]);
            }
            q
        };
        let xr = along(-1.0);
        let fr = f(&xr);
        if fr < pts[0].1 {
            let xe = along(-2.0);
            let fe = f(&xe);
            pts[3] = if fe < fr { (xe, fe) } else { (xr, fr) };
        } else if fr < pts[2].1 {
            pts[3] = (xr, fr);
        } else {
            let xc = if fr < worst.1 {
                along(-0.5)
            } else {
                along(0.5)
            };
            let fc = f(&xc);
            if fc < worst.1.min(fr) {
                pts[3] = (xc, fc);
            } else {
                let best = pts[0].0;
                for p in pts.iter_mut().skip(1) {
                    for k in 0..3 {
                        p.0[k] = best[k] + 0.5 * (p.0[k] - best[k]);
                    }
                    p.1 = f(&p.0);
                }
            }
        }
    }
    pts.sort_by(|a, b| a.1.total_cmp(&b.1));
    pts[0]
}

/// The complement of the Kolmogorov distribution, `Q_KS(lambda)` (Numerical Recipes `probks`).
pub fn q_ks(lambda: f64) -> f64 {
    if lambda < 0.2 {
        // the series converges slowly there; Q_KS(0.2) = 1 - 1e-12
        return 1.0;
    }
    let a2 = -2.0 * lambda * lambda;
    let (mut sum, mut fac, mut prev) = (0.0, 2.0, 0.0f64);
    for j in 1..=200 {
        let jf = j as f64;
        let term = fac * (a2 * jf * jf).exp();
        sum += term;
        if term.abs() <= 1e-10 * prev || term.abs() <= 1e-16 * sum.abs() {
            return sum.clamp(0.0, 1.0);
        }
        fac = -fac;
        prev = term.abs();
    }
    1.0
}

/// Two-sample Kolmogorov-Smirnov statistic and asymptotic p-value.
pub fn ks_two_sample(a: &mut [f64], b: &mut [f64]) -> (f64, f64) {
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (n1, n2) = (a.len() as f64, b.len() as f64);
    let (mut i, mut j, mut d) = (0usize, 0usize, 0.0f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] <= x {
            i += 1;
        }
        while j < b.len() && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / n1 - j as f64 / n2).abs());
    }
    let ne = (n1 * n2 / (n1 + n2)).sqrt();
    (d, q_ks((ne + 0.12 + 0.11 / ne) * d))
}

/// Registers AFTER on BEFORE and compares them (see the module's documentation).
pub fn register(before: &HeightMap, after: &HeightMap) -> Result<Registration, ImageError> {
    if (before.pixel_m - after.pixel_m).abs() > 1e-9 * before.pixel_m {
        return Err(ImageError::new(
            &after.file,
            0,
            format!(
                "pixel_m {} differs from BEFORE's {}: resample one map first",
                after.pixel_m, before.pixel_m
            ),
        ));
    }
    let mut finite: Vec<f64> = before.h.iter().copied().filter(|v| v.is_finite()).collect();
    finite.sort_by(f64::total_cmp);
    // default valley threshold: BEFORE's 30th percentile (the lower third of the heights, like
    // the thesis's fixed cuts below the mean plane)
    let valley_below_m = before
        .valley_below_m
        .unwrap_or_else(|| finite[(finite.len() as f64 * 0.3) as usize]);
    let valley: Vec<(f64, f64, f64)> = (0..before.rows)
        .flat_map(|r| (0..before.cols).map(move |c| (r, c)))
        .filter_map(|(r, c)| {
            let v = before.at(r, c);
            (v.is_finite() && v < valley_below_m).then_some((c as f64, r as f64, v))
        })
        .collect();
    if valley.len() < 10 {
        return Err(ImageError::new(
            &before.file,
            0,
            format!(
                "only {} points below the valley threshold {valley_below_m:e} m: raise `valley_below_m`",
                valley.len()
            ),
        ));
    }
    let centre = (
        (before.cols as f64 - 1.0) / 2.0,
        (before.rows as f64 - 1.0) / 2.0,
    );
    let pb = before.points.map(|[r, c]| (c, r));
    let pa = after.points.map(|[r, c]| (c, r));
    let th0 =
        (pa[1].1 - pa[0].1).atan2(pa[1].0 - pa[0].0) - (pb[1].1 - pb[0].1).atan2(pb[1].0 - pb[0].0);
    let th0 = (th0 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    let prob = Problem {
        after,
        min_overlap: valley.len().div_ceil(2),
        valley,
        centre,
    };
    let mb = ((pb[0].0 + pb[1].0) / 2.0, (pb[0].1 + pb[1].1) / 2.0);
    let ma = ((pa[0].0 + pa[1].0) / 2.0, (pa[0].1 + pa[1].1) / 2.0);
    // the start the picks give (reported)
    let mapped = prob.map(mb.0, mb.1, (0.0, 0.0), th0);
    let d0 = (ma.0 - mapped.0, ma.1 - mapped.1);
    let ell = 0.5 * ((before.cols as f64).hypot(before.rows as f64));
    let f = |v: &[f64; 3]| prob.cost((v[0], v[1]), v[2] / ell).0;
    // the grid: picks off by up to PICK_ERROR_PX per coordinate turn the pair's direction by up
    // to 2 sqrt(2) PICK_ERROR_PX / separation (0.26 rad for points 33 pixels apart), beyond
    // what Nelder-Mead recovers from: rotations over that range, in steps that move BEFORE's
    // corners by a pixel (at most ROTATION_STEPS each way), each with its whole-pixel
    // translations within 4 pixels of where it maps the picked midpoint; judged on at most
    // GRID_POINTS of the valley points (evenly strided: a large map's grid costs no more)
    let sep = (pb[1].0 - pb[0].0).hypot(pb[1].1 - pb[0].1).max(1.0);
    let th_range = (2.0 * std::f64::consts::SQRT_2 * PICK_ERROR_PX / sep).min(1.0);
    let th_step = (1.0 / ell).max(th_range / ROTATION_STEPS as f64);
    let k_max = (th_range / th_step).ceil() as i32;
    let stride = prob.valley.len().div_ceil(GRID_POINTS);
    let coarse = Problem {
        after: prob.after,
        valley: prob.valley.iter().step_by(stride).copied().collect(),
        centre: prob.centre,
        min_overlap: prob.valley.len().div_ceil(stride).div_ceil(2),
    };
    let mut grid: Vec<([f64; 3], f64)> = Vec::new();
    for k in -k_max..=k_max {
        let th = th0 + k as f64 * th_step;
        let mapped = prob.map(mb.0, mb.1, (0.0, 0.0), th);
        let dk = (ma.0 - mapped.0, ma.1 - mapped.1);
        for i in -4..=4 {
            for j in -4..=4 {
                let v = [dk.0 + i as f64, dk.1 + j as f64, th * ell];
                grid.push((v, coarse.cost((v[0], v[1]), th).0));
            }
        }
    }
    grid.sort_by(|a, b| a.1.total_cmp(&b.1));
    if !grid[0].1.is_finite() {
        return Err(ImageError::new(
            &after.file,
            0,
            "the maps do not overlap on half of BEFORE's valleys near the picked points: check `points`",
        ));
    }
    let best = grid
        .iter()
        .take(3)
        .map(|(v, _)| nelder_mead(&f, *v, [0.7, 0.7, 0.7], 400))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("three starts");
    // robust refinement: a changed patch (the very thing the difference map is to show) pulls a
    // least-squares match towards it (a 0.2 um patch of radius 6 pixels moved the match by
    // 0.104 pixel on one synthetic pair whose match without the patch is 0.006 pixel off):
    // drop the valley points whose difference lies beyond TRIM_SIGMAS robust sigmas of the
    // median, and minimise again from the match, until the kept set stops changing
    let mut best = best;
    let mut trimmed = 0usize;
    for _ in 0..TRIM_ROUNDS {
        let (d, th) = ((best.0[0], best.0[1]), best.0[2] / ell);
        let kept = prob.inliers(d, th);
        if kept.len() == prob.valley.len() - trimmed || kept.len() < prob.min_overlap {
            break;
        }
        trimmed = prob.valley.len() - kept.len();
        let robust = Problem {
            after: prob.after,
            min_overlap: kept.len().div_ceil(2),
            valley: kept,
            centre: prob.centre,
        };
        let g = |v: &[f64; 3]| robust.cost((v[0], v[1]), v[2] / ell).0;
        best = nelder_mead(&g, best.0, [0.2, 0.2, 0.2], 400);
    }
    let (d, th) = ((best.0[0], best.0[1]), best.0[2] / ell);
    let (rms, _, n) = prob.cost(d, th);
    let dm = difference_map(before, after, &prob, d, th);
    let px = before.pixel_m;
    Ok(Registration {
        shift_m: [d.0 * px, d.1 * px],
        rotation_rad: th,
        rms_m: rms,
        offset_m: dm.offset_m,
        valley_below_m,
        valley_points: n,
        trimmed_points: trimmed,
        start_shift_m: [d0.0 * px, d0.1 * px],
        start_rotation_rad: th0,
        noise_m: dm.noise_m,
        change_threshold_m: dm.threshold_m,
        changed_area_m2: dm.changed as f64 * px * px,
        compared_points: dm.compared,
        ks_statistic: dm.ks,
        ks_p: dm.ks_p,
        difference: dm.difference,
        shape: [before.rows, before.cols],
    })
}

/// The difference map AFTER - BEFORE at the registration `(d, th)` and what it shows.
struct DifferenceMap {
    /// AFTER - BEFORE - offset at every BEFORE point [m] (NaN where not compared).
    difference: Vec<f64>,
    /// Median difference [m].
    offset_m: f64,
    /// Robust noise of the difference (1.4826 MAD) [m].
    noise_m: f64,
    /// Change threshold, 5 noise [m].
    threshold_m: f64,
    /// Points beyond the threshold.
    changed: usize,
    /// Points compared.
    compared: usize,
    /// Two-sample KS statistic of the heights before and after, and its p-value.
    ks: f64,
    ks_p: f64,
}

fn difference_map(
    before: &HeightMap,
    after: &HeightMap,
    prob: &Problem<'_>,
    d: (f64, f64),
    th: f64,
) -> DifferenceMap {
    // difference map over every BEFORE point; the height offset is the median difference
    // (robust to a changed patch, and free of the bias that bilinear interpolation gives a
    // valley-only mean: it fills valleys in)
    let mut raw = vec![f64::NAN; before.rows * before.cols];
    for r in 0..before.rows {
        for c in 0..before.cols {
            let b = before.at(r, c);
            if !b.is_finite() {
                continue;
            }
            let (u, v) = prob.map(c as f64, r as f64, d, th);
            if let Some(a) = after.sample(u, v) {
                raw[r * before.cols + c] = a - b;
            }
        }
    }
    let mut dev: Vec<f64> = raw.iter().copied().filter(|v| v.is_finite()).collect();
    let offset = median(&mut dev);
    let diff: Vec<f64> = raw.iter().map(|v| v - offset).collect();
    let mut bvals = Vec::new();
    let mut avals = Vec::new();
    for (i, dv) in diff.iter().enumerate() {
        if dv.is_finite() {
            let b = before.h[i];
            bvals.push(b);
            avals.push(b + dv);
        }
    }
    let mut absdev: Vec<f64> = diff
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .map(f64::abs)
        .collect();
    let noise = 1.4826 * median(&mut absdev);
    let thr = 5.0 * noise;
    let changed = absdev.iter().filter(|v| **v > thr).count();
    let compared = absdev.len();
    let (ks, p) = ks_two_sample(&mut bvals, &mut avals);
    DifferenceMap {
        difference: diff,
        offset_m: offset,
        noise_m: noise,
        threshold_m: thr,
        changed,
        compared,
        ks,
        ks_p: p,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kolmogorov_distribution_matches_published_values() {
        // Q_KS(lambda) = 1 - K(lambda); K(1.36) = 0.9505 and K(1.63) = 0.9902 (the 5 % and 1 %
        // critical values of the Kolmogorov distribution, e.g. Smirnov 1948 tables)
        assert!((q_ks(1.358) - 0.05).abs() < 5e-4, "{}", q_ks(1.358));
        assert!((q_ks(1.628) - 0.01).abs() < 2e-4, "{}", q_ks(1.628));
        assert_eq!(q_ks(0.1), 1.0);
    }

    #[test]
    fn ks_statistic_of_disjoint_and_equal_samples() {
        let (d, p) = ks_two_sample(&mut [1.0, 2.0, 3.0], &mut [4.0, 5.0, 6.0]);
        assert_eq!(d, 1.0);
        assert!(p < 0.1);
        let (d, p) = ks_two_sample(&mut [1.0, 2.0, 3.0], &mut [1.0, 2.0, 3.0]);
        assert_eq!(d, 0.0);
        assert_eq!(p, 1.0);
    }
}
