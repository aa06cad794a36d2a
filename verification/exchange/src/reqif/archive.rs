//! `.reqifz`: a ZIP archive of ReqIF documents and the files their XHTML embeds, as Polarion,
//! ReqIF Studio and DOORS Next export them.
//!
//! The archive's `.reqif` document is imported as a `.reqif` file is (its messages name it
//! `ARCHIVE!DOCUMENT:LINE`); the other files (pictures, OLE objects) are the embedded objects
//! the text refers to as `[object: DATA]` and are not imported. An archive of several
//! documents imports the first (in name order) and says which were left out; `--strict`
//! refuses it. macOS resource forks (`__MACOSX/`) are skipped.
//!
//! Why the `zip` crate: it is already in the tree (the XLSX writer's), with deflate only, so
//! reading archives adds no crate; a ZIP reader by hand would repeat its central-directory,
//! ZIP64 and deflate handling for nothing.

use super::import::{ImportError, ImportOptions, Imported, Warning, import};
use std::io::Read;
use std::path::Path;

/// Largest size of a document read out of an archive [bytes]: the limit the CLI sets on a
/// `.reqif` file (256 MiB), a guard against archives that expand without bound.
pub const MAX_DOCUMENT_BYTES: u64 = 256 << 20;

/// Largest number of entries of an archive read.
pub const MAX_ENTRIES: usize = 100_000;

/// Whether `bytes` are a ZIP archive (a `.reqifz`).
pub fn is_archive(bytes: &[u8]) -> bool {
    bytes.starts_with(b"PK\x03\x04") || bytes.starts_with(b"PK\x05\x06")
}

/// Imports a `.reqif` file or a `.reqifz` archive from its bytes (`file` names it in
/// messages). The result's [`Imported::document`] names what was read.
pub fn import_file(
    file: &Path,
    bytes: &[u8],
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let fname = file.display().to_string();
    let fail = |cause: String| ImportError {
        file: fname.clone(),
        line: 1,
        cause,
    };
    if !is_archive(bytes) {
        let text = geodesic_util::fsio::utf8(bytes.to_vec()).map_err(|e| ImportError {
            file: fname.clone(),
            line: e.line().max(1) as u32,
            cause: e.cause(),
        })?;
        let mut imp = import(file, &text, opts)?;
        imp.document = fname;
        return Ok(imp);
    }
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| fail(format!("not a readable .reqifz (ZIP) archive: {e}")))?;
    if zip.len() > MAX_ENTRIES {
        return Err(fail(format!(
            "the archive holds {} entries, more than {MAX_ENTRIES}",
            zip.len()
        )));
    }
    let mut documents: Vec<(usize, String)> = (0..zip.len())
        .filter_map(|i| {
            let e = zip.by_index_raw(i).ok()?;
            let name = e.name().ok()?.to_string();
            let doc = e.is_file()
                && name.to_ascii_lowercase().ends_with(".reqif")
                && !name.starts_with("__MACOSX/")
                && !name.rsplit('/').next().unwrap_or("").starts_with("._");
            doc.then_some((i, name))
        })
        .collect();
    documents.sort_by(|a, b| a.1.cmp(&b.1));
    let Some((first, name)) = documents.first().cloned() else {
        return Err(fail(
            "the archive holds no .reqif document (a .reqifz must hold one)".into(),
        ));
    };
    let inner = format!("{fname}!{name}");
    let mut entry = zip
        .by_index(first)
        .map_err(|e| fail(format!("{name}: cannot be read from the archive: {e}")))?;
    let mut data = Vec::new();
    (&mut entry)
        .take(MAX_DOCUMENT_BYTES + 1)
        .read_to_end(&mut data)
        .map_err(|e| fail(format!("{name}: cannot be read from the archive: {e}")))?;
    drop(entry);
    if data.len() as u64 > MAX_DOCUMENT_BYTES {
        return Err(fail(format!(
            "{name}: expands beyond {} MiB",
            MAX_DOCUMENT_BYTES >> 20
        )));
    }
    let text = geodesic_util::fsio::utf8(data).map_err(|e| ImportError {
        file: inner.clone(),
        line: e.line().max(1) as u32,
        cause: e.cause(),
    })?;
    let left_out: Vec<&str> = documents[1..].iter().map(|(_, n)| n.as_str()).collect();
    // the archive's own problem comes before any of its document's
    let several = (!left_out.is_empty()).then(|| Warning {
        line: 1,
        cause: format!(
            "the archive holds {} ReqIF documents: {name} is imported, {} not (unzip the archive and import each)",
            documents.len(),
            left_out.join(", ")
        ),
    });
    if let (Some(w), true) = (&several, opts.strict) {
        return Err(ImportError {
            file: inner,
            line: 1,
            cause: format!(
                "{} (--strict refuses the file at its first problem; without it, each is a warning)",
                w.cause
            ),
        });
    }
    let mut imp = import(Path::new(&inner), &text, opts)?;
    if let Some(w) = several {
        imp.warnings.insert(0, w);
    }
    imp.document = inner;
    Ok(imp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn archive(entries: &[(&str, &[u8])]) -> Vec<u8> {
        let mut w = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        let o = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        for (name, data) in entries {
            w.start_file(*name, o).unwrap();
            w.write_all(data).unwrap();
        }
        w.finish().unwrap().into_inner()
    }

    const DOC: &str = r#"<REQ-IF xmlns="http://www.omg.org/spec/ReqIF/20110401/reqif.xsd"><CORE-CONTENT><REQ-IF-CONTENT><SPEC-OBJECTS><SPEC-OBJECT IDENTIFIER="a" LONG-NAME="The TM shall be free."/></SPEC-OBJECTS></REQ-IF-CONTENT></CORE-CONTENT></REQ-IF>"#;

    #[test]
    fn archives_are_read_and_their_problems_said() {
        let p = Path::new("x.reqifz");
        let o = ImportOptions::default();
        let a = archive(&[("img/fig.png", b"\x89PNG"), ("doc.reqif", DOC.as_bytes())]);
        let imp = import_file(p, &a, &o).unwrap();
        assert_eq!(imp.document, "x.reqifz!doc.reqif");
        assert_eq!(imp.count(), 1);
        // two documents: the first imported, the other said; --strict refuses
        let a = archive(&[("b.reqif", DOC.as_bytes()), ("a.reqif", DOC.as_bytes())]);
        let imp = import_file(p, &a, &o).unwrap();
        assert_eq!(imp.document, "x.reqifz!a.reqif");
        assert!(imp.warnings[0].cause.contains("b.reqif not"));
        let strict = ImportOptions {
            strict: true,
            ..ImportOptions::default()
        };
        let e = import_file(p, &a, &strict).unwrap_err().to_string();
        assert!(
            e.starts_with("x.reqifz!a.reqif:1: the archive holds 2"),
            "{e}"
        );
        // no document, a broken archive, a document that is not UTF-8
        let e = import_file(p, &archive(&[("a.png", b"x")]), &o).unwrap_err();
        assert!(e.to_string().contains("no .reqif document"), "{e}");
        let mut broken = archive(&[("a.reqif", DOC.as_bytes())]);
        broken.truncate(broken.len() / 2);
        let e = import_file(p, &broken, &o).unwrap_err();
        assert!(e.to_string().contains("not a readable .reqifz"), "{e}");
        let e = import_file(p, &archive(&[("a.reqif", b"<a>\xff</a>")]), &o).unwrap_err();
        assert!(e.to_string().starts_with("x.reqifz!a.reqif:1: "), "{e}");
    }
}
