//! A first build into directories that do not exist yet: each topmost missing directory
//! is staged whole as a hidden sibling (`.<name>.<n>.mapc-tmp-<pid>`; `n` tells apart
//! writes that run at once in one process, as `mapc build`'s workers do, whose outputs
//! may share a new top), its files written there
//! under their own names (no temporary per file), made durable with the other outputs,
//! and renamed into place at once: a reader sees the whole tree or nothing of it, and no
//! file needs a rename of its own. The staging directory is a registered temporary: the signal watcher
//! removes it, and one left by a killed process is swept by the next first build there.

use super::{alive, GATE, LIVE, TMP_MARK};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Numbers the staging directories of this process.
static STAGINGS: AtomicUsize = AtomicUsize::new(0);

/// The missing top directories of a write and where each is staged.
#[derive(Default)]
pub(super) struct Fresh {
    /// (top, staging directory beside it).
    tops: Vec<(PathBuf, PathBuf)>,
}

impl Fresh {
    /// The topmost missing ancestor of every root that does not exist. A root written
    /// with `..` (or any other odd component) is left to the per-file path.
    pub(super) fn find<'a>(roots: impl Iterator<Item = &'a Path>) -> Fresh {
        let mut tops: Vec<(PathBuf, PathBuf)> = Vec::new();
        for root in roots {
            let plain = root.components().all(|c| {
                matches!(
                    c,
                    Component::Normal(_) | Component::CurDir | Component::RootDir
                )
            });
            if !plain || std::fs::symlink_metadata(root).is_ok() {
                continue;
            }
            let mut top = root;
            let parent = loop {
                let Some(p) = top.parent() else { break None };
                let p = if p.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    p
                };
                if std::fs::symlink_metadata(p).is_ok() {
                    break Some(p);
                }
                top = p;
            };
            let (Some(parent), Some(name)) = (parent, top.file_name()) else {
                continue;
            };
            if tops.iter().any(|(t, _)| t == top) {
                continue;
            }
            let n = STAGINGS.fetch_add(1, Ordering::Relaxed);
            let mut hidden = std::ffi::OsString::from(".");
            hidden.push(name);
            hidden.push(format!(".{n}{TMP_MARK}{}", std::process::id()));
            tops.push((top.to_path_buf(), parent.join(hidden)));
        }
        Fresh { tops }
    }

    /// Where `path` is written: inside a staging directory when it lies under a new top.
    pub(super) fn staged(&self, path: &Path) -> Option<PathBuf> {
        self.tops
            .iter()
            .find_map(|(top, staging)| path.strip_prefix(top).ok().map(|rel| staging.join(rel)))
    }

    /// Creates the staging directories (registered), after sweeping ones that a process
    /// no longer running left beside the same tops.
    pub(super) fn create(&self) -> std::io::Result<()> {
        for (top, staging) in &self.tops {
            sweep_beside(top);
            let _gate = GATE.read().unwrap_or_else(|e| e.into_inner());
            match std::fs::create_dir(staging) {
                // Left by an earlier process with this pid: nothing of this one is in it.
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    std::fs::remove_dir_all(staging)?;
                    std::fs::create_dir(staging)?;
                }
                r => r?,
            }
            LIVE.lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(staging.clone());
        }
        Ok(())
    }

    /// Renames each staging directory into place. Where its top appeared meanwhile
    /// (another process made it), the files are moved in one by one, each replacing what
    /// is there, and the staging directory is removed.
    pub(super) fn commit(&self) -> std::io::Result<()> {
        for (top, staging) in &self.tops {
            if std::fs::rename(staging, top).is_err() {
                merge(staging, top)?;
                std::fs::remove_dir_all(staging)?;
            }
        }
        Ok(())
    }

    /// Removes the staging directories (a failed write).
    pub(super) fn discard(&self) {
        for (_, staging) in &self.tops {
            let _ = std::fs::remove_dir_all(staging);
        }
    }

    /// Forgets the staging directories (renamed or removed).
    pub(super) fn release(&self) {
        let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
        live.retain(|p| !self.tops.iter().any(|(_, s)| s == p));
    }
}

/// Removes `.<top name>.<n>.mapc-tmp-<pid>` directories of processes that no longer run from
/// beside `top`: a first build killed before its rename. Only those names: the parent is
/// not the output directory, nothing else of it is touched.
fn sweep_beside(top: &Path) {
    let (Some(name), Some(parent)) = (top.file_name().and_then(|n| n.to_str()), top.parent())
    else {
        return;
    };
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    let prefix = format!(".{name}.");
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let n = e.file_name();
        let Some((k, pid)) = n
            .to_str()
            .and_then(|n| n.strip_prefix(&prefix))
            .and_then(|rest| rest.split_once(TMP_MARK))
        else {
            continue;
        };
        if k.is_empty() || !k.bytes().all(|c| c.is_ascii_digit()) {
            continue;
        }
        if pid.parse::<u32>().is_ok_and(|p| !alive(p)) && e.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

/// Moves every file under `from` to the same place under `to`, making directories.
fn merge(from: &Path, to: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(to)?;
    for e in std::fs::read_dir(from)? {
        let e = e?;
        let dest = to.join(e.file_name());
        if e.file_type()?.is_dir() {
            merge(&e.path(), &dest)?;
        } else {
            std::fs::rename(e.path(), dest)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_topmost_missing_directory_is_staged_beside_itself() {
        let t = tempfile::tempdir().unwrap();
        let out = t.path().join("out");
        let models = out.join("models");
        let fresh = Fresh::find([out.as_path(), models.as_path()].into_iter());
        assert_eq!(fresh.tops.len(), 1);
        let staging = fresh.tops[0].1.clone();
        let name = staging.file_name().unwrap().to_str().unwrap();
        let pid = format!("{TMP_MARK}{}", std::process::id());
        assert!(name.starts_with(".out.") && name.ends_with(&pid), "{name}");
        assert_eq!(staging.parent(), Some(t.path()));
        assert_eq!(fresh.tops[0].0, out);
        // Two writes at once get two staging directories.
        assert_ne!(Fresh::find([out.as_path()].into_iter()).tops[0].1, staging);
        assert_eq!(
            fresh.staged(&models.join("m/model.sdf")),
            Some(staging.join("models/m/model.sdf"))
        );
        assert_eq!(fresh.staged(&t.path().join("elsewhere")), None);
        // An existing root, or one written with `..`, is not staged.
        assert!(Fresh::find([t.path()].into_iter()).tops.is_empty());
        let odd = t.path().join("a/../b");
        assert!(Fresh::find([odd.as_path()].into_iter()).tops.is_empty());
    }

    #[test]
    fn commit_renames_or_merges_and_dead_stagings_are_swept() {
        let t = tempfile::tempdir().unwrap();
        let out = t.path().join("out");
        // A staging directory a killed process left (pid 4194304999 cannot run), and an
        // unrelated hidden directory that must stay.
        let dead = t.path().join(format!(".out.7{TMP_MARK}4194304999"));
        std::fs::create_dir_all(dead.join("models")).unwrap();
        std::fs::create_dir(t.path().join(".other.7.mapc-tmp-4194304999")).unwrap();
        std::fs::create_dir(t.path().join(".out.x.mapc-tmp-4194304999")).unwrap();
        let fresh = Fresh::find([out.as_path()].into_iter());
        fresh.create().unwrap();
        assert!(!dead.exists(), "the dead run's staging was not swept");
        assert!(t.path().join(".other.7.mapc-tmp-4194304999").exists());
        assert!(t.path().join(".out.x.mapc-tmp-4194304999").exists());
        let staged = fresh.staged(&out.join("a/f.txt")).unwrap();
        std::fs::create_dir_all(staged.parent().unwrap()).unwrap();
        std::fs::write(&staged, "new").unwrap();
        fresh.commit().unwrap();
        fresh.release();
        assert_eq!(std::fs::read_to_string(out.join("a/f.txt")).unwrap(), "new");
        assert!(!fresh.tops[0].1.exists());

        // The top appeared meanwhile (another process): files are moved in one by one,
        // each replacing what is there; what else is there stays.
        let out2 = t.path().join("out2");
        let fresh = Fresh::find([out2.as_path()].into_iter());
        fresh.create().unwrap();
        let staged = fresh.staged(&out2.join("a/f.txt")).unwrap();
        std::fs::create_dir_all(staged.parent().unwrap()).unwrap();
        std::fs::write(&staged, "new").unwrap();
        std::fs::create_dir_all(out2.join("a")).unwrap();
        std::fs::write(out2.join("a/f.txt"), "old").unwrap();
        std::fs::write(out2.join("keep.txt"), "theirs").unwrap();
        fresh.commit().unwrap();
        fresh.release();
        assert_eq!(
            std::fs::read_to_string(out2.join("a/f.txt")).unwrap(),
            "new"
        );
        assert_eq!(
            std::fs::read_to_string(out2.join("keep.txt")).unwrap(),
            "theirs"
        );
        assert!(!fresh.tops[0].1.exists());
    }
}
