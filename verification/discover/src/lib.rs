//! geodesic-discover: model identification, which model explains a record, on top of
//! `geodesic-fit`, which fits one given model to one record. Named for its main job: `discover`
//! (the loop that `diagnose` is one round of) finds the effects a model misses, catalogue
//! effects or kinds of term outside the catalogue.
//!
//! - [`diagnose`]: candidate effects ranked by delta BIC (one round);
//! - [`kinds`]: the kinds of term outside the catalogue (position, velocity, delay, creep,
//!   slip, impulse, vibration) fitted to what a model leaves;
//! - [`discover`]: the discovery loop, its text, and `--scaffold`'s orchestration (a new
//!   effect's code is written by `geodesic-codegen`);
//! - [`session`]: the identification session a front end calls: a dataset, a model and options
//!   in, `fit`, `diagnose` or `discover` run with their outputs, typed results out, progress
//!   through the caller's observer.
//!
//! The modules use each other without a cycle (`modules_form_no_cycle` below checks the graph).
//! The engine names no scenario: what differs between scenarios is asked of the scenario's
//! implementation in the facility crate (`geodesic_facility::scenario`).

#![warn(missing_docs)]
pub mod diagnose;
pub mod discover;
pub mod kinds;
pub mod session;

pub use diagnose::{DiagnoseReport, diagnose};
pub use discover::{DiscoverOptions, DiscoverReport, discover};
pub use session::{Discovered, FitRequest, PosteriorRequest, Session};

// The engine this crate builds on, imported (privately) at the root so that the modules name
// its parts as `crate::estimate`, `crate::dataset`, ... as they did inside `geodesic-fit`.
#[cfg(test)]
use geodesic_dataset::synth;
use geodesic_dataset::{FitError, coords, dataset, error};
use geodesic_fit::{design, estimate, outliers, prepare, record, report, screen, summary};
use geodesic_fit::{history, plot};
use geodesic_numeric as numeric;

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
    /// `diagnose -> discover -> kinds -> discover` loop). The graph is read from the source:
    /// every `crate::MODULE` a module's files name, tests included, comments excluded; the
    /// engine's modules imported at the root (`crate::estimate`, ...) are another crate's and
    /// no node here (cargo forbids `geodesic-fit` an edge back).
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
            deps.get("discover").is_some_and(|d| d.contains("kinds")),
            "the scan sees the known edge discover -> kinds: {deps:?}"
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
