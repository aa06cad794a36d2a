//! geodesic-fit: fit one model of the facility to one measurement record.
//!
//! Estimation on top of the numeric core, the crate `geodesic-numeric` (Levenberg-Marquardt,
//! linear algebra, noise, sampling and posteriors; it knows no dataset, model, effect or
//! scenario), re-exported as [`numeric`] because its types are part of this crate's results
//! ([`numeric::noise::ArNoise`], [`numeric::posterior::Posterior`], ...). The records (datasets,
//! synthetic records, a parameter's fit coordinates, the error type [`FitError`]) are the crate
//! `geodesic-dataset`. Which model explains a record (`diagnose`, the kinds of term outside the
//! catalogue, `discover`) and the identification session that runs fit, diagnose and discover
//! are the crate `geodesic-discover`, on top of this one. The modules use each other without a
//! cycle (`modules_form_no_cycle` below checks the graph):
//! - [`prepare`]: noise per channel, the smooth tip profile, data-driven guesses;
//! - [`identify`]: symmetries, held values, identifiable combinations;
//! - [`estimate`]: data-driven multi-start fits, covariance, profile likelihood;
//! - [`report`]: the fit object of interface.md, with [`outliers`] (outliers and stuck
//!   parameters, said out loud); [`summary`]: a fit's text summary;
//! - [`record`], [`screen`]: the record as the fit sees it, its screening for bad samples;
//! - [`fit`]: the public face of the three above (re-exports only);
//! - [`history`], [`plot`] (the plain data of the plots `geodesic-plot` draws), [`design`];
//! - [`spectral`]: a series' amplitude spectral density judged against a spectral requirement.
//!
//! The engine names no scenario: what differs between scenarios is asked of the scenario's
//! implementation in the facility crate (`geodesic_facility::scenario`).

#![warn(missing_docs)]
pub mod design;
pub mod estimate;
pub mod fit;
pub mod history;
pub mod identify;
pub mod plot;
pub mod prepare;
pub mod record;
pub mod report;
pub mod screen;
pub mod spectral;
pub mod summary;

pub use fit::{FitOptions, FitOutcome, FitReport, Prepared, fit};
pub use geodesic_dataset::FitError;
/// The numeric core (the crate `geodesic-numeric`), whose types appear in this crate's results;
/// the modules here name it `crate::numeric`.
pub use geodesic_numeric as numeric;
pub use report::outliers;

// The records, from geodesic-dataset, imported (privately) at the root so that the modules name
// them `crate::dataset`, `crate::error`, ... Callers import `geodesic_dataset` themselves.
#[cfg(test)]
use geodesic_dataset::synth;
use geodesic_dataset::{coords, dataset, error};

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};
    use std::path::{Path, PathBuf};

    /// The module of a source file: its top-level module.
    fn module_of(rel: &Path) -> Option<String> {
        let top = rel.components().next()?.as_os_str().to_string_lossy();
        let top = top.strip_suffix(".rs").unwrap_or(&top);
        (top != "lib").then(|| top.to_string())
    }

    fn files(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                files(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }

    /// The crate's modules use each other without a cycle (issue 34, item 4: the former
    /// `diagnose -> discover -> kinds -> discover` and `noise <-> residual` loops, and the
    /// engine's own). The graph is read from the source: every `crate::MODULE` a module's files
    /// name, tests included, comments excluded. (The numeric core is a crate of its own,
    /// `geodesic-numeric`, which does not depend on this one: cargo forbids the edge back.)
    #[test]
    fn modules_form_no_cycle() {
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut all = Vec::new();
        files(&src, &mut all);
        let of: Vec<(String, PathBuf)> = all
            .into_iter()
            .filter_map(|p| module_of(p.strip_prefix(&src).unwrap()).map(|m| (m, p)))
            .collect();
        let modules: BTreeSet<String> = of.iter().map(|(m, _)| m.clone()).collect();
        let mut deps: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (m, p) in &of {
            let text = std::fs::read_to_string(p).unwrap();
            for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
                for (i, _) in line.match_indices("crate::") {
                    let rest = &line[i + "crate::".len()..];
                    let word = |s: &str| -> String {
                        s.chars()
                            .take_while(|c| c.is_alphanumeric() || *c == '_')
                            .collect()
                    };
                    let name = word(rest);
                    if modules.contains(&name) && &name != m {
                        deps.entry(m.clone()).or_default().insert(name);
                    }
                }
            }
        }
        assert!(
            deps.get("estimate").is_some_and(|d| d.contains("prepare")),
            "the scan sees the known edge estimate -> prepare: {deps:?}"
        );
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
