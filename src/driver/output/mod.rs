//! Writing outputs: confined to the output directory, atomic per file, and accountable.
//!
//! Each command that writes a directory keeps a manifest there (`.mapc-manifest...`, one
//! `<group>\t<path>` line per file it wrote), so the next run removes what the previous one
//! wrote and this one did not (a graph index that no longer exists, a renamed level). Only
//! files named in a manifest are ever removed, and only in the groups this run owns.
//!
//! Temporary files (`.<name>.mapc-tmp-<pid>`) are registered while they exist, so the signal
//! watcher can remove them; ones left by a killed process are swept before the next write
//! into their directory. An output directory that does not exist yet is staged whole and
//! renamed into place once (`fresh`).

mod fresh;
mod pending;

pub use pending::{is_stream, Pending};

use mapc_backends::OutputFile;
use std::collections::{BTreeSet, HashMap, HashSet};
use std::ffi::OsString;
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::{Mutex, RwLock};

use crate::ui::shown;

/// Temporaries that exist right now (created and not yet renamed or removed).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Held shared while a temporary is created and registered (by several threads at once),
/// and exclusively by the signal watcher's sweep: it never runs while a temporary exists
/// unregistered.
static GATE: RwLock<()> = RwLock::new(());
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
    let _gate = GATE.write().unwrap_or_else(|e| e.into_inner());
    let live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    for p in live.iter() {
        // A staging directory of a first build (`fresh`) goes whole.
        if std::fs::remove_file(p).is_err() {
            let _ = std::fs::remove_dir_all(p);
        }
    }
    let _ = std::io::stderr().flush();
    eprintln!("\ninterrupted; temporary files removed");
    std::process::exit(code)
}

/// Creates a registered temporary for `path`; `None` once a signal asked to stop.
pub fn create_temporary(path: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    let tmp = temporary_name(path);
    let f = create_registered(&tmp)?;
    Ok((tmp, f))
}

/// Creates `tmp` as a new file and registers it. A new file, never one found there: a
/// temporary left by an earlier process with this pid may be a hard link to a texture,
/// which truncating would empty; such a leftover is removed and the creation retried.
fn create_registered(tmp: &Path) -> std::io::Result<std::fs::File> {
    let open = || {
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(tmp)
    };
    // Created under the gate: the watcher either sees it registered or it never exists.
    let _gate = GATE.read().unwrap_or_else(|e| e.into_inner());
    let f = match open() {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            let _ = std::fs::remove_file(tmp);
            open()?
        }
        r => r?,
    };
    LIVE.lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(tmp.to_path_buf());
    Ok(f)
}

/// Hard-links `src` at `tmp` and registers it (as [`create_registered`]).
fn link_registered(src: &Path, tmp: &Path) -> std::io::Result<()> {
    let _gate = GATE.read().unwrap_or_else(|e| e.into_inner());
    match std::fs::hard_link(src, tmp) {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            let _ = std::fs::remove_file(tmp);
            std::fs::hard_link(src, tmp)?
        }
        r => r?,
    }
    LIVE.lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(tmp.to_path_buf());
    Ok(())
}

/// Forgets a temporary that was renamed or removed.
pub fn release_temporary(tmp: &Path) {
    let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    live.retain(|p| p != tmp);
}

/// Forgets many temporaries at once (one pass over the registry, not one per file).
fn release_temporaries<'a>(done: impl IntoIterator<Item = &'a Path>) {
    let done: HashSet<&Path> = done.into_iter().collect();
    let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    live.retain(|p| !done.contains(p.as_path()));
}

/// Writes `contents` to `path` via a temporary file in the same directory and a rename,
/// so a reader never sees a half-written file and a failure leaves the old file intact;
/// a stream (`/dev/null`, a pipe) is written in place ([`Pending`]).
pub fn write_atomic(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    if !is_stream(path) {
        let dir = path.parent().unwrap_or(Path::new("."));
        std::fs::create_dir_all(dir)?;
    }
    let (pending, mut f) = Pending::create(path)?;
    f.write_all(contents)?;
    pending.commit(&f)
}

/// Whether process `pid` still runs (Linux: /proc; elsewhere assume it does not).
fn alive(pid: u32) -> bool {
    pid == std::process::id() || Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes temporaries of processes that no longer run from `dir` (not recursive).
pub fn sweep_temporaries(dir: &Path) {
    let _ = sweep_and_list(dir);
}

/// [`sweep_temporaries`], returning the names the directory holds besides temporaries
/// (one `readdir` tells which outputs already exist).
fn sweep_and_list(dir: &Path) -> std::io::Result<HashSet<OsString>> {
    let mut names = HashSet::new();
    for e in std::fs::read_dir(dir)?.flatten() {
        let name = e.file_name();
        let Some(s) = name.to_str() else {
            names.insert(name);
            continue;
        };
        let Some((_, pid)) = s.rsplit_once(TMP_MARK) else {
            names.insert(name);
            continue;
        };
        if !s.starts_with('.') || !e.file_type().is_ok_and(|t| t.is_file()) {
            names.insert(name);
            continue;
        }
        if pid.parse::<u32>().is_ok_and(|p| !alive(p)) {
            let _ = std::fs::remove_file(e.path());
        }
    }
    Ok(names)
}

/// What a write did: how many files the outputs are, and how many were already identical.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Written {
    pub files: usize,
    pub unchanged: usize,
    /// Files of a previous run removed because this run did not write them.
    pub removed: usize,
}

/// Files read from disk whose bytes an output may repeat verbatim (textures), with their
/// length: such an output is hard-linked to the file instead of written (no data to copy
/// or flush). Only paths are kept, not bytes: a candidate is compared with the file itself.
static LINK_SOURCES: Mutex<Vec<(PathBuf, u64)>> = Mutex::new(Vec::new());

/// Records that `path` holds `len` bytes that an output with the same file name may repeat.
pub fn note_link_source(path: &Path, len: u64) {
    let mut l = LINK_SOURCES.lock().unwrap_or_else(|e| e.into_inner());
    if !l.iter().any(|(p, _)| p == path) {
        l.push((path.to_path_buf(), len));
    }
}

/// A known source file with `target`'s name whose bytes are exactly `contents` now.
fn link_source(target: &Path, contents: &[u8]) -> Option<PathBuf> {
    let candidates: Vec<PathBuf> = LINK_SOURCES
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .filter(|(p, len)| p.file_name() == target.file_name() && *len == contents.len() as u64)
        .map(|(p, _)| p.clone())
        .collect();
    candidates.into_iter().find(|p| holds(p, contents))
}

/// Whether the file at `path` holds exactly `contents` (read in small pieces: no copy of
/// a whole texture in memory).
fn holds(path: &Path, contents: &[u8]) -> bool {
    let Ok(mut f) = std::fs::File::open(path) else {
        return false;
    };
    let mut buf = vec![0u8; 64 << 10];
    let mut at = 0;
    loop {
        match f.read(&mut buf) {
            Ok(0) => return at == contents.len(),
            Ok(n) => {
                if contents.get(at..at + n) != Some(&buf[..n]) {
                    return false;
                }
                at += n;
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(_) => return false,
        }
    }
}

/// A new file staged as a temporary beside its target, renamed over it at commit.
struct Staged {
    tmp: PathBuf,
    target: PathBuf,
    /// Written here (its data must be flushed), rather than linked to an existing file.
    written: bool,
    /// Under a new top directory staged whole (`fresh`): in place once that is renamed.
    fresh: bool,
}

/// Stages `data` for `path` at `tmp`: a hard link to a file with the same bytes when
/// possible (a linked output, or bytes that repeat a known source; same file system), else
/// a temporary written with those bytes.
fn stage(path: &Path, tmp: PathBuf, data: Data) -> std::io::Result<Staged> {
    let src = match data {
        Data::Link(src) => Some(src.to_path_buf()),
        Data::Bytes(contents) => link_source(path, contents),
    };
    if let Some(src) = src {
        if link_registered(&src, &tmp).is_ok() {
            return Ok(Staged {
                tmp,
                target: path.to_path_buf(),
                written: false,
                fresh: false,
            });
        }
        // Another device, or links not allowed: copy.
    }
    let read;
    let contents = match data {
        Data::Bytes(b) => b,
        Data::Link(src) => {
            read = std::fs::read(src)?;
            &read[..]
        }
    };
    let mut f = create_registered(&tmp)?;
    if let Err(e) = f.write_all(contents) {
        let _ = std::fs::remove_file(&tmp);
        release_temporary(&tmp);
        return Err(e);
    }
    Ok(Staged {
        tmp,
        target: path.to_path_buf(),
        written: true,
        fresh: false,
    })
}

/// Whether the existing file at `path` already holds `data`.
fn unchanged(path: &Path, data: Data) -> bool {
    match data {
        Data::Bytes(contents) => std::fs::read(path).is_ok_and(|old| old == contents),
        Data::Link(src) => {
            #[cfg(unix)]
            {
                use std::os::unix::fs::MetadataExt;
                let (Ok(a), Ok(b)) = (std::fs::metadata(path), std::fs::metadata(src)) else {
                    return false;
                };
                if a.dev() == b.dev() && a.ino() == b.ino() {
                    return true;
                }
            }
            std::fs::read(src).is_ok_and(|bytes| holds(path, &bytes))
        }
    }
}

/// Makes the data of every written temporary durable, in one pass: on Linux one `syncfs`
/// per file system, elsewhere `fsync` of each file.
/// Kept for speed: on the 357 files of `mapc build` one `syncfs` took 0.1 s, an `fsync` each 0.7 s.
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
            // A stat per directory; a descriptor only for the first of each file system.
            if devices.insert(std::fs::metadata(d)?.dev()) {
                let f = std::fs::File::open(d)?;
                // SAFETY: a plain syscall on an open descriptor. std has no `syncfs`.
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

fn discard<'a>(staged: impl IntoIterator<Item = &'a Staged> + Clone) {
    for s in staged.clone() {
        let _ = std::fs::remove_file(&s.tmp);
    }
    release_temporaries(staged.into_iter().map(|s| s.tmp.as_path()));
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
        files: files.iter().collect(),
        links: Vec::new(),
        manifest: None,
    }])
    .map(|w| w[0])
}

/// One directory's share of a [`write_dirs`] call.
pub struct DirWrite<'a> {
    pub root: &'a Path,
    /// The argument that named `root`, for messages (`OUTPUT_DIR`).
    pub role: &'a str,
    pub files: Vec<&'a OutputFile>,
    /// Outputs that repeat a file on disk (after `files`).
    pub links: Vec<&'a LinkedFile>,
    pub manifest: Option<&'a Manifest<'a>>,
}

/// An output that repeats a file already on disk byte for byte (a texture found on the
/// texture path): a hard link to it, or a copy when no link can be made (another file
/// system). Nothing of it is read into memory on a first build.
pub struct LinkedFile {
    /// Relative to the output directory, as [`OutputFile::path`].
    pub path: PathBuf,
    pub source: PathBuf,
}

/// What an output holds: bytes in memory, or those of a file on disk.
#[derive(Clone, Copy)]
enum Data<'a> {
    Bytes(&'a [u8]),
    Link(&'a Path),
}

impl<'a> DirWrite<'a> {
    /// Every output: relative path and data, `files` then `links`.
    fn entries(&self) -> impl Iterator<Item = (&'a Path, Data<'a>)> + '_ {
        let files = self
            .files
            .iter()
            .map(|f| (f.path.as_path(), Data::Bytes(&f.contents)));
        let links = self
            .links
            .iter()
            .map(|l| (l.path.as_path(), Data::Link(&l.source)));
        files.chain(links)
    }
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
        .entries()
        .map(|(rel, _)| confined(d.root, rel))
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
    let now: BTreeSet<&Path> = d.entries().map(|(rel, _)| rel).collect();
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
    for (rel, _) in d.entries() {
        text.push_str(&format!("{}\t{}\n", (manifest.group)(rel), rel.display()));
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
    let fresh = fresh::Fresh::find(dirs.iter().map(|d| d.root));
    if let Err(e) = fresh.create() {
        fresh.discard();
        fresh.release();
        return Err(io_message(dirs[0].root, dirs[0].role, dirs[0].root, &e));
    }
    let result = write_staged(dirs, &plans, &fresh);
    if result.is_err() {
        fresh.discard();
    }
    fresh.release();
    result
}

/// [`write_dirs`] once the new top directories are staged (`fresh`).
fn write_staged(
    dirs: &[DirWrite],
    plans: &[Plan],
    fresh: &fresh::Fresh,
) -> Result<Vec<Written>, String> {
    for d in dirs {
        let root = d.root;
        if root.exists() && !root.is_dir() {
            return Err(format!(
                "`{}` is a file; {} must be a directory",
                shown(root),
                d.role
            ));
        }
        let at = fresh.staged(root);
        if let Err(e) = std::fs::create_dir_all(at.as_deref().unwrap_or(root)) {
            return Err(io_message(root, d.role, &root.join("x"), &e));
        }
    }
    // Every directory once, parents before children (paths order by components). One that
    // already existed is read once: temporaries of dead processes are swept, and its names
    // tell which outputs exist (only those are read to see whether they are unchanged). One
    // created now is empty: nothing to read.
    let mut needed: std::collections::BTreeMap<&Path, (usize, &Path)> = Default::default();
    for (i, (d, p)) in dirs.iter().zip(plans).enumerate() {
        needed.entry(d.root).or_insert((i, d.root));
        for t in &p.targets {
            needed
                .entry(t.parent().unwrap_or(d.root))
                .or_insert((i, t.as_path()));
        }
    }
    let mut existing: HashMap<&Path, HashSet<OsString>> = HashMap::new();
    for (&dir, &(i, inside)) in &needed {
        // Under a new top: made in its staging directory, empty.
        let made = match fresh.staged(dir) {
            Some(at) => std::fs::create_dir_all(at),
            None => match std::fs::create_dir(dir) {
                Ok(()) => Ok(()),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    sweep_and_list(dir).map(|names| {
                        existing.insert(dir, names);
                    })
                }
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => std::fs::create_dir_all(dir),
                Err(e) => Err(e),
            },
        };
        if let Err(e) = made {
            let target = if inside == dir {
                dir.join("x")
            } else {
                inside.to_path_buf()
            };
            return Err(io_message(dirs[i].root, dirs[i].role, &target, &e));
        }
    }
    let exists = |path: &Path| {
        let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
            return true;
        };
        existing.get(dir).is_some_and(|names| names.contains(name))
    };

    struct Job<'a> {
        target: &'a Path,
        data: Data<'a>,
        /// Which [`DirWrite`] it belongs to (for messages).
        dir: usize,
        manifest: bool,
    }
    let mut jobs: Vec<Job> = Vec::new();
    // Target -> position in `jobs`: a path given twice is written once, with the last
    // contents.
    let mut index: HashMap<&Path, usize> =
        HashMap::with_capacity(plans.iter().map(|p| p.targets.len()).sum());
    let mut written = Vec::with_capacity(dirs.len());
    for (i, (d, p)) in dirs.iter().zip(plans).enumerate() {
        let mut w = Written {
            files: d.files.len() + d.links.len(),
            ..Written::default()
        };
        for ((_, data), path) in d.entries().zip(&p.targets) {
            if exists(path) && unchanged(path, data) {
                w.unchanged += 1;
                continue;
            }
            let job = Job {
                target: path,
                data,
                dir: i,
                manifest: false,
            };
            match index.get(path.as_path()) {
                Some(&k) => jobs[k] = job,
                None => {
                    index.insert(path, jobs.len());
                    jobs.push(job);
                }
            }
        }
        written.push(w);
    }
    let outputs = jobs.len();
    for (i, p) in plans.iter().enumerate() {
        if let Some((mpath, text)) = &p.manifest {
            jobs.push(Job {
                target: mpath,
                data: Data::Bytes(text.as_bytes()),
                dir: i,
                manifest: true,
            });
        }
    }
    // Under a new top, a file is written in the staging directory under its own name.
    let results: Vec<std::io::Result<Staged>> = jobs
        .iter()
        .map(|j| match fresh.staged(j.target) {
            Some(at) => stage(j.target, at, j.data).map(|s| Staged { fresh: true, ..s }),
            None => stage(j.target, temporary_name(j.target), j.data),
        })
        .collect();
    let mut all: Vec<Staged> = Vec::with_capacity(jobs.len());
    let mut failed = None;
    for (j, r) in jobs.iter().zip(results) {
        match r {
            Ok(s) => all.push(s),
            Err(e) => {
                failed.get_or_insert_with(|| {
                    let d = &dirs[j.dir];
                    io_message(d.root, d.role, j.target, &e)
                });
            }
        }
    }
    debug_assert!(jobs.iter().skip(outputs).all(|j| j.manifest));
    if let Some(msg) = failed {
        discard(&all);
        return Err(msg);
    }
    if let Err(e) = flush(&all) {
        discard(&all);
        return Err(format!("cannot write to the output directory: {e}"));
    }
    // Stale files go before the new manifest lands: a crash in between leaves the old
    // manifest, which still names them, so the next run finishes the job.
    for ((d, p), w) in dirs.iter().zip(plans).zip(written.iter_mut()) {
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
    // New top directories first, whole (their own manifests inside): the world refers to
    // the models. Then the other outputs, and their
    // manifests only once every output is in place.
    if let Err(e) = fresh.commit() {
        discard(&all);
        return Err(format!(
            "cannot move the new output directory into place: {e}"
        ));
    }
    let (files, manifests) = all.split_at(outputs);
    let files: Vec<&Staged> = files.iter().filter(|s| !s.fresh).collect();
    let manifests: Vec<&Staged> = manifests.iter().filter(|s| !s.fresh).collect();
    let renamed: Vec<std::io::Result<()>> = files
        .iter()
        .map(|s| std::fs::rename(&s.tmp, &s.target))
        .collect();
    let mut failed = None;
    for (s, r) in files.iter().zip(&renamed) {
        if let Err(e) = r {
            let _ = std::fs::remove_file(&s.tmp);
            failed.get_or_insert_with(|| format!("cannot write `{}`: {e}", shown(&s.target)));
        }
    }
    if failed.is_none() {
        for (k, s) in manifests.iter().enumerate() {
            if let Err(e) = std::fs::rename(&s.tmp, &s.target) {
                discard(manifests[k..].iter().copied());
                failed = Some(format!("cannot write `{}`: {e}", shown(&s.target)));
                break;
            }
        }
    } else {
        discard(manifests.iter().copied());
    }
    release_temporaries(all.iter().map(|s| s.tmp.as_path()));
    if let Some(msg) = failed {
        return Err(msg);
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
        files: files.iter().collect(),
        links: Vec::new(),
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
    let dirs: Vec<_> = dirs
        .iter()
        .map(|&(r, role, f)| (r, role, f, &[][..]))
        .collect();
    single_writes_linked(&dirs, command, map)
}

/// [`single_writes`] with, per directory, outputs that repeat files on disk.
pub fn single_writes_linked(
    dirs: &[(&Path, &str, &[OutputFile], &[LinkedFile])],
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
    let mut merged: Vec<(DirWrite, Vec<usize>)> = Vec::new();
    for (i, &(root, role, files, links)) in dirs.iter().enumerate() {
        match merged.iter_mut().find(|m| same_dir(m.0.root, root)) {
            Some((d, at)) => {
                d.files.extend(files);
                d.links.extend(links);
                at.push(i);
            }
            None => merged.push((
                DirWrite {
                    root,
                    role,
                    files: files.iter().collect(),
                    links: links.iter().collect(),
                    manifest: Some(&manifest),
                },
                vec![i],
            )),
        }
    }
    let (jobs, at): (Vec<DirWrite>, Vec<Vec<usize>>) = merged.into_iter().unzip();
    let done = write_dirs(&jobs)?;
    // Reported per directory asked for: a merged job's figures go to its first entry.
    let mut out = vec![Written::default(); dirs.len()];
    for (at, w) in at.iter().zip(done) {
        out[at[0]] = w;
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
    fn linked_outputs_are_links_recorded_in_the_manifest_and_unchanged_on_rerun() {
        use std::os::unix::fs::MetadataExt;
        let dir = tempfile::tempdir().unwrap();
        let src = dir.path().join("wall.png");
        std::fs::write(&src, b"texture bytes").unwrap();
        let out = dir.path().join("out");
        let files = [OutputFile {
            path: "L1/model.sdf".into(),
            contents: b"<sdf/>".to_vec(),
        }];
        let links = [LinkedFile {
            path: "L1/meshes/wall.png".into(),
            source: src.clone(),
        }];
        let run = || single_writes_linked(&[(&out, "DIR", &files, &links)], "gz", "m").unwrap();
        assert_eq!(
            run()[0],
            Written {
                files: 2,
                unchanged: 0,
                removed: 0
            }
        );
        let png = out.join("L1/meshes/wall.png");
        assert_eq!(std::fs::read(&png).unwrap(), b"texture bytes");
        let (a, b) = (
            std::fs::metadata(&png).unwrap(),
            std::fs::metadata(&src).unwrap(),
        );
        assert_eq!((a.dev(), a.ino()), (b.dev(), b.ino()));
        let manifest = std::fs::read_to_string(out.join(".mapc-manifest-gz-m")).unwrap();
        assert_eq!(manifest, "gz\tL1/model.sdf\ngz\tL1/meshes/wall.png\n");
        assert_eq!(
            run()[0],
            Written {
                files: 2,
                unchanged: 2,
                removed: 0
            }
        );
        // A copy with the same bytes (another tool wrote it) is unchanged too; other bytes
        // are replaced by the link.
        std::fs::remove_file(&png).unwrap();
        std::fs::write(&png, b"texture bytes").unwrap();
        assert_eq!(run()[0].unchanged, 2);
        std::fs::remove_file(&png).unwrap();
        std::fs::write(&png, b"older texture").unwrap();
        assert_eq!(run()[0].unchanged, 1);
        assert_eq!(std::fs::metadata(&png).unwrap().ino(), b.ino());
        // Dropped from the outputs: removed as stale, the source kept.
        let none: [LinkedFile; 0] = [];
        let w = single_writes_linked(&[(&out, "DIR", &files, &none)], "gz", "m").unwrap();
        assert_eq!(w[0].removed, 1);
        assert!(!png.exists() && src.exists());
        assert_eq!(std::fs::read_dir(out.join("L1")).unwrap().count(), 1);
    }

    #[test]
    fn many_files_in_fresh_and_existing_directories() {
        // Enough files for two staging threads; some directories exist with files.
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        std::fs::create_dir_all(out.join("d3")).unwrap();
        std::fs::write(out.join("d3/f3.txt"), "3 in d3").unwrap();
        std::fs::write(out.join("d3/f8.txt"), "old").unwrap();
        let files: Vec<OutputFile> = (0..40)
            .map(|i| OutputFile {
                path: format!("d{}/f{i}.txt", i % 5).into(),
                contents: format!("{i} in d{}", i % 5).into_bytes(),
            })
            .collect();
        let w = write_all(&out, "DIR", &files).unwrap();
        assert_eq!(
            w,
            Written {
                files: 40,
                unchanged: 1,
                removed: 0
            }
        );
        for f in &files {
            assert_eq!(std::fs::read(out.join(&f.path)).unwrap(), f.contents);
        }
        let leftovers = (0..5)
            .flat_map(|d| std::fs::read_dir(out.join(format!("d{d}"))).unwrap())
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .contains(TMP_MARK)
            })
            .count();
        assert_eq!(leftovers, 0);
        let live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
        assert!(!live.iter().any(|p| p.starts_with(&out)));
    }

    #[test]
    fn shown_drops_cur_dir() {
        assert_eq!(shown(Path::new("./../x/./y")), "../x/y");
        assert_eq!(shown(Path::new("./")), ".");
    }
}
