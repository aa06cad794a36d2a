//! `discover --scaffold NAME` (issue 36): a new effect written into the catalogue from the
//! leading term outside the catalogue of a discover report. The name and the repository are
//! checked before any computation ([`preflight`]); after the discovery, [`scaffold`] derives
//! the effect and the conditions of its hiding test from the record, writes every file or none,
//! and says what it wrote.

use std::path::Path;

use super::DiscoverReport;
use crate::prepare::Prepared;
use geodesic_codegen::{self as scaffold, Conditions, Scaffold, lit};

/// What [`scaffold`] wrote: lines for the terminal and the `scaffold` object of `--json`.
pub struct Scaffolded {
    /// The lines for the terminal (each ends with a newline).
    pub text: String,
    /// The `scaffold` object of the discover JSON.
    pub json: ScaffoldDoc,
}

/// The `scaffold` object of `discover --scaffold NAME --json` (docs/outputs.md). Fields in byte
/// order: the document prints as the `json!` object it replaced did.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct ScaffoldDoc {
    /// The term's delta BIC (its joint fit against the model without it).
    pub delta_bic: f64,
    /// The files written or edited, relative to the repository's root.
    pub files: Vec<String>,
    /// The term's kind (`position`, `velocity`, `delay`, `creep`, `slip`, `impulse`,
    /// `vibration`).
    pub kind: String,
    /// The new effect's name.
    pub name: String,
    /// Its parameters by `effect.param`.
    pub params: std::collections::BTreeMap<String, ScaffoldParam>,
    /// The scenario of the record (`tmmf-release`, `rt-retraction`).
    pub scenario: String,
}

/// A parameter of [`ScaffoldDoc`], in SI units (`unit`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct ScaffoldParam {
    /// Lower end of its range [unit].
    pub lower: f64,
    /// Its unit.
    pub unit: String,
    /// Upper end of its range [unit].
    pub upper: f64,
    /// Its starting (nominal) value, the fitted term's [unit].
    pub value: f64,
}

/// Before any computation: the name (snake_case, not in the catalogue, no file of that name)
/// and `root`, the repository's root (its catalogue and hiding tests).
pub fn preflight(name: &str, root: &Path) -> Result<(), String> {
    scaffold::check_root(root)?;
    scaffold::check_name(name, Some(&root.join(scaffold::EFFECTS_DIR)))
}

/// After the discovery of `dataset` (prepared as `prep`): the effect `name` from `report`'s
/// leading term outside the catalogue, its files written under `root` (every one or none),
/// formatted by rustfmt. Refused when the record is explained or holds no such term.
pub fn scaffold(
    name: &str,
    root: &Path,
    dataset: &Path,
    prep: &Prepared,
    report: &DiscoverReport,
) -> Result<Scaffolded, String> {
    if report.explained {
        return Err(format!(
            "{} is explained by the catalogue ({}): no term outside the catalogue to scaffold",
            dataset.display(),
            report.reason
        ));
    }
    if report.residual.terms.is_empty() {
        return Err(format!(
            "discover found no term outside the catalogue in {}: nothing to scaffold",
            dataset.display()
        ));
    }
    let record = dataset.display().to_string();
    let s = Scaffold::from_terms(
        name,
        prep.dataset.scenario,
        &terms(&report.residual.terms),
        &record,
        &report.residual.indistinguishable,
        &scaffold::today(),
        conditions(prep, report),
    )?;
    let mut edits = s.edits(root)?;
    for (_, text) in edits.iter_mut() {
        *text = scaffold::rustfmt(text, root)?;
    }
    scaffold::write_all(&edits)?;
    let files: Vec<String> = edits
        .iter()
        .map(|(p, _)| p.strip_prefix(root).unwrap_or(p).display().to_string())
        .collect();
    let baseline = report
        .rounds
        .first()
        .map(|r| r.effects.join(","))
        .unwrap_or_default();
    Ok(Scaffolded {
        text: text(name, &s, &files, &record, &baseline),
        json: json(name, &s, &files),
    })
}

/// The conditions of the new effect's hiding test: the record's sampling (at most 20 000
/// samples after the trigger), its length, the fitted channel's noise, the scenario's first
/// known constant (the TM mass, the initial voltage) as loaded, and the tip's profile.
fn conditions(prep: &Prepared, report: &DiscoverReport) -> Conditions {
    let ds = &prep.dataset;
    let t = &ds.t;
    let mut dts: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    dts.sort_by(f64::total_cmp);
    let dt = dts.get(dts.len() / 2).copied().unwrap_or(1e-5);
    let post_s = t.last().copied().unwrap_or(0.0).max(dt);
    let channel = ds.scenario.fitted_channel();
    let noise = report
        .final_fit
        .noise
        .get(channel)
        .or_else(|| ds.noise.get(channel))
        .copied()
        .filter(|v| v.is_finite() && *v > 0.0)
        .unwrap_or(1e-9);
    let known = ds
        .scenario
        .required_known()
        .first()
        .map_or(("", 0.0), |&k| (k, ds.known.get(k).copied().unwrap_or(0.0)));
    Conditions {
        fs_hz: (1.0 / dt).min(20_000.0 / post_s),
        post_s,
        known,
        noise,
        jerk_m_s3: prep.inputs.profile.jerk_m_s3,
        v_m_s: prep.inputs.profile.v_m_s,
    }
}

/// What was written and what to run next, for the terminal.
fn text(name: &str, s: &Scaffold, files: &[String], record: &str, baseline: &str) -> String {
    let mut text = format!(
        "scaffold: wrote the effect `{name}` ({}: {}) from the {} term [{}] (delta BIC {:.1}):\n",
        s.scenario.name(),
        s.law(),
        if s.passed_over.is_some() {
            "runner-up"
        } else {
            "leading"
        },
        s.kind,
        s.delta_bic
    );
    if let Some(why) = &s.passed_over {
        text.push_str(&format!(
            "  the leading term was passed over ({why}); `{}` is a term the record could not tell from it\n",
            s.kind
        ));
    }
    for p in &s.params {
        text.push_str(&format!(
            "  {name}.{} = {} {} (range {} .. {})\n",
            p.name,
            lit(p.nominal),
            p.unit,
            lit(p.lower),
            lit(p.upper)
        ));
    }
    for f in files {
        text.push_str(&format!("  wrote {f}\n"));
    }
    text.push_str(&format!(
        "next: cargo build --release -p geodesic; geodesic discover {record} --effects {baseline}; cargo test --release -p geodesic-discover --test hide_each hidden_{name}\n"
    ));
    text
}

/// The `scaffold` object of the discover JSON (docs/outputs.md): the effect, its kind and
/// scenario, the term's delta BIC, its parameters with units and ranges, the files written.
fn json(name: &str, s: &Scaffold, files: &[String]) -> ScaffoldDoc {
    let params = s
        .params
        .iter()
        .map(|p| {
            let doc = ScaffoldParam {
                lower: p.lower,
                unit: p.unit.to_string(),
                upper: p.upper,
                value: p.nominal,
            };
            (format!("{name}.{}", p.name), doc)
        })
        .collect();
    ScaffoldDoc {
        delta_bic: s.delta_bic,
        files: files.to_vec(),
        kind: s.kind.clone(),
        name: name.to_string(),
        params,
        scenario: s.scenario.name().to_string(),
    }
}

/// Discover's terms as the code generator reads them (plain data).
fn terms(fitted: &[crate::kinds::KindFit]) -> Vec<geodesic_codegen::Term> {
    fitted
        .iter()
        .map(|k| geodesic_codegen::Term {
            kind: k.kind.clone(),
            term: k.term.clone(),
            parameter: k
                .parameter
                .as_ref()
                .map(|p| geodesic_codegen::TermParameter {
                    name: p.name.clone(),
                    value: p.value,
                    unit: p.unit.clone(),
                }),
            coefs: k.coefs.clone(),
            delta_bic: k.delta_bic,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::{KindFit, TermParameter};
    use geodesic_facility::Scenario;

    /// The typed `scaffold` object prints as the `json!` object it replaced (keys sorted).
    #[test]
    fn the_scaffold_document_prints_as_the_sorted_object() {
        let k = KindFit {
            kind: "velocity".into(),
            state: String::new(),
            term: "dx/dt".into(),
            coefficient: -100.0,
            sigma: 0.4,
            coefficient_unit: "1/s".into(),
            parameter: Some(TermParameter {
                name: "gamma".into(),
                value: 100.0,
                unit: "1/s".into(),
            }),
            delta_chi2: 9e4,
            delta_bic: -87068.8,
            shape: Vec::new(),
            coefs: vec![-100.0],
            scan: 0.0,
        };
        let conditions = Conditions {
            fs_hz: 1e5,
            post_s: 0.02,
            known: ("m", 0.089),
            noise: 8e-10,
            jerk_m_s3: 6000.0,
            v_m_s: 3e-3,
        };
        let s = Scaffold::from_term(
            "visc",
            Scenario::TmmfRelease,
            &terms(std::slice::from_ref(&k))[0],
            "r.yaml",
            &[],
            "2026-11-28",
            conditions,
        )
        .expect("scaffold");
        let files = vec!["a.rs".to_string(), "b.rs".to_string()];
        let params: serde_json::Map<String, serde_json::Value> = s
            .params
            .iter()
            .map(|p| {
                (
                    format!("visc.{}", p.name),
                    serde_json::json!({"value": p.nominal, "unit": p.unit, "lower": p.lower, "upper": p.upper}),
                )
            })
            .collect();
        let old = serde_json::json!({
            "name": "visc",
            "kind": s.kind,
            "scenario": s.scenario.name(),
            "delta_bic": s.delta_bic,
            "params": params,
            "files": files,
        });
        let doc = json("visc", &s, &files);
        assert_eq!(
            serde_json::to_string(&doc).unwrap(),
            serde_json::to_string(&old).unwrap()
        );
        let back: ScaffoldDoc = serde_json::from_value(old).expect("reads back");
        assert_eq!(back, doc);
    }
}
