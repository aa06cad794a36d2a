//! ReqIF export and import: the round trip on the repository's requirements, files written as
//! DOORS and Polarion write them, and bad files.

use geodesic_core::Requirements;
use geodesic_exchange::reqif::{self, ExportOptions, Field, ImportOptions};
use geodesic_exchange::status::StatusSet;
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn fixture(name: &str) -> (PathBuf, String) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name);
    let t = std::fs::read_to_string(&p).unwrap();
    (PathBuf::from(format!("fixtures/{name}")), t)
}

fn repo_requirements() -> Requirements {
    Requirements::load_dir(&workspace().join("requirements")).unwrap()
}

fn opts<'a>(time: &'a str, status: Option<&'a StatusSet>) -> ExportOptions<'a> {
    ExportOptions {
        creation_time: time,
        tool_version: "geodesic test",
        status,
    }
}

/// Everything a requirement set says, without where it was read from.
fn content(r: &Requirements) -> serde_json::Value {
    let mut v = serde_json::to_value(r).unwrap();
    for item in v["items"].as_array_mut().unwrap() {
        item.as_object_mut().unwrap().remove("origin");
    }
    v
}

fn import_to_set(name: &Path, text: &str, o: &ImportOptions) -> (reqif::Imported, Requirements) {
    let imp = reqif::import(name, text, o).unwrap();
    let sources: Vec<(PathBuf, String)> = imp
        .families
        .iter()
        .map(|f| (PathBuf::from(&f.file_name), f.yaml.clone()))
        .collect();
    let set = Requirements::from_sources(&sources).unwrap();
    (imp, set)
}

fn without_creation_time(s: &str) -> String {
    s.lines()
        .filter(|l| !l.contains("<CREATION-TIME>"))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn export_import_export_is_lossless() {
    let reqs = repo_requirements();
    let first = reqif::export(&reqs, &opts("2026-01-01T00:00:00Z", None));
    let (imp, back) = import_to_set(Path::new("set.reqif"), &first, &ImportOptions::default());
    assert!(imp.skipped.is_empty());
    assert_eq!(imp.count(), reqs.items.len());
    // the same requirement set: every field, family descriptions, parents and margins
    assert_eq!(content(&back), content(&reqs));
    // one file per family, named as in requirements/
    let names: Vec<&str> = imp.families.iter().map(|f| f.file_name.as_str()).collect();
    assert_eq!(
        names,
        [
            "capture.yaml",
            "charge.yaml",
            "facility.yaml",
            "performance.yaml",
            "plunger.yaml",
            "release.yaml",
            "tm-state.yaml"
        ]
    );
    let second = reqif::export(&back, &opts("2027-06-30T12:00:00Z", None));
    assert_ne!(first, second, "the creation time differs");
    assert_eq!(
        without_creation_time(&first),
        without_creation_time(&second)
    );
    assert_eq!(
        first
            .lines()
            .filter(|l| l.contains("<CREATION-TIME>"))
            .count(),
        1
    );
}

#[test]
fn export_is_deterministic_and_carries_every_field() {
    let reqs = repo_requirements();
    let a = reqif::export(&reqs, &opts("2026-01-01T00:00:00Z", None));
    let b = reqif::export(&reqs, &opts("2026-01-01T00:00:00Z", None));
    assert_eq!(a, b);
    assert!(a.contains("xmlns=\"http://www.omg.org/spec/ReqIF/20110401/reqif.xsd\""));
    // ID as ReqIF.ForeignID, title as ReqIF.Name, text as XHTML, limit with value and unit
    let obj = a
        .split("<SPEC-OBJECT IDENTIFIER=\"geodesic-req-REL-DFACS-VEL\"")
        .nth(1)
        .unwrap()
        .split("</SPEC-OBJECT>")
        .next()
        .unwrap();
    assert!(obj.contains("THE-VALUE=\"REL-DFACS-VEL\""), "{obj}");
    assert!(obj.contains("THE-VALUE=\"DFACS design release velocity\""));
    assert!(obj.contains("<xhtml:div>The DFACS shall be designed"));
    assert!(obj.contains("THE-VALUE=\"&lt;= 7.5 um/s\""));
    assert!(obj.contains("THE-VALUE=\"7.5\""));
    assert!(obj.contains("<ENUM-VALUE-REF>geodesic-ev-method-analysis</ENUM-VALUE-REF>"));
    // the derivation as a SPEC-RELATION child -> parent with its margin
    assert!(a.contains("IDENTIFIER=\"geodesic-rel-REL-DFACS-VEL-derived-from-REL-GPRM-VEL\""));
    assert_eq!(
        a.matches("<SPEC-RELATION IDENTIFIER=").count(),
        reqs.items.iter().filter(|r| r.parent.is_some()).count()
    );
    // no random identifiers, no dates but the header's creation time and the fixed LAST-CHANGE
    for l in a.lines() {
        if l.contains("LAST-CHANGE=") {
            assert!(l.contains("LAST-CHANGE=\"1970-01-01T00:00:00Z\""), "{l}");
        }
    }
}

#[test]
fn export_with_the_matrix_carries_the_vcd_status() {
    let reqs = repo_requirements();
    let mp = workspace().join("verification/baseline/compliance.json");
    let st = StatusSet::parse(&mp, &std::fs::read_to_string(&mp).unwrap()).unwrap();
    st.check_against(&mp, &reqs).unwrap();
    let a = reqif::export(&reqs, &opts("2026-01-01T00:00:00Z", Some(&st)));
    let chg = a
        .split("<SPEC-OBJECT IDENTIFIER=\"geodesic-req-CHG-Q\"")
        .nth(1)
        .unwrap()
        .split("</SPEC-OBJECT>")
        .next()
        .unwrap();
    assert!(chg.contains("geodesic-ev-status-non-compliant"), "{chg}");
    assert!(chg.contains("geodesic-ev-basis-model"));
    assert!(chg.contains("geodesic-ev-close-out-open"));
    assert!(chg.contains("THE-VALUE=\"NCR NCR-GEO-001\""));
    assert!(chg.contains("THE-VALUE=\"-0.04322934809813976\""));
    let vel = a
        .split("<SPEC-OBJECT IDENTIFIER=\"geodesic-req-TMS-X-VEL\"")
        .nth(1)
        .unwrap()
        .split("</SPEC-OBJECT>")
        .next()
        .unwrap();
    assert!(vel.contains("geodesic-ev-status-not-verified"));
    assert!(vel.contains("no model gives vx at release"));
    assert!(
        !vel.contains("geodesic-ad-req-value<"),
        "no value when not verified"
    );
    // the status is a result, not part of the requirement: the import ignores it
    let (_, back) = import_to_set(Path::new("s.reqif"), &a, &ImportOptions::default());
    assert_eq!(content(&back), content(&reqs));

    // a matrix of another requirement set is refused
    let mut other = reqs.clone();
    other.items[0].limit.as_mut().unwrap().text = "< 2".into();
    let e = st.check_against(&mp, &other).unwrap_err().to_string();
    assert!(
        e.contains("CAP-QUARTIC") && e.contains("verify again"),
        "{e}"
    );
    other.items.remove(0);
    let e = st.check_against(&mp, &other).unwrap_err().to_string();
    assert!(e.contains("CAP-QUARTIC"), "{e}");
}

#[test]
fn doors_module_imports_with_headings_prefixes_enumerations_and_links() {
    let (name, text) = fixture("doors-style-lpf.reqif");
    // GRS-21 has no limit and no method: a qualitative requirement, closed by review of design
    let (imp, set) = import_to_set(&name, &text, &ImportOptions::default());
    assert!(imp.skipped.is_empty());
    assert_eq!(imp.qualitative, 1);
    let ids: Vec<&str> = set.items.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(ids, ["GRS-12", "GRS-13", "GRS-20", "GRS-21"]);
    let g21 = set.get("GRS-21").unwrap();
    assert!(g21.limit.is_none() && g21.check.is_none() && g21.parent.is_none());
    assert_eq!(g21.method.to_string(), "review-of-design");
    assert_eq!(
        g21.text,
        "The charge management shall be described in the design justification file."
    );
    // --skip-incomplete keeps the quantitative ones only, listing the qualitative one
    let o = ImportOptions {
        skip_incomplete: true,
        ..ImportOptions::default()
    };
    let (imp, set) = import_to_set(&name, &text, &o);
    assert_eq!(imp.source_tool, "IBM Rational DOORS");
    assert_eq!(imp.skipped.len(), 1);
    assert_eq!(imp.skipped[0].id, "GRS-21");
    assert_eq!(imp.skipped[0].line, 123);
    assert!(imp.skipped[0].missing[0].contains("qualitative"));
    assert_eq!(imp.qualitative, 0);
    assert_eq!(imp.headings, 2);
    let ids: Vec<&str> = set.items.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(ids, ["GRS-12", "GRS-13", "GRS-20"]);
    let fams: Vec<(&str, &str)> = imp
        .families
        .iter()
        .map(|f| (f.family.as_str(), f.file_name.as_str()))
        .collect();
    // "release-velocity" sorts after "charge": numbered to keep the module's order
    assert_eq!(
        fams,
        [
            ("Release velocity", "01-release-velocity.yaml"),
            ("Charge", "02-charge.yaml")
        ]
    );
    let r12 = set.get("GRS-12").unwrap();
    assert_eq!(
        r12.text,
        "The GPRM shall release the TM with a velocity along the release axis below 5 µm/s\nwith 99.73 % probability."
    );
    assert_eq!(r12.source, "LPF-RS-0340 Tab. 4");
    let l12 = r12.limit.as_ref().unwrap();
    assert_eq!(l12.text, "<= 5 µm/s");
    assert_eq!(l12.dim.name(), Some("velocity"));
    assert_eq!(r12.method.to_string(), "analysis");
    assert_eq!(r12.activity, "not stated in the ReqIF file");
    assert!(r12.check.is_none(), "verify reports it not verified");
    // the numeric foreign ID with its prefix; the title falls back to the text
    assert!(r12.title.starts_with("The GPRM shall release"));
    // "Derived From" becomes the parent, its margin computed from the limits
    let (p, m) = set.get("GRS-13").unwrap().parent.clone().unwrap();
    assert_eq!(p.as_str(), "GRS-12");
    assert!((m - 1.5).abs() < 1e-12, "{m}");
    // a multi-valued method takes the first; other links are kept in the note
    assert_eq!(
        set.get("GRS-20").unwrap().method.to_string(),
        "review-of-design"
    );
    assert_eq!(
        set.get("GRS-20").unwrap().note.as_deref(),
        Some("ReqIF relation 'Satisfies' to GRS-12")
    );
}

#[test]
fn attribute_names_can_be_given() {
    let (name, text) = fixture("doors-style-lpf.reqif");
    let mut o = ImportOptions {
        skip_incomplete: true,
        ..ImportOptions::default()
    };
    o.attribute
        .insert(Field::Title, "ReqIF.ForeignCreatedBy".into());
    // an attribute the file does not have is the user's mistake: refused, naming the flag and
    // the attributes there are
    o.attribute.insert(Field::Limit, "Maximum".into());
    let e = reqif::import(&name, &text, &o).unwrap_err().to_string();
    assert!(
        e.contains("--attribute limit=Maximum: no attribute `Maximum` in this file")
            && e.contains("Verification Method"),
        "{e}"
    );
    o.attribute.remove(&Field::Limit);
    let (_, set) = import_to_set(&name, &text, &o);
    assert_eq!(set.get("GRS-12").unwrap().title, "jdoe");
    // a limit without a method is never given one: left out with a warning at its line, or
    // refused there with --strict
    let mut o = ImportOptions::default();
    o.attribute
        .insert(Field::Method, "ReqIF.ForeignCreatedBy".into());
    let imp = reqif::import(&name, &text, &o).unwrap();
    assert!(imp.skipped.iter().any(|s| s.id == "GRS-13"));
    let w = imp.warnings.iter().find(|w| w.line == 96).unwrap();
    assert!(
        w.cause.contains("requirement GRS-13 ")
            && w.cause
                .contains("no verification method (attribute `ReqIF.ForeignCreatedBy`)")
            && w.cause.ends_with("left out"),
        "{w:?}"
    );
    // GRS-12's method `jdoe` cannot be read: left out too
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.line == 83 && w.cause.contains("`jdoe`"))
    );
    o.strict = true;
    let e = reqif::import(&name, &text, &o).unwrap_err().to_string();
    assert!(
        e.starts_with("fixtures/doors-style-lpf.reqif:83: requirement GRS-12 ")
            && e.contains("--strict"),
        "{e}"
    );
}

/// Other tools name the statement and the identifier differently: DOORS Next's "Primary Text"
/// and a generic "Requirement ID" are read as ReqIF.Text and IE PUID are.
#[test]
fn other_tools_attribute_names_are_read() {
    let (name, text) = fixture("doors-capella-sample.reqif");
    let (_, want) = import_to_set(&name, &text, &ImportOptions::default());
    let renamed = text
        .replace("LONG-NAME=\"ReqIF.Text\"", "LONG-NAME=\"Primary Text\"")
        .replace("LONG-NAME=\"IE PUID\"", "LONG-NAME=\"Requirement ID\"");
    assert_ne!(renamed, text);
    let (_, got) = import_to_set(&name, &renamed, &ImportOptions::default());
    assert_eq!(content(&got), content(&want));
    assert!(!got.items.is_empty() && got.items.iter().all(|r| !r.text.is_empty()));
}

/// Imports `text`, loads the YAML, exports it, imports and exports again: the two exports are
/// the same apart from the creation time and the two loaded sets are the same.
fn assert_round_trip(name: &Path, text: &str, o: &ImportOptions) -> Requirements {
    let (_, set) = import_to_set(name, text, o);
    let first = reqif::export(&set, &opts("2026-01-01T00:00:00Z", None));
    let (imp2, back) = import_to_set(Path::new("set.reqif"), &first, &ImportOptions::default());
    assert!(imp2.skipped.is_empty());
    assert_eq!(content(&back), content(&set));
    let second = reqif::export(&back, &opts("2027-06-30T12:00:00Z", None));
    assert_eq!(
        without_creation_time(&first),
        without_creation_time(&second)
    );
    set
}

#[test]
fn polarion_doors_and_rmf_exports_without_limits_import_as_qualitative() {
    // real files: prose requirements, no limit, no method
    let (name, text) = fixture("polarion-sample.reqif");
    let (imp, set) = import_to_set(&name, &text, &ImportOptions::default());
    assert_eq!(imp.count(), 1);
    assert_eq!(imp.qualitative, 1);
    let r = &set.items[0];
    assert_eq!(r.id.as_str(), "LOREM-818");
    assert!(r.limit.is_none());
    assert_eq!(r.method.to_string(), "review-of-design");
    assert!(!r.text.trim().is_empty());
    assert_round_trip(&name, &text, &ImportOptions::default());
    // only quantitative ones wanted: nothing to import, each listed
    let o = ImportOptions {
        skip_incomplete: true,
        ..ImportOptions::default()
    };
    let e = reqif::import(&name, &text, &o).unwrap_err().to_string();
    assert!(
        e.starts_with("fixtures/polarion-sample.reqif:129: ")
            && e.contains("none of its 1 requirements"),
        "{e}"
    );

    let (name, text) = fixture("doors-capella-sample.reqif");
    let (imp, set) = import_to_set(&name, &text, &ImportOptions::default());
    assert_eq!(imp.source_tool, "IBM Rational DOORS");
    assert_eq!(imp.qualitative, imp.count());
    assert_eq!(set.items[0].id.as_str(), "PUID-1");
    assert!(set.items.iter().all(|r| r.limit.is_none()));
    assert_round_trip(&name, &text, &ImportOptions::default());

    // RIF/ReqIF 1.0.1 namespace: read; its objects have no text, so nothing is a requirement
    // until the attribute that holds one is named
    let (name, text) = fixture("rmf-spec-relation.reqif");
    let e = reqif::import(&name, &text, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no requirement in this file"), "{e}");
    // and names the attributes that could hold the text
    assert!(
        e.contains("Author") && e.contains("--attribute text=NAME"),
        "{e}"
    );
    let mut o = ImportOptions::default();
    o.attribute.insert(Field::Text, "Author".into());
    let (imp, set) = import_to_set(&name, &text, &o);
    assert_eq!(imp.count(), 2);
    assert!(
        set.get("REQ-2C84E85A-59D1-11DA-8EF5-AFDBD01C7A79")
            .is_some_and(|r| r.limit.is_none() && r.text == "Max Mustermann")
    );
    assert_round_trip(&name, &text, &o);

    // Eclipse RMF / ProR: names in XHTML `ReqIF.Name`, the prose in a string attribute `A1`
    let (name, text) = fixture("rmf-pror-sample.reqif");
    let mut o = ImportOptions::default();
    o.attribute.insert(Field::Text, "A1".into());
    let (imp, set) = import_to_set(&name, &text, &o);
    assert_eq!(imp.count(), 6);
    assert_eq!(imp.qualitative, 6);
    assert!(set.items.iter().all(|r| r.limit.is_none()
        && r.method.to_string() == "review-of-design"
        && !r.title.trim().is_empty()));
    assert_round_trip(&name, &text, &o);
}

#[test]
fn bad_files_name_the_line() {
    let (name, text) = fixture("doors-style-lpf.reqif");
    let cut = &text[..text.len() / 2];
    let e = reqif::import(&name, cut, &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("malformed XML"), "{e}");
    let e = reqif::import(&name, "<html><body/></html>", &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("fixtures/doors-style-lpf.reqif:1: not a ReqIF file"),
        "{e}"
    );
    // a limit the loader cannot read: that requirement is left out, said at its line
    let bad_limit = text.replace("&lt;= 1.1 V", "&lt;= 1.1 furlong");
    let imp = reqif::import(&name, &bad_limit, &ImportOptions::default()).unwrap();
    assert!(
        imp.skipped
            .iter()
            .any(|s| s.id == "GRS-20" && s.missing.iter().any(|m| m.contains("furlong")))
    );
    assert!(
        imp.warnings
            .iter()
            .any(|w| w.line == 113 && w.cause.contains("furlong"))
    );
    assert_eq!(imp.count(), 3);
}

/// What a StrictDoc round trip does to an export: the relations keep their type and ends but
/// lose `geodesic.DerivationMargin`, and a limit edited there leaves `geodesic.LimitValue` as
/// it was. Both are said; the margin is recomputed from the edited limits (issue 52).
#[test]
fn a_round_trip_that_drops_margins_or_edits_a_limit_warns() {
    let reqs = repo_requirements();
    let first = reqif::export(&reqs, &opts("2026-01-01T00:00:00Z", None));
    // every tool reads it: no REAL, no empty value
    assert!(!first.contains("REAL") && !first.contains("THE-VALUE=\"\""));
    let (imp, _) = import_to_set(Path::new("g.reqif"), &first, &ImportOptions::default());
    assert!(imp.warnings.is_empty(), "{:?}", imp.warnings);
    // the margins dropped
    let mut edited = String::new();
    let mut rest = first.as_str();
    while let Some(i) = rest.find("<SPEC-RELATION ") {
        let (head, tail) = rest.split_at(i);
        edited.push_str(head);
        let v0 = tail.find("<VALUES>").unwrap();
        let v1 = tail.find("</VALUES>").unwrap() + "</VALUES>".len();
        assert!(v1 < tail.find("<SOURCE>").unwrap());
        edited.push_str(&tail[..v0]);
        rest = &tail[v1..];
    }
    edited.push_str(rest);
    // REL-DFACS-VEL's limit doubled in its text only
    let child = reqs.get("REL-DFACS-VEL").unwrap();
    let (parent, margin) = child.parent.clone().unwrap();
    let l = child.limit.as_ref().unwrap();
    let at = edited
        .find("IDENTIFIER=\"geodesic-req-REL-DFACS-VEL\"")
        .unwrap();
    let def = at
        + edited[at..]
            .find(">geodesic-ad-req-limit</ATTRIBUTE-DEFINITION-STRING-REF>")
            .unwrap();
    let v = edited[..def].rfind("THE-VALUE=\"").unwrap() + "THE-VALUE=\"".len();
    let end = v + edited[v..].find('"').unwrap();
    let new_limit = format!("&lt;= {} {}", 2.0 * l.in_unit(), l.unit.symbol);
    edited.replace_range(v..end, &new_limit);
    let (imp, back) = import_to_set(Path::new("s.reqif"), &edited, &ImportOptions::default());
    let said = |what: &str| imp.warnings.iter().any(|w| w.cause.contains(what));
    assert!(
        said("from REL-DFACS-VEL to REL-GPRM-VEL has no geodesic.DerivationMargin: recomputed"),
        "{:?}",
        imp.warnings
    );
    assert!(said("contradicts geodesic.Limit"), "{:?}", imp.warnings);
    let moved = back.get("REL-DFACS-VEL").unwrap().parent.clone().unwrap();
    assert_eq!(moved.0, parent);
    assert!((moved.1 - 2.0 * margin).abs() < 1e-9 * margin, "{moved:?}");
}

/// A StrictDoc export: its `[TEXT]` node is not a requirement; a requirement without a UID
/// gets an ID from its content, the same whatever identifier the export gave it (issue 52).
#[test]
fn strictdoc_text_nodes_are_left_out_and_nodes_without_a_uid_keep_their_id() {
    let (name, text) = fixture("strictdoc-text-node.reqif");
    let ids = |text: &str| -> Vec<String> {
        let (imp, set) = import_to_set(&name, text, &ImportOptions::default());
        assert!(imp.warnings.is_empty(), "{:?}", imp.warnings);
        assert_eq!(imp.spec_objects, 3);
        set.items.iter().map(|r| r.id.to_string()).collect()
    };
    let first = ids(&text);
    assert_eq!(first.len(), 2, "{first:?}");
    assert!(first.contains(&"REL-B".to_string()), "{first:?}");
    let generated = first.iter().find(|i| *i != "REL-B").unwrap();
    assert!(
        generated.starts_with("REQ-") && generated.len() == 14,
        "{generated}"
    );
    // the next export: new UUIDs, the same IDs
    let again = text
        .replace(
            "026322f4-1bb6-4579-97c2-9167e4ad3d47",
            "11111111-2222-4333-8444-555555555555",
        )
        .replace(
            "a0493ed1-d908-440d-97ef-171baaffe1b4",
            "66666666-7777-4888-9999-aaaaaaaaaaaa",
        )
        .replace(
            "67dad31e-88b0-482a-ad14-a9653a7d4974",
            "bbbbbbbb-cccc-4ddd-8eee-ffffffffffff",
        );
    assert_ne!(again, text);
    assert_eq!(ids(&again), first);
}
