//! The identification of the controlled documents `geodesic verify` writes, read from a small
//! YAML file (`verification/document.yaml`): document identifier, issue, title and project.
//! Every report carries it with the run's identification.

use crate::requirement::{LoadError, LoadKind, Origin, yaml_error};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Document identification (every field non-empty).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Document {
    /// Document identifier (`GEO-WID-VCD-001`).
    pub id: String,
    /// Issue (`1`, `2.1`).
    pub issue: String,
    /// Document title.
    pub title: String,
    /// Project.
    pub project: String,
}

impl Document {
    /// Parses the YAML `text` of `file` (the path is used in messages only). Errors name
    /// `file:line:column` and the cause in one line.
    pub fn from_yaml(text: &str, file: &Path) -> Result<Document, LoadError> {
        let d: Document = serde_saphyr::from_str(text).map_err(|e| yaml_error(file, &e))?;
        for (name, v) in [
            ("id", &d.id),
            ("issue", &d.issue),
            ("title", &d.title),
            ("project", &d.project),
        ] {
            if v.trim().is_empty() || v.contains('\n') {
                return Err(LoadError {
                    origin: Origin {
                        file: file.to_path_buf(),
                        line: line_of(text, name),
                        column: 1,
                    },
                    kind: LoadKind::Invalid,
                    cause: format!("document `{name}` must be one non-empty line"),
                });
            }
        }
        Ok(d)
    }
}

fn line_of(text: &str, key: &str) -> u64 {
    text.lines()
        .position(|l| l.starts_with(&format!("{key}:")))
        .map_or(1, |i| i as u64 + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_repository_file_and_names_bad_fields() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../document.yaml");
        let d = Document::from_yaml(&std::fs::read_to_string(&p).unwrap(), &p).unwrap();
        assert!(!d.id.is_empty() && !d.issue.is_empty());
        let e = Document::from_yaml(
            "id: A\nissue: \"\"\ntitle: t\nproject: p\n",
            Path::new("d.yaml"),
        )
        .unwrap_err()
        .to_string();
        assert_eq!(e, "d.yaml:2:1: document `issue` must be one non-empty line");
        let e = Document::from_yaml(
            "id: A\nissue: \"1\"\ntitle: t\nproject: p\nowner: x\n",
            Path::new("d.yaml"),
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("d.yaml:5:") && e.contains("owner"), "{e}");
    }
}
