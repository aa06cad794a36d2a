//! The requirement set as a ReqIF 1.2 document.
//!
//! Deterministic: the same requirement set (and matrix) gives the same bytes apart from the
//! header's `CREATION-TIME`. Identifiers derive from requirement IDs (`geodesic-req-REL-GPRM-VEL`)
//! and family positions; the header's identifier is a SHA-256 of the content; every
//! `LAST-CHANGE` (required by the schema on every identifiable) is the fixed
//! [`LAST_CHANGE`], since the file states the requirement set, not an edit history.

use super::{CHAPTER_NAME, FOREIGN_ID, NAME, NAMESPACE, TEXT, XHTML_NAMESPACE, text_to_xhtml};
use crate::status::{RowStatus, StatusSet};
use crate::xml::Writer;
use geodesic_core::Requirements;
use geodesic_core::requirement::{Method, Requirement};

/// The `LAST-CHANGE` of every element: fixed, so that the output depends on the content only.
pub const LAST_CHANGE: &str = "1970-01-01T00:00:00Z";

/// What the export needs besides the requirements.
#[derive(Clone, Debug)]
pub struct ExportOptions<'a> {
    /// `CREATION-TIME` of the header (xsd:dateTime, e.g. `2026-11-23T18:40:00Z`).
    pub creation_time: &'a str,
    /// The tool version written in `REQ-IF-TOOL-ID` (`geodesic 0.1.0`).
    pub tool_version: &'a str,
    /// The VCD status of each requirement, if a compliance matrix was given.
    pub status: Option<&'a StatusSet>,
}

#[derive(Clone, Copy)]
/// An attribute's datatype. Numbers are STRING values (the shortest decimal that reads back to
/// the same double, `7.5`, `1e-7`): StrictDoc (0.30) reads no REAL attribute, and every tool
/// reads a string (docs/exchange.md).
enum Kind {
    String,
    Xhtml,
    Enum(&'static str),
}

impl Kind {
    fn def(self) -> &'static str {
        match self {
            Kind::String => "STRING",
            Kind::Xhtml => "XHTML",
            Kind::Enum(_) => "ENUMERATION",
        }
    }

    fn datatype(self) -> &'static str {
        match self {
            Kind::String => DT_STRING,
            Kind::Xhtml => DT_XHTML,
            Kind::Enum(dt) => dt,
        }
    }
}

const DT_STRING: &str = "geodesic-dt-string";
const DT_XHTML: &str = "geodesic-dt-xhtml";
const DT_METHOD: &str = "geodesic-dt-method";
const DT_STATUS: &str = "geodesic-dt-status";
const DT_BASIS: &str = "geodesic-dt-basis";
const DT_CLOSE_OUT: &str = "geodesic-dt-close-out";

const TYPE_HEADING: &str = "geodesic-type-heading";
const TYPE_REQUIREMENT: &str = "geodesic-type-requirement";
const TYPE_DERIVED: &str = "geodesic-type-derived-from";
const TYPE_SPEC: &str = "geodesic-type-specification";

/// Largest string length declared for the string datatype.
const MAX_LENGTH: &str = "1000000";

#[derive(Clone, Copy)]
struct Attr {
    id: &'static str,
    name: &'static str,
    kind: Kind,
    desc: &'static str,
}

const fn attr(id: &'static str, name: &'static str, kind: Kind, desc: &'static str) -> Attr {
    Attr {
        id,
        name,
        kind,
        desc,
    }
}

const HEADING_ATTRS: &[Attr] = &[
    attr(
        "geodesic-ad-heading-chapter-name",
        CHAPTER_NAME,
        Kind::String,
        "requirement family (one YAML file of requirements/)",
    ),
    attr(
        "geodesic-ad-heading-text",
        TEXT,
        Kind::Xhtml,
        "description of the family",
    ),
];

const REQ_ATTRS: &[Attr] = &[
    attr(
        "geodesic-ad-req-foreign-id",
        FOREIGN_ID,
        Kind::String,
        "geodesic requirement ID",
    ),
    attr("geodesic-ad-req-name", NAME, Kind::String, "title"),
    attr(
        "geodesic-ad-req-text",
        TEXT,
        Kind::Xhtml,
        "the shall statement",
    ),
    attr(
        "geodesic-ad-req-source",
        "geodesic.Source",
        Kind::String,
        "where the requirement comes from (a source document's table or section)",
    ),
    attr(
        "geodesic-ad-req-quantity",
        "geodesic.Quantity",
        Kind::String,
        "what is measured or computed",
    ),
    attr(
        "geodesic-ad-req-dimension",
        "geodesic.Dimension",
        Kind::String,
        "dimension of the quantity (velocity, length, angle, ...)",
    ),
    attr(
        "geodesic-ad-req-limit",
        "geodesic.Limit",
        Kind::String,
        "the limit as written, with comparison and unit (<= 5 um/s)",
    ),
    attr(
        "geodesic-ad-req-limit-value",
        "geodesic.LimitValue",
        Kind::String,
        "the limit's number in the unit of geodesic.Unit",
    ),
    attr(
        "geodesic-ad-req-unit",
        "geodesic.Unit",
        Kind::String,
        "unit of geodesic.LimitValue and geodesic.Value (empty: dimensionless)",
    ),
    attr(
        "geodesic-ad-req-probability",
        "geodesic.Probability",
        Kind::String,
        "probability level the limit applies at",
    ),
    attr(
        "geodesic-ad-req-level",
        "geodesic.Level",
        Kind::String,
        "ECSS-E-ST-10-02C verification level (equipment, subsystem, element, system)",
    ),
    attr(
        "geodesic-ad-req-stage",
        "geodesic.Stage",
        Kind::String,
        "ECSS-E-ST-10-02C verification stage (qualification, acceptance, pre-launch, in-orbit, post-landing)",
    ),
    attr(
        "geodesic-ad-req-spectrum-band",
        "geodesic.SpectrumBand",
        Kind::String,
        "band of a spectral limit (F1 .. F2); the limit is its level x geodesic.SpectrumShape over it",
    ),
    attr(
        "geodesic-ad-req-spectrum-shape",
        "geodesic.SpectrumShape",
        Kind::String,
        "shape of a spectral limit over frequency f (1 + (f / 3 mHz)^2)",
    ),
    attr(
        "geodesic-ad-req-method",
        "geodesic.Method",
        Kind::Enum(DT_METHOD),
        "verification method (ECSS-E-ST-10-02C)",
    ),
    attr(
        "geodesic-ad-req-activity",
        "geodesic.Activity",
        Kind::String,
        "the verification activity that provides the evidence",
    ),
    attr(
        "geodesic-ad-req-check",
        "geodesic.Check",
        Kind::String,
        "the registered geodesic check that runs the activity",
    ),
    attr(
        "geodesic-ad-req-note",
        "geodesic.Note",
        Kind::String,
        "note",
    ),
];

const STATUS_ATTRS: &[Attr] = &[
    attr(
        "geodesic-ad-req-status",
        "geodesic.Status",
        Kind::Enum(DT_STATUS),
        "compliance status from geodesic verify",
    ),
    attr(
        "geodesic-ad-req-basis",
        "geodesic.Basis",
        Kind::Enum(DT_BASIS),
        "what the verdict rests on",
    ),
    attr(
        "geodesic-ad-req-verdict",
        "geodesic.Verdict",
        Kind::String,
        "the status as it must be read: its basis when not a model, what it assumes, a rejected input, a test problem",
    ),
    attr(
        "geodesic-ad-req-sample",
        "geodesic.Sample",
        Kind::String,
        "for a sampled value: the quantile or probability, N, the confidence bounds",
    ),
    attr(
        "geodesic-ad-req-value",
        "geodesic.Value",
        Kind::String,
        "verified value in the unit of geodesic.Unit (a sampled value: the deciding confidence bound)",
    ),
    attr(
        "geodesic-ad-req-margin",
        "geodesic.Margin",
        Kind::String,
        "margin as a fraction of the limit (0.25 = 25 %; negative: violated)",
    ),
    attr(
        "geodesic-ad-req-credibility",
        "geodesic.Credibility",
        Kind::String,
        "the verdict's credibility: its level (0-4), the weakest factor and each factor's level and why (docs/credibility.md)",
    ),
    attr(
        "geodesic-ad-req-close-out",
        "geodesic.CloseOut",
        Kind::Enum(DT_CLOSE_OUT),
        "VCD close-out",
    ),
    attr(
        "geodesic-ad-req-disposition",
        "geodesic.Disposition",
        Kind::String,
        "NCR, waiver or RFD of a known non-compliance",
    ),
    attr(
        "geodesic-ad-req-remarks",
        "geodesic.Remarks",
        Kind::String,
        "why the requirement is not verified",
    ),
];

const REL_ATTRS: &[Attr] = &[attr(
    "geodesic-ad-rel-margin",
    "geodesic.DerivationMargin",
    Kind::String,
    "child limit = margin x parent limit",
)];

const METHODS: &[&str] = &["test", "analysis", "review-of-design", "inspection"];
const STATUSES: &[&str] = &["compliant", "non-compliant", "not-verified"];
const BASES: &[&str] = &[
    "model",
    "flow-down",
    "measurement",
    "method-validation",
    "accepted",
    "illustration",
];
const CLOSE_OUTS: &[&str] = &["closed", "open"];

/// A value written for one attribute.
enum Val {
    Str(String),
    Xhtml(String),
    Real(f64),
    Enum(String),
}

fn method_str(m: Method) -> &'static str {
    match m {
        Method::Test => "test",
        Method::Analysis => "analysis",
        Method::ReviewOfDesign => "review-of-design",
        Method::Inspection => "inspection",
    }
}

/// A real number as xsd:double: Rust's shortest round-trip form (`7.5`, `1e-7`).
fn real(v: f64) -> String {
    let s = format!("{v:?}");
    if v.is_nan() {
        "NaN".into()
    } else if v.is_infinite() {
        if v > 0.0 { "INF".into() } else { "-INF".into() }
    } else {
        s
    }
}

/// An NCName piece from free text (letters, digits, `-`).
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

fn enum_value_id(dt: &str, v: &str) -> String {
    format!("{}-{}", dt.replace("-dt-", "-ev-"), slug(v))
}

fn write_values(w: &mut Writer, attrs: &[Attr], vals: &[(&str, Val)]) {
    if vals.is_empty() {
        return;
    }
    w.open("VALUES", &[]);
    for a in attrs {
        // no empty attribute value (StrictDoc refuses one): an empty string is left out, as the
        // import reads it (a dimensionless limit has no geodesic.Unit)
        for (_, v) in vals
            .iter()
            .filter(|(id, v)| *id == a.id && !matches!(v, Val::Str(s) if s.is_empty()))
        {
            let tag = format!("ATTRIBUTE-VALUE-{}", a.kind.def());
            let def_ref = format!("ATTRIBUTE-DEFINITION-{}-REF", a.kind.def());
            match v {
                Val::Str(s) => w.open(&tag, &[("THE-VALUE", s)]),
                Val::Real(x) => w.open(&tag, &[("THE-VALUE", &real(*x))]),
                Val::Xhtml(_) | Val::Enum(_) => w.open(&tag, &[]),
            }
            w.open("DEFINITION", &[]);
            w.text(&def_ref, a.id);
            w.close("DEFINITION");
            match v {
                Val::Xhtml(t) => w.raw("THE-VALUE", &text_to_xhtml(t)),
                Val::Enum(e) => {
                    w.open("VALUES", &[]);
                    w.text("ENUM-VALUE-REF", &enum_value_id(a.kind.datatype(), e));
                    w.close("VALUES");
                }
                _ => {}
            }
            w.close(&tag);
        }
    }
    w.close("VALUES");
}

fn write_attr_defs(w: &mut Writer, attrs: &[Attr]) {
    w.open("SPEC-ATTRIBUTES", &[]);
    for a in attrs {
        let tag = format!("ATTRIBUTE-DEFINITION-{}", a.kind.def());
        let mut at = vec![
            ("DESC", a.desc),
            ("IDENTIFIER", a.id),
            ("IS-EDITABLE", "true"),
            ("LAST-CHANGE", LAST_CHANGE),
            ("LONG-NAME", a.name),
        ];
        if matches!(a.kind, Kind::Enum(_)) {
            at.push(("MULTI-VALUED", "false"));
        }
        w.open(&tag, &at);
        w.open("TYPE", &[]);
        w.text(
            &format!("DATATYPE-DEFINITION-{}-REF", a.kind.def()),
            a.kind.datatype(),
        );
        w.close("TYPE");
        w.close(&tag);
    }
    w.close("SPEC-ATTRIBUTES");
}

fn write_enum(w: &mut Writer, id: &str, name: &str, values: &[&str]) {
    w.open(
        "DATATYPE-DEFINITION-ENUMERATION",
        &[
            ("IDENTIFIER", id),
            ("LAST-CHANGE", LAST_CHANGE),
            ("LONG-NAME", name),
        ],
    );
    w.open("SPECIFIED-VALUES", &[]);
    for (k, v) in values.iter().enumerate() {
        w.open(
            "ENUM-VALUE",
            &[
                ("IDENTIFIER", &enum_value_id(id, v)),
                ("LAST-CHANGE", LAST_CHANGE),
                ("LONG-NAME", v),
            ],
        );
        w.open("PROPERTIES", &[]);
        w.empty(
            "EMBEDDED-VALUE",
            &[("KEY", &k.to_string()), ("OTHER-CONTENT", v)],
        );
        w.close("PROPERTIES");
        w.close("ENUM-VALUE");
    }
    w.close("SPECIFIED-VALUES");
    w.close("DATATYPE-DEFINITION-ENUMERATION");
}

fn requirement_values(r: &Requirement, st: Option<&RowStatus>) -> Vec<(&'static str, Val)> {
    let mut v: Vec<(&'static str, Val)> = vec![
        ("geodesic-ad-req-foreign-id", Val::Str(r.id.to_string())),
        ("geodesic-ad-req-name", Val::Str(r.title.clone())),
        ("geodesic-ad-req-text", Val::Xhtml(r.text.clone())),
        ("geodesic-ad-req-source", Val::Str(r.source.clone())),
    ];
    match &r.limit {
        Some(l) => v.extend([
            ("geodesic-ad-req-quantity", Val::Str(r.quantity.clone())),
            (
                "geodesic-ad-req-dimension",
                Val::Str(
                    l.dim
                        .name()
                        .map_or_else(|| l.dim.to_string(), str::to_string),
                ),
            ),
            ("geodesic-ad-req-limit", Val::Str(l.text.clone())),
            // the limit's number in its written unit
            ("geodesic-ad-req-limit-value", Val::Real(l.in_unit())),
            ("geodesic-ad-req-unit", Val::Str(l.unit.symbol.clone())),
        ]),
        // qualitative: no limit, dimension nor unit (the importer reads their absence back)
        None if !r.quantity.is_empty() => {
            v.push(("geodesic-ad-req-quantity", Val::Str(r.quantity.clone())));
        }
        None => {}
    }
    if let Some(p) = &r.probability {
        v.push(("geodesic-ad-req-probability", Val::Str(p.clone())));
    }
    v.push(("geodesic-ad-req-level", Val::Str(r.level.as_str().into())));
    v.push(("geodesic-ad-req-stage", Val::Str(r.stage.as_str().into())));
    if let Some(sp) = &r.spectrum {
        v.push((
            "geodesic-ad-req-spectrum-band",
            Val::Str(sp.band_text.clone()),
        ));
        v.push((
            "geodesic-ad-req-spectrum-shape",
            Val::Str(sp.shape_text.clone()),
        ));
    }
    v.push((
        "geodesic-ad-req-method",
        Val::Enum(method_str(r.method).into()),
    ));
    v.push(("geodesic-ad-req-activity", Val::Str(r.activity.clone())));
    if let Some(c) = &r.check {
        v.push(("geodesic-ad-req-check", Val::Str(c.clone())));
    }
    if let Some(n) = &r.note {
        v.push(("geodesic-ad-req-note", Val::Str(n.clone())));
    }
    if let Some(s) = st {
        v.push(("geodesic-ad-req-status", Val::Enum(s.status.clone())));
        if let Some(b) = &s.basis {
            v.push(("geodesic-ad-req-basis", Val::Enum(b.clone())));
        }
        if let Some(t) = &s.verdict {
            v.push(("geodesic-ad-req-verdict", Val::Str(t.clone())));
        }
        if let Some(t) = &s.sample {
            v.push(("geodesic-ad-req-sample", Val::Str(t.clone())));
        }
        if let Some(x) = s.value.filter(|x| x.is_finite()) {
            v.push(("geodesic-ad-req-value", Val::Real(x)));
        }
        if let Some(m) = s.margin.filter(|m| m.is_finite()) {
            v.push(("geodesic-ad-req-margin", Val::Real(m)));
        }
        if let Some(c) = &s.credibility {
            v.push(("geodesic-ad-req-credibility", Val::Str(c.clone())));
        }
        v.push(("geodesic-ad-req-close-out", Val::Enum(s.close_out.clone())));
        if let Some(d) = &s.disposition {
            v.push(("geodesic-ad-req-disposition", Val::Str(d.clone())));
        }
        if let Some(reason) = &s.reason {
            v.push(("geodesic-ad-req-remarks", Val::Str(reason.clone())));
        }
    }
    v
}

/// Consecutive requirements of one family: a chapter of the specification.
struct Chapter<'a> {
    family: &'a str,
    id: String,
    items: Vec<&'a Requirement>,
}

fn chapters(reqs: &Requirements) -> Vec<Chapter<'_>> {
    let mut out: Vec<Chapter> = Vec::new();
    for r in &reqs.items {
        match out.last_mut() {
            Some(c) if c.family == r.family => c.items.push(r),
            _ => {
                let n = out.len() + 1;
                out.push(Chapter {
                    family: &r.family,
                    id: format!("geodesic-family-{n}-{}", slug(&r.family)),
                    items: vec![r],
                });
            }
        }
    }
    out
}

fn object_id(r: &Requirement) -> String {
    format!("geodesic-req-{}", r.id)
}

/// The requirement set (with the VCD status of each row when `opts.status` is given) as a
/// ReqIF 1.2 document.
pub fn export(reqs: &Requirements, opts: &ExportOptions) -> String {
    let status = opts.status;
    let chapters = chapters(reqs);
    let mut b = Writer::fragment(3);
    write_datatypes(&mut b, status.is_some());
    write_spec_types(&mut b, status.is_some());
    write_spec_objects(&mut b, reqs, &chapters, status);
    write_relations(&mut b, reqs);
    write_specification(&mut b, &chapters);
    let body = b.finish();

    let mut out = header(reqs, &chapters, opts, &body);
    out.push_str(&body);
    out.push_str("    </REQ-IF-CONTENT>\n  </CORE-CONTENT>\n</REQ-IF>\n");
    out
}

/// The datatypes: string, XHTML, the method's enumeration, and with a status the
/// enumerations of status, basis and close-out.
fn write_datatypes(b: &mut Writer, with_status: bool) {
    b.open("DATATYPES", &[]);
    b.empty(
        "DATATYPE-DEFINITION-STRING",
        &[
            ("IDENTIFIER", DT_STRING),
            ("LAST-CHANGE", LAST_CHANGE),
            ("LONG-NAME", "String"),
            ("MAX-LENGTH", MAX_LENGTH),
        ],
    );
    b.empty(
        "DATATYPE-DEFINITION-XHTML",
        &[
            ("IDENTIFIER", DT_XHTML),
            ("LAST-CHANGE", LAST_CHANGE),
            ("LONG-NAME", "Rich text"),
        ],
    );
    write_enum(b, DT_METHOD, "Verification method", METHODS);
    if with_status {
        write_enum(b, DT_STATUS, "Compliance status", STATUSES);
        write_enum(b, DT_BASIS, "Basis of the verdict", BASES);
        write_enum(b, DT_CLOSE_OUT, "Close-out", CLOSE_OUTS);
    }
    b.close("DATATYPES");
}

/// The types: heading, requirement (with the status attributes when there is a status), the
/// derivation relation and the specification.
fn write_spec_types(b: &mut Writer, with_status: bool) {
    b.open("SPEC-TYPES", &[]);
    for (tag, id, name, attrs) in [
        ("SPEC-OBJECT-TYPE", TYPE_HEADING, "Heading", HEADING_ATTRS),
        (
            "SPEC-OBJECT-TYPE",
            TYPE_REQUIREMENT,
            "Requirement",
            REQ_ATTRS,
        ),
        (
            "SPEC-RELATION-TYPE",
            TYPE_DERIVED,
            "geodesic.DerivedFrom",
            REL_ATTRS,
        ),
    ] {
        b.open(
            tag,
            &[
                ("IDENTIFIER", id),
                ("LAST-CHANGE", LAST_CHANGE),
                ("LONG-NAME", name),
            ],
        );
        if id == TYPE_REQUIREMENT && with_status {
            let all: Vec<Attr> = REQ_ATTRS.iter().chain(STATUS_ATTRS).copied().collect();
            write_attr_defs(b, &all);
        } else {
            write_attr_defs(b, attrs);
        }
        b.close(tag);
    }
    b.empty(
        "SPECIFICATION-TYPE",
        &[
            ("IDENTIFIER", TYPE_SPEC),
            ("LAST-CHANGE", LAST_CHANGE),
            ("LONG-NAME", "geodesic requirement set"),
        ],
    );
    b.close("SPEC-TYPES");
}

/// The objects: the family headings, then the requirements.
fn write_spec_objects(
    b: &mut Writer,
    reqs: &Requirements,
    chapters: &[Chapter],
    status: Option<&StatusSet>,
) {
    b.open("SPEC-OBJECTS", &[]);
    for c in chapters {
        b.open(
            "SPEC-OBJECT",
            &[("IDENTIFIER", &c.id), ("LAST-CHANGE", LAST_CHANGE)],
        );
        let mut vals = vec![(
            "geodesic-ad-heading-chapter-name",
            Val::Str(c.family.to_string()),
        )];
        if let Some(d) = reqs.families.get(c.family).filter(|d| !d.trim().is_empty()) {
            vals.push(("geodesic-ad-heading-text", Val::Xhtml(d.clone())));
        }
        write_values(b, HEADING_ATTRS, &vals);
        b.open("TYPE", &[]);
        b.text("SPEC-OBJECT-TYPE-REF", TYPE_HEADING);
        b.close("TYPE");
        b.close("SPEC-OBJECT");
    }
    let all_req_attrs: Vec<Attr> = REQ_ATTRS.iter().chain(STATUS_ATTRS).copied().collect();
    for r in &reqs.items {
        b.open(
            "SPEC-OBJECT",
            &[
                ("IDENTIFIER", &object_id(r)),
                ("LAST-CHANGE", LAST_CHANGE),
                ("LONG-NAME", r.id.as_str()),
            ],
        );
        let st = status.and_then(|s| s.rows.get(r.id.as_str()));
        write_values(b, &all_req_attrs, &requirement_values(r, st));
        b.open("TYPE", &[]);
        b.text("SPEC-OBJECT-TYPE-REF", TYPE_REQUIREMENT);
        b.close("TYPE");
        b.close("SPEC-OBJECT");
    }
    b.close("SPEC-OBJECTS");
}

/// The relations: each child derived from its parent, with the margin (none without a
/// derivation).
fn write_relations(b: &mut Writer, reqs: &Requirements) {
    let derived: Vec<&Requirement> = reqs.items.iter().filter(|r| r.parent.is_some()).collect();
    if derived.is_empty() {
        return;
    }
    b.open("SPEC-RELATIONS", &[]);
    for r in derived {
        let (pid, margin) = r.parent.as_ref().expect("filtered");
        b.open(
            "SPEC-RELATION",
            &[
                (
                    "IDENTIFIER",
                    &format!("geodesic-rel-{}-derived-from-{pid}", r.id),
                ),
                ("LAST-CHANGE", LAST_CHANGE),
            ],
        );
        write_values(
            b,
            REL_ATTRS,
            &[("geodesic-ad-rel-margin", Val::Real(*margin))],
        );
        b.open("SOURCE", &[]);
        b.text("SPEC-OBJECT-REF", &object_id(r));
        b.close("SOURCE");
        b.open("TARGET", &[]);
        b.text("SPEC-OBJECT-REF", &format!("geodesic-req-{pid}"));
        b.close("TARGET");
        b.open("TYPE", &[]);
        b.text("SPEC-RELATION-TYPE-REF", TYPE_DERIVED);
        b.close("TYPE");
        b.close("SPEC-RELATION");
    }
    b.close("SPEC-RELATIONS");
}

/// The document: one chapter per family, its requirements below its heading.
fn write_specification(b: &mut Writer, chapters: &[Chapter]) {
    b.open("SPECIFICATIONS", &[]);
    b.open(
        "SPECIFICATION",
        &[
            ("IDENTIFIER", "geodesic-specification"),
            ("LAST-CHANGE", LAST_CHANGE),
            ("LONG-NAME", "geodesic requirements"),
        ],
    );
    b.open("TYPE", &[]);
    b.text("SPECIFICATION-TYPE-REF", TYPE_SPEC);
    b.close("TYPE");
    b.open("CHILDREN", &[]);
    for c in chapters {
        b.open(
            "SPEC-HIERARCHY",
            &[
                ("IDENTIFIER", &format!("geodesic-h-{}", c.id)),
                ("LAST-CHANGE", LAST_CHANGE),
            ],
        );
        b.open("OBJECT", &[]);
        b.text("SPEC-OBJECT-REF", &c.id);
        b.close("OBJECT");
        b.open("CHILDREN", &[]);
        for r in &c.items {
            b.open(
                "SPEC-HIERARCHY",
                &[
                    ("IDENTIFIER", &format!("geodesic-h-{}", r.id)),
                    ("LAST-CHANGE", LAST_CHANGE),
                ],
            );
            b.open("OBJECT", &[]);
            b.text("SPEC-OBJECT-REF", &object_id(r));
            b.close("OBJECT");
            b.close("SPEC-HIERARCHY");
        }
        b.close("CHILDREN");
        b.close("SPEC-HIERARCHY");
    }
    b.close("CHILDREN");
    b.close("SPECIFICATION");
    b.close("SPECIFICATIONS");
}

/// The document's start up to `REQ-IF-CONTENT`: the header, identified by the SHA-256 of
/// `body` (the content).
fn header(reqs: &Requirements, chapters: &[Chapter], opts: &ExportOptions, body: &str) -> String {
    let content_hash = geodesic_util::hash::sha256_hex(body.as_bytes());
    let mut w = Writer::new();
    w.open(
        "REQ-IF",
        &[("xmlns", NAMESPACE), ("xmlns:xhtml", XHTML_NAMESPACE)],
    );
    w.open("THE-HEADER", &[]);
    w.open(
        "REQ-IF-HEADER",
        &[("IDENTIFIER", &format!("geodesic-{}", &content_hash[..32]))],
    );
    let mut comment = format!(
        "{} requirements in {} families exported by geodesic; the geodesic.* attributes are described in geodesic's docs/exchange.md",
        reqs.items.len(),
        chapters.len()
    );
    if let Some(s) = opts.status {
        comment.push_str("; ");
        comment.push_str(&s.provenance);
    }
    w.text("COMMENT", &comment);
    w.text("CREATION-TIME", opts.creation_time);
    w.text("REQ-IF-TOOL-ID", opts.tool_version);
    w.text("REQ-IF-VERSION", "1.0");
    w.text("SOURCE-TOOL-ID", "geodesic");
    w.text(
        "TITLE",
        if opts.status.is_some() {
            "geodesic requirements with their verification status"
        } else {
            "geodesic requirements"
        },
    );
    w.close("REQ-IF-HEADER");
    w.close("THE-HEADER");
    w.open("CORE-CONTENT", &[]);
    w.open("REQ-IF-CONTENT", &[]);
    w.finish()
}
