//! What an import leaves behind: the requirement files written whole or not at all, and the
//! import's warnings and attribute mapping as text for a program to print.

use super::{Imported, ImportedFamily};
use std::path::Path;

/// Why the families could not be written.
#[derive(Debug)]
pub enum WriteFamilies {
    /// The folder already holds requirement YAML (a usage error).
    Occupied(String),
    /// Writing failed.
    Io(String),
}

/// Writes the families into `out` whole or not at all: staged in `out/.staging-PID`, then
/// moved into `out`; refuses a folder that already holds requirement YAML.
pub fn write_families(out: &Path, families: &[ImportedFamily]) -> Result<(), WriteFamilies> {
    // write whole or not at all: stage in DIR/.staging-PID, then move the files into DIR
    if out.is_dir() {
        let existing = std::fs::read_dir(out)
            .map_err(|e| WriteFamilies::Io(format!("{}: {e}", out.display())))?
            .filter_map(|e| e.ok())
            .any(|e| {
                matches!(
                    e.path().extension().and_then(|x| x.to_str()),
                    Some("yaml" | "yml")
                )
            });
        if existing {
            return Err(WriteFamilies::Occupied(format!(
                "{}: already holds requirement YAML files; import into an empty or new directory",
                out.display()
            )));
        }
    }
    let stage = out.join(format!(".staging-{}", std::process::id()));
    let io = |e: std::io::Error| WriteFamilies::Io(format!("{}: {e}", out.display()));
    std::fs::create_dir_all(&stage).map_err(io)?;
    let staged = (|| -> std::io::Result<()> {
        for f in families {
            std::fs::write(stage.join(&f.file_name), &f.yaml)?;
        }
        for f in families {
            std::fs::rename(stage.join(&f.file_name), out.join(&f.file_name))?;
        }
        Ok(())
    })();
    let _ = std::fs::remove_dir_all(&stage);
    staged.map_err(io)?;
    Ok(())
}

/// The import's warnings (at most `max`) and the qualitative requirements `--skip-incomplete`
/// left out, one line each (`warning: FILE:LINE: cause`).
pub fn warning_lines(imported: &Imported, max: usize) -> Vec<String> {
    let mut out = Vec::new();
    let shown = imported.warnings.len().min(max);
    for w in &imported.warnings[..shown] {
        out.push(format!(
            "warning: {}:{}: {}",
            imported.document, w.line, w.cause
        ));
    }
    if imported.warnings.len() > shown {
        out.push(format!(
            "warning: {}: {} more warnings (all of them in --json)",
            imported.document,
            imported.warnings.len() - shown
        ));
    }
    // the qualitative requirements --skip-incomplete left out (the incomplete ones are warned)
    for s in imported
        .skipped
        .iter()
        .filter(|s| s.missing.len() == 1 && s.missing[0].ends_with(": qualitative"))
    {
        out.push(format!(
            "{}:{}: skipped requirement {}: {}",
            imported.document,
            s.line,
            s.id,
            s.missing.join("; ")
        ));
    }
    out
}

/// Which ReqIF attribute each geodesic field was taken from (`import reqif --report`), as text.
pub fn mapping_text(imported: &Imported) -> String {
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{}: ReqIF attribute -> geodesic field, over the {} requirements imported:",
        imported.document,
        imported.count()
    );
    for m in &imported.mapping {
        let parts: Vec<String> = m
            .sources
            .iter()
            .map(|(s, n)| format!("{s} ({n})"))
            .collect();
        let _ = writeln!(o, "  {:<15} <- {}", m.field.name(), parts.join("; "));
    }
    if imported.unmapped.is_empty() {
        let _ = writeln!(o, "  every attribute with a value was taken by a field");
    } else {
        let parts: Vec<String> = imported
            .unmapped
            .iter()
            .map(|(n, k)| format!("`{n}` ({k})"))
            .collect();
        let _ = writeln!(o, "  not taken by any field: {}", parts.join(", "));
    }
    let _ = writeln!(
        o,
        "  to take another attribute for a field: --attribute FIELD=NAME (docs/exchange.md)"
    );
    o
}
