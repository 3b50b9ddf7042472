//! docs/diagnostics.md is generated from the doc comments of the frontend's, the backends'
//! and the scenario codes (frontend/src/codes.rs, backends/src/codes.rs, sim/src/codes.rs)
//! and of every validation rule (ir/src/validate/<group>/<rule>.rs).
//! This test fails when the file is stale; `MAPC_UPDATE_DOCS=1 cargo test --test docs`
//! rewrites it.

use std::collections::BTreeMap;
use std::path::Path;

struct Entry {
    code: String,
    name: String,
    body: String,
    source: String,
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Splits `# CODE name` off a doc block.
fn parse_block(lines: &[String], source: &str) -> Entry {
    let first = lines.first().map(String::as_str).unwrap_or("");
    let heading = first
        .strip_prefix("# ")
        .unwrap_or_else(|| panic!("{source}: doc must start with `# CODE name`, found {first:?}"));
    let (code, name) = heading
        .split_once(' ')
        .unwrap_or_else(|| panic!("{source}: heading needs a code and a name"));
    let body = lines[1..].join("\n").trim().to_string();
    Entry {
        code: code.into(),
        name: name.into(),
        body,
        source: source.into(),
    }
}

/// Files that list `pub const` codes with `///` docs.
const CODE_LISTS: [&str; 5] = [
    "frontend/src/codes.rs",
    "frontend/src/site/codes.rs",
    "backends/src/codes.rs",
    "sim/src/codes.rs",
    "src/codes/sweep.rs",
];

/// `E` codes are errors and `W` codes warnings; scenario (`S`) codes are errors unless
/// their doc says `**Severity:** warning`.
fn severity(e: &Entry) -> &'static str {
    let warning = e.code.starts_with('W')
        || (e.code.starts_with('S') && e.body.contains("**Severity:** warning"));
    if warning {
        "warning"
    } else {
        "error"
    }
}

fn code_list_entries() -> Vec<Entry> {
    CODE_LISTS.iter().flat_map(|f| code_entries(f)).collect()
}

fn code_entries(file: &str) -> Vec<Entry> {
    let text = std::fs::read_to_string(root().join(file)).unwrap();
    let mut out = Vec::new();
    let mut block: Vec<String> = Vec::new();
    for line in text.lines() {
        let t = line.trim_start();
        if let Some(doc) = t.strip_prefix("///") {
            block.push(doc.strip_prefix(' ').unwrap_or(doc).to_string());
        } else {
            if t.starts_with("pub const") && !block.is_empty() {
                out.push(parse_block(&block, file));
            }
            block.clear();
        }
    }
    out
}

fn rule_entries() -> Vec<Entry> {
    let mut out = Vec::new();
    let vdir = root().join("ir/src/validate");
    let mut groups: Vec<_> = std::fs::read_dir(&vdir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    groups.sort();
    for g in groups {
        let mut files: Vec<_> = std::fs::read_dir(&g)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "rs"))
            .collect();
        files.sort();
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            if !text.contains("static RULE: Rule") {
                continue; // mod.rs and helpers
            }
            let rel = f.strip_prefix(root()).unwrap().display().to_string();
            let block: Vec<String> = text
                .lines()
                .take_while(|l| l.starts_with("//!"))
                .map(|l| {
                    let d = &l[3..];
                    d.strip_prefix(' ').unwrap_or(d).to_string()
                })
                .collect();
            let e = parse_block(&block, &rel);
            assert!(
                text.contains(&format!("code: \"{}\"", e.code)),
                "{rel}: heading code {} differs from RULE.code",
                e.code
            );
            assert!(
                text.contains(&format!("name: \"{}\"", e.name)),
                "{rel}: heading name {} differs from RULE.name",
                e.name
            );
            for section in [
                "**What:**",
                "**Why it matters:**",
                "**Fix:**",
                "**Example:**",
            ] {
                assert!(e.body.contains(section), "{rel}: doc lacks {section}");
            }
            out.push(e);
        }
    }
    out
}

const SCHEMA: &str = r#"## Output formats

`mapc check` (and every command that reads a map) prints diagnostics in one of three
formats, chosen with `--format`:

- `human` (default): source snippets with underlines on stderr, colour only on a terminal.
- `json`: JSON Lines on stdout, one object per diagnostic, in the order found:

  ```json
  {"severity": "error", "code": "E0103", "name": "vertex-index-out-of-range",
   "message": "vertex index 5 is out of range: level `L1` has 2 vertices (0..1)",
   "location": {"file": "site.building.yaml", "line": 11, "column": 13,
                "end_line": 11, "end_column": 14, "byte_start": 272, "byte_end": 273},
   "labels": [{"file": "...", "line": 9, "column": 9, "end_line": 9, "end_column": 21,
               "byte_start": 150, "byte_end": 162, "message": "the vertex"}],
   "help": "use the 0-based index of a vertex in this level's `vertices` list"}
  ```

  `severity` is `error` or `warning`; `code` and `name` are stable; lines are 1-based and
  columns count characters from 1; `end_*` is exclusive; `labels` are secondary locations;
  `help` may be absent. A diagnostic about the whole file has only `location.file`. Fields
  are only ever added, never renamed or removed.
- `sarif`: one SARIF 2.1.0 log on stdout (all inputs in one run), for code-scanning tools.

**How many are shown.** At most 20 diagnostics per code are shown (`--max-diagnostics N`
changes the number, `--max-diagnostics all` shows every one; in the style of clang's
`-ferror-limit`). For each code with more, every format states the true total once, after
the diagnostics:

- `human`: one line per code,
  `W0207 unconnected-near-waypoints: 3,046 found, 20 shown; --max-diagnostics all to see them`
  (the per-map total line that follows still counts every diagnostic).
- `json`: one summary record per code, after the diagnostics; it is told apart from a
  diagnostic by its `kind`:

  ```json
  {"kind": "summary", "code": "W0207", "name": "unconnected-near-waypoints",
   "found": 3046, "shown": 20, "message": "W0207 unconnected-near-waypoints: 3,046 found, ..."}
  ```
- `sarif`: `runs[0].invocations[0].toolExecutionNotifications`, one per code, with
  `level: "note"`, `descriptor.id` = the code, `properties.found` and `properties.shown`.

`nav`, `gazebo`, `ignition` and `classic`, the drop-ins for `building_map_generator` that
build systems run, print one `file:line:col: severity[code]: message` line per diagnostic
in `human` format (source snippets with `--verbose`); `check` and the other commands print
snippets. Control and bidirectional-control characters in messages and snippets are shown
escaped (`\t`, `\u{202e}`), and a source line longer than 160 characters is cut around the
underlined part (`…`).

Exit codes: 0 every output asked for was written (`mapc check`: no errors; warnings are
fine), 1 an error (or a denied warning) blocked an output asked for (`mapc check`: any
error), 2 usage or I/O error, 130/143 interrupted by SIGINT/SIGTERM.

## Lint levels

Every command that reads a map takes `--allow CODE`, `--warn CODE` and `--deny CODE`
(repeatable; CODE is a code such as `W0204` or a name such as `lane-crosses-wall`), and
`--deny warnings` (or `--deny-warnings`). A `mapc.toml` beside the map or in the nearest
parent directory that has one (or the file given with `--config FILE`, which replaces that
search) sets levels too:

```toml
[lints]
E0302 = "allow"              # or "warn", "deny"
lane-crosses-wall = "deny"
warnings = "deny"
```

Precedence: a code's level on the command line, else its level in the file, else its
default (`E` error, `W` warning). Then every diagnostic still at warning level takes the
level of the `warnings` group, if one is set (command line over file): `--deny warnings`
makes them errors, `--allow warnings` silences them; a code allowed or denied by name keeps
its level.

An error blocks only the outputs it breaks (the **blocks** column: `nav`, `gltf`, `meshes`,
`worlds`; a world includes its level meshes): `mapc build` writes the other targets and
exits 1, a single-output command whose output is not broken writes it. Errors after which
no correct output can be written (unreadable input, an element dropped for a wrong type or a
dangling index, no usable coordinates) cannot be allowed or lowered to warnings: trying is a
usage error (exit 2). The exception among the frontend's errors is `E0112` (a likely typo
of a known key): the key is only ignored, as with `W0103`, so it can be allowed or lowered
to a warning when the key really is an extension; while an error it blocks every output.
The **can be allowed** column says which codes can.
"#;

/// The lint group a map code declares (frontend, site, rule or backend table).
fn group_of(code: &str) -> mapc_ir::lints::Group {
    mapc_frontend::CODES
        .iter()
        .chain(mapc_frontend::site::codes::CODES)
        .chain(mapc_backends::CODES)
        .find(|c| c.code == code)
        .map(|c| c.group)
        .or_else(|| mapc_ir::rule(code).map(|r| r.group))
        .unwrap_or_else(|| panic!("{code}: declared in no table"))
}

/// "yes"/"no" and the outputs blocked, from the code's lint group (scenario codes are not
/// lints: `—`).
fn lint_columns(e: &Entry) -> (&'static str, String) {
    if e.code.starts_with('S') {
        return ("—", "—".into());
    }
    let p = group_of(&e.code).policy();
    let blocks = if !p.can_allow || p.blocks == mapc_ir::lints::Outputs::ALL {
        "every output".to_string()
    } else {
        let mut b = p.blocks.names().join(", ");
        if p.nav_only_with_lanes {
            b = b.replace("nav", "nav (when the map has lanes)");
        }
        b
    };
    (if p.can_allow { "yes" } else { "no" }, blocks)
}

fn render(entries: &[Entry]) -> String {
    let mut s = String::from(
        "# mapc diagnostics\n\n<!-- Generated by `MAPC_UPDATE_DOCS=1 cargo test --test docs` from the doc \
         comments in frontend/src/codes.rs, backends/src/codes.rs, sim/src/codes.rs, src/codes/sweep.rs and ir/src/validate/. Do not edit by hand. -->\n\n\
         Every problem mapc reports has a stable code: `E` codes are errors (the outputs they \
         break are not written), `W` codes are warnings; both can be changed (see Lint levels). `E00xx`/`E01xx` come from reading the file, `E02xx` lanes and \
         graphs, `E03xx` doors, `E04xx` lifts, `E05xx` names and roles, `E06xx` geometry and \
         coordinates, `W07xx` outputs (textures). `S` codes come from `mapc sim` scenario files \
         (see docs/sim.md): `S00xx` reading the file, `S01xx` values, `S02xx` the scenario against \
         the map, `S03xx` its own consistency, `S04xx` `mapc sweep` files (docs/sweep.md); their severity is in the table.\n\n",
    );
    s.push_str(SCHEMA);
    s.push_str("\n## All codes\n\n| code | name | severity | can be allowed | blocks | defined in |\n|---|---|---|---|---|---|\n");
    for e in entries {
        let sev = severity(e);
        let (allow, blocks) = lint_columns(e);
        s.push_str(&format!(
            "| [{}](#{}) | `{}` | {sev} | {allow} | {blocks} | `{}` |\n",
            e.code,
            format!("{}-{}", e.code, e.name).to_ascii_lowercase(),
            e.name,
            e.source
        ));
    }
    for e in entries {
        s.push_str(&format!("\n## {} {}\n\n", e.code, e.name));
        if !e.code.starts_with('S') {
            let (allow, blocks) = lint_columns(e);
            s.push_str(&format!(
                "**Default:** {}; **can be allowed:** {allow}; **as an error, blocks:** {blocks}.\n\n",
                severity(e)
            ));
        }
        // Demote headings inside the body below the entry's own.
        for line in e.body.lines() {
            if line.starts_with('#') && !line.starts_with("#!") {
                s.push_str("##");
            }
            s.push_str(line);
            s.push('\n');
        }
    }
    s
}

fn all_entries() -> Vec<Entry> {
    let mut by_code: BTreeMap<String, Entry> = BTreeMap::new();
    for e in code_list_entries().into_iter().chain(rule_entries()) {
        if let Some(prev) = by_code.get(&e.code) {
            panic!(
                "code {} documented twice: {} and {}",
                e.code, prev.source, e.source
            );
        }
        by_code.insert(e.code.clone(), e);
    }
    // Map codes by number (E before W), then the scenario codes.
    let mut v: Vec<Entry> = by_code.into_values().collect();
    v.sort_by_key(|e| {
        (
            e.code.starts_with('S'),
            e.code[1..].to_string(),
            e.code.clone(),
        )
    });
    v
}

#[test]
fn every_code_in_use_is_documented() {
    let documented: Vec<String> = all_entries().into_iter().map(|e| e.code).collect();
    // Codes the frontend and the backends emit as literals.
    let sources = ["frontend/src", "backends/src", "sim/src"]
        .iter()
        .flat_map(|d| std::fs::read_dir(root().join(d)).unwrap());
    for f in sources {
        let path = f.unwrap().path();
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        for (i, _) in text.match_indices('"') {
            let rest = &text[i + 1..];
            let code: String = rest.chars().take(5).collect();
            let is_code = code.len() == 5
                && (code.starts_with('E') || code.starts_with('W') || code.starts_with('S'))
                && code[1..].chars().all(|c| c.is_ascii_digit())
                && rest[5..].starts_with('"');
            if is_code {
                assert!(
                    documented.contains(&code),
                    "{code} used in {} is not documented",
                    path.display()
                );
            }
        }
    }
    // Every registered rule, and every frontend code entry.
    for r in mapc_ir::rules() {
        assert!(
            documented.iter().any(|c| c == r.code),
            "rule {} has no doc",
            r.code
        );
    }
    for c in mapc_backends::CODES {
        assert!(
            documented.iter().any(|d| d == c.code),
            "backend code {} has no doc",
            c.code
        );
    }
    for c in mapc_sim::codes::CODES {
        assert!(
            documented.iter().any(|d| d == c.code),
            "scenario code {} has no doc",
            c.code
        );
    }
    for c in mapc_frontend::CODES {
        assert!(
            documented.iter().any(|d| d == c.code),
            "frontend code {} has no doc",
            c.code
        );
    }
    // And every documented rule is registered (a rule file not in any RULES array).
    for e in rule_entries() {
        assert!(
            mapc_ir::rule(&e.code).is_some(),
            "{} documents {} but it is not registered",
            e.source,
            e.code
        );
    }
}

#[test]
fn diagnostics_md_is_current() {
    let want = render(&all_entries());
    let path = root().join("docs/diagnostics.md");
    if std::env::var_os("MAPC_UPDATE_DOCS").is_some() {
        std::fs::write(&path, &want).unwrap();
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/diagnostics.md is stale: run `MAPC_UPDATE_DOCS=1 cargo test --test docs`"
    );
}
