//! Text that is safe to put on a terminal: control characters and bidirectional controls
//! (the Trojan Source class, CVE-2021-42574) are shown escaped, as `\t` or `\u{202e}`,
//! so a name cannot break a message across lines or display reversed text.

use std::borrow::Cow;

/// Bidirectional formatting characters: the embeddings and overrides U+202A–U+202E, the
/// isolates U+2066–U+2069, and the marks U+200E, U+200F and U+061C.
pub fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}' | '\u{200e}' | '\u{200f}' | '\u{61c}')
}

/// Must `c` be escaped before it is displayed?
pub fn needs_escape(c: char) -> bool {
    c.is_control() || is_bidi_control(c)
}

/// `s` with every control and bidi character escaped (`\t`, `\n`, `\r`, `\u{202e}`).
pub fn display_safe(s: &str) -> Cow<'_, str> {
    if !s.chars().any(needs_escape) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        push_safe(&mut out, c);
    }
    Cow::Owned(out)
}

/// Appends `c` to `out`, escaped if it must be.
pub fn push_safe(out: &mut String, c: char) {
    match c {
        '\t' => out.push_str("\\t"),
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        c if needs_escape(c) => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
        c => out.push(c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_controls_and_bidi() {
        assert_eq!(display_safe("L1"), "L1");
        assert!(matches!(display_safe("plain ünïcode"), Cow::Borrowed(_)));
        assert_eq!(display_safe("L0_tab\there"), "L0_tab\\there");
        assert_eq!(display_safe("a\nb\r"), "a\\nb\\r");
        assert_eq!(display_safe("x\u{202e}y\u{2066}"), "x\\u{202e}y\\u{2066}");
        assert_eq!(display_safe("bell\u{7}"), "bell\\u{7}");
        assert!(!display_safe("\u{200f}\u{61c}\u{1b}[31m")
            .chars()
            .any(needs_escape));
    }
}
