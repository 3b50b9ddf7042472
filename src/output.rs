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
    for (f, path) in files.iter().zip(&targets) {
        if std::fs::read(path).is_ok_and(|old| old == f.contents) {
            continue;
        }
        write_atomic(path, &f.contents).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
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
}
