//! A located YAML tree built from saphyr-parser events, with explicit limits.
//!
//! Why our own tree: we need the span of every node, duplicate-key detection, and hard
//! bounds on depth and alias expansion (alias bombs) that a generic loader does not give.

use mapc_ir::{Diagnostic, FileId, Span};
use saphyr_parser::{Event, Parser, ScalarStyle};
use std::collections::HashMap;

/// Deepest nesting accepted; real maps use 6 levels.
pub const MAX_DEPTH: usize = 64;
/// Most nodes accepted, counting every alias expansion.
pub const MAX_NODES: usize = 2_000_000;
/// Most nodes that aliases may add. The editor never writes aliases; this only bounds
/// alias bombs, cheaply (each expansion is a copy).
pub const MAX_ALIAS_NODES: usize = 100_000;

#[derive(Debug, Clone)]
pub enum Kind {
    /// A scalar; `plain` is false for quoted, block and `!!str`-tagged scalars, which are
    /// always strings.
    Scalar {
        text: String,
        plain: bool,
    },
    Seq(Vec<Node>),
    Map(Vec<(Node, Node)>),
}

#[derive(Debug, Clone)]
pub struct Node {
    pub kind: Kind,
    pub span: Span,
}

/// A scalar resolved by the YAML 1.2 core schema (plus int spellings of floats).
#[derive(Debug, Clone, PartialEq)]
pub enum Scalar<'a> {
    Null,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(&'a str),
}

impl Node {
    pub fn scalar(&self) -> Option<Scalar<'_>> {
        match &self.kind {
            Kind::Scalar { text, plain: false } => Some(Scalar::Str(text)),
            Kind::Scalar { text, plain: true } => Some(resolve_plain(text)),
            _ => None,
        }
    }
    pub fn is_null(&self) -> bool {
        matches!(self.scalar(), Some(Scalar::Null))
    }
    pub fn as_map(&self) -> Option<&[(Node, Node)]> {
        match &self.kind {
            Kind::Map(m) => Some(m),
            _ => None,
        }
    }
    pub fn as_seq(&self) -> Option<&[Node]> {
        match &self.kind {
            Kind::Seq(s) => Some(s),
            _ => None,
        }
    }
    /// Value of `key` in a mapping (the last one, as PyYAML does with duplicates).
    pub fn get(&self, key: &str) -> Option<&Node> {
        self.as_map()?
            .iter()
            .rev()
            .find(|(k, _)| k.key_text() == Some(key))
            .map(|(_, v)| v)
    }
    /// Text of a scalar used as a mapping key or a name: any scalar but null.
    pub fn key_text(&self) -> Option<&str> {
        match &self.kind {
            Kind::Scalar { text, plain } => {
                if *plain && matches!(resolve_plain(text), Scalar::Null) {
                    None
                } else {
                    Some(text)
                }
            }
            _ => None,
        }
    }
    pub fn as_f64(&self) -> Option<f64> {
        match self.scalar()? {
            Scalar::Int(i) => Some(i as f64),
            Scalar::Float(f) => Some(f),
            _ => None,
        }
    }
    pub fn as_i64(&self) -> Option<i64> {
        match self.scalar()? {
            Scalar::Int(i) => Some(i),
            // The editor reads indices as doubles; accept integral floats like `3.0`.
            Scalar::Float(f) if f.fract() == 0.0 && f.abs() < 9.0e15 => Some(f as i64),
            _ => None,
        }
    }
    pub fn as_bool(&self) -> Option<bool> {
        match self.scalar()? {
            Scalar::Bool(b) => Some(b),
            _ => None,
        }
    }
    /// Human name of the node's type, for "expected X, found Y" messages.
    pub fn type_name(&self) -> &'static str {
        match &self.kind {
            Kind::Seq(_) => "a sequence",
            Kind::Map(_) => "a mapping",
            Kind::Scalar { .. } => match self.scalar() {
                Some(Scalar::Null) => "null",
                Some(Scalar::Bool(_)) => "a boolean",
                Some(Scalar::Int(_)) => "an integer",
                Some(Scalar::Float(_)) => "a number",
                _ => "a string",
            },
        }
    }
}

fn resolve_plain(t: &str) -> Scalar<'_> {
    match t {
        "" | "~" | "null" | "Null" | "NULL" => return Scalar::Null,
        "true" | "True" | "TRUE" => return Scalar::Bool(true),
        "false" | "False" | "FALSE" => return Scalar::Bool(false),
        ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" => {
            return Scalar::Float(f64::INFINITY)
        }
        "-.inf" | "-.Inf" | "-.INF" => return Scalar::Float(f64::NEG_INFINITY),
        ".nan" | ".NaN" | ".NAN" => return Scalar::Float(f64::NAN),
        _ => {}
    }
    let b = t.as_bytes();
    let digits = b.strip_prefix(b"-").or(b.strip_prefix(b"+")).unwrap_or(b);
    if !digits.is_empty() && digits.iter().all(u8::is_ascii_digit) {
        if let Ok(i) = t.parse::<i64>() {
            return Scalar::Int(i);
        }
        // Too large for i64: still a number.
        return t.parse::<f64>().map_or(Scalar::Str(t), Scalar::Float);
    }
    if let Some(hex) = t.strip_prefix("0x") {
        if let Ok(i) = i64::from_str_radix(hex, 16) {
            return Scalar::Int(i);
        }
    }
    if let Some(oct) = t.strip_prefix("0o") {
        if let Ok(i) = i64::from_str_radix(oct, 8) {
            return Scalar::Int(i);
        }
    }
    if is_float_syntax(digits) {
        if let Ok(f) = t.parse::<f64>() {
            return Scalar::Float(f);
        }
    }
    Scalar::Str(t)
}

/// `(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?` (the core schema's float, sign stripped).
fn is_float_syntax(b: &[u8]) -> bool {
    let mut i = 0;
    let int_start = i;
    while i < b.len() && b[i].is_ascii_digit() {
        i += 1;
    }
    let int_digits = i - int_start;
    let mut frac_digits = 0;
    if i < b.len() && b[i] == b'.' {
        i += 1;
        let s = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        frac_digits = i - s;
    }
    if int_digits == 0 && frac_digits == 0 {
        return false;
    }
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        i += 1;
        if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
            i += 1;
        }
        let s = i;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
        }
        if i == s {
            return false;
        }
    }
    i == b.len()
}

/// Maps saphyr's character positions to byte offsets.
struct Positions<'a> {
    text: &'a str,
    line_starts: Vec<usize>,
    /// Whether each line is pure ASCII (then char column == byte column).
    line_ascii: Vec<bool>,
}

impl<'a> Positions<'a> {
    fn new(text: &'a str) -> Self {
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
        }
    }
    /// Byte offset of (1-based line, 0-based char column).
    fn byte(&self, line: usize, col: usize) -> usize {
        let i = line.saturating_sub(1);
        let Some(&start) = self.line_starts.get(i) else {
            return self.text.len();
        };
        if self.line_ascii[i] {
            return (start + col).min(self.text.len());
        }
        let rest = &self.text[start..];
        start + rest.char_indices().nth(col).map_or(rest.len(), |(i, _)| i)
    }
    fn span(&self, file: FileId, s: saphyr_parser::Span) -> Span {
        let start = self.byte(s.start.line(), s.start.col());
        let end = self.byte(s.end.line(), s.end.col()).max(start);
        Span {
            file,
            start: start as u32,
            end: end as u32,
            line: s.start.line() as u32,
            col: s.start.col() as u32 + 1,
        }
    }
}

/// An open collection: its items, start span, anchor id and size in nodes so far.
enum Frame {
    Seq(Vec<Node>, Span, usize, usize),
    Map(Vec<(Node, Node)>, Option<Node>, Span, usize, usize),
}

/// Parses one YAML document. Returns the root or a single error diagnostic (a syntax
/// error leaves nothing trustworthy to lower).
pub fn parse(text: &str, file: FileId) -> Result<Node, Diagnostic> {
    let pos = Positions::new(text);
    let mut stack: Vec<Frame> = Vec::new();
    let mut anchors: HashMap<usize, (Node, usize)> = HashMap::new();
    let mut root: Option<Node> = None;
    let mut total_nodes = 0usize;
    let mut alias_nodes = 0usize;
    let mut documents = 0;

    for item in Parser::new_from_str(text) {
        let (event, sp) = match item {
            Ok(x) => x,
            Err(e) => {
                let m = e.marker();
                let start = pos.byte(m.line(), m.col());
                let span = Span {
                    file,
                    start: start as u32,
                    end: start as u32,
                    line: m.line() as u32,
                    col: m.col() as u32 + 1,
                };
                return Err(Diagnostic::error(
                    "E0001",
                    span,
                    format!("invalid YAML: {}", e.info()),
                )
                .with_help("fix the YAML syntax at this position"));
            }
        };
        let span = pos.span(file, sp);
        // (node, anchor id) completed by this event, if any.
        let done: Option<(Node, usize, usize)> = match event {
            Event::StreamStart | Event::StreamEnd | Event::Nothing | Event::DocumentEnd => None,
            Event::DocumentStart(_) => {
                documents += 1;
                if documents > 1 {
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
            Event::Alias(id) => match anchors.get(&id) {
                Some((node, size)) => {
                    total_nodes += size;
                    alias_nodes += size;
                    if alias_nodes > MAX_ALIAS_NODES {
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
                total_nodes += 1;
                let is_str_tag = tag.as_ref().is_some_and(|t| t.suffix == "str");
                let plain = style == ScalarStyle::Plain && !is_str_tag;
                Some((
                    Node {
                        kind: Kind::Scalar {
                            text: text.into_owned(),
                            plain,
                        },
                        span,
                    },
                    anchor,
                    1,
                ))
            }
            Event::SequenceStart(anchor, _) => {
                if stack.len() >= MAX_DEPTH {
                    return Err(limit_error(span, "nesting depth", MAX_DEPTH));
                }
                stack.push(Frame::Seq(Vec::new(), span, anchor, 1));
                total_nodes += 1;
                None
            }
            Event::MappingStart(anchor, _) => {
                if stack.len() >= MAX_DEPTH {
                    return Err(limit_error(span, "nesting depth", MAX_DEPTH));
                }
                stack.push(Frame::Map(Vec::new(), None, span, anchor, 1));
                total_nodes += 1;
                None
            }
            Event::SequenceEnd => match stack.pop() {
                Some(Frame::Seq(items, start, anchor, size)) => Some((
                    Node {
                        kind: Kind::Seq(items),
                        span: join(text, start, span),
                    },
                    anchor,
                    size,
                )),
                _ => return Err(Diagnostic::error("E0001", span, "unbalanced sequence end")),
            },
            Event::MappingEnd => match stack.pop() {
                Some(Frame::Map(items, _, start, anchor, size)) => Some((
                    Node {
                        kind: Kind::Map(items),
                        span: join(text, start, span),
                    },
                    anchor,
                    size,
                )),
                _ => return Err(Diagnostic::error("E0001", span, "unbalanced mapping end")),
            },
        };
        if total_nodes > MAX_NODES {
            return Err(limit_error(span, "node count", MAX_NODES));
        }
        if let Some((node, anchor, size)) = done {
            if anchor > 0 {
                anchors.insert(anchor, (node.clone(), size));
            }
            match stack.last_mut() {
                None => root = Some(node),
                Some(Frame::Seq(items, _, _, total)) => {
                    *total += size;
                    items.push(node)
                }
                Some(Frame::Map(items, pending, _, _, total)) => {
                    *total += size;
                    match pending.take() {
                        None => *pending = Some(node),
                        Some(key) => items.push((key, node)),
                    }
                }
            }
        }
    }
    Ok(root.unwrap_or(Node {
        kind: Kind::Scalar {
            text: String::new(),
            plain: true,
        },
        span: Span {
            file,
            start: 0,
            end: 0,
            line: 1,
            col: 1,
        },
    }))
}

/// Span of a collection from its start to its end event: through the closing bracket of
/// a flow collection, and without trailing whitespace for block collections.
fn join(text: &str, a: Span, b: Span) -> Span {
    let bytes = text.as_bytes();
    let mut end = b.start as usize;
    if matches!(bytes.get(end), Some(b']' | b'}')) {
        end += 1;
    } else {
        while end > a.start as usize && bytes.get(end - 1).is_some_and(u8::is_ascii_whitespace) {
            end -= 1;
        }
    }
    Span {
        end: (end as u32).max(a.start),
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

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> Node {
        parse(s, FileId(0)).unwrap()
    }

    #[test]
    fn scalars_resolve_by_core_schema() {
        let n = p("[1, -2, 1.5, 1e-3, .5, true, null, '3', abc, 0x10]");
        let s: Vec<_> = n
            .as_seq()
            .unwrap()
            .iter()
            .map(|n| format!("{:?}", n.scalar().unwrap()))
            .collect();
        assert_eq!(
            s,
            [
                "Int(1)",
                "Int(-2)",
                "Float(1.5)",
                "Float(0.001)",
                "Float(0.5)",
                "Bool(true)",
                "Null",
                "Str(\"3\")",
                "Str(\"abc\")",
                "Int(16)"
            ]
        );
    }

    #[test]
    fn spans_have_line_and_column() {
        let n = p("a:\n  b: [1, 2]\n");
        let b = n.get("a").unwrap().get("b").unwrap();
        assert_eq!((b.span.line, b.span.col), (2, 6));
        let two = &b.as_seq().unwrap()[1];
        assert_eq!((two.span.line, two.span.col), (2, 10));
        assert_eq!(two.span.start, 12);
    }

    #[test]
    fn alias_bomb_is_bounded() {
        let mut s = String::from("a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n");
        for i in 1..12 {
            let prev = i - 1;
            s.push_str(&format!(
                "a{i}: &a{i} [*a{prev}, *a{prev}, *a{prev}, *a{prev}, *a{prev}, *a{prev}, *a{prev}, *a{prev}, *a{prev}, *a{prev}]\n"
            ));
        }
        let e = parse(&s, FileId(0)).unwrap_err();
        assert_eq!(e.code, "E0002");
    }

    #[test]
    fn deep_nesting_is_bounded() {
        // saphyr stops very deep flow nesting itself; block nesting reaches our limit.
        let e = parse(&"[".repeat(10_000), FileId(0)).unwrap_err();
        assert!(e.code == "E0001" || e.code == "E0002", "{e:?}");
        let s2: String = (0..100)
            .map(|i| format!("{}k{i}:\n", " ".repeat(i)))
            .collect();
        let e2 = parse(&s2, FileId(0)).unwrap_err();
        assert_eq!(e2.code, "E0002", "{e2:?}");
    }

    #[test]
    fn duplicate_keys_last_wins() {
        let n = p("a: 1\na: 2\n");
        assert_eq!(n.get("a").unwrap().as_i64(), Some(2));
    }
}
