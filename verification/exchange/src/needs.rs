//! The requirement set (and, given a `compliance.json`, the verification status of each
//! requirement) as a sphinx-needs `needs.json` (the format of its `needs` builder, read by its
//! `needs_import` directive and `needs_external_needs`), so that a Sphinx project shows the
//! matrix.
//!
//! One version (`versions.<v>.needs`, `<v>` the tool version, also `current_version`), one need
//! per requirement, keyed by its ID: `id`, `type` `req`, `type_name` `Requirement`, `title`,
//! `content` (the shall statement, as reStructuredText: `|`, `*`, `` ` `` and `\\` escaped),
//! `status` (the VCD status with `--matrix`: `compliant`, `non-compliant`, `not-verified`;
//! else `open`), `tags` (family, method), `links` (the parent: the requirement this one is
//! derived from), `sections` (the family), and the extra options `verdict`, `basis`, `limit`,
//! `value`, `unit`, `margin` (a fraction of the limit), `derivation_margin`, `source`, `method`,
//! `family` (a Sphinx project declares them in `needs_extra_options` to show them). Every value
//! is a string, as sphinx-needs' options are; empty when not known. Deterministic: the only
//! date is `created` (the export's creation time).

use crate::status::StatusSet;
use geodesic_core::Requirements;
use serde_json::{Map, Value, json};

/// The extra options every need carries (declare them in `needs_extra_options`).
pub const EXTRA_OPTIONS: &[&str] = &[
    "verdict",
    "basis",
    "limit",
    "value",
    "unit",
    "margin",
    "derivation_margin",
    "source",
    "method",
    "family",
];

/// What `geodesic export needs --json` prints.
#[derive(Debug, serde::Serialize, schemars::JsonSchema)]
pub struct Summary {
    /// The file written.
    pub out: String,
    /// Needs written (one per requirement).
    pub requirements: usize,
    /// Where the requirements were read from.
    pub source: String,
    /// Whether a compliance matrix gave the status.
    pub with_status: bool,
    /// The version key (`versions.<v>`), the tool's version.
    pub version: String,
}

/// Plain text as reStructuredText, which a need's `content` is: `\\`, `|`, `*` and `` ` ``
/// escaped (`|X'|` would be a substitution reference, `*` emphasis).
fn rst_text(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        if matches!(c, '\\' | '|' | '*' | '`') {
            o.push('\\');
        }
        o.push(c);
    }
    o
}

/// A number as a need option: the shortest decimal that reads back to it; empty for none.
fn num(v: Option<f64>) -> String {
    v.filter(|x| x.is_finite())
        .map_or_else(String::new, |x| format!("{x:?}"))
}

/// The `needs.json` document of `reqs` (with `status` when given), created at `created`
/// (ISO 8601) by tool version `version`.
pub fn export(
    reqs: &Requirements,
    status: Option<&StatusSet>,
    created: &str,
    version: &str,
) -> Value {
    let mut needs = Map::new();
    for r in &reqs.items {
        let st = status.and_then(|s| s.rows.get(r.id.as_str()));
        let s =
            |f: fn(&crate::status::RowStatus) -> Option<String>| st.and_then(f).unwrap_or_default();
        let need = json!({
            "id": r.id.as_str(),
            "type": "req",
            "type_name": "Requirement",
            "title": r.title,
            "content": rst_text(&r.text),
            "status": st.map_or("open".to_string(), |s| s.status.clone()),
            "tags": [r.family.clone(), r.method.to_string()],
            "links": r.parent.iter().map(|(p, _)| p.as_str()).collect::<Vec<_>>(),
            "sections": [r.family.clone()],
            "verdict": s(|s| s.verdict.clone()),
            "basis": s(|s| s.basis.clone()),
            "limit": r.limit.as_ref().map_or(String::new(), |l| l.text.clone()),
            "value": num(st.and_then(|s| s.value)),
            "unit": r.limit.as_ref().map_or(String::new(), |l| l.unit.symbol.clone()),
            "margin": num(st.and_then(|s| s.margin)),
            "derivation_margin": num(r.parent.as_ref().map(|p| p.1)),
            "source": r.source,
            "method": r.method.to_string(),
            "family": r.family,
        });
        needs.insert(r.id.as_str().to_string(), need);
    }
    let n = needs.len();
    json!({
        "created": created,
        "current_version": version,
        "project": "geodesic",
        "versions": {
            version: {
                "created": created,
                "needs": needs,
                "needs_amount": n,
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn reqs() -> Requirements {
        Requirements::load_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../requirements"))
            .unwrap()
    }

    #[test]
    fn one_need_per_requirement_with_its_parent_link() {
        let reqs = reqs();
        let doc = export(&reqs, None, "2026-01-01T00:00:00Z", "0.1.0");
        assert_eq!(doc["current_version"], "0.1.0");
        let needs = doc["versions"]["0.1.0"]["needs"].as_object().unwrap();
        assert_eq!(needs.len(), reqs.items.len());
        assert_eq!(doc["versions"]["0.1.0"]["needs_amount"], reqs.items.len());
        let d = &needs["REL-DFACS-VEL"];
        assert_eq!(d["id"], "REL-DFACS-VEL");
        assert_eq!(d["type"], "req");
        assert_eq!(d["links"], json!(["REL-GPRM-VEL"]));
        assert_eq!(d["derivation_margin"], "1.5");
        assert_eq!(d["status"], "open");
        assert!(d["content"].as_str().unwrap().contains("shall"));
        for (id, n) in needs {
            assert_eq!(&n["id"], id);
            for o in EXTRA_OPTIONS {
                assert!(n[*o].is_string(), "{id}: {o}");
            }
        }
        // deterministic
        assert_eq!(doc, export(&reqs, None, "2026-01-01T00:00:00Z", "0.1.0"));
        // content is reStructuredText: |X'| is no substitution
        assert_eq!(rst_text("|X'| < 5 *um*"), "\\|X'\\| < 5 \\*um\\*");
        assert!(
            needs
                .values()
                .any(|n| n["content"].as_str().unwrap().contains("\\|"))
        );
    }
}
