//! ReqIF files written by other tools (`tests/fixtures/tools/`, unchanged copies of public
//! exports; origin and licence in its README) and mutated copies of them: every file imports
//! with a warning per problem, every SPEC-OBJECT is accounted for, the count of SPEC-OBJECTs is
//! the reference parser's (`reference-counts.json`, written by
//! `verification/exchange/reqif-reference-counts.py` with the PyPI package `reqif`), `strict`
//! refuses a file at its first problem, and what is imported goes through an export, import,
//! export round trip unchanged.

use geodesic_core::Requirements;
use geodesic_exchange::reqif::{self, ExportOptions, Field, ImportOptions, Imported};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/tools")
}

fn tool_file(name: &str) -> (PathBuf, String) {
    let t = std::fs::read_to_string(dir().join(name)).unwrap();
    (PathBuf::from(format!("tools/{name}")), t)
}

/// Imports a test file of another tool as `geodesic import reqif` does (a `.reqifz` too).
fn import_tool(name: &str, o: &ImportOptions) -> Result<Imported, reqif::ImportError> {
    let bytes = std::fs::read(dir().join(name)).unwrap();
    reqif::import_file(&PathBuf::from(format!("tools/{name}")), &bytes, o)
}

fn tool_files() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".reqif") || n.ends_with(".reqifz"))
        .collect();
    v.sort();
    v
}

/// The reference parser's count of SPEC-OBJECTs of a file (the XML's count of SPEC-OBJECT
/// elements when the reference parser fails on it).
fn reference_count(name: &str) -> usize {
    let counts: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir().join("reference-counts.json")).unwrap(),
    )
    .unwrap();
    let f = &counts["files"][name];
    f["spec_objects"]
        .as_u64()
        .or(f["xml_spec_object_elements"].as_u64())
        .unwrap_or_else(|| panic!("{name}: no reference count")) as usize
}

fn loads(imp: &Imported) -> Requirements {
    let sources: Vec<(PathBuf, String)> = imp
        .families
        .iter()
        .map(|f| (PathBuf::from(&f.file_name), f.yaml.clone()))
        .collect();
    Requirements::from_sources(&sources).unwrap()
}

/// Everything a requirement set says, without where it was read from.
fn content(r: &Requirements) -> serde_json::Value {
    let mut v = serde_json::to_value(r).unwrap();
    for item in v["items"].as_array_mut().unwrap() {
        item.as_object_mut().unwrap().remove("origin");
    }
    v
}

fn accounted(imp: &Imported) -> usize {
    imp.count() + imp.headings + imp.other_objects + imp.duplicates + imp.skipped.len()
}

fn opts() -> ImportOptions {
    ImportOptions::default()
}

fn export(set: &Requirements, time: &str) -> String {
    reqif::export(
        set,
        &ExportOptions {
            creation_time: time,
            tool_version: "geodesic test",
            status: None,
        },
    )
}

fn without_creation_time(s: &str) -> String {
    s.lines()
        .filter(|l| !l.contains("<CREATION-TIME>"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// What each real file gives: requirements, headings, objects without any text, and a
/// phrase its warnings must hold (empty: no warning). The counts are read off the files: see
/// the comment of each.
const EXPECTED: &[(&str, usize, usize, usize, &str)] = &[
    // DOORS module exported for Capella: one object, IE PUID and ReqIF.Text, no problem
    ("capella-rvp-doors-sample1.reqif", 2, 0, 0, ""),
    // Capella RVP test model of an unnamed tool: 7 ReqIF.ChapterName headings, 8 objects that
    // carry only bookkeeping (dates, authors, an enumeration, a boolean), 28 with ReqIF.Text;
    // its "IE IVV Method" values (scrambled: `1`, `8`, `c`) are no ECSS method
    (
        "capella-rvp-model1.reqif",
        28,
        7,
        8,
        "attribute `IE IVV Method`: verification method `c`",
    ),
    // three DOORS headings and nothing else: the headings are what it says
    (
        "doors-headings-only.reqif",
        3,
        0,
        0,
        "headings are imported as requirements",
    ),
    // DOORS Next without the object type nor attribute definitions: values kept by reference
    (
        "doors-next-without-types.reqif",
        1,
        0,
        0,
        "SPEC-OBJECT-TYPE",
    ),
    (
        "doors-next-dangling-hierarchy.reqif",
        1,
        0,
        0,
        "the hierarchy entry is left out",
    ),
    // Enterprise Architect: attribute definitions without LONG-NAME (FUNC-REQ-TXT), a
    // hierarchy and a relation that name objects the export left out
    (
        "enterprise-architect-8.reqif",
        3,
        0,
        0,
        "SPEC-OBJECT `FUNC-REQ-1`",
    ),
    // ProR / ReqIF Studio (fmStudio) template: 5 headings (ReqIF.ChapterName without text)
    ("fmstudio-traceability-template.reqif", 16, 5, 0, ""),
    // Polarion, anonymised: every ReqIF.ForeignID is `aaa`; 42 "Heading" objects and the
    // "Document" object (ReqIF.ChapterName, no text) are headings
    (
        "polarion-anonymised.reqif",
        58,
        43,
        0,
        "value `aaa` of the ID attribute",
    ),
    // Polarion export whose hierarchy names 68 objects the file does not hold
    (
        "polarion-dangling-hierarchy.reqif",
        3,
        0,
        0,
        "the hierarchy entry is left out",
    ),
    // ProR datatype demo: every datatype; its XHTML attribute (named `XHTML`, not a text
    // attribute) embeds objects (a picture, a PDF)
    ("pror-datatype-demo.reqif", 3, 0, 0, ""),
    // ReqIF Studio, anonymised: the ForeignID of every object is the same; one hierarchy
    // entry names a missing object; relations of a missing type
    (
        "reqif-studio-anonymised.reqif",
        137,
        0,
        0,
        "`_B9RbAGunEeuNUYnTveUm8Q`",
    ),
    // RMF test case without a text attribute: ReqIF.Name is the text
    ("rmf-tc1100-no-text.reqif", 5, 0, 0, "its title is its text"),
    // RMF test case of XHTML values, no text attribute by name: the XHTML one is the text
    (
        "rmf-tc1200-xhtml.reqif",
        44,
        0,
        0,
        "TC1200 AttributeDefinitionXHTML",
    ),
    (
        "rmf-tc1801-two-specifications.reqif",
        6,
        0,
        0,
        "none of the text attributes",
    ),
    // StrictDoc: sections as ReqIF.ChapterName objects; no LAST-CHANGE nor MAX-LENGTH, which
    // the schema requires
    (
        "strictdoc-sample.reqif",
        8,
        10,
        0,
        "lacks the LAST-CHANGE the ReqIF schema requires",
    ),
    // .reqifz archives: Polarion's (STRING values of an XHTML definition), one with its
    // attachments in nested folders and macOS resource forks, and an RMF test case of two
    // documents (the second holds only a relation to the first: not imported, said)
    (
        "polarion-archive.reqifz",
        1,
        1,
        0,
        "ATTRIBUTE-VALUE-STRING refers to the ATTRIBUTE-DEFINITION-XHTML",
    ),
    (
        "reqifz-nested-attachments.reqifz",
        2,
        0,
        0,
        "none of the text attributes",
    ),
    (
        "rmf-tc1700-two-documents.reqifz",
        2,
        0,
        0,
        "the archive holds 2 ReqIF documents",
    ),
];

#[test]
fn every_file_of_other_tools_imports_and_accounts_for_every_object() {
    let files = tool_files();
    let listed: BTreeSet<&str> = EXPECTED.iter().map(|e| e.0).collect();
    for f in &files {
        let want = reference_count(f);
        if f == "doors-date-only.reqif" {
            // one object with a date only: nothing to import, said with the count
            let e = import_tool(f, &opts()).unwrap_err().to_string();
            assert!(
                e.contains("no requirement in this file (1 SPEC-OBJECTs"),
                "{f}: {e}"
            );
            continue;
        }
        assert!(listed.contains(f.as_str()), "{f}: not in EXPECTED");
        let imp = import_tool(f, &opts()).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert_eq!(imp.spec_objects, want, "{f}: SPEC-OBJECTs");
        assert_eq!(accounted(&imp), want, "{f}: every object accounted for");
        let (_, reqs, heads, others, warn) = *EXPECTED.iter().find(|e| e.0 == f).unwrap();
        assert_eq!(
            (imp.count(), imp.headings, imp.other_objects),
            (reqs, heads, others),
            "{f}"
        );
        if warn.is_empty() {
            assert!(imp.warnings.is_empty(), "{f}: {:?}", imp.warnings);
        } else {
            assert!(
                imp.warnings.iter().any(|w| w.cause.contains(warn)),
                "{f}: no warning with `{warn}`: {:?}",
                imp.warnings
            );
        }
        let lines = if f.ends_with(".reqifz") {
            u32::MAX
        } else {
            tool_file(f).1.lines().count() as u32
        };
        for w in &imp.warnings {
            assert!(w.line >= 1 && w.line <= lines, "{f}: {w:?}");
            assert!(!w.cause.contains('\n'), "{f}: {w:?}");
        }
        // sorted by line: the first is what --strict reports
        assert!(imp.warnings.windows(2).all(|p| p[0].line <= p[1].line));
        let set = loads(&imp);
        assert_eq!(set.items.len(), reqs);
        let ids: BTreeSet<&str> = set.items.iter().map(|r| r.id.as_str()).collect();
        assert_eq!(ids.len(), reqs, "{f}: IDs unique");
        assert!(set.items.iter().all(|r| !r.text.trim().is_empty()));
    }
    assert_eq!(files.len(), EXPECTED.len() + 1);
    // an archive's messages name the document in it
    let imp = import_tool("polarion-archive.reqifz", &opts()).unwrap();
    assert_eq!(
        imp.document,
        "tools/polarion-archive.reqifz!sample1_polarion.reqif"
    );
}

#[test]
fn strict_refuses_a_file_at_its_first_problem() {
    for (f, _, _, _, warn) in EXPECTED {
        let lenient = import_tool(f, &opts()).unwrap();
        let o = ImportOptions {
            strict: true,
            ..opts()
        };
        let strict = import_tool(f, &o);
        if warn.is_empty() {
            assert!(
                strict.is_ok(),
                "{f}: a file without problem passes --strict"
            );
            continue;
        }
        let e = strict.unwrap_err();
        let first = &lenient.warnings[0];
        assert_eq!(e.line, first.line, "{f}");
        assert!(e.cause.starts_with(&first.cause), "{f}: {e}");
        assert!(e.cause.contains("--strict"), "{f}: {e}");
        let shown = e.to_string();
        assert!(
            shown.starts_with(&format!("{}:{}: ", lenient.document, first.line)),
            "{shown}"
        );
        assert!(!shown.contains('\n'));
    }
}

#[test]
fn what_is_imported_from_other_tools_goes_round_trip() {
    for (f, ..) in EXPECTED {
        let imp = import_tool(f, &opts()).unwrap();
        let set = loads(&imp);
        let first = export(&set, "2026-01-01T00:00:00Z");
        let again = reqif::import(Path::new("set.reqif"), &first, &opts()).unwrap();
        assert!(again.warnings.is_empty(), "{f}: {:?}", again.warnings);
        assert_eq!(again.count(), imp.count(), "{f}");
        let back = loads(&again);
        let second = export(&back, "2027-06-30T12:00:00Z");
        assert_eq!(
            without_creation_time(&first),
            without_creation_time(&second),
            "{f}"
        );
    }
}

#[test]
fn what_the_files_say_is_read() {
    // Enterprise Architect: the text of an attribute without LONG-NAME, the IDs its
    // SPEC-OBJECT identifiers (no ID attribute), the title its LONG-NAME
    let (name, text) = tool_file("enterprise-architect-8.reqif");
    let imp = reqif::import(&name, &text, &opts()).unwrap();
    let set = loads(&imp);
    let r1 = set.get("R001").unwrap();
    assert_eq!(r1.text, "The system shall observe the earths surface.");
    assert_eq!(r1.title, "Observe earths surface.");
    assert_eq!(r1.method.to_string(), "review-of-design");
    let text_rows = &imp
        .mapping
        .iter()
        .find(|m| m.field == Field::Text)
        .unwrap()
        .sources;
    assert_eq!(text_rows.len(), 2, "{text_rows:?}");
    assert!(text_rows[0].0.contains("FUNC-REQ-TXT"), "{text_rows:?}");
    // the relation names objects the file does not hold: not imported, said
    assert_eq!(imp.relations, 1);
    assert!(set.items.iter().all(|r| r.note.is_none()));

    // Polarion, anonymised: IDs from the SPEC-OBJECT identifiers, the shared value kept in
    // each note
    let (name, text) = tool_file("polarion-anonymised.reqif");
    let imp = reqif::import(&name, &text, &opts()).unwrap();
    let set = loads(&imp);
    assert!(set.items.iter().all(|r| r.id.as_str().starts_with("RMF-")));
    assert!(
        set.items[0]
            .note
            .as_deref()
            .unwrap()
            .contains("its ReqIF.ForeignID `aaa` is not unique")
    );
    let id_rows = &imp
        .mapping
        .iter()
        .find(|m| m.field == Field::Id)
        .unwrap()
        .sources;
    assert_eq!(
        id_rows,
        &[(
            "SPEC-OBJECT IDENTIFIER (`ReqIF.ForeignID` not unique)".to_string(),
            58
        )]
    );
    assert_eq!(
        imp.warnings
            .iter()
            .filter(|w| w.cause.contains("shared by"))
            .count(),
        1,
        "one warning per shared value"
    );

    // ProR: with its XHTML attribute as the text, an embedded picture and PDF are references
    // in the text, each said
    let (name, text) = tool_file("pror-datatype-demo.reqif");
    let mut o = opts();
    o.attribute.insert(Field::Text, "XHTML".into());
    let imp = reqif::import(&name, &text, &o).unwrap();
    assert_eq!(
        imp.warnings
            .iter()
            .filter(|w| w.cause.contains("embeds the object `Datatype-Demo/"))
            .count(),
        2,
        "{:?}",
        imp.warnings
    );
    let set = loads(&imp);
    assert!(
        set.items
            .iter()
            .any(|r| r.text.contains("[object: Datatype-Demo/ReqIF.png]"))
    );
    assert!(set.items.iter().any(|r| {
        r.text
            .contains("[object: Datatype-Demo/reqif-reference-v1.2.pdf]")
            && !r.text.contains("application-pdf.png")
    }));

    // two specifications: two families, named by them
    let (name, text) = tool_file("rmf-tc1801-two-specifications.reqif");
    let imp = reqif::import(&name, &text, &opts()).unwrap();
    assert_eq!(imp.families.len(), 2);

    // ReqIF Studio: relations of a type the file left out are kept in the notes by the name
    // of the reference
    let (name, text) = tool_file("reqif-studio-anonymised.reqif");
    let imp = reqif::import(&name, &text, &opts()).unwrap();
    assert_eq!(imp.relations, 14);
    let set = loads(&imp);
    assert_eq!(
        set.items
            .iter()
            .filter_map(|r| r.note.as_deref())
            .map(|n| n
                .matches("ReqIF relation '_gFhrYGojEeuExICsU7Acmg'")
                .count())
            .sum::<usize>(),
        14
    );
}

// ------------------------------------------------------------------ mutated copies

/// Cuts the first element `<tag ...>...</tag>` (or `<tag .../>`) whose start contains `key`.
fn cut_element(text: &str, tag: &str, key: &str) -> String {
    let open = format!("<{tag} ");
    let mut from = 0;
    while let Some(i) = text[from..].find(&open).map(|i| i + from) {
        let head_end = text[i..].find('>').unwrap() + i;
        if text[i..head_end].contains(key) {
            let end = if text[..=head_end].ends_with("/>") {
                head_end + 1
            } else {
                let close = format!("</{tag}>");
                text[i..].find(&close).unwrap() + i + close.len()
            };
            return format!("{}{}", &text[..i], &text[end..]);
        }
        from = head_end;
    }
    panic!("no <{tag}> with `{key}`");
}

fn lpf() -> (PathBuf, String) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/doors-style-lpf.reqif");
    (
        PathBuf::from("fixtures/doors-style-lpf.reqif"),
        std::fs::read_to_string(p).unwrap(),
    )
}

/// 1-based line of the first `needle`.
fn line_of(text: &str, needle: &str) -> u32 {
    line_at(text, text.find(needle).unwrap())
}

/// 1-based line of byte `pos`.
fn line_at(text: &str, pos: usize) -> u32 {
    text[..pos].matches('\n').count() as u32 + 1
}

/// Imports a mutated copy: it imports with a warning holding `warn` at `line`, and `strict`
/// refuses it at that line (the mutation's is the file's only problem).
fn warned(name: &Path, text: &str, line: u32, warn: &str) -> Imported {
    let imp = reqif::import(name, text, &opts()).unwrap_or_else(|e| panic!("{warn}: {e}"));
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.line == line && w.cause.contains(warn)),
        "no warning `{warn}` at line {line}: {:?}",
        imp.warnings
    );
    let o = ImportOptions {
        strict: true,
        ..opts()
    };
    let e = reqif::import(name, text, &o).unwrap_err();
    assert_eq!(e.line, imp.warnings[0].line);
    assert_eq!(accounted(&imp), imp.spec_objects);
    loads(&imp);
    imp
}

#[test]
fn mutated_copies_import_with_a_warning_each() {
    let (name, text) = lpf();
    let clean = reqif::import(&name, &text, &opts()).unwrap();
    assert!(clean.warnings.is_empty());
    dangling_references(&name, &text);
    missing_definitions(&name, &text);
    duplicated_objects_and_ids(&name, &text);
    unread_content(&name, &text, &clean);
    string_encoded_numbers(&name, &text);
}

/// Mutations of the clean file `text`: references to elements the file does not hold.
fn dangling_references(name: &Path, text: &str) {
    // dangling reference in the hierarchy: the object is imported all the same, with its
    // children in place
    let t = text.replace(
        "<OBJECT><SPEC-OBJECT-REF>_obj_1</SPEC-OBJECT-REF></OBJECT>",
        "<OBJECT><SPEC-OBJECT-REF>_obj_404</SPEC-OBJECT-REF></OBJECT>",
    );
    let imp = warned(name, &t, line_of(&t, "_obj_404"), "SPEC-OBJECT `_obj_404`");
    assert_eq!(imp.count(), 4);

    // dangling relation target: the relation is left out
    let t = text.replace(
        "<TARGET><SPEC-OBJECT-REF>_obj_12</SPEC-OBJECT-REF></TARGET>\n        </SPEC-RELATION>\n        <SPEC-RELATION IDENTIFIER=\"_rel_20_12\"",
        "<TARGET><SPEC-OBJECT-REF>_obj_99</SPEC-OBJECT-REF></TARGET>\n        </SPEC-RELATION>\n        <SPEC-RELATION IDENTIFIER=\"_rel_20_12\"",
    );
    let imp = warned(name, &t, line_of(&t, "_obj_99"), "the relation is left out");
    assert!(loads(&imp).get("GRS-13").unwrap().parent.is_none());

    // a missing enumeration value: its identifier is the label (here, no method geodesic
    // reads: GRS-12 is left out, said)
    let t = text.replacen("_ev_vm_a</ENUM-VALUE-REF>", "_ev_vm_x</ENUM-VALUE-REF>", 1);
    let imp = warned(name, &t, line_of(&t, "_ev_vm_x"), "ENUM-VALUE `_ev_vm_x`");
    assert!(imp.skipped.iter().any(|s| s.id == "GRS-12"));
}

/// Mutations of the clean file `text`: definitions (datatypes, attribute definitions, object
/// types) left out.
fn missing_definitions(name: &Path, text: &str) {
    // no DATATYPES at all: enumeration labels are their identifiers; `_ev_vm_a` is not a
    // method, so the two quantitative requirements it is the first method of are left out
    let start = text.find("      <DATATYPES>").unwrap();
    let end = text.find("</DATATYPES>\n").unwrap() + "</DATATYPES>\n".len();
    let t = format!("{}{}", &text[..start], &text[end..]);
    let imp = reqif::import(name, &t, &opts()).unwrap();
    assert_eq!(imp.spec_objects, 6);
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.cause.contains("ENUM-VALUE `_ev_vm_r`"))
    );
    assert_eq!(accounted(&imp), 6);

    // a missing attribute definition: its values are named by the reference
    let t = cut_element(text, "ATTRIBUTE-DEFINITION-STRING", "_ad_source");
    let imp = warned(
        name,
        &t,
        line_of(&t, "<ATTRIBUTE-DEFINITION-STRING-REF>_ad_source"),
        "ATTRIBUTE-DEFINITION-STRING `_ad_source`",
    );
    assert!(
        imp.unmapped.iter().any(|(n, _)| n == "_ad_source"),
        "{:?}",
        imp.unmapped
    );

    // a missing object type: the object is read without it
    let t = cut_element(text, "SPEC-OBJECT-TYPE", "_type_obj");
    let imp = reqif::import(name, &t, &opts()).unwrap();
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.cause.contains("SPEC-OBJECT-TYPE `_type_obj`"))
    );
    assert_eq!(imp.spec_objects, 6);
}

/// Mutations of the clean file `text`: an object defined twice, IDs shared or empty, an object
/// embedded in a text.
fn duplicated_objects_and_ids(name: &Path, text: &str) {
    // an object defined twice: the second is ignored
    let obj = {
        let s = text.find("<SPEC-OBJECT IDENTIFIER=\"_obj_21\"").unwrap();
        let e = text[s..].find("</SPEC-OBJECT>").unwrap() + s + "</SPEC-OBJECT>".len();
        text[s..e].to_string()
    };
    let t = text.replace("</SPEC-OBJECTS>", &format!("{obj}\n      </SPEC-OBJECTS>"));
    let second = t.rfind("<SPEC-OBJECT IDENTIFIER=\"_obj_21\"").unwrap();
    let imp = warned(name, &t, line_at(&t, second), "is defined twice");
    assert_eq!((imp.duplicates, imp.spec_objects, imp.count()), (1, 7, 4));

    // the same ID value on two objects: both take their SPEC-OBJECT identifier
    let t = text.replace("THE-VALUE=\"13\"", "THE-VALUE=\"12\"");
    let imp = warned(
        name,
        &t,
        line_of(&t, "<SPEC-OBJECT IDENTIFIER=\"_obj_12\""),
        "value `GRS-12` of the ID attribute `ReqIF.ForeignID` is shared by 2 objects",
    );
    let set = loads(&imp);
    assert!(set.get("OBJ-12").is_some() && set.get("OBJ-13").is_some());
    assert!(set.get("GRS-12").is_none() && set.get("GRS-20").is_some());
    // the derivation follows the objects, not the IDs
    assert_eq!(
        set.get("OBJ-13")
            .unwrap()
            .parent
            .as_ref()
            .unwrap()
            .0
            .as_str(),
        "OBJ-12"
    );

    // an empty ID value: the SPEC-OBJECT identifier
    let t = text.replace("THE-VALUE=\"20\"", "THE-VALUE=\"\"");
    let imp = warned(
        name,
        &t,
        line_of(&t, "<SPEC-OBJECT IDENTIFIER=\"_obj_20\""),
        "its ID attribute `ReqIF.ForeignID` is empty",
    );
    assert!(loads(&imp).get("OBJ-20").is_some());

    // an embedded object in a requirement's XHTML
    let t = text.replace(
        "with 99.73 % probability.",
        "with 99.73 % probability. <xhtml:object data=\"fig/release.png\" type=\"image/png\">release</xhtml:object>",
    );
    let imp = warned(
        name,
        &t,
        line_of(&t, "<SPEC-OBJECT IDENTIFIER=\"_obj_12\""),
        "embeds the object `fig/release.png`",
    );
    assert!(
        loads(&imp)
            .get("GRS-12")
            .unwrap()
            .text
            .ends_with("probability. [object: fig/release.png]")
    );
}

/// Mutations of the clean file `text` that change nothing imported (`clean`: its import):
/// tool extensions, a second specification naming objects already placed.
fn unread_content(name: &Path, text: &str, clean: &Imported) {
    // TOOL-EXTENSIONS, whatever they hold, change nothing
    let t = text.replace(
        "  </CORE-CONTENT>",
        "  </CORE-CONTENT>\n  <TOOL-EXTENSIONS><REQ-IF-TOOL-EXTENSION><x:cfg xmlns:x=\"urn:x\" IDENTIFIER=\"_obj_12\"><SPEC-OBJECT IDENTIFIER=\"_ghost\"/></x:cfg></REQ-IF-TOOL-EXTENSION></TOOL-EXTENSIONS>",
    );
    let imp = reqif::import(name, &t, &opts()).unwrap();
    assert!(imp.warnings.is_empty());
    assert_eq!(content(&loads(&imp)), content(&loads(clean)));

    // a second specification naming some of the objects: they stay where they were first
    let spec2 = "<SPECIFICATION IDENTIFIER=\"_module2\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\" LONG-NAME=\"Annex\"><CHILDREN><SPEC-HIERARCHY IDENTIFIER=\"_h2_12\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\"><OBJECT><SPEC-OBJECT-REF>_obj_12</SPEC-OBJECT-REF></OBJECT></SPEC-HIERARCHY></CHILDREN></SPECIFICATION>";
    let t = text.replace("</SPECIFICATIONS>", &format!("{spec2}</SPECIFICATIONS>"));
    let imp = reqif::import(name, &t, &opts()).unwrap();
    assert!(imp.warnings.is_empty());
    assert_eq!(content(&loads(&imp)), content(&loads(clean)));
}

/// Mutations of the clean file `text`: string-encoded numbers, a derivation margin and a limit
/// with a decimal comma.
fn string_encoded_numbers(name: &Path, text: &str) {
    // string-encoded numbers: a derivation margin with a decimal comma, a limit with one
    let t = text.replace(
        "<SOURCE><SPEC-OBJECT-REF>_obj_13</SPEC-OBJECT-REF></SOURCE>",
        "<VALUES><ATTRIBUTE-VALUE-STRING THE-VALUE=\" 1,5 \"><DEFINITION><ATTRIBUTE-DEFINITION-STRING-REF>_ad_margin</ATTRIBUTE-DEFINITION-STRING-REF></DEFINITION></ATTRIBUTE-VALUE-STRING></VALUES><SOURCE><SPEC-OBJECT-REF>_obj_13</SPEC-OBJECT-REF></SOURCE>",
    )
    .replace(
        "<SPEC-RELATION-TYPE IDENTIFIER=\"_type_derived\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\" LONG-NAME=\"Derived From\"/>",
        "<SPEC-RELATION-TYPE IDENTIFIER=\"_type_derived\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\" LONG-NAME=\"Derived From\"><SPEC-ATTRIBUTES><ATTRIBUTE-DEFINITION-STRING IDENTIFIER=\"_ad_margin\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\" LONG-NAME=\"Margin\"><TYPE><DATATYPE-DEFINITION-STRING-REF>_dt_string</DATATYPE-DEFINITION-STRING-REF></TYPE></ATTRIBUTE-DEFINITION-STRING></SPEC-ATTRIBUTES></SPEC-RELATION-TYPE>",
    )
    .replace("&lt;= 7.5 um/s", "&lt;= 7,5 um/s");
    let imp = warned(
        name,
        &t,
        line_of(&t, "<SPEC-OBJECT IDENTIFIER=\"_obj_13\""),
        "limit `<= 7,5 um/s` read as `<= 7.5 um/s`",
    );
    let set = loads(&imp);
    let g13 = set.get("GRS-13").unwrap();
    assert_eq!(g13.limit.as_ref().unwrap().text, "<= 7.5 um/s");
    assert_eq!(g13.parent.as_ref().unwrap().1, 1.5);
}

/// A deterministic stream (64-bit LCG, Knuth's constants): the same mutations every run.
struct Lcg(u64);
impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 33) as usize) % n.max(1)
    }
}

/// Every element `<tag ...>...</tag>` of the text, as byte ranges.
fn spans(text: &str, tag: &str) -> Vec<(usize, usize)> {
    let open = format!("<{tag} ");
    let close = format!("</{tag}>");
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(i) = text[from..].find(&open).map(|i| i + from) {
        let head_end = text[i..].find('>').unwrap() + i;
        let end = if text[..=head_end].ends_with("/>") {
            head_end + 1
        } else {
            match text[i..].find(&close) {
                Some(e) => e + i + close.len(),
                None => break,
            }
        };
        out.push((i, end));
        from = end;
    }
    out
}

/// Classes of damage real exports show, applied to every real file with a fixed stream:
/// an object left out, an attribute definition left out, an enumeration value left out, an
/// object type left out, an object defined twice, an ID value copied onto another object.
/// Each copy imports (or, when nothing is left, is refused naming the count), accounts for
/// every SPEC-OBJECT, and says what is wrong.
#[test]
fn every_real_file_survives_each_class_of_damage() {
    let mut rng = Lcg(2026);
    let mut runs = 0;
    for (f, ..) in EXPECTED.iter().filter(|e| e.0.ends_with(".reqif")) {
        let (name, text) = tool_file(f);
        let base = reqif::import(&name, &text, &opts()).unwrap();
        for (class, tag) in [
            ("object left out", "SPEC-OBJECT"),
            ("definition left out", "ATTRIBUTE-DEFINITION-XHTML"),
            ("definition left out", "ATTRIBUTE-DEFINITION-STRING"),
            ("enumeration value left out", "ENUM-VALUE"),
            ("type left out", "SPEC-OBJECT-TYPE"),
            ("object twice", "SPEC-OBJECT"),
        ] {
            let all = spans(&text, tag);
            if all.is_empty() {
                continue;
            }
            let (s, e) = all[rng.below(all.len())];
            let t = if class == "object twice" {
                format!("{}{}{}", &text[..e], &text[s..e], &text[e..])
            } else {
                format!("{}{}", &text[..s], &text[e..])
            };
            runs += 1;
            match reqif::import(&name, &t, &opts()) {
                Ok(imp) => {
                    assert_eq!(accounted(&imp), imp.spec_objects, "{f}: {class}");
                    let removed = usize::from(class == "object left out");
                    let added = usize::from(class == "object twice");
                    assert_eq!(
                        imp.spec_objects,
                        base.spec_objects - removed + added,
                        "{f}: {class}"
                    );
                    if class == "object twice" {
                        assert_eq!(imp.duplicates, 1, "{f}");
                    }
                    // a removed definition, value or type that something refers to is said
                    if class != "object left out" && class != "object twice" {
                        let idents: Vec<&str> = text[s..e]
                            .split("IDENTIFIER=\"")
                            .skip(1)
                            .filter_map(|r| r.split('"').next())
                            .collect();
                        // references from the content (TOOL-EXTENSIONS are not read)
                        let content_end = text.find("<TOOL-EXTENSIONS").unwrap_or(text.len());
                        let referenced: Vec<&&str> = idents
                            .iter()
                            .filter(|i| {
                                let r = format!(">{i}<");
                                text[..s].contains(&r)
                                    || (e < content_end && text[e..content_end].contains(&r))
                            })
                            .collect();
                        if !referenced.is_empty() {
                            assert!(
                                imp.warnings.iter().any(|w| referenced
                                    .iter()
                                    .any(|i| w.cause.contains(&format!("`{i}`")))),
                                "{f}: {class}: {referenced:?} are referenced, yet not said"
                            );
                        }
                    }
                    loads(&imp);
                }
                Err(e) => {
                    let e = e.to_string();
                    assert!(
                        e.contains("no requirement in this file"),
                        "{f}: {class}: {e}"
                    );
                }
            }
        }
    }
    assert!(runs > 60, "{runs} mutated copies");
}

/// XHTML and hierarchies nested 100 000 deep are read with stacks, not recursion: no stack
/// overflow (an abort no error message can report).
#[test]
fn nesting_as_deep_as_a_file_goes() {
    let (name, text) = lpf();
    let n = 100_000;
    let deep = format!(
        "{}deep{}",
        "<xhtml:div>".repeat(n),
        "</xhtml:div>".repeat(n)
    );
    let t = text.replace(
        "<xhtml:div>The TM potential after release shall not exceed 1.1 V.</xhtml:div>",
        &deep,
    );
    let imp = reqif::import(&name, &t, &opts()).unwrap();
    assert_eq!(loads(&imp).get("GRS-20").unwrap().text, "deep");
    let mut h = String::new();
    for i in 0..n {
        h.push_str(&format!(
            "<SPEC-HIERARCHY IDENTIFIER=\"_d{i}\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\"><CHILDREN>"
        ));
    }
    h.push_str("<SPEC-HIERARCHY IDENTIFIER=\"_leaf\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\"><OBJECT><SPEC-OBJECT-REF>_obj_21</SPEC-OBJECT-REF></OBJECT></SPEC-HIERARCHY>");
    h.push_str(&"</CHILDREN></SPEC-HIERARCHY>".repeat(n));
    let t = text.replace(
        "<SPEC-HIERARCHY IDENTIFIER=\"_h_21\" LAST-CHANGE=\"2025-03-14T09:26:53.000+01:00\"><OBJECT><SPEC-OBJECT-REF>_obj_21</SPEC-OBJECT-REF></OBJECT></SPEC-HIERARCHY>",
        &h,
    );
    assert_ne!(t, text);
    let imp = reqif::import(&name, &t, &opts()).unwrap();
    assert_eq!(imp.count(), 4);
}
