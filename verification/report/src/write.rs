//! Writing report files whole or not at all: every file is first written into a staging
//! directory beside the target, then all are renamed into place. A failure before the renames
//! leaves the previous reports untouched.

use std::path::{Path, PathBuf};

/// A failure writing reports: the path and the cause.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {cause}")]
pub struct WriteError {
    /// File or directory.
    pub path: String,
    /// Cause.
    pub cause: String,
}

/// A staging directory inside `dir`; files written here are moved into `dir` by
/// [`Staging::commit`], or removed when the staging is dropped uncommitted.
pub struct Staging {
    dir: PathBuf,
    stage: PathBuf,
    committed: bool,
}

impl Staging {
    /// Creates `dir` if needed and a fresh staging directory inside it.
    pub fn new(dir: &Path) -> Result<Staging, WriteError> {
        let err = |p: &Path, e: std::io::Error| WriteError {
            path: p.display().to_string(),
            cause: e.to_string(),
        };
        std::fs::create_dir_all(dir).map_err(|e| err(dir, e))?;
        let stage = dir.join(format!(".staging-{}", std::process::id()));
        if stage.exists() {
            std::fs::remove_dir_all(&stage).map_err(|e| err(&stage, e))?;
        }
        std::fs::create_dir_all(&stage).map_err(|e| err(&stage, e))?;
        Ok(Staging {
            dir: dir.to_path_buf(),
            stage,
            committed: false,
        })
    }

    /// The staging directory (give it to checks as their reports directory).
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// Writes one file into the staging directory.
    pub fn write(&self, name: &str, contents: &[u8]) -> Result<(), WriteError> {
        let p = self.stage.join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| WriteError {
                path: parent.display().to_string(),
                cause: e.to_string(),
            })?;
        }
        std::fs::write(&p, contents).map_err(|e| WriteError {
            path: p.display().to_string(),
            cause: e.to_string(),
        })
    }

    /// Moves every staged file into the target directory; returns the final paths.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, WriteError> {
        let mut files = Vec::new();
        collect(&self.stage, &mut files);
        files.sort();
        let mut out = Vec::new();
        for f in files {
            let rel = f.strip_prefix(&self.stage).unwrap_or(&f).to_path_buf();
            let target = self.dir.join(&rel);
            if let Some(parent) = target.parent() {
                std::fs::create_dir_all(parent).map_err(|e| WriteError {
                    path: parent.display().to_string(),
                    cause: e.to_string(),
                })?;
            }
            std::fs::rename(&f, &target).map_err(|e| WriteError {
                path: target.display().to_string(),
                cause: e.to_string(),
            })?;
            out.push(target);
        }
        let _ = std::fs::remove_dir_all(&self.stage);
        self.committed = true;
        Ok(out)
    }
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                collect(&p, out);
            } else {
                out.push(p);
            }
        }
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.stage);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uncommitted_staging_leaves_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("reports");
        {
            let s = Staging::new(&dir).unwrap();
            s.write("a.md", b"x").unwrap();
        }
        assert!(!dir.join("a.md").exists());
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"x").unwrap();
        s.write("sub/b.svg", b"y").unwrap();
        let out = s.commit().unwrap();
        assert_eq!(out.len(), 2);
        assert_eq!(std::fs::read(dir.join("sub/b.svg")).unwrap(), b"y");
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().starts_with(".staging"))
            .collect();
        assert!(left.is_empty());
    }
}
