//! ReqIF 1.2 (OMG formal/2016-07-01, XML namespace `http://www.omg.org/spec/ReqIF/20110401/reqif.xsd`).
//!
//! A ReqIF file holds datatypes, object types with attribute definitions, objects (the
//! requirements and the headings), a hierarchy of those objects per specification (the
//! document), and relations between objects. geodesic maps its requirement set as:
//!
//! | geodesic | ReqIF |
//! | --- | --- |
//! | family (one YAML file) | a heading object (type `Heading`): `ReqIF.ChapterName` = family, `ReqIF.Text` = description; its requirements are its children in the SPEC-HIERARCHY |
//! | `id` | `ReqIF.ForeignID`; object identifier `geodesic-req-ID` |
//! | `title` | `ReqIF.Name` |
//! | `text` | `ReqIF.Text` (XHTML `div`, line breaks as `br`) |
//! | `source`, `quantity`, `dimension`, `limit`, `probability`, `activity`, `check`, `note` | `geodesic.Source`, `geodesic.Quantity`, ... (strings) |
//! | the limit's number and unit | `geodesic.LimitValue` (real, in the unit), `geodesic.Unit` |
//! | `method` | `geodesic.Method`, an enumeration (test, analysis, review-of-design, inspection) |
//! | `parent: {id, margin}` | a SPEC-RELATION of type `geodesic.DerivedFrom` from the child (source) to the parent (target) with `geodesic.DerivationMargin` |
//! | VCD status (with `--matrix`) | `geodesic.Status`, `geodesic.Basis`, `geodesic.CloseOut` (enumerations), `geodesic.Value`, `geodesic.Margin` (reals), `geodesic.Disposition`, `geodesic.Remarks` |

mod archive;
mod doc;
mod export;
mod fields;
mod import;
mod output;
mod read;
mod xhtml;
pub mod yaml;

pub use archive::{MAX_DOCUMENT_BYTES, import_file, is_archive};
pub use doc::{
    ExportDoc, FamilyDoc, ImportDoc, MappingSourceDoc, SkippedDoc, UnmappedDoc, WarningDoc,
};
pub use export::{ExportOptions, export};
pub use fields::Field;
pub use import::{
    ImportError, ImportOptions, Imported, ImportedFamily, ImportedRequirement, MappingRow, Skipped,
    Warning, import,
};
pub use output::{WriteFamilies, mapping_text, warning_lines, write_families};
pub use xhtml::{text_to_xhtml, xhtml_objects, xhtml_to_text};

/// The ReqIF 1.2 XML namespace.
pub const NAMESPACE: &str = "http://www.omg.org/spec/ReqIF/20110401/reqif.xsd";
/// The XHTML namespace of rich-text values.
pub const XHTML_NAMESPACE: &str = "http://www.w3.org/1999/xhtml";

/// Standard attribute: the identifier in the tool that wrote the object.
pub const FOREIGN_ID: &str = "ReqIF.ForeignID";
/// Standard attribute: the object's name (title).
pub const NAME: &str = "ReqIF.Name";
/// Standard attribute: the object's text (XHTML).
pub const TEXT: &str = "ReqIF.Text";
/// Standard attribute: a heading's text (DOORS "Object Heading").
pub const CHAPTER_NAME: &str = "ReqIF.ChapterName";
/// Standard attribute: a description (some tools put the text here).
pub const DESCRIPTION: &str = "ReqIF.Description";
/// Standard attribute: a prefix of the foreign ID (DOORS module prefix).
pub const PREFIX: &str = "ReqIF.Prefix";
