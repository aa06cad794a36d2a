//! Requirement YAML in geodesic's format (`requirements/*.yaml`, loaded by
//! `geodesic_core::Requirements`), written from imported requirements.
//!
//! Every string is written as a double-quoted scalar with JSON escaping (JSON strings are YAML
//! 1.2 double-quoted scalars), so any text survives; numbers in Rust's shortest round-trip form.

use crate::reqif::{ImportedFamily, ImportedRequirement};

fn q(s: &str) -> String {
    serde_json::to_string(s).expect("a string always serialises")
}

fn entry(o: &mut String, r: &ImportedRequirement) {
    o.push_str(&format!("  - id: {}\n", q(&r.id)));
    o.push_str(&format!("    title: {}\n", q(&r.title)));
    o.push_str(&format!("    text: {}\n", q(&r.text)));
    o.push_str(&format!("    source: {}\n", q(&r.source)));
    if r.limit.is_empty() {
        // qualitative: no limit, nor the dimension tied to it
        if !r.quantity.is_empty() {
            o.push_str(&format!("    quantity: {}\n", q(&r.quantity)));
        }
    } else {
        o.push_str(&format!("    quantity: {}\n", q(&r.quantity)));
        o.push_str(&format!("    dimension: {}\n", q(&r.dimension)));
        o.push_str(&format!("    limit: {}\n", q(&r.limit)));
    }
    if let Some(p) = &r.probability {
        o.push_str(&format!("    probability: {}\n", q(p)));
    }
    if let Some((band, shape)) = &r.spectrum {
        o.push_str(&format!(
            "    spectrum: {{band: {}, shape: {}}}\n",
            q(band),
            q(shape)
        ));
    }
    if let Some(l) = &r.level {
        o.push_str(&format!("    level: {}\n", q(l)));
    }
    if let Some(st) = &r.stage {
        o.push_str(&format!("    stage: {}\n", q(st)));
    }
    o.push_str(&format!("    method: {}\n", r.method));
    o.push_str(&format!("    activity: {}\n", q(&r.activity)));
    if let Some(c) = &r.check {
        o.push_str(&format!("    check: {}\n", q(c)));
    }
    if let Some((id, margin)) = &r.parent {
        o.push_str(&format!(
            "    parent: {{id: {}, margin: {margin:?}}}\n",
            q(id)
        ));
    }
    if let Some(n) = &r.note {
        o.push_str(&format!("    note: {}\n", q(n)));
    }
}

/// One family file: a comment naming where it came from, `family`, `description` and the
/// requirements. Returns the text and, for each requirement, its first and last line
/// (1-based), so that a load error in the YAML can be traced back to the requirement.
pub fn family_file(fam: &ImportedFamily, comment: &str) -> (String, Vec<(u64, u64)>) {
    let mut o = String::new();
    for l in comment.lines() {
        o.push_str("# ");
        o.push_str(l);
        o.push('\n');
    }
    o.push_str(&format!("family: {}\n", q(&fam.family)));
    if let Some(d) = fam.description.as_ref().filter(|d| !d.trim().is_empty()) {
        o.push_str(&format!("description: {}\n", q(d)));
    }
    o.push_str("requirements:\n");
    let mut spans = Vec::new();
    // lines so far, counted once per entry (not over the whole text each time)
    let mut lines = o.lines().count() as u64;
    for r in &fam.requirements {
        let start = lines + 1;
        let at = o.len();
        entry(&mut o, r);
        lines += o[at..].lines().count() as u64;
        spans.push((start, lines));
    }
    (o, spans)
}
