//! The dependency picture of `src/` (issue 37): every `crate::` and `super::` path of every
//! file, resolved to the module (file) it names. Checked: nothing but main.rs names an item
//! of main.rs; the layers only point down (commands → driver → ui → codes); no command
//! names another; and the modules form no cycle.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

/// The layers, top down: a module may name its own layer's modules and those below.
const LAYERS: [&str; 4] = ["commands", "driver", "ui", "codes"];

fn layer(m: &Module) -> usize {
    let top = m.first().map(String::as_str).unwrap_or("");
    LAYERS.iter().position(|l| *l == top).unwrap_or_else(|| {
        panic!("src/{top}: a top-level module outside the layers {LAYERS:?}; add it there")
    })
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

fn module_of(src: &Path, file: &Path) -> Module {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Module = rel
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    match last.as_str() {
        "main.rs" | "mod.rs" => {}
        f => parts.push(f.trim_end_matches(".rs").to_string()),
    }
    parts
}

/// The text without comments (line comments and doc comments; mapc has no block
/// comments in src/) and without string literals' contents.
fn code_only(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let mut in_str = false;
        let mut prev = ' ';
        let mut cut = line.len();
        for (i, c) in line.char_indices() {
            if c == '"' && prev != '\\' {
                in_str = !in_str;
            } else if !in_str && c == '/' && prev == '/' {
                cut = i - 1;
                break;
            }
            prev = if prev == '\\' && c == '\\' { ' ' } else { c };
        }
        let mut in_str = false;
        let mut prev = ' ';
        for c in line[..cut].chars() {
            if c == '"' && prev != '\\' {
                in_str = !in_str;
                out.push(c);
            } else if !in_str {
                out.push(c);
            }
            prev = if prev == '\\' && c == '\\' { ' ' } else { c };
        }
        out.push('\n');
    }
    out
}

fn ident(s: &[u8], mut i: usize) -> (String, usize) {
    let start = i;
    while i < s.len() && (s[i].is_ascii_alphanumeric() || s[i] == b'_') {
        i += 1;
    }
    (String::from_utf8_lossy(&s[start..i]).into_owned(), i)
}

fn skip_ws(s: &[u8], mut i: usize) -> usize {
    while i < s.len() && s[i].is_ascii_whitespace() {
        i += 1;
    }
    i
}

/// The paths of a `use`-style tree starting at `i` (after `prefix::`): `a::b`, `{a, b::c}`.
fn tree(s: &[u8], i: usize, prefix: &Module, out: &mut Vec<Module>) -> usize {
    let mut i = skip_ws(s, i);
    if i < s.len() && s[i] == b'{' {
        i += 1;
        loop {
            i = skip_ws(s, i);
            if i >= s.len() || s[i] == b'}' {
                return i + 1;
            }
            i = tree(s, i, prefix, out);
            i = skip_ws(s, i);
            if i < s.len() && s[i] == b',' {
                i += 1;
            }
        }
    }
    let (name, j) = ident(s, i);
    if name.is_empty() {
        out.push(prefix.clone());
        return j.max(i + 1);
    }
    let mut path = prefix.clone();
    path.push(name);
    if s[j..].starts_with(b"::") {
        return tree(s, j + 2, &path, out);
    }
    out.push(path);
    j
}

/// Every path after `crate::` or `super::` in `code`, made absolute from `module`.
fn paths(code: &str, module: &Module) -> Vec<Module> {
    let s = code.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < s.len() {
        let boundary = i == 0 || !(s[i - 1].is_ascii_alphanumeric() || s[i - 1] == b'_');
        if boundary && s[i..].starts_with(b"crate::") {
            i = tree(s, i + 7, &Vec::new(), &mut out);
        } else if boundary && s[i..].starts_with(b"super::") {
            // `super` of a file `a/b.rs` (module a::b) is `a`; of `a/b/mod.rs` too.
            let mut base = module.clone();
            let mut j = i;
            while s[j..].starts_with(b"super::") {
                base.pop();
                j += 7;
            }
            i = tree(s, j, &base, &mut out);
        } else {
            i += 1;
        }
    }
    out
}

/// `pub(crate) use sub::{a, b}` lines of a mod.rs: which child module each name is from.
fn reexports(code: &str, module: &Module) -> BTreeMap<String, Module> {
    let mut map = BTreeMap::new();
    for stmt in code.split(';') {
        let t = stmt.trim();
        let Some(rest) = t
            .strip_prefix("pub(crate) use ")
            .or_else(|| t.strip_prefix("pub use "))
        else {
            continue;
        };
        let mut found = Vec::new();
        tree(rest.as_bytes(), 0, module, &mut found);
        for p in found {
            if p.len() > module.len() + 1 {
                let name = p.last().unwrap().clone();
                map.insert(name, p[..module.len() + 1].to_vec());
            }
        }
    }
    map
}

#[test]
fn src_has_layers_and_no_cycles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut all = Vec::new();
    files(&src, &mut all);
    let mut code: BTreeMap<Module, (String, bool)> = BTreeMap::new();
    for f in &all {
        let is_mod = f
            .file_name()
            .is_some_and(|n| n == "mod.rs" || n == "main.rs");
        let mut text = std::fs::read_to_string(f).unwrap();
        // Unit tests (an inline `mod tests` at the end, whose `super` is the file itself)
        // are not part of the picture.
        if let Some(i) = text.find("#[cfg(test)]\nmod ") {
            text.truncate(i);
        }
        let text = code_only(&text);
        code.insert(module_of(&src, f), (text, is_mod));
    }
    let modules: BTreeSet<Module> = code.keys().cloned().collect();
    let re: BTreeMap<Module, BTreeMap<String, Module>> = code
        .iter()
        .filter(|(_, (_, is_mod))| *is_mod)
        .map(|(m, (text, _))| (m.clone(), reexports(text, m)))
        .collect();
    // The module a path names: its longest prefix that is a file, then through that
    // module's re-exports.
    let resolve = |p: &Module| -> (Module, Option<String>) {
        let mut m: Module = Vec::new();
        for seg in p {
            let mut next = m.clone();
            next.push(seg.clone());
            if modules.contains(&next) {
                m = next;
            } else {
                break;
            }
        }
        let item = p.get(m.len()).cloned();
        if let (Some(name), Some(map)) = (&item, re.get(&m)) {
            if let Some(sub) = map.get(name) {
                return (sub.clone(), item);
            }
        }
        (m, item)
    };
    let mut edges: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    let mut problems = Vec::new();
    for (m, (text, _)) in &code {
        if m.is_empty() {
            continue; // main.rs: the top, it may name anything.
        }
        for p in paths(text, m) {
            let (target, item) = resolve(&p);
            let name = |m: &Module| format!("crate::{}", m.join("::"));
            if target.is_empty() {
                problems.push(format!(
                    "{}: names `{}` of main.rs (main.rs is clap and exit codes only)",
                    name(m),
                    item.unwrap_or_default()
                ));
                continue;
            }
            if &target == m {
                continue;
            }
            if layer(&target) < layer(m) {
                problems.push(format!(
                    "{}: names {}, a layer above it ({LAYERS:?}, top down)",
                    name(m),
                    name(&target)
                ));
            }
            if m[0] == "commands"
                && target[0] == "commands"
                && target.len() > 1
                && m[1] != target[1]
            {
                problems.push(format!(
                    "{}: names another command, {} (shared work belongs in the driver)",
                    name(m),
                    name(&target)
                ));
            }
            edges.entry(m.clone()).or_default().insert(target);
        }
    }
    // Cycles: a depth-first search that reports the first back edge's loop.
    fn visit(
        m: &Module,
        edges: &BTreeMap<Module, BTreeSet<Module>>,
        state: &mut BTreeMap<Module, u8>,
        stack: &mut Vec<Module>,
        cycles: &mut Vec<String>,
    ) {
        state.insert(m.clone(), 1);
        stack.push(m.clone());
        for t in edges.get(m).into_iter().flatten() {
            match state.get(t) {
                Some(1) => {
                    let start = stack.iter().position(|s| s == t).unwrap();
                    let names: Vec<String> = stack[start..]
                        .iter()
                        .chain([t])
                        .map(|m| m.join("::"))
                        .collect();
                    cycles.push(format!("cycle: {}", names.join(" -> ")));
                }
                Some(_) => {}
                None => visit(t, edges, state, stack, cycles),
            }
        }
        stack.pop();
        state.insert(m.clone(), 2);
    }
    let mut state = BTreeMap::new();
    for m in edges.keys() {
        if !state.contains_key(m) {
            visit(m, &edges, &mut state, &mut Vec::new(), &mut problems);
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // The check sees the imports at all (a parser that found nothing would pass).
    assert!(edges.values().map(BTreeSet::len).sum::<usize>() > 50);
}

#[test]
fn the_parser_reads_grouped_and_relative_paths() {
    let m: Module = vec!["commands".into(), "nav".into()];
    let p = paths(
        &code_only(
            "use crate::driver::{self, CliError, report::Style};\nlet x = super::OutputDir; // crate::ui\n",
        ),
        &m,
    );
    let names: Vec<String> = p.iter().map(|p| p.join("::")).collect();
    assert_eq!(
        names,
        [
            "driver::self",
            "driver::CliError",
            "driver::report::Style",
            "commands::OutputDir"
        ]
    );
    assert_eq!(
        code_only("let s = \"crate::x\"; // crate::y"),
        "let s = \"\"; \n"
    );
}
