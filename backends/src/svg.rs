//! The one SVG writer of mapc, for both pictures: `mapc render`'s level maps and `mapc
//! sweep`'s capacity chart. Elements are appended to a string, one per line; attribute
//! values and text are escaped; the shape helpers write numbers with two decimals (no
//! `-0`). Output is deterministic for the same calls.

use std::fmt::{Display, Write};

/// A number with at most two decimals, trailing zeros and `-0` removed.
pub fn num(v: f64) -> String {
    let v = if v.is_finite() { v } else { 0.0 };
    let mut s = format!("{:.2}", v);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".into();
    }
    s
}

/// Escapes text for an XML text node or attribute value.
pub fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // XML 1.0 forbids most control characters even escaped.
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' && c != '\r' => out.push('?'),
            c => out.push(c),
        }
    }
    out
}

/// The document being written.
#[derive(Default)]
pub struct Svg {
    pub out: String,
}

/// An element's attributes: names and values (escaped when written).
pub type Attrs<'a> = &'a [(&'a str, &'a dyn Display)];

impl Svg {
    /// Writes `<name a="v" ...` (no end).
    fn start(&mut self, name: &str, attrs: Attrs) {
        self.out.push('<');
        self.out.push_str(name);
        for (k, v) in attrs {
            let _ = write!(self.out, r#" {k}="{}""#, esc(&v.to_string()));
        }
    }

    /// `<name a="v" ...>` on a line of its own; [`Svg::close`] ends the element.
    pub fn begin(&mut self, name: &str, attrs: Attrs) {
        self.start(name, attrs);
        self.out.push_str(">\n");
    }

    /// `<name a="v" .../>`: an element without content.
    pub fn empty(&mut self, name: &str, attrs: Attrs) {
        self.start(name, attrs);
        self.out.push_str("/>\n");
    }

    /// `<name a="v" ...>text</name>`, the text escaped.
    pub fn leaf(&mut self, name: &str, attrs: Attrs, text: &str) {
        self.start(name, attrs);
        let _ = writeln!(self.out, ">{}</{name}>", esc(text));
    }

    pub fn raw(&mut self, s: &str) {
        self.out.push_str(s);
    }

    pub fn open(&mut self, tag_and_attrs: &str) {
        let _ = writeln!(self.out, "<{tag_and_attrs}>");
    }

    pub fn close(&mut self, tag: &str) {
        let _ = writeln!(self.out, "</{tag}>");
    }

    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), attrs: &str) {
        let _ = writeln!(
            self.out,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" {attrs}/>"#,
            num(a.0),
            num(a.1),
            num(b.0),
            num(b.1)
        );
    }

    pub fn polygon(&mut self, pts: &[(f64, f64)], attrs: &str) {
        let _ = writeln!(self.out, r#"<polygon points="{}" {attrs}/>"#, points(pts));
    }

    pub fn path(&mut self, d: &str, attrs: &str) {
        let _ = writeln!(self.out, r#"<path d="{d}" {attrs}/>"#);
    }

    pub fn circle(&mut self, c: (f64, f64), r: f64, attrs: &str) {
        let _ = writeln!(
            self.out,
            r#"<circle cx="{}" cy="{}" r="{}" {attrs}/>"#,
            num(c.0),
            num(c.1),
            num(r)
        );
    }

    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, attrs: &str) {
        let _ = writeln!(
            self.out,
            r#"<rect x="{}" y="{}" width="{}" height="{}" {attrs}/>"#,
            num(x),
            num(y),
            num(w),
            num(h)
        );
    }

    pub fn text(&mut self, p: (f64, f64), size: f64, attrs: &str, text: &str) {
        let _ = writeln!(
            self.out,
            r#"<text x="{}" y="{}" font-size="{}" {attrs}>{}</text>"#,
            num(p.0),
            num(p.1),
            num(size),
            esc(text)
        );
    }
}

pub fn points(pts: &[(f64, f64)]) -> String {
    let mut s = String::new();
    for (i, p) in pts.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        let _ = write!(s, "{},{}", num(p.0), num(p.1));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_never_negative_zero() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(1.5), "1.5");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(2.346), "2.35");
        assert_eq!(num(f64::NAN), "0");
        assert_eq!(num(-12.0), "-12");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(esc("a<b & \"c\"\u{1}"), "a&lt;b &amp; &quot;c&quot;?");
    }

    #[test]
    fn elements_have_escaped_attributes_and_text() {
        let mut s = Svg::default();
        s.begin("g", &[("class", &"a&b")]);
        s.empty("line", &[("x1", &1), ("y1", &format_args!("{:.1}", 2.0))]);
        s.leaf("text", &[("x", &3.5)], "1 < 2");
        s.close("g");
        assert_eq!(
            s.out,
            "<g class=\"a&amp;b\">\n<line x1=\"1\" y1=\"2.0\"/>\n<text x=\"3.5\">1 &lt; 2</text>\n</g>\n"
        );
    }
}
