//! One named output file (a report, a trace, a depfile): replaced atomically when it is a
//! file, written in place when it is a stream.
//!
//! A target that exists and is neither a regular file nor a directory (a device such as
//! `/dev/null`, a FIFO, `/dev/stdout`, a shell's `/dev/fd/N`) is opened and written
//! directly. Renaming a temporary over it, as a file is replaced, would put a regular file
//! where the device was: run as root with `--report /dev/null`, that replaced `/dev/null`
//! itself, which then collected every other program's discarded output.

use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};

/// Whether `path` exists and is something written in place (see the module doc). Symbolic
/// links are followed: `/dev/stdout` is one, to the process's own descriptor.
pub fn is_stream(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// An output being written: a registered temporary beside the target, renamed over it by
/// [`Pending::commit`] and removed when dropped uncommitted; or the stream itself.
pub struct Pending {
    path: PathBuf,
    /// `None` for a stream.
    tmp: Option<PathBuf>,
}

impl Pending {
    /// Opens `path` for writing. Opening a FIFO waits for its reader, as a shell's `>` does.
    pub fn create(path: &Path) -> io::Result<(Pending, File)> {
        if is_stream(path) {
            let f = std::fs::OpenOptions::new().write(true).open(path)?;
            let p = Pending {
                path: path.to_path_buf(),
                tmp: None,
            };
            return Ok((p, f));
        }
        let (tmp, f) = super::create_temporary(path)?;
        let p = Pending {
            path: path.to_path_buf(),
            tmp: Some(tmp),
        };
        Ok((p, f))
    }

    /// Makes the written file durable and puts it in place; `file` is the one `create`
    /// returned, flushed by the caller. A stream has nothing to sync or rename.
    pub fn commit(mut self, file: &File) -> io::Result<()> {
        let Some(tmp) = self.tmp.take() else {
            return Ok(());
        };
        let r = file
            .sync_all()
            .and_then(|()| std::fs::rename(&tmp, &self.path));
        if r.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        super::release_temporary(&tmp);
        r
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if let Some(tmp) = self.tmp.take() {
            let _ = std::fs::remove_file(&tmp);
            super::release_temporary(&tmp);
        }
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::io::{Read, Write};

    #[test]
    fn a_file_is_replaced_whole_and_a_fifo_is_written_in_place() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("report.json");
        std::fs::write(&file, "old").unwrap();
        let (p, mut f) = Pending::create(&file).unwrap();
        f.write_all(b"new").unwrap();
        // Until the commit the old bytes stay under the name.
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "old");
        p.commit(&f).unwrap();
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary is left");

        // A dropped, uncommitted output leaves the old file and no temporary.
        let (p, mut f) = Pending::create(&file).unwrap();
        f.write_all(b"half").unwrap();
        drop((p, f));
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);

        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        assert!(is_stream(&fifo));
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || {
                let mut s = String::new();
                File::open(&fifo).unwrap().read_to_string(&mut s).unwrap();
                s
            })
        };
        let (p, mut f) = Pending::create(&fifo).unwrap();
        f.write_all(b"through the pipe").unwrap();
        p.commit(&f).unwrap();
        drop(f);
        // Before the join: a reader of a FIFO that was replaced would wait for ever.
        let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        use std::os::unix::fs::FileTypeExt;
        assert!(
            kind.is_fifo(),
            "the FIFO is still a FIFO, not a file put in its place"
        );
        assert_eq!(reader.join().unwrap(), "through the pipe");
    }
}
