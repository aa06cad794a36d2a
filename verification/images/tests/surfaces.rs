//! Registration of synthetic height maps with a known sub-pixel shift, rotation, height offset
//! and transferred patch (a smooth random rough surface, exact at any position; measurement
//! noise; missing points), and bad map inputs refused.
//!
//! Asserted: the shift within 0.05 pixel and the rotation within 1 mrad of the truth (the
//! stated accuracy, docs/images.md), the transferred patch's area within one pixel around its
//! rim, a large KS statistic with a patch and a small one without; bad CSVs name file and line.

use geodesic_images::render::{RoughSurface, map_csv};
use geodesic_images::surfaces::{HeightMap, register};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::path::{Path, PathBuf};

const PIXEL_M: f64 = 1.10365e-7; // the thesis's profilometer resolution

struct Truth {
    rows: usize,
    cols: usize,
    dx: f64,
    dy: f64,
    theta: f64,
    offset_m: f64,
    /// Transferred patch in AFTER: centre (col, row), radius [px], height [m].
    patch: Option<(f64, f64, f64, f64)>,
    noise_m: f64,
    pick_error_px: f64,
    seed: u64,
}

fn write_maps(dir: &Path, t: &Truth) -> (PathBuf, PathBuf) {
    let s = RoughSurface::new(40, 3e-7, t.seed);
    let (cx, cy) = ((t.cols as f64 - 1.0) / 2.0, (t.rows as f64 - 1.0) / 2.0);
    let mut rng = ChaCha8Rng::seed_from_u64(t.seed + 1);
    let noise = Normal::new(0.0, t.noise_m).unwrap();
    let missing =
        |r: usize, c: usize, k: u64| (r * 7919 + c * 104_729 + k as usize * 31).is_multiple_of(53);
    let before: Vec<Option<f64>> = (0..t.rows * t.cols)
        .map(|i| {
            let (r, c) = (i / t.cols, i % t.cols);
            (!missing(r, c, 1)).then(|| s.at(c as f64, r as f64) + noise.sample(&mut rng))
        })
        .collect();
    let (sn, cs) = t.theta.sin_cos();
    let after: Vec<Option<f64>> = (0..t.rows * t.cols)
        .map(|i| {
            let (r, c) = (i / t.cols, i % t.cols);
            // AFTER(q) = S(T^-1(q)), T(p) = R (p - c) + c + d
            let (qx, qy) = (c as f64 - cx - t.dx, r as f64 - cy - t.dy);
            let (px, py) = (cs * qx + sn * qy + cx, -sn * qx + cs * qy + cy);
            let mut v = s.at(px, py) + t.offset_m + noise.sample(&mut rng);
            if let Some((pc, pr, rad, h)) = t.patch
                && (c as f64 - pc).hypot(r as f64 - pr) <= rad
            {
                v += h;
            }
            (!missing(r, c, 2)).then_some(v)
        })
        .collect();
    std::fs::write(
        dir.join("before.csv"),
        map_csv(t.rows, t.cols, |r, c| before[r * t.cols + c]),
    )
    .unwrap();
    std::fs::write(
        dir.join("after.csv"),
        map_csv(t.rows, t.cols, |r, c| after[r * t.cols + c]),
    )
    .unwrap();
    // two picked features, and where the user clicks on AFTER (off by up to pick_error_px)
    let p = [
        (0.3 * t.cols as f64, 0.35 * t.rows as f64),
        (0.7 * t.cols as f64, 0.6 * t.rows as f64),
    ];
    let q: Vec<(f64, f64)> = p
        .iter()
        .enumerate()
        .map(|(k, &(x, y))| {
            let (px, py) = (x - cx, y - cy);
            let e = t.pick_error_px * if k == 0 { 1.0 } else { -0.7 };
            (
                cs * px - sn * py + cx + t.dx + e,
                sn * px + cs * py + cy + t.dy - e,
            )
        })
        .collect();
    let yaml = |name: &str, csv: &str, pts: [(f64, f64); 2]| {
        let f = dir.join(name);
        std::fs::write(
            &f,
            format!(
                "map: {csv}\npixel_m: {PIXEL_M}\npoints: [[{:.2}, {:.2}], [{:.2}, {:.2}]]\n",
                pts[0].1, pts[0].0, pts[1].1, pts[1].0
            ),
        )
        .unwrap();
        f
    };
    (
        yaml("before.yaml", "before.csv", p),
        yaml("after.yaml", "after.csv", [q[0], q[1]]),
    )
}

fn run(t: &Truth) -> geodesic_images::surfaces::Registration {
    let dir = tempfile::tempdir().unwrap();
    let (b, a) = write_maps(dir.path(), t);
    register(&HeightMap::load(&b).unwrap(), &HeightMap::load(&a).unwrap()).unwrap()
}

fn base() -> Truth {
    Truth {
        rows: 100,
        cols: 120,
        dx: 7.3,
        dy: -4.6,
        theta: 0.0,
        offset_m: 4e-8,
        patch: None,
        noise_m: 5e-9,
        pick_error_px: 2.0,
        seed: 11,
    }
}

#[test]
fn a_known_sub_pixel_shift_is_found() {
    let t = base();
    let r = run(&t);
    assert!(
        (r.shift_m[0] / PIXEL_M - t.dx).abs() < 0.05,
        "{:?}",
        r.shift_m
    );
    assert!(
        (r.shift_m[1] / PIXEL_M - t.dy).abs() < 0.05,
        "{:?}",
        r.shift_m
    );
    assert!(r.rotation_rad.abs() < 1e-3, "{}", r.rotation_rad);
    assert!((r.offset_m - t.offset_m).abs() < 5e-9, "{}", r.offset_m);
    // nothing changed: no area above 5 sigma of noise beyond a few stray points, and the KS
    // test does not tell the distributions apart strongly
    assert!(
        r.changed_area_m2 < 5.0 * PIXEL_M * PIXEL_M,
        "{}",
        r.changed_area_m2
    );
    assert!(r.ks_statistic < 0.05, "{}", r.ks_statistic);
}

#[test]
fn a_rotation_and_a_transferred_patch_are_found() {
    let rad = 6.0;
    let t = Truth {
        theta: 0.02,
        patch: Some((40.0, 60.0, rad, 2.0e-7)),
        ..base()
    };
    let r = run(&t);
    assert!(
        (r.shift_m[0] / PIXEL_M - t.dx).abs() < 0.05,
        "{:?}",
        r.shift_m
    );
    assert!(
        (r.shift_m[1] / PIXEL_M - t.dy).abs() < 0.05,
        "{:?}",
        r.shift_m
    );
    assert!(
        (r.rotation_rad - t.theta).abs() < 1e-3,
        "{}",
        r.rotation_rad
    );
    let area_px = r.changed_area_m2 / (PIXEL_M * PIXEL_M);
    let disk = std::f64::consts::PI * rad * rad;
    assert!(
        (area_px - disk).abs() < std::f64::consts::TAU * rad,
        "{area_px} vs {disk}"
    );
    // 113 of 12 000 points raised by 0.2 um hardly move the height distribution
    assert!(r.ks_statistic < 0.03, "{} {}", r.ks_statistic, r.ks_p);
}

#[test]
fn flattened_peaks_change_the_height_distribution() {
    // AFTER's peaks above 0.2 um flattened to 0.2 um (the thesis's asperities flattened by the
    // contact): the registration holds on the valleys, and the KS test separates the heights
    let dir = tempfile::tempdir().unwrap();
    let t = base();
    let (b, a) = write_maps(dir.path(), &t);
    let csv = dir.path().join("after.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let cut = 2.0e-7 + t.offset_m;
    let flat: String = text
        .lines()
        .map(|l| {
            l.split(',')
                .map(|c| match c.parse::<f64>() {
                    Ok(v) if v > cut => format!("{cut:e}"),
                    _ => c.to_string(),
                })
                .collect::<Vec<_>>()
                .join(",")
                + "\n"
        })
        .collect();
    std::fs::write(&csv, flat).unwrap();
    let r = register(&HeightMap::load(&b).unwrap(), &HeightMap::load(&a).unwrap()).unwrap();
    assert!(
        (r.shift_m[0] / PIXEL_M - t.dx).abs() < 0.05,
        "{:?}",
        r.shift_m
    );
    assert!(
        (r.shift_m[1] / PIXEL_M - t.dy).abs() < 0.05,
        "{:?}",
        r.shift_m
    );
    assert!(
        r.ks_statistic > 0.05 && r.ks_p < 1e-6,
        "{} {}",
        r.ks_statistic,
        r.ks_p
    );
    assert!(
        r.changed_area_m2 > 100.0 * PIXEL_M * PIXEL_M,
        "{}",
        r.changed_area_m2
    );
}

/// A small map (70 x 70) whose picks are off by 2.56 pixels in opposite directions: the pairs'
/// directions differ by 0.16 rad, and a start grid over translations only ended 4 to 5 pixels
/// off (found by `other_shifts_rotations_and_sizes`, seed 189); the grid over rotations finds it.
#[test]
fn picks_that_turn_a_small_map_are_recovered() {
    let t = Truth {
        rows: 70,
        cols: 70,
        dx: 0.0,
        dy: 0.0,
        theta: 0.0,
        pick_error_px: 2.564,
        seed: 189,
        ..base()
    };
    let r = run(&t);
    assert!((r.shift_m[0] / PIXEL_M).abs() < 0.05, "{:?}", r.shift_m);
    assert!((r.shift_m[1] / PIXEL_M).abs() < 0.05, "{:?}", r.shift_m);
    assert!(r.rotation_rad.abs() < 1e-3, "{}", r.rotation_rad);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]
    #[test]
    fn other_shifts_rotations_and_sizes(
        dx in -10.0f64..10.0, dy in -10.0f64..10.0, theta in -0.03f64..0.03,
        rows in 70usize..120, cols in 70usize..130, seed in 0u64..1000, pick in 0.0f64..3.0,
    ) {
        let t = Truth { rows, cols, dx, dy, theta, pick_error_px: pick, seed, ..base() };
        let r = run(&t);
        prop_assert!((r.shift_m[0] / PIXEL_M - dx).abs() < 0.05, "{:?}", r.shift_m);
        prop_assert!((r.shift_m[1] / PIXEL_M - dy).abs() < 0.05, "{:?}", r.shift_m);
        prop_assert!((r.rotation_rad - theta).abs() < 1e-3, "{}", r.rotation_rad);
    }
}

#[test]
fn bad_maps_are_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let (b, _) = write_maps(
        dir.path(),
        &Truth {
            rows: 20,
            cols: 20,
            ..base()
        },
    );
    let csv = dir.path().join("before.csv");
    let good = std::fs::read_to_string(&csv).unwrap();
    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    lines[3].push_str(",1e-7");
    std::fs::write(&csv, lines.join("\n")).unwrap();
    let e = HeightMap::load(&b).unwrap_err().to_string();
    assert!(e.contains("before.csv:4:") && e.contains("21 cells"), "{e}");
    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    lines[5] = lines[5].replacen(',', ",abc,", 1).replacen(",,", ",", 1);
    lines[5] = format!("abc{}", &lines[5][lines[5].find(',').unwrap()..]);
    std::fs::write(&csv, lines.join("\n")).unwrap();
    let e = HeightMap::load(&b).unwrap_err().to_string();
    assert!(e.contains("before.csv:6:") && e.contains("`abc`"), "{e}");
    std::fs::write(&csv, good.replacen("e-", "e+999", 1)).unwrap();
    let e = HeightMap::load(&b).unwrap_err().to_string();
    assert!(e.contains("before.csv:1:"), "{e}");
    std::fs::write(&csv, &good).unwrap();
    let y = std::fs::read_to_string(&b).unwrap();
    std::fs::write(&b, y.replace("points: [[", "points: [[1, 2], [")).unwrap();
    assert!(
        HeightMap::load(&b)
            .unwrap_err()
            .to_string()
            .contains("two [row, col] pairs")
    );
    std::fs::write(
        &b,
        y.replace(&format!("pixel_m: {PIXEL_M}"), "pixel_m: -1e-7"),
    )
    .unwrap();
    assert!(
        HeightMap::load(&b)
            .unwrap_err()
            .to_string()
            .contains("pixel_m")
    );
    std::fs::write(&b, format!("{y}colour: red\n")).unwrap();
    let e = HeightMap::load(&b).unwrap_err().to_string();
    assert!(e.contains("before.yaml:") && e.contains("colour"), "{e}");
}
