//! Reads `.building.yaml` (and legacy `.project.yaml`) into the mapc IR.
//!
//! The frontend never panics on any input: it returns what it could read plus diagnostics.
//! A building is returned only when it has at least one level; it may still carry
//! diagnostics, and callers must not generate outputs when any of them is an error.

pub mod codes;
pub mod crs;
mod lower;
pub mod site;
pub mod spelling;
mod transform;
mod yaml;

pub use codes::{Code, CODES};
pub use site::is_site_file;

/// The located YAML tree the frontend reads maps with, for other YAML inputs of mapc
/// (simulation scenarios) that want the same limits, spans and YAML 1.2 scalars.
pub mod yaml_tree {
    pub use crate::yaml::{
        max_nodes, parse, Kind, Node, Scalar, MAX_ALIAS_NODES, MAX_DEPTH, MAX_NODES,
    };
}
use mapc_ir::{Building, Diagnostic, FileId, Span};
use std::path::{Path, PathBuf};

/// Hooks for fuzz targets only (feature `fuzzing`); not part of the stable API.
#[cfg(feature = "fuzzing")]
#[doc(hidden)]
pub mod fuzzing {
    /// `Ok(true)` when the fast YAML reader accepted `text` and built the same tree as the
    /// general reader, `Ok(false)` when it declined, `Err` on any disagreement.
    pub fn yaml_differential(text: &str) -> Result<bool, String> {
        crate::yaml::oracle::check(text)
    }
}

/// Largest input file accepted (bytes). Real maps are under 1 MB.
pub const MAX_FILE_BYTES: u64 = 64 * 1024 * 1024;

/// A source file kept for diagnostics rendering.
#[derive(Debug, Clone)]
pub struct SourceFile {
    pub name: String,
    pub text: String,
}

/// The result of reading a map.
#[derive(Debug)]
pub struct Parsed {
    pub building: Option<Building>,
    pub diagnostics: Vec<Diagnostic>,
    /// Indexed by `FileId`.
    pub sources: Vec<SourceFile>,
}

impl Parsed {
    pub fn has_errors(&self) -> bool {
        mapc_ir::has_errors(&self.diagnostics)
    }
    /// The building when there are no errors.
    pub fn valid_building(&self) -> Option<&Building> {
        if self.has_errors() {
            None
        } else {
            self.building.as_ref()
        }
    }
}

/// Parses a `.building.yaml` document held in memory. `name` is used in diagnostics.
pub fn parse_str(name: &str, text: &str) -> Parsed {
    let mut sources = vec![SourceFile {
        name: name.to_string(),
        text: text.to_string(),
    }];
    let mut diagnostics = Vec::new();
    let building = parse_into(FileId(0), text, &mut diagnostics);
    sources.truncate(1);
    Parsed {
        building,
        diagnostics,
        sources,
    }
}

/// Parses an rmf_site `.site.json` document held in memory. `name` is used in diagnostics.
pub fn parse_site_str(name: &str, text: &str) -> Parsed {
    let sources = vec![SourceFile {
        name: name.to_string(),
        text: text.to_string(),
    }];
    let mut diagnostics = Vec::new();
    let building = site::parse_into(FileId(0), text, &mut diagnostics);
    Parsed {
        building,
        diagnostics,
        sources,
    }
}

/// Below this size a map is read into one whole tree: its lists are then read once, not
/// checked and read again item by item (a tenth of a first compile of a demo map), and the
/// tree, about ten times the text, stays far below the 64 MiB a run may take anyway.
const WHOLE_TREE_BELOW: usize = 1 << 20;

fn parse_into(file: FileId, text: &str, diags: &mut Vec<Diagnostic>) -> Option<Building> {
    parse_and_lower(text.len() >= WHOLE_TREE_BELOW, file, text, diags)
}

/// With `defer`, the level lists are left out of the tree and read again one item at a
/// time as they are lowered.
fn parse_and_lower(
    defer: bool,
    file: FileId,
    text: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<Building> {
    let parsed = if defer {
        yaml::parse_map(text, file)
    } else {
        yaml::parse(text, file).map(|root| (root, yaml::Lists::whole(text, file)))
    };
    let (mut root, lists) = match parsed {
        Ok(r) => r,
        Err(d) => {
            diags.push(d);
            return None;
        }
    };
    let mut b = lower::Lower { diags: &mut *diags }.building(&mut root, &lists)?;
    drop(root);
    transform::apply(&mut b, diags);
    Some(b)
}

/// An I/O problem reading the input (exit code 2 in the CLI).
#[derive(Debug)]
pub struct LoadError {
    pub path: PathBuf,
    pub message: String,
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

/// Reads a file; `Ok(None)` when it is larger than [`MAX_FILE_BYTES`] (a map problem, not
/// an I/O one). The read itself is bounded too, in case the file grows meanwhile.
fn read(path: &Path) -> Result<Option<Vec<u8>>, LoadError> {
    use std::io::Read;
    let err = |message: String| LoadError {
        path: path.to_path_buf(),
        message,
    };
    let meta = std::fs::metadata(path).map_err(|e| err(e.to_string()))?;
    if !meta.is_file() {
        return Err(err("not a regular file".into()));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Ok(None);
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| err(e.to_string()))?;
    Ok((bytes.len() as u64 <= MAX_FILE_BYTES).then_some(bytes))
}

/// Reads and parses a map file. A `.project.yaml` is followed to the building file it
/// names (relative to the project file).
pub fn load(path: &Path) -> Result<Parsed, LoadError> {
    let mut sources = Vec::new();
    let mut diagnostics = Vec::new();
    let building = load_into(path, &mut sources, &mut diagnostics, 0)?;
    Ok(Parsed {
        building,
        diagnostics,
        sources,
    })
}

fn is_project_file(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.ends_with(".project.yaml"))
}

fn load_into(
    path: &Path,
    sources: &mut Vec<SourceFile>,
    diags: &mut Vec<Diagnostic>,
    depth: usize,
) -> Result<Option<Building>, LoadError> {
    let file = FileId(sources.len() as u32);
    let name = path.display().to_string();
    let Some(bytes) = read(path)? else {
        diags.push(
            Diagnostic::error(
                "E0002",
                Span {
                    file,
                    ..Span::UNKNOWN
                },
                format!("the file is larger than the input limit of {MAX_FILE_BYTES} bytes"),
            )
            .with_help("real building maps are under a few MB; check that this is the right file"),
        );
        sources.push(SourceFile {
            name,
            text: String::new(),
        });
        return Ok(None);
    };
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let line = valid.iter().filter(|&&c| c == b'\n').count() + 1;
            let col = valid.iter().rev().take_while(|&&c| c != b'\n').count() + 1;
            let off = valid.len() as u32;
            diags.push(
                Diagnostic::error(
                    "E0003",
                    Span {
                        file,
                        start: off,
                        end: off,
                        line: line as u32,
                        col: col as u32,
                    },
                    "the file is not valid UTF-8",
                )
                .with_help("save the map as UTF-8"),
            );
            let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
            sources.push(SourceFile { name, text });
            return Ok(None);
        }
    };
    if !is_project_file(path) {
        // Parsed from the kept source: no second copy of a large file.
        let is_site = is_site_file(&name);
        sources.push(SourceFile { name, text });
        let text = &sources[sources.len() - 1].text;
        if is_site {
            return Ok(site::parse_into(file, text, diags));
        }
        return Ok(parse_into(file, text, diags));
    }
    sources.push(SourceFile {
        name,
        text: text.clone(),
    });
    // Legacy project file: {building: {filename: x.building.yaml}, ...}.
    let root = match yaml::parse(&text, file) {
        Ok(r) => r,
        Err(d) => {
            diags.push(d);
            return Ok(None);
        }
    };
    let target = root
        .get("building")
        .and_then(|b| b.get("filename"))
        .and_then(|f| f.key_text());
    let Some(target) = target else {
        diags.push(
            Diagnostic::error(
                "E0111",
                root.span,
                "project file has no `building: {filename: ...}`",
            )
            .with_help("name the .building.yaml file under `building.filename`, or pass the .building.yaml directly"),
        );
        return Ok(None);
    };
    let bpath = path.parent().unwrap_or(Path::new(".")).join(target);
    if depth > 0 || is_project_file(&bpath) {
        diags.push(
            Diagnostic::error(
                "E0111",
                root.span,
                "a project file must point at a .building.yaml, not another project file",
            )
            .with_help("set `building.filename` to the .building.yaml file"),
        );
        return Ok(None);
    }
    load_into(&bpath, sources, diags, depth + 1)
}

#[cfg(test)]
mod lowering_paths {
    use super::*;
    use std::path::Path;

    /// Both readers: `text` as written (the fast reader takes most maps), and with CRLF
    /// line ends (which only the general reader takes).
    fn same(name: &str, text: &str) {
        same_read(name, text);
        same_read(&format!("{name} (CRLF)"), &text.replace('\n', "\r\n"));
    }

    fn same_read(name: &str, text: &str) {
        let (mut d1, mut d2) = (Vec::new(), Vec::new());
        let a = parse_and_lower(true, FileId(0), text, &mut d1);
        let b = parse_and_lower(false, FileId(0), text, &mut d2);
        assert_eq!(
            format!("{a:?}"),
            format!("{b:?}"),
            "{name}: buildings differ"
        );
        assert_eq!(
            format!("{d1:?}"),
            format!("{d2:?}"),
            "{name}: diagnostics differ"
        );
    }

    /// Single edits near structure (as the fast reader's differential test makes): the
    /// deferred and whole-tree paths must agree on each.
    fn mutations(name: &str, text: &str) {
        const EDITS: &[&str] = &[
            "",
            " ",
            "\n",
            "- ",
            ": ",
            ",",
            "[",
            "]",
            "{",
            "}",
            "#",
            "'",
            "  ",
            "x: y",
            "\n    - [0, 0, 0, v]\n",
            "\n  L9:\n    lanes:\n    - [0, 1]\n",
        ];
        let mut seed = 0x9E3779B97F4A7C15u64 ^ text.len() as u64;
        for _ in 0..12 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let mut at = (seed % text.len().max(1) as u64) as usize;
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            let mut end = (at + ((seed >> 32) % 3) as usize).min(text.len());
            while !text.is_char_boundary(end) {
                end += 1;
            }
            let edit = EDITS[((seed >> 40) as usize) % EDITS.len()];
            let m = format!("{}{edit}{}", &text[..at], &text[end..]);
            same(&format!("{name} with {edit:?} at {at}"), &m);
        }
    }

    /// Reading level lists again from the text gives the same building and diagnostics,
    /// spans included, as lowering the whole tree: on every fixture and demo map, and on
    /// lists written in each way the reader knows (indentless, maps as items, comments,
    /// lists of other levels and of lifts beside them).
    #[test]
    fn deferred_lists_lower_as_the_whole_tree() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut n = 0;
        for dir in ["fixtures", "fixtures/invalid", "tests/fuzz_regressions"] {
            for e in std::fs::read_dir(root.join(dir)).unwrap() {
                let p = e.unwrap().path();
                if p.to_string_lossy().ends_with(".building.yaml") {
                    let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
                    same(&p.display().to_string(), &text);
                    mutations(&p.display().to_string(), &text);
                    n += 1;
                }
            }
        }
        match std::fs::read_dir(root.join("../shared/maps")) {
            Ok(maps) => {
                for m in maps {
                    let m = m.unwrap().path();
                    let name = m.file_name().unwrap().to_string_lossy().into_owned();
                    let p = m.join(format!("{name}.building.yaml"));
                    same(&name, &std::fs::read_to_string(&p).unwrap());
                    n += 1;
                }
            }
            Err(_) => println!("skipped demo maps: ../shared not found"),
        }
        assert!(n > 20, "{n} maps");
        for text in [
            // Indentless lists, a comment between items, a bad vertex and a bad index.
            "name: t\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    vertices:\n    - [0, 0, 0, a]\n    # c\n    - [1, 0, 0, b, {is_charger: [4, true]}]\n    - [x, 0, 0, c]\n    lanes:\n    - [0, 1, {graph_idx: [2, 0]}]\n    - [0, 9, {graph_idx: [2, 0]}]\n",
            // Items written as block mappings and sequences, a second level, flow lists.
            "name: t\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    lanes:\n      -\n        - 0\n        - 1\n        - graph_idx: [2, 0]\n    vertices:\n      - [0, 0, 0, a]\n      - [1, 1, 0, 'b c']\n    walls: [[0, 1]]\n  L2:\n    vertices:\n      - [0, 0, 0, x]\n    doors:\n      - [0, 0, {name: [1, d], type: [1, hinged]}]\nlifts:\n  lift1:\n    levels: [L1]\n",
            // Flow lists, one after its key and one on its own lines; a tab (general
            // reader); a list item spanning lines; quoted names with escapes.
            "name: t\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a],\n      [1, 0, 0, \"b\\tc\"], [2, 0, 0, 'd''e']]\n    lanes:\n      [[0, 1, {graph_idx: [2, 0]}],\n       [1, 2, {graph_idx: [2, 0],\n               bidirectional: [4, true]}]]\n    walls:\n    - [0,\t1]\n",
            // JSON, as a converter would write it.
            "{\"name\": \"t\", \"coordinate_system\": \"cartesian_meters\", \"levels\": {\"L1\": {\"vertices\": [[0, 0, 0, \"a\"], [3, 4, 0, \"b\"]], \"lanes\": [[0, 1, {\"graph_idx\": [2, 0]}]]}}}\n",
            // Pretty-printed JSON; then a list whose brackets are indented less than its
            // key, which is not a document of its own: read from the whole tree instead.
            "{\n  \"name\": \"t\",\n  \"coordinate_system\": \"cartesian_meters\",\n  \"levels\": {\n    \"L1\": {\n      \"vertices\": [\n        [0, 0, 0, \"a\"],\n        [3, 4, 0, \"b\"]\n      ],\n      \"lanes\": [\n[0, 1, {\"graph_idx\": [2, 0]}],\n[1, 0, {\"graph_idx\": [2, 0]}]\n]\n    }\n  }\n}\n",
            // An anchor: the general reader keeps every list.
            "name: t\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n    vertices:\n    - &v [0, 0, 0, a]\n    - *v\n    lanes:\n    - [0, 1, {graph_idx: [2, 0]}]\n",
            // `levels` not at the root, lists under other keys: never deferred.
            "name: t\ncoordinate_system: cartesian_meters\nx:\n  levels:\n    L:\n      vertices:\n        - [0, 0, 0, a]\nlevels:\n  L1:\n    vertices: null\n    lanes:\n      - [0, 0]\n",
        ] {
            same(text, text);
        }
    }
}
