//! Writing a report set whole or not at all: the new set is written beside the old one and the
//! two are switched in one atomic step.
//!
//! Layout of a reports directory `DIR`:
//!
//! ```text
//! DIR/.geodesic/sets/<pid>-<n>/...      one complete report set per folder
//! DIR/.geodesic/current -> sets/<id>    symbolic link: the set in force
//! DIR/compliance.json -> .geodesic/current/compliance.json   (one stable link per file)
//! DIR/fits/x.svg -> ../.geodesic/current/fits/x.svg
//! ```
//!
//! A run writes its files into a fresh `sets/<id>` folder ([`Staging::write`]), then
//! [`Staging::commit`]: (1) makes the per-file links (a link to a file the old set lacks dangles,
//! so that file reads as absent until the switch), (2) replaces `current` by a new link with one
//! `rename(2)`, the only step that changes what a reader sees, (3) removes the old set and the
//! links the new set no longer has. A reader of `DIR/*` therefore sees the old set or the new
//! one, never a mixture, whenever the run is killed. A run that fails or is interrupted by
//! SIGINT/SIGTERM/SIGHUP removes its own folder; the folder of a killed (SIGKILL) run is removed
//! by the next run in the same directory. Files in `DIR` that are not links into
//! `.geodesic/current` (the outputs of `fit`, a README) are never touched.
//!
//! Unix only (symbolic links); geodesic targets Linux.

use std::path::{Path, PathBuf};

pub use geodesic_util::output::WriteError;
use geodesic_util::output::{critical, register, unregister};

/// Hidden folder holding the sets inside a reports directory.
pub const SETS_ROOT: &str = ".geodesic";

fn werr(p: &Path, e: impl ToString) -> WriteError {
    WriteError {
        path: p.display().to_string(),
        cause: e.to_string(),
    }
}

/// A report set being written; see the module documentation.
pub struct Staging {
    dir: PathBuf,
    root: PathBuf,
    stage: PathBuf,
    committed: bool,
}

/// Whether process `pid` is alive (Linux: /proc). Unknown: assume alive.
fn alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    let proc_dir = Path::new("/proc");
    if !proc_dir.is_dir() {
        return true;
    }
    proc_dir.join(pid.to_string()).exists()
}

/// The set folder name the `current` link points to, if any.
fn current_set(root: &Path) -> Option<String> {
    let t = std::fs::read_link(root.join("current")).ok()?;
    t.file_name().map(|n| n.to_string_lossy().into_owned())
}

impl Staging {
    /// Creates `dir` if needed and a fresh set folder in `dir/.geodesic/sets/`; removes the
    /// folders that killed runs left there.
    pub fn new(dir: &Path) -> Result<Staging, WriteError> {
        if dir.exists() && !dir.is_dir() {
            return Err(werr(
                dir,
                "is not a directory; give a folder for the reports",
            ));
        }
        std::fs::create_dir_all(dir).map_err(|e| werr(dir, e))?;
        let root = dir.join(SETS_ROOT);
        let sets = root.join("sets");
        std::fs::create_dir_all(&sets).map_err(|e| werr(&sets, e))?;
        collect_garbage(&root);
        static SEQ: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = SEQ.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.subsec_nanos())
            .unwrap_or(0);
        let stage = sets.join(format!("{}-{n}-{nanos:09}", std::process::id()));
        register(&stage);
        std::fs::create_dir_all(&stage).map_err(|e| {
            unregister(&stage);
            werr(&stage, e)
        })?;
        Ok(Staging {
            dir: dir.to_path_buf(),
            root,
            stage,
            committed: false,
        })
    }

    /// The folder of the new set (give it to checks as their reports directory).
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// Writes one file of the set (`name` may contain `/` for a subfolder).
    pub fn write(&self, name: &str, contents: &[u8]) -> Result<(), WriteError> {
        let p = self.stage.join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| werr(parent, e))?;
        }
        std::fs::write(&p, contents).map_err(|e| werr(&p, e))
    }

    /// Makes the new set the one in force (see the module documentation); returns the paths a
    /// reader uses (`DIR/<name>`), sorted.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, WriteError> {
        let mut files = Vec::new();
        collect(&self.stage, &mut files);
        let mut rels: Vec<PathBuf> = files
            .iter()
            .filter_map(|f| f.strip_prefix(&self.stage).ok().map(Path::to_path_buf))
            .collect();
        rels.sort();
        let set_name = self
            .stage
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let result = critical(|registered| -> Result<(), WriteError> {
            // (1) one stable link per file, through `current`
            for rel in &rels {
                link_file(&self.dir, rel)?;
            }
            // (2) the switch: a new link renamed over `current`
            let old = current_set(&self.root);
            let tmp_link = self.root.join(format!("current.{set_name}"));
            let _ = std::fs::remove_file(&tmp_link);
            symlink(Path::new(&format!("sets/{set_name}")), &tmp_link)?;
            let current = self.root.join("current");
            if let Err(e) = std::fs::rename(&tmp_link, &current) {
                let _ = std::fs::remove_file(&tmp_link);
                return Err(werr(&current, e));
            }
            registered.retain(|p| p != &self.stage);
            self.committed = true;
            // (3) tidy: the old set and the links the new set does not have
            if let Some(old) = old
                && old != set_name
            {
                let _ = std::fs::remove_dir_all(self.root.join("sets").join(old));
            }
            remove_dangling(&self.dir, &self.dir);
            Ok(())
        });
        result?;
        Ok(rels.iter().map(|r| self.dir.join(r)).collect())
    }
}

#[cfg(unix)]
fn symlink(target: &Path, link: &Path) -> Result<(), WriteError> {
    std::os::unix::fs::symlink(target, link).map_err(|e| werr(link, e))
}

#[cfg(not(unix))]
fn symlink(_target: &Path, link: &Path) -> Result<(), WriteError> {
    Err(werr(link, "report sets need symbolic links (Unix)"))
}

/// The link target for `DIR/rel`: `../` per folder level, then `.geodesic/current/rel`.
fn link_target(rel: &Path) -> PathBuf {
    let depth = rel.components().count().saturating_sub(1);
    let mut t = PathBuf::new();
    for _ in 0..depth {
        t.push("..");
    }
    t.push(SETS_ROOT);
    t.push("current");
    t.push(rel);
    t
}

/// Makes `dir/rel` a link into the current set unless it already is one.
fn link_file(dir: &Path, rel: &Path) -> Result<(), WriteError> {
    let link = dir.join(rel);
    let want = link_target(rel);
    if std::fs::read_link(&link).ok().as_deref() == Some(want.as_path()) {
        return Ok(());
    }
    if let Some(parent) = link.parent() {
        std::fs::create_dir_all(parent).map_err(|e| werr(parent, e))?;
    }
    if link.is_dir() && !link.is_symlink() {
        return Err(werr(
            &link,
            "is a directory; a report file of this name cannot be written",
        ));
    }
    let name = link
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = link.with_file_name(format!(".{name}.link-geodesic-{}", std::process::id()));
    let _ = std::fs::remove_file(&tmp);
    symlink(&want, &tmp)?;
    std::fs::rename(&tmp, &link).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        werr(&link, e)
    })
}

/// Whether `link` (a symbolic link found under `dir`) points into `.geodesic/current`.
fn points_into_sets(target: &Path) -> bool {
    let mut comps = target
        .components()
        .skip_while(|c| matches!(c, std::path::Component::ParentDir));
    comps.next().map(|c| c.as_os_str() == SETS_ROOT) == Some(true)
        && comps.next().map(|c| c.as_os_str() == "current") == Some(true)
}

/// Removes the links into `.geodesic/current` that lead nowhere (files of an older set).
fn remove_dangling(top: &Path, dir: &Path) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.file_name().map(|n| n == SETS_ROOT) == Some(true) && dir == top {
            continue;
        }
        let Ok(ft) = e.file_type() else { continue };
        if ft.is_symlink() {
            if let Ok(t) = std::fs::read_link(&p)
                && points_into_sets(&t)
                && !p.exists()
            {
                let _ = std::fs::remove_file(&p);
            }
        } else if ft.is_dir() {
            remove_dangling(top, &p);
        }
    }
}

/// Removes the set folders and temporary links of runs that are no longer alive.
fn collect_garbage(root: &Path) {
    let current = current_set(root);
    if let Ok(rd) = std::fs::read_dir(root.join("sets")) {
        for e in rd.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if Some(&name) == current.as_ref() {
                continue;
            }
            let pid = name.split('-').next().and_then(|p| p.parse::<u32>().ok());
            if pid.is_none_or(|p| !alive(p)) {
                let _ = std::fs::remove_dir_all(e.path());
            }
        }
    }
    if let Ok(rd) = std::fs::read_dir(root) {
        for e in rd.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if let Some(set) = name.strip_prefix("current.") {
                let pid = set.split('-').next().and_then(|p| p.parse::<u32>().ok());
                if pid.is_none_or(|p| !alive(p)) {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
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
            unregister(&self.stage);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sets(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir.join(SETS_ROOT).join("sets"))
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect()
    }

    #[test]
    fn uncommitted_staging_leaves_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("reports");
        {
            let s = Staging::new(&dir).unwrap();
            s.write("a.md", b"x").unwrap();
        }
        assert!(!dir.join("a.md").exists());
        assert!(sets(&dir).is_empty());
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"x").unwrap();
        s.write("sub/b.svg", b"y").unwrap();
        let out = s.commit().unwrap();
        assert_eq!(out, vec![dir.join("a.md"), dir.join("sub/b.svg")]);
        assert_eq!(std::fs::read(dir.join("sub/b.svg")).unwrap(), b"y");
        assert_eq!(sets(&dir).len(), 1);
    }

    #[test]
    fn a_new_set_replaces_the_old_one_whole() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("reports");
        std::fs::create_dir_all(dir.join("fits")).unwrap();
        std::fs::write(dir.join("README.md"), b"mine").unwrap();
        std::fs::write(dir.join("fits/user.svg"), b"fit output").unwrap();
        std::fs::write(dir.join("a.md"), b"pre-set regular file").unwrap();
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"1").unwrap();
        s.write("old-only.md", b"1").unwrap();
        s.write("fits/verify.svg", b"1").unwrap();
        s.commit().unwrap();
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"2").unwrap();
        s.write("fits/verify.svg", b"2").unwrap();
        s.commit().unwrap();
        assert_eq!(std::fs::read(dir.join("a.md")).unwrap(), b"2");
        assert_eq!(std::fs::read(dir.join("fits/verify.svg")).unwrap(), b"2");
        assert!(!dir.join("old-only.md").exists() && !dir.join("old-only.md").is_symlink());
        assert_eq!(std::fs::read(dir.join("README.md")).unwrap(), b"mine");
        assert_eq!(
            std::fs::read(dir.join("fits/user.svg")).unwrap(),
            b"fit output"
        );
        assert_eq!(sets(&dir).len(), 1, "the old set is removed");
    }

    #[test]
    fn a_set_left_by_a_dead_run_is_removed_and_a_live_one_kept() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("reports");
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"1").unwrap();
        s.commit().unwrap();
        // a killed run's folder: a PID that cannot be alive (above the kernel's pid_max)
        let dead = dir
            .join(SETS_ROOT)
            .join("sets")
            .join("4294967294-0-000000000");
        std::fs::create_dir_all(&dead).unwrap();
        std::fs::write(dead.join("a.md"), b"half").unwrap();
        let s = Staging::new(&dir).unwrap();
        assert!(!dead.exists());
        assert_eq!(sets(&dir).len(), 2, "the current set and this run's");
        drop(s);
        assert_eq!(std::fs::read(dir.join("a.md")).unwrap(), b"1");
    }

    #[test]
    fn a_run_killed_after_linking_and_before_the_switch_shows_the_old_set() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("reports");
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"old").unwrap();
        s.commit().unwrap();
        // step (1) of a second commit, then the process "dies" (no switch, no drop)
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"new").unwrap();
        s.write("b.md", b"new").unwrap();
        for rel in ["a.md", "b.md"] {
            link_file(&dir, Path::new(rel)).unwrap();
        }
        std::mem::forget(s);
        assert_eq!(std::fs::read(dir.join("a.md")).unwrap(), b"old");
        assert!(
            !dir.join("b.md").exists(),
            "a file of the new set only is absent"
        );
        // the next run in this process (the same PID: alive) commits and tidies
        let s = Staging::new(&dir).unwrap();
        s.write("a.md", b"third").unwrap();
        s.commit().unwrap();
        assert_eq!(std::fs::read(dir.join("a.md")).unwrap(), b"third");
        assert!(
            !dir.join("b.md").is_symlink(),
            "the dangling link is removed"
        );
    }

    #[test]
    fn links_are_relative_to_their_folder() {
        assert_eq!(
            link_target(Path::new("a.md")),
            Path::new(".geodesic/current/a.md")
        );
        assert_eq!(
            link_target(Path::new("fits/x/b.svg")),
            Path::new("../../.geodesic/current/fits/x/b.svg")
        );
        assert!(points_into_sets(Path::new("../.geodesic/current/x")));
        assert!(!points_into_sets(Path::new("../elsewhere/x")));
    }
}
