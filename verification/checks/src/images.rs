//! `image-analyses` (issue 17): the accuracy of geodesic's two ground-test image analyses, the
//! way FAC-FIT-QUAL judges the fit: each is run on synthetic inputs rendered from a known truth,
//! and the error against that truth is the evidence. These are **method validations** (basis
//! `method-validation`): they show what the tool achieves on scenes defined in code, not what a
//! ground test achieved. The scenes are a fixed set ([`TIPTRACK_SCENES`],
//! [`REGISTRATION_SCENES`]), so the verdict does not move with the run's seed; the worst scene
//! decides.
//!
//! - FAC-TIPTRACK-ACC: 40 frames of the thesis's camera (80 x 60 pixels, 8 bit, blur 0.8 px,
//!   noise 1 gray level, vignetting 5 %) of a tip retracting 12 px with a 1.5 px shear
//!   oscillation; thresholds 75-175, offset 10 px; value: the largest |x| or |z| error over the
//!   frames [px].
//! - FAC-SURF-REG: a 120 x 100 rough surface (0.3 um RMS) before, and after shifted by
//!   (7.3, -4.6) px, rotated by 0.02 rad, with a 0.2 um transferred patch, 5 nm noise; value:
//!   the larger shift error [px].
//!
//! Plots (trajectory, difference map of scene 1) go into the report. The truth is known only
//! because the inputs are synthetic: this verifies the analyses, not a ground test.

use crate::plots;
use geodesic_core::{Basis, Check, CheckContext, CheckError, Dim, Evidence, Quantity};
use geodesic_images::frames::Sequence;
use geodesic_images::render::{Camera, RoughSurface, tip_frame};
use geodesic_images::surfaces::{HeightMap, register};
use geodesic_images::tiptrack::{Config, track};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::path::PathBuf;

/// The checks of this family.
pub fn checks() -> Vec<Box<dyn Check>> {
    vec![Box::new(ImageAnalyses)]
}

/// `image-analyses`.
pub struct ImageAnalyses;

/// Frames rendered for the tip-trajectory accuracy.
pub const FRAMES: usize = 40;

/// The largest tip-position error [px] over [`FRAMES`] frames rendered with `seed`, with the
/// trajectory (for the plot).
pub fn tiptrack_error_px(
    seed: u64,
) -> Result<(f64, geodesic_images::tiptrack::Trajectory), CheckError> {
    let cam = Camera::default();
    let (pixel_m, fps) = (2.5e-6, 31_466.0);
    let mut frames = Vec::new();
    let mut truth = Vec::new();
    for k in 0..FRAMES {
        let s = k as f64 / FRAMES as f64;
        let x = 20.0 + 12.0 * s;
        let z = 30.0 + 1.5 * (std::f64::consts::TAU * 2.0 * s).sin();
        truth.push((x, z));
        frames.push(tip_frame(
            &cam,
            x,
            z,
            seed.wrapping_mul(1000).wrapping_add(k as u64),
        ));
    }
    let seq = Sequence {
        sources: (0..FRAMES)
            .map(|k| PathBuf::from(format!("<synthetic frame {k}>")))
            .collect(),
        frames,
    };
    let cfg = Config {
        file: PathBuf::from("<synthetic>"),
        frames: PathBuf::from("<synthetic>"),
        fps,
        pixel_m,
        thresholds: vec![75.0, 100.0, 125.0, 150.0, 175.0],
        offset_px: 10.0,
        validity: None,
    };
    let tr =
        track(&seq, &cfg).map_err(|e| CheckError::model("tiptrack", format!("tiptrack: {e}")))?;
    let mut worst = 0.0f64;
    for (k, (x, z)) in truth.iter().enumerate() {
        let (Some(tx), Some(tz)) = (tr.x_m[k], tr.z_m[k]) else {
            return Err(CheckError::model(
                "tiptrack",
                format!("tiptrack: synthetic frame {k} gave no crossing"),
            ));
        };
        worst = worst
            .max((tx / pixel_m - x).abs())
            .max((tz / pixel_m - z).abs());
    }
    Ok((worst, tr))
}

/// The larger shift error [px] of registering a synthetic pair rendered with `seed`, with the
/// registration (for the plot).
pub fn registration_error_px(
    seed: u64,
) -> Result<(f64, geodesic_images::surfaces::Registration), CheckError> {
    let (rows, cols) = (100usize, 120usize);
    let (dx, dy, th, off) = (7.3, -4.6, 0.02, 4e-8);
    let pixel_m = 1.10365e-7;
    let s = RoughSurface::new(40, 3e-7, 11 + seed);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12 + seed);
    let noise = Normal::new(0.0, 5e-9).expect("valid");
    let (cx, cy) = ((cols as f64 - 1.0) / 2.0, (rows as f64 - 1.0) / 2.0);
    let missing =
        |r: usize, c: usize, k: usize| (r * 7919 + c * 104_729 + k * 31).is_multiple_of(53);
    let before: Vec<f64> = (0..rows * cols)
        .map(|i| {
            let (r, c) = (i / cols, i % cols);
            if missing(r, c, 1) {
                f64::NAN
            } else {
                s.at(c as f64, r as f64) + noise.sample(&mut rng)
            }
        })
        .collect();
    let (sn, cs) = f64::sin_cos(th);
    let after: Vec<f64> = (0..rows * cols)
        .map(|i| {
            let (r, c) = (i / cols, i % cols);
            let (qx, qy) = (c as f64 - cx - dx, r as f64 - cy - dy);
            let (px, py) = (cs * qx + sn * qy + cx, -sn * qx + cs * qy + cy);
            let mut v = s.at(px, py) + off + noise.sample(&mut rng);
            if (c as f64 - 40.0).hypot(r as f64 - 60.0) <= 6.0 {
                v += 2e-7;
            }
            if missing(r, c, 2) { f64::NAN } else { v }
        })
        .collect();
    let map = |h: Vec<f64>, points: [[f64; 2]; 2]| HeightMap {
        file: PathBuf::from("<synthetic>"),
        rows,
        cols,
        h,
        pixel_m,
        points,
        valley_below_m: None,
    };
    // the user's picked points, two pixels off the truth as a user's would be
    let reg = register(
        &map(before, [[35.0, 36.0], [60.0, 84.0]]),
        &map(after, [[32.0, 45.0], [58.0, 90.0]]),
    )
    .map_err(|e| CheckError::model("surfaces", format!("surfaces: {e}")))?;
    let err = (reg.shift_m[0] / pixel_m - dx)
        .abs()
        .max((reg.shift_m[1] / pixel_m - dy).abs());
    Ok((err, reg))
}

/// Scenes the tip-trajectory accuracy is validated on (their render seeds): fixed, so that the
/// verdict does not move with the run's seed.
pub const TIPTRACK_SCENES: [u64; 16] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16];

/// Scenes the registration accuracy is validated on (their render seeds).
pub const REGISTRATION_SCENES: [u64; 4] = [1, 2, 3, 4];

impl Check for ImageAnalyses {
    fn name(&self) -> &'static str {
        "image-analyses"
    }

    fn verifies(&self) -> &'static [&'static str] {
        &["FAC-TIPTRACK-ACC", "FAC-SURF-REG"]
    }

    fn run(&self, ctx: &CheckContext) -> Result<Vec<Evidence>, CheckError> {
        use rayon::prelude::*;
        // a method validation on a fixed set of synthetic scenes: the same value whatever the
        // run's seed (each scene's render seed is fixed), the worst scene decides
        let tips: Vec<(f64, geodesic_images::tiptrack::Trajectory)> = TIPTRACK_SCENES
            .par_iter()
            .map(|s| tiptrack_error_px(*s))
            .collect::<Result<_, _>>()?;
        let regs: Vec<(f64, geodesic_images::surfaces::Registration)> = REGISTRATION_SCENES
            .par_iter()
            .map(|s| registration_error_px(*s))
            .collect::<Result<_, _>>()?;
        let worst = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        let tip_errors: Vec<f64> = tips.iter().map(|t| t.0).collect();
        let reg_errors: Vec<f64> = regs.iter().map(|r| r.0).collect();
        let a1 = plots::write(
            &ctx.reports_dir,
            "images/tiptrack-synthetic.svg",
            &geodesic_images::plot::trajectory_svg(
                &tips[0].1,
                "Tip trajectory recovered from synthetic frames, scene 1 (FAC-TIPTRACK-ACC)",
            ),
        )?;
        let a2 = plots::write(
            &ctx.reports_dir,
            "images/surfaces-synthetic.svg",
            &geodesic_images::plot::difference_svg(
                &regs[0].1,
                "Difference map of a synthetic pair, scene 1 (FAC-SURF-REG)",
            ),
        )?;
        let scene_note =
            "synthetic scenes of known truth, fixed render seeds (the run's seed does not enter)";
        Ok(vec![
            Evidence::measured(
                "FAC-TIPTRACK-ACC",
                Quantity::new(worst(&tip_errors), Dim::DIMENSIONLESS),
                Basis::MethodValidation,
                format!(
                    "Method validation: geodesic tiptrack on {} scenes of {FRAMES} frames each rendered from a known trajectory with the thesis's camera (blur 0.8 px, noise 1 gray level, vignetting 5 %): largest |x| or |z| error over every frame of every scene",
                    TIPTRACK_SCENES.len()
                ),
            )
            .with_input("frames", FRAMES)
            .with_input("scenes", serde_json::json!(TIPTRACK_SCENES))
            .with_input("scene_errors_px", serde_json::json!(tip_errors))
            .with_input("scene_set", scene_note)
            .with_input("pixel_m", 2.5e-6)
            .with_artifact(a1),
            Evidence::measured(
                "FAC-SURF-REG",
                Quantity::new(worst(&reg_errors), Dim::DIMENSIONLESS),
                Basis::MethodValidation,
                format!(
                    "Method validation: geodesic surfaces on {} synthetic pairs (shift 7.3, -4.6 px, rotation 0.02 rad, 0.2 um patch, 5 nm noise, 2 % missing, picked points 2 px off): larger shift error of the worst pair",
                    REGISTRATION_SCENES.len()
                ),
            )
            .with_input("scenes", serde_json::json!(REGISTRATION_SCENES))
            .with_input("scene_errors_px", serde_json::json!(reg_errors))
            .with_input("scene_set", scene_note)
            .with_input("rotation_error_rad", regs[0].1.rotation_rad - 0.02)
            .with_input("ks_statistic", regs[0].1.ks_statistic)
            .with_input("changed_area_m2", regs[0].1.changed_area_m2)
            .with_artifact(a2),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A transferred patch pulled the least-squares registration of scene 9910 0.104 pixel off
    /// (beyond FAC-SURF-REG's 0.1 px; the same pair without the patch is 0.006 px off): the
    /// robust refinement (surfaces::TRIM_SIGMAS) leaves it within 0.01 px.
    #[test]
    fn a_transferred_patch_does_not_pull_the_registration() {
        let (e, reg) = registration_error_px(9910).unwrap();
        assert!(e < 0.01, "{e}");
        assert!(reg.trimmed_points > 0);
        assert!((reg.rotation_rad - 0.02).abs() < 1e-3);
    }

    #[test]
    fn the_verdict_does_not_move_with_the_seed() {
        let run = |seed| {
            let ctx = crate::builtin_context(crate::scratch_dir(), 10, seed);
            ImageAnalyses
                .run(&ctx)
                .unwrap()
                .iter()
                .map(|e| match &e.outcome {
                    geodesic_core::Outcome::Measured(q) => q.value,
                    geodesic_core::Outcome::NotVerified(w) => panic!("{w}"),
                })
                .collect::<Vec<f64>>()
        };
        assert_eq!(run(1), run(2));
    }
}
