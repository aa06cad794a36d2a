//! Ground-test image analyses of the thesis's facility (appendices "Mitigation of Non Linear
//! Motion of the Ground Release Tip" and "Surfaces matching", ch. 5 "Surface Analysis Before
//! and After the Tests"):
//!
//! * [`tiptrack`]: the release tip's trajectory from high-speed camera frames (its shadow
//!   against a constant light), by threshold crossings with sub-pixel interpolation, repeated
//!   over several gray levels;
//! * [`surfaces`]: the registration of two surface height maps of the same spot (before and
//!   after contact) on their valleys, the difference map and a two-sample Kolmogorov-Smirnov
//!   test of the height distributions;
//! * [`render`]: synthetic frames and height maps from a known truth, which the tests use to
//!   prove the extraction and registration errors.
//!
//! Readers ([`frames`], [`surfaces::HeightMap`]) refuse bad input with a one-line cause naming
//! the file (and line or frame).

pub mod frames;
pub mod plot;
pub mod render;
pub mod surfaces;
pub mod tiptrack;

use geodesic_util::text::one_line;
use std::path::Path;

/// Bad input or an analysis that cannot run: `file[:line]: cause`, one line.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}", at(.file, *.line, .cause))]
pub struct ImageError {
    /// The file (or folder) concerned.
    pub file: String,
    /// 1-based line, 0 when the whole file.
    pub line: usize,
    /// What is wrong.
    pub cause: String,
}

fn at(file: &str, line: usize, cause: &str) -> String {
    let (file, cause) = (one_line(file), one_line(cause));
    if line > 0 {
        format!("{file}:{line}: {cause}")
    } else {
        format!("{file}: {cause}")
    }
}

impl ImageError {
    /// An error about `file` (line 0: the whole file).
    pub fn new(file: &Path, line: usize, cause: impl Into<String>) -> ImageError {
        ImageError {
            file: file.display().to_string(),
            line,
            cause: cause.into(),
        }
    }
}

/// A YAML error of serde-saphyr as an [`ImageError`] with its line.
pub(crate) fn yaml_error(file: &Path, e: &serde_saphyr::Error) -> ImageError {
    let y = geodesic_util::yaml_error(e);
    ImageError::new(file, y.line.unwrap_or(0) as usize, y.cause)
}

/// `v` must be finite and positive.
pub(crate) fn positive(file: &Path, name: &str, v: f64) -> Result<f64, ImageError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ImageError::new(
            file,
            0,
            format!("`{name}` must be a finite positive number, not {v}"),
        ))
    }
}
