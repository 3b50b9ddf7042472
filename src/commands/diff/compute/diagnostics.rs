//! Diagnostics that appeared or went, matched by code and message.

use super::*;

/// A diagnostic as a reviewer compares it: code and message with element indices left
/// out (they shift when anything before them is inserted).
pub(super) fn diag_key(d: &Diagnostic) -> (String, String) {
    let mut msg = String::new();
    let mut rest = d.message.as_str();
    while let Some(i) = rest.find("index ") {
        msg.push_str(&rest[..i]);
        let after = &rest[i + 6..];
        let digits = after.chars().take_while(char::is_ascii_digit).count();
        if digits > 0 {
            msg.push_str("index #");
            rest = &after[digits..];
        } else {
            msg.push_str("index ");
            rest = after;
        }
    }
    msg.push_str(rest);
    (d.code.to_string(), msg)
}

pub(super) fn diagnostics(old: &[Diagnostic], new: &[Diagnostic], out: &mut Vec<Change>) {
    let count = |ds: &[Diagnostic]| {
        let mut m: BTreeMap<(String, String, bool), usize> = BTreeMap::new();
        for d in ds {
            let (c, msg) = diag_key(d);
            *m.entry((c, msg, d.is_error())).or_default() += 1;
        }
        m
    };
    let (o, n) = (count(old), count(new));
    let sev = |e: bool| if e { "error" } else { "warning" };
    for (k, c) in &o {
        for _ in n.get(k).copied().unwrap_or(0)..*c {
            out.push(change(
                Section::Diagnostics,
                None,
                Kind::Removed,
                format!("{}[{}]", sev(k.2), k.0),
                k.1.clone(),
            ));
        }
    }
    for (k, c) in &n {
        for _ in o.get(k).copied().unwrap_or(0)..*c {
            out.push(change(
                Section::Diagnostics,
                None,
                Kind::Added,
                format!("{}[{}]", sev(k.2), k.0),
                k.1.clone(),
            ));
        }
    }
}
