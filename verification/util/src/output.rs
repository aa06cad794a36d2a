//! Writing outputs whole or not at all, and leaving nothing behind.
//!
//! Every temporary path a run creates (a staged report set, the temporary file of an atomic
//! write) is registered here while it exists. The command-line binary's signal thread calls
//! [`remove_registered`] on SIGINT, SIGTERM or SIGHUP before it exits, so an interrupted run
//! leaves no `.tmp` file or staging folder behind. A commit (the switch from an old report set to
//! a new one) runs inside [`critical`], which a signal waits for: a set is never half switched
//! by a signal. A SIGKILL cannot be caught: what it leaves is removed by the next run (see
//! `geodesic_report::write`).

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

static REGISTERED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn registry() -> MutexGuard<'static, Vec<PathBuf>> {
    REGISTERED.lock().unwrap_or_else(|e| e.into_inner())
}

/// Registers a temporary file or directory to remove if the run is interrupted.
pub fn register(path: &Path) {
    registry().push(path.to_path_buf());
}

/// Forgets a registered path (it was renamed into place or removed).
pub fn unregister(path: &Path) {
    registry().retain(|p| p != path);
}

/// Runs `f` while holding the registry: a signal arriving meanwhile is handled after `f`.
/// `f` receives the registered paths (to forget the ones it commits: calling [`register`] or
/// [`unregister`] inside `f` would deadlock).
pub fn critical<R>(f: impl FnOnce(&mut Vec<PathBuf>) -> R) -> R {
    let mut g = registry();
    f(&mut g)
}

/// Removes every registered path (files and directories); called on an interrupting signal.
/// Waits for a running [`critical`] section to finish first.
pub fn remove_registered() {
    let mut reg = registry();
    for p in reg.drain(..) {
        if p.is_dir() {
            let _ = std::fs::remove_dir_all(&p);
        } else {
            let _ = std::fs::remove_file(&p);
        }
    }
    // keep the registry locked: the process is about to exit and nothing may stage again
    std::mem::forget(reg);
}

/// Why an output was not written: the path and the cause, one line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {cause}")]
pub struct WriteError {
    /// File or directory concerned.
    pub path: String,
    /// Cause.
    pub cause: String,
}

impl WriteError {
    fn new(path: &Path, cause: impl ToString) -> WriteError {
        WriteError {
            path: path.display().to_string(),
            cause: cause.to_string(),
        }
    }
}

/// Checks that `path` can be an output file: not a directory, and its folder exists.
/// Call it before a long run so that a bad output path fails in a second, not after the work.
pub fn check_target(path: &Path) -> Result<(), WriteError> {
    if path.as_os_str().is_empty() {
        return Err(WriteError::new(path, "empty output path"));
    }
    if path.is_dir() {
        return Err(WriteError::new(
            path,
            "is a directory; give a file name for this output",
        ));
    }
    let dir = parent_of(path);
    if !dir.is_dir() {
        return Err(WriteError::new(
            path,
            format!("folder {} does not exist", dir.display()),
        ));
    }
    Ok(())
}

fn parent_of(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// A file written beside its target under a temporary name, renamed into place by
/// [`PendingFile::commit`]; removed if dropped uncommitted or if the run is interrupted.
pub struct PendingFile {
    tmp: PathBuf,
    target: PathBuf,
    done: bool,
}

impl PendingFile {
    /// Writes `bytes` to a temporary file beside `target` (`.NAME.tmp-geodesic-PID`).
    /// Fails, leaving nothing, if `target` is a directory or its folder does not exist.
    pub fn prepare(target: &Path, bytes: &[u8]) -> Result<PendingFile, WriteError> {
        check_target(target)?;
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = parent_of(target).join(format!(".{name}.tmp-geodesic-{}", std::process::id()));
        register(&tmp);
        let p = PendingFile {
            tmp,
            target: target.to_path_buf(),
            done: false,
        };
        std::fs::write(&p.tmp, bytes).map_err(|e| WriteError::new(target, e))?;
        Ok(p)
    }

    /// Renames the file into place.
    pub fn commit(mut self) -> Result<PathBuf, WriteError> {
        let r = critical(|reg| {
            let r = std::fs::rename(&self.tmp, &self.target);
            if r.is_ok() {
                reg.retain(|p| p != &self.tmp);
            }
            r
        });
        r.map_err(|e| WriteError::new(&self.target, e))?;
        self.done = true;
        Ok(self.target.clone())
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        if !self.done {
            let _ = std::fs::remove_file(&self.tmp);
            unregister(&self.tmp);
        }
    }
}

/// Writes `bytes` to `path` whole or not at all (a temporary file beside it, then a rename).
/// The folder must exist ([`write_whole`] creates it).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<PathBuf, WriteError> {
    PendingFile::prepare(path, bytes)?.commit()
}

/// Writes `bytes` to `path` whole or not at all ([`write_atomic`]), creating its folder first
/// if it is missing (an output whose folder a command creates: `--out a/b/FILE`).
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<PathBuf, WriteError> {
    let dir = parent_of(path);
    std::fs::create_dir_all(dir)
        .map_err(|e| WriteError::new(dir, format!("cannot create directory: {e}")))?;
    write_atomic(path, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains("tmp-geodesic"))
            .collect()
    }

    #[test]
    fn atomic_write_replaces_whole_and_leaves_nothing() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("out.json");
        std::fs::write(&p, b"old").unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        assert!(leftovers(d.path()).is_empty());
    }

    #[test]
    fn write_whole_creates_the_folder_and_refuses_a_file_in_its_way() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("a/b/out.reqif");
        write_whole(&p, b"new").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        assert!(leftovers(&d.path().join("a/b")).is_empty());
        // a file where the folder should be: one line naming it, nothing written
        std::fs::write(d.path().join("f"), b"x").unwrap();
        let e = write_whole(&d.path().join("f/out.reqif"), b"x").unwrap_err();
        assert!(e.path.ends_with("f"), "{e}");
        assert!(e.cause.starts_with("cannot create directory: "), "{e}");
    }

    #[test]
    fn bad_targets_fail_before_writing_anything() {
        let d = tempfile::tempdir().unwrap();
        let e = write_atomic(d.path(), b"x").unwrap_err();
        assert!(e.cause.contains("is a directory"), "{e}");
        let e = write_atomic(&d.path().join("missing/out.xml"), b"x").unwrap_err();
        assert!(e.cause.contains("does not exist"), "{e}");
        assert!(leftovers(d.path()).is_empty());
    }

    #[test]
    fn a_dropped_pending_file_is_removed_and_the_old_file_kept() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("junit.xml");
        std::fs::write(&p, b"old").unwrap();
        {
            let _pending = PendingFile::prepare(&p, b"new").unwrap();
            assert_eq!(leftovers(d.path()).len(), 1);
        }
        let committed = PendingFile::prepare(&d.path().join("b.xml"), b"b").unwrap();
        committed.commit().unwrap();
        assert!(
            !registry().iter().any(|r| r.starts_with(d.path())),
            "committed and dropped files are forgotten"
        );
        assert!(leftovers(d.path()).is_empty());
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
    }
}
