//! A ReqIF file read into geodesic requirements.
//!
//! Reads what geodesic writes and what DOORS, DOORS Next, Polarion, ReqIF Studio and other
//! tools write: attribute values of every datatype (XHTML read as text, enumerations by the
//! label of their values, defaults of attribute definitions), the SPEC-HIERARCHY of each
//! specification (headings become families), and SPEC-RELATIONs (derivations become parents;
//! other links are kept in the note). Elements are matched by local name, so files of the
//! ReqIF 1.0.1 namespace (`http://www.omg.org/spec/ReqIF/20101201`) are read too.
//!
//! Field by field (the first attribute present wins; names compared without case, spaces,
//! `_` and `-`; `ImportOptions::attribute` replaces a list by one name):
//!
//! | field | attributes | when the file has none |
//! | --- | --- | --- |
//! | id | `ReqIF.ForeignID` (with `ReqIF.Prefix`), `geodesic.ID`, `ID`, `Identifier`, `PUID`, `IE PUID`, `Object Identifier`, `Absolute Number` | the object's LONG-NAME, else its IDENTIFIER; made a geodesic ID (upper case, `-`), the original kept in the note |
//! | title | `ReqIF.Name`, `geodesic.Title`, `Title`, `Name` | `ReqIF.ChapterName`, the object's LONG-NAME, else the text's first 80 characters |
//! | text | `ReqIF.Text`, `geodesic.Text`, `Object Text`, `Text`, `ReqIF.Description`, `Description` | not a requirement (an object without text or heading is skipped) |
//! | source | `geodesic.Source`, `Source` | the file, its specification and the object |
//! | quantity | `geodesic.Quantity`, `Quantity` | empty |
//! | dimension | `geodesic.Dimension`, `Dimension` | the dimension of the limit's unit |
//! | limit | `geodesic.Limit`, `Limit` | none: a *qualitative* requirement (closed by its method) |
//! | probability | `geodesic.Probability`, `Probability` | none |
//! | method | `geodesic.Method`, `Verification Method`, `Verification Methods`, `Method` | `review-of-design` for a qualitative requirement; **incomplete** for one with a limit |
//! | activity | `geodesic.Activity`, `Verification Activity`, `Activity` | "not stated in the ReqIF file" |
//! | check | `geodesic.Check` | none (verify reports the requirement not verified) |
//! | note | `geodesic.Note`, `Note`, `Comment`, `Comments` | none |
//!
//! A requirement without a limit (the prose requirements of most DOORS and Polarion modules) is
//! imported as *qualitative*: no limit, dimension, probability, check nor parent (its
//! derivation links are kept in the note), method `review-of-design` (ECSS-E-ST-10-02C review
//! of design) unless the file states one; `verify` reports it not verified. A requirement
//! with a limit but no method, or with a limit, method or check geodesic cannot read, is never
//! given an invented one: the import fails naming each such requirement (file and line), or
//! with `ImportOptions::skip_incomplete` leaves them out, with the qualitative ones, and lists
//! them in `Imported::skipped`.

use super::{CHAPTER_NAME, DESCRIPTION, FOREIGN_ID, NAME, PREFIX, TEXT, xhtml_to_text};
use crate::yaml;
use geodesic_core::Requirements;
use geodesic_core::units::{Quantity, parse_quantity};
use roxmltree::{Document, Node, ParsingOptions};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

/// Largest number of XML nodes read (a guard on memory: about 20 million nodes of a ReqIF file
/// of a few hundred MB).
pub const MAX_NODES: u32 = 20_000_000;

/// Why a ReqIF file was refused. Display is one line: `file:line: cause`.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{file}:{line}: {}", geodesic_core::text::one_line(.cause))]
pub struct ImportError {
    /// The ReqIF file.
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// One-line cause.
    pub cause: String,
}

/// A field of a geodesic requirement that an attribute of the file can supply.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Field {
    /// `id`
    Id,
    /// `title`
    Title,
    /// `text`
    Text,
    /// `source`
    Source,
    /// `quantity`
    Quantity,
    /// `dimension`
    Dimension,
    /// `limit`
    Limit,
    /// `probability`
    Probability,
    /// `level` (ECSS verification level)
    Level,
    /// `stage` (ECSS verification stage)
    Stage,
    /// `spectrum.band`
    SpectrumBand,
    /// `spectrum.shape`
    SpectrumShape,
    /// `method`
    Method,
    /// `activity`
    Activity,
    /// `check`
    Check,
    /// `note`
    Note,
}

impl Field {
    /// Every field, in YAML order.
    pub const ALL: [Field; 16] = [
        Field::Id,
        Field::Title,
        Field::Text,
        Field::Source,
        Field::Quantity,
        Field::Dimension,
        Field::Limit,
        Field::Probability,
        Field::SpectrumBand,
        Field::SpectrumShape,
        Field::Level,
        Field::Stage,
        Field::Method,
        Field::Activity,
        Field::Check,
        Field::Note,
    ];

    /// The YAML key.
    pub fn name(self) -> &'static str {
        match self {
            Field::Id => "id",
            Field::Title => "title",
            Field::Text => "text",
            Field::Source => "source",
            Field::Quantity => "quantity",
            Field::Dimension => "dimension",
            Field::Limit => "limit",
            Field::Probability => "probability",
            Field::Level => "level",
            Field::Stage => "stage",
            Field::SpectrumBand => "spectrum-band",
            Field::SpectrumShape => "spectrum-shape",
            Field::Method => "method",
            Field::Activity => "activity",
            Field::Check => "check",
            Field::Note => "note",
        }
    }

    /// The field of a YAML key.
    pub fn parse(s: &str) -> Option<Field> {
        Field::ALL.into_iter().find(|f| f.name() == s)
    }

    fn candidates(self) -> &'static [&'static str] {
        match self {
            Field::Id => &[
                FOREIGN_ID,
                "geodesic.ID",
                "ID",
                "Identifier",
                "PUID",
                "IE PUID",
                "Object Identifier",
                "Absolute Number",
                "Requirement ID",
                "Req ID",
                "Key",
                "Document Key",
                "Item ID",
            ],
            Field::Title => &[NAME, "geodesic.Title", "Title", "Name"],
            // the names tools give the statement: DOORS ("Object Text"), DOORS Next
            // ("Primary Text"), Polarion and Jama ("Description"), Codebeamer and Integrity
            // ("Text"), Enterprise Architect ("Notes"), and generic exports
            Field::Text => &[
                TEXT,
                "geodesic.Text",
                "Object Text",
                "Primary Text",
                "Text",
                "Requirement Text",
                "Statement",
                "Shall Statement",
                DESCRIPTION,
                "Description",
                "Notes",
                "Content",
                "Body",
            ],
            Field::Source => &["geodesic.Source", "Source"],
            Field::Quantity => &["geodesic.Quantity", "Quantity"],
            Field::Dimension => &["geodesic.Dimension", "Dimension"],
            Field::Limit => &["geodesic.Limit", "Limit"],
            Field::Probability => &["geodesic.Probability", "Probability"],
            Field::Level => &["geodesic.Level", "Verification Level"],
            Field::Stage => &["geodesic.Stage", "Verification Stage"],
            Field::SpectrumBand => &["geodesic.SpectrumBand", "Spectrum Band"],
            Field::SpectrumShape => &["geodesic.SpectrumShape", "Spectrum Shape"],
            Field::Method => &[
                "geodesic.Method",
                "Verification Method",
                "Verification Methods",
                "Method",
            ],
            Field::Activity => &["geodesic.Activity", "Verification Activity", "Activity"],
            Field::Check => &["geodesic.Check"],
            Field::Note => &["geodesic.Note", "Note", "Comment", "Comments"],
        }
    }
}

/// How to import.
#[derive(Clone, Debug, Default)]
pub struct ImportOptions {
    /// Import only complete quantitative requirements: leave out the incomplete ones (a limit
    /// without a method, a limit or method that cannot be read) instead of failing, and the
    /// qualitative ones (no limit); all are listed in [`Imported::skipped`].
    pub skip_incomplete: bool,
    /// The attribute (LONG-NAME) that supplies a field, replacing the built-in list.
    pub attribute: BTreeMap<Field, String>,
}

/// One requirement as read, ready to be written as YAML.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedRequirement {
    /// geodesic ID.
    pub id: String,
    /// Title.
    pub title: String,
    /// Shall statement.
    pub text: String,
    /// Source.
    pub source: String,
    /// Quantity.
    pub quantity: String,
    /// Dimension name (empty when qualitative).
    pub dimension: String,
    /// Limit as written (empty: a qualitative requirement).
    pub limit: String,
    /// Probability level.
    pub probability: Option<String>,
    /// Band and shape of a spectral limit.
    pub spectrum: Option<(String, String)>,
    /// ECSS verification level, if stated.
    pub level: Option<String>,
    /// ECSS verification stage, if stated.
    pub stage: Option<String>,
    /// Method (test, analysis, review-of-design, inspection).
    pub method: String,
    /// Verification activity.
    pub activity: String,
    /// Registered check.
    pub check: Option<String>,
    /// Parent and margin.
    pub parent: Option<(String, f64)>,
    /// Note.
    pub note: Option<String>,
    /// Line of the SPEC-OBJECT in the ReqIF file.
    pub line: u32,
}

/// One family: one YAML file.
#[derive(Clone, Debug)]
pub struct ImportedFamily {
    /// Family name.
    pub family: String,
    /// Description.
    pub description: Option<String>,
    /// File name to write (`release.yaml`).
    pub file_name: String,
    /// Requirements in document order.
    pub requirements: Vec<ImportedRequirement>,
    /// The YAML text.
    pub yaml: String,
}

/// A requirement left out because a field geodesic needs is missing (or, with
/// [`ImportOptions::skip_incomplete`], because it is qualitative).
#[derive(Clone, Debug)]
pub struct Skipped {
    /// geodesic ID it would have had.
    pub id: String,
    /// Line of the SPEC-OBJECT.
    pub line: u32,
    /// What is missing, one phrase each.
    pub missing: Vec<String>,
}

/// The result of an import.
#[derive(Clone, Debug)]
pub struct Imported {
    /// Families in document order.
    pub families: Vec<ImportedFamily>,
    /// Requirements left out (only with `skip_incomplete`).
    pub skipped: Vec<Skipped>,
    /// Requirements imported as qualitative (no limit).
    pub qualitative: usize,
    /// `SOURCE-TOOL-ID` of the header.
    pub source_tool: String,
    /// Heading objects read.
    pub headings: usize,
    /// Objects that are neither requirement nor heading (no text).
    pub other_objects: usize,
    /// SPEC-RELATIONs read.
    pub relations: usize,
}

impl Imported {
    /// Number of requirements imported.
    pub fn count(&self) -> usize {
        self.families.iter().map(|f| f.requirements.len()).sum()
    }
}

fn norm(s: &str) -> String {
    s.chars()
        .filter(|c| !c.is_whitespace() && *c != '_' && *c != '-')
        .flat_map(char::to_lowercase)
        .collect()
}

#[derive(Clone, Debug)]
struct AttrValue {
    name: String,
    text: String,
}

#[derive(Debug)]
struct Object {
    ident: String,
    long_name: Option<String>,
    type_name: String,
    values: Vec<AttrValue>,
    line: u32,
}

impl Object {
    fn get_any(&self, names: &[&str]) -> Option<&str> {
        for n in names {
            let k = norm(n);
            if let Some(v) = self
                .values
                .iter()
                .find(|v| norm(&v.name) == k && !v.text.trim().is_empty())
            {
                return Some(v.text.trim());
            }
        }
        None
    }

    fn get(&self, f: Field, opts: &ImportOptions) -> Option<&str> {
        match opts.attribute.get(&f) {
            Some(name) => self.get_any(&[name.as_str()]),
            None => self.get_any(f.candidates()),
        }
    }
}

struct Ctx<'a, 'input> {
    file: String,
    doc: &'a Document<'input>,
}

impl Ctx<'_, '_> {
    fn line(&self, n: Node) -> u32 {
        self.doc.text_pos_at(n.range().start).row
    }

    fn err(&self, n: Node, cause: impl Into<String>) -> ImportError {
        ImportError {
            file: self.file.clone(),
            line: self.line(n),
            cause: cause.into(),
        }
    }
}

fn child<'a, 'i>(n: Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == name)
}

fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

/// The text of the `*-REF` element inside `n`'s child `wrapper` (`TYPE`, `DEFINITION`, ...).
fn ref_in<'a, 'i>(n: Node<'a, 'i>, wrapper: &str) -> Option<(String, Node<'a, 'i>)> {
    let w = child(n, wrapper)?;
    let r = elements(w).next()?;
    Some((r.text().unwrap_or("").trim().to_string(), r))
}

/// Everything with an IDENTIFIER, by identifier (first occurrence).
fn index<'a, 'i>(root: Node<'a, 'i>) -> HashMap<String, Node<'a, 'i>> {
    let mut m = HashMap::new();
    for n in root.descendants().filter(|n| n.is_element()) {
        if let Some(id) = n.attribute("IDENTIFIER") {
            m.entry(id.to_string()).or_insert(n);
        }
    }
    m
}

struct Model<'a, 'i> {
    ids: HashMap<String, Node<'a, 'i>>,
}

impl<'a, 'i> Model<'a, 'i> {
    fn resolve(
        &self,
        ctx: &Ctx,
        r: (String, Node<'a, 'i>),
        what: &str,
    ) -> Result<Node<'a, 'i>, ImportError> {
        let (id, at) = r;
        if id.is_empty() {
            return Err(ctx.err(at, format!("empty {what} reference")));
        }
        self.ids.get(&id).copied().ok_or_else(|| {
            ctx.err(
                at,
                format!("dangling reference: {what} `{id}` is not defined in this file"),
            )
        })
    }

    /// The text of one ATTRIBUTE-VALUE-* element.
    fn value_text(&self, ctx: &Ctx, v: Node<'a, 'i>) -> Result<String, ImportError> {
        let kind = v.tag_name().name().trim_start_matches("ATTRIBUTE-VALUE-");
        Ok(match kind {
            "XHTML" => match child(v, "THE-VALUE") {
                Some(tv) => xhtml_to_text(tv),
                None => String::new(),
            },
            "ENUMERATION" => {
                let mut labels = Vec::new();
                if let Some(vals) = child(v, "VALUES") {
                    for r in elements(vals) {
                        let id = r.text().unwrap_or("").trim().to_string();
                        let ev = self.resolve(ctx, (id, r), "enumeration value")?;
                        let label = ev
                            .attribute("LONG-NAME")
                            .map(str::to_string)
                            .or_else(|| {
                                ev.descendants()
                                    .find(|d| d.tag_name().name() == "EMBEDDED-VALUE")
                                    .and_then(|e| e.attribute("OTHER-CONTENT"))
                                    .map(str::to_string)
                            })
                            .unwrap_or_default();
                        labels.push(label);
                    }
                }
                labels.join(", ")
            }
            _ => v.attribute("THE-VALUE").unwrap_or("").to_string(),
        })
    }

    fn attr_name(&self, ctx: &Ctx, v: Node<'a, 'i>) -> Result<String, ImportError> {
        let r = ref_in(v, "DEFINITION")
            .ok_or_else(|| ctx.err(v, "attribute value without DEFINITION"))?;
        let def = self.resolve(ctx, r, "attribute definition")?;
        Ok(def
            .attribute("LONG-NAME")
            .or(def.attribute("IDENTIFIER"))
            .unwrap_or("")
            .to_string())
    }

    fn values(&self, ctx: &Ctx, n: Node<'a, 'i>) -> Result<Vec<AttrValue>, ImportError> {
        let mut out = Vec::new();
        if let Some(vals) = child(n, "VALUES") {
            for v in elements(vals) {
                if !v.tag_name().name().starts_with("ATTRIBUTE-VALUE-") {
                    continue;
                }
                out.push(AttrValue {
                    name: self.attr_name(ctx, v)?,
                    text: self.value_text(ctx, v)?,
                });
            }
        }
        Ok(out)
    }

    fn object(&self, ctx: &Ctx, n: Node<'a, 'i>) -> Result<Object, ImportError> {
        let ident = n
            .attribute("IDENTIFIER")
            .ok_or_else(|| ctx.err(n, "SPEC-OBJECT without IDENTIFIER"))?
            .to_string();
        let tr = ref_in(n, "TYPE")
            .ok_or_else(|| ctx.err(n, format!("SPEC-OBJECT {ident} has no TYPE")))?;
        let ty = self.resolve(ctx, tr, "SPEC-OBJECT-TYPE")?;
        let mut values = self.values(ctx, n)?;
        // defaults of the type's attribute definitions for values the object does not carry
        if let Some(attrs) = child(ty, "SPEC-ATTRIBUTES") {
            for def in elements(attrs) {
                let Some(dv) = child(def, "DEFAULT-VALUE").and_then(|d| elements(d).next()) else {
                    continue;
                };
                let name = def.attribute("LONG-NAME").unwrap_or("").to_string();
                if values.iter().any(|v| v.name == name) {
                    continue;
                }
                values.push(AttrValue {
                    name,
                    text: self.value_text(ctx, dv)?,
                });
            }
        }
        Ok(Object {
            ident,
            long_name: n.attribute("LONG-NAME").map(str::to_string),
            type_name: ty.attribute("LONG-NAME").unwrap_or("").to_string(),
            values,
            line: ctx.line(n),
        })
    }
}

/// Where an object sits: the nearest heading above it, else its specification.
#[derive(Clone, Debug, Default)]
struct Place {
    family: Option<(String, Option<String>)>,
    spec: Option<String>,
}

fn is_heading(o: &Object, opts: &ImportOptions) -> bool {
    let chapter = o.get_any(&[CHAPTER_NAME]).is_some();
    let text = o.get(Field::Text, opts).is_some();
    o.type_name.to_lowercase().contains("heading") || (chapter && !text)
}

fn heading_of(o: &Object, opts: &ImportOptions) -> (String, Option<String>) {
    let name = o
        .get_any(&[CHAPTER_NAME])
        .or(o.get(Field::Title, opts))
        .or(o.long_name.as_deref())
        .unwrap_or(&o.ident)
        .to_string();
    let desc = o.get(Field::Text, opts).map(str::to_string);
    (name, desc)
}

/// A geodesic requirement ID made from an identifier of another tool.
fn to_req_id(s: &str) -> String {
    let mut o = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            o.push(c.to_ascii_uppercase());
        } else if !o.ends_with('-') {
            o.push('-');
        }
    }
    let o = o.trim_matches('-').to_string();
    if o.is_empty() || o.starts_with(|c: char| c.is_ascii_digit()) {
        format!("REQ-{o}").trim_end_matches('-').to_string()
    } else {
        o
    }
}

fn slug(s: &str) -> String {
    let mut o = String::new();
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            o.push(c.to_ascii_lowercase());
        } else if !o.ends_with('-') {
            o.push('-');
        }
    }
    o.trim_matches('-').to_string()
}

fn method_of(s: &str) -> Result<&'static str, String> {
    let first = s.split([',', ';', '/']).next().unwrap_or("").trim();
    let k: String = first
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .flat_map(|c| c.to_lowercase())
        .collect();
    Ok(match k.as_str() {
        "test" | "t" | "testing" => "test",
        "analysis" | "a" | "simulation" | "similarity" => "analysis",
        "reviewofdesign" | "rod" | "r" | "review" | "designreview" => "review-of-design",
        "inspection" | "i" => "inspection",
        _ => {
            return Err(format!(
                "verification method `{first}` is none of test, analysis, review-of-design, inspection (ECSS-E-ST-10-02C)"
            ));
        }
    })
}

/// The comparison and the SI quantity of a limit as written (`<= 5 um/s`).
fn parse_limit(s: &str) -> Result<(Quantity, String), String> {
    let t = s.trim();
    for sym in ["<=", "≤", ">=", "≥", "<", ">"] {
        if let Some(rest) = t.strip_prefix(sym) {
            // an amplitude spectral density limit (`... Hz^-1/2`): the dimension is that of the
            // quantity whose spectrum is bounded
            let stripped = geodesic_core::spectrum::strip_asd_unit(rest.trim());
            let rest = stripped.as_deref().unwrap_or(rest);
            let (q, _) = parse_quantity(rest.trim()).map_err(|e| format!("limit `{t}`: {e}"))?;
            let dim = q
                .dim
                .name()
                .ok_or_else(|| format!("limit `{t}`: its unit has no dimension geodesic names"))?;
            return Ok((q, dim.to_string()));
        }
    }
    Err(format!(
        "limit `{t}` must start with <=, <, >= or > (e.g. `<= 5 um/s`)"
    ))
}

const PARENT_RELATIONS: &[&str] = &[
    "geodesic.DerivedFrom",
    "Derived From",
    "Derives From",
    "Is Derived From",
    "Parent",
    "Child Of",
    "Refines",
];

struct Pending {
    req: ImportedRequirement,
    ident: String,
    family: (String, Option<String>),
    missing: Vec<String>,
    /// No limit in the file: imported as a qualitative requirement (`missing` says why not
    /// quantitative, for `skip_incomplete`).
    qualitative: Option<String>,
    limit_si: Option<Quantity>,
    extra_notes: Vec<String>,
}

/// Reads a ReqIF document (`file` names it in messages) into requirement families.
pub fn import(file: &Path, text: &str, opts: &ImportOptions) -> Result<Imported, ImportError> {
    let fname = file.display().to_string();
    if text.starts_with("PK") {
        return Err(ImportError {
            file: fname,
            line: 1,
            cause: "this is a zip archive (.reqifz): unzip it and import the .reqif file inside"
                .into(),
        });
    }
    let po = ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_NODES,
        ..ParsingOptions::default()
    };
    let doc = Document::parse_with_options(text, po).map_err(|e| ImportError {
        file: fname.clone(),
        line: e.pos().row,
        cause: format!("malformed XML: {e}"),
    })?;
    let ctx = Ctx {
        file: fname.clone(),
        doc: &doc,
    };
    let root = doc.root_element();
    let ns_ok = root
        .tag_name()
        .namespace()
        .is_some_and(|n| n.starts_with("http://www.omg.org/spec/ReqIF/"));
    if root.tag_name().name() != "REQ-IF" || !ns_ok {
        return Err(ctx.err(
            root,
            format!(
                "not a ReqIF file: the root element is `{}` in namespace `{}` (expected REQ-IF in {})",
                root.tag_name().name(),
                root.tag_name().namespace().unwrap_or(""),
                super::NAMESPACE
            ),
        ));
    }
    let source_tool = child(root, "THE-HEADER")
        .and_then(|h| child(h, "REQ-IF-HEADER"))
        .and_then(|h| child(h, "SOURCE-TOOL-ID"))
        .and_then(|s| s.text())
        .unwrap_or("")
        .trim()
        .to_string();
    let content = child(root, "CORE-CONTENT")
        .and_then(|c| child(c, "REQ-IF-CONTENT"))
        .ok_or_else(|| ctx.err(root, "no CORE-CONTENT/REQ-IF-CONTENT"))?;
    let model = Model {
        ids: index(content),
    };

    // objects, in document order
    let mut objects: Vec<Object> = Vec::new();
    let mut by_ident: HashMap<String, usize> = HashMap::new();
    if let Some(so) = child(content, "SPEC-OBJECTS") {
        for n in elements(so).filter(|n| n.tag_name().name() == "SPEC-OBJECT") {
            let o = model.object(&ctx, n)?;
            if by_ident.contains_key(&o.ident) {
                return Err(ctx.err(n, format!("SPEC-OBJECT {} is defined twice", o.ident)));
            }
            by_ident.insert(o.ident.clone(), objects.len());
            objects.push(o);
        }
    }

    // hierarchy: document order and the heading above each object
    let mut order: Vec<(usize, Place)> = Vec::new();
    let mut placed: HashSet<usize> = HashSet::new();
    if let Some(specs) = child(content, "SPECIFICATIONS") {
        for spec in elements(specs).filter(|n| n.tag_name().name() == "SPECIFICATION") {
            let spec_values = model.values(&ctx, spec)?;
            let spec_name = spec.attribute("LONG-NAME").map(str::to_string).or_else(|| {
                spec_values
                    .iter()
                    .find(|v| norm(&v.name) == norm(NAME) && !v.text.trim().is_empty())
                    .map(|v| v.text.trim().to_string())
            });
            let place = Place {
                family: None,
                spec: spec_name,
            };
            if let Some(ch) = child(spec, "CHILDREN") {
                walk(
                    &ctx,
                    &model,
                    ch,
                    &place,
                    &objects,
                    &by_ident,
                    opts,
                    &mut order,
                    &mut placed,
                )?;
            }
        }
    }
    for i in 0..objects.len() {
        if !placed.contains(&i) {
            order.push((i, Place::default()));
        }
    }

    let stem = file
        .file_stem()
        .map_or("imported".to_string(), |s| s.to_string_lossy().into_owned());
    let mut headings = 0;
    let mut other_objects = 0;
    // attributes with a value on the objects without text: the candidates for --attribute text=
    let mut untexted_attributes: Vec<String> = Vec::new();
    let mut pending: Vec<Pending> = Vec::new();
    let mut ids_seen: HashMap<String, u32> = HashMap::new();
    let mut req_of_ident: HashMap<String, usize> = HashMap::new();
    for (i, place) in &order {
        let o = &objects[*i];
        if is_heading(o, opts) {
            headings += 1;
            continue;
        }
        let Some(text) = o.get(Field::Text, opts) else {
            other_objects += 1;
            for v in &o.values {
                if !v.text.trim().is_empty() && !untexted_attributes.contains(&v.name) {
                    untexted_attributes.push(v.name.clone());
                }
            }
            continue;
        };
        let mut notes: Vec<String> = Vec::new();
        let raw_id = match o.get(Field::Id, opts) {
            Some(fid) => match o.get_any(&[PREFIX]) {
                Some(p) if !fid.starts_with(p) => format!("{p}{fid}"),
                _ => fid.to_string(),
            },
            None => o.long_name.clone().unwrap_or_else(|| o.ident.clone()),
        };
        let id = to_req_id(&raw_id);
        if id != raw_id {
            notes.push(format!(
                "imported from ReqIF object {} (identifier in the source tool: {raw_id})",
                o.ident
            ));
        }
        if let Some(prev) = ids_seen.insert(id.clone(), o.line) {
            return Err(ImportError {
                file: fname.clone(),
                line: o.line,
                cause: format!(
                    "requirement ID {id} (from `{raw_id}`) is also the ID of the object at line {prev}; IDs must be unique"
                ),
            });
        }
        let title = o
            .get(Field::Title, opts)
            .or(o.get_any(&[CHAPTER_NAME]))
            .or(o.long_name.as_deref().filter(|l| !l.trim().is_empty()))
            .map(str::to_string)
            .unwrap_or_else(|| {
                let first = text.lines().next().unwrap_or(text);
                if first.chars().count() > 80 {
                    let cut: String = first.chars().take(80).collect();
                    format!("{}...", cut.trim_end())
                } else {
                    first.to_string()
                }
            });
        let spec_part = place
            .spec
            .as_ref()
            .map_or(String::new(), |s| format!(", specification '{s}'"));
        let tool_part = if source_tool.is_empty() {
            String::new()
        } else {
            format!(" ({source_tool})")
        };
        let source = o.get(Field::Source, opts).map_or_else(
            || {
                format!(
                    "ReqIF file {}{tool_part}{spec_part}, object {raw_id}",
                    file.file_name()
                        .map_or(fname.clone(), |n| n.to_string_lossy().into_owned())
                )
            },
            str::to_string,
        );
        let mut missing = Vec::new();
        let mut qualitative = None;
        let (limit, limit_si, dim_from_limit) = match o.get(Field::Limit, opts) {
            Some(l) => match parse_limit(l) {
                Ok((q, d)) => (l.to_string(), Some(q), Some(d)),
                Err(e) => {
                    missing.push(e);
                    (l.to_string(), None, None)
                }
            },
            None => {
                qualitative = Some(format!(
                    "no limit (attribute {}): qualitative",
                    attr_names(Field::Limit, opts)
                ));
                (String::new(), None, None)
            }
        };
        let method = match o.get(Field::Method, opts) {
            Some(m) => match method_of(m) {
                Ok(m) => m.to_string(),
                Err(e) => {
                    missing.push(e);
                    String::new()
                }
            },
            // a qualitative requirement is closed by review of design unless the file says
            // otherwise; a limit without a method is not given one
            None if qualitative.is_some() => "review-of-design".to_string(),
            None => {
                missing.push(format!(
                    "no verification method (attribute {})",
                    attr_names(Field::Method, opts)
                ));
                String::new()
            }
        };
        let mut dimension = o
            .get(Field::Dimension, opts)
            .map(str::to_string)
            .or(dim_from_limit)
            .unwrap_or_default();
        let mut probability = o.get(Field::Probability, opts).map(str::to_string);
        let check = o.get(Field::Check, opts).map(str::to_string);
        let mut spectrum = match (
            o.get(Field::SpectrumBand, opts),
            o.get(Field::SpectrumShape, opts),
        ) {
            (Some(b), Some(sh)) => Some((b.to_string(), sh.to_string())),
            (None, None) => None,
            _ => {
                missing.push(format!(
                    "a spectral limit needs both {} and {}",
                    attr_names(Field::SpectrumBand, opts),
                    attr_names(Field::SpectrumShape, opts)
                ));
                None
            }
        };
        if qualitative.is_some() {
            if let Some((b, sh)) = spectrum.take() {
                notes.push(format!("spectrum '{b}', '{sh}' stated without a limit"));
            }
            // what is tied to a limit cannot be kept without one: said in the note
            if !dimension.is_empty() {
                notes.push(format!("dimension '{dimension}' stated without a limit"));
                dimension.clear();
            }
            if let Some(p) = probability.take() {
                notes.push(format!("probability '{p}' stated without a limit"));
            }
            if let Some(c) = &check {
                missing.push(format!(
                    "check `{c}` named but no limit (attribute {}) to judge its value against",
                    attr_names(Field::Limit, opts)
                ));
            }
        }
        let family = place
            .family
            .clone()
            .or_else(|| place.spec.clone().map(|s| (s, None)))
            .unwrap_or_else(|| (stem.clone(), None));
        let note = o.get(Field::Note, opts).map(str::to_string);
        req_of_ident.insert(o.ident.clone(), pending.len());
        pending.push(Pending {
            req: ImportedRequirement {
                id,
                title,
                text: text.to_string(),
                source,
                quantity: o.get(Field::Quantity, opts).unwrap_or("").to_string(),
                dimension,
                limit,
                probability,
                spectrum,
                level: o.get(Field::Level, opts).map(str::to_string),
                stage: o.get(Field::Stage, opts).map(str::to_string),
                method,
                activity: o
                    .get(Field::Activity, opts)
                    .unwrap_or("not stated in the ReqIF file")
                    .to_string(),
                check,
                parent: None,
                note,
                line: o.line,
            },
            ident: o.ident.clone(),
            family,
            missing,
            qualitative,
            limit_si,
            extra_notes: notes,
        });
    }

    // relations
    let mut relations = 0;
    if let Some(rels) = child(content, "SPEC-RELATIONS") {
        for rel in elements(rels).filter(|n| n.tag_name().name() == "SPEC-RELATION") {
            relations += 1;
            let tr =
                ref_in(rel, "TYPE").ok_or_else(|| ctx.err(rel, "SPEC-RELATION without TYPE"))?;
            let ty = model.resolve(&ctx, tr, "SPEC-RELATION-TYPE")?;
            let type_name = ty.attribute("LONG-NAME").unwrap_or("relation").to_string();
            let end = |w: &str| -> Result<String, ImportError> {
                let r = ref_in(rel, w)
                    .ok_or_else(|| ctx.err(rel, format!("SPEC-RELATION without {w}")))?;
                let at = r.1;
                let n = model.resolve(&ctx, r, "SPEC-OBJECT")?;
                let id = n.attribute("IDENTIFIER").unwrap_or("").to_string();
                if !by_ident.contains_key(&id) {
                    return Err(ctx.err(at, format!("{w} `{id}` is not a SPEC-OBJECT")));
                }
                Ok(id)
            };
            let (src, dst) = (end("SOURCE")?, end("TARGET")?);
            let (Some(&si), Some(&ti)) = (req_of_ident.get(&src), req_of_ident.get(&dst)) else {
                continue; // a link to or from a heading or a non-requirement object
            };
            let values = model.values(&ctx, rel)?;
            let margin_attr = values
                .iter()
                .find(|v| {
                    norm(&v.name) == norm("geodesic.DerivationMargin")
                        || norm(&v.name) == norm("Margin")
                })
                .map(|v| v.text.trim().to_string());
            let is_parent = PARENT_RELATIONS.iter().any(|p| norm(p) == norm(&type_name));
            let target_id = pending[ti].req.id.clone();
            // a margin links two limits: a qualitative end keeps the link in its note
            let both_limits =
                pending[si].qualitative.is_none() && pending[ti].qualitative.is_none();
            let mut as_note = !is_parent || !both_limits || pending[si].req.parent.is_some();
            if !as_note {
                let margin = match margin_attr {
                    Some(m) => Some(m.parse::<f64>().map_err(|_| {
                        ctx.err(rel, format!("derivation margin `{m}` is not a number"))
                    })?),
                    None => match (pending[si].limit_si, pending[ti].limit_si) {
                        (Some(c), Some(p)) if c.dim == p.dim && p.value != 0.0 => {
                            Some(c.value / p.value)
                        }
                        _ => None,
                    },
                };
                match margin {
                    Some(m) => pending[si].req.parent = Some((target_id.clone(), m)),
                    None => as_note = true,
                }
            }
            if as_note {
                pending[si]
                    .extra_notes
                    .push(format!("ReqIF relation '{type_name}' to {target_id}"));
            }
        }
    }

    // incomplete requirements
    let incomplete: Vec<&Pending> = pending.iter().filter(|p| !p.missing.is_empty()).collect();
    if !incomplete.is_empty() && !opts.skip_incomplete {
        let p = incomplete[0];
        let more = if incomplete.len() > 1 {
            format!(
                " (and {} more requirements: {}; --skip-incomplete imports the others)",
                incomplete.len() - 1,
                incomplete[1..]
                    .iter()
                    .take(5)
                    .map(|p| format!("{} at line {}", p.req.id, p.req.line))
                    .collect::<Vec<_>>()
                    .join(", ")
                    + if incomplete.len() > 6 { ", ..." } else { "" }
            )
        } else {
            String::new()
        };
        return Err(ImportError {
            file: fname,
            line: p.req.line,
            cause: format!(
                "requirement {} (object {}) cannot be judged by geodesic: {}{more}",
                p.req.id,
                p.ident,
                p.missing.join("; ")
            ),
        });
    }
    // with skip_incomplete, only complete quantitative requirements are kept
    let left_out =
        |p: &Pending| !p.missing.is_empty() || (opts.skip_incomplete && p.qualitative.is_some());
    let skipped: Vec<Skipped> = pending
        .iter()
        .filter(|p| left_out(p))
        .map(|p| Skipped {
            id: p.req.id.clone(),
            line: p.req.line,
            missing: p.qualitative.iter().chain(&p.missing).cloned().collect(),
        })
        .collect();
    let skipped_ids: HashSet<String> = skipped.iter().map(|s| s.id.clone()).collect();
    let mut kept: Vec<Pending> = pending.into_iter().filter(|p| !left_out(p)).collect();
    let qualitative = kept.iter().filter(|p| p.qualitative.is_some()).count();
    for p in &mut kept {
        if let Some((pid, _)) = &p.req.parent
            && skipped_ids.contains(pid)
        {
            p.extra_notes.push(format!(
                "parent {pid} not imported (incomplete or qualitative in the ReqIF file)"
            ));
            p.req.parent = None;
        }
        if !p.extra_notes.is_empty() {
            let mut parts: Vec<String> = p.req.note.take().into_iter().collect();
            parts.append(&mut p.extra_notes);
            p.req.note = Some(parts.join("; "));
        }
    }
    if kept.is_empty() {
        let line = skipped.first().map_or(1, |s| s.line);
        return Err(ImportError {
            file: fname,
            line,
            cause: if skipped.is_empty() {
                if untexted_attributes.is_empty() {
                    format!(
                        "no requirement in this file ({headings} headings, {other_objects} objects without text)"
                    )
                } else {
                    format!(
                        "no requirement in this file ({headings} headings, {other_objects} objects without text); \
                         their attributes with a value: {}; if one holds the requirement text, name it with \
                         --attribute text=NAME",
                        untexted_attributes.join(", ")
                    )
                }
            } else {
                format!(
                    "none of its {} requirements has both a limit and a verification method: nothing to import",
                    skipped.len()
                )
            },
        });
    }

    // families in order of first appearance, one file each
    let mut fams: Vec<ImportedFamily> = Vec::new();
    for p in kept {
        let (name, desc) = p.family;
        match fams.iter_mut().find(|f| f.family == name) {
            Some(f) => f.requirements.push(p.req),
            None => fams.push(ImportedFamily {
                family: name,
                description: desc,
                file_name: String::new(),
                requirements: vec![p.req],
                yaml: String::new(),
            }),
        }
    }
    let mut used: HashSet<String> = HashSet::new();
    let mut names: Vec<String> = Vec::new();
    for f in &fams {
        let base = match slug(&f.family) {
            s if s.is_empty() => "requirements".to_string(),
            s => s,
        };
        let mut n = base.clone();
        let mut k = 2;
        while !used.insert(n.clone()) {
            n = format!("{base}-{k}");
            k += 1;
        }
        names.push(n);
    }
    // the loader reads files sorted by name: number them when that would change the order
    let mut sorted = names.clone();
    sorted.sort();
    let numbered = sorted != names;
    let comment = format!(
        "Imported by `geodesic import reqif` from {}{}.\nThe ReqIF attributes read for each field are listed in docs/exchange.md.",
        file.file_name()
            .map_or(fname.clone(), |n| n.to_string_lossy().into_owned()),
        if source_tool.is_empty() {
            String::new()
        } else {
            format!(" (written by {source_tool})")
        }
    );
    let mut sources: Vec<(PathBuf, String)> = Vec::new();
    let mut spans: Vec<Vec<(u64, u64)>> = Vec::new();
    for (i, (f, n)) in fams.iter_mut().zip(&names).enumerate() {
        f.file_name = if numbered {
            format!("{:02}-{n}.yaml", i + 1)
        } else {
            format!("{n}.yaml")
        };
        let (text, sp) = yaml::family_file(f, &comment);
        f.yaml = text;
        sources.push((PathBuf::from(&f.file_name), f.yaml.clone()));
        spans.push(sp);
    }
    // what is written must load: a limit, unit or derivation the loader refuses is reported at
    // the requirement's line in the ReqIF file
    if let Err(e) = Requirements::from_sources(&sources) {
        let fi = sources
            .iter()
            .position(|(p, _)| *p == e.origin.file)
            .unwrap_or(0);
        let hit = spans[fi]
            .iter()
            .position(|(a, b)| (*a..=*b).contains(&e.origin.line));
        let (line, id) = match hit {
            Some(k) => {
                let r = &fams[fi].requirements[k];
                (r.line, r.id.clone())
            }
            None => (1, "?".into()),
        };
        return Err(ImportError {
            file: fname,
            line,
            cause: format!("requirement {id}: {}", e.cause),
        });
    }
    Ok(Imported {
        families: fams,
        skipped,
        qualitative,
        source_tool,
        headings,
        other_objects,
        relations,
    })
}

fn attr_names(f: Field, opts: &ImportOptions) -> String {
    match opts.attribute.get(&f) {
        Some(n) => format!("`{n}`"),
        None => f
            .candidates()
            .iter()
            .map(|c| format!("`{c}`"))
            .collect::<Vec<_>>()
            .join(" or "),
    }
}

#[allow(clippy::too_many_arguments)]
fn walk<'a, 'i>(
    ctx: &Ctx,
    model: &Model<'a, 'i>,
    children: Node<'a, 'i>,
    place: &Place,
    objects: &[Object],
    by_ident: &HashMap<String, usize>,
    opts: &ImportOptions,
    order: &mut Vec<(usize, Place)>,
    placed: &mut HashSet<usize>,
) -> Result<(), ImportError> {
    for h in elements(children).filter(|n| n.tag_name().name() == "SPEC-HIERARCHY") {
        let mut inner = place.clone();
        if let Some(r) = ref_in(h, "OBJECT") {
            let at = r.1;
            let n = model.resolve(ctx, r, "SPEC-OBJECT")?;
            let id = n.attribute("IDENTIFIER").unwrap_or("");
            let &i = by_ident
                .get(id)
                .ok_or_else(|| ctx.err(at, format!("`{id}` is not a SPEC-OBJECT")))?;
            if placed.insert(i) {
                order.push((i, place.clone()));
            }
            if is_heading(&objects[i], opts) {
                inner.family = Some(heading_of(&objects[i], opts));
            }
        }
        if let Some(ch) = child(h, "CHILDREN") {
            walk(
                ctx, model, ch, &inner, objects, by_ident, opts, order, placed,
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_from_other_tools() {
        assert_eq!(to_req_id("REL-GPRM-VEL"), "REL-GPRM-VEL");
        assert_eq!(to_req_id("LOREM-818"), "LOREM-818");
        assert_eq!(to_req_id("sys_req 12"), "SYS-REQ-12");
        assert_eq!(to_req_id("42"), "REQ-42");
        assert_eq!(to_req_id("_3a15c15b-8af5"), "REQ-3A15C15B-8AF5");
        assert_eq!(to_req_id("--"), "REQ");
    }

    #[test]
    fn methods_as_tools_write_them() {
        assert_eq!(method_of("Test").unwrap(), "test");
        assert_eq!(method_of("A").unwrap(), "analysis");
        assert_eq!(method_of("Review of Design").unwrap(), "review-of-design");
        assert_eq!(method_of("RoD").unwrap(), "review-of-design");
        assert_eq!(method_of("Inspection, Test").unwrap(), "inspection");
        assert!(
            method_of("Demonstration")
                .unwrap_err()
                .contains("Demonstration")
        );
    }
}
