//! Writing outputs: confined to the output directory, atomic per file, and accountable.
//!
//! Each command that writes a directory keeps a manifest there (`.mapc-manifest...`, one
//! `<group>\t<path>` line per file it wrote), so the next run removes what the previous one
//! wrote and this one did not (a graph index that no longer exists, a renamed level). Only
//! files named in a manifest are ever removed, and only in the groups this run owns.
//!
//! Temporary files (`.<name>.mapc-tmp-<pid>`) are registered while they exist, so the signal
//! watcher can remove them; ones left by a killed process are swept before the next write
//! into their directory.

use mapc_backends::OutputFile;
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

/// Temporaries that exist right now (created and not yet renamed or removed).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
const TMP_MARK: &str = ".mapc-tmp-";

/// Resolves `rel` inside `root`, refusing anything that could escape it (absolute paths,
/// `..`, drive prefixes, empty paths).
pub fn confined(root: &Path, rel: &Path) -> Result<PathBuf, String> {
    let mut out = root.to_path_buf();
    let mut any = false;
    for c in rel.components() {
        match c {
            Component::Normal(p) => {
                out.push(p);
                any = true;
            }
            Component::CurDir => {}
            _ => {
                return Err(format!(
                    "refusing to write `{}`: it leaves the output directory",
                    rel.display()
                ))
            }
        }
    }
    if !any {
        return Err("refusing to write an empty path".into());
    }
    Ok(out)
}

/// A path as users wrote it, without `./` noise (`./../x` prints as `../x`).
pub fn shown(p: &Path) -> String {
    let mut out = PathBuf::new();
    for c in p.components() {
        if c != Component::CurDir {
            out.push(c);
        }
    }
    if out.as_os_str().is_empty() {
        ".".into()
    } else {
        out.display().to_string()
    }
}

/// An I/O error on `path` said in terms of what is wrong, for the argument `role` (e.g.
/// `OUTPUT_DIR`) whose value is `root`: a file where a directory must be, a directory where
/// a file must be, no permission.
pub fn io_message(root: &Path, role: &str, path: &Path, e: &std::io::Error) -> String {
    use std::io::ErrorKind;
    // The first existing ancestor that is not a directory is the usual culprit.
    let mut prefix = PathBuf::new();
    for c in path.parent().unwrap_or(Path::new("")).components() {
        prefix.push(c);
        if prefix.exists() && !prefix.is_dir() {
            let r = if prefix == root {
                format!("; {role} must be a directory")
            } else {
                String::new()
            };
            return format!("`{}` is a file{r}", shown(&prefix));
        }
    }
    if path.is_dir() {
        return format!("`{}` is a directory; mapc writes a file there", shown(path));
    }
    match e.kind() {
        ErrorKind::PermissionDenied => {
            let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
            format!(
                "cannot write `{}`: permission denied (is `{}` writable?)",
                shown(path),
                shown(dir.unwrap_or(Path::new(".")))
            )
        }
        _ => format!("cannot write `{}`: {e}", shown(path)),
    }
}

/// Removes every registered temporary and exits with `code` (called by the signal watcher).
/// Exits while holding the registry lock, so no new temporary can appear after the sweep.
pub fn remove_temporaries_and_exit(code: i32) -> ! {
    let live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    for p in live.iter() {
        let _ = std::fs::remove_file(p);
    }
    let _ = std::io::stderr().flush();
    eprintln!("\ninterrupted; temporary files removed");
    std::process::exit(code)
}

/// Creates a registered temporary for `path`; `None` once a signal asked to stop.
pub fn create_temporary(path: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(".{name}{TMP_MARK}{}", std::process::id()));
    let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    // Created under the lock: the watcher either sees it registered or it never exists.
    let f = std::fs::File::create(&tmp)?;
    live.push(tmp.clone());
    Ok((tmp, f))
}

/// Forgets a temporary that was renamed or removed.
pub fn release_temporary(tmp: &Path) {
    let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    live.retain(|p| p != tmp);
}

/// Writes `contents` to `path` via a temporary file in the same directory and a rename,
/// so a reader never sees a half-written file and a failure leaves the old file intact.
pub fn write_atomic(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let (tmp, mut f) = create_temporary(path)?;
    let result = (|| {
        f.write_all(contents)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    release_temporary(&tmp);
    result
}

/// Whether process `pid` still runs (Linux: /proc; elsewhere assume it does not).
fn alive(pid: u32) -> bool {
    pid == std::process::id() || Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes temporaries of processes that no longer run from `dir` (not recursive).
pub fn sweep_temporaries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some((_, pid)) = name.rsplit_once(TMP_MARK) else {
            continue;
        };
        if !name.starts_with('.') || !e.file_type().is_ok_and(|t| t.is_file()) {
            continue;
        }
        if pid.parse::<u32>().is_ok_and(|p| !alive(p)) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// What a write did: how many files the outputs are, and how many were already identical.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Written {
    pub files: usize,
    pub unchanged: usize,
    /// Files of a previous run removed because this run did not write them.
    pub removed: usize,
}

/// Writes every file under `root`, skipping files whose content is already identical.
/// `root` is created even when there is nothing to write (CMake installs the directory).
/// `role` names the argument in messages (`OUTPUT_DIR`).
pub fn write_all(root: &Path, role: &str, files: &[OutputFile]) -> Result<Written, String> {
    // Resolve every path first so nothing is written if any name is unsafe.
    let targets: Vec<PathBuf> = files
        .iter()
        .map(|f| confined(root, &f.path))
        .collect::<Result<_, _>>()?;
    if root.exists() && !root.is_dir() {
        return Err(format!(
            "`{}` is a file; {role} must be a directory",
            shown(root)
        ));
    }
    std::fs::create_dir_all(root).map_err(|e| io_message(root, role, &root.join("x"), &e))?;
    let dirs: BTreeSet<&Path> = targets
        .iter()
        .filter_map(|t| t.parent())
        .chain([root])
        .collect();
    for d in dirs {
        sweep_temporaries(d);
    }
    let mut w = Written {
        files: files.len(),
        ..Written::default()
    };
    for (f, path) in files.iter().zip(&targets) {
        if std::fs::read(path).is_ok_and(|old| old == f.contents) {
            w.unchanged += 1;
            continue;
        }
        write_atomic(path, &f.contents).map_err(|e| io_message(root, role, path, &e))?;
    }
    Ok(w)
}

/// A manifest: which files a command wrote into a directory, by group.
pub struct Manifest<'a> {
    /// File name inside the output directory, e.g. `.mapc-manifest-nav-office`.
    pub name: String,
    /// The group of each file this run writes (a `mapc build` target; one group for the
    /// single-map commands).
    pub group: &'a dyn Fn(&Path) -> String,
    /// Groups this run owns: earlier files of these groups that it did not write are
    /// removed; entries of other groups are kept as they were.
    pub owned: BTreeSet<String>,
}

/// [`write_all`], then removes what the previous run recorded in the manifest (for the
/// groups this run owns) and did not write this time, and records this run.
pub fn write_dir(
    root: &Path,
    role: &str,
    files: &[OutputFile],
    manifest: &Manifest,
) -> Result<Written, String> {
    let mut w = write_all(root, role, files)?;
    let mpath = confined(root, Path::new(&manifest.name))?;
    let old = std::fs::read_to_string(&mpath).unwrap_or_default();
    let now: BTreeSet<PathBuf> = files.iter().map(|f| f.path.clone()).collect();
    let mut kept = Vec::new();
    for line in old.lines() {
        let Some((group, rel)) = line.split_once('\t') else {
            continue;
        };
        let rel = PathBuf::from(rel);
        if !manifest.owned.contains(group) {
            kept.push(line.to_string());
            continue;
        }
        if now.contains(&rel) {
            continue;
        }
        let Ok(path) = confined(root, &rel) else {
            continue;
        };
        if path.is_file() && std::fs::remove_file(&path).is_ok() {
            w.removed += 1;
            // Directories the removal emptied go too (a level model of a renamed level).
            let mut dir = path.parent();
            while let Some(d) = dir.filter(|d| *d != root && d.starts_with(root)) {
                if std::fs::remove_dir(d).is_err() {
                    break;
                }
                dir = d.parent();
            }
        }
    }
    let mut text = String::new();
    for l in kept {
        text.push_str(&l);
        text.push('\n');
    }
    for f in files {
        text.push_str(&format!(
            "{}\t{}\n",
            (manifest.group)(&f.path),
            f.path.display()
        ));
    }
    if std::fs::read_to_string(&mpath).ok().as_deref() != Some(text.as_str()) {
        write_atomic(&mpath, text.as_bytes()).map_err(|e| io_message(root, role, &mpath, &e))?;
    }
    Ok(w)
}

/// The manifest of a single-map command: one group, owned.
pub fn single_write(
    root: &Path,
    role: &str,
    files: &[OutputFile],
    command: &str,
    map: &str,
) -> Result<Written, String> {
    let group = |_: &Path| command.to_string();
    let manifest = Manifest {
        name: format!(".mapc-manifest-{command}-{map}"),
        group: &group,
        owned: [command.to_string()].into(),
    };
    write_dir(root, role, files, &manifest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_escapes() {
        let root = Path::new("/out");
        assert!(confined(root, Path::new("../x")).is_err());
        assert!(confined(root, Path::new("/etc/x")).is_err());
        assert!(confined(root, Path::new("a/../../x")).is_err());
        assert!(confined(root, Path::new("")).is_err());
        assert_eq!(
            confined(root, Path::new("./a/b.yaml")).unwrap(),
            Path::new("/out/a/b.yaml")
        );
    }

    #[test]
    fn shown_drops_cur_dir() {
        assert_eq!(shown(Path::new("./../x/./y")), "../x/y");
        assert_eq!(shown(Path::new("./")), ".");
    }
}
