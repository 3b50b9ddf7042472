//! A small XML element tree for SDF and model.config output: attributes keep insertion
//! order, text is escaped, output is deterministic (two-space indentation, one element per
//! line, `<tag attr="v" />` for empty elements, as the reference's `xml.etree` writes).

use std::borrow::Cow;

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Element {
    // `Cow`: nearly every tag, attribute name and many texts are literals; a world of a
    // thousand models was a quarter allocations of such copies.
    pub name: Text,
    pub attrs: Vec<(Text, Text)>,
    pub children: Vec<Element>,
    pub text: Option<Text>,
}

/// A literal, or text made at run time.
pub type Text = Cow<'static, str>;

impl Element {
    pub fn new(name: impl Into<Text>) -> Element {
        Element {
            name: name.into(),
            ..Element::default()
        }
    }
    /// Adds an attribute (builder style).
    pub fn attr(mut self, k: impl Into<Text>, v: impl Into<Text>) -> Element {
        self.attrs.push((k.into(), v.into()));
        self
    }
    /// Sets the text content (builder style).
    pub fn text(mut self, t: impl Into<Text>) -> Element {
        self.text = Some(t.into());
        self
    }
    /// Appends a child (builder style).
    pub fn child(mut self, c: Element) -> Element {
        self.children.push(c);
        self
    }
    /// Appends a child `<name>text</name>` (builder style).
    pub fn leaf(self, name: &'static str, text: impl Into<Text>) -> Element {
        self.child(Element::new(name).text(text))
    }
    pub fn push(&mut self, c: Element) {
        self.children.push(c);
    }
    /// XML already written at the depth where it sits: a subtree made on another thread
    /// (its text is written as it is; an empty one writes nothing).
    pub fn verbatim(xml: String) -> Element {
        Element {
            text: Some(xml.into()),
            ..Element::default()
        }
    }
    pub fn is_verbatim(&self) -> bool {
        self.name.is_empty()
    }
    /// First child named `name`.
    pub fn find(&self, name: &str) -> Option<&Element> {
        self.children.iter().find(|c| c.name == name)
    }

    /// The element as an XML document. `declaration` adds the
    /// `<?xml version='1.0' encoding='utf-8'?>` line (model.sdf, model.config).
    pub fn to_document(&self, declaration: bool) -> String {
        let mut out = String::new();
        if declaration {
            out.push_str("<?xml version='1.0' encoding='utf-8'?>\n");
        }
        self.write_at(&mut out, 0);
        out
    }

    /// Appends the element as it is written `depth` levels deep.
    pub fn write_at(&self, out: &mut String, depth: usize) {
        // Pushes rather than `write!`: the world of a large map is half a megabyte of
        // these, and formatting machinery was most of its time.
        if self.is_verbatim() {
            out.push_str(self.text.as_deref().unwrap_or_default());
            return;
        }
        for _ in 0..depth {
            out.push_str("  ");
        }
        out.push('<');
        out.push_str(&self.name);
        for (k, v) in &self.attrs {
            out.push(' ');
            out.push_str(k);
            out.push_str("=\"");
            escape_into(out, v, true);
            out.push('"');
        }
        match (&self.text, self.children.is_empty()) {
            (None, true) => out.push_str(" />\n"),
            (Some(t), true) => {
                out.push('>');
                escape_into(out, t, false);
                out.push_str("</");
                out.push_str(&self.name);
                out.push_str(">\n");
            }
            (text, false) => {
                out.push('>');
                if let Some(t) = text {
                    escape_into(out, t, false);
                }
                out.push('\n');
                for c in &self.children {
                    c.write_at(out, depth + 1);
                }
                for _ in 0..depth {
                    out.push_str("  ");
                }
                out.push_str("</");
                out.push_str(&self.name);
                out.push_str(">\n");
            }
        }
    }
}

/// Appends `s` escaped; text without anything to escape (nearly all of it) is copied whole.
fn escape_into(out: &mut String, s: &str, attr: bool) {
    let special = |b: u8| {
        matches!(b, b'&' | b'<' | b'>')
            || (attr && b == b'"')
            || (b < 0x20 && b != b'\t' && b != b'\n')
    };
    if !s.bytes().any(special) {
        out.push_str(s);
        return;
    }
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' if attr => out.push_str("&quot;"),
            // Control characters other than tab and newline are not allowed in XML 1.0.
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_and_escaping() {
        let e = Element::new("sdf").attr("version", "1.7").child(
            Element::new("model")
                .attr("name", "a<b>&\"c\"")
                .leaf("static", "true")
                .child(Element::new("plugin").attr("name", "x")),
        );
        let mut x = String::new();
        escape_into(&mut x, "tab\there\u{1}é<", false);
        assert_eq!(x, "tab\there\u{fffd}é&lt;");
        assert_eq!(
            e.to_document(true),
            "<?xml version='1.0' encoding='utf-8'?>\n<sdf version=\"1.7\">\n  <model name=\"a&lt;b&gt;&amp;&quot;c&quot;\">\n    <static>true</static>\n    <plugin name=\"x\" />\n  </model>\n</sdf>\n"
        );
    }
}
