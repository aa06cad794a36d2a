//! The JSON Schemas (draft 2020-12) of the commands' `--json` documents (`geodesic schema`),
//! generated from the typed structs the commands serialize: each output type derives
//! `schemars::JsonSchema` beside its `Serialize`, so schemars reads the same serde attributes
//! (renames, skipped fields, tags, flattening) and the structs' doc comments (with their units)
//! become the schemas' `description`s. A schema cannot drift from the code that prints the
//! document; `verification/cli/tests/schema.rs` and `.ci/clients.sh` validate real output
//! against it.

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema};
use serde::Serialize;
use std::path::Path;

/// One command's schema: the command's name (as typed after `geodesic`) and the generator of
/// the schema of the JSON document it prints with `--json`.
#[derive(Clone, Copy)]
pub struct Entry {
    /// The command (`verify`, `fit`, `montecarlo`, ...).
    pub command: &'static str,
    /// The schema of its `--json` document, without `$id` and `title` ([`Entry::schema`] adds them).
    pub generate: fn() -> Schema,
}

impl Entry {
    /// The entry of `command`, whose `--json` document is a serialised `T`.
    pub fn of<T: JsonSchema>(command: &'static str) -> Entry {
        Entry {
            command,
            generate: root::<T>,
        }
    }

    /// The command's schema: draft 2020-12, `$id` `urn:geodesic:schema:COMMAND`, `title`
    /// `geodesic COMMAND --json`, and the output type's doc comment as its `description`.
    pub fn schema(&self) -> Schema {
        let mut s = (self.generate)();
        s.insert(
            "$id".into(),
            format!("urn:geodesic:schema:{}", self.command).into(),
        );
        s.insert(
            "title".into(),
            format!("geodesic {} --json", self.command).into(),
        );
        s
    }

    /// The schema as the text `geodesic schema COMMAND` prints (pretty JSON, one newline at the
    /// end).
    pub fn text(&self) -> String {
        let mut t = serde_json::to_string_pretty(&self.schema())
            .expect("a schema is a JSON value and always serialises");
        t.push('\n');
        t
    }
}

/// The root schema of `T` for a document that is written (serde's serialisation contract:
/// a field skipped when empty is optional, every other field required).
fn root<T: JsonSchema>() -> Schema {
    SchemaSettings::draft2020_12()
        .for_serialize()
        .into_generator()
        .into_root_schema_for::<T>()
}

/// Writes `DIR/<command>.schema.json` for every entry, each file whole or not at all.
pub fn write_all(entries: &[Entry], dir: &Path) -> Result<Vec<std::path::PathBuf>, String> {
    let mut written = Vec::new();
    for e in entries {
        let path = dir.join(format!("{}.schema.json", e.command));
        geodesic_util::output::write_whole(&path, e.text().as_bytes())
            .map_err(|err| format!("{}: {err}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

/// The document `geodesic verify --json` prints (and `reports/compliance.json`): the compliance
/// report, and with `--baseline` the comparison with the baseline.
#[derive(Serialize, JsonSchema)]
pub struct VerifyDoc<'a> {
    /// The compliance report: the matrix and how it was produced.
    #[serde(flatten)]
    pub report: &'a geodesic_report::Report,
    /// With `--baseline OLD.json`: what changed against the baseline and whether the gate
    /// passes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline_diff: Option<&'a geodesic_report::baseline::Diff>,
}

/// What `geodesic schema --json` prints without a command: the commands that have a schema,
/// and with `--all --out DIR` the files written.
#[derive(Serialize, JsonSchema)]
pub struct ListDoc {
    /// The commands whose `--json` document has a schema (`geodesic schema COMMAND`).
    pub commands: Vec<String>,
    /// With `--all --out DIR`: the files written, `DIR/<command>.schema.json`, one a command.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub written: Vec<String>,
}
