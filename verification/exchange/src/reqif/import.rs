//! A ReqIF file read into geodesic requirements.
//!
//! Reads what geodesic writes and what DOORS, DOORS Next, Polarion, ReqIF Studio, Enterprise
//! Architect, Capella and other tools write: attribute values of every datatype (XHTML read as
//! text, enumerations by the label of their values, defaults of attribute definitions), the
//! SPEC-HIERARCHY of each specification (headings become families), and SPEC-RELATIONs
//! (derivations become parents; other links are kept in the note). Elements are matched by
//! local name, so files of the ReqIF 1.0.1 namespace (`http://www.omg.org/spec/ReqIF/20101201`)
//! are read too.
//!
//! **What real tools write is imported, and each problem is said.** A reference to an element
//! the export left out (an object of the hierarchy or of a relation, a type, an attribute
//! definition, an enumeration value), an object defined twice, an ID attribute whose values are
//! empty or shared by several objects, an attribute value that cannot be read: each is a
//! [`Warning`] with its line, and the import goes on with what is meaningful (see
//! `docs/exchange.md`). [`ImportOptions::strict`] refuses the file with its first problem
//! instead. The file is refused whatever the options only when it is not a ReqIF document or
//! holds no requirement at all.
//!
//! Field by field (the first attribute present wins; names compared without case, spaces,
//! `_` and `-`; `ImportOptions::attribute` replaces a list by one name), see [`Field`] and
//! `docs/exchange.md`. Every object is accounted for: it is a requirement, a heading (a
//! family), an object without any text, a duplicate, or a requirement left out (listed in
//! [`Imported::skipped`]); [`Imported::spec_objects`] counts them all, as a ReqIF parser counts
//! SPEC-OBJECTs.

use super::CHAPTER_NAME;
use super::fields::{
    BOOKKEEPING, Field, HEADING_ATTRIBUTES, lenient_number, method_of, norm, parse_limit, slug,
    to_req_id,
};
pub use super::read::Warning;
use super::read::{AttrValue, Kind, Model, Object, child, elements, ref_in};
use super::yaml;
use geodesic_core::Requirements;
use geodesic_core::units::Quantity;
use geodesic_util::text::clip;
use roxmltree::{Document, Node, ParsingOptions};
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::path::{Path, PathBuf};

/// Largest number of XML nodes read (a guard on memory: about 20 million nodes of a ReqIF file
/// of a few hundred MB).
pub const MAX_NODES: u32 = 20_000_000;

/// Why a ReqIF file was refused. Display is one line: `file:line: cause`.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{file}:{line}: {}", geodesic_util::text::one_line(.cause))]
pub struct ImportError {
    /// The ReqIF file.
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// One-line cause.
    pub cause: String,
}

/// How to import.
#[derive(Clone, Debug, Default)]
pub struct ImportOptions {
    /// Import only complete quantitative requirements: leave out the qualitative ones (no
    /// limit) too; all are listed in [`Imported::skipped`].
    pub skip_incomplete: bool,
    /// The attribute (LONG-NAME) that supplies a field, replacing the built-in list.
    pub attribute: BTreeMap<Field, String>,
    /// Refuse the file at its first problem (by line) instead of importing what is meaningful
    /// with a warning per problem.
    pub strict: bool,
    /// The checks `verify` can run: a `geodesic.Check` naming another is left out with a
    /// warning (`None`: not checked here).
    pub checks: Option<BTreeSet<String>>,
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

/// A requirement left out: a field geodesic needs is missing or cannot be read (a warning
/// says so), or, with [`ImportOptions::skip_incomplete`], it is qualitative.
#[derive(Clone, Debug)]
pub struct Skipped {
    /// geodesic ID it would have had.
    pub id: String,
    /// Line of the SPEC-OBJECT.
    pub line: u32,
    /// What is missing, one phrase each.
    pub missing: Vec<String>,
}

/// Where one field's values came from: `attribute `NAME``, or the fallback used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MappingRow {
    /// The field.
    pub field: Field,
    /// Each source with the number of requirements it supplied.
    pub sources: Vec<(String, usize)>,
}

/// The result of an import.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The document read, as messages name it: the file, or `ARCHIVE!DOCUMENT` for a
    /// `.reqifz` ([`super::import_file`]).
    pub document: String,
    /// Families in document order.
    pub families: Vec<ImportedFamily>,
    /// Requirements left out.
    pub skipped: Vec<Skipped>,
    /// Requirements imported as qualitative (no limit).
    pub qualitative: usize,
    /// `SOURCE-TOOL-ID` of the header.
    pub source_tool: String,
    /// SPEC-OBJECT elements in the file (what a ReqIF parser counts): requirements imported,
    /// headings, objects without text, duplicates and skipped requirements add up to it.
    pub spec_objects: usize,
    /// Heading objects read (families).
    pub headings: usize,
    /// Objects without any text: not requirements.
    pub other_objects: usize,
    /// SPEC-OBJECTs defined a second time with the same IDENTIFIER (ignored).
    pub duplicates: usize,
    /// SPEC-RELATIONs read.
    pub relations: usize,
    /// The file's problems, by line; empty for a file geodesic wrote.
    pub warnings: Vec<Warning>,
    /// Which attribute supplied each field (the import's report).
    pub mapping: Vec<MappingRow>,
    /// Attributes with values on the imported requirements that no field took, with the
    /// number of requirements carrying each (candidates for `--attribute`).
    pub unmapped: Vec<(String, usize)>,
}

impl Imported {
    /// Number of requirements imported.
    pub fn count(&self) -> usize {
        self.families.iter().map(|f| f.requirements.len()).sum()
    }
}

fn get<'o>(o: &'o Object, f: Field, opts: &ImportOptions) -> Option<&'o AttrValue> {
    match opts.attribute.get(&f) {
        Some(name) => o.get_any(&[name.as_str()]),
        None => o.get_keys(f.candidate_keys()),
    }
}

fn text_of<'o>(o: &'o Object, f: Field, opts: &ImportOptions) -> Option<&'o str> {
    get(o, f, opts).map(|v| v.text.trim())
}

/// The text attributes, shortly: the one named with `--attribute`, else the first few known.
fn text_attribute_names(opts: &ImportOptions) -> String {
    match opts.attribute.get(&Field::Text) {
        Some(n) => format!("attribute `{}`", clip(n, 80)),
        None => format!(
            "`ReqIF.Text`, `Object Text`, `Description` or the {} others of docs/exchange.md",
            Field::Text.candidates().len() - 3
        ),
    }
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

/// Where an object sits: the nearest heading above it, else its specification.
#[derive(Clone, Debug, Default)]
struct Place {
    family: Option<(String, Option<String>)>,
    spec: Option<String>,
}

fn is_heading(o: &Object, opts: &ImportOptions) -> bool {
    let chapter = o.get_any(HEADING_ATTRIBUTES).is_some();
    let text = get(o, Field::Text, opts).is_some();
    o.type_name.to_lowercase().contains("heading") || (chapter && !text)
}

fn heading_of(o: &Object, opts: &ImportOptions) -> (String, Option<String>) {
    let name = o
        .get_any(HEADING_ATTRIBUTES)
        .or(get(o, Field::Title, opts))
        .map(|v| v.text.trim())
        .or(o.long_name.as_deref())
        .unwrap_or(&o.ident)
        .to_string();
    let desc = text_of(o, Field::Text, opts).map(str::to_string);
    (name, desc)
}

/// Names (as [`norm`]ed) that are never an object's text when the file has no text attribute.
fn not_text(key: &str) -> bool {
    static SET: std::sync::OnceLock<HashSet<String>> = std::sync::OnceLock::new();
    SET.get_or_init(|| {
        BOOKKEEPING
            .iter()
            .chain(HEADING_ATTRIBUTES)
            .chain(
                Field::ALL
                    .iter()
                    .filter(|f| **f != Field::Text)
                    .flat_map(|f| f.candidates()),
            )
            .map(|n| norm(n))
            .collect()
    })
    .contains(key)
}

/// Bookkeeping and heading attributes (as [`norm`]ed): never listed as unmapped.
fn bookkeeping(key: &str) -> bool {
    static SET: std::sync::OnceLock<HashSet<String>> = std::sync::OnceLock::new();
    SET.get_or_init(|| {
        BOOKKEEPING
            .iter()
            .chain(HEADING_ATTRIBUTES)
            .chain(&[super::PREFIX])
            .map(|n| norm(n))
            .collect()
    })
    .contains(key)
}

/// The text of an object with none of the text attributes: its longest XHTML value, else its
/// longest string value (bookkeeping and other fields' attributes excluded).
fn auto_text(o: &Object) -> Option<&AttrValue> {
    let longest = |kind: Kind| {
        o.values
            .iter()
            .filter(|v| v.kind == kind && !v.text.trim().is_empty() && !not_text(&v.key))
            .max_by_key(|v| v.text.trim().chars().count())
    };
    longest(Kind::Xhtml).or_else(|| longest(Kind::String))
}

/// An object that is a requirement: its text and where the text came from.
struct Cand {
    index: usize,
    place: Place,
    text: String,
    source: String,
    key: Option<String>,
    embedded: Vec<String>,
}

impl Cand {
    fn of(index: usize, place: &Place, v: &AttrValue, source: String) -> Cand {
        Cand {
            index,
            place: place.clone(),
            text: v.text.trim().to_string(),
            source,
            key: Some(v.key.clone()),
            embedded: v.embedded.clone(),
        }
    }
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
    /// The value of the ID attribute (with its prefix), if the object has one.
    raw_id: Option<(String, String)>,
    family: (String, Option<String>),
    missing: Vec<String>,
    /// No limit in the file: imported as a qualitative requirement (`missing` says why not
    /// quantitative, for `skip_incomplete`).
    qualitative: Option<String>,
    limit_si: Option<Quantity>,
    extra_notes: Vec<String>,
    /// Field -> where its value came from.
    sources: Vec<(Field, String)>,
    /// Attributes a field took.
    used: HashSet<String>,
}

/// Reads a ReqIF document (`file` names it in messages) into requirement families.
pub fn import(file: &Path, text: &str, opts: &ImportOptions) -> Result<Imported, ImportError> {
    let (result, warnings) = read(file, text, opts);
    if opts.strict
        && let Some(first) = warnings.first()
    {
        let more = match warnings.len() {
            1 => String::new(),
            n => format!("; {} more problems", n - 1),
        };
        return Err(ImportError {
            file: file.display().to_string(),
            line: first.line,
            cause: format!(
                "{} (--strict refuses the file at its first problem{more}; without it, each is a warning)",
                first.cause
            ),
        });
    }
    result.map(|mut imp| {
        imp.warnings = warnings;
        imp
    })
}

fn read(
    file: &Path,
    text: &str,
    opts: &ImportOptions,
) -> (Result<Imported, ImportError>, Vec<Warning>) {
    let fname = file.display().to_string();
    let fail = |line: u32, cause: String| ImportError {
        file: fname.clone(),
        line,
        cause,
    };
    if text.starts_with("PK") {
        return (
            Err(fail(
                1,
                "this is a zip archive (.reqifz): unzip it and import the .reqif file inside"
                    .into(),
            )),
            Vec::new(),
        );
    }
    let po = ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_NODES,
        ..ParsingOptions::default()
    };
    let doc = match Document::parse_with_options(text, po) {
        Ok(d) => d,
        Err(e) => {
            return (
                Err(fail(e.pos().row, format!("malformed XML: {e}"))),
                Vec::new(),
            );
        }
    };
    let root = doc.root_element();
    let ns_ok = root
        .tag_name()
        .namespace()
        .is_some_and(|n| n.starts_with("http://www.omg.org/spec/ReqIF/"));
    if root.tag_name().name() != "REQ-IF" || !ns_ok {
        return (
            Err(fail(
                doc.text_pos_at(root.range().start).row,
                format!(
                    "not a ReqIF file: the root element is `{}` in namespace `{}` (expected REQ-IF in {})",
                    clip(root.tag_name().name(), 80),
                    clip(root.tag_name().namespace().unwrap_or(""), 120),
                    super::NAMESPACE
                ),
            )),
            Vec::new(),
        );
    }
    let Some(content) = child(root, "CORE-CONTENT").and_then(|c| child(c, "REQ-IF-CONTENT")) else {
        return (
            Err(fail(
                doc.text_pos_at(root.range().start).row,
                "no CORE-CONTENT/REQ-IF-CONTENT: the file holds no requirement".into(),
            )),
            Vec::new(),
        );
    };
    let mut model = Model::new(&doc, content);
    let result = read_content(file, &fname, root, content, &mut model, opts);
    let problems = std::mem::take(&mut model.problems);
    (result, problems.finish())
}

/// What does not change from one requirement to the next: the file (`fname` as messages name
/// it), its header's `SOURCE-TOOL-ID`, the document's stem (the family of objects outside any
/// specification) and the options.
struct Context<'c> {
    file: &'c Path,
    fname: &'c str,
    source_tool: &'c str,
    stem: &'c str,
    opts: &'c ImportOptions,
}

impl Context<'_> {
    fn fail(&self, line: u32, cause: String) -> ImportError {
        ImportError {
            file: self.fname.to_string(),
            line,
            cause,
        }
    }
}

/// The SPEC-OBJECTs in document order (a second definition of an identifier is ignored, said),
/// indexed by identifier.
struct Objects {
    list: Vec<Object>,
    by_ident: HashMap<String, usize>,
    /// SPEC-OBJECT elements read, duplicates included.
    spec_objects: usize,
    /// Second definitions ignored.
    duplicates: usize,
}

/// What the objects are: the number of headings (families), the requirements (with their
/// text), and the number of objects without any text.
struct Sorted {
    headings: usize,
    cands: Vec<Cand>,
    other_objects: usize,
}

fn read_content<'a, 'i>(
    file: &Path,
    fname: &str,
    root: Node<'a, 'i>,
    content: Node<'a, 'i>,
    model: &mut Model<'a, 'i>,
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let source_tool = source_tool(root);
    let stem = document_stem(file);
    let ctx = Context {
        file,
        fname,
        source_tool: &source_tool,
        stem: &stem,
        opts,
    };
    schema_attributes(content, model);
    let objects = read_objects(content, model);
    named_attributes_exist(content, &objects.list, opts).map_err(|cause| ctx.fail(1, cause))?;
    let order = document_order(content, model, &objects, opts);
    let sorted = sort_objects(&order, &objects.list, model, opts);
    let mut pending: Vec<Pending> = Vec::new();
    for c in sorted.cands {
        let o = &objects.list[c.index];
        pending.push(ctx.pending(c, o, model));
    }
    assign_ids(&mut pending, model);
    let relations = read_relations(content, model, &mut pending);
    check_derivations(&mut pending, model);
    let (kept, skipped) = leave_out_incomplete(pending, model, opts);
    let counts = Counts {
        spec_objects: objects.spec_objects,
        headings: sorted.headings,
        other_objects: sorted.other_objects,
        duplicates: objects.duplicates,
        relations,
    };
    write_loading(&ctx, kept, skipped, &objects, &counts, model)
}

/// The header's `SOURCE-TOOL-ID` (empty when none).
fn source_tool(root: Node) -> String {
    child(root, "THE-HEADER")
        .and_then(|h| child(h, "REQ-IF-HEADER"))
        .and_then(|h| child(h, "SOURCE-TOOL-ID"))
        .and_then(|s| s.text())
        .unwrap_or("")
        .trim()
        .to_string()
}

/// The document's own name: in an archive (`a.reqifz!dir/doc.reqif`), the document's.
fn document_stem(file: &Path) -> String {
    let name = file.to_string_lossy();
    let inner = name.rsplit(['!', '/']).next().unwrap_or("");
    Path::new(inner)
        .file_stem()
        .map_or("imported".to_string(), |s| s.to_string_lossy().into_owned())
}

/// The SPEC-OBJECTs, in document order; a second definition of an identifier is ignored.
fn read_objects<'a, 'i>(content: Node<'a, 'i>, model: &mut Model<'a, 'i>) -> Objects {
    let mut objects = Objects {
        list: Vec::new(),
        by_ident: HashMap::new(),
        spec_objects: 0,
        duplicates: 0,
    };
    let Some(so) = child(content, "SPEC-OBJECTS") else {
        return objects;
    };
    for n in elements(so).filter(|n| n.tag_name().name() == "SPEC-OBJECT") {
        objects.spec_objects += 1;
        let o = model.object(n);
        if let Some(&first) = objects.by_ident.get(&o.ident) {
            objects.duplicates += 1;
            model.problems.warn(
                o.line,
                format!(
                    "SPEC-OBJECT `{}` is defined twice (first at line {}): this definition is ignored",
                    clip(&o.ident, 100),
                    objects.list[first].line
                ),
            );
            continue;
        }
        objects.by_ident.insert(o.ident.clone(), objects.list.len());
        objects.list.push(o);
    }
    objects
}

/// The attributes the user named (`--attribute`) must exist: the cause when one does not,
/// with the file's attributes.
fn named_attributes_exist(
    content: Node,
    objects: &[Object],
    opts: &ImportOptions,
) -> Result<(), String> {
    for (field, name) in &opts.attribute {
        let key = norm(name);
        let mut known: BTreeSet<String> = BTreeSet::new();
        for d in content
            .descendants()
            .filter(|d| d.is_element() && d.tag_name().name().starts_with("ATTRIBUTE-DEFINITION-"))
        {
            if let Some(n) = d.attribute("LONG-NAME").or(d.attribute("IDENTIFIER")) {
                known.insert(n.to_string());
            }
        }
        known.extend(
            objects
                .iter()
                .flat_map(|o| o.values.iter().map(|v| v.name.clone())),
        );
        if !known.iter().any(|k| norm(k) == key) {
            let list: Vec<String> = known.iter().take(30).map(|k| clip(k, 60)).collect();
            return Err(format!(
                "--attribute {}={}: no attribute `{}` in this file (its attributes: {}{})",
                field.name(),
                clip(name, 80),
                clip(name, 80),
                if list.is_empty() {
                    "none".to_string()
                } else {
                    list.join(", ")
                },
                if known.len() > 30 { ", ..." } else { "" }
            ));
        }
    }
    Ok(())
}

/// The hierarchy: every object in document order with the heading above it (objects no
/// specification names last, in the order they are defined).
fn document_order<'a, 'i>(
    content: Node<'a, 'i>,
    model: &mut Model<'a, 'i>,
    objects: &Objects,
    opts: &ImportOptions,
) -> Vec<(usize, Place)> {
    let mut order: Vec<(usize, Place)> = Vec::new();
    let mut placed: HashSet<usize> = HashSet::new();
    if let Some(specs) = child(content, "SPECIFICATIONS") {
        for spec in elements(specs).filter(|n| n.tag_name().name() == "SPECIFICATION") {
            let spec_values = model.values(spec);
            let spec_name = spec
                .attribute("LONG-NAME")
                .filter(|l| !l.trim().is_empty())
                .map(str::to_string)
                .or_else(|| {
                    spec_values
                        .iter()
                        .find(|v| v.key == norm(super::NAME) && !v.text.trim().is_empty())
                        .map(|v| v.text.trim().to_string())
                });
            let place = Place {
                family: None,
                spec: spec_name,
            };
            if let Some(ch) = child(spec, "CHILDREN") {
                walk(
                    model,
                    ch,
                    &place,
                    &objects.list,
                    &objects.by_ident,
                    opts,
                    &mut order,
                    &mut placed,
                );
            }
        }
    }
    for i in 0..objects.list.len() {
        if !placed.contains(&i) {
            order.push((i, Place::default()));
        }
    }
    order
}

/// What each object is: a heading, a requirement (with its text and where it came from), or
/// an object without text (said). A document of headings only: its headings are what it
/// says.
fn sort_objects(
    order: &[(usize, Place)],
    objects: &[Object],
    model: &mut Model,
    opts: &ImportOptions,
) -> Sorted {
    let mut heading_objects: Vec<(usize, Place)> = Vec::new();
    let mut cands: Vec<Cand> = Vec::new();
    let mut other_objects = 0;
    let mut auto_used: BTreeMap<String, (u32, usize)> = BTreeMap::new();
    for (i, place) in order {
        let o = &objects[*i];
        if is_heading(o, opts) {
            heading_objects.push((*i, place.clone()));
            continue;
        }
        // StrictDoc's free text between requirements (`[TEXT]`, type `TEXT`): not a
        // requirement, counted with the objects without a requirement text
        if o.type_name.trim().eq_ignore_ascii_case("text") {
            other_objects += 1;
            continue;
        }
        match candidate(*i, place, o, opts, &mut auto_used, model) {
            Some(c) => cands.push(c),
            None => other_objects += 1,
        }
    }
    for (name, (line, n)) in &auto_used {
        let (objs, their) = if *n == 1 {
            ("1 object has".to_string(), "its")
        } else {
            (format!("{n} objects have"), "their")
        };
        model.problems.warn(
            *line,
            format!(
                "{objs} none of the text attributes ({}): {their} longest text value, attribute `{}`, is taken as the text (--attribute text=NAME names another)",
                text_attribute_names(opts),
                clip(name, 80)
            ),
        );
    }
    let mut headings = heading_objects.len();
    if cands.is_empty() && !heading_objects.is_empty() {
        cands = headings_as_requirements(heading_objects, objects, model, opts);
        headings = 0;
    }
    Sorted {
        headings,
        cands,
        other_objects,
    }
}

/// Object `o` (index `i`, at `place`) as a requirement: its text attribute, else its longest
/// text (counted in `auto_used` by attribute: first line, objects), else its title (said);
/// `None` for an object without text, title nor name (said).
fn candidate(
    i: usize,
    place: &Place,
    o: &Object,
    opts: &ImportOptions,
    auto_used: &mut BTreeMap<String, (u32, usize)>,
    model: &mut Model,
) -> Option<Cand> {
    if let Some(v) = get(o, Field::Text, opts) {
        return Some(Cand::of(i, place, v, format!("attribute `{}`", v.name)));
    }
    if !opts.attribute.contains_key(&Field::Text)
        && let Some(v) = auto_text(o)
    {
        let e = auto_used.entry(v.name.clone()).or_insert((o.line, 0));
        e.1 += 1;
        return Some(Cand::of(
            i,
            place,
            v,
            format!(
                "attribute `{}` (the object's longest text; no text attribute)",
                v.name
            ),
        ));
    }
    let title = get(o, Field::Title, opts)
        .map(|v| {
            (
                v.text.trim().to_string(),
                format!("attribute `{}` (the title; no text)", v.name),
            )
        })
        .or_else(|| {
            o.long_name
                .clone()
                .map(|l| (l, "SPEC-OBJECT LONG-NAME (no text)".to_string()))
        });
    let Some((t, src)) = title else {
        model.problems.warn(
            o.line,
            format!(
                "SPEC-OBJECT `{}` has no text, title nor name (attributes with a value: {}): not a requirement",
                clip(&o.ident, 100),
                {
                    let names: Vec<String> = o
                        .values
                        .iter()
                        .filter(|v| !v.text.trim().is_empty())
                        .map(|v| clip(&v.name, 60))
                        .collect();
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                }
            ),
        );
        return None;
    };
    model.problems.warn(
        o.line,
        format!(
            "SPEC-OBJECT `{}` has no text ({}): its title is its text",
            clip(&o.ident, 100),
            text_attribute_names(opts)
        ),
    );
    Some(Cand {
        index: i,
        place: place.clone(),
        text: t,
        source: src,
        key: None,
        embedded: Vec::new(),
    })
}

/// A document of headings only (no object has a requirement text): its headings are
/// imported as requirements, their heading as text (said once).
fn headings_as_requirements(
    heading_objects: Vec<(usize, Place)>,
    objects: &[Object],
    model: &mut Model,
    opts: &ImportOptions,
) -> Vec<Cand> {
    model.problems.warn(
        objects[heading_objects[0].0].line,
        format!(
            "no object has a requirement text: the {} headings are imported as requirements, their heading as text",
            heading_objects.len()
        ),
    );
    let mut cands = Vec::new();
    for (i, place) in heading_objects {
        let o = &objects[i];
        let (name, desc) = heading_of(o, opts);
        let text = match desc {
            Some(d) if d != name => format!("{name}\n{d}"),
            _ => name,
        };
        let key = o.get_any(HEADING_ATTRIBUTES).map(|v| v.key.clone());
        cands.push(Cand {
            index: i,
            place,
            text,
            source: "heading (no object has a requirement text)".into(),
            key,
            embedded: Vec::new(),
        });
    }
    cands
}

/// The fields of one requirement object as they are read: where each value came from, the
/// notes to add, and what is missing for geodesic to judge it.
struct Fields<'o> {
    o: &'o Object,
    opts: &'o ImportOptions,
    /// Field -> where its value came from.
    sources: Vec<(Field, String)>,
    notes: Vec<String>,
    missing: Vec<String>,
}

/// The limit of a requirement as read.
struct ReadLimit {
    /// As written (a decimal comma read as a point); empty when none.
    text: String,
    /// In SI, when it could be read.
    si: Option<Quantity>,
    /// The dimension the limit's unit gives.
    dim: Option<String>,
    /// No limit: why the requirement is qualitative.
    qualitative: Option<String>,
}

impl Fields<'_> {
    /// The value of field `f`, recording its attribute as its source.
    fn take(&mut self, f: Field) -> Option<String> {
        get(self.o, f, self.opts).map(|v| {
            self.sources.push((f, format!("attribute `{}`", v.name)));
            v.text.trim().to_string()
        })
    }

    /// The title: the title attribute, the chapter name, the LONG-NAME, else the text's first
    /// line (at most 80 characters).
    fn title(&mut self, text: &str) -> String {
        if let Some(t) = self.take(Field::Title) {
            return t;
        }
        if let Some(v) = self.o.get_any(&[CHAPTER_NAME]) {
            self.sources
                .push((Field::Title, format!("attribute `{}`", v.name)));
            return v.text.trim().to_string();
        }
        if let Some(l) = &self.o.long_name {
            self.sources
                .push((Field::Title, "SPEC-OBJECT LONG-NAME".into()));
            return l.clone();
        }
        self.sources
            .push((Field::Title, "the text's first line (80 characters)".into()));
        let first = text.lines().next().unwrap_or(text);
        if first.chars().count() > 80 {
            let cut: String = first.chars().take(80).collect();
            format!("{}...", cut.trim_end())
        } else {
            first.to_string()
        }
    }

    /// The limit: read with its unit (a decimal comma is read, said and noted), missing when
    /// it cannot be read, qualitative when there is none.
    fn limit(&mut self, model: &mut Model) -> ReadLimit {
        let Some(l) = self.take(Field::Limit) else {
            return ReadLimit {
                text: String::new(),
                si: None,
                dim: None,
                qualitative: Some(format!(
                    "no limit (attribute {}): qualitative",
                    attr_names(Field::Limit, self.opts)
                )),
            };
        };
        let (text, si, dim) = match parse_limit(&l) {
            Ok((q, d, Some(f))) => {
                model.problems.warn(
                    self.o.line,
                    format!("limit `{}` read as `{f}` (a decimal comma)", clip(&l, 80)),
                );
                self.notes
                    .push(format!("limit written `{l}` in the ReqIF file"));
                (f, Some(q), Some(d))
            }
            Ok((q, d, None)) => (l, Some(q), Some(d)),
            Err(e) => {
                self.missing.push(e);
                (l, None, None)
            }
        };
        if let Some(q) = si {
            self.check_limit_value(&text, q, model);
        }
        ReadLimit {
            text,
            si,
            dim,
            qualitative: None,
        }
    }

    /// A `geodesic.LimitValue` (in the unit of `geodesic.Unit`) that contradicts the limit as
    /// written (`limit`, `q` in SI), as after a tool edited one and not the other: said; the
    /// limit as written is taken.
    fn check_limit_value(&self, limit: &str, q: Quantity, model: &mut Model) {
        let Some(v) = self.o.get_any(&["geodesic.LimitValue"]) else {
            return;
        };
        let unit = self
            .o
            .get_any(&["geodesic.Unit"])
            .map_or(String::new(), |u| u.text.trim().to_string());
        let value = v.text.trim();
        // a unit geodesic cannot compare (a spectral density's `Hz^-1/2`) is not judged
        let agrees = match lenient_number(value) {
            None => false,
            Some(x) => match geodesic_core::units::parse_quantity(&format!("{x:e} {unit}")) {
                Ok((s, _)) if s.dim == q.dim => {
                    (s.value - q.value).abs() <= 1e-9 * q.value.abs().max(s.value.abs())
                }
                _ => true,
            },
        };
        if !agrees {
            model.problems.warn(
                self.o.line,
                format!(
                    "geodesic.LimitValue `{}{}` contradicts geodesic.Limit `{}`: the limit as \
                     written is taken; correct or remove geodesic.LimitValue",
                    clip(value, 40),
                    if unit.is_empty() {
                        String::new()
                    } else {
                        format!(" {}", clip(&unit, 20))
                    },
                    clip(limit, 80)
                ),
            );
        }
    }

    /// The verification method. A qualitative requirement is closed by review of design
    /// unless the file says otherwise: a method that cannot be read is said, and kept in the
    /// note.
    fn method(&mut self, qualitative: bool, model: &mut Model) -> String {
        let method_attr =
            get(self.o, Field::Method, self.opts).map_or(String::new(), |v| v.name.clone());
        match self.take(Field::Method) {
            Some(m) => match method_of(&m).map_err(|e| format!("attribute `{method_attr}`: {e}")) {
                Ok(m) => m.to_string(),
                Err(e) if qualitative => {
                    model.problems.warn(
                        self.o.line,
                        format!(
                            "SPEC-OBJECT `{}`: {e}: review-of-design, as for a requirement without a limit that states no method",
                            clip(&self.o.ident, 100)
                        ),
                    );
                    self.notes
                        .push(format!("verification method '{m}' in the ReqIF file"));
                    "review-of-design".to_string()
                }
                Err(e) => {
                    self.missing.push(e);
                    String::new()
                }
            },
            None if qualitative => {
                self.sources.push((
                    Field::Method,
                    "default for a qualitative requirement: review-of-design".into(),
                ));
                "review-of-design".to_string()
            }
            None => {
                self.missing.push(format!(
                    "no verification method (attribute {})",
                    attr_names(Field::Method, self.opts)
                ));
                String::new()
            }
        }
    }

    /// The band and shape of a spectral limit: both or neither.
    fn spectrum(&mut self) -> Option<(String, String)> {
        let band = self.take(Field::SpectrumBand);
        let shape = self.take(Field::SpectrumShape);
        match (band, shape) {
            (Some(b), Some(sh)) => Some((b, sh)),
            (None, None) => None,
            _ => {
                self.missing.push(format!(
                    "a spectral limit needs both {} and {}",
                    attr_names(Field::SpectrumBand, self.opts),
                    attr_names(Field::SpectrumShape, self.opts)
                ));
                None
            }
        }
    }

    /// A requirement without a limit: what is tied to a limit cannot be kept without one
    /// (spectrum, dimension, probability: said in the note; a check: the requirement is
    /// missing its limit).
    fn without_limit(
        &mut self,
        spectrum: &mut Option<(String, String)>,
        dimension: &mut String,
        probability: &mut Option<String>,
        check: Option<&String>,
    ) {
        if let Some((b, sh)) = spectrum.take() {
            self.notes
                .push(format!("spectrum '{b}', '{sh}' stated without a limit"));
        }
        if !dimension.is_empty() {
            self.notes
                .push(format!("dimension '{dimension}' stated without a limit"));
            dimension.clear();
        }
        if let Some(p) = probability.take() {
            self.notes
                .push(format!("probability '{p}' stated without a limit"));
        }
        if let Some(c) = check {
            self.missing.push(format!(
                "check `{c}` named but no limit (attribute {}) to judge its value against",
                attr_names(Field::Limit, self.opts)
            ));
        }
    }

    /// A check that `verify` does not run (of a quantitative requirement) is left out, said
    /// and noted.
    fn registered_check(
        &mut self,
        check: &mut Option<String>,
        qualitative: bool,
        model: &mut Model,
    ) {
        let (Some(c), Some(known)) = (check.as_deref(), &self.opts.checks) else {
            return;
        };
        if known.contains(c) || qualitative {
            return;
        }
        model.problems.warn(
            self.o.line,
            format!(
                "SPEC-OBJECT `{}`: check `{}` is not one geodesic runs: left out (verify reports the requirement not verified, no check)",
                clip(&self.o.ident, 100),
                clip(c, 80)
            ),
        );
        self.notes.push(format!(
            "check '{c}' named in the ReqIF file is not registered"
        ));
        *check = None;
    }
}

/// Each object embedded in the text of object `o` (`embedded`: their `data`) is kept as a
/// mention, said.
fn warn_embedded(o: &Object, embedded: &[String], model: &mut Model) {
    for data in embedded {
        model.problems.warn(
            o.line,
            format!(
                "SPEC-OBJECT `{}` embeds the object `{}` in its text: kept as [object: {}]; the object's file is not imported",
                clip(&o.ident, 100),
                clip(data, 200),
                clip(data, 200)
            ),
        );
    }
}

/// The attributes (as [`norm`]ed) a field takes on object `o`: the text's (`text_key`) and
/// those of the other fields.
fn used_keys(o: &Object, text_key: Option<String>, opts: &ImportOptions) -> HashSet<String> {
    let mut used: HashSet<String> = text_key.into_iter().collect();
    let mut used_later: Vec<String> = Vec::new();
    for field in Field::ALL {
        if field != Field::Text
            && let Some(v) = get(o, field, opts)
        {
            used_later.push(v.key.clone());
        }
    }
    used.extend(used_later);
    used
}

/// The value of the ID attribute with the prefix attribute's value before it, and the
/// attribute's name (added to `used`); an ID attribute that is there but empty is said.
fn raw_id(
    o: &Object,
    opts: &ImportOptions,
    model: &mut Model,
    used: &mut HashSet<String>,
) -> Option<(String, String)> {
    let raw_id = get(o, Field::Id, opts).map(|v| {
        let fid = v.text.trim();
        let id = match o.get_any(&[super::PREFIX]) {
            Some(p) if !fid.starts_with(p.text.trim()) => format!("{}{fid}", p.text.trim()),
            _ => fid.to_string(),
        };
        (id, v.name.clone())
    });
    if let Some((_, name)) = &raw_id {
        used.insert(norm(name));
    } else if let Some(v) = o.has_any(match opts.attribute.get(&Field::Id) {
        Some(_) => &[],
        None => Field::Id.candidates(),
    }) {
        model.problems.warn(
            o.line,
            format!(
                "SPEC-OBJECT `{}`: its ID attribute `{}` is empty: its SPEC-OBJECT identifier gives its ID",
                clip(&o.ident, 100),
                v.name
            ),
        );
    }
    raw_id
}

impl Context<'_> {
    /// The fields of requirement `c` (object `o`): a requirement waiting for its ID.
    fn pending(&self, c: Cand, o: &Object, model: &mut Model) -> Pending {
        let opts = self.opts;
        warn_embedded(o, &c.embedded, model);
        let (place, text) = (c.place, c.text);
        let mut f = Fields {
            o,
            opts,
            sources: vec![(Field::Text, c.source)],
            notes: Vec::new(),
            missing: Vec::new(),
        };
        let mut used = used_keys(o, c.key, opts);
        let raw_id = raw_id(o, opts, model, &mut used);
        let title = f.title(&text);
        let source = self.source(&mut f, &place, raw_id.as_ref(), o);
        let limit = f.limit(model);
        let qualitative = limit.qualitative.is_some();
        let method = f.method(qualitative, model);
        let mut dimension = match f.take(Field::Dimension) {
            Some(d) => d,
            None => limit.dim.unwrap_or_default(),
        };
        let mut probability = f.take(Field::Probability);
        let mut check = f.take(Field::Check);
        let mut spectrum = f.spectrum();
        if qualitative {
            f.without_limit(
                &mut spectrum,
                &mut dimension,
                &mut probability,
                check.as_ref(),
            );
        }
        f.registered_check(&mut check, qualitative, model);
        let family = self.family(&place);
        let note = f.take(Field::Note);
        let quantity = f.take(Field::Quantity).unwrap_or_default();
        let level = f.take(Field::Level);
        let stage = f.take(Field::Stage);
        let activity = f.take(Field::Activity).unwrap_or_else(|| {
            f.sources.push((
                Field::Activity,
                "default: not stated in the ReqIF file".into(),
            ));
            "not stated in the ReqIF file".to_string()
        });
        Pending {
            req: ImportedRequirement {
                id: String::new(),
                title,
                text,
                source,
                quantity,
                dimension,
                limit: limit.text,
                probability,
                spectrum,
                level,
                stage,
                method,
                activity,
                check,
                parent: None,
                note,
                line: o.line,
            },
            ident: o.ident.clone(),
            raw_id,
            family,
            missing: f.missing,
            qualitative: limit.qualitative,
            limit_si: limit.si,
            extra_notes: f.notes,
            sources: f.sources,
            used,
        }
    }

    /// The family of an object at `place`: the heading above it, else its specification, else
    /// the document's stem.
    fn family(&self, place: &Place) -> (String, Option<String>) {
        place
            .family
            .clone()
            .or_else(|| place.spec.clone().map(|s| (s, None)))
            .unwrap_or_else(|| (self.stem.to_string(), None))
    }

    /// The source: the source attribute, else the file, its tool, the specification and the
    /// object (its ID attribute's value, else its identifier).
    fn source(
        &self,
        f: &mut Fields,
        place: &Place,
        raw_id: Option<&(String, String)>,
        o: &Object,
    ) -> String {
        let spec_part = place
            .spec
            .as_ref()
            .map_or(String::new(), |s| format!(", specification '{s}'"));
        let tool_part = if self.source_tool.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.source_tool)
        };
        if let Some(s) = f.take(Field::Source) {
            return s;
        }
        f.sources
            .push((Field::Source, "the file, specification and object".into()));
        format!(
            "ReqIF file {}{tool_part}{spec_part}, object {}",
            self.file
                .file_name()
                .map_or(self.fname.to_string(), |n| n.to_string_lossy().into_owned()),
            raw_id.map_or(o.ident.as_str(), |(r, _)| r.as_str())
        )
    }
}

/// The SPEC-RELATIONs between requirements: a derivation becomes the child's parent, any
/// other link is kept in the source's note. Returns the number of relations read.
fn read_relations<'a, 'i>(
    content: Node<'a, 'i>,
    model: &mut Model<'a, 'i>,
    pending: &mut [Pending],
) -> usize {
    let req_of_ident: HashMap<String, usize> = pending
        .iter()
        .enumerate()
        .map(|(k, p)| (p.ident.clone(), k))
        .collect();
    let mut relations = 0;
    let Some(rels) = child(content, "SPEC-RELATIONS") else {
        return relations;
    };
    for rel in elements(rels).filter(|n| n.tag_name().name() == "SPEC-RELATION") {
        relations += 1;
        let line = model.line(rel);
        let type_name = match ref_in(rel, "TYPE") {
            Some(tr) => match model.resolve(
                &tr,
                "SPEC-RELATION-TYPE",
                "the relation's type is named by the reference",
            ) {
                Some(ty) => ty.attribute("LONG-NAME").unwrap_or("relation").to_string(),
                None => tr.0.clone(),
            },
            None => {
                model
                    .problems
                    .warn(line, "SPEC-RELATION without TYPE: read as a plain link");
                "relation".to_string()
            }
        };
        let mut end = |w: &str| -> Option<String> {
            let Some(r) = ref_in(rel, w) else {
                model
                    .problems
                    .warn(line, format!("SPEC-RELATION without {w}: left out"));
                return None;
            };
            let n = model.resolve(&r, "SPEC-OBJECT", "the relation is left out")?;
            Some(n.attribute("IDENTIFIER").unwrap_or("").to_string())
        };
        let (Some(src), Some(dst)) = (end("SOURCE"), end("TARGET")) else {
            continue;
        };
        let (Some(&si), Some(&ti)) = (req_of_ident.get(&src), req_of_ident.get(&dst)) else {
            continue; // a link to or from a heading or an object without text
        };
        let values = model.values(rel);
        let margin_attr = values
            .iter()
            .find(|v| v.key == norm("geodesic.DerivationMargin") || v.key == norm("Margin"))
            .map(|v| v.text.trim().to_string());
        link(pending, (si, ti), &type_name, margin_attr, line, model);
    }
    relations
}

/// Relation `type_name` (at `line`) from requirement `si` to `ti`: a derivation between two
/// limits makes `ti` the parent of `si`, with the relation's margin (`margin_attr`) or else
/// the ratio of the limits; anything else is kept in the note of `si`.
fn link(
    pending: &mut [Pending],
    (si, ti): (usize, usize),
    type_name: &str,
    margin_attr: Option<String>,
    line: u32,
    model: &mut Model,
) {
    let is_parent = PARENT_RELATIONS.iter().any(|p| norm(p) == norm(type_name));
    let target_id = pending[ti].req.id.clone();
    // a margin links two limits: a qualitative end keeps the link in its note
    let both_limits = pending[si].qualitative.is_none() && pending[ti].qualitative.is_none();
    let mut as_note = !is_parent || !both_limits || pending[si].req.parent.is_some();
    if !as_note {
        let margin = match margin_attr {
            Some(m) => match lenient_number(&m) {
                Some(v) => Some(v),
                None => {
                    model.problems.warn(
                        line,
                        format!(
                            "derivation margin `{}` is not a number: the link is kept in the note",
                            clip(&m, 80)
                        ),
                    );
                    None
                }
            },
            None => match (pending[si].limit_si, pending[ti].limit_si) {
                (Some(c), Some(p)) if c.dim == p.dim && p.value != 0.0 => {
                    let m = Some(c.value / p.value).filter(|m| m.is_finite());
                    // geodesic's own relation without its margin: a tool kept the link and
                    // dropped the attribute (StrictDoc), and a limit edited there would move
                    // the margin silently. Other tools' links carry no margin: the ratio of
                    // the limits is their margin, as documented.
                    let lost = norm(type_name) == norm("geodesic.DerivedFrom");
                    if let Some(m) = m.filter(|_| lost) {
                        model.problems.warn(
                            line,
                            format!(
                                "relation '{type_name}' from {} to {target_id} has no \
                                 geodesic.DerivationMargin: recomputed from the limits as {} \
                                 (child limit / parent limit); check it against the flow-down",
                                pending[si].req.id,
                                geodesic_core::units::fmt_num_digits(m, 6)
                            ),
                        );
                    }
                    m
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

/// Incomplete requirements are left out, each with a warning; with `skip_incomplete` the
/// qualitative ones too (the user's choice, not a problem of the file). Returns those kept
/// and those left out.
fn leave_out_incomplete(
    pending: Vec<Pending>,
    model: &mut Model,
    opts: &ImportOptions,
) -> (Vec<Pending>, Vec<Skipped>) {
    for p in pending.iter().filter(|p| !p.missing.is_empty()) {
        model.problems.warn(
            p.req.line,
            format!(
                "requirement {} (object {}) cannot be judged by geodesic: {}: left out",
                p.req.id,
                clip(&p.ident, 100),
                p.missing.join("; ")
            ),
        );
    }
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
    let kept: Vec<Pending> = pending.into_iter().filter(|p| !left_out(p)).collect();
    (kept, skipped)
}

/// What the import counted: for [`Imported`], and for the message of a file with no
/// requirement.
struct Counts {
    spec_objects: usize,
    headings: usize,
    other_objects: usize,
    duplicates: usize,
    relations: usize,
}

/// The kept requirements written as YAML files that load. What is written must load: a
/// requirement the loader refuses is left out, said at its line in the ReqIF file (first
/// every one it refuses on its own, then one at a time by the loader's message). The file is
/// refused when none is left.
fn write_loading(
    ctx: &Context,
    mut kept: Vec<Pending>,
    mut skipped: Vec<Skipped>,
    objects: &Objects,
    counts: &Counts,
    model: &mut Model,
) -> Result<Imported, ImportError> {
    let mut checked_alone = false;
    loop {
        if kept.is_empty() {
            let line = skipped.first().map_or(1, |s| s.line);
            return Err(ctx.fail(
                line,
                nothing_to_import(&skipped, &objects.list, counts, ctx.opts),
            ));
        }
        let (fams, sources, spans) =
            families(&kept, &skipped, ctx.file, ctx.fname, ctx.source_tool);
        let e = match Requirements::from_sources(&sources) {
            Ok(_) => {
                let qualitative = kept.iter().filter(|p| p.qualitative.is_some()).count();
                let (mapping, unmapped) = mapping(&kept, &objects.list, &objects.by_ident);
                return Ok(Imported {
                    document: ctx.fname.to_string(),
                    families: fams,
                    skipped,
                    qualitative,
                    source_tool: ctx.source_tool.to_string(),
                    spec_objects: counts.spec_objects,
                    headings: counts.headings,
                    other_objects: counts.other_objects,
                    duplicates: counts.duplicates,
                    relations: counts.relations,
                    warnings: Vec::new(),
                    mapping,
                    unmapped,
                });
            }
            Err(e) => e,
        };
        // first every requirement the loader refuses on its own, all at once (one load per
        // requirement, not one load of the whole set per refusal)
        if !checked_alone {
            checked_alone = true;
            if leave_out_refused_alone(&mut kept, &mut skipped, model) {
                continue;
            }
        }
        let fi = sources.iter().position(|(p, _)| *p == e.origin.file);
        let hit = fi.and_then(|fi| {
            spans[fi]
                .iter()
                .position(|(a, b)| (*a..=*b).contains(&e.origin.line))
                .map(|k| fams[fi].requirements[k].line)
        });
        let Some(line) = hit else {
            return Err(ctx.fail(
                1,
                format!("the imported requirements do not load: {}", e.cause),
            ));
        };
        let k = kept
            .iter()
            .position(|p| p.req.line == line)
            .expect("each written requirement is a kept one");
        let p = kept.remove(k);
        model.problems.warn(
            line,
            format!("requirement {}: {}: left out", p.req.id, e.cause),
        );
        skipped.push(Skipped {
            id: p.req.id,
            line,
            missing: vec![e.cause.clone()],
        });
    }
}

/// Leaves out every kept requirement that does not load on its own, each said: whether any
/// was.
fn leave_out_refused_alone(
    kept: &mut Vec<Pending>,
    skipped: &mut Vec<Skipped>,
    model: &mut Model,
) -> bool {
    let mut k = 0;
    let mut removed = false;
    while k < kept.len() {
        match loads_alone(&kept[k].req) {
            Ok(()) => k += 1,
            Err(cause) => {
                let p = kept.remove(k);
                model.problems.warn(
                    p.req.line,
                    format!("requirement {}: {cause}: left out", p.req.id),
                );
                skipped.push(Skipped {
                    id: p.req.id,
                    line: p.req.line,
                    missing: vec![cause],
                });
                removed = true;
            }
        }
    }
    removed
}

/// Why nothing is imported: no requirement in the file (its counts, and the attributes with
/// a value, one of which may hold the text), or none of those read can be imported.
fn nothing_to_import(
    skipped: &[Skipped],
    objects: &[Object],
    counts: &Counts,
    opts: &ImportOptions,
) -> String {
    if !skipped.is_empty() {
        return if opts.skip_incomplete {
            format!(
                "none of its {} requirements has both a limit and a verification method: nothing to import",
                skipped.len()
            )
        } else {
            format!(
                "none of its {} requirements can be imported (the first: {}): nothing to import",
                skipped.len(),
                skipped[0].missing.join("; ")
            )
        };
    }
    let mut names: Vec<&str> = Vec::new();
    for o in objects {
        for v in o.values.iter().filter(|v| !v.text.trim().is_empty()) {
            if !names.contains(&v.name.as_str()) {
                names.push(&v.name);
            }
        }
    }
    let hint = if names.is_empty() {
        String::new()
    } else {
        format!(
            "; their attributes with a value: {}{}; if one holds the requirement text, name it with --attribute text=NAME",
            names
                .iter()
                .take(20)
                .map(|n| clip(n, 60))
                .collect::<Vec<_>>()
                .join(", "),
            if names.len() > 20 { ", ..." } else { "" }
        )
    };
    let Counts {
        spec_objects,
        headings,
        other_objects,
        duplicates,
        ..
    } = counts;
    format!(
        "no requirement in this file ({spec_objects} SPEC-OBJECTs: {headings} headings, {other_objects} without any text, {duplicates} duplicates){hint}"
    )
}

/// The attributes the ReqIF schema requires and tools leave out: `LAST-CHANGE` on every
/// identifiable element, `MAX-LENGTH` of a string datatype, `MIN` and `MAX` of an integer one,
/// `ACCURACY`, `MIN` and `MAX` of a real one. The import needs none of them: one warning per
/// element kind and attribute, with the count and the first line.
fn schema_attributes(content: Node, model: &mut Model) {
    let mut missing: BTreeMap<(String, &'static str), (u32, usize)> = BTreeMap::new();
    for n in content.descendants().filter(|n| n.is_element()) {
        let tag = n.tag_name().name();
        let mut need: Vec<&'static str> = Vec::new();
        if n.attribute("IDENTIFIER").is_some() && tag != "ALTERNATIVE-ID" {
            need.push("LAST-CHANGE");
        }
        match tag {
            "DATATYPE-DEFINITION-STRING" => need.push("MAX-LENGTH"),
            "DATATYPE-DEFINITION-INTEGER" => need.extend(["MIN", "MAX"]),
            "DATATYPE-DEFINITION-REAL" => need.extend(["ACCURACY", "MIN", "MAX"]),
            _ => {}
        }
        for a in need {
            if n.attribute(a).is_none() {
                let line = model.line(n);
                let e = missing.entry((tag.to_string(), a)).or_insert((line, 0));
                e.1 += 1;
            }
        }
    }
    for ((tag, a), (line, n)) in missing {
        let what = if n == 1 {
            format!("1 {tag} element lacks")
        } else {
            format!("{n} {tag} elements lack")
        };
        model.problems.warn(
            line,
            format!(
                "{what} the {a} the ReqIF schema requires (the first at line {line}): read all the same"
            ),
        );
    }
}

/// IDs: the ID attribute's value made a geodesic ID; where it is empty, or not unique, the
/// SPEC-OBJECT identifier (said once per shared value); where two IDs still collide, a
/// numbered suffix.
fn assign_ids(pending: &mut [Pending], model: &mut Model) {
    let mut groups: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (k, p) in pending.iter().enumerate() {
        if let Some((raw, _)) = &p.raw_id {
            groups.entry(to_req_id(raw)).or_default().push(k);
        }
    }
    let mut from_ident: HashSet<usize> = (0..pending.len())
        .filter(|k| pending[*k].raw_id.is_none())
        .collect();
    for (id, ks) in &groups {
        if ks.len() < 2 {
            continue;
        }
        let raws: BTreeSet<&str> = ks
            .iter()
            .filter_map(|k| pending[*k].raw_id.as_ref().map(|(r, _)| r.as_str()))
            .collect();
        let attr = pending[ks[0]]
            .raw_id
            .as_ref()
            .map_or("", |(_, n)| n.as_str())
            .to_string();
        let mut at: Vec<u32> = ks.iter().map(|k| pending[*k].req.line).collect();
        at.sort_unstable();
        let lines: Vec<String> = at.iter().take(6).map(u32::to_string).collect();
        let what = if raws.len() == 1 {
            format!(
                "value `{}` of the ID attribute `{attr}`",
                clip(raws.first().unwrap_or(&""), 80)
            )
        } else {
            format!(
                "values {} of the ID attribute `{attr}` (all make the ID {id})",
                raws.iter()
                    .take(4)
                    .map(|r| format!("`{}`", clip(r, 40)))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        model.problems.warn(
            at[0],
            format!(
                "{what} is shared by {} objects (lines {}{}): their SPEC-OBJECT identifiers give their IDs",
                ks.len(),
                lines.join(", "),
                if ks.len() > 6 { ", ..." } else { "" }
            ),
        );
        from_ident.extend(ks.iter().copied());
    }
    let mut taken: HashSet<String> = HashSet::new();
    // IDs from the attribute first, so that a fallback never takes an attribute's ID
    for (k, p) in pending.iter_mut().enumerate() {
        if from_ident.contains(&k) {
            continue;
        }
        let Some((raw, attr)) = p.raw_id.clone() else {
            continue;
        };
        let id = to_req_id(&raw);
        if id != raw {
            p.extra_notes.push(format!(
                "imported from ReqIF object {} (identifier in the source tool: {raw})",
                p.ident
            ));
        }
        taken.insert(id.clone());
        p.req.id = id;
        p.sources.push((Field::Id, format!("attribute `{attr}`")));
    }
    for (k, p) in pending.iter_mut().enumerate() {
        if !from_ident.contains(&k) {
            continue;
        }
        let ident = p.ident.clone();
        let base = match (&p.raw_id, generated_identifier(&ident)) {
            // a tool that makes a new identifier on every export (StrictDoc's UUIDs): an ID
            // from the content, the same on every export
            (None, true) => content_id(&p.req.title, &p.req.text),
            _ => to_req_id(&ident),
        };
        let mut id = base.clone();
        let mut n = 2;
        while taken.contains(&id) {
            id = format!("{base}-{n}");
            n += 1;
        }
        if id != base {
            model.problems.warn(
                p.req.line,
                format!(
                    "SPEC-OBJECT `{}` gives the ID {base}, already taken: imported as {id}",
                    clip(&ident, 100)
                ),
            );
        }
        taken.insert(id.clone());
        let note = match &p.raw_id {
            Some((raw, attr)) => format!(
                "imported from ReqIF object {ident} (its {attr} `{raw}` is not unique in the file)"
            ),
            None => format!("imported from ReqIF object {ident}"),
        };
        if id != ident || p.raw_id.is_some() {
            p.extra_notes.insert(0, note);
        }
        p.req.id = id;
        p.sources.push((
            Field::Id,
            match &p.raw_id {
                Some((_, n)) => format!("SPEC-OBJECT IDENTIFIER (`{n}` not unique)"),
                None => "SPEC-OBJECT IDENTIFIER (no ID attribute)".into(),
            },
        ));
    }
}

/// Whether a SPEC-OBJECT identifier is one StrictDoc generates anew on each export of a node
/// without a UID: its node type and a random UUID (`REQUIREMENT-66d7a1a0-6c84-43d3-9ea9-
/// aa8023764b4c`). Other tools' UUIDs (ProR, DOORS) stay with their object: they are kept.
fn generated_identifier(ident: &str) -> bool {
    let groups: Vec<&str> = ident.split('-').collect();
    groups.len() == 6
        && !groups[0].is_empty()
        && groups[0]
            .chars()
            .all(|c| c.is_ascii_uppercase() || c == '_')
        && groups[1..].iter().map(|g| g.len()).eq([8, 4, 4, 4, 12])
        && groups[1..]
            .iter()
            .all(|g| g.chars().all(|c| c.is_ascii_hexdigit()))
}

/// An ID from a requirement's title and text: `REQ-` and the first 10 hexadecimal digits of
/// their SHA-256 (the same on every export of the same requirement).
fn content_id(title: &str, text: &str) -> String {
    let h =
        geodesic_util::hash::sha256_parts([("title", title.as_bytes()), ("text", text.as_bytes())]);
    format!("REQ-{}", h[..10].to_ascii_uppercase())
}

/// A derivation the loader would refuse (a margin that is not positive, limits of other
/// dimensions, a child limit that is not margin x parent limit, a chain that returns to where
/// it started) is dropped, kept in the note and said: the requirements themselves stay.
fn check_derivations(pending: &mut [Pending], model: &mut Model) {
    let index: HashMap<String, usize> = pending
        .iter()
        .enumerate()
        .map(|(k, p)| (p.req.id.clone(), k))
        .collect();
    let mut drop = |pending: &mut [Pending], k: usize, why: String| {
        let (pid, m) = pending[k].req.parent.take().expect("a derivation to drop");
        model.problems.warn(
            pending[k].req.line,
            format!(
                "derivation of {} from {pid} (margin {m}): {why}: kept in the note only",
                pending[k].req.id
            ),
        );
        pending[k]
            .extra_notes
            .push(format!("ReqIF derivation from {pid} (margin {m}): {why}"));
    };
    for k in 0..pending.len() {
        let Some((pid, m)) = pending[k].req.parent.clone() else {
            continue;
        };
        let why = match (index.get(&pid), pending[k].limit_si) {
            _ if !(m.is_finite() && m > 0.0) => Some("a margin must be a positive number".into()),
            (Some(&t), _) if t == k => Some("it names itself".into()),
            (Some(&t), Some(c)) => match pending[t].limit_si {
                Some(p) if p.dim != c.dim => Some("the two limits are of other dimensions".into()),
                Some(p) => {
                    let expect = p.value * m;
                    ((c.value - expect).abs() > 1e-9 * expect.abs()).then(|| {
                        format!(
                            "the child's limit {} is not the margin times the parent's limit {}",
                            pending[k].req.limit, pending[t].req.limit
                        )
                    })
                }
                None => Some("the parent has no limit".into()),
            },
            _ => None,
        };
        if let Some(why) = why {
            drop(pending, k, why);
        }
    }
    // a chain of derivations must end
    for start in 0..pending.len() {
        let mut seen: HashSet<usize> = HashSet::from([start]);
        let mut at = start;
        while let Some(next) = pending[at]
            .req
            .parent
            .as_ref()
            .and_then(|(pid, _)| index.get(pid).copied())
        {
            if !seen.insert(next) {
                drop(
                    pending,
                    at,
                    "the chain of derivations returns to itself".into(),
                );
                break;
            }
            at = next;
        }
    }
}

/// Whether a requirement loads as a set of its own (without its parent, which is checked
/// with the whole set): the loader's cause when it does not.
fn loads_alone(req: &ImportedRequirement) -> Result<(), String> {
    let fam = ImportedFamily {
        family: "check".into(),
        description: None,
        file_name: "check.yaml".into(),
        requirements: vec![ImportedRequirement {
            parent: None,
            ..req.clone()
        }],
        yaml: String::new(),
    };
    let (text, _) = yaml::family_file(&fam, "");
    Requirements::from_sources(&[(PathBuf::from("check.yaml"), text)])
        .map(|_| ())
        .map_err(|e| e.cause)
}

/// Requirements per YAML file: a family with more is written in several files.
pub const MAX_PER_FILE: usize = 2000;

type Written = (
    Vec<ImportedFamily>,
    Vec<(PathBuf, String)>,
    Vec<Vec<(u64, u64)>>,
);

/// Families in order of first appearance, one YAML file each.
fn families(
    kept: &[Pending],
    skipped: &[Skipped],
    file: &Path,
    fname: &str,
    source_tool: &str,
) -> Written {
    let skipped_ids: HashSet<&str> = skipped.iter().map(|s| s.id.as_str()).collect();
    let mut fams: Vec<ImportedFamily> = Vec::new();
    for p in kept {
        let mut req = p.req.clone();
        let mut notes = p.extra_notes.clone();
        if let Some((pid, _)) = &req.parent
            && skipped_ids.contains(pid.as_str())
        {
            notes.push(format!(
                "parent {pid} not imported (incomplete or qualitative in the ReqIF file)"
            ));
            req.parent = None;
        }
        if !notes.is_empty() {
            let mut parts: Vec<String> = req.note.take().into_iter().collect();
            parts.append(&mut notes);
            req.note = Some(parts.join("; "));
        }
        let (name, desc) = p.family.clone();
        // a family's requirements in files of at most MAX_PER_FILE (the YAML loader's node
        // limit holds about 20 000 entries per file)
        match fams
            .iter_mut()
            .rev()
            .find(|f| f.family == name && f.requirements.len() < MAX_PER_FILE)
        {
            Some(f) => f.requirements.push(req),
            None => fams.push(ImportedFamily {
                family: name,
                description: desc,
                file_name: String::new(),
                requirements: vec![req],
                yaml: String::new(),
            }),
        }
    }
    let mut used: HashSet<String> = HashSet::new();
    let mut names: Vec<String> = Vec::new();
    for f in &fams {
        let base = match slug(&f.family) {
            s if s.is_empty() => "requirements".to_string(),
            s => s
                .chars()
                .take(80)
                .collect::<String>()
                .trim_end_matches('-')
                .to_string(),
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
    let width = fams.len().to_string().len().max(2);
    let comment = format!(
        "Imported by `geodesic import reqif` from {}{}.\nThe ReqIF attributes read for each field are listed in docs/exchange.md.",
        file.file_name()
            .map_or(fname.to_string(), |n| n.to_string_lossy().into_owned()),
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
            format!("{:0width$}-{n}.yaml", i + 1)
        } else {
            format!("{n}.yaml")
        };
        let (text, sp) = yaml::family_file(f, &comment);
        f.yaml = text;
        sources.push((PathBuf::from(&f.file_name), f.yaml.clone()));
        spans.push(sp);
    }
    (fams, sources, spans)
}

/// The import's report: the sources of each field, and the attributes no field took.
fn mapping(
    kept: &[Pending],
    objects: &[Object],
    by_ident: &HashMap<String, usize>,
) -> (Vec<MappingRow>, Vec<(String, usize)>) {
    let mut rows: Vec<MappingRow> = Vec::new();
    for f in Field::ALL {
        let mut counts: Vec<(String, usize)> = Vec::new();
        for p in kept {
            for (g, s) in &p.sources {
                if *g == f {
                    match counts.iter_mut().find(|(c, _)| c == s) {
                        Some(c) => c.1 += 1,
                        None => counts.push((s.clone(), 1)),
                    }
                }
            }
        }
        if !counts.is_empty() {
            rows.push(MappingRow {
                field: f,
                sources: counts,
            });
        }
    }
    let mut unmapped: Vec<(String, usize)> = Vec::new();
    for p in kept {
        let Some(o) = by_ident.get(&p.ident).map(|&i| &objects[i]) else {
            continue;
        };
        let mut seen: HashSet<&str> = HashSet::new();
        for v in &o.values {
            if v.text.trim().is_empty()
                || p.used.contains(&v.key)
                || bookkeeping(&v.key)
                || !seen.insert(v.key.as_str())
            {
                continue;
            }
            match unmapped.iter_mut().find(|(n, _)| norm(n) == v.key) {
                Some(u) => u.1 += 1,
                None => unmapped.push((v.name.clone(), 1)),
            }
        }
    }
    (rows, unmapped)
}

/// The objects of a specification's hierarchy in document order, each with the heading above
/// it (depth first, with a stack: a hierarchy nested arbitrarily deep cannot overflow it).
#[allow(clippy::too_many_arguments)]
fn walk<'a, 'i>(
    model: &mut Model<'a, 'i>,
    children: Node<'a, 'i>,
    place: &Place,
    objects: &[Object],
    by_ident: &HashMap<String, usize>,
    opts: &ImportOptions,
    order: &mut Vec<(usize, Place)>,
    placed: &mut HashSet<usize>,
) {
    let entries = |n: Node<'a, 'i>| {
        let mut v: Vec<Node<'a, 'i>> = elements(n)
            .filter(|c| c.tag_name().name() == "SPEC-HIERARCHY")
            .collect();
        v.reverse();
        v
    };
    let mut stack: Vec<(Node<'a, 'i>, Place)> = entries(children)
        .into_iter()
        .map(|h| (h, place.clone()))
        .collect();
    while let Some((h, place)) = stack.pop() {
        let mut inner = place.clone();
        if let Some(r) = ref_in(h, "OBJECT") {
            let found = model
                .resolve(
                    &r,
                    "SPEC-OBJECT",
                    "the hierarchy entry is left out (its children are kept)",
                )
                .and_then(|n| n.attribute("IDENTIFIER"))
                .and_then(|id| by_ident.get(id).copied());
            if let Some(i) = found {
                if placed.insert(i) {
                    order.push((i, place.clone()));
                }
                if is_heading(&objects[i], opts) {
                    inner.family = Some(heading_of(&objects[i], opts));
                }
            }
        }
        if let Some(ch) = child(h, "CHILDREN") {
            stack.extend(entries(ch).into_iter().map(|c| (c, inner.clone())));
        }
    }
}
