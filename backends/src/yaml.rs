//! A small YAML emitter for the documents mapc writes. Deterministic: mappings keep the
//! order they are built in; strings are quoted whenever a YAML 1.1 or 1.2 reader could
//! take them for anything but a string.

use crate::fmt::py_float;
use std::fmt::Write;

#[derive(Debug, Clone, PartialEq)]
pub enum Yaml {
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    Seq(Vec<Yaml>),
    Map(Vec<(String, Yaml)>),
    /// Render the inner collection on one line in flow style.
    Flow(Box<Yaml>),
}

impl Yaml {
    pub fn str(s: impl Into<String>) -> Yaml {
        Yaml::Str(s.into())
    }
    fn is_collection(&self) -> bool {
        matches!(self, Yaml::Seq(_) | Yaml::Map(_) | Yaml::Flow(_))
    }
    fn is_empty_collection(&self) -> bool {
        match self {
            Yaml::Seq(s) => s.is_empty(),
            Yaml::Map(m) => m.is_empty(),
            _ => false,
        }
    }
    /// Collections of scalars only go on one line, as PyYAML does.
    fn wants_flow(&self) -> bool {
        match self {
            Yaml::Flow(_) => true,
            Yaml::Seq(s) => s.iter().all(|v| !v.is_collection()),
            Yaml::Map(m) => m.iter().all(|(_, v)| !v.is_collection()),
            _ => false,
        }
    }
}

/// Renders a document (root must be a mapping) with a trailing newline.
pub fn to_string(root: &Yaml) -> String {
    let mut out = String::new();
    match root {
        Yaml::Map(m) if !m.is_empty() => block_map(&mut out, m, 0),
        other => {
            flow(&mut out, other);
            out.push('\n');
        }
    }
    out
}

/// Writes the entries of a block mapping at indent `ind`, as they would appear inside a
/// document: for documents written piece by piece.
pub(crate) fn write_entries(out: &mut String, m: &[(String, Yaml)], ind: usize) {
    block_map(out, m, ind);
}

/// Writes `key:` on its own line at indent `ind`: the start of a block mapping or
/// sequence whose entries the caller writes next.
pub(crate) fn write_key(out: &mut String, key: &str, ind: usize) {
    indent(out, ind);
    write_scalar(out, key);
    out.push_str(":\n");
}

/// Writes `key:` and the sequence `items` under it (not indented further, as inside a
/// mapping), rendering one item at a time: the sequence is never built whole. Items must
/// be collections (then the sequence is in block style, as [`to_string`] writes it).
pub(crate) fn write_key_seq(
    out: &mut String,
    key: &str,
    ind: usize,
    items: impl IntoIterator<Item = Yaml>,
) {
    indent(out, ind);
    write_scalar(out, key);
    out.push(':');
    let mut any = false;
    for v in items {
        debug_assert!(v.is_collection());
        if !any {
            out.push('\n');
            any = true;
        }
        indent(out, ind);
        out.push('-');
        block_value(out, &v, ind, false);
    }
    if !any {
        out.push_str(" []\n");
    }
}

fn indent(out: &mut String, n: usize) {
    const SPACES: &str = "                                ";
    let mut n = n;
    while n > 0 {
        let k = n.min(SPACES.len());
        out.push_str(&SPACES[..k]);
        n -= k;
    }
}

fn block_map(out: &mut String, m: &[(String, Yaml)], ind: usize) {
    for (k, v) in m {
        indent(out, ind);
        write_scalar(out, k);
        out.push(':');
        block_value(out, v, ind, true);
    }
}

fn block_seq(out: &mut String, s: &[Yaml], ind: usize) {
    for v in s {
        indent(out, ind);
        out.push('-');
        block_value(out, v, ind, false);
    }
}

/// After `key:` or `-`: a scalar or flow collection on the same line, else a nested block.
fn block_value(out: &mut String, v: &Yaml, ind: usize, in_map: bool) {
    if !v.is_collection() || v.wants_flow() || v.is_empty_collection() {
        out.push(' ');
        flow(out, v);
        out.push('\n');
        return;
    }
    out.push('\n');
    match v {
        Yaml::Map(m) => block_map(out, m, ind + 2),
        // PyYAML style: sequences under a key are not indented further.
        Yaml::Seq(s) => block_seq(out, s, if in_map { ind } else { ind + 2 }),
        _ => unreachable!("flow handled above"),
    }
}

fn flow(out: &mut String, v: &Yaml) {
    match v {
        Yaml::Str(s) => write_scalar(out, s),
        Yaml::Int(i) => {
            let _ = write!(out, "{i}");
        }
        Yaml::Float(f) => out.push_str(&yaml_float(*f)),
        Yaml::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
        Yaml::Flow(inner) => flow(out, inner),
        Yaml::Seq(s) => {
            out.push('[');
            for (i, x) in s.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                flow(out, x);
            }
            out.push(']');
        }
        Yaml::Map(m) => {
            out.push('{');
            for (i, (k, x)) in m.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                write_scalar(out, k);
                out.push_str(": ");
                flow(out, x);
            }
            out.push('}');
        }
    }
}

fn yaml_float(f: f64) -> String {
    if f.is_nan() {
        return ".nan".into();
    }
    if f.is_infinite() {
        return if f > 0.0 {
            ".inf".into()
        } else {
            "-.inf".into()
        };
    }
    let s = py_float(f);
    // YAML 1.1 floats need a dot in the mantissa: 1e-05 -> 1.0e-05.
    match s.split_once('e') {
        Some((m, e)) if !m.contains('.') => format!("{m}.0e{e}"),
        _ => s,
    }
}

/// Writes a string scalar, plain when that is unambiguous (the common case, no allocation).
fn write_scalar(out: &mut String, s: &str) {
    if is_plain_safe(s) {
        out.push_str(s);
    } else {
        out.push_str(&quoted(s));
    }
}

#[cfg(test)]
fn scalar_str(s: &str) -> String {
    let mut out = String::new();
    write_scalar(&mut out, s);
    out
}

fn quoted(s: &str) -> String {
    if s.chars().all(|c| !c.is_control()) {
        return format!("'{}'", s.replace('\'', "''"));
    }
    let mut q = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => q.push_str("\\\""),
            '\\' => q.push_str("\\\\"),
            '\n' => q.push_str("\\n"),
            '\t' => q.push_str("\\t"),
            '\r' => q.push_str("\\r"),
            c if c.is_control() => {
                let _ = write!(q, "\\u{:04x}", c as u32);
            }
            c => q.push(c),
        }
    }
    q.push('"');
    q
}

fn is_plain_safe(s: &str) -> bool {
    let b = s.as_bytes();
    let Some(&first) = b.first() else {
        return false;
    };
    if !(first.is_ascii_alphabetic() || first == b'_' || first == b'/') {
        return false;
    }
    if !b
        .iter()
        .all(|&c| c.is_ascii_alphanumeric() || matches!(c, b'_' | b'-' | b'.' | b'/'))
    {
        return false;
    }
    // Words YAML 1.1 resolves to booleans or null.
    !(b.len() <= 5
        && ["y", "n", "yes", "no", "on", "off", "true", "false", "null"]
            .iter()
            .any(|w| s.eq_ignore_ascii_case(w)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoting() {
        assert_eq!(scalar_str("coe_door"), "coe_door");
        assert_eq!(scalar_str(""), "''");
        assert_eq!(scalar_str("123"), "'123'");
        assert_eq!(scalar_str("yes"), "'yes'");
        assert_eq!(scalar_str("a: b"), "'a: b'");
        assert_eq!(scalar_str("it's"), "'it''s'");
        assert_eq!(scalar_str("a\nb"), "\"a\\nb\"");
        assert_eq!(scalar_str("EPSG:3414"), "'EPSG:3414'");
        assert_eq!(scalar_str("Open-RMF/TinyRobot"), "Open-RMF/TinyRobot");
    }

    #[test]
    fn layout() {
        let doc = Yaml::Map(vec![
            ("a".into(), Yaml::Int(1)),
            (
                "b".into(),
                Yaml::Seq(vec![
                    Yaml::Seq(vec![Yaml::Float(1e-5), Yaml::Float(2.0)]),
                    Yaml::Flow(Box::new(Yaml::Seq(vec![
                        Yaml::Int(0),
                        Yaml::Map(vec![("k".into(), Yaml::str(""))]),
                    ]))),
                ]),
            ),
            ("c".into(), Yaml::Map(vec![])),
        ]);
        assert_eq!(
            to_string(&doc),
            "a: 1\nb:\n- [1.0e-05, 2.0]\n- [0, {k: ''}]\nc: {}\n"
        );
    }
}
