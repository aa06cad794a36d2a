//! Up-front checks of a command's outputs and inputs, made before any computation (issue 35,
//! item 2): a folder that cannot be written, a file where a folder is expected, a missing or
//! unreadable input is one line naming the flag and the path, exit 2, within a second, instead
//! of after a long run. Nothing is created: a writable folder is probed with a uniquely named
//! empty file, removed at once. Also the worker pool of `--threads` ([`with_threads`]), shared
//! by the commands that take it.

use std::path::{Path, PathBuf};

use crate::error::Error as CliError;

/// The nearest existing ancestor of `p` (itself if it exists; `.` for a relative path none of
/// whose ancestors exists).
fn existing_ancestor(p: &Path) -> PathBuf {
    let mut cur = Some(p);
    while let Some(c) = cur {
        let c = if c.as_os_str().is_empty() {
            Path::new(".")
        } else {
            c
        };
        if c.exists() {
            return c.to_path_buf();
        }
        cur = c.parent();
    }
    PathBuf::from(".")
}

/// Whether a file can be created in the folder `dir` (created and removed at once).
fn probe(dir: &Path) -> Result<(), String> {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let f = dir.join(format!(
        ".geodesic-write-probe-{}-{nanos}",
        std::process::id()
    ));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&f)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&f);
            Ok(())
        }
        Err(e) => Err(format!("folder {} cannot be written: {e}", dir.display())),
    }
}

/// `flag DIR` names a folder a command writes into (created if missing): it must be a folder,
/// or not exist below a writable folder.
pub fn out_dir(flag: &str, dir: &Path) -> Result<(), CliError> {
    let bad =
        |why: String| CliError::io(format!("{flag} {}: {why}", dir.display())).in_file(dir, 0);
    if dir.as_os_str().is_empty() {
        return Err(bad("empty path; give a folder".into()));
    }
    let base = existing_ancestor(dir);
    if !base.is_dir() {
        return Err(if base == dir {
            bad("is a file, not a folder; give a folder".into())
        } else {
            bad(format!(
                "{} is a file, not a folder; give a folder",
                base.display()
            ))
        });
    }
    probe(&base).map_err(bad)
}

/// `flag FILE` names one output file: not a folder, in a writable folder that exists.
pub fn out_file(flag: &str, file: &Path) -> Result<(), CliError> {
    geodesic_util::output::check_target(file)
        .map_err(|e| CliError::io(format!("{flag} {e}")).in_file(file, 0))?;
    let dir = file
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    probe(dir)
        .map_err(|why| CliError::io(format!("{flag} {}: {why}", file.display())).in_file(file, 0))
}

/// `flag FILE` names one output file whose folder is created if missing: not a folder, below
/// a writable folder.
pub fn out_file_in_new_dir(flag: &str, file: &Path) -> Result<(), CliError> {
    if file.is_dir() {
        return Err(CliError::usage(format!(
            "{flag} {}: is a folder; give a file name for this output",
            file.display()
        )));
    }
    let dir = file
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    out_dir(flag, dir)
}

/// `flag FILE` names an input file: it must exist, be a file and be readable.
pub fn in_file(flag: &str, file: &Path) -> Result<(), CliError> {
    let bad = |why: String| {
        CliError::unreadable(format!("{flag} {}: {why}", file.display())).in_file(file, 0)
    };
    let meta = std::fs::metadata(file).map_err(|e| bad(e.to_string()))?;
    if meta.is_dir() {
        return Err(bad("is a folder; give a file".into()));
    }
    std::fs::File::open(file).map_err(|e| bad(e.to_string()))?;
    Ok(())
}

/// Where a command of the image analyses writes: `DIR/images/`, refusing a file as DIR.
pub fn images_dir(reports: &Path) -> Result<PathBuf, CliError> {
    if reports.exists() && !reports.is_dir() {
        return Err(CliError::usage(format!(
            "--reports {}: is not a directory",
            reports.display()
        )));
    }
    Ok(reports.join("images"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A temporary folder of the test's own, removed when it is dropped.
    fn scratch() -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix("geodesic-preflight-")
            .tempdir()
            .unwrap()
    }

    #[test]
    fn a_missing_folder_below_a_writable_one_passes_and_nothing_is_created() {
        let t = scratch();
        let d = t.path();
        let out = d.join("a/b/reports");
        out_dir("--reports", &out).unwrap();
        assert!(!d.join("a").exists());
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 0, "probe removed");
    }

    #[test]
    fn a_file_where_a_folder_is_expected_is_named() {
        let t = scratch();
        let d = t.path();
        let f = d.join("reports");
        std::fs::write(&f, "x").unwrap();
        let e = out_dir("--reports", &f).unwrap_err().to_string();
        assert!(e.contains("--reports") && e.contains("is a file"), "{e}");
        let e = out_dir("--reports", &f.join("sub"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("is a file"), "{e}");
    }

    #[test]
    fn an_input_that_is_missing_or_a_folder_is_named() {
        let t = scratch();
        let d = t.path();
        let e = in_file("--baseline", &d.join("nope.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--baseline") && e.contains("nope.json"), "{e}");
        let e = in_file("--baseline", d).unwrap_err().to_string();
        assert!(e.contains("is a folder"), "{e}");
        let e = out_file("--out", d).unwrap_err().to_string();
        assert!(e.contains("--out"), "{e}");
    }
}
