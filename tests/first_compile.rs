//! Issue 12, part 5: how `mapc gazebo` writes a first compile. Textures are hard links to
//! the files they were read from (nothing copied), every file of a command is written in
//! one batch, and a world written into its own model directory shares that directory's
//! manifest (the batch once wrote a manifest per output and removed the other's files).

mod support;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};
use support::mapc;

const CLINIC: &str = "fixtures/two_level_clinic.building.yaml";

/// A texture directory holding a copy of `name.png` for every texture the clinic fixture
/// names, each a distinct valid PNG (with a text chunk, which the glTF writer strips).
fn textures(dir: &Path) -> Vec<PathBuf> {
    let map = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(CLINIC)).unwrap();
    let mut names: Vec<String> = Vec::new();
    for key in ["texture_name: [1, ", "texture: [1, "] {
        for part in map.split(key).skip(1) {
            let name = part.split(']').next().unwrap().trim().trim_matches('"');
            if !name.is_empty() && !names.iter().any(|n| n == name) {
                names.push(name.to_string());
            }
        }
    }
    std::fs::create_dir_all(dir).unwrap();
    names
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let mut png = Vec::new();
            {
                let mut enc = png::Encoder::new(&mut png, 2, 2);
                enc.set_color(png::ColorType::Rgb);
                enc.add_text_chunk("Comment".into(), format!("texture {i}"))
                    .unwrap();
                let mut w = enc.write_header().unwrap();
                w.write_image_data(&[i as u8; 12]).unwrap();
            }
            let p = dir.join(format!("{n}.png"));
            std::fs::write(&p, png).unwrap();
            p
        })
        .collect()
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            if e.file_type().unwrap().is_dir() {
                stack.push(e.path());
            } else {
                out.push(e.path());
            }
        }
    }
    out.sort();
    out
}

#[test]
fn textures_are_linked_not_copied() {
    let tmp = tempfile::tempdir().unwrap();
    let tex = tmp.path().join("textures");
    let sources = textures(&tex);
    assert!(!sources.is_empty());
    let out = tmp.path().join("out");
    let (code, _, err) = mapc(&[
        "gazebo",
        CLINIC,
        out.join("w.world").to_str().unwrap(),
        out.join("models").to_str().unwrap(),
        "--texture-path",
        tex.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let pngs: Vec<PathBuf> = files(&out.join("models"))
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    assert!(!pngs.is_empty());
    for p in &pngs {
        let src = tex.join(p.file_name().unwrap());
        let (a, b) = (
            std::fs::metadata(p).unwrap(),
            std::fs::metadata(&src).unwrap(),
        );
        // The same file (same inode), so the same bytes as read, chunks and all.
        assert_eq!((a.dev(), a.ino()), (b.dev(), b.ino()), "{}", p.display());
    }
    // A rerun finds them unchanged; a changed texture replaces the link, never writes
    // through it into the source.
    let (code, _, err) = mapc(&[
        "gazebo",
        CLINIC,
        out.join("w.world").to_str().unwrap(),
        out.join("models").to_str().unwrap(),
        "--texture-path",
        tex.to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    let line = err
        .lines()
        .find(|l| l.contains(" files written to "))
        .unwrap();
    let (total, rest) = line.split_once(" files written to ").unwrap();
    let total = total.rsplit(' ').next().unwrap();
    assert!(rest.contains(&format!("({total} unchanged)")), "{line}");
    let first = &pngs[0];
    let src = tex.join(first.file_name().unwrap());
    let before = std::fs::read(&src).unwrap();
    std::fs::remove_dir_all(&tex).unwrap();
    let (code, _, _) = mapc(&[
        "gazebo",
        CLINIC,
        out.join("w.world").to_str().unwrap(),
        out.join("models").to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    assert_ne!(std::fs::read(first).unwrap(), before, "placeholder written");
    assert!(std::fs::metadata(first).unwrap().nlink() == 1);
}

#[test]
fn world_beside_its_models_keeps_them() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let world = out.join("w.world");
    let (code, _, err) = mapc(&["gazebo", CLINIC, world.to_str().unwrap(), o]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("stale removed"), "{err}");
    let written = files(&out);
    assert!(written.iter().any(|p| p.ends_with("w.world")));
    let objs = written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .count();
    assert!(objs >= 4, "{written:?}");
    // One manifest naming every file, and a rerun changes nothing.
    let manifests: Vec<_> = written
        .iter()
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .starts_with(".mapc-manifest")
        })
        .collect();
    assert_eq!(manifests.len(), 1, "{manifests:?}");
    let listed = std::fs::read_to_string(manifests[0])
        .unwrap()
        .lines()
        .count();
    assert_eq!(listed, written.len() - 1);
    let (code, _, err) = mapc(&["gazebo", CLINIC, world.to_str().unwrap(), o]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(files(&out), written);
    assert!(!err.contains("stale removed"), "{err}");
}
