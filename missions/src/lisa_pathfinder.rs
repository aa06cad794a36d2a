//! The root mission: LISA Pathfinder's test-mass release (`mission.yaml` at the repository's
//! root). Its checks are `geodesic-checks`'s registry; its fidelity table compares geodesic's
//! figures with the thesis's and shares the checks' release Monte Carlo.

use geodesic_checks::release::SharedMonteCarlo;
use geodesic_verify::{Mission, Session};

/// The descriptor, built into the program.
pub const DESCRIPTOR: &str = include_str!("../../mission.yaml");

/// The built-in copies of the mission's requirement and document files (paths relative to the
/// descriptor).
const FILES: &[(&str, &str)] = &[
    (
        "requirements/capture.yaml",
        include_str!("../../requirements/capture.yaml"),
    ),
    (
        "requirements/charge.yaml",
        include_str!("../../requirements/charge.yaml"),
    ),
    (
        "requirements/facility.yaml",
        include_str!("../../requirements/facility.yaml"),
    ),
    (
        "requirements/performance.yaml",
        include_str!("../../requirements/performance.yaml"),
    ),
    (
        "requirements/plunger.yaml",
        include_str!("../../requirements/plunger.yaml"),
    ),
    (
        "requirements/release.yaml",
        include_str!("../../requirements/release.yaml"),
    ),
    (
        "requirements/tm-state.yaml",
        include_str!("../../requirements/tm-state.yaml"),
    ),
    (
        "verification/document.yaml",
        include_str!("../../verification/document.yaml"),
    ),
];

// the built-in copy of each input the descriptor declares, by its name there
use geodesic_checks::INPUT_COPIES;

fn session() -> Session {
    let mc = SharedMonteCarlo::new();
    let checks = geodesic_checks::registry_with(mc.clone());
    Session {
        checks,
        reference: Some(Box::new(move |ctx| {
            // the fidelity table compares the release with the thesis: only for a requirement
            // set that has the release family
            if ctx.requirements.items.iter().any(|r| r.family == "release") {
                geodesic_checks::fidelity::table(&mc, ctx)
            } else {
                Ok(Vec::new())
            }
        })),
    }
}

/// The mission, found in the current directory (the repository's root) or built in.
pub fn mission() -> Mission {
    let mut m = Mission::new(DESCRIPTOR, "mission.yaml", ".", session)
        .expect("the built-in mission.yaml is valid (tested)")
        .series(geodesic_checks::spectral::validate_series)
        .validate("budget", |f| {
            let b = geodesic_release::budget::Budget::from_yaml(&f.text, &f.label)
                .map_err(|e| e.to_string())?;
            if !f.label.starts_with("<built-in>") {
                // its adhesion_from (a campaign result) must load before anything runs
                geodesic_release::population::resolve(b, Some(std::path::Path::new(&f.label)))?;
            }
            crate::ranges::question(&f.text, &f.label, crate::ranges::of("budget"))
        })
        .validate("capture", |f| {
            geodesic_capture::CaptureInputs::from_yaml_str(&f.text, &f.label)
                .map_err(|e| e.to_string())?;
            crate::ranges::question(&f.text, &f.label, crate::ranges::of("capture"))
        })
        .validate("charge", |f| {
            geodesic_charge::ChargeFile::from_yaml_str(&f.text, &f.label)
                .map_err(|e| e.to_string())?;
            crate::ranges::question(&f.text, &f.label, crate::ranges::of("charge"))
        });
    for (p, t) in FILES {
        m = m.builtin(p, t);
    }
    let declared: Vec<(String, String)> = m
        .spec
        .inputs
        .iter()
        .map(|i| (i.name.clone(), i.path.clone()))
        .collect();
    for (name, path) in declared {
        let copy = INPUT_COPIES.iter().find(|(n, _)| *n == name);
        let (_, text) = copy.unwrap_or_else(|| panic!("no built-in copy of input `{name}`"));
        m = m.builtin(&path, text);
    }
    m
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_declared_input_has_a_built_in_copy_and_ranges() {
        let m = super::mission();
        assert_eq!(m.spec.inputs.len(), super::INPUT_COPIES.len());
        for i in &m.spec.inputs {
            assert!(m.builtin.contains_key(&i.path), "{}", i.name);
            assert!(!crate::ranges::of(&i.name).is_empty(), "{}", i.name);
        }
    }

    #[test]
    fn the_monte_carlo_options_are_declared_with_the_models_cap() {
        let m = super::mission();
        let n = m.spec.options.iter().find(|o| o.key() == "mc_n").unwrap();
        assert_eq!(
            n.max,
            Some(geodesic_release::montecarlo::MAX_N as u64),
            "mission.yaml's mc-n max must be the release model's MAX_N"
        );
        assert_eq!((n.default, n.min), (100_000, 1));
        let seed = m.spec.options.iter().find(|o| o.key() == "seed").unwrap();
        assert_eq!(seed.default, 1);
        let o = m.spec.run_options(&Default::default()).unwrap();
        assert_eq!(
            o.lines(),
            vec![("Monte Carlo", "N = 100000, seed = 1".to_string())]
        );
        let big = [("mc-n".to_string(), 10_000_001)].into_iter().collect();
        assert_eq!(
            m.spec.run_options(&big).unwrap_err(),
            "--mc-n 10000001: must be between 1 and 10000000"
        );
    }

    #[test]
    fn every_requirement_file_is_built_in() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../requirements");
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".yaml"))
            .collect();
        on_disk.sort();
        let m = super::mission();
        let built: Vec<String> = m
            .builtin_requirements()
            .iter()
            .map(|(n, _)| n.to_string())
            .collect();
        assert_eq!(on_disk, built);
    }
}
