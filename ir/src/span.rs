//! Source locations.

/// Identifies a source file in a [`crate::SourceMap`]-like table kept by the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct FileId(pub u32);

/// A region of a source file: byte range for snippet rendering plus the 1-based line and
/// column (in characters) of its start, ready to print as `file:line:col`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Span {
    pub file: FileId,
    pub start: u32,
    pub end: u32,
    pub line: u32,
    pub col: u32,
}

impl Span {
    /// A span that points nowhere (for synthesised elements); line 0 marks it.
    pub const UNKNOWN: Span = Span {
        file: FileId(0),
        start: 0,
        end: 0,
        line: 0,
        col: 0,
    };
    pub fn is_known(&self) -> bool {
        self.line > 0
    }
}
