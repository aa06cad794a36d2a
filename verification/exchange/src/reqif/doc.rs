//! The JSON documents of `geodesic export reqif --json` and `geodesic import reqif --json`
//! (docs/spec/interface.md). Fields are declared in byte order of their keys, the order the
//! documents have always printed. Counts are numbers of requirements (or of ReqIF elements, as
//! named); lines are 1-based lines of the ReqIF file; nothing here has a physical unit.

use super::{ExportOptions, Imported};
use geodesic_core::Requirements;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The summary of `geodesic export reqif --json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ExportDoc {
    /// The header's `CREATION-TIME` (xsd:dateTime, UTC; `SOURCE_DATE_EPOCH` fixes it).
    pub creation_time: String,
    /// The file written, as given on the command line.
    pub out: String,
    /// Derivations written (SPEC-RELATIONs: requirements with a parent).
    pub relations: usize,
    /// Requirements written.
    pub requirements: usize,
    /// Where the requirement set came from (a folder, or the built-in set).
    pub requirements_source: String,
    /// SHA-256 of the file written, lower-case hex.
    pub sha256: String,
    /// Whether the VCD status of a compliance matrix was written.
    pub with_status: bool,
}

impl ExportDoc {
    /// The summary of `reqif`, the document [`super::export`] made of `reqs` with `opts`,
    /// written to `out`; `requirements_source` names where `reqs` came from.
    pub fn new(
        reqs: &Requirements,
        reqif: &str,
        out: &Path,
        requirements_source: &str,
        opts: &ExportOptions,
    ) -> ExportDoc {
        ExportDoc {
            creation_time: opts.creation_time.to_string(),
            out: out.display().to_string(),
            relations: reqs.items.iter().filter(|r| r.parent.is_some()).count(),
            requirements: reqs.items.len(),
            requirements_source: requirements_source.to_string(),
            sha256: geodesic_util::hash::sha256_hex(reqif.as_bytes()),
            with_status: opts.status.is_some(),
        }
    }
}

/// The summary of `geodesic import reqif --json`: what was imported, left out and warned
/// about, and which attribute supplied each field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ImportDoc {
    /// The document read: the file, or `ARCHIVE!DOCUMENT` for a `.reqifz`.
    pub document: String,
    /// SPEC-OBJECTs defined a second time with the same IDENTIFIER (ignored).
    pub duplicates: usize,
    /// The families written, one YAML file each, in document order.
    pub families: Vec<FamilyDoc>,
    /// The ReqIF file, as given on the command line.
    pub file: String,
    /// Heading objects read (families).
    pub headings: usize,
    /// Per field (its YAML key, e.g. `limit`), each source of its values with the number of
    /// requirements it supplied.
    pub mapping: BTreeMap<String, Vec<MappingSourceDoc>>,
    /// Objects without any text: not requirements.
    pub other_objects: usize,
    /// The folder written, as given on the command line.
    pub out: String,
    /// Requirements imported as qualitative (no limit).
    pub qualitative: usize,
    /// SPEC-RELATIONs read.
    pub relations: usize,
    /// Requirements imported.
    pub requirements: usize,
    /// Requirements left out, and why.
    pub skipped: Vec<SkippedDoc>,
    /// `SOURCE-TOOL-ID` of the header.
    pub source_tool: String,
    /// SPEC-OBJECT elements in the file: requirements, headings, objects without text,
    /// duplicates and skipped requirements add up to it.
    pub spec_objects: usize,
    /// Attributes with values on the imported requirements that no field took (candidates for
    /// `--attribute`).
    pub unmapped: Vec<UnmappedDoc>,
    /// Every problem of the file, by line (standard error prints the first ones only).
    pub warnings: Vec<WarningDoc>,
}

/// One family of [`ImportDoc`].
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FamilyDoc {
    /// Family name.
    pub family: String,
    /// The YAML file's name in the output folder (`01-release-velocity.yaml`).
    pub file: String,
    /// Requirements in it.
    pub requirements: usize,
}

/// One requirement left out ([`ImportDoc::skipped`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SkippedDoc {
    /// The geodesic ID it would have had.
    pub id: String,
    /// Line of its SPEC-OBJECT.
    pub line: u32,
    /// What is missing, one phrase each.
    pub missing: Vec<String>,
}

/// One problem of the file ([`ImportDoc::warnings`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct WarningDoc {
    /// One-line cause and what was done about it.
    pub cause: String,
    /// Line in the ReqIF file.
    pub line: u32,
}

/// One source of a field's values ([`ImportDoc::mapping`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct MappingSourceDoc {
    /// Requirements whose value came from it.
    pub requirements: usize,
    /// `attribute `NAME``, or the fallback used.
    pub source: String,
}

/// An attribute no field took ([`ImportDoc::unmapped`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct UnmappedDoc {
    /// The attribute's LONG-NAME.
    pub attribute: String,
    /// Imported requirements carrying it.
    pub requirements: usize,
}

impl ImportDoc {
    /// The summary of `imported`, read from `file` and written into the folder `out`.
    pub fn new(imported: &Imported, file: &Path, out: &Path) -> ImportDoc {
        ImportDoc {
            document: imported.document.clone(),
            duplicates: imported.duplicates,
            families: imported
                .families
                .iter()
                .map(|f| FamilyDoc {
                    family: f.family.clone(),
                    file: f.file_name.clone(),
                    requirements: f.requirements.len(),
                })
                .collect(),
            file: file.display().to_string(),
            headings: imported.headings,
            mapping: imported
                .mapping
                .iter()
                .map(|m| {
                    let sources = m.sources.iter().map(|(s, n)| MappingSourceDoc {
                        requirements: *n,
                        source: s.clone(),
                    });
                    (m.field.name().to_string(), sources.collect())
                })
                .collect(),
            other_objects: imported.other_objects,
            out: out.display().to_string(),
            qualitative: imported.qualitative,
            relations: imported.relations,
            requirements: imported.count(),
            skipped: imported
                .skipped
                .iter()
                .map(|s| SkippedDoc {
                    id: s.id.clone(),
                    line: s.line,
                    missing: s.missing.clone(),
                })
                .collect(),
            source_tool: imported.source_tool.clone(),
            spec_objects: imported.spec_objects,
            unmapped: imported
                .unmapped
                .iter()
                .map(|(n, k)| UnmappedDoc {
                    attribute: n.clone(),
                    requirements: *k,
                })
                .collect(),
            warnings: imported
                .warnings
                .iter()
                .map(|w| WarningDoc {
                    cause: w.cause.clone(),
                    line: w.line,
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reqif::{ImportOptions, import};

    /// The document as printed (fields in declaration order) equals it with every object's
    /// keys sorted (a `serde_json::Value`): the declaration order is byte order, the order the
    /// documents have always printed.
    fn printed_in_byte_order<T: Serialize>(doc: &T) -> String {
        let printed = serde_json::to_string(doc).unwrap();
        let sorted = serde_json::to_value(doc).unwrap().to_string();
        assert_eq!(printed, sorted);
        printed
    }

    #[test]
    fn import_doc_keeps_its_keys_and_reads_back() {
        let fixtures = [
            (
                "doors-style-lpf.reqif",
                include_str!("../../tests/fixtures/doors-style-lpf.reqif"),
            ),
            (
                "polarion-sample.reqif",
                include_str!("../../tests/fixtures/polarion-sample.reqif"),
            ),
            (
                "doors-capella-sample.reqif",
                include_str!("../../tests/fixtures/doors-capella-sample.reqif"),
            ),
        ];
        let opts = ImportOptions {
            skip_incomplete: true,
            ..ImportOptions::default()
        };
        let mut docs = Vec::new();
        for (name, text) in fixtures {
            let file = Path::new(name);
            // doors-style-lpf with --skip-incomplete: its qualitative GRS-21 is skipped
            let o = if name.starts_with("doors-style") {
                opts.clone()
            } else {
                ImportOptions::default()
            };
            let doc = ImportDoc::new(&import(file, text, &o).unwrap(), file, Path::new("out"));
            let printed = printed_in_byte_order(&doc);
            // interface.md's keys
            for k in [
                "file",
                "out",
                "source_tool",
                "requirements",
                "families",
                "skipped",
                "headings",
                "other_objects",
                "relations",
            ] {
                assert!(printed.contains(&format!("\"{k}\":")), "{name}: {k}");
            }
            assert_eq!(serde_json::from_str::<ImportDoc>(&printed).unwrap(), doc);
            docs.push(doc);
        }
        // each list of the document is exercised (not empty) by one fixture
        assert_eq!(docs[0].requirements, 3);
        assert_eq!(docs[0].skipped[0].id, "GRS-21");
        assert!(docs[0].mapping.contains_key("limit"));
        assert!(!docs[1].warnings.is_empty());
        assert!(!docs[2].unmapped.is_empty());
        assert!(docs.iter().all(|d| !d.families.is_empty()));
    }

    #[test]
    fn export_doc_keeps_its_keys_and_reads_back() {
        let doc = ExportDoc {
            creation_time: "2026-11-28T00:00:00Z".into(),
            out: "reports/requirements.reqif".into(),
            relations: 2,
            requirements: 28,
            requirements_source: "requirements".into(),
            sha256: "00".repeat(32),
            with_status: false,
        };
        let printed = printed_in_byte_order(&doc);
        assert_eq!(serde_json::from_str::<ExportDoc>(&printed).unwrap(), doc);
    }
}
