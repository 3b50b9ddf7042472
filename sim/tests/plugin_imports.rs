//! Issue 37: no plugin imports another. The plugins (slotcar, door, lift, workcell,
//! supervisor, crowd) read and write the shared truths (`truth`), the messages, the robot
//! parameters, the motion profile, the scenario's types and the report they add to; `world`
//! owns them all and wires them together. A plugin reaching into another would bring back the cycles this rule
//! removed (slotcar ↔ workcell, lift → slotcar, slotcar → crowd).

use std::path::{Path, PathBuf};

const PLUGINS: &[&str] = &["slotcar", "door", "lift", "workcell", "supervisor", "crowd"];
const ALLOWED: &[&str] = &[
    "msgs", "params", "profile", "truth", "scenario", "report", "Report",
];

/// The source files of plugin `name` (a file, or a folder of them).
fn sources(src: &Path, name: &str) -> Vec<PathBuf> {
    let file = src.join(format!("{name}.rs"));
    if file.is_file() {
        return vec![file];
    }
    let mut out: Vec<PathBuf> = std::fs::read_dir(src.join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    out.sort();
    out
}

/// The first module of every `crate::` path in `text`, comments left out.
fn crate_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(i) = rest.find("crate::") {
            let after = &rest[i + "crate::".len()..];
            let name: String = after
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            out.push(name);
            rest = after;
        }
    }
    out
}

#[test]
fn no_plugin_imports_another() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut wrong = Vec::new();
    for plugin in PLUGINS {
        for file in sources(&src, plugin) {
            let text = std::fs::read_to_string(&file).unwrap();
            for m in crate_paths(&text) {
                // `crate::crowd::x` inside crowd/ is the plugin's own module.
                if m != *plugin && !ALLOWED.contains(&m.as_str()) {
                    wrong.push(format!("{}: crate::{m}", file.display()));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "plugins importing what they may not:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_reader_finds_paths_and_skips_comments() {
    let text = "use crate::truth::{Body, Item};\nlet x = crate::slotcar::Ctx; // crate::lift\n";
    assert_eq!(crate_paths(text), ["truth", "slotcar"]);
}
