//! Tip trajectories recovered from synthetic high-speed frames rendered from a known trajectory
//! (area-sampled shadow, Gaussian blur, noise, vignetting), and bad frame inputs refused.
//!
//! Asserted: every frame's x and z within the stated accuracy of the extraction (docs/images.md:
//! 0.03 pixel + the displacement of a crossing by quantisation, vignetting and four noise
//! sigmas; 0.14 pixel for the thesis's camera), for
//! frame sizes, blurs (0.6 to 1.6 pixels), noise levels (up to 2 gray levels on a contrast of
//! 190), vignetting (up to 5 %), offsets and trajectories drawn by proptest; a bad input names
//! its file.

use geodesic_images::frames::Frame;
use geodesic_images::render::{Camera, tip_frame};
use geodesic_images::tiptrack;
use proptest::prelude::*;
use std::path::Path;

/// Stated accuracy of x and z [pixels] (docs/images.md): `0.03 max(1, 0.8 / blur)` pixel for the
/// linear interpolation between pixel centres of a blurred edge (its error goes as about
/// `1 / blur`; a constant 0.03 failed at blur 0.6 in CI), plus the displacement of a crossing
/// by a gray-level error `e`, `e / slope`, the edge's slope being `contrast / (sqrt(2 pi) blur)`
/// gray levels per pixel, with `e` = half a level of quantisation + the vignetting's change of
/// the edge's mid level (`vignetting (bright + dark) / 2` at worst) + four noise sigmas.
/// 0.14 pixel for the thesis's camera (blur 0.8 pixel, noise 1 gray level, contrast 190,
/// vignetting 5 %).
fn accuracy_px(cam: &Camera) -> f64 {
    let slope = (cam.bright - cam.dark) / ((std::f64::consts::TAU).sqrt() * cam.blur_px.max(0.5));
    let e = 0.5 + cam.vignetting * (cam.bright + cam.dark) / 2.0 + 4.0 * cam.noise;
    0.03 * (0.8 / cam.blur_px.max(0.5)).max(1.0) + e / slope
}

struct Case {
    cam: Camera,
    offset_px: f64,
    n: usize,
    x0: f64,
    vx: f64,
    z0: f64,
    dz: f64,
}

impl Case {
    fn truth(&self, k: usize) -> (f64, f64) {
        let s = k as f64 / self.n as f64;
        (
            self.x0 + self.vx * s,
            self.z0 + self.dz * (std::f64::consts::TAU * s).sin(),
        )
    }
}

fn write_case(dir: &Path, c: &Case, fps: f64, pixel_m: f64) -> std::path::PathBuf {
    let frames = dir.join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    for k in 0..c.n {
        let (x, z) = c.truth(k);
        let f = tip_frame(&c.cam, x, z, 1000 + k as u64);
        std::fs::write(frames.join(format!("retraction{k:05}.pgm")), f.to_pgm()).unwrap();
    }
    let yaml = dir.join("frames.yaml");
    let mid = (c.cam.bright + c.cam.dark) / 2.0;
    let half = (c.cam.bright - c.cam.dark) / 2.0;
    let th: Vec<String> = [-0.5, -0.25, 0.0, 0.25, 0.5]
        .iter()
        .map(|f| format!("{}", (mid + f * half).round()))
        .collect();
    std::fs::write(
        &yaml,
        format!(
            "frames: frames\nfps: {fps}\npixel_m: {pixel_m}\nthresholds: [{}]\noffset_px: {}\n",
            th.join(", "),
            c.offset_px
        ),
    )
    .unwrap();
    yaml
}

fn check(c: &Case) -> Result<(), TestCaseError> {
    let dir = tempfile::tempdir().unwrap();
    let (fps, pixel_m) = (31_466.0, 2.5e-6);
    let yaml = write_case(dir.path(), c, fps, pixel_m);
    let (_, tr) = tiptrack::run(&yaml).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(tr.t_s.len(), c.n);
    let tol = accuracy_px(&c.cam);
    for k in 0..c.n {
        let (x, z) = c.truth(k);
        let xe = tr.x_m[k].expect("x found") / pixel_m;
        let ze = tr.z_m[k].expect("z found") / pixel_m;
        prop_assert!(
            (xe - x).abs() < tol,
            "frame {}: x {} vs {} (accuracy {})",
            k,
            xe,
            x,
            tol
        );
        prop_assert!(
            (ze - z).abs() < tol,
            "frame {}: z {} vs {} (accuracy {})",
            k,
            ze,
            z,
            tol
        );
        prop_assert!((tr.t_s[k] - k as f64 / fps).abs() < 1e-15);
    }
    Ok(())
}

#[test]
fn the_thesis_camera_recovers_a_shearing_retraction() {
    // 80 x 60 frames, a 12-pixel retraction with a 2-pixel shear oscillation, to 0.14 pixel
    assert!((accuracy_px(&Camera::default()) - 0.14).abs() < 0.01);
    check(&Case {
        cam: Camera::default(),
        offset_px: 10.0,
        n: 40,
        x0: 20.0,
        vx: 12.0,
        z0: 30.0,
        dz: 2.0,
    })
    .unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]
    #[test]
    fn other_cameras_and_trajectories(
        w in 50usize..140, h in 40usize..100, blur in 0.6f64..1.6, noise in 0.0f64..2.0,
        vig in 0.0f64..0.05, offset in 6.0f64..14.0, xf in 0.15f64..0.4, zf in 0.3f64..0.6,
        vx in -5.0f64..15.0, dz in -3.0f64..3.0,
    ) {
        let cam = Camera { width: w, height: h, blur_px: blur, noise, vignetting: vig, ..Camera::default() };
        check(&Case {
            cam, offset_px: offset, n: 12,
            x0: xf * w as f64 + 5.0, vx, z0: zf * h as f64, dz,
        })?;
    }
}

#[test]
fn validity_judges_the_shear_in_the_window() {
    let mut c = Case {
        cam: Camera::default(),
        offset_px: 10.0,
        n: 20,
        x0: 20.0,
        vx: 5.0,
        z0: 30.0,
        dz: 1.5,
    };
    c.cam.noise = 0.0;
    let dir = tempfile::tempdir().unwrap();
    let yaml = write_case(dir.path(), &c, 1.0e4, 1.0e-6);
    let (_, tr) = tiptrack::run(&yaml).unwrap();
    // the shear reaches 1.5 px (1.5 um) at a quarter of the record (5 frames = 0.5 ms)
    let v = tiptrack::Validity {
        window_s: 1.0e-3,
        max_shear_m: 1.0e-6,
    };
    let r = tiptrack::judge(&tr, v).unwrap();
    assert!((r.shear_m - 1.5e-6).abs() < 0.1e-6, "{r:?}");
    assert!(!r.valid);
    let loose = tiptrack::Validity {
        window_s: 1.0e-3,
        max_shear_m: 2.0e-6,
    };
    assert!(tiptrack::judge(&tr, loose).unwrap().valid);
    // within the first 0.1 ms (frames 0 and 1) the shear is sin(2 pi / 20) * 1.5 px
    let early = tiptrack::Validity {
        window_s: 1.0e-4,
        max_shear_m: 1.0e-6,
    };
    let r = tiptrack::judge(&tr, early).unwrap();
    assert_eq!(r.frames, 2);
    assert!(
        (r.shear_m - 1.5e-6 * (std::f64::consts::TAU / 20.0).sin()).abs() < 0.1e-6,
        "{r:?}"
    );
}

fn err_of(yaml: &Path) -> String {
    tiptrack::run(yaml).unwrap_err().to_string()
}

#[test]
fn bad_frames_are_refused_with_the_file_named() {
    let dir = tempfile::tempdir().unwrap();
    let c = Case {
        cam: Camera::default(),
        offset_px: 10.0,
        n: 4,
        x0: 20.0,
        vx: 5.0,
        z0: 30.0,
        dz: 0.0,
    };
    let yaml = write_case(dir.path(), &c, 1.0e4, 1.0e-6);
    let frames = dir.path().join("frames");
    // a frame of another size
    let small = tip_frame(
        &Camera {
            width: 40,
            ..Camera::default()
        },
        10.0,
        20.0,
        1,
    );
    std::fs::write(frames.join("retraction00004.pgm"), small.to_pgm()).unwrap();
    let e = err_of(&yaml);
    assert!(
        e.contains("retraction00004.pgm") && e.contains("40 x 60"),
        "{e}"
    );
    // another bit depth
    let deep = Frame {
        maxval: 4095,
        ..tip_frame(&Camera::default(), 10.0, 20.0, 1)
    };
    std::fs::write(frames.join("retraction00004.pgm"), deep.to_pgm()).unwrap();
    let e = err_of(&yaml);
    assert!(
        e.contains("retraction00004.pgm") && e.contains("bit depth"),
        "{e}"
    );
    // a missing frame
    std::fs::remove_file(frames.join("retraction00004.pgm")).unwrap();
    std::fs::remove_file(frames.join("retraction00002.pgm")).unwrap();
    let e = err_of(&yaml);
    assert!(
        e.contains("missing frame") && e.contains("retraction00001.pgm"),
        "{e}"
    );
    std::fs::write(
        frames.join("retraction00002.pgm"),
        b"P5\n80 60\n255\n\x01\x02",
    )
    .unwrap();
    let e = err_of(&yaml);
    assert!(
        e.contains("retraction00002.pgm") && e.contains("truncated"),
        "{e}"
    );
    std::fs::write(frames.join("retraction00002.pgm"), b"not an image").unwrap();
    assert!(err_of(&yaml).contains("not a grayscale PGM"));
    let ok = tip_frame(&Camera::default(), 25.0, 30.0, 1);
    std::fs::write(frames.join("retraction00002.pgm"), ok.to_pgm()).unwrap();
    tiptrack::run(&yaml).unwrap();
    // NaN, a threshold outside the gray range, an unknown key
    let good = std::fs::read_to_string(&yaml).unwrap();
    std::fs::write(&yaml, good.replace("fps: 10000", "fps: .nan")).unwrap();
    let e = err_of(&yaml);
    assert!(e.contains("frames.yaml") && e.contains("fps"), "{e}");
    std::fs::write(&yaml, good.replace("thresholds: [", "thresholds: [300, ")).unwrap();
    assert!(err_of(&yaml).contains("threshold 300"));
    std::fs::write(&yaml, format!("{good}colour: red\n")).unwrap();
    let e = err_of(&yaml);
    assert!(e.contains("frames.yaml:") && e.contains("colour"), "{e}");
    std::fs::write(&yaml, good.replace("frames: frames", "frames: nowhere")).unwrap();
    assert!(err_of(&yaml).contains("nowhere"));
}

#[test]
fn png_frames_and_one_multi_frame_pgm_give_the_same_trajectory() {
    let dir = tempfile::tempdir().unwrap();
    let c = Case {
        cam: Camera::default(),
        offset_px: 10.0,
        n: 6,
        x0: 20.0,
        vx: 5.0,
        z0: 30.0,
        dz: 1.0,
    };
    let yaml = write_case(dir.path(), &c, 1.0e4, 1.0e-6);
    let (_, a) = tiptrack::run(&yaml).unwrap();
    // the same frames as one concatenated PGM
    let mut all = Vec::new();
    for k in 0..c.n {
        all.extend(std::fs::read(dir.path().join(format!("frames/retraction{k:05}.pgm"))).unwrap());
    }
    std::fs::write(dir.path().join("all.pgm"), all).unwrap();
    let text = std::fs::read_to_string(&yaml).unwrap();
    std::fs::write(&yaml, text.replace("frames: frames", "frames: all.pgm")).unwrap();
    let (_, b) = tiptrack::run(&yaml).unwrap();
    assert_eq!(a, b);
    // and as 8-bit PNGs
    let png_dir = dir.path().join("png");
    std::fs::create_dir(&png_dir).unwrap();
    for k in 0..c.n {
        let f = geodesic_images::frames::read_file(
            &dir.path().join(format!("frames/retraction{k:05}.pgm")),
        )
        .unwrap()
        .remove(0);
        let file = std::fs::File::create(png_dir.join(format!("f{k:03}.png"))).unwrap();
        let mut enc = png::Encoder::new(
            std::io::BufWriter::new(file),
            f.width as u32,
            f.height as u32,
        );
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().unwrap();
        let bytes: Vec<u8> = f.data.iter().map(|&v| v as u8).collect();
        w.write_image_data(&bytes).unwrap();
    }
    std::fs::write(&yaml, text.replace("frames: frames", "frames: png")).unwrap();
    let (_, p) = tiptrack::run(&yaml).unwrap();
    assert_eq!(a, p);
}
