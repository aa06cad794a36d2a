//! `verify --only ID[,ID...]`: a partial run (issue 37, item 5).
//!
//! The chosen requirements run with what their verdicts depend on, found as the run goes:
//!
//! - their parents (the flow-down sources), up to the top;
//! - the requirements a flow-down assumes (the evidence's `assumes`), with their parents;
//! - the requirements whose check judges a model input the evidence is computed from (the
//!   evidence's `model_inputs` against [`Check::judges`]: a calibration check judges the input every
//!   release row is computed from, and a non-compliant FAC-ADH-CAL marks those rows);
//!
//! until nothing new is needed. The checks that give those rows their evidence run (each once;
//! the release Monte Carlo is shared), the others do not. The matrix holds those rows only, each
//! marked `chosen` or `dependency` with why, and the run information says it was partial
//! ([`geodesic_report::Partial`]). A gate never compares a partial run: `--baseline` with
//! `--only`, or a baseline that is itself partial, is refused (exit 2), so that a partial run can
//! never make the gate say "no regression" for rows it did not run.

use crate::error::Error as CliError;
use geodesic_core::Requirements;
use geodesic_core::check::{Check, Evidence};
use geodesic_core::matrix::{Matrix, Selection as RowSelection};
use std::collections::BTreeMap;

/// The rows of a partial run: the chosen IDs and their dependencies with why.
#[derive(Debug, Clone)]
pub struct Selection {
    /// The IDs given to `--only`, in their order, without repeats.
    pub chosen: Vec<String>,
    /// Every row of the run: `id -> why` (`chosen`, `parent of X`, ...).
    pub rows: BTreeMap<String, String>,
}

impl Selection {
    /// The selection of `--only` (empty: a whole run, `None`). An unknown ID is one line with
    /// the nearest loaded IDs.
    pub fn parse(only: &[String], reqs: &Requirements) -> Result<Option<Selection>, CliError> {
        let ids: Vec<&str> = only
            .iter()
            .flat_map(|s| s.split(','))
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        if only.is_empty() {
            return Ok(None);
        }
        if ids.is_empty() {
            return Err(CliError::usage(
                "--only: name at least one requirement ID, e.g. --only CHG-V,TMS-X-POS",
            ));
        }
        let mut s = Selection {
            chosen: Vec::new(),
            rows: BTreeMap::new(),
        };
        for id in ids {
            let Some(r) = reqs.get(id) else {
                return Err(crate::ids::unknown_id("--only ", id, reqs));
            };
            let id = r.id.to_string();
            if !s.chosen.contains(&id) {
                s.chosen.push(id.clone());
            }
            s.rows.insert(id, "chosen".into());
        }
        for id in s.chosen.clone() {
            s.add_parents(&id, reqs);
        }
        Ok(Some(s))
    }

    /// Adds `id` (if loaded and not yet in) with why, and its parents; whether it was new.
    fn add(&mut self, id: &str, why: String, reqs: &Requirements) -> bool {
        if self.rows.contains_key(id) || reqs.get(id).is_none() {
            return false;
        }
        self.rows.insert(id.to_string(), why);
        self.add_parents(id, reqs);
        true
    }

    fn add_parents(&mut self, id: &str, reqs: &Requirements) {
        if let Some((p, _)) = reqs.get(id).and_then(|r| r.parent.as_ref()) {
            self.add(p.as_str(), format!("parent of {id}"), reqs);
        }
    }

    /// Whether `check` gives one of the selected rows its evidence.
    pub fn wants(&self, check: &dyn Check, reqs: &Requirements) -> bool {
        check
            .verifies()
            .iter()
            .any(|id| self.rows.contains_key(*id))
            || self
                .rows
                .keys()
                .any(|id| reqs.get(id).and_then(|r| r.check.as_deref()) == Some(check.name()))
    }

    /// Adds what the evidence so far shows the selected rows depend on (assumed rows, the rows
    /// judging their model inputs); whether anything was added (then more checks may run).
    pub fn grow(
        &mut self,
        evidence: &[(String, Vec<Evidence>)],
        registry: &[Box<dyn Check>],
        reqs: &Requirements,
    ) -> bool {
        let mut added = false;
        let mut wanted: Vec<(String, String)> = Vec::new();
        for e in evidence.iter().flat_map(|(_, evs)| evs) {
            if !self.rows.contains_key(&e.requirement) {
                continue;
            }
            for a in &e.assumes {
                wanted.push((a.clone(), format!("assumed by {}", e.requirement)));
            }
            for input in &e.model_inputs {
                for c in registry
                    .iter()
                    .filter(|c| c.judges().contains(&input.as_str()))
                {
                    for id in c.verifies() {
                        if *id != e.requirement {
                            wanted.push((
                                id.to_string(),
                                format!("judges the {input} {} is computed from", e.requirement),
                            ));
                        }
                    }
                }
            }
        }
        for (id, why) in wanted {
            added |= self.add(&id, why, reqs);
        }
        added
    }

    /// Keeps the selected rows of `m` only, each marked chosen or dependency.
    pub fn apply(&self, m: &mut Matrix) {
        m.retain_rows(|r| self.rows.contains_key(&r.id));
        for r in &mut m.requirements {
            let why = self.rows.get(&r.id).cloned().unwrap_or_default();
            r.selection = Some(RowSelection {
                role: if self.chosen.contains(&r.id) {
                    "chosen".into()
                } else {
                    "dependency".into()
                },
                why,
            });
        }
    }

    /// The run information's account of the partial run.
    pub fn partial(&self, reqs: &Requirements) -> geodesic_report::Partial {
        let dependencies: Vec<geodesic_report::PartialDependency> = self
            .rows
            .iter()
            .filter(|(id, _)| !self.chosen.contains(id))
            .map(|(id, why)| geodesic_report::PartialDependency {
                id: id.clone(),
                why: why.clone(),
            })
            .collect();
        let not_run = reqs.items.len() - self.rows.len();
        let note = format!(
            "--only {}: {} chosen, {} run as their dependencies{}; {} of {} requirements not run (no verdict on them; a gate refuses a partial run)",
            self.chosen.join(","),
            self.chosen.len(),
            dependencies.len(),
            if dependencies.is_empty() {
                String::new()
            } else {
                format!(
                    " ({})",
                    dependencies
                        .iter()
                        .map(|d| format!("{}: {}", d.id, d.why))
                        .collect::<Vec<_>>()
                        .join("; ")
                )
            },
            not_run,
            reqs.items.len()
        );
        geodesic_report::Partial {
            only: self.chosen.clone(),
            dependencies,
            not_run,
            note,
        }
    }
}

/// Refuses to gate a partial run: `--only` with `--baseline`, or a baseline written by a
/// partial run (its `run.partial`). A baseline that cannot be read is left to the gate's own
/// error.
pub fn refuse_partial_gate(
    only: &[String],
    baseline: Option<&std::path::Path>,
) -> Result<(), CliError> {
    let Some(b) = baseline else {
        return Ok(());
    };
    if !only.is_empty() {
        return Err(CliError::usage(format!(
            "--baseline {} with --only: a partial run is never gated (the rows it does not run would read as unchanged); gate a whole run",
            b.display()
        )));
    }
    let partial = std::fs::read(b)
        .ok()
        .and_then(|t| serde_json::from_slice::<serde_json::Value>(&t).ok())
        .is_some_and(|v| !v["run"]["partial"].is_null());
    if partial {
        return Err(CliError::usage(format!(
            "--baseline {}: a partial run (verify --only): gate against the compliance.json of a whole run",
            b.display()
        )));
    }
    Ok(())
}
