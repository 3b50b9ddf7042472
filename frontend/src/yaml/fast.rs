//! A fast reader for the YAML subset that traffic_editor (and careful hand editing)
//! produces: block mappings and sequences indented with spaces, single-line flow
//! collections, plain and quoted single-line scalars, comments.
//!
//! Why: the general parser costs ~380 instructions per byte, which puts the largest demo
//! maps at 15-20 ms; this reader is an order of magnitude cheaper. It is not a second YAML
//! implementation: on anything outside the subset (anchors, tags, block scalars, tabs,
//! multi-line flow or plain scalars, documents markers, odd indentation, invalid input) it
//! returns `None` and the caller uses saphyr, which also produces every syntax error. A
//! differential test and a fuzz target check that whenever this reader accepts an input,
//! it builds exactly the tree (kinds, texts, spans) that the saphyr path builds.

use super::{max_nodes, Kind, Node, LIST_KEYS, MAX_DEPTH};
use mapc_ir::{FileId, Span};
use std::borrow::Cow;

/// Gives up: the input is outside the subset (not necessarily invalid).
struct Bail;

type R<T> = Result<T, Bail>;

struct P<'a> {
    s: &'a str,
    b: &'a [u8],
    pos: usize,
    line: u32,
    line_start: usize,
    file: FileId,
    nodes: usize,
    node_limit: usize,
    /// Indent of the line the cursor's content is on; `None` at end of input.
    indent: Option<usize>,
    /// Whether the current line is ASCII (so columns are byte offsets); computed once per
    /// line on first use.
    line_ascii: Option<bool>,
    /// Items of the collections being read, innermost last: each collection takes its
    /// items off the top into an allocation of exactly their number. Growing a `Vec` per
    /// collection and shrinking it left a hole per collection in the heap (a tree of a
    /// large map then took about twice its size in resident memory).
    seq_items: Vec<Node<'a>>,
    map_items: Vec<(Node<'a>, Node<'a>)>,
    /// Where the node being read sits among a map's lists (see [`Ctx`]); `None` when the
    /// caller wants the whole tree.
    ctx: Ctx,
    /// The level lists read but not kept, in document order.
    lists: Vec<List>,
}

/// The place of the node about to be read, as far as deferring level lists cares: the
/// root mapping, the `levels` mapping, a level, a list of a level, anything else.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Ctx {
    None,
    Root,
    Levels,
    Level,
    List,
}

/// A level list that was read (so the document is known to be in the subset, within the
/// node limit) but whose items were dropped: [`Items`] reads them again, one at a time,
/// when lowering asks for them. The tree holds an empty sequence with the list's span.
#[derive(Clone, Copy)]
pub(crate) struct List {
    /// Start of the list's span in the tree (the key that finds it).
    pub(crate) key: u32,
    /// Number of items.
    pub(crate) len: usize,
    /// The reader's state at the first `-`.
    pos: usize,
    line: u32,
    line_start: usize,
    indent: usize,
    depth: usize,
}

pub(super) fn parse(text: &str, file: FileId) -> Option<Node<'_>> {
    parse_lists(text, file, false).map(|(root, _)| root)
}

/// [`parse`]; with `defer`, the large lists of each level (vertices, lanes, walls, ...)
/// are read and checked but left out of the tree, and returned to be read again one item
/// at a time ([`Items`]): the whole tree of a large map is then never in memory.
pub(super) fn parse_lists(text: &str, file: FileId, defer: bool) -> Option<(Node<'_>, Vec<List>)> {
    if text.starts_with('\u{feff}') || has_unprintable(text.as_bytes()) {
        return None;
    }
    parse_from_start(text, file, defer)
}

/// The reader over the whole text.
fn parse_from_start(text: &str, file: FileId, defer: bool) -> Option<(Node<'_>, Vec<List>)> {
    let mut p = P::new(text, file, 0, 1, None, max_nodes(text.len()));
    let root = (|| {
        p.next_content()?;
        let indent = p.indent.ok_or(Bail)?;
        let c = p.b[p.pos];
        // Only collections at the root; anything else is left to saphyr.
        let root = if c == b'-' && p.is_sep(p.pos + 1) {
            p.block_seq(indent, 1)?
        } else if c == b'[' || c == b'{' {
            return Err(Bail);
        } else if p.line_has_key()? {
            if defer {
                p.ctx = Ctx::Root;
            }
            p.block_map(indent, 1)?
        } else {
            return Err(Bail);
        };
        if p.indent.is_some() {
            return Err(Bail); // content after the root collection
        }
        Ok(root)
    })();
    #[cfg(test)]
    if root.is_err() {
        eprintln!("fast reader declined at line {} byte {}", p.line, p.pos);
    }
    let lists = std::mem::take(&mut p.lists);
    root.ok().map(|r| (r, lists))
}

/// The items of a deferred level list, read again from the text one at a time. Reading
/// cannot fail: the same reader accepted the same text before (should it ever, the
/// iteration ends early).
pub(crate) struct Items<'a> {
    p: P<'a>,
    left: usize,
    indent: usize,
    depth: usize,
}

impl<'a> Items<'a> {
    pub(crate) fn new(text: &'a str, file: FileId, list: &List) -> Self {
        // Nodes were counted when the list was first read.
        let mut p = P::new(
            text,
            file,
            list.pos,
            list.line,
            Some(list.indent),
            usize::MAX,
        );
        p.line_start = list.line_start;
        Items {
            p,
            left: list.len,
            indent: list.indent,
            depth: list.depth,
        }
    }
}

impl<'a> Iterator for Items<'a> {
    type Item = Node<'a>;
    fn next(&mut self) -> Option<Node<'a>> {
        if self.left == 0 {
            return None;
        }
        self.left -= 1;
        match self.p.seq_item(self.indent, self.depth) {
            Ok((item, _)) => Some(item),
            Err(Bail) => {
                // Never seen: the caller then reads the whole tree (`yaml::Items`).
                self.left = 0;
                None
            }
        }
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        (0, Some(self.left))
    }
}

/// Characters YAML does not allow in a stream (controls other than tab, LF and CR; C1
/// controls other than NEL; U+FFFE and U+FFFF; a byte order mark inside the document),
/// which the general reader reports, and CR, which this reader leaves to it.
fn has_unprintable(b: &[u8]) -> bool {
    // Nearly all of a map is printable ASCII: a block without any byte that needs a closer
    // look is passed by a branch-free test, which the compiler vectorises.
    const BLOCK: usize = 64;
    let closer =
        |c: u8| (c < 0x20 && c != b'\t' && c != b'\n') | (c == 0x7f) | (c == 0xc2) | (c == 0xef);
    b.chunks(BLOCK).enumerate().any(|(k, block)| {
        block.iter().fold(false, |any, &c| any | closer(c))
            && unprintable_in(b, k * BLOCK..k * BLOCK + block.len())
    })
}

/// [`has_unprintable`] byte by byte, for the bytes at `range` (multi-byte sequences may
/// reach past its end).
fn unprintable_in(b: &[u8], range: std::ops::Range<usize>) -> bool {
    range.into_iter().any(|i| match b[i] {
        // A carriage return is a line break in YAML, even alone inside a comment; CRLF
        // files go to the general reader.
        b'\r' => true,
        b'\t' | b'\n' => false,
        0..=0x1f | 0x7f => true,
        // U+0080..U+009F are C2 80..C2 9F; U+0085 (NEL) is allowed.
        0xc2 => b
            .get(i + 1)
            .is_some_and(|&n| (0x80..=0x9f).contains(&n) && n != 0x85),
        // U+FFFE, U+FFFF are EF BF BE, EF BF BF; a byte order mark (EF BB BF) may only
        // start the stream, and even there we leave it to the general reader.
        0xef => {
            (b.get(i + 1) == Some(&0xbf) && matches!(b.get(i + 2), Some(0xbe | 0xbf)))
                || (b.get(i + 1) == Some(&0xbb) && b.get(i + 2) == Some(&0xbf))
        }
        _ => false,
    })
}

/// Bytes that can end or complicate a plain scalar.
static SPECIAL: [bool; 256] = {
    let mut t = [false; 256];
    let list = b"\n\t\r:#,[]{} ";
    let mut i = 0;
    while i < list.len() {
        t[list[i] as usize] = true;
        i += 1;
    }
    t
};

/// YAML limits implicit keys to 1024 characters; longer ones are left to saphyr, which
/// reports them.
fn check_key_length(k: &Node<'_>) -> R<()> {
    if k.span.end - k.span.start > 1024 {
        return Err(Bail);
    }
    Ok(())
}

fn is_flow_indicator(c: u8) -> bool {
    matches!(c, b',' | b'[' | b']' | b'{' | b'}')
}

impl<'a> P<'a> {
    /// A reader of `text` from `pos`, on line `line` (taken to start at `pos`: a caller
    /// starting inside a line sets `line_start`), whose content there is at `indent`.
    fn new(
        text: &'a str,
        file: FileId,
        pos: usize,
        line: u32,
        indent: Option<usize>,
        node_limit: usize,
    ) -> Self {
        P {
            s: text,
            b: text.as_bytes(),
            pos,
            line,
            line_start: pos,
            file,
            nodes: 0,
            node_limit,
            indent,
            line_ascii: None,
            seq_items: Vec::new(),
            map_items: Vec::new(),
            ctx: Ctx::None,
            lists: Vec::new(),
        }
    }

    fn span(&mut self, start: usize, end: usize) -> Span {
        // The start is always on the current line.
        let ascii = *self.line_ascii.get_or_insert_with(|| {
            let rest = &self.b[self.line_start..];
            let len = rest.iter().position(|&c| c == b'\n').unwrap_or(rest.len());
            rest[..len].is_ascii()
        });
        let col = if ascii {
            start - self.line_start
        } else {
            self.s[self.line_start..start].chars().count()
        };
        Span {
            file: self.file,
            start: start as u32,
            end: end as u32,
            line: self.line,
            col: col as u32 + 1,
        }
    }

    fn count(&mut self) -> R<()> {
        self.nodes += 1;
        if self.nodes > self.node_limit {
            return Err(Bail);
        }
        Ok(())
    }

    /// Is `i` end of input, a space or a newline (what may follow `-` or `:`)?
    fn is_sep(&self, i: usize) -> bool {
        matches!(self.b.get(i), None | Some(b' ') | Some(b'\n'))
    }

    /// From a line start: skips blank and comment-only lines, leaves the cursor on the
    /// first content byte and records its indent (or `None` at end of input).
    fn next_content(&mut self) -> R<()> {
        loop {
            let mut i = self.pos;
            while self.b.get(i) == Some(&b' ') {
                i += 1;
            }
            match self.b.get(i) {
                None => {
                    self.pos = i;
                    self.indent = None;
                    return Ok(());
                }
                Some(b'\n') => self.newline(i),
                Some(b'#') => {
                    let nl = self.b[i..].iter().position(|&c| c == b'\n');
                    match nl {
                        Some(n) => self.newline(i + n),
                        None => {
                            self.pos = self.b.len();
                            self.indent = None;
                            return Ok(());
                        }
                    }
                }
                Some(b'\t' | b'\r') => return Err(Bail),
                Some(_) => {
                    self.pos = i;
                    self.indent = Some(i - self.line_start);
                    return Ok(());
                }
            }
        }
    }

    /// Moves past the newline at `i`.
    fn newline(&mut self, i: usize) {
        self.pos = i + 1;
        self.line += 1;
        self.line_start = i + 1;
        self.line_ascii = None;
    }

    fn skip_spaces(&mut self) -> R<()> {
        while let Some(&c) = self.b.get(self.pos) {
            match c {
                b' ' => self.pos += 1,
                b'\t' | b'\r' => return Err(Bail),
                _ => break,
            }
        }
        Ok(())
    }

    /// After a value: only spaces and a comment may remain on the line; then moves to
    /// the next content line.
    fn finish_line(&mut self) -> R<()> {
        self.skip_spaces()?;
        match self.b.get(self.pos) {
            None => {
                self.indent = None;
                Ok(())
            }
            Some(b'\n') => {
                self.newline(self.pos);
                self.next_content()
            }
            Some(b'#') if self.pos > 0 && self.b[self.pos - 1] == b' ' => {
                match self.b[self.pos..].iter().position(|&c| c == b'\n') {
                    Some(n) => {
                        self.newline(self.pos + n);
                        self.next_content()
                    }
                    None => {
                        self.pos = self.b.len();
                        self.indent = None;
                        Ok(())
                    }
                }
            }
            _ => Err(Bail),
        }
    }

    fn at_comment_or_eol(&self) -> bool {
        match self.b.get(self.pos) {
            None | Some(b'\n') => true,
            Some(b'#') => self.pos > 0 && self.b[self.pos - 1] == b' ',
            _ => false,
        }
    }

    /// Does the current line hold `key:` (plain or quoted key) at the cursor?
    fn line_has_key(&self) -> R<bool> {
        let b = self.b;
        let mut i = self.pos;
        match b.get(i) {
            Some(b'"') | Some(b'\'') => {
                let q = b[i];
                i += 1;
                loop {
                    match b.get(i) {
                        None | Some(b'\n') => return Err(Bail),
                        Some(b'\\') if q == b'"' => i += 2,
                        Some(&c) if c == q => {
                            if q == b'\'' && b.get(i + 1) == Some(&b'\'') {
                                i += 2;
                            } else {
                                i += 1;
                                break;
                            }
                        }
                        _ => i += 1,
                    }
                }
                while b.get(i) == Some(&b' ') {
                    i += 1;
                }
                Ok(b.get(i) == Some(&b':') && self.is_sep(i + 1))
            }
            _ => {
                while let Some(&c) = b.get(i) {
                    match c {
                        b'\n' => return Ok(false),
                        b':' if self.is_sep(i + 1) => return Ok(true),
                        b'#' if i > 0 && b[i - 1] == b' ' => return Ok(false),
                        b'\t' | b'\r' => return Err(Bail),
                        _ => i += 1,
                    }
                }
                Ok(false)
            }
        }
    }

    /// A null value where nothing follows `key:`: zero width at the colon, where saphyr
    /// puts it too.
    fn null_at(&mut self, at: usize, key_span: Span) -> R<Node<'a>> {
        self.count()?;
        Ok(Node {
            kind: Kind::Scalar {
                text: Cow::Borrowed(""),
                plain: true,
            },
            span: Span {
                start: at as u32,
                end: at as u32,
                col: key_span.col + self.s[key_span.start as usize..at].chars().count() as u32,
                ..key_span
            },
        })
    }

    fn block_map(&mut self, indent: usize, depth: usize) -> R<Node<'a>> {
        if depth > MAX_DEPTH {
            return Err(Bail);
        }
        self.count()?;
        let start = self.span(self.pos, self.pos);
        let mark = self.map_items.len();
        let ctx = std::mem::replace(&mut self.ctx, Ctx::None);
        self.map_entries(indent, depth, ctx)?;
        let items: Vec<_> = self.map_items.drain(mark..).collect();
        let end = items
            .last()
            .map_or(start.start, |(_, v)| v.span.end.max(v.span.start));
        Ok(Node {
            kind: Kind::Map(items),
            span: Span { end, ..start },
        })
    }

    /// The entries of a block mapping at `indent` (its first key at the cursor), pushed on
    /// `map_items`, up to the first line indented less.
    fn map_entries(&mut self, indent: usize, depth: usize, ctx: Ctx) -> R<()> {
        loop {
            let key = self.key()?;
            // Only an entry's own value may see the context; whatever it holds resets it.
            self.ctx = match (ctx, key.key_text()) {
                (Ctx::Root, Some("levels")) => Ctx::Levels,
                (Ctx::Levels, _) => Ctx::Level,
                (Ctx::Level, Some(k)) if LIST_KEYS.contains(&k) => Ctx::List,
                _ => Ctx::None,
            };
            self.skip_spaces()?;
            // In block context the `:` of a key must be followed by a space or a line end,
            // after quoted keys too (`'k':v` is not a mapping entry).
            if self.b.get(self.pos) != Some(&b':') || !self.is_sep(self.pos + 1) {
                return Err(Bail);
            }
            let colon = self.pos;
            self.pos += 1;
            self.skip_spaces()?;
            let value = if self.at_comment_or_eol() {
                let key_span = key.span;
                self.finish_line()?;
                match self.indent {
                    Some(ind) if ind > indent => self.block_node(ind, depth + 1)?,
                    Some(ind)
                        if ind == indent
                            && self.b[self.pos] == b'-'
                            && self.is_sep(self.pos + 1) =>
                    {
                        // An indentless sequence (`key:` then `- item` at the key's indent).
                        // saphyr starts it at its first item; when that item is not on the
                        // dash's line the position is subtle, so leave those to saphyr.
                        let rest = &self.b[self.pos + 1..];
                        let first_on_line = rest
                            .iter()
                            .position(|&c| c != b' ')
                            .is_some_and(|i| !matches!(rest[i], b'\n' | b'#'));
                        if !first_on_line {
                            return Err(Bail);
                        }
                        let (mut seq, first) = self.block_seq_first(indent, depth + 1)?;
                        // saphyr starts such a sequence at its first item.
                        if let Some(first) = first {
                            if let Some(list) =
                                self.lists.last_mut().filter(|l| l.key == seq.span.start)
                            {
                                list.key = first.start;
                            }
                            seq.span = Span {
                                end: seq.span.end,
                                ..first
                            };
                        }
                        seq
                    }
                    _ => self.null_at(colon, key_span)?,
                }
            } else {
                let v = self.inline_value(depth + 1)?;
                self.finish_line()?;
                if self.indent.is_some_and(|i| i > indent) {
                    return Err(Bail); // continuation lines of a multi-line value
                }
                v
            };
            self.ctx = Ctx::None;
            self.map_items.push((key, value));
            match self.indent {
                Some(i) if i == indent => {
                    if self.b[self.pos] == b'-' && self.is_sep(self.pos + 1) {
                        return Err(Bail);
                    }
                }
                Some(i) if i > indent => return Err(Bail),
                _ => break,
            }
        }
        Ok(())
    }

    fn block_seq(&mut self, indent: usize, depth: usize) -> R<Node<'a>> {
        self.block_seq_first(indent, depth).map(|(n, _)| n)
    }

    /// A block sequence and the span of its first item. A level list (`Ctx::List`) is
    /// read whole but its items are dropped as soon as they are read: the node is an
    /// empty sequence with the list's span, and `lists` says where to read the items.
    fn block_seq_first(&mut self, indent: usize, depth: usize) -> R<(Node<'a>, Option<Span>)> {
        if depth > MAX_DEPTH {
            return Err(Bail);
        }
        let defer = std::mem::replace(&mut self.ctx, Ctx::None) == Ctx::List;
        self.count()?;
        let start = self.span(self.pos, self.pos);
        let mark = self.seq_items.len();
        let resume = List {
            key: start.start,
            len: 0,
            pos: self.pos,
            line: self.line,
            line_start: self.line_start,
            indent,
            depth,
        };
        let mut first = None;
        let mut last_end;
        let mut len = 0;
        loop {
            let (item, more) = self.seq_item(indent, depth)?;
            len += 1;
            first.get_or_insert(item.span);
            last_end = item.span.end.max(item.span.start);
            if !defer {
                self.seq_items.push(item);
            }
            if !more {
                break;
            }
        }
        let items: Vec<_> = self.seq_items.drain(mark..).collect();
        if defer {
            self.lists.push(List { len, ..resume });
        }
        Ok((
            Node {
                kind: Kind::Seq(items),
                span: Span {
                    end: last_end,
                    ..start
                },
            },
            first,
        ))
    }

    /// One item of a block sequence, from its `-`; and whether another item follows.
    fn seq_item(&mut self, indent: usize, depth: usize) -> R<(Node<'a>, bool)> {
        // At `-`.
        self.pos += 1;
        self.skip_spaces()?;
        let item = if self.at_comment_or_eol() {
            self.finish_line()?;
            match self.indent {
                Some(ind) if ind > indent => self.block_node(ind, depth + 1)?,
                _ => return Err(Bail), // an empty item
            }
        } else if self.b[self.pos] == b'-' && self.is_sep(self.pos + 1) {
            return Err(Bail); // `- - x`
        } else if !matches!(self.b[self.pos], b'[' | b'{') && self.line_has_key()? {
            let col = self.pos - self.line_start;
            self.block_map(col, depth + 1)?
        } else {
            let v = self.inline_value(depth + 1)?;
            self.finish_line()?;
            if self.indent.is_some_and(|i| i > indent) {
                return Err(Bail);
            }
            v
        };
        let more = match self.indent {
            // Another item, or the next key of a parent mapping at the same indent.
            Some(i) if i == indent => self.b[self.pos] == b'-' && self.is_sep(self.pos + 1),
            Some(i) if i > indent => return Err(Bail),
            _ => false,
        };
        Ok((item, more))
    }

    /// A node that starts on its own line at `indent`.
    fn block_node(&mut self, indent: usize, depth: usize) -> R<Node<'a>> {
        let c = self.b[self.pos];
        if c == b'-' && self.is_sep(self.pos + 1) {
            self.block_seq(indent, depth)
        } else if self.line_has_key()? {
            self.block_map(indent, depth)
        } else {
            // A flow collection or scalar alone on its line (the editor writes `layers:`
            // then `{}` on the next line). Continuation lines are caught by the caller,
            // which declines anything indented deeper than its own entries after this.
            let v = self.inline_value(depth)?;
            self.finish_line()?;
            Ok(v)
        }
    }

    fn key(&mut self) -> R<Node<'a>> {
        let k = match self.b.get(self.pos) {
            Some(b'"') => self.double_quoted(),
            Some(b'\'') => self.single_quoted(),
            _ => self.plain(false),
        }?;
        check_key_length(&k)?;
        Ok(k)
    }

    fn inline_value(&mut self, depth: usize) -> R<Node<'a>> {
        match self.b.get(self.pos) {
            Some(b'[' | b'{') => self.flow(depth),
            Some(b'"') => self.double_quoted(),
            Some(b'\'') => self.single_quoted(),
            _ => self.plain(false),
        }
    }

    /// A plain scalar; `in_flow` ends it at flow indicators too.
    fn plain(&mut self, in_flow: bool) -> R<Node<'a>> {
        let b = self.b;
        let start = self.pos;
        match b.get(start) {
            None => return Err(Bail),
            Some(&c) => {
                if matches!(
                    c,
                    b'&' | b'*' | b'!' | b'|' | b'>' | b'%' | b'@' | b'`' | b'#' | b'\'' | b'"'
                ) || is_flow_indicator(c)
                {
                    return Err(Bail);
                }
                if matches!(c, b'-' | b'?' | b':') && self.is_sep(start + 1) {
                    return Err(Bail);
                }
                if matches!(c, b'-' | b'?' | b':')
                    && in_flow
                    && b.get(start + 1).is_some_and(|&n| is_flow_indicator(n))
                {
                    return Err(Bail);
                }
            }
        }
        let mut i = start;
        let mut end = start;
        while let Some(&c) = b.get(i) {
            if !SPECIAL[c as usize] {
                // Most bytes of a scalar are ordinary: no further checks.
                i += 1;
                end = i;
                continue;
            }
            match c {
                b'\n' => break,
                b'\t' | b'\r' => return Err(Bail),
                b':' if self.is_sep(i + 1)
                    || (in_flow && b.get(i + 1).is_some_and(|&n| is_flow_indicator(n))) =>
                {
                    break
                }
                b'#' if b[i - 1] == b' ' => break,
                c if in_flow && is_flow_indicator(c) => break,
                // In flow context saphyr rejects `-`, `?` or `:` after a space when a flow
                // indicator follows; leave such rare text to it.
                b' ' if in_flow
                    && matches!(b.get(i + 1), Some(b'-' | b'?' | b':'))
                    && b.get(i + 2)
                        .is_none_or(|&n| is_flow_indicator(n) || n == b' ') =>
                {
                    return Err(Bail)
                }
                b' ' => {}
                _ => end = i + 1,
            }
            i += 1;
        }
        if end == start {
            return Err(Bail);
        }
        self.pos = end;
        self.count()?;
        Ok(Node {
            kind: Kind::Scalar {
                text: Cow::Borrowed(&self.s[start..end]),
                plain: true,
            },
            span: self.span(start, end),
        })
    }

    fn single_quoted(&mut self) -> R<Node<'a>> {
        let b = self.b;
        let start = self.pos;
        let mut i = start + 1;
        let mut owned: Option<String> = None;
        let mut run = i;
        loop {
            match b.get(i) {
                None | Some(b'\n') | Some(b'\r') => return Err(Bail),
                Some(b'\'') => {
                    if b.get(i + 1) == Some(&b'\'') {
                        let t = owned.get_or_insert_with(String::new);
                        t.push_str(&self.s[run..i]);
                        t.push('\'');
                        i += 2;
                        run = i;
                    } else {
                        i += 1;
                        break;
                    }
                }
                _ => i += 1,
            }
        }
        let text = match owned {
            None => Cow::Borrowed(&self.s[start + 1..i - 1]),
            Some(mut t) => {
                t.push_str(&self.s[run..i - 1]);
                Cow::Owned(t)
            }
        };
        self.pos = i;
        self.count()?;
        Ok(Node {
            kind: Kind::Scalar { text, plain: false },
            span: self.span(start, i),
        })
    }

    fn double_quoted(&mut self) -> R<Node<'a>> {
        let b = self.b;
        let start = self.pos;
        let mut i = start + 1;
        let mut owned: Option<String> = None;
        let mut run = i;
        loop {
            match b.get(i) {
                None | Some(b'\n') | Some(b'\r') | Some(b'\t') => return Err(Bail),
                Some(b'"') => {
                    i += 1;
                    break;
                }
                Some(b'\\') => {
                    let text = owned.get_or_insert_with(String::new);
                    text.push_str(&self.s[run..i]);
                    let (c, len) = match b.get(i + 1) {
                        Some(b'\\') => ('\\', 2),
                        Some(b'"') => ('"', 2),
                        Some(b'/') => ('/', 2),
                        Some(b'n') => ('\n', 2),
                        Some(b't') => ('\t', 2),
                        Some(b'r') => ('\r', 2),
                        Some(b'0') => ('\0', 2),
                        Some(b'u') => {
                            let hex = self.s.get(i + 2..i + 6).ok_or(Bail)?;
                            let v = u32::from_str_radix(hex, 16).map_err(|_| Bail)?;
                            (char::from_u32(v).ok_or(Bail)?, 6)
                        }
                        _ => return Err(Bail),
                    };
                    text.push(c);
                    i += len;
                    run = i;
                }
                _ => i += 1,
            }
        }
        let text = match owned {
            None => Cow::Borrowed(&self.s[start + 1..i - 1]),
            Some(mut t) => {
                t.push_str(&self.s[run..i - 1]);
                Cow::Owned(t)
            }
        };
        self.pos = i;
        self.count()?;
        Ok(Node {
            kind: Kind::Scalar { text, plain: false },
            span: self.span(start, i),
        })
    }

    fn flow_skip(&mut self) -> R<()> {
        while let Some(&c) = self.b.get(self.pos) {
            match c {
                b' ' => self.pos += 1,
                b'\n' | b'\t' | b'\r' | b'#' => return Err(Bail),
                _ => break,
            }
        }
        Ok(())
    }

    fn flow_item(&mut self, depth: usize) -> R<Node<'a>> {
        match self.b.get(self.pos) {
            Some(b'[' | b'{') => self.flow(depth),
            Some(b'"') => self.double_quoted(),
            Some(b'\'') => self.single_quoted(),
            _ => self.plain(true),
        }
    }

    fn flow(&mut self, depth: usize) -> R<Node<'a>> {
        if depth > MAX_DEPTH {
            return Err(Bail);
        }
        self.count()?;
        let start = self.pos;
        let open = self.b[start];
        self.pos += 1;
        let kind = if open == b'[' {
            let mark = self.seq_items.len();
            loop {
                self.flow_skip()?;
                if self.b.get(self.pos) == Some(&b']') {
                    break;
                }
                let item = self.flow_item(depth + 1)?;
                self.seq_items.push(item);
                self.flow_skip()?;
                match self.b.get(self.pos) {
                    Some(b',') => self.pos += 1,
                    Some(b']') => break,
                    _ => return Err(Bail),
                }
            }
            Kind::Seq(self.seq_items.drain(mark..).collect())
        } else {
            let mark = self.map_items.len();
            loop {
                self.flow_skip()?;
                if self.b.get(self.pos) == Some(&b'}') {
                    break;
                }
                let key = match self.b.get(self.pos) {
                    Some(b'[' | b'{') => return Err(Bail),
                    _ => self.flow_item(depth + 1)?,
                };
                check_key_length(&key)?;
                self.flow_skip()?;
                // `key:` must be followed by a space here (YAML forbids `a:[` in flow maps).
                if self.b.get(self.pos) != Some(&b':') || self.b.get(self.pos + 1) != Some(&b' ') {
                    return Err(Bail);
                }
                self.pos += 1;
                self.flow_skip()?;
                if matches!(self.b.get(self.pos), Some(b',' | b'}')) {
                    return Err(Bail); // null value
                }
                let value = self.flow_item(depth + 1)?;
                self.map_items.push((key, value));
                self.flow_skip()?;
                match self.b.get(self.pos) {
                    Some(b',') => self.pos += 1,
                    Some(b'}') => break,
                    _ => return Err(Bail),
                }
            }
            Kind::Map(self.map_items.drain(mark..).collect())
        };
        self.pos += 1; // the closing bracket
        Ok(Node {
            kind,
            span: self.span(start, self.pos),
        })
    }
}

#[cfg(test)]
mod unprintable_tests {
    use super::*;

    /// The block test passes nothing that the byte-by-byte one finds, wherever it is
    /// (inside a block, on either side of a block's edge, split across two blocks).
    #[test]
    fn blocks_find_what_bytes_find() {
        let bad: [&[u8]; 7] = [
            b"\r",
            b"\x01",
            b"\x1f",
            b"\x7f",
            b"\xc2\x80",
            b"\xef\xbf\xbe",
            b"\xef\xbb\xbf",
        ];
        let good: [&[u8]; 5] = [b"\t", b"\n", b"\xc2\x85", b"\xc2\xa0", b"\xef\xbc\x81"];
        for (seqs, want) in [(&bad[..], true), (&good[..], false)] {
            for seq in seqs {
                for at in [0, 1, 62, 63, 64, 65, 126, 127, 128, 190] {
                    let mut text = vec![b'a'; 200];
                    text.splice(at..at + seq.len(), seq.iter().copied());
                    assert_eq!(has_unprintable(&text), want, "{seq:?} at {at}");
                    assert_eq!(unprintable_in(&text, 0..text.len()), want);
                }
            }
        }
        assert!(!has_unprintable(b""));
        // A sequence cut by the end of the text.
        assert!(!has_unprintable(b"ab\xef\xbf"));
    }
}
