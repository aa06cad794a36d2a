//! geodesic-exchange: the requirement set exchanged with the tools system engineers use.
//!
//! - [`reqif::export`] writes the requirement set (and, given a `compliance.json`, the status of
//!   each row of the Verification Control Document) as a ReqIF 1.2 file (OMG, namespace
//!   `http://www.omg.org/spec/ReqIF/20110401/reqif.xsd`) that validates against the OMG schema.
//! - [`needs::export`] writes the same as a sphinx-needs `needs.json`.
//! - [`reqif::import`] reads a ReqIF file written by geodesic, IBM DOORS / DOORS Next, Polarion
//!   or another tool into requirement YAML in geodesic's format ([`yaml`]).
//!
//! The mapping of attributes (standard `ReqIF.*` names and geodesic's `geodesic.*` ones), the
//! fallbacks for fields a foreign file lacks and the determinism rules are in
//! `docs/exchange.md`.
//!
//! # Why `roxmltree`, and no XML crate for writing
//!
//! Reading: `roxmltree` (MIT/Apache-2.0, one dependency, `memchr`, already in the tree) parses
//! the whole document into a read-only tree with namespaces resolved and the line and column of
//! every node, which is what an importer needs: ReqIF is a graph of identifiers (attribute
//! definitions, enumeration values, objects, hierarchy, relations) resolved by look-up, and
//! every error must name `file:line`. It refuses malformed XML with a position, refuses a DTD
//! by default (so no entity expansion attacks, no external entities), caps the node count
//! (set here), and is `#![forbid(unsafe_code)]`.
//! `quick-xml` is a fast streaming reader/writer; with it the importer would build its own tree
//! and compute lines from byte offsets, for no gain on files of a few megabytes. `xml-rs` is
//! slower and its maintenance has been uneven; `libxml` bindings need a system library.
//!
//! Writing: the export is one fixed document shape with deterministic identifiers, written with
//! a small escaping writer ([`xml`]) as the project writes its HTML and JUnit; a writer crate
//! would add a dependency for `&lt;` and indentation.

#![warn(missing_docs)]
pub mod needs;
pub mod reqif;
pub mod status;
pub mod xml;
