//! Writing backend outputs: confined to the output directory and atomic per file.

use mapc_backends::OutputFile;
use std::io::Write;
use std::path::{Component, Path, PathBuf};

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

/// Writes `contents` to `path` via a temporary file in the same directory and a rename,
/// so a reader never sees a half-written file and a failure leaves the old file intact.
pub fn write_atomic(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    let tmp = dir.join(format!(".{name}.mapc-tmp-{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes every file under `root`, skipping files whose content is already identical.
pub fn write_all(root: &Path, files: &[OutputFile]) -> Result<(), String> {
    // Resolve every path first so nothing is written if any name is unsafe.
    let targets: Vec<PathBuf> = files
        .iter()
        .map(|f| confined(root, &f.path))
        .collect::<Result<_, _>>()?;
    // Temporaries a killed run (kill -9, power loss) left where this run writes.
    let mut swept = std::collections::BTreeSet::new();
    for path in &targets {
        if let Some(dir) = path.parent() {
            if swept.insert(dir) {
                sweep_stale_temporaries(dir);
            }
        }
    }
    for (f, path) in files.iter().zip(&targets) {
        if std::fs::read(path).is_ok_and(|old| old == f.contents) {
            continue;
        }
        write_atomic(path, &f.contents).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// Removes `.<name>.mapc-tmp-<pid>` files in `dir` (the temporaries of `write_atomic`)
/// whose process is gone, so that a run after a killed one leaves the tree a clean run
/// leaves. A temporary of a live process (this one, or another mapc writing here now) is
/// kept, and so is every one where liveness cannot be told (no /proc). Best effort: a file
/// that cannot be removed is left.
pub fn sweep_stale_temporaries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let me = std::process::id();
    let proc_fs = Path::new("/proc/self").exists();
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some(pid) = name
            .strip_prefix('.')
            .and_then(|n| n.rsplit_once(".mapc-tmp-"))
            .and_then(|(_, pid)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let stale = pid != me && proc_fs && !Path::new("/proc").join(pid.to_string()).exists();
        if stale && e.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
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
    fn sweeps_stale_temporaries_only() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // A pid that is not running (above Linux's pid_max).
        let dead = d.join(".floor_7.obj.mapc-tmp-4294967");
        let live = d.join(format!(".a.yaml.mapc-tmp-{}", std::process::id()));
        let parent_pid = std::fs::read_to_string("/proc/self/stat")
            .ok()
            .and_then(|s| s.split_whitespace().nth(3).map(str::to_string));
        let other = parent_pid.map(|p| d.join(format!(".b.yaml.mapc-tmp-{p}")));
        let keep = d.join("floor_7.obj");
        for f in [&dead, &live, &keep].into_iter().chain(other.as_ref()) {
            std::fs::write(f, "x").unwrap();
        }
        sweep_stale_temporaries(d);
        assert!(!dead.exists() && live.exists() && keep.exists());
        if let Some(o) = other {
            assert!(o.exists(), "a live process's temporary was removed");
        }
    }
}
