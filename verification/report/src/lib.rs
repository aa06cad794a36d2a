//! geodesic-report: writes what `geodesic verify` produces.
//!
//! - [`markdown`]: the compliance report `compliance.md` (matrix, one section per requirement,
//!   trace views).
//! - [`terminal`]: the short table printed on a terminal.
//! - [`vcd`]: the Verification Control Document (Markdown, CSV; also inside the HTML page).
//! - [`html`]: `index.html`, self-contained, with the plots inlined.
//! - [`junit`]: JUnit XML for CI dashboards.
//! - [`baseline`]: change impact against a baseline `compliance.json`.
//! - [`write`]: writing a set of report files whole or not at all (staged, then renamed).
//!
//! The JSON form is the [`geodesic_core::matrix::Matrix`] itself, wrapped in [`Report`].

pub mod baseline;
pub mod html;
pub mod junit;
pub mod markdown;
pub mod terminal;
pub mod vcd;
pub mod write;

use geodesic_core::matrix::Matrix;
use serde::Serialize;

/// How the verification was run (stated in every report).
#[derive(Clone, Debug, Serialize)]
pub struct RunInfo {
    /// geodesic version.
    pub geodesic_version: String,
    /// Requirements directory (or `built-in`).
    pub requirements: String,
    /// Monte Carlo sample count given to the checks [-].
    pub mc_n: usize,
    /// Monte Carlo seed.
    pub seed: u64,
    /// Checks that ran, with the requirements they verify and their wall time [s].
    pub checks: Vec<CheckRun>,
}

/// One check that ran.
#[derive(Clone, Debug, Serialize)]
pub struct CheckRun {
    /// Check name.
    pub name: String,
    /// Requirement IDs it declares.
    pub verifies: Vec<String>,
    /// Wall time [s].
    pub seconds: f64,
}

/// The compliance report: the matrix and how it was produced. Serialises to the JSON of
/// `geodesic verify --json` (`{"requirements": [...], "summary": ..., "run": ...}`).
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Matrix rows, summary and orphan checks (flattened).
    #[serde(flatten)]
    pub matrix: Matrix,
    /// Run information.
    pub run: RunInfo,
}

/// Formats a value for a table: 4 significant digits, `—` when absent.
pub fn fmt_opt(v: Option<f64>) -> String {
    v.map_or_else(|| "—".to_string(), geodesic_core::units::fmt_num)
}

/// Formats a margin as a percentage (`70.0 %`), `—` when absent.
pub fn fmt_margin(m: Option<f64>) -> String {
    m.map_or_else(|| "—".to_string(), |m| format!("{:.1} %", 100.0 * m))
}
