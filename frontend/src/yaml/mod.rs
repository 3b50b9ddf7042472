//! A located YAML tree built from saphyr-parser events, with explicit limits.
//!
//! Why our own tree: we need the span of every node, duplicate-key detection, and hard
//! bounds on depth and alias expansion (alias bombs) that a generic loader does not give.

mod fast;
mod general;

use mapc_ir::{Diagnostic, FileId, Span};
use std::borrow::Cow;

/// Deepest nesting accepted; real maps use 6 levels.
pub const MAX_DEPTH: usize = 64;
/// Most nodes accepted in a small file, counting every alias expansion; larger files may
/// hold more ([`max_nodes`]).
pub const MAX_NODES: usize = 2_000_000;
/// Bytes of text per node that the node limit allows, beyond [`MAX_NODES`]. Maps written by
/// the editors take 5 or more bytes per node (a lane of 12 nodes is about 70 bytes), so any
/// map within the file-size cap is read; text denser than this (`[1,1,1,...]`) is refused
/// before its tree grows past about 14 times the file.
pub const BYTES_PER_NODE: usize = 4;

/// The node limit for a text of `len` bytes: the limit follows the file-size cap rather
/// than a fixed count.
pub fn max_nodes(len: usize) -> usize {
    MAX_NODES.max(len / BYTES_PER_NODE)
}
/// Most nodes that aliases may add. The editor never writes aliases; this only bounds
/// alias bombs, cheaply (each expansion is a copy).
pub const MAX_ALIAS_NODES: usize = 100_000;

/// A node's content. Scalars borrow from the source text when they can, which keeps
/// parsing and dropping large maps cheap.
#[derive(Debug, Clone)]
pub enum Kind<'a> {
    /// A scalar; `plain` is false for quoted, block and `!!str`-tagged scalars, which are
    /// always strings.
    Scalar {
        text: Cow<'a, str>,
        plain: bool,
    },
    Seq(Vec<Node<'a>>),
    Map(Vec<(Node<'a>, Node<'a>)>),
}

#[derive(Debug, Clone)]
pub struct Node<'a> {
    pub kind: Kind<'a>,
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

impl<'a> Node<'a> {
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
    pub fn as_map(&self) -> Option<&[(Node<'a>, Node<'a>)]> {
        match &self.kind {
            Kind::Map(m) => Some(m),
            _ => None,
        }
    }
    pub fn as_seq(&self) -> Option<&[Node<'a>]> {
        match &self.kind {
            Kind::Seq(s) => Some(s),
            _ => None,
        }
    }
    /// Value of `key` in a mapping (the last one, as PyYAML does with duplicates).
    pub fn get(&self, key: &str) -> Option<&Node<'a>> {
        self.as_map()?
            .iter()
            .rev()
            .find(|(k, _)| k.key_text() == Some(key))
            .map(|(_, v)| v)
    }
    /// Mutable value of `key` in a mapping (the last one, as [`Node::get`]).
    pub fn get_mut(&mut self, key: &str) -> Option<&mut Node<'a>> {
        match &mut self.kind {
            Kind::Map(m) => m
                .iter_mut()
                .rev()
                .find(|(k, _)| k.key_text() == Some(key))
                .map(|(_, v)| v),
            _ => None,
        }
    }
    pub fn as_map_mut(&mut self) -> Option<&mut [(Node<'a>, Node<'a>)]> {
        match &mut self.kind {
            Kind::Map(m) => Some(m),
            _ => None,
        }
    }
    /// Takes the node out of its tree, leaving a null with the same span: lowering frees
    /// the large lists of a map (vertices, lanes) as it goes, so that the tree and the IR
    /// built from it are not both whole in memory.
    pub fn take(&mut self) -> Node<'a> {
        let null = Node {
            kind: Kind::Scalar {
                text: Cow::Borrowed(""),
                plain: true,
            },
            span: self.span,
        };
        std::mem::replace(self, null)
    }
    /// The items of a sequence (none for any other node), by value.
    pub fn into_seq(self) -> Vec<Node<'a>> {
        match self.kind {
            Kind::Seq(s) => s,
            _ => Vec::new(),
        }
    }
    /// Text of a scalar used as a mapping key or a name: any scalar but null.
    pub fn key_text(&self) -> Option<&str> {
        match &self.kind {
            Kind::Scalar { text, plain } => {
                // Same null spellings as `resolve_plain`, without resolving numbers.
                if *plain && matches!(&**text, "" | "~" | "null" | "Null" | "NULL") {
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

/// Parses one YAML document. Returns the root or a single error diagnostic (a syntax
/// error leaves nothing trustworthy to lower). Both readers build the same tree: the fast
/// one for the subset maps are written in, saphyr for everything else.
pub fn parse(text: &str, file: FileId) -> Result<Node<'_>, Diagnostic> {
    match fast::parse(text, file) {
        Some(root) => Ok(root),
        None => parse_general(text, file),
    }
}

/// The tree of a map to lower, with its level lists left out when the fast reader read
/// it (see [`Lists`]): the whole tree of a large map is then never in memory, only one
/// list item at a time.
pub(crate) fn parse_map(text: &str, file: FileId) -> Result<(Node<'_>, Lists<'_>), Diagnostic> {
    let mut lists = Lists {
        text,
        file,
        fast: Vec::new(),
        general: Vec::new(),
    };
    match fast::parse_lists(text, file, true) {
        Some((root, fast)) => {
            lists.fast = fast;
            Ok((root, lists))
        }
        None => general::parse_lists(text, file, true).map(|(root, general)| {
            lists.general = general;
            (root, lists)
        }),
    }
}

/// The general reader (saphyr-parser events), whole tree.
pub(crate) fn parse_general(text: &str, file: FileId) -> Result<Node<'_>, Diagnostic> {
    general::parse_lists(text, file, false).map(|(root, _)| root)
}

/// Keys of a level whose lists grow with the map (one entry per line) and are lowered one
/// entry at a time ([`Lists`]).
const LIST_KEYS: &[&str] = &[
    "vertices",
    "lanes",
    "walls",
    "measurements",
    "doors",
    "human_lanes",
];

/// The level lists (vertices, lanes, walls, measurements, doors, human_lanes) that
/// [`parse_map`] left out of the tree: such a list is an empty sequence in the tree, with
/// the list's span, and [`Lists::items`] reads its items again from the text, with the
/// reader that read the document.
///
/// Why: a map's tree took 56 bytes a node, a lane of 70 bytes 12 nodes; whole at the end
/// of parsing, the tree of a large map was 10 times the file (issue 18 bounds the whole
/// process by that). Read again one item at a time, each item's tree lives only while it
/// is lowered. The lists are read twice (the first time to check the document and count
/// its nodes), which costs less than building and freeing the tree did.
pub(crate) struct Lists<'a> {
    text: &'a str,
    file: FileId,
    fast: Vec<fast::List>,
    general: Vec<general::List>,
}

/// The items of a sequence, by value: from the tree, or read again from the text.
pub(crate) struct Items<'a> {
    from: From<'a>,
    /// Items handed out so far, and how many the list has (when read again).
    yielded: usize,
    len: usize,
    /// To read the whole tree if a list ever failed to read again.
    text: &'a str,
    file: FileId,
    key: u32,
}

/// Readers are boxed: a saphyr parser's state is a few hundred bytes.
enum From<'a> {
    Tree(std::vec::IntoIter<Node<'a>>),
    Fast(Box<fast::Items<'a>>),
    General(Box<general::Items<'a>>),
}

impl<'a> Iterator for Items<'a> {
    type Item = Node<'a>;
    fn next(&mut self) -> Option<Node<'a>> {
        let next = match &mut self.from {
            From::Tree(i) => return i.next(),
            From::Fast(i) => i.next(),
            From::General(i) => i.next(),
        };
        if next.is_some() {
            self.yielded += 1;
            return next;
        }
        if self.yielded < self.len {
            // The same reader accepted this text before, so this does not happen; if it
            // ever did, the list is taken from the whole tree rather than cut short.
            let rest = parse(self.text, self.file)
                .ok()
                .and_then(|root| whole_list(root, self.key))
                .unwrap_or_default();
            let mut rest = rest.into_iter();
            if self.yielded > 0 {
                rest.nth(self.yielded - 1);
            }
            self.from = From::Tree(rest);
            self.yielded = self.len;
            return self.next();
        }
        None
    }
}

/// The level list starting at `key` in a whole tree.
fn whole_list(root: Node<'_>, key: u32) -> Option<Vec<Node<'_>>> {
    let Kind::Map(entries) = root.kind else {
        return None;
    };
    let (_, levels) = entries
        .into_iter()
        .rev()
        .find(|(k, _)| k.key_text() == Some("levels"))?;
    let Kind::Map(levels) = levels.kind else {
        return None;
    };
    levels
        .into_iter()
        .filter_map(|(_, level)| match level.kind {
            Kind::Map(lists) => Some(lists),
            _ => None,
        })
        .flatten()
        .find(|(_, v)| v.span.start == key && matches!(v.kind, Kind::Seq(_)))
        .map(|(_, v)| v.into_seq())
}

impl<'a> Lists<'a> {
    /// No list left out: every sequence is read from the tree.
    pub(crate) fn whole(text: &'a str, file: FileId) -> Self {
        Lists {
            text,
            file,
            fast: Vec::new(),
            general: Vec::new(),
        }
    }
    /// The list left out at `node`, by the reader that left it out.
    fn find(&self, node: &Node) -> Option<Result<&fast::List, &general::List>> {
        match &node.kind {
            Kind::Seq(items) if items.is_empty() => {}
            _ => return None,
        }
        let key = node.span.start;
        if let Ok(i) = self.fast.binary_search_by_key(&key, |l| l.key) {
            return Some(Ok(&self.fast[i]));
        }
        let i = self.general.binary_search_by_key(&key, |l| l.key).ok()?;
        Some(Err(&self.general[i]))
    }
    /// Number of items of a sequence (0 for any other node).
    pub(crate) fn len(&self, node: &Node) -> usize {
        match self.find(node) {
            Some(Ok(l)) => l.len,
            Some(Err(l)) => l.len,
            None => node.as_seq().map_or(0, <[Node]>::len),
        }
    }
    /// The items of a sequence by value (none for any other node).
    pub(crate) fn items(&self, node: Node<'a>) -> Items<'a> {
        let key = node.span.start;
        let (from, len) = match self.find(&node) {
            Some(Ok(l)) => (
                From::Fast(Box::new(fast::Items::new(self.text, self.file, l))),
                l.len,
            ),
            Some(Err(l)) => (
                From::General(Box::new(general::Items::new(self.text, self.file, l))),
                l.len,
            ),
            None => (From::Tree(node.into_seq().into_iter()), 0),
        };
        Items {
            from,
            yielded: 0,
            len,
            text: self.text,
            file: self.file,
            key,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> Node<'_> {
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

    /// Both readers leave the level lists out of a map's tree and read them again with the
    /// same items and spans as the whole tree has.
    #[test]
    fn level_lists_are_left_out_and_read_again() {
        let lf = "levels:\n  L1:\n    vertices:\n    - [0, 0, 0, a]\n    - [1, 2, 0, \"\u{e9}\"]\n    lanes:\n      - [0, 1]\n    models:\n      - {name: m}\n";
        let crlf = lf.replace('\n', "\r\n");
        let json = "{\n  \"levels\": {\n    \"L1\": {\n      \"vertices\": [[0, 0, 0, \"a\"],\n        [1, 2, 0, \"b\"]],\n      \"lanes\": [[0, 1]]\n    }\n  }\n}\n";
        for (text, fast) in [(lf, true), (crlf.as_str(), false), (json, false)] {
            let (mut root, lists) = parse_map(text, FileId(0)).unwrap();
            assert_eq!(lists.fast.len(), if fast { 2 } else { 0 }, "{text:?}");
            assert_eq!(lists.general.len(), if fast { 0 } else { 2 }, "{text:?}");
            let whole = parse(text, FileId(0)).unwrap();
            let level = root.get_mut("levels").unwrap().get_mut("L1").unwrap();
            let level_whole = whole.get("levels").unwrap().get("L1").unwrap();
            for key in ["vertices", "lanes"] {
                let list = level.get_mut(key).unwrap().take();
                let expected = level_whole.get(key).unwrap();
                assert_eq!(list.span, expected.span, "{text:?} {key}");
                assert_eq!(lists.len(&list), expected.as_seq().unwrap().len());
                let items: Vec<Node> = lists.items(list).collect();
                let items = Node {
                    kind: Kind::Seq(items),
                    span: expected.span,
                };
                oracle::same(&items, expected, key).unwrap();
            }
            // Other lists stay in the tree.
            if let Some(models) = level.get("models") {
                assert_eq!(models.as_seq().unwrap().len(), 1);
            }
        }
    }

    #[test]
    fn duplicate_keys_last_wins() {
        let n = p("a: 1\na: 2\n");
        assert_eq!(n.get("a").unwrap().as_i64(), Some(2));
    }
}

/// The differential oracle: whenever the fast reader accepts an input, its tree must equal
/// the general reader's, node for node and span for span. Used by the tests below and by
/// the `yaml_diff` fuzz target (feature `fuzzing`).
#[cfg(any(test, feature = "fuzzing"))]
pub(crate) mod oracle {
    use super::*;

    pub(crate) fn same(a: &Node, b: &Node, at: &str) -> Result<(), String> {
        if a.span != b.span {
            return Err(format!("{at}: span {:?} != {:?}", a.span, b.span));
        }
        match (&a.kind, &b.kind) {
            (
                Kind::Scalar {
                    text: t1,
                    plain: p1,
                },
                Kind::Scalar {
                    text: t2,
                    plain: p2,
                },
            ) => {
                if t1 != t2 || p1 != p2 {
                    return Err(format!("{at}: scalar {t1:?}/{p1} != {t2:?}/{p2}"));
                }
            }
            (Kind::Seq(x), Kind::Seq(y)) => {
                if x.len() != y.len() {
                    return Err(format!("{at}: seq length {} != {}", x.len(), y.len()));
                }
                for (i, (p, q)) in x.iter().zip(y).enumerate() {
                    same(p, q, &format!("{at}[{i}]"))?;
                }
            }
            (Kind::Map(x), Kind::Map(y)) => {
                if x.len() != y.len() {
                    return Err(format!("{at}: map length {} != {}", x.len(), y.len()));
                }
                for (i, ((k1, v1), (k2, v2))) in x.iter().zip(y).enumerate() {
                    same(k1, k2, &format!("{at}.key{i}"))?;
                    same(v1, v2, &format!("{at}.{}", k1.key_text().unwrap_or("?")))?;
                }
            }
            _ => return Err(format!("{at}: kinds differ")),
        }
        Ok(())
    }

    /// Some(true) if fast accepted and agreed, Some(false) if fast declined.
    pub(crate) fn check(text: &str) -> Result<bool, String> {
        let Some(f) = fast::parse(text, FileId(0)) else {
            return Ok(false);
        };
        match parse_general(text, FileId(0)) {
            Ok(g) => same(&f, &g, "root").map(|_| true),
            Err(d) => Err(format!(
                "fast accepted input the general reader rejects: {}",
                d.message
            )),
        }
    }
}

#[cfg(test)]
mod differential {
    use super::oracle::check;
    use std::path::{Path, PathBuf};

    fn inputs() -> Vec<PathBuf> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut out = Vec::new();
        for dir in ["fixtures", "fixtures/invalid", "tests/fuzz_regressions"] {
            for e in std::fs::read_dir(root.join(dir)).unwrap() {
                let p = e.unwrap().path();
                if p.extension().is_some_and(|x| x == "yaml") {
                    out.push(p);
                }
            }
        }
        let shared = root.join("../shared/maps");
        if let Ok(maps) = std::fs::read_dir(&shared) {
            for m in maps {
                let m = m.unwrap().path();
                let name = m.file_name().unwrap().to_string_lossy().into_owned();
                out.push(m.join(format!("{name}.building.yaml")));
            }
        } else {
            println!("skipped demo maps: ../shared not found");
        }
        out.sort();
        out
    }

    #[test]
    fn fast_reader_accepts_real_maps_and_agrees() {
        for p in inputs() {
            let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
            let name = p.display().to_string();
            let accepted = check(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            // Every map we or traffic_editor wrote must take the fast path.
            let must = !name.contains("/invalid/")
                && !name.contains("fuzz_regressions")
                && !name.contains("web_mercator");
            if must {
                assert!(accepted, "{name}: fast reader declined a real map");
            }
        }
    }

    #[test]
    fn fast_reader_declines_what_yaml_forbids() {
        // Found by the yaml_diff fuzz target: control characters are not printable YAML.
        for text in [
            "a: b\u{b}\nc: d\n",
            "a: [1\u{0} 0]\n",
            "a: x\u{7f}\n",
            "a: \u{9f}\n",
            "a: \u{fffe}\n",
            "a: [0,\u{feff} 0]\n",
            "a: 1  # x\ry: 2\n",
            "a: 1\r\nb: 2\r\n",
        ] {
            assert_eq!(check(text), Ok(false), "{text:?}");
        }
        // Found by yaml_diff too: a quoted key's `:` needs a space after it in block context.
        for text in [
            "'a':\n'b':c\n",
            "a: 1\n\"b\":c\n",
            "a: [3 -, 4]\n",
            "a: [x ?]\n",
        ] {
            assert_eq!(check(text), Ok(false), "{text:?}");
        }
        assert_eq!(check("a: caf\u{e9} \u{85}\n"), Ok(true));
    }

    #[test]
    fn fast_reader_agrees_on_mutations() {
        // Deterministic single-edit mutations of every input near structural characters.
        let alphabet: &[&str] = &[
            "",
            " ",
            "  ",
            "\n",
            "- ",
            ": ",
            ":",
            ",",
            "[",
            "]",
            "{",
            "}",
            "#",
            " #",
            "'",
            "\"",
            "&a ",
            "*a",
            "!",
            "|",
            "\t",
            "?",
            "-",
            "\\",
            "''",
            "\"\\u00e9\"",
            "é",
            "x: y",
        ];
        let mut checked = 0;
        let mut accepted = 0;
        // MAPC_DIFF_SCALE=k runs k times more mutations (with another seed).
        let scale: usize = std::env::var("MAPC_DIFF_SCALE")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1);
        let mut seed = 0x2545F4914F6CDD1Du64 ^ (scale as u64).wrapping_mul(0x9E3779B97F4A7C15);
        for p in inputs() {
            let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
            let bytes = text.as_bytes();
            let n = match bytes.len() {
                0..=5_000 => 150,
                5_001..=50_000 => 40,
                _ => 8,
            } * scale;
            for _ in 0..n {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let mut at = (seed % bytes.len().max(1) as u64) as usize;
                while !text.is_char_boundary(at) {
                    at -= 1;
                }
                let cut = ((seed >> 32) % 3) as usize;
                let mut end = (at + cut).min(text.len());
                while !text.is_char_boundary(end) {
                    end += 1;
                }
                let ins = alphabet[((seed >> 40) as usize) % alphabet.len()];
                let mutated = format!("{}{}{}", &text[..at], ins, &text[end..]);
                match check(&mutated) {
                    Ok(a) => accepted += a as usize,
                    Err(e) => panic!(
                        "{}: mutation at byte {at} (cut {cut}, insert {ins:?}): {e}",
                        p.display()
                    ),
                }
                checked += 1;
            }
        }
        assert!(checked > 1000, "{checked}");
        assert!(
            accepted > checked / 4,
            "fast path accepted only {accepted} of {checked}"
        );
    }
}
