//! Synthetic inputs from a known truth: camera frames of the tip's shadow along a trajectory,
//! and surface height maps with a known shift, rotation and transferred patch. The tests prove
//! the extraction and registration errors on them; `geodesic tiptrack`/`surfaces` users can
//! render their own to check a setup (the test helpers are public for that reason).

use crate::frames::Frame;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// How a frame is rendered.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Gray level of the lit background.
    pub bright: f64,
    /// Gray level of the shadow.
    pub dark: f64,
    /// Largest gray level (255 for 8 bit).
    pub maxval: u16,
    /// Gaussian blur of the optics [pixels, 1 sigma]; 0 for none.
    pub blur_px: f64,
    /// Gaussian noise [gray levels, 1 sigma].
    pub noise: f64,
    /// Vignetting: the light falls by this fraction from the centre to the corners.
    pub vignetting: f64,
}

impl Default for Camera {
    /// The thesis's camera: 80 x 60 pixels, 8 bit.
    fn default() -> Self {
        Camera {
            width: 80,
            height: 60,
            bright: 220.0,
            dark: 30.0,
            maxval: 255,
            blur_px: 0.8,
            noise: 1.0,
            vignetting: 0.05,
        }
    }
}

/// Overlap of `[a, a + 1]` with `[lo, inf)`.
fn cover_from(a: f64, lo: f64) -> f64 {
    (a + 1.0 - lo).clamp(0.0, 1.0)
}

/// One frame of the tip's shadow: the dark region right of `x_px` (from the left edge) and
/// below `z_px` (its upper boundary, from the bottom edge), area-sampled, then blurred, lit
/// with vignetting, noised and quantised. `seed` draws the noise.
pub fn tip_frame(cam: &Camera, x_px: f64, z_px: f64, seed: u64) -> Frame {
    let (w, h) = (cam.width, cam.height);
    // coverage of the shadow, rows from the top
    let mut cov = vec![0.0f64; w * h];
    for r in 0..h {
        let from_bottom = (h - 1 - r) as f64;
        // rows from the bottom: [from_bottom, from_bottom + 1] inside (-inf, z]
        let cy = (z_px - from_bottom).clamp(0.0, 1.0);
        for c in 0..w {
            cov[r * w + c] = cover_from(c as f64, x_px) * cy;
        }
    }
    let cov = if cam.blur_px > 0.0 {
        blur(&cov, w, h, cam.blur_px)
    } else {
        cov
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let noise = Normal::new(0.0, cam.noise.max(0.0)).expect("finite noise");
    let (cx, cy) = ((w as f64 - 1.0) / 2.0, (h as f64 - 1.0) / 2.0);
    let dmax2 = cx * cx + cy * cy;
    let data = (0..w * h)
        .map(|i| {
            let (r, c) = ((i / w) as f64, (i % w) as f64);
            let light = 1.0 - cam.vignetting * ((c - cx).powi(2) + (r - cy).powi(2)) / dmax2;
            let g =
                light * (cam.bright - (cam.bright - cam.dark) * cov[i]) + noise.sample(&mut rng);
            g.round().clamp(0.0, f64::from(cam.maxval)) as u16
        })
        .collect();
    Frame {
        width: w,
        height: h,
        maxval: cam.maxval,
        data,
    }
}

/// Separable Gaussian blur with the edge values extended.
fn blur(img: &[f64], w: usize, h: usize, sigma: f64) -> Vec<f64> {
    let rad = (4.0 * sigma).ceil() as isize;
    let k: Vec<f64> = (-rad..=rad)
        .map(|i| (-(i as f64).powi(2) / (2.0 * sigma * sigma)).exp())
        .collect();
    let s: f64 = k.iter().sum();
    let k: Vec<f64> = k.iter().map(|v| v / s).collect();
    let mut tmp = vec![0.0; w * h];
    for r in 0..h {
        for c in 0..w {
            tmp[r * w + c] = (-rad..=rad)
                .map(|i| {
                    let cc = (c as isize + i).clamp(0, w as isize - 1) as usize;
                    k[(i + rad) as usize] * img[r * w + cc]
                })
                .sum();
        }
    }
    let mut out = vec![0.0; w * h];
    for r in 0..h {
        for c in 0..w {
            out[r * w + c] = (-rad..=rad)
                .map(|i| {
                    let rr = (r as isize + i).clamp(0, h as isize - 1) as usize;
                    k[(i + rad) as usize] * tmp[rr * w + c]
                })
                .sum();
        }
    }
    out
}

/// A smooth random rough surface defined everywhere (a sum of plane waves with wavelengths
/// from 6 to 40 pixels), so that a shifted and rotated copy is exact at sub-pixel positions.
#[derive(Debug, Clone)]
pub struct RoughSurface {
    waves: Vec<(f64, f64, f64, f64)>,
}

impl RoughSurface {
    /// `n` waves drawn with `seed`; heights of about `rms_m` [m] RMS.
    pub fn new(n: usize, rms_m: f64, seed: u64) -> RoughSurface {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let a = rms_m * (2.0 / n as f64).sqrt();
        let waves = (0..n)
            .map(|_| {
                let lambda = rng.random_range(6.0..40.0);
                let dir: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                let k = std::f64::consts::TAU / lambda;
                (
                    a,
                    k * dir.cos(),
                    k * dir.sin(),
                    rng.random_range(0.0..std::f64::consts::TAU),
                )
            })
            .collect();
        RoughSurface { waves }
    }

    /// Height [m] at `(x, y)` in pixels.
    pub fn at(&self, x: f64, y: f64) -> f64 {
        self.waves
            .iter()
            .map(|(a, kx, ky, ph)| a * (kx * x + ky * y + ph).sin())
            .sum()
    }
}

/// A height map as the CSV `geodesic surfaces` reads: `rows` lines of `cols` heights [m];
/// `None` cells are written empty (missing points).
pub fn map_csv(rows: usize, cols: usize, h: impl Fn(usize, usize) -> Option<f64>) -> String {
    let mut s = String::with_capacity(rows * cols * 14);
    for r in 0..rows {
        for c in 0..cols {
            if c > 0 {
                s.push(',');
            }
            if let Some(v) = h(r, c) {
                s.push_str(&format!("{v:.6e}"));
            }
        }
        s.push('\n');
    }
    s
}
