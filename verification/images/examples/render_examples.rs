//! Writes the example inputs of `geodesic tiptrack` and `geodesic surfaces` under `data/`
//! (`cargo run -p geodesic-images --example render_examples -- data`): synthetic, from a known
//! truth written beside them (`truth.json`), so that a user can see what the commands recover.
//!
//! * `data/camera/`: 60 frames of the thesis's camera (80 x 60 pixels, 8 bit, 31 466 Hz,
//!   2.5 um pixels) of a tip retracting by 12 pixels with a 1.5-pixel shear oscillation, blur
//!   0.8 pixel, noise 1 gray level, vignetting 5 %; `frames.yaml` with a validity criterion.
//! * `data/surfaces/`: a 120 x 100 rough surface (0.3 um RMS, the thesis's 0.110 um pixels)
//!   before, and after shifted by (7.3, -4.6) pixels and rotated by 0.02 rad with a 0.2 um
//!   transferred patch of radius 6 pixels, 5 nm noise, 2 % missing points.

use geodesic_images::render::{Camera, RoughSurface, map_csv, tip_frame};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::path::Path;

fn main() {
    let root = std::env::args().nth(1).unwrap_or_else(|| "data".into());
    let root = Path::new(&root);
    // camera
    let cam_dir = root.join("camera");
    let frames = cam_dir.join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    let cam = Camera::default();
    let (n, pixel_m, fps) = (60usize, 2.5e-6, 31_466.0);
    let mut truth_x = Vec::new();
    let mut truth_z = Vec::new();
    for k in 0..n {
        let s = k as f64 / n as f64;
        let x = 20.0 + 12.0 * s;
        let z = 30.0 + 1.5 * (std::f64::consts::TAU * 2.0 * s).sin();
        truth_x.push(x * pixel_m);
        truth_z.push(z * pixel_m);
        let f = tip_frame(&cam, x, z, 500 + k as u64);
        std::fs::write(frames.join(format!("retraction{k:05}.pgm")), f.to_pgm()).unwrap();
    }
    std::fs::write(
        cam_dir.join("frames.yaml"),
        "# synthetic frames of the thesis's camera (verification/images/examples/render_examples.rs)\n\
         frames: frames\nfps: 31466\npixel_m: 2.5e-6\nthresholds: [75, 100, 125, 150, 175]\noffset_px: 10\n\
         # test validity: the tip's shear (z) excursion in the first 0.5 ms must stay below 5 um\n\
         validity: {window_s: 5.0e-4, max_shear_m: 5.0e-6}\n",
    )
    .unwrap();
    let t: Vec<f64> = (0..n).map(|k| k as f64 / fps).collect();
    std::fs::write(
        cam_dir.join("truth.json"),
        format!(
            "{{\"t_s\": {t:?}, \"x_m\": {truth_x:?}, \"z_m\": {truth_z:?}, \"camera\": \"{cam:?}\"}}\n"
        ),
    )
    .unwrap();
    // surfaces
    let sdir = root.join("surfaces");
    std::fs::create_dir_all(&sdir).unwrap();
    let (rows, cols) = (100usize, 120usize);
    let (dx, dy, th, off) = (7.3, -4.6, 0.02, 4e-8);
    let s = RoughSurface::new(40, 3e-7, 11);
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let noise = Normal::new(0.0, 5e-9).unwrap();
    let (cx, cy) = ((cols as f64 - 1.0) / 2.0, (rows as f64 - 1.0) / 2.0);
    let missing =
        |r: usize, c: usize, k: usize| (r * 7919 + c * 104_729 + k * 31).is_multiple_of(53);
    let b: Vec<Option<f64>> = (0..rows * cols)
        .map(|i| {
            let (r, c) = (i / cols, i % cols);
            (!missing(r, c, 1)).then(|| s.at(c as f64, r as f64) + noise.sample(&mut rng))
        })
        .collect();
    let (sn, cs) = f64::sin_cos(th);
    let a: Vec<Option<f64>> = (0..rows * cols)
        .map(|i| {
            let (r, c) = (i / cols, i % cols);
            let (qx, qy) = (c as f64 - cx - dx, r as f64 - cy - dy);
            let (px, py) = (cs * qx + sn * qy + cx, -sn * qx + cs * qy + cy);
            let mut v = s.at(px, py) + off + noise.sample(&mut rng);
            if (c as f64 - 40.0).hypot(r as f64 - 60.0) <= 6.0 {
                v += 2e-7;
            }
            (!missing(r, c, 2)).then_some(v)
        })
        .collect();
    std::fs::write(
        sdir.join("before.csv"),
        map_csv(rows, cols, |r, c| b[r * cols + c]),
    )
    .unwrap();
    std::fs::write(
        sdir.join("after.csv"),
        map_csv(rows, cols, |r, c| a[r * cols + c]),
    )
    .unwrap();
    std::fs::write(
        sdir.join("before.yaml"),
        "map: before.csv\npixel_m: 1.10365e-7\npoints: [[35, 36], [60, 84]]\n",
    )
    .unwrap();
    std::fs::write(
        sdir.join("after.yaml"),
        "map: after.csv\npixel_m: 1.10365e-7\npoints: [[32, 45], [58, 90]]\n",
    )
    .unwrap();
    std::fs::write(
        sdir.join("truth.json"),
        format!(
            "{{\"shift_px\": [{dx}, {dy}], \"shift_m\": [{}, {}], \"rotation_rad\": {th}, \"offset_m\": {off}, \"patch\": {{\"centre_col_row_in_after\": [40, 60], \"radius_px\": 6, \"height_m\": 2e-7, \"area_m2\": {}}}}}\n",
            dx * 1.10365e-7,
            dy * 1.10365e-7,
            std::f64::consts::PI * 36.0 * 1.10365e-7 * 1.10365e-7
        ),
    )
    .unwrap();
    println!("wrote {} and {}", cam_dir.display(), sdir.display());
}
