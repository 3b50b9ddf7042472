//! Open documents: their text, version, kind, and the conversion between byte offsets
//! (what spans hold) and LSP positions (lines and UTF-16 code units, the protocol's
//! default encoding).

use lsp_types::{Position, Range, TextDocumentContentChangeEvent};
use std::path::PathBuf;

/// What a file is, from its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Building,
    /// An rmf_site `.site.json`.
    Site,
    Project,
    Scenario,
}

impl Kind {
    pub(crate) fn of(name: &str) -> Option<Kind> {
        if name.ends_with(".building.yaml") {
            Some(Kind::Building)
        } else if mapc_frontend::site::is_site_file(name) {
            Some(Kind::Site)
        } else if name.ends_with(".project.yaml") {
            Some(Kind::Project)
        } else if name.ends_with(".scenario.yaml") {
            Some(Kind::Scenario)
        } else {
            None
        }
    }
}

/// Byte offsets of line starts, for offset <-> position conversion.
#[derive(Debug, Clone, Default)]
pub(crate) struct LineIndex {
    starts: Vec<u32>,
}

impl LineIndex {
    pub(crate) fn new(text: &str) -> LineIndex {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i as u32 + 1),
        );
        LineIndex { starts }
    }

    /// The position of byte `offset` (clamped to the text, and back to a char boundary).
    pub(crate) fn position(&self, text: &str, offset: u32) -> Position {
        let mut offset = (offset as usize).min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.starts.partition_point(|&s| s as usize <= offset) - 1;
        let start = self.starts[line] as usize;
        let character = text[start..offset].encode_utf16().count() as u32;
        Position::new(line as u32, character)
    }

    pub(crate) fn range(&self, text: &str, start: u32, end: u32) -> Range {
        Range::new(self.position(text, start), self.position(text, end))
    }

    /// The byte offset of `pos`; positions past a line's end mean its end, past the last
    /// line the end of the text (as the protocol asks).
    pub(crate) fn offset(&self, text: &str, pos: Position) -> usize {
        let Some(&start) = self.starts.get(pos.line as usize) else {
            return text.len();
        };
        let start = start as usize;
        let end = self
            .starts
            .get(pos.line as usize + 1)
            .map_or(text.len(), |&e| e as usize);
        let line = &text[start..end];
        let line = line.strip_suffix('\n').unwrap_or(line);
        let line = line.strip_suffix('\r').unwrap_or(line);
        let mut units = 0u32;
        for (i, c) in line.char_indices() {
            if units >= pos.character {
                return start + i;
            }
            units += c.len_utf16() as u32;
        }
        start + line.len()
    }
}

/// One open document.
pub(crate) struct Document {
    pub(crate) uri: String,
    pub(crate) path: Option<PathBuf>,
    pub(crate) kind: Kind,
    pub(crate) version: i32,
    pub(crate) text: String,
    pub(crate) lines: LineIndex,
}

impl Document {
    pub(crate) fn new(uri: String, kind: Kind, version: i32, text: String) -> Document {
        Document {
            path: file_path(&uri),
            uri,
            kind,
            version,
            lines: LineIndex::new(&text),
            text,
        }
    }

    /// Applies `didChange` events in order: a full replacement, or a range edit whose
    /// positions refer to the text after the previous event.
    pub(crate) fn apply(&mut self, version: i32, changes: Vec<TextDocumentContentChangeEvent>) {
        for change in changes {
            match change.range {
                None => self.text = change.text,
                Some(r) => {
                    let start = self.lines.offset(&self.text, r.start);
                    let end = self.lines.offset(&self.text, r.end).max(start);
                    self.text.replace_range(start..end, &change.text);
                }
            }
            self.lines = LineIndex::new(&self.text);
        }
        self.version = version;
    }

    pub(crate) fn range(&self, span: mapc_ir::Span) -> Range {
        self.lines.range(&self.text, span.start, span.end)
    }

    pub(crate) fn offset(&self, pos: Position) -> u32 {
        self.lines.offset(&self.text, pos) as u32
    }
}

/// The local path of a `file:` URI (percent-decoded), if it is one.
pub(crate) fn file_path(uri: &str) -> Option<PathBuf> {
    let rest = uri.strip_prefix("file://")?;
    // `file:///p` (empty authority) or `file://localhost/p`.
    let path = rest.strip_prefix("localhost").unwrap_or(rest);
    if !path.starts_with('/') {
        return None;
    }
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStringExt;
        Some(PathBuf::from(std::ffi::OsString::from_vec(out)))
    }
    #[cfg(not(unix))]
    {
        String::from_utf8(out).ok().map(PathBuf::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_columns_round_trip() {
        // `é` is 2 bytes and 1 UTF-16 unit; `😀` is 4 bytes and 2 units.
        let text = "a: é😀x\nb: 1\n";
        let idx = LineIndex::new(text);
        let x = text.find('x').unwrap() as u32;
        assert_eq!(idx.position(text, x), Position::new(0, 6));
        assert_eq!(idx.offset(text, Position::new(0, 6)), x as usize);
        assert_eq!(
            idx.position(text, text.find('b').unwrap() as u32),
            Position::new(1, 0)
        );
        // Past the end of a line: the line's end; past the last line: the text's end.
        assert_eq!(idx.offset(text, Position::new(0, 99)), x as usize + 1);
        assert_eq!(idx.offset(text, Position::new(9, 0)), text.len());
    }

    #[test]
    fn incremental_edits_apply_in_order() {
        let mut d = Document::new(
            "file:///m.building.yaml".into(),
            Kind::Building,
            1,
            "ab\ncd\n".into(),
        );
        let edit = |l1, c1, l2, c2, t: &str| TextDocumentContentChangeEvent {
            range: Some(Range::new(Position::new(l1, c1), Position::new(l2, c2))),
            range_length: None,
            text: t.into(),
        };
        d.apply(2, vec![edit(0, 1, 1, 1, "X"), edit(0, 0, 0, 0, "é")]);
        assert_eq!(d.text, "éaXd\n");
        assert_eq!(d.version, 2);
    }

    #[test]
    fn file_uris_decode() {
        assert_eq!(
            file_path("file:///tmp/a%20b.yaml"),
            Some(PathBuf::from("/tmp/a b.yaml"))
        );
        assert_eq!(file_path("untitled:1"), None);
    }
}
