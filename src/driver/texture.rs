//! The texture search path: `--texture-path DIR` options in order, then the directories of
//! the `MAPC_TEXTURE_PATH` environment variable (colon-separated), then
//! `share/rmf_building_map_tools/textures` under every prefix of `AMENT_PREFIX_PATH` (where
//! an RMF install keeps the editor's textures), then the map file's directory. The first
//! `<name>.png` found wins.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// Textures larger than this are treated as unreadable (a GLB holds at most 4 GiB).
const MAX_TEXTURE_BYTES: u64 = 256 << 20;

pub struct SearchPath {
    pub dirs: Vec<PathBuf>,
}

impl SearchPath {
    /// The path from the environment's `MAPC_TEXTURE_PATH` and `AMENT_PREFIX_PATH`.
    pub fn from_env(cli: &[PathBuf], map_file: &Path) -> Self {
        Self::new(
            cli,
            std::env::var_os("MAPC_TEXTURE_PATH"),
            std::env::var_os("AMENT_PREFIX_PATH"),
            map_file,
        )
    }

    pub fn new(
        cli: &[PathBuf],
        env: Option<OsString>,
        ament: Option<OsString>,
        map_file: &Path,
    ) -> Self {
        let mut dirs: Vec<PathBuf> = cli.to_vec();
        if let Some(env) = env {
            dirs.extend(std::env::split_paths(&env).filter(|p| !p.as_os_str().is_empty()));
        }
        if let Some(ament) = ament {
            dirs.extend(
                std::env::split_paths(&ament)
                    .filter(|p| !p.as_os_str().is_empty())
                    .map(|p| p.join("share/rmf_building_map_tools/textures")),
            );
        }
        let map_dir = map_file.parent().filter(|p| !p.as_os_str().is_empty());
        dirs.push(map_dir.unwrap_or(Path::new(".")).to_path_buf());
        SearchPath { dirs }
    }

    /// Contents of the first `file` (a plain file name) found in the search directories.
    pub fn find(&self, file: &str) -> Option<Vec<u8>> {
        self.locate(file).map(|(_, bytes)| bytes)
    }

    /// The first `file` in the search directories that is a regular file within the size
    /// limit, opened: opening it first and asking the open file walks each path once.
    fn open_first(&self, file: &str) -> Option<(PathBuf, std::fs::File)> {
        self.dirs.iter().find_map(|d| {
            let p = d.join(file);
            let mut open = std::fs::OpenOptions::new();
            open.read(true);
            // Non-blocking: a FIFO of that name must not stall the run (it is then passed
            // over as not a regular file).
            #[cfg(unix)]
            std::os::unix::fs::OpenOptionsExt::custom_flags(&mut open, libc::O_NONBLOCK);
            let f = open.open(&p).ok()?;
            let m = f.metadata().ok()?;
            (m.is_file() && m.len() <= MAX_TEXTURE_BYTES).then_some((p, f))
        })
    }

    /// As [`SearchPath::locate`] for an image that is linked into the outputs rather than
    /// copied: only the head of the file, as far as a PNG decoder reads to accept it (the
    /// chunks before the pixel data; the whole file when they are not within its first
    /// 64 KiB), so that whether it is a PNG is decided as on the whole file.
    pub fn find_head(&self, file: &str) -> Option<(PathBuf, Vec<u8>)> {
        use std::io::Read;
        let (p, mut f) = self.open_first(file)?;
        let mut head = Vec::new();
        // 4 KiB holds the header chunks of nearly every image; 64 KiB those with a colour
        // profile or text; beyond that, the whole file. Room is made first, so that each
        // step is one read (from an empty buffer, reading starts with 32 bytes and doubles).
        for want in [4 << 10, 64 << 10] {
            let have = head.len() as u64;
            head.reserve_exact((want - have) as usize);
            (&mut f).take(want - have).read_to_end(&mut head).ok()?;
            if (head.len() as u64) < want || mapc_backends::png_head_is_enough(&head) {
                return Some((p, head));
            }
        }
        f.read_to_end(&mut head).ok()?;
        Some((p, head))
    }

    /// As [`SearchPath::find`], with the path the file was read from (for depfiles).
    pub fn locate(&self, file: &str) -> Option<(PathBuf, Vec<u8>)> {
        self.dirs.iter().find_map(|d| {
            let p = d.join(file);
            let meta = std::fs::metadata(&p).ok()?;
            if !meta.is_file() || meta.len() > MAX_TEXTURE_BYTES {
                return None;
            }
            let bytes = std::fs::read(&p).ok()?;
            // An output repeating these bytes can be a link to this file, not a copy.
            super::output::note_link_source(&p, bytes.len() as u64);
            Some((p, bytes))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_is_cli_then_env_then_map_dir() {
        let sp = SearchPath::new(
            &[PathBuf::from("a"), PathBuf::from("b")],
            Some(OsString::from("c::d")),
            Some(OsString::from("/opt/ros/jazzy")),
            Path::new("maps/x.building.yaml"),
        );
        let want: Vec<PathBuf> = [
            "a",
            "b",
            "c",
            "d",
            "/opt/ros/jazzy/share/rmf_building_map_tools/textures",
            "maps",
        ]
        .iter()
        .map(PathBuf::from)
        .collect();
        assert_eq!(sp.dirs, want);
        let sp = SearchPath::new(&[], None, None, Path::new("x.building.yaml"));
        assert_eq!(sp.dirs, [PathBuf::from(".")]);
    }

    #[test]
    fn heads_are_read_as_far_as_the_header_chunks_go() {
        let dir = std::env::temp_dir().join(format!("mapc-heads-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // Header chunks past 4 KiB: a 20 KB text chunk before the pixels.
        let mut big = Vec::new();
        {
            let mut e = png::Encoder::new(&mut big, 2, 2);
            e.set_color(png::ColorType::Rgb);
            e.add_text_chunk("Comment".into(), "x".repeat(20_000))
                .unwrap();
            let mut w = e.write_header().unwrap();
            w.write_image_data(&[0u8; 12]).unwrap();
        }
        std::fs::write(dir.join("big_header.png"), &big).unwrap();
        std::fs::write(dir.join("junk.png"), vec![7u8; 100_000]).unwrap();
        let small = mapc_backends::placeholder_png();
        std::fs::write(dir.join("small.png"), &small).unwrap();
        let sp = SearchPath {
            dirs: vec![dir.clone()],
        };
        let (p, h) = sp.find_head("big_header.png").unwrap();
        assert_eq!(p, dir.join("big_header.png"));
        assert!(h.len() > 4 << 10 && h.len() <= 64 << 10, "{}", h.len());
        assert!(mapc_backends::is_png(&h));
        // No PNG signature: the first 4 KiB decide as well as the whole file.
        let (_, j) = sp.find_head("junk.png").unwrap();
        assert_eq!(j.len(), 4 << 10);
        assert!(!mapc_backends::is_png(&j));
        assert!(!mapc_backends::is_png(
            &std::fs::read(dir.join("junk.png")).unwrap()
        ));
        // A PNG signature, then 100 KB of one chunk that never ends: read whole.
        let mut endless = small[..8].to_vec();
        endless.extend_from_slice(&200_000u32.to_be_bytes());
        endless.extend_from_slice(b"tEXt");
        endless.resize(100_000, b'x');
        std::fs::write(dir.join("endless.png"), &endless).unwrap();
        assert_eq!(sp.find_head("endless.png").unwrap().1, endless);
        assert_eq!(sp.find_head("small.png").unwrap().1, small);
        assert!(sp.find_head("missing.png").is_none());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A directory or a FIFO of the texture's name is passed over for the next directory's
    /// file, and the FIFO (which no process writes) does not stall the search.
    #[cfg(unix)]
    #[test]
    fn only_regular_files_are_found() {
        let tmp = tempfile::tempdir().unwrap();
        let (a, b, c) = (
            tmp.path().join("a"),
            tmp.path().join("b"),
            tmp.path().join("c"),
        );
        for d in [&a, &b, &c] {
            std::fs::create_dir(d).unwrap();
        }
        std::fs::create_dir(a.join("wood.png")).unwrap();
        let fifo = std::ffi::CString::new(b.join("wood.png").into_os_string().into_encoded_bytes())
            .unwrap();
        // SAFETY: a valid NUL-terminated path. std cannot make a FIFO.
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o644) }, 0);
        let png = mapc_backends::placeholder_png();
        std::fs::write(c.join("wood.png"), &png).unwrap();
        let sp = SearchPath {
            dirs: vec![a, b, c.clone()],
        };
        assert_eq!(sp.find_head("wood.png"), Some((c.join("wood.png"), png)));
    }
}
