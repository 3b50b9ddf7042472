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
    let tmp = temporary_name(path);
    let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    // Created under the lock: the watcher either sees it registered or it never exists.
    // A new file, never one found there: a temporary left by an earlier process with
    // this pid may be a hard link to a texture, which truncating would empty.
    let _ = std::fs::remove_file(&tmp);
    let f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)?;
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

/// Files read from disk whose bytes an output may repeat verbatim (textures): such an
/// output is hard-linked to the file instead of written (no data to copy or flush).
static LINK_SOURCES: Mutex<Vec<(PathBuf, Vec<u8>)>> = Mutex::new(Vec::new());

/// Records that `path` holds `bytes`, so an output with exactly these bytes and the same
/// file name may be a hard link to it.
pub fn note_link_source(path: &Path, bytes: &[u8]) {
    let mut l = LINK_SOURCES.lock().unwrap_or_else(|e| e.into_inner());
    if !l.iter().any(|(p, _)| p == path) {
        l.push((path.to_path_buf(), bytes.to_vec()));
    }
}

fn link_source(target: &Path, contents: &[u8]) -> Option<PathBuf> {
    let l = LINK_SOURCES.lock().unwrap_or_else(|e| e.into_inner());
    l.iter()
        .find(|(p, b)| p.file_name() == target.file_name() && b.as_slice() == contents)
        .map(|(p, _)| p.clone())
}

/// A new file staged as a temporary beside its target, renamed over it at commit.
struct Staged {
    tmp: PathBuf,
    target: PathBuf,
    /// Written here (its data must be flushed), rather than linked to an existing file.
    written: bool,
}

/// Stages `contents` for `path`: a hard link to a known source with the same bytes when
/// possible (same file system), else a temporary written with those bytes.
fn stage(path: &Path, contents: &[u8]) -> std::io::Result<Staged> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    if let Some(src) = link_source(path, contents) {
        let tmp = temporary_name(path);
        let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
        let _ = std::fs::remove_file(&tmp);
        if std::fs::hard_link(&src, &tmp).is_ok() {
            live.push(tmp.clone());
            return Ok(Staged {
                tmp,
                target: path.to_path_buf(),
                written: false,
            });
        }
        // Another device, or links not allowed: copy.
    }
    let (tmp, mut f) = create_temporary(path)?;
    let result = f.write_all(contents);
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        release_temporary(&tmp);
        return Err(e);
    }
    Ok(Staged {
        tmp,
        target: path.to_path_buf(),
        written: true,
    })
}

/// Makes the data of every staged temporary durable, in one pass: on Linux one `syncfs`
/// per file system (one journal commit, instead of one per file), elsewhere `fsync` of
/// each file.
fn flush(staged: &[Staged]) -> std::io::Result<()> {
    let written: Vec<&Staged> = staged.iter().filter(|s| s.written).collect();
    if written.is_empty() {
        return Ok(());
    }
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        use std::os::unix::fs::MetadataExt;
        let dirs: BTreeSet<&Path> = written.iter().filter_map(|s| s.tmp.parent()).collect();
        let mut devices = BTreeSet::new();
        for d in dirs {
            let f = std::fs::File::open(d)?;
            if devices.insert(f.metadata()?.dev()) {
                // SAFETY: a plain syscall on an open descriptor.
                if unsafe { libc::syncfs(f.as_raw_fd()) } != 0 {
                    return Err(std::io::Error::last_os_error());
                }
            }
        }
        Ok(())
    }
    #[cfg(not(target_os = "linux"))]
    {
        for s in written {
            std::fs::File::open(&s.tmp)?.sync_all()?;
        }
        Ok(())
    }
}

fn discard(staged: &[Staged]) {
    for s in staged {
        let _ = std::fs::remove_file(&s.tmp);
        release_temporary(&s.tmp);
    }
}

fn temporary_name(path: &Path) -> PathBuf {
    let dir = path.parent().unwrap_or(Path::new("."));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("out");
    dir.join(format!(".{name}{TMP_MARK}{}", std::process::id()))
}

/// Writes every file under `root`, skipping files whose content is already identical.
/// `root` is created even when there is nothing to write (CMake installs the directory).
/// `role` names the argument in messages (`OUTPUT_DIR`).
pub fn write_all(root: &Path, role: &str, files: &[OutputFile]) -> Result<Written, String> {
    write_dirs(&[DirWrite {
        root,
        role,
        files,
        manifest: None,
    }])
    .map(|w| w[0])
}

/// One directory's share of a [`write_dirs`] call.
pub struct DirWrite<'a> {
    pub root: &'a Path,
    /// The argument that named `root`, for messages (`OUTPUT_DIR`).
    pub role: &'a str,
    pub files: &'a [OutputFile],
    pub manifest: Option<&'a Manifest<'a>>,
}

/// What one directory of a write will do, computed before anything is written.
struct Plan {
    targets: Vec<PathBuf>,
    /// Earlier files (of owned groups) this run does not write.
    stale: Vec<PathBuf>,
    /// The manifest's path and new text, when it changes.
    manifest: Option<(PathBuf, String)>,
}

fn plan(d: &DirWrite) -> Result<Plan, String> {
    // Resolve every path first so nothing is written if any name is unsafe.
    let targets: Vec<PathBuf> = d
        .files
        .iter()
        .map(|f| confined(d.root, &f.path))
        .collect::<Result<_, _>>()?;
    let Some(manifest) = d.manifest else {
        return Ok(Plan {
            targets,
            stale: Vec::new(),
            manifest: None,
        });
    };
    let mpath = confined(d.root, Path::new(&manifest.name))?;
    let old = std::fs::read_to_string(&mpath).unwrap_or_default();
    let now: BTreeSet<&Path> = d.files.iter().map(|f| f.path.as_path()).collect();
    let mut text = String::new();
    let mut stale = Vec::new();
    for line in old.lines() {
        let Some((group, rel)) = line.split_once('\t') else {
            continue;
        };
        if !manifest.owned.contains(group) {
            text.push_str(line);
            text.push('\n');
            continue;
        }
        if now.contains(Path::new(rel)) {
            continue;
        }
        if let Ok(path) = confined(d.root, Path::new(rel)) {
            stale.push(path);
        }
    }
    for f in d.files {
        text.push_str(&format!(
            "{}\t{}\n",
            (manifest.group)(&f.path),
            f.path.display()
        ));
    }
    let manifest = (old != text).then_some((mpath, text));
    Ok(Plan {
        targets,
        stale,
        manifest,
    })
}

/// Writes several directories as one transaction as far as a file system allows: every new
/// file (and manifest) is first staged as a temporary, all of them are made durable
/// together, stale files of the previous run are removed, then the temporaries are renamed
/// over their targets (manifests last). A crash at any moment leaves
/// each file either old or new, never partly written (ARCHITECTURE.md, "Crash safety").
pub fn write_dirs(dirs: &[DirWrite]) -> Result<Vec<Written>, String> {
    let plans: Vec<Plan> = dirs.iter().map(plan).collect::<Result<_, _>>()?;
    let mut staged: Vec<Staged> = Vec::new();
    // Target -> position in `staged`.
    let mut index: std::collections::HashMap<PathBuf, usize> = std::collections::HashMap::new();
    let mut manifests: Vec<Staged> = Vec::new();
    let mut written = Vec::with_capacity(dirs.len());
    let fail = |staged: &[Staged], manifests: &[Staged], msg: String| {
        discard(staged);
        discard(manifests);
        msg
    };
    for (d, p) in dirs.iter().zip(&plans) {
        let root = d.root;
        if root.exists() && !root.is_dir() {
            return Err(fail(
                &staged,
                &manifests,
                format!(
                    "`{}` is a file; {} must be a directory",
                    shown(root),
                    d.role
                ),
            ));
        }
        if let Err(e) = std::fs::create_dir_all(root) {
            return Err(fail(
                &staged,
                &manifests,
                io_message(root, d.role, &root.join("x"), &e),
            ));
        }
        let targets: BTreeSet<&Path> = p
            .targets
            .iter()
            .filter_map(|t| t.parent())
            .chain([root])
            .collect();
        for t in targets {
            sweep_temporaries(t);
        }
        let mut w = Written {
            files: d.files.len(),
            ..Written::default()
        };
        for (f, path) in d.files.iter().zip(&p.targets) {
            if std::fs::read(path).is_ok_and(|old| old == f.contents) {
                w.unchanged += 1;
                continue;
            }
            match stage(path, &f.contents) {
                // A path given twice: the last contents win, in the one temporary.
                Ok(s) => match index.get(&s.target) {
                    Some(&i) => staged[i] = s,
                    None => {
                        index.insert(s.target.clone(), staged.len());
                        staged.push(s);
                    }
                },
                Err(e) => {
                    return Err(fail(
                        &staged,
                        &manifests,
                        io_message(root, d.role, path, &e),
                    ))
                }
            }
        }
        if let Some((mpath, text)) = &p.manifest {
            match stage(mpath, text.as_bytes()) {
                Ok(s) => manifests.push(s),
                Err(e) => {
                    return Err(fail(
                        &staged,
                        &manifests,
                        io_message(root, d.role, mpath, &e),
                    ))
                }
            }
        }
        written.push(w);
    }
    let all: Vec<Staged> = staged.into_iter().chain(manifests).collect();
    if let Err(e) = flush(&all) {
        discard(&all);
        return Err(format!("cannot write to the output directory: {e}"));
    }
    // Stale files go before the new manifest lands: a crash in between leaves the old
    // manifest, which still names them, so the next run finishes the job.
    for ((d, p), w) in dirs.iter().zip(&plans).zip(written.iter_mut()) {
        for path in &p.stale {
            if path.is_file() && std::fs::remove_file(path).is_ok() {
                w.removed += 1;
                // Directories the removal emptied go too (a level model of a renamed level).
                let mut dir = path.parent();
                while let Some(dd) = dir.filter(|dd| *dd != d.root && dd.starts_with(d.root)) {
                    if std::fs::remove_dir(dd).is_err() {
                        break;
                    }
                    dir = dd.parent();
                }
            }
        }
    }
    for (i, s) in all.iter().enumerate() {
        if let Err(e) = std::fs::rename(&s.tmp, &s.target) {
            discard(&all[i..]);
            return Err(format!("cannot write `{}`: {e}", shown(&s.target)));
        }
        release_temporary(&s.tmp);
    }
    // The renames are not synced: a power loss may undo the last of them, which leaves
    // those files old (and whole); the next run writes them again.
    Ok(written)
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
    write_dirs(&[DirWrite {
        root,
        role,
        files,
        manifest: Some(manifest),
    }])
    .map(|w| w[0])
}

/// The manifest of a single-map command: one group, owned.
pub fn single_write(
    root: &Path,
    role: &str,
    files: &[OutputFile],
    command: &str,
    map: &str,
) -> Result<Written, String> {
    single_writes(&[(root, role, files)], command, map).map(|w| w[0])
}

/// [`single_write`] into several directories at once (one flush for all of them).
pub fn single_writes(
    dirs: &[(&Path, &str, &[OutputFile])],
    command: &str,
    map: &str,
) -> Result<Vec<Written>, String> {
    let group = |_: &Path| command.to_string();
    let manifest = Manifest {
        name: format!(".mapc-manifest-{command}-{map}"),
        group: &group,
        owned: [command.to_string()].into(),
    };
    // Two outputs into one directory (a world beside its models) share its manifest: one
    // job, or each would record only its own files and remove the other's as stale.
    let mut merged: Vec<(&Path, &str, Vec<OutputFile>, Vec<usize>)> = Vec::new();
    for (i, &(root, role, files)) in dirs.iter().enumerate() {
        match merged.iter_mut().find(|m| same_dir(m.0, root)) {
            Some(m) => {
                m.2.extend_from_slice(files);
                m.3.push(i);
            }
            None => merged.push((root, role, files.to_vec(), vec![i])),
        }
    }
    if merged.len() == dirs.len() {
        let jobs: Vec<DirWrite> = dirs
            .iter()
            .map(|&(root, role, files)| DirWrite {
                root,
                role,
                files,
                manifest: Some(&manifest),
            })
            .collect();
        return write_dirs(&jobs);
    }
    let jobs: Vec<DirWrite> = merged
        .iter()
        .map(|(root, role, files, _)| DirWrite {
            root,
            role,
            files,
            manifest: Some(&manifest),
        })
        .collect();
    let done = write_dirs(&jobs)?;
    // Reported per directory asked for: the merged job's figures go to its first entry.
    let mut out = vec![Written::default(); dirs.len()];
    for (m, w) in merged.iter().zip(done) {
        out[m.3[0]] = w;
    }
    Ok(out)
}

/// Whether two directory paths name the same directory as written (`out` and `./out`).
fn same_dir(a: &Path, b: &Path) -> bool {
    let norm =
        |p: &Path| -> PathBuf { p.components().filter(|c| *c != Component::CurDir).collect() };
    norm(a) == norm(b)
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
    fn a_leftover_temporary_linked_to_a_source_is_replaced_not_truncated() {
        let dir = tempfile::tempdir().unwrap();
        let src = dir.path().join("brick.png");
        std::fs::write(&src, b"source texture").unwrap();
        let out = dir.path().join("out");
        std::fs::create_dir_all(&out).unwrap();
        // What a killed earlier process with this pid left: a link to the source.
        std::fs::hard_link(&src, temporary_name(&out.join("brick.png"))).unwrap();
        let files = [
            OutputFile {
                path: "brick.png".into(),
                contents: b"first".to_vec(),
            },
            // Given twice: the last contents win.
            OutputFile {
                path: "brick.png".into(),
                contents: b"generated".to_vec(),
            },
        ];
        write_all(&out, "DIR", &files).unwrap();
        assert_eq!(std::fs::read(&src).unwrap(), b"source texture");
        assert_eq!(std::fs::read(out.join("brick.png")).unwrap(), b"generated");
        assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1);
    }

    #[test]
    fn shown_drops_cur_dir() {
        assert_eq!(shown(Path::new("./../x/./y")), "../x/y");
        assert_eq!(shown(Path::new("./")), ".");
    }
}
