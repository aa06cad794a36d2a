//! geodesic-checks: the one registry of the root mission's verification activities (the
//! Drag-Free CubeSat's are in its own crate, `missions/drag-free-cubesat/`), and the generic
//! spectral check every mission may name.
//!
//! Each family module (`release`, `capture`, `charge`, `tm_state`, `facility`) exposes
//! `checks()`; [`registry`] lists them all, and `geodesic verify`, the reports and the tests
//! read that list. Adding a check is one type in its family module and one line there.
//!
//! The tests that trace to requirements (`geodesic_core::verifies!`) are not listed here: the
//! compliance matrix reads them from a recorded test run (`cargo xtask test`, see
//! `geodesic_core::testrun`).

pub mod capture;
pub mod charge;
pub mod facility;
pub mod fidelity;
pub mod images;
pub mod plots;
pub mod plunger;
pub mod release;
pub mod sensitivity;
pub mod spectral;
pub mod tipradius;
pub mod tm_state;

use geodesic_core::check::{InputFile, Inputs, RunOptions};
use geodesic_core::{Check, CheckContext, Requirements};
use std::path::PathBuf;
use std::sync::Arc;

/// The root mission's inputs as their built-in copies (labelled `<built-in>/PATH`), for tests
/// and examples: their names, words and paths are the descriptor's (`mission.yaml` `inputs:`,
/// read at run time from the mission the tests run in, [`geodesic_core::trace::mission_root`]).
pub fn builtin_inputs() -> Inputs {
    let root = geodesic_core::trace::mission_root().expect("a mission.yaml above the tests");
    let label = root.join("mission.yaml").display().to_string();
    let text = std::fs::read_to_string(root.join("mission.yaml")).expect("a readable mission.yaml");
    let spec =
        geodesic_verify::MissionSpec::from_yaml(&text, &label).expect("a valid mission.yaml");
    let mut inputs = Inputs::default();
    for i in &spec.inputs {
        if let Some((_, copy)) = INPUT_COPIES.iter().find(|(n, _)| *n == i.name) {
            inputs.insert(
                &i.name,
                &i.words,
                InputFile::new(format!("<built-in>/{}", i.path), *copy),
            );
        }
    }
    inputs
}

/// The built-in copy of each input the root mission's descriptor declares, by its name there
/// (the model crates embed their own files; the descriptor gives the path and the words).
pub const INPUT_COPIES: &[(&str, &str)] = &[
    ("budget", geodesic_release::budget::DEFAULT_BUDGET_YAML),
    ("capture", geodesic_capture::DEFAULT_CAPTURE_YAML),
    ("charge", geodesic_charge::DEFAULT_CHARGE_YAML),
];

/// A check context on the repository's embedded requirements and built-in model inputs, for
/// tests and examples, with the root mission's run options (its descriptor's `options:`) set
/// to `mc_n` Monte Carlo draws [-] and `seed`.
pub fn builtin_context(reports_dir: PathBuf, mc_n: usize, seed: u64) -> CheckContext {
    CheckContext {
        requirements: Arc::new(geodesic_core::trace::requirements().clone()),
        inputs: Arc::new(builtin_inputs()),
        reports_dir,
        options: builtin_options(mc_n, seed),
        confidence: DEFAULT_CONFIDENCE,
        quiet: true,
    }
}

/// The root mission's run options (the descriptor's `options:`, read at run time as
/// [`builtin_inputs`] reads its inputs) with `mc_n` draws [-] and `seed`, for tests and
/// examples.
pub fn builtin_options(mc_n: usize, seed: u64) -> RunOptions {
    let root = geodesic_core::trace::mission_root().expect("a mission.yaml above the tests");
    let label = root.join("mission.yaml").display().to_string();
    let text = std::fs::read_to_string(root.join("mission.yaml")).expect("a readable mission.yaml");
    let spec =
        geodesic_verify::MissionSpec::from_yaml(&text, &label).expect("a valid mission.yaml");
    let given = [
        ("mc-n".to_string(), mc_n as u64),
        ("seed".to_string(), seed),
    ]
    .into_iter()
    .collect();
    spec.run_options(&given)
        .expect("mc-n and seed declared, in range")
}

/// The confidence of the bounds a sampled verdict is decided by, unless `verify --confidence`
/// says otherwise [-].
pub const DEFAULT_CONFIDENCE: f64 = 0.95;

/// A check context for a loaded requirement set, model inputs and run options (a mission's
/// declared `options:`; [`RunOptions::default`] for none).
pub fn context(
    requirements: Requirements,
    inputs: Inputs,
    reports_dir: PathBuf,
    options: RunOptions,
    confidence: f64,
    quiet: bool,
) -> CheckContext {
    CheckContext {
        requirements: Arc::new(requirements),
        inputs: Arc::new(inputs),
        reports_dir,
        options,
        confidence,
        quiet,
    }
}

/// Every check of the root mission, in a stable order (other missions' checks are their own
/// crates').
pub fn registry() -> Vec<Box<dyn Check>> {
    registry_with(release::SharedMonteCarlo::new())
}

/// The root mission's checks (LISA Pathfinder's release and the generic spectral check), with
/// a given release Monte Carlo cache (shared by the checks that need its velocities, and by
/// [`fidelity::table`], so that `geodesic verify` runs it once).
pub fn registry_with(mc: std::sync::Arc<release::SharedMonteCarlo>) -> Vec<Box<dyn Check>> {
    let mut all: Vec<Box<dyn Check>> = Vec::new();
    all.extend(release::checks_with(mc.clone()));
    all.extend(capture::checks_with(Some(release::vz_source(mc.clone()))));
    all.extend(charge::checks());
    all.extend(tm_state::checks_with(Some(release::vz_source(mc.clone()))));
    all.extend(facility::checks());
    all.extend(images::checks());
    all.extend(plunger::checks_with(Some(release::vz_source(mc))));
    all.extend(tipradius::checks());
    all.extend(sensitivity::checks());
    all.extend(spectral::checks());
    all
}

/// Names of the registered checks.
pub fn check_names() -> Vec<&'static str> {
    registry().iter().map(|c| c.name()).collect()
}

/// A scratch reports directory of its own for the unit test running on this thread (removed when
/// the test's thread ends), so that tests running in parallel never share a path.
#[cfg(test)]
pub(crate) fn scratch_dir() -> PathBuf {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::Builder::new()
            .prefix("geodesic-checks-")
            .tempdir()
            .expect("a temporary directory");
    }
    DIR.with(|d| d.path().to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_names_are_unique() {
        let mut n = check_names();
        let len = n.len();
        n.sort_unstable();
        n.dedup();
        assert_eq!(n.len(), len);
    }
}
