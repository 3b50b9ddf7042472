//! The general reader: any YAML 1.2 document, through saphyr-parser's events. Span
//! conventions, shared with `fast`: scalars cover their text (quotes included), flow
//! collections run through their closing bracket, block collections end where their last
//! child ends.
//!
//! Like the fast reader, it can leave a map's level lists out of the tree
//! ([`super::Lists`]): such a list is read and checked whole, its items dropped as they
//! complete, and [`Items`] reads them again one at a time, by running the parser over the
//! list's own text (a list is a YAML document of its own once cut at its line start, or at
//! its bracket for a flow list after its key) with positions moved back to the file's.

use super::{max_nodes, Kind, Node, LIST_KEYS, MAX_ALIAS_NODES, MAX_DEPTH};
use mapc_ir::{Diagnostic, FileId, Span};
use saphyr_parser::{Event, Parser, ScalarStyle, StrInput};
use std::borrow::Cow;
use std::collections::HashMap;

/// Maps saphyr's character positions in the text it reads to byte offsets, lines and
/// columns of the file, which that text starts at byte `base` of, a line start (line
/// `line_base` + 1).
struct Positions<'a> {
    text: &'a str,
    line_starts: Vec<usize>,
    /// Whether each line is pure ASCII (then char column == byte column).
    line_ascii: Vec<bool>,
    base: usize,
    line_base: usize,
}

impl<'a> Positions<'a> {
    fn new(text: &'a str, base: usize, line_base: usize) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        let line_ascii = line_starts
            .iter()
            .enumerate()
            .map(|(i, &s)| {
                let e = line_starts.get(i + 1).copied().unwrap_or(text.len());
                text.as_bytes()[s..e].is_ascii()
            })
            .collect();
        Positions {
            text,
            line_starts,
            line_ascii,
            base,
            line_base,
        }
    }
    /// Byte offset in the file of (1-based line, 0-based char column) of the text read.
    fn byte(&self, line: usize, col: usize) -> usize {
        let i = line.saturating_sub(1);
        let Some(&start) = self.line_starts.get(i) else {
            return self.base + self.text.len();
        };
        if self.line_ascii[i] {
            return self.base + (start + col).min(self.text.len());
        }
        let rest = &self.text[start..];
        self.base + start + rest.char_indices().nth(col).map_or(rest.len(), |(i, _)| i)
    }
    /// 1-based line and column in the file of (1-based line, 0-based char column).
    fn line_col(&self, line: usize, col: usize) -> (u32, u32) {
        ((line + self.line_base) as u32, col as u32 + 1)
    }
    fn span(&self, file: FileId, s: saphyr_parser::Span) -> Span {
        let start = self.byte(s.start.line(), s.start.col());
        let end = self.byte(s.end.line(), s.end.col()).max(start);
        let (line, col) = self.line_col(s.start.line(), s.start.col());
        Span {
            file,
            start: start as u32,
            end: end as u32,
            line,
            col,
        }
    }
}

/// An open collection: its items, start span, anchor id and size in nodes so far.
enum Frame<'a> {
    Seq(Vec<Node<'a>>, Span, usize, usize),
    Map(
        Vec<(Node<'a>, Node<'a>)>,
        Option<Node<'a>>,
        Span,
        usize,
        usize,
    ),
}

/// A level list whose items were dropped: where its text is, to read it again.
#[derive(Clone, Copy)]
pub(crate) struct List {
    /// Start of the list's span in the tree (the key that finds it).
    pub(crate) key: u32,
    /// Number of items.
    pub(crate) len: usize,
    /// The list's text as a document of its own: `start..end` of the file, from the start
    /// of its key's line (line `line_base` + 1); the list's items are those of the
    /// sequence open at stack height `height` there (2: the value of the key).
    start: usize,
    end: usize,
    line_base: usize,
    height: usize,
}

/// The level list being read whose items are dropped: stack height of its frame, and the
/// spans of its first and last items (for the list's own span).
struct Dropping {
    height: usize,
    first: Option<Span>,
    last: Option<Span>,
    list: List,
}

/// The reader's state between events.
struct General<'a> {
    /// The whole file: spans index it.
    source: &'a str,
    file: FileId,
    pos: Positions<'a>,
    stack: Vec<Frame<'a>>,
    anchors: HashMap<usize, (Node<'a>, usize)>,
    total_nodes: usize,
    node_limit: usize,
    alias_nodes: usize,
    documents: usize,
    /// Leave level lists out of the tree.
    defer: bool,
    dropping: Option<Dropping>,
    lists: Vec<List>,
    /// Reading a list again: the items of the sequence open at this stack height are
    /// handed out, not kept.
    items: Option<usize>,
}

/// What an event completed.
enum Step<'a> {
    None,
    /// An item of the list, when reading a list again.
    Item(Node<'a>),
}

impl<'a> General<'a> {
    fn error_at(&self, line: usize, col: usize, message: String) -> Diagnostic {
        let start = self.pos.byte(line, col) as u32;
        let (line, col) = self.pos.line_col(line, col);
        let span = Span {
            file: self.file,
            start,
            end: start,
            line,
            col,
        };
        Diagnostic::error("E0001", span, message).with_help("fix the YAML syntax at this position")
    }

    /// If the sequence starting now at `start` is a level list to leave out of the tree,
    /// where its text is as a document of its own (see [`List`]).
    fn level_list(&self, start: Span) -> Option<List> {
        fn pending<'f, 'a>(f: &'f Frame<'a>) -> Option<&'f Node<'a>> {
            match f {
                Frame::Map(_, Some(k), ..) => Some(k),
                _ => None,
            }
        }
        let is_list = self.defer
            && self.dropping.is_none()
            && self.stack.len() == 3
            && pending(&self.stack[0]).and_then(|k| k.key_text()) == Some("levels")
            && pending(&self.stack[1]).is_some();
        if !is_list {
            return None;
        }
        let key = pending(&self.stack[2])?;
        if !key.key_text().is_some_and(|k| LIST_KEYS.contains(&k)) {
            return None;
        }
        // The list's text, from the start of its key's line: a document of its own where
        // the list is the value of its key, as in the file. (Cut at the list itself, a flow
        // list would be a possible key of a mapping, which the parser can only tell at its
        // end: it would hold the whole list's tokens.)
        let at = key.span.start as usize;
        let from = self.source[..at].rfind('\n').map_or(0, |i| i + 1);
        if !self.source.as_bytes()[from..at].iter().all(|&c| c == b' ') {
            return None; // a key inside a flow mapping
        }
        let (line, height) = (key.span.line, 2);
        Some(List {
            key: start.start,
            len: 0,
            start: from,
            end: 0,
            line_base: line as usize - 1,
            height,
        })
    }

    fn event(
        &mut self,
        event: Event<'a>,
        sp: saphyr_parser::Span,
        root: &mut Option<Node<'a>>,
    ) -> Result<Step<'a>, Diagnostic> {
        let file = self.file;
        let span = self.pos.span(file, sp);
        // (node, anchor id, size) completed by this event, if any.
        let done: Option<(Node<'a>, usize, usize)> = match event {
            Event::StreamStart | Event::StreamEnd | Event::Nothing | Event::DocumentEnd => None,
            Event::DocumentStart(_) => {
                self.documents += 1;
                if self.documents > 1 {
                    return Err(Diagnostic::error(
                        "E0001",
                        span,
                        "more than one YAML document in the file",
                    )
                    .with_help(
                        "a .building.yaml holds exactly one document; remove the extra `---`",
                    ));
                }
                None
            }
            Event::Alias(id) => match self.anchors.get(&id) {
                Some((node, size)) => {
                    self.total_nodes += size;
                    self.alias_nodes += size;
                    if self.alias_nodes > MAX_ALIAS_NODES {
                        return Err(limit_error(span, "alias expansion", MAX_ALIAS_NODES));
                    }
                    let mut n = node.clone();
                    n.span = span;
                    Some((n, 0, *size))
                }
                None => {
                    return Err(Diagnostic::error(
                        "E0001",
                        span,
                        "alias to an unknown anchor",
                    ))
                }
            },
            Event::Scalar(text, style, anchor, tag) => {
                self.total_nodes += 1;
                let is_str_tag = tag.as_ref().is_some_and(|t| t.suffix == "str");
                let plain = style == ScalarStyle::Plain && !is_str_tag;
                let mut span = span;
                if matches!(style, ScalarStyle::SingleQuoted | ScalarStyle::DoubleQuoted) {
                    // saphyr's end runs past trailing blanks and comments; stop at the quote.
                    span.end = quoted_end(self.source, span.start as usize) as u32;
                }
                Some((
                    Node {
                        kind: Kind::Scalar { text, plain },
                        span,
                    },
                    anchor,
                    1,
                ))
            }
            Event::SequenceStart(anchor, _) => {
                if self.stack.len() >= MAX_DEPTH {
                    return Err(limit_error(span, "nesting depth", MAX_DEPTH));
                }
                if let Some(list) = self.level_list(span) {
                    self.dropping = Some(Dropping {
                        height: self.stack.len() + 1,
                        first: None,
                        last: None,
                        list,
                    });
                }
                self.stack.push(Frame::Seq(Vec::new(), span, anchor, 1));
                self.total_nodes += 1;
                None
            }
            Event::MappingStart(anchor, _) => {
                if self.stack.len() >= MAX_DEPTH {
                    return Err(limit_error(span, "nesting depth", MAX_DEPTH));
                }
                self.stack
                    .push(Frame::Map(Vec::new(), None, span, anchor, 1));
                self.total_nodes += 1;
                None
            }
            Event::SequenceEnd => {
                let height = self.stack.len();
                let dropped = self.dropping.take_if(|d| d.height == height);
                match self.stack.pop() {
                    Some(Frame::Seq(items, start, anchor, size)) => {
                        let (first, last) = match &dropped {
                            Some(d) => (d.first, d.last),
                            None => (items.first().map(|n| n.span), items.last().map(|n| n.span)),
                        };
                        let node = Node {
                            span: join(self.source, start, span, first, last),
                            kind: Kind::Seq(items),
                        };
                        if let Some(d) = dropped {
                            self.lists.push(List {
                                key: node.span.start,
                                end: node.span.end as usize,
                                ..d.list
                            });
                        }
                        Some((node, anchor, size))
                    }
                    _ => return Err(Diagnostic::error("E0001", span, "unbalanced sequence end")),
                }
            }
            Event::MappingEnd => match self.stack.pop() {
                Some(Frame::Map(items, _, start, anchor, size)) => Some((
                    Node {
                        span: join(
                            self.source,
                            start,
                            span,
                            items.first().map(|(k, _)| k.span),
                            items.last().map(|(_, v)| v.span),
                        ),
                        kind: Kind::Map(items),
                    },
                    anchor,
                    size,
                )),
                _ => return Err(Diagnostic::error("E0001", span, "unbalanced mapping end")),
            },
        };
        if self.total_nodes > self.node_limit {
            return Err(limit_error(span, "node count", self.node_limit));
        }
        let Some((node, anchor, size)) = done else {
            return Ok(Step::None);
        };
        if anchor > 0 {
            self.anchors.insert(anchor, (node.clone(), size));
        }
        if self.items == Some(self.stack.len()) {
            if let Some(Frame::Seq(_, _, _, total)) = self.stack.last_mut() {
                *total += size;
                return Ok(Step::Item(node));
            }
        }
        let height = self.stack.len();
        match self.stack.last_mut() {
            None => *root = Some(node),
            Some(Frame::Seq(items, _, _, total)) => {
                *total += size;
                match &mut self.dropping {
                    // An item of a level list: counted, then dropped.
                    Some(d) if d.height == height => {
                        d.first.get_or_insert(node.span);
                        d.last = Some(node.span);
                        d.list.len += 1;
                    }
                    _ => items.push(node),
                }
            }
            Some(Frame::Map(items, pending, _, _, total)) => {
                *total += size;
                match pending.take() {
                    None => *pending = Some(node),
                    Some(key) => items.push((key, node)),
                }
            }
        }
        Ok(Step::None)
    }
}

/// Reads a document. With `defer`, level lists are left out of the tree and returned.
pub(super) fn parse_lists(
    text: &str,
    file: FileId,
    defer: bool,
) -> Result<(Node<'_>, Vec<List>), Diagnostic> {
    // A list read on its own would not see anchors, aliases or tag directives of the rest
    // of the document: such documents are kept whole (aliases are bounded anyway).
    let defer = defer
        && !text.bytes().any(|c| c == b'&' || c == b'*')
        && !text.starts_with('%')
        && !text.contains("\n%");
    let mut g = General {
        source: text,
        file,
        pos: Positions::new(text, 0, 0),
        stack: Vec::new(),
        anchors: HashMap::new(),
        total_nodes: 0,
        node_limit: max_nodes(text.len()),
        alias_nodes: 0,
        documents: 0,
        defer,
        dropping: None,
        lists: Vec::new(),
        items: None,
    };
    let mut root = None;
    for item in Parser::new_from_str(text) {
        let (event, sp) = match item {
            Ok(x) => x,
            Err(e) => {
                let m = e.marker();
                return Err(g.error_at(m.line(), m.col(), format!("invalid YAML: {}", e.info())));
            }
        };
        g.event(event, sp, &mut root)?;
    }
    let root = root.unwrap_or(Node {
        kind: Kind::Scalar {
            text: Cow::Borrowed(""),
            plain: true,
        },
        span: Span {
            file,
            start: 0,
            end: 0,
            line: 1,
            col: 1,
        },
    });
    Ok((root, g.lists))
}

/// The items of a level list that [`parse_lists`] left out, read again one at a time.
/// Reading cannot fail (the same parser accepted the same text before); should it ever,
/// the iteration ends early.
pub(crate) struct Items<'a> {
    parser: Parser<'a, StrInput<'a>>,
    g: General<'a>,
    left: usize,
}

impl<'a> Items<'a> {
    pub(crate) fn new(text: &'a str, file: FileId, list: &List) -> Self {
        let own = &text[list.start..list.end];
        Items {
            parser: Parser::new_from_str(own),
            g: General {
                source: text,
                file,
                pos: Positions::new(own, list.start, list.line_base),
                stack: Vec::new(),
                anchors: HashMap::new(),
                total_nodes: 0,
                // Counted when the list was first read.
                node_limit: usize::MAX,
                alias_nodes: 0,
                documents: 0,
                defer: false,
                dropping: None,
                lists: Vec::new(),
                items: Some(list.height),
            },
            left: list.len,
        }
    }
}

impl<'a> Iterator for Items<'a> {
    type Item = Node<'a>;
    fn next(&mut self) -> Option<Node<'a>> {
        if self.left == 0 {
            return None;
        }
        let mut root = None;
        for item in self.parser.by_ref() {
            let step = item
                .map_err(|_| ())
                .and_then(|(event, sp)| self.g.event(event, sp, &mut root).map_err(|_| ()));
            match step {
                Ok(Step::Item(node)) => {
                    self.left -= 1;
                    return Some(node);
                }
                Ok(Step::None) => {}
                Err(()) => break,
            }
        }
        // Never seen: the caller then reads the whole tree (`yaml::Items`).
        self.left = 0;
        None
    }
}

/// Byte just past the closing quote of the quoted scalar starting at `start`.
fn quoted_end(text: &str, start: usize) -> usize {
    let b = text.as_bytes();
    let Some(&q) = b.get(start) else {
        return start;
    };
    if q != b'"' && q != b'\'' {
        return start;
    }
    let mut i = start + 1;
    while i < b.len() {
        match b[i] {
            b'\\' if q == b'"' => i += 2,
            c if c == q => {
                if q == b'\'' && b.get(i + 1) == Some(&b'\'') {
                    i += 2;
                } else {
                    return i + 1;
                }
            }
            _ => i += 1,
        }
    }
    b.len()
}

/// Span of a collection: a flow collection runs through its closing bracket, a block
/// collection ends where its last child ends.
fn join(
    text: &str,
    a: Span,
    end_event: Span,
    first_child: Option<Span>,
    last_child: Option<Span>,
) -> Span {
    let bytes = text.as_bytes();
    // saphyr starts an indentless block sequence at its first item, which may itself be a
    // flow collection: a flow collection never starts where its first child does.
    let flow = matches!(bytes.get(a.start as usize), Some(b'[' | b'{'))
        && first_child.is_none_or(|c| c.start != a.start);
    let end = if flow {
        // The end event sits on the closing bracket, or on a trailing comma before it.
        let mut i = end_event.start as usize;
        while matches!(bytes.get(i), Some(b',' | b' ' | b'\n' | b'\t' | b'\r')) {
            i += 1;
        }
        i as u32 + 1
    } else {
        last_child.map_or(a.start, |c| c.end.max(c.start))
    };
    Span {
        end: end.max(a.start),
        ..a
    }
}

fn limit_error(span: Span, what: &str, limit: usize) -> Diagnostic {
    Diagnostic::error(
        "E0002",
        span,
        format!("input exceeds the {what} limit of {limit}"),
    )
    .with_help(
        "this is far beyond any real building map; check for runaway aliases or generated nesting",
    )
}
