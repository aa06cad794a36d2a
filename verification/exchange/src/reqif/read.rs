//! Reading the ReqIF graph: identifiers resolved by look-up, attribute values as text, every
//! position as a line, and every problem of the file recorded instead of stopping the import.

use super::fields::norm;
use super::xhtml::{xhtml_objects, xhtml_to_text};
use geodesic_util::text::clip;
use roxmltree::{Document, Node};
use std::collections::HashMap;

/// Lines of a text: the line of a byte offset by binary search over the line starts
/// (`roxmltree::Document::text_pos_at` scans from the start: quadratic over a large file).
pub struct Lines {
    starts: Vec<usize>,
}

impl Lines {
    /// The line starts of `text`.
    pub fn new(text: &str) -> Lines {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i + 1),
        );
        Lines { starts }
    }

    /// 1-based line of byte offset `pos`.
    pub fn line(&self, pos: usize) -> u32 {
        let i = self.starts.partition_point(|&s| s <= pos);
        u32::try_from(i.max(1)).unwrap_or(u32::MAX)
    }
}

/// A problem of the file that the import worked around, at a line of the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// 1-based line in the ReqIF file.
    pub line: u32,
    /// One-line cause and what was done about it.
    pub cause: String,
}

/// The problems found so far. A reference that dangles many times is one problem (the
/// element is missing), reported once with its count at its first use.
#[derive(Default)]
pub struct Problems {
    list: Vec<Warning>,
    dangling: HashMap<(String, String), (u32, usize, String)>,
}

impl Problems {
    /// Records a problem.
    pub fn warn(&mut self, line: u32, cause: impl Into<String>) {
        self.list.push(Warning {
            line,
            cause: geodesic_util::text::one_line(&cause.into()),
        });
    }

    /// Records a reference to `id` (an element of kind `what`) that is not in the file;
    /// `done` says what the import did instead.
    pub fn dangling(&mut self, what: &str, id: &str, line: u32, done: &str) {
        let e = self
            .dangling
            .entry((what.to_string(), id.to_string()))
            .or_insert((line, 0, done.to_string()));
        e.1 += 1;
    }

    /// Every problem, in the order of the file's lines.
    pub fn finish(mut self) -> Vec<Warning> {
        for ((what, id), (line, n, done)) in self.dangling {
            let id = clip(&id, 100);
            let uses = if n > 1 {
                format!(" ({n} references)")
            } else {
                String::new()
            };
            self.list.push(Warning {
                line,
                cause: format!(
                    "dangling reference: {what} `{id}` is not defined in this file{uses}; {done}"
                ),
            });
        }
        self.list
            .sort_by(|a, b| a.line.cmp(&b.line).then(a.cause.cmp(&b.cause)));
        self.list
    }
}

/// What kind of ATTRIBUTE-VALUE an attribute value was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// XHTML (rich text)
    Xhtml,
    /// STRING
    String,
    /// ENUMERATION (the labels, joined by `, `)
    Enumeration,
    /// INTEGER, REAL, BOOLEAN, DATE
    Other,
}

/// One attribute value of an object, as text.
#[derive(Clone, Debug)]
pub struct AttrValue {
    /// The attribute's LONG-NAME (its IDENTIFIER when it has none or is not in the file).
    pub name: String,
    /// [`norm`] of the name.
    pub key: String,
    /// The value as text.
    pub text: String,
    /// What kind of value.
    pub kind: Kind,
    /// Embedded objects of an XHTML value (`data` of each `xhtml:object`).
    pub embedded: Vec<String>,
}

/// A SPEC-OBJECT as read.
#[derive(Debug)]
pub struct Object {
    /// IDENTIFIER.
    pub ident: String,
    /// LONG-NAME.
    pub long_name: Option<String>,
    /// LONG-NAME of its type (empty when the type is not in the file).
    pub type_name: String,
    /// Attribute values, the type's defaults included.
    pub values: Vec<AttrValue>,
    /// Line of the SPEC-OBJECT element.
    pub line: u32,
}

impl Object {
    /// The first non-empty value of the first of `names` present.
    pub fn get_any(&self, names: &[&str]) -> Option<&AttrValue> {
        names.iter().find_map(|n| self.get_key(&norm(n)))
    }

    /// The first non-empty value of the first of `keys` ([`norm`]ed names) present.
    pub fn get_keys(&self, keys: &[String]) -> Option<&AttrValue> {
        keys.iter().find_map(|k| self.get_key(k))
    }

    fn get_key(&self, k: &str) -> Option<&AttrValue> {
        self.values
            .iter()
            .find(|v| v.key == k && !v.text.trim().is_empty())
    }

    /// Whether the object carries a value (even empty) of one of `names`.
    pub fn has_any(&self, names: &[&str]) -> Option<&AttrValue> {
        names.iter().find_map(|n| {
            let k = norm(n);
            self.values.iter().find(|v| v.key == k)
        })
    }
}

/// Child element `name` of `n`.
pub fn child<'a, 'i>(n: Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == name)
}

/// Child elements of `n`.
pub fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

/// The text of the `*-REF` element inside `n`'s child `wrapper` (`TYPE`, `DEFINITION`, ...).
pub fn ref_in<'a, 'i>(n: Node<'a, 'i>, wrapper: &str) -> Option<(String, Node<'a, 'i>)> {
    let w = child(n, wrapper)?;
    let r = elements(w).next()?;
    Some((r.text().unwrap_or("").trim().to_string(), r))
}

/// The document's identifiable elements and the problems found reading them.
pub struct Model<'a, 'i> {
    ids: HashMap<&'a str, Node<'a, 'i>>,
    lines: Lines,
    /// Problems found so far.
    pub problems: Problems,
}

impl<'a, 'i> Model<'a, 'i> {
    /// Indexes every element of `content` with an IDENTIFIER (the first of each).
    pub fn new(doc: &'a Document<'i>, content: Node<'a, 'i>) -> Model<'a, 'i> {
        let mut ids = HashMap::new();
        for n in content.descendants().filter(|n| n.is_element()) {
            if let Some(id) = n.attribute("IDENTIFIER") {
                ids.entry(id).or_insert(n);
            }
        }
        Model {
            ids,
            lines: Lines::new(doc.input_text()),
            problems: Problems::default(),
        }
    }

    /// Line of a node.
    pub fn line(&self, n: Node) -> u32 {
        self.lines.line(n.range().start)
    }

    /// The element a reference names, if it is in the file and of the kind `tag` (a missing
    /// one is recorded as a dangling reference; `done` says what the import does instead).
    pub fn resolve(
        &mut self,
        r: &(String, Node<'a, 'i>),
        tag: &str,
        done: &str,
    ) -> Option<Node<'a, 'i>> {
        let line = self.line(r.1);
        if r.0.is_empty() {
            self.problems
                .warn(line, format!("empty {tag} reference; {done}"));
            return None;
        }
        match self.ids.get(r.0.as_str()) {
            Some(n) if n.tag_name().name() == tag || tag.is_empty() => Some(*n),
            Some(n) => {
                self.problems.warn(
                    line,
                    format!(
                        "reference `{}` names a {}, not a {tag}; {done}",
                        clip(&r.0, 100),
                        n.tag_name().name()
                    ),
                );
                None
            }
            None => {
                self.problems.dangling(tag, &r.0, line, done);
                None
            }
        }
    }

    /// The text of one ATTRIBUTE-VALUE-* element, its kind and the embedded objects of XHTML.
    fn value_text(&mut self, v: Node<'a, 'i>) -> (String, Kind, Vec<String>) {
        let kind = v.tag_name().name().trim_start_matches("ATTRIBUTE-VALUE-");
        match kind {
            "XHTML" => match child(v, "THE-VALUE") {
                Some(tv) => (xhtml_to_text(tv), Kind::Xhtml, xhtml_objects(tv)),
                None => (String::new(), Kind::Xhtml, Vec::new()),
            },
            "ENUMERATION" => {
                let mut labels = Vec::new();
                if let Some(vals) = child(v, "VALUES") {
                    for r in elements(vals) {
                        let id = r.text().unwrap_or("").trim().to_string();
                        let reference = (id.clone(), r);
                        match self.resolve(
                            &reference,
                            "ENUM-VALUE",
                            "its identifier is kept as the label",
                        ) {
                            Some(ev) => labels.push(
                                ev.attribute("LONG-NAME")
                                    .filter(|l| !l.trim().is_empty())
                                    .or(ev.attribute("IDENTIFIER"))
                                    .unwrap_or_default()
                                    .to_string(),
                            ),
                            None if !id.is_empty() => labels.push(id),
                            None => {}
                        }
                    }
                }
                (labels.join(", "), Kind::Enumeration, Vec::new())
            }
            "STRING" => (
                v.attribute("THE-VALUE").unwrap_or("").to_string(),
                Kind::String,
                Vec::new(),
            ),
            _ => (
                v.attribute("THE-VALUE").unwrap_or("").to_string(),
                Kind::Other,
                Vec::new(),
            ),
        }
    }

    /// The name of a value's attribute definition: its LONG-NAME, else its IDENTIFIER; the
    /// referenced identifier when the definition is not in the file (recorded).
    fn attr_name(&mut self, v: Node<'a, 'i>) -> Option<String> {
        let Some(r) = ref_in(v, "DEFINITION") else {
            let line = self.line(v);
            self.problems.warn(
                line,
                format!("{} without DEFINITION: value ignored", v.tag_name().name()),
            );
            return None;
        };
        let tag = r.1.tag_name().name().trim_end_matches("-REF").to_string();
        let def = match self.ids.get(r.0.as_str()) {
            // a value whose definition is of another datatype (Polarion writes STRING values
            // of XHTML definitions): the definition names it all the same
            Some(d)
                if d.tag_name().name() != tag
                    && d.tag_name().name().starts_with("ATTRIBUTE-DEFINITION-") =>
            {
                let line = self.line(v);
                self.problems.warn(
                    line,
                    format!(
                        "{} refers to the {} `{}` (`{}`): read as its text",
                        v.tag_name().name(),
                        d.tag_name().name(),
                        clip(&r.0, 100),
                        clip(d.attribute("LONG-NAME").unwrap_or(""), 80)
                    ),
                );
                Some(*d)
            }
            _ => self.resolve(
                &r,
                &tag,
                "the value is kept under the referenced identifier as its attribute name",
            ),
        };
        match def {
            Some(def) => Some(
                def.attribute("LONG-NAME")
                    .filter(|l| !l.trim().is_empty())
                    .or(def.attribute("IDENTIFIER"))
                    .unwrap_or("")
                    .to_string(),
            ),
            None if !r.0.is_empty() => Some(r.0),
            None => None,
        }
    }

    /// The attribute values of an element (object, specification, relation).
    pub fn values(&mut self, n: Node<'a, 'i>) -> Vec<AttrValue> {
        let mut out = Vec::new();
        if let Some(vals) = child(n, "VALUES") {
            for v in elements(vals) {
                if !v.tag_name().name().starts_with("ATTRIBUTE-VALUE-") {
                    continue;
                }
                let Some(name) = self.attr_name(v) else {
                    continue;
                };
                let (text, kind, embedded) = self.value_text(v);
                out.push(AttrValue {
                    key: norm(&name),
                    name,
                    text,
                    kind,
                    embedded,
                });
            }
        }
        out
    }

    /// A SPEC-OBJECT: its values and the defaults of its type's attribute definitions for
    /// values it does not carry.
    pub fn object(&mut self, n: Node<'a, 'i>) -> Object {
        let line = self.line(n);
        let ident = match n.attribute("IDENTIFIER").filter(|i| !i.trim().is_empty()) {
            Some(i) => i.to_string(),
            None => {
                let made = format!("line-{line}");
                self.problems.warn(
                    line,
                    format!("SPEC-OBJECT without IDENTIFIER: read as `{made}`"),
                );
                made
            }
        };
        let ty = match ref_in(n, "TYPE") {
            Some(tr) => self.resolve(
                &tr,
                "SPEC-OBJECT-TYPE",
                "its objects are read without the type's name and defaults",
            ),
            None => {
                self.problems.warn(
                    line,
                    format!(
                        "SPEC-OBJECT `{}` has no TYPE: read without the type's name and defaults",
                        clip(&ident, 100)
                    ),
                );
                None
            }
        };
        let mut values = self.values(n);
        if let Some(attrs) = ty.and_then(|t| child(t, "SPEC-ATTRIBUTES")) {
            for def in elements(attrs) {
                let Some(dv) = child(def, "DEFAULT-VALUE").and_then(|d| elements(d).next()) else {
                    continue;
                };
                let name = def
                    .attribute("LONG-NAME")
                    .filter(|l| !l.trim().is_empty())
                    .or(def.attribute("IDENTIFIER"))
                    .unwrap_or("")
                    .to_string();
                let key = norm(&name);
                if values.iter().any(|v| v.key == key) {
                    continue;
                }
                let (text, kind, embedded) = self.value_text(dv);
                values.push(AttrValue {
                    name,
                    key,
                    text,
                    kind,
                    embedded,
                });
            }
        }
        Object {
            ident,
            long_name: n
                .attribute("LONG-NAME")
                .filter(|l| !l.trim().is_empty())
                .map(str::to_string),
            type_name: ty
                .and_then(|t| t.attribute("LONG-NAME"))
                .unwrap_or("")
                .to_string(),
            values,
            line,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_of_offsets() {
        let l = Lines::new("ab\ncd\n\nef");
        assert_eq!(l.line(0), 1);
        assert_eq!(l.line(2), 1);
        assert_eq!(l.line(3), 2);
        assert_eq!(l.line(6), 3);
        assert_eq!(l.line(7), 4);
        assert_eq!(l.line(100), 4);
    }
}
