//! Identification models of the measurement scenarios (physics.md sections 4 and 5).
//!
//! A model is a composition of named effects ([`effects::Effect`]), each one Rust type in its own
//! file under `effects/`, registered in one list ([`effects::catalogue`]) that fit, diagnose,
//! synth and the reports read. A scenario is a type implementing [`ScenarioSpec`], registered
//! in [`scenario::registry`]. Two scenarios exist:
//!
//! - `tmmf-release` ([`tmmf`]): one-sided release of a pendulum TM mock-up in the TMMF
//!   (thesis ch. 5, physics.md section 4); the measured tip motion drives the TM dynamics.
//! - `rt-retraction` ([`retraction`]): unloaded retraction of the GPRM release tip (thesis ch. 3,
//!   physics.md sections 1 and 5), a linear ODE in charge, plunger and tip.
//!
//! This crate does no I/O: datasets, fitting and reports live in `geodesic-fit`.

pub mod effects;
pub mod model;
pub mod predict;
pub mod profile;
pub mod retraction;
pub mod rk4;
pub mod scenario;
pub mod tmmf;
pub mod trap;

pub use effects::{Effect, EffectKind, ParamSpec, by_name, catalogue};
pub use model::{Model, ModelError};
pub use profile::TipProfile;
pub use scenario::{Scenario, ScenarioSpec};

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};

    /// The crate's modules use each other without a cycle (issue 13, item 7: the former
    /// `effects -> retraction -> model -> tmmf -> effects` loop). The graph is read from the
    /// source: every `crate::MODULE` a module's files name (the effect files count as
    /// `effects`), doc comments excluded.
    #[test]
    fn modules_form_no_cycle() {
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files: Vec<(String, std::path::PathBuf)> = Vec::new();
        for e in std::fs::read_dir(&src).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "rs") {
                let m = p.file_stem().unwrap().to_string_lossy().into_owned();
                files.push((m, p));
            }
        }
        for e in std::fs::read_dir(src.join("effects")).unwrap() {
            files.push(("effects".into(), e.unwrap().path()));
        }
        let modules: BTreeSet<String> = files.iter().map(|(m, _)| m.clone()).collect();
        let mut deps: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (m, p) in &files {
            let text = std::fs::read_to_string(p).unwrap();
            for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
                for (i, _) in line.match_indices("crate::") {
                    let rest = &line[i + "crate::".len()..];
                    let name: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    if modules.contains(&name) && &name != m {
                        deps.entry(m.clone()).or_default().insert(name);
                    }
                }
            }
        }
        assert!(
            deps.get("effects")
                .is_some_and(|d| d.contains("retraction")),
            "the scan sees the known edge effects -> retraction: {deps:?}"
        );
        // depth-first search for a back edge
        fn visit(
            m: &str,
            deps: &BTreeMap<String, BTreeSet<String>>,
            state: &mut BTreeMap<String, u8>,
            path: &mut Vec<String>,
        ) {
            match state.get(m) {
                Some(2) => return,
                Some(1) => panic!("module cycle: {} -> {m}", path.join(" -> ")),
                _ => {}
            }
            state.insert(m.to_string(), 1);
            path.push(m.to_string());
            for d in deps.get(m).into_iter().flatten() {
                visit(d, deps, state, path);
            }
            path.pop();
            state.insert(m.to_string(), 2);
        }
        let mut state = BTreeMap::new();
        for m in &modules {
            visit(m, &deps, &mut state, &mut Vec::new());
        }
    }
}
