//! Model inputs questioned (issue 49): every numeric parameter of a model input file states its
//! **pedigree** (measured, calibrated, cited, design value, assumed) with a reference and, where
//! it has one, an uncertainty, and lies within a **plausible range** that its mission states
//! with a physical argument; a value outside it is refused (one line `file:line: cause` naming
//! the range and the unit expected) unless the file overrides the range with a reason.
//!
//! The pedigree is written in the input file itself, in a `pedigree:` section keyed by the
//! parameter's path (`tm_mass_kg`, `capacitances.c_eh_f`, `materials.*.yield_mpa`; `*` stands
//! for one path segment):
//!
//! ```yaml
//! pedigree:
//!   mass_kg: {kind: cited, ref: "the design report, sec. 2", uncertainty: "+-0.01 kg"}
//!   spring.*: {kind: calibrated, ref: "fitted to the qualification model's test"}
//!   preload_n: {kind: design, ref: "...", range: {min: 0.1, max: 3.0, reason: "a stiffer spring under test"}}
//! ```
//!
//! The ranges are the mission's ([`Range`], in its code, each with its unit and argument): the
//! file cannot widen one silently, only with a `range:` and a `reason:` that every report
//! shows. [`parameters`] flattens any input file into `path -> value` for the gate, which
//! compares them with the baseline's ("input changed, needs review").
//!
//! A parameter is a number, a list of numbers, or a distribution (`{fixed: V}`,
//! `{uniform: {min, max}}`, `{normal: {mean, sd | rel_sd, min, max, clip_sd}}`); the values a
//! distribution is checked by are its nominal value and the ends of what it draws (its bounds,
//! or its mean +- `clip_sd` (else 3) standard deviations where it has none).

use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use serde_saphyr::Spanned;
use std::collections::BTreeMap;

/// Where a parameter's value comes from.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// Measured on the hardware (or its qualification model).
    Measured,
    /// Fitted to a measurement (a model parameter calibrated on a campaign).
    Calibrated,
    /// Taken from a cited source (a report, a handbook, an FE analysis).
    Cited,
    /// A design value: what the design states, not yet measured.
    Design,
    /// Assumed: no measurement, calibration or source behind it.
    Assumed,
}

impl Kind {
    /// In words.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Measured => "measured",
            Kind::Calibrated => "calibrated",
            Kind::Cited => "cited",
            Kind::Design => "design",
            Kind::Assumed => "assumed",
        }
    }
}

/// A plausible range the mission states for a parameter (SI or the unit in its key).
#[derive(Clone, Copy, Debug)]
pub struct Range {
    /// The parameter's path; `*` matches one segment (`materials.*.yield_mpa`).
    pub path: &'static str,
    /// The unit of the values (`kg`, `F`, `MPa`, `-`).
    pub unit: &'static str,
    /// Smallest plausible value.
    pub min: f64,
    /// Largest plausible value.
    pub max: f64,
    /// Why: the physical argument and its source.
    pub why: &'static str,
}

/// A range the input file sets in place of the mission's, with its reason.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RangeOverride {
    /// Smallest accepted value.
    pub min: f64,
    /// Largest accepted value.
    pub max: f64,
    /// Why the mission's range does not apply (required, non-empty).
    pub reason: String,
}

/// One parameter's pedigree as its file states it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Measured, calibrated, cited, design or assumed.
    pub kind: Kind,
    /// Where it comes from (a report's section, a document, a campaign).
    #[serde(rename = "ref")]
    pub reference: String,
    /// Its uncertainty in words with its unit (`+-0.01 kg`), where it has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<String>,
    /// A range in place of the mission's, with a reason.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<RangeOverride>,
}

/// One parameter of an input file, questioned.
#[derive(Clone, Debug, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Param {
    /// Its value as written (a distribution in flow style).
    pub value: String,
    /// The line it is on.
    pub line: u64,
    /// Its pedigree.
    pub pedigree: Entry,
    /// The range it was judged against: `[min, max]` and the unit.
    pub range: (f64, f64, String),
}

/// A YAML node with the line of every value.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    /// A mapping, in file order: (key, line of the value, value).
    Map(Vec<(String, u64, Node)>),
    /// A sequence: (line, value).
    Seq(Vec<(u64, Node)>),
    /// A number.
    Num(f64),
    /// A string.
    Str(String),
    /// A boolean.
    Bool(bool),
    /// Null.
    Null,
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Node, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Node;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a YAML value")
            }
            fn visit_bool<E: de::Error>(self, v: bool) -> Result<Node, E> {
                Ok(Node::Bool(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Node, E> {
                Ok(Node::Num(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Node, E> {
                Ok(Node::Num(v as f64))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Node, E> {
                Ok(Node::Num(v))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Node, E> {
                Ok(Node::Str(v.to_string()))
            }
            fn visit_string<E: de::Error>(self, v: String) -> Result<Node, E> {
                Ok(Node::Str(v))
            }
            fn visit_unit<E: de::Error>(self) -> Result<Node, E> {
                Ok(Node::Null)
            }
            fn visit_none<E: de::Error>(self) -> Result<Node, E> {
                Ok(Node::Null)
            }
            fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Node, D::Error> {
                Node::deserialize(d)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<Node, A::Error> {
                let mut v = Vec::new();
                while let Some(s) = a.next_element::<Spanned<Node>>()? {
                    v.push((s.referenced.line(), s.value));
                }
                Ok(Node::Seq(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> Result<Node, A::Error> {
                let mut v = Vec::new();
                while let Some((k, s)) = a.next_entry::<String, Spanned<Node>>()? {
                    v.push((k, s.referenced.line(), s.value));
                }
                Ok(Node::Map(v))
            }
        }
        d.deserialize_any(V)
    }
}

impl Node {
    fn get(&self, key: &str) -> Option<&Node> {
        match self {
            Node::Map(m) => m.iter().find(|(k, _, _)| k == key).map(|(_, _, v)| v),
            _ => None,
        }
    }

    fn num(&self, key: &str) -> Option<f64> {
        match self.get(key) {
            Some(Node::Num(x)) => Some(*x),
            _ => None,
        }
    }

    /// The node in flow style, numbers as written by Rust (`{normal: {mean: 371.2, ...}}`).
    pub fn flow(&self) -> String {
        match self {
            Node::Map(m) => format!(
                "{{{}}}",
                m.iter()
                    .map(|(k, _, v)| format!("{k}: {}", v.flow()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Node::Seq(s) => format!(
                "[{}]",
                s.iter()
                    .map(|(_, v)| v.flow())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Node::Num(x) => format!("{x:?}"),
            Node::Str(s) => format!("{s:?}"),
            Node::Bool(b) => b.to_string(),
            Node::Null => "null".into(),
        }
    }

    /// The values a parameter node is judged by; `None` when the node is no parameter (a
    /// string, a mapping of other parameters).
    fn values(&self) -> Option<Vec<f64>> {
        match self {
            Node::Num(x) => Some(vec![*x]),
            Node::Seq(s) if !s.is_empty() && s.iter().all(|(_, v)| matches!(v, Node::Num(_))) => {
                Some(
                    s.iter()
                        .filter_map(|(_, v)| match v {
                            Node::Num(x) => Some(*x),
                            _ => None,
                        })
                        .collect(),
                )
            }
            Node::Map(m) if m.len() == 1 => {
                let (k, _, d) = &m[0];
                match k.as_str() {
                    "fixed" => match d {
                        Node::Num(x) => Some(vec![*x]),
                        _ => None,
                    },
                    "uniform" => Some(vec![d.num("min")?, d.num("max")?]),
                    "normal" => {
                        let mean = d.num("mean")?;
                        let sd = d
                            .num("sd")
                            .or_else(|| d.num("rel_sd").map(|r| r * mean.abs()))
                            .unwrap_or(0.0);
                        let k = d.num("clip_sd").unwrap_or(3.0);
                        let lo = d.num("min").unwrap_or(f64::NEG_INFINITY).max(mean - k * sd);
                        let hi = d.num("max").unwrap_or(f64::INFINITY).min(mean + k * sd);
                        Some(vec![mean, lo, hi])
                    }
                    _ => None,
                }
            }
            _ => None,
        }
    }
}

/// Parses a YAML text into a [`Node`]; the error is the parser's first line.
pub fn tree(text: &str) -> Result<Node, String> {
    serde_saphyr::from_str::<Node>(text).map_err(|e| {
        let y = geodesic_util::yaml_error(&e);
        format!("{}: {}", y.line.unwrap_or(0), y.cause)
    })
}

/// Every parameter of a tree (outside its `pedigree:` section): `(path, line, node, values)`.
fn walk<'a>(
    node: &'a Node,
    path: &str,
    line: u64,
    out: &mut Vec<(String, u64, &'a Node, Vec<f64>)>,
) {
    if let Some(v) = node.values() {
        out.push((path.to_string(), line, node, v));
        return;
    }
    let join = |k: &str| {
        if path.is_empty() {
            k.to_string()
        } else {
            format!("{path}.{k}")
        }
    };
    match node {
        Node::Map(m) => {
            for (k, l, v) in m {
                if path.is_empty() && k == "pedigree" {
                    continue;
                }
                walk(v, &join(k), *l, out);
            }
        }
        Node::Seq(s) => {
            for (i, (l, v)) in s.iter().enumerate() {
                walk(v, &format!("{path}[{i}]"), *l, out);
            }
        }
        _ => {}
    }
}

/// Every parameter of an input file by path, its value in flow style (`{fixed: 1.96}`, `34.4e-12`
/// as `3.44e-11`): what the gate compares with the baseline's. Empty when the text is no YAML.
pub fn parameters(text: &str) -> BTreeMap<String, String> {
    let Ok(t) = tree(text) else {
        return BTreeMap::new();
    };
    let mut out = Vec::new();
    walk(&t, "", 0, &mut out);
    out.into_iter().map(|(p, _, n, _)| (p, n.flow())).collect()
}

/// The pedigree kind of every parameter whose file states one, by path (the most specific
/// entry that names it). Empty when the text is no YAML or has no `pedigree:` section.
pub fn kinds(text: &str) -> BTreeMap<String, Kind> {
    let (Ok(t), Ok(doc)) = (tree(text), serde_saphyr::from_str::<Doc>(text)) else {
        return BTreeMap::new();
    };
    let entries: Vec<(String, Kind)> = doc
        .pedigree
        .into_iter()
        .map(|(k, s)| (k, s.value.kind))
        .collect();
    let mut out = Vec::new();
    walk(&t, "", 0, &mut out);
    out.into_iter()
        .filter_map(|(p, _, _, _)| find(&entries, &p).map(|(_, k)| (p, *k)))
        .collect()
}

#[derive(Deserialize)]
struct Doc {
    #[serde(default)]
    pedigree: BTreeMap<String, Spanned<Entry>>,
}

/// Whether `pattern` (segments separated by `.`, `*` one segment, `[*]` any index) names `path`.
pub fn matches(pattern: &str, path: &str) -> bool {
    let norm = |s: &str| {
        // `a[3].b` -> segments `a`, `[3]`, `b`
        s.replace('[', ".[")
            .split('.')
            .filter(|x| !x.is_empty())
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let (p, q) = (norm(pattern), norm(path));
    p.len() == q.len()
        && p.iter().zip(&q).all(|(a, b)| {
            a == b || (a == "*" && !b.starts_with('[')) || (a == "[*]" && b.starts_with('['))
        })
}

/// The most specific entry whose pattern names `path` (fewest `*`).
fn find<'a, T>(items: &'a [(String, T)], path: &str) -> Option<&'a (String, T)> {
    items
        .iter()
        .filter(|(p, _)| matches(p, path))
        .min_by_key(|(p, _)| p.matches('*').count())
}

fn num(x: f64) -> String {
    crate::units::fmt_num(x)
}

/// Questions every parameter of an input file (`label` names it in errors): each must have a
/// pedigree entry, and its values must lie within the mission's range for it (or the entry's
/// own `range:`, which needs a reason). Returns the parameters by path; the error is one line,
/// `label:line: cause`.
pub fn question(
    text: &str,
    label: &str,
    ranges: &[Range],
) -> Result<BTreeMap<String, Param>, String> {
    let t = tree(text).map_err(|e| format!("{label}:{e}"))?;
    let doc: Doc = serde_saphyr::from_str(text).map_err(|e| {
        let y = geodesic_util::yaml_error(&e);
        format!("{label}:{}: pedigree: {}", y.line.unwrap_or(0), y.cause)
    })?;
    let entries: Vec<(String, (u64, Entry))> = doc
        .pedigree
        .into_iter()
        .map(|(k, s)| (k, (s.referenced.line(), s.value)))
        .collect();
    for (k, (line, e)) in &entries {
        if e.reference.trim().is_empty() {
            return Err(format!(
                "{label}:{line}: pedigree of {k}: `ref` is empty; name the source"
            ));
        }
        if let Some(r) = &e.range
            && (r.reason.trim().is_empty() || r.min.is_nan() || r.max.is_nan() || r.min > r.max)
        {
            return Err(format!(
                "{label}:{line}: pedigree of {k}: a range override needs min <= max and a non-empty reason"
            ));
        }
    }
    let rules: Vec<(String, &Range)> = ranges.iter().map(|r| (r.path.to_string(), r)).collect();
    let mut params = Vec::new();
    walk(&t, "", 0, &mut params);
    let mut out = BTreeMap::new();
    for (path, line, node, values) in params {
        let Some((_, (_, entry))) = find(&entries, &path) else {
            return Err(format!(
                "{label}:{line}: {path} states no pedigree: add `{path}: {{kind: measured|calibrated|cited|design|assumed, ref: \"...\"}}` under `pedigree:`"
            ));
        };
        let rule = find(&rules, &path).map(|(_, r)| *r);
        let (min, max, unit, why) = match (&entry.range, rule) {
            (Some(o), r) => (o.min, o.max, r.map_or("", |r| r.unit), o.reason.as_str()),
            (None, Some(r)) => (r.min, r.max, r.unit, r.why),
            (None, None) => {
                return Err(format!(
                    "{label}:{line}: {path}: no plausible range is known for it; state one in its pedigree: `range: {{min: A, max: B, reason: \"...\"}}`"
                ));
            }
        };
        if let Some(bad) = values
            .iter()
            .find(|v| !(v.is_finite() && **v >= min && **v <= max))
        {
            let drawn = if values.len() > 1 {
                format!(" (it is {})", node.flow())
            } else {
                String::new()
            };
            return Err(format!(
                "{label}:{line}: {path} = {} is outside its plausible range [{}, {}] {unit} ({why}){drawn}; if the value is meant, give its pedigree `range: {{min, max, reason}}`",
                num(*bad),
                num(min),
                num(max)
            ));
        }
        out.insert(
            path,
            Param {
                value: node.flow(),
                line,
                pedigree: entry.clone(),
                range: (min, max, unit.to_string()),
            },
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: &[Range] = &[
        Range {
            path: "m_kg",
            unit: "kg",
            min: 1.0,
            max: 3.0,
            why: "a 2 kg mass",
        },
        Range {
            path: "caps.*",
            unit: "F",
            min: 1e-13,
            max: 1e-9,
            why: "pF",
        },
        Range {
            path: "alt[*].mu_r",
            unit: "-",
            min: 1.0,
            max: 1e6,
            why: "real materials",
        },
    ];

    const OK: &str = "m_kg: {fixed: 1.96}\ncaps:\n  a_f: 3.44e-11\n  b_f: 1.0e-11\nalt:\n  - {name: x, mu_r: 2.0e4}\npedigree:\n  m_kg: {kind: cited, ref: \"report\", uncertainty: \"0.01 kg\"}\n  caps.*: {kind: cited, ref: \"FE\"}\n  alt[*].mu_r: {kind: assumed, ref: \"typical\"}\n";

    #[test]
    fn a_file_within_its_ranges_is_questioned_and_flattened() {
        let q = question(OK, "f.yaml", R).unwrap();
        assert_eq!(q.len(), 4);
        assert_eq!(q["m_kg"].value, "{fixed: 1.96}");
        assert_eq!(q["m_kg"].line, 1);
        assert_eq!(q["caps.a_f"].line, 3);
        assert_eq!(q["alt[0].mu_r"].pedigree.kind, Kind::Assumed);
        let p = parameters(OK);
        assert_eq!(p["caps.b_f"], "1e-11");
        assert!(!p.keys().any(|k| k.starts_with("pedigree")));
    }

    #[test]
    fn a_value_outside_its_range_is_refused_with_line_range_and_unit() {
        let e = question(&OK.replace("1.96", "19.6"), "f.yaml", R).unwrap_err();
        assert!(
            e.starts_with("f.yaml:1: m_kg = 19.6 is outside its plausible range [1, 3] kg"),
            "{e}"
        );
        let e = question(&OK.replace("3.44e-11", "34.4"), "f.yaml", R).unwrap_err();
        assert!(e.starts_with("f.yaml:3: caps.a_f = 34.4 is outside"), "{e}");
        assert!(e.contains(" F ("), "{e}");
        let e = question(&OK.replace("2.0e4", "2e12"), "f.yaml", R).unwrap_err();
        assert!(
            e.starts_with("f.yaml:6: alt[0].mu_r = 2e12 is outside its plausible range [1, 1e6] -"),
            "{e}"
        );
    }

    #[test]
    fn a_distribution_is_judged_by_what_it_draws() {
        let t = OK.replace("{fixed: 1.96}", "{normal: {mean: 2.0, sd: 0.5}}");
        let e = question(&t, "f.yaml", R).unwrap_err();
        assert!(e.contains("m_kg = 0.5 is outside"), "{e}");
        let t = OK.replace(
            "{fixed: 1.96}",
            "{normal: {mean: 2.0, sd: 0.5, min: 1.5, max: 2.5}}",
        );
        assert!(question(&t, "f.yaml", R).is_ok());
    }

    #[test]
    fn an_override_needs_a_reason_and_then_holds() {
        let t = OK.replace("1.96", "19.6").replace(
            "uncertainty: \"0.01 kg\"",
            "range: {min: 10, max: 30, reason: \"a heavier TM\"}",
        );
        let q = question(&t, "f.yaml", R).unwrap();
        assert_eq!(q["m_kg"].range, (10.0, 30.0, "kg".into()));
        let t2 = t.replace("a heavier TM", " ");
        assert!(
            question(&t2, "f.yaml", R)
                .unwrap_err()
                .contains("needs min <= max and a non-empty reason")
        );
    }

    #[test]
    fn a_parameter_without_pedigree_or_range_is_refused() {
        let t = OK.replace(
            "  m_kg: {kind: cited, ref: \"report\", uncertainty: \"0.01 kg\"}\n",
            "",
        );
        let e = question(&t, "f.yaml", R).unwrap_err();
        assert!(e.starts_with("f.yaml:1: m_kg states no pedigree"), "{e}");
        let t = format!("{OK}  x_s: {{kind: assumed, ref: \"?\"}}\n")
            .replace("m_kg: {fixed", "x_s: 4\nm_kg: {fixed");
        let e = question(&t, "f.yaml", R).unwrap_err();
        assert!(e.contains("x_s: no plausible range is known"), "{e}");
    }
}
