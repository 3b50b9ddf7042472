//! `mapc lsp` driven as an editor drives it, over stdin/stdout: initialize, open, change
//! (incremental and full), hover, definition, references, document and workspace symbols,
//! code actions, shutdown and exit; each answer checked against the map's real contents.

#[path = "support/lsp_client.rs"]
mod lsp_client;

use lsp_client::{file_uri, find, pos, Client};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn fixture() -> (PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/lsp/lsp_test.building.yaml");
    let text = std::fs::read_to_string(&path).expect("fixture");
    (path, text)
}

fn codes(diags: &[Value]) -> Vec<String> {
    let mut c: Vec<String> = diags
        .iter()
        .map(|d| d["code"].as_str().unwrap_or("").to_string())
        .collect();
    c.sort();
    c
}

fn diag<'a>(diags: &'a [Value], code: &str) -> &'a Value {
    diags
        .iter()
        .find(|d| d["code"] == code)
        .unwrap_or_else(|| panic!("no {code} in {diags:?}"))
}

fn td(uri: &str, line: u32, character: u32) -> Value {
    json!({"textDocument": {"uri": uri}, "position": pos(line, character)})
}

#[test]
fn editor_session() {
    let (path, text) = fixture();
    let uri = file_uri(&path);
    let dir = tempfile::tempdir().expect("tempdir");
    let mut c = Client::start(&[], dir.path());
    let init = c.initialize();
    let caps = &init["capabilities"];
    assert_eq!(caps["textDocumentSync"]["change"], 2, "incremental sync");
    for p in [
        "hoverProvider",
        "definitionProvider",
        "referencesProvider",
        "documentSymbolProvider",
        "workspaceSymbolProvider",
        "codeActionProvider",
    ] {
        assert_eq!(caps[p], true, "{p}");
    }
    assert_eq!(init["serverInfo"]["name"], "mapc");

    // Diagnostics on open: what `mapc check` finds, with ranges, related places, links.
    c.open(&uri, &text);
    let d1 = c.diagnostics(&uri, 1);
    assert_eq!(codes(&d1), ["E0201", "E0501", "W0203", "W0207", "W0208"]);
    let self_loop = diag(&d1, "E0201");
    let (line, col) = find(&text, "[3, 3,");
    assert_eq!(self_loop["range"]["start"], pos(line, col));
    assert_eq!(self_loop["severity"], 1);
    assert_eq!(self_loop["source"], "mapc");
    assert!(self_loop["codeDescription"]["href"]
        .as_str()
        .unwrap()
        .ends_with("docs/diagnostics.md#e0201-lane-self-loop"));
    let (office, _) = find(&text, "[8, 0, 0, office]");
    assert_eq!(
        self_loop["relatedInformation"][0]["location"]["range"]["start"]["line"],
        office
    );
    assert_eq!(self_loop["relatedInformation"][0]["message"], "the vertex");
    assert_eq!(diag(&d1, "W0207")["severity"], 2);

    // Hover on the `1` of `[1, 4, ...]`: vertex 1, `pantry`, at (4, 0) m, used by 3 lanes.
    let (l, col) = find(&text, "[1, 4,");
    let h = c.request("textDocument/hover", td(&uri, l, col + 1));
    let v = h["contents"]["value"].as_str().unwrap();
    assert!(v.contains("**vertex 1** `pantry` on level `L1`"), "{v}");
    assert!(v.contains("position: (4.000, 0.000) m"), "{v}");
    assert!(v.contains("used by 3 lanes"), "{v}");
    assert_eq!(h["range"]["start"], pos(l, col + 1));
    assert_eq!(h["range"]["end"], pos(l, col + 2));
    // Hover on vertex 0 through a wall-less index: roles and its name with non-ASCII text.
    let (l0, c0) = find(&text, "[0, 1, {bidirectional");
    let v = c.request("textDocument/hover", td(&uri, l0, c0 + 1))["contents"]["value"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(
        v.contains("`café😀dock`") && v.contains("roles: charger, parking spot"),
        "{v}"
    );
    // Hover on a parameter after `é` and `😀` (UTF-16 columns: 😀 counts 2).
    let (lp, cp) = find(&text, "is_charger");
    let line_text = text.lines().nth(lp as usize).unwrap();
    assert_ne!(
        cp as usize,
        line_text.find("is_charger").unwrap(),
        "the line must have non-ASCII text before the key"
    );
    let h = c.request("textDocument/hover", td(&uri, lp, cp + 3));
    assert!(h["contents"]["value"]
        .as_str()
        .unwrap()
        .starts_with("**`is_charger`** — bool (4)"));
    assert_eq!(h["range"]["start"], pos(lp, cp));
    assert_eq!(h["range"]["end"], pos(lp, cp + "is_charger".len() as u32));
    // The building's own `name` is not the door parameter `name`.
    let (ln, _) = find(&text, "name: lsp_test");
    assert!(c.request("textDocument/hover", td(&uri, ln, 1)).is_null());
    // A door's `name` parameter is.
    let (ldn, cdn) = find(&text, "name: [1, main_door]");
    let v = c.request("textDocument/hover", td(&uri, ldn, cdn + 1))["contents"]["value"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(v.starts_with("**`name`** — string (1)"), "{v}");
    // Hover on a diagnostic: its documentation.
    let (ls, cs) = find(&text, "[3, 3,");
    let v = c.request("textDocument/hover", td(&uri, ls, cs))["contents"]["value"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(v.contains("**E0201** lane-self-loop (error)"), "{v}");
    assert!(v.contains("**Fix:** delete the lane"), "{v}");

    // Definition: the `4` of `[1, 4,` is the second `pantry` vertex.
    let def = c.request("textDocument/definition", td(&uri, l, col + 4));
    let (lv4, cv4) = find(&text, "[4, 4, 0, pantry]");
    assert_eq!(def["uri"], uri.as_str());
    assert_eq!(def["range"]["start"], pos(lv4, cv4));
    assert_eq!(
        def["range"]["end"],
        pos(lv4, cv4 + "[4, 4, 0, pantry]".len() as u32)
    );

    // References of vertex 1 from its own entry: the entry and the three lanes using it.
    let (lv1, cv1) = find(&text, "[4, 0, 0, pantry]");
    let refs = c.request("textDocument/references", json!({"textDocument": {"uri": uri}, "position": pos(lv1, cv1 + 1), "context": {"includeDeclaration": true}}));
    let mut lines: Vec<u64> = refs
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["range"]["start"]["line"].as_u64().unwrap())
        .collect();
    lines.sort();
    let lane = |s: &str| find(&text, s).0 as u64;
    let mut want = vec![
        lv1 as u64,
        lane("[0, 1, {bidirectional"),
        lane("[1, 4,"),
        lane("[0, 1, {bidirectional") + 4,
    ];
    want.sort();
    assert_eq!(lines, want);
    // Without the declaration, from the door's `6`: the wall and the door.
    let (ld, cd) = find(&text, "[5, 6, {motion");
    let refs = c.request("textDocument/references", json!({"textDocument": {"uri": uri}, "position": pos(ld, cd + 4), "context": {"includeDeclaration": false}}));
    assert_eq!(refs.as_array().unwrap().len(), 2, "{refs}");

    // Document symbols: the level with its door and named waypoints, then the graph.
    let syms = c.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri}}),
    );
    let syms = syms.as_array().unwrap();
    assert_eq!(syms.len(), 2);
    assert_eq!(syms[0]["name"], "L1");
    let names: Vec<&str> = syms[0]["children"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["main_door", "café😀dock", "pantry", "office", "pantry"]
    );
    assert_eq!(syms[1]["name"], "graph 0: tinyRobot");

    // Workspace symbols over the open maps.
    let ws = c.request("workspace/symbol", json!({"query": "PANT"}));
    let ws = ws.as_array().unwrap();
    assert_eq!(ws.len(), 2);
    assert!(ws
        .iter()
        .all(|s| s["name"] == "pantry" && s["containerName"] == "L1"));

    // Code actions over the whole map, one per fixable diagnostic.
    let actions = c.request("textDocument/codeAction", json!({"textDocument": {"uri": uri}, "range": {"start": pos(0, 0), "end": pos(40, 0)}, "context": {"diagnostics": []}}));
    let actions = actions.as_array().unwrap();
    let titles: Vec<&str> = actions
        .iter()
        .map(|a| a["title"].as_str().unwrap())
        .collect();
    assert_eq!(
        titles,
        [
            "Remove this self-loop lane",
            "Remove this duplicate lane",
            "Join vertex 2 to vertex 1: reconnect its lanes to vertex 1",
            "Rename `pantry` to `pantry_2`",
        ]
    );
    let edit = |i: usize| actions[i]["edit"]["changes"][uri.as_str()][0].clone();
    assert_eq!(
        edit(0)["range"],
        json!({"start": pos(ls, 0), "end": pos(ls + 1, 0)})
    );
    assert_eq!(edit(0)["newText"], "");
    let (lj, cj) = find(&text, "[2, 3,");
    assert_eq!(edit(2)["range"]["start"], pos(lj, cj + 1));
    assert_eq!(edit(2)["newText"], "1");
    assert_eq!(
        edit(3)["range"]["start"],
        pos(lv4, cv4 + "[4, 4, 0, ".len() as u32)
    );
    assert_eq!(edit(3)["newText"], "pantry_2");

    // Apply the self-loop fix as an incremental change: E0201 is gone, lines moved up.
    c.notify("textDocument/didChange", json!({"textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"range": edit(0)["range"], "text": ""}]}));
    let d2 = c.diagnostics(&uri, 2);
    assert_eq!(codes(&d2), ["E0501", "W0203", "W0207", "W0208"]);
    assert_eq!(
        diag(&d2, "W0203")["range"]["start"]["line"],
        diag(&d1, "W0203")["range"]["start"]["line"]
            .as_u64()
            .unwrap()
            - 1
    );

    // A full change with both remaining fixes applied by hand; and a hover on the new text.
    let fixed = text
        .replace(
            "      - [3, 3, {bidirectional: [4, true], graph_idx: [2, 0]}]\n",
            "",
        )
        .replace("[4, 4, 0, pantry]", "[4, 4, 0, pantry_2]")
        .replace("[2, 3, {", "[1, 3, {");
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 3}, "contentChanges": [{"text": fixed}]}),
    );
    assert_eq!(codes(&c.diagnostics(&uri, 3)), ["W0203"]);

    // Several changes in a row, then a request: the answer is about the last text.
    for v in 4..=8 {
        let t = fixed.replace("[8, 0, 0, office]", &format!("[{v}, 0, 0, office]"));
        c.notify(
            "textDocument/didChange",
            json!({"textDocument": {"uri": uri, "version": v}, "contentChanges": [{"text": t}]}),
        );
    }
    let (lo, co) = find(&fixed, "[1, 3, {");
    let v = c.request("textDocument/hover", td(&uri, lo, co + 4))["contents"]["value"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(v.contains("position: (8.000, 0.000) m"), "{v}");
    assert!(
        c.notifications.iter().any(|n| n["params"]["version"] == 8),
        "diagnostics of the last version come before the answer"
    );

    // Closing clears the file's diagnostics.
    c.notify(
        "textDocument/didClose",
        json!({"textDocument": {"uri": uri}}),
    );
    let cleared = c.request("workspace/symbol", json!({"query": ""}));
    assert_eq!(cleared, json!([]));
    assert!(c
        .notifications
        .iter()
        .any(|n| n["params"]["uri"] == uri.as_str()
            && n["params"]["diagnostics"] == json!([])
            && n["params"]["version"].is_null()));
    assert_eq!(c.shutdown(), 0);
}

#[test]
fn lint_levels_as_on_the_command_line() {
    let (_, text) = fixture();
    let dir = tempfile::tempdir().expect("tempdir");
    let map = dir.path().join("m.building.yaml");
    std::fs::write(&map, &text).unwrap();
    std::fs::write(
        dir.path().join("mapc.toml"),
        "[lints]\nW0207 = \"allow\"\nduplicate-lane = \"deny\"\n",
    )
    .unwrap();
    let uri = file_uri(&map);
    // The file's levels plus the command line's.
    let mut c = Client::start(&["--allow", "W0208"], dir.path());
    c.initialize();
    c.open(&uri, &text);
    let d = c.diagnostics(&uri, 1);
    assert_eq!(codes(&d), ["E0201", "E0501", "W0203"]);
    assert_eq!(diag(&d, "W0203")["severity"], 1, "denied: an error");
    // A broken mapc.toml is said in the file, and the command line's levels still apply.
    std::fs::write(
        dir.path().join("mapc.toml"),
        "[lints]\nW0207 = \"sometimes\"\n",
    )
    .unwrap();
    c.notify(
        "textDocument/didSave",
        json!({"textDocument": {"uri": uri}}),
    );
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": text}]}),
    );
    let d = c.diagnostics(&uri, 2);
    let cfg = d
        .iter()
        .find(|x| x["code"].is_null())
        .expect("a config diagnostic");
    assert!(
        cfg["message"]
            .as_str()
            .unwrap()
            .contains("W0207 must be \"allow\", \"warn\" or \"deny\""),
        "{cfg}"
    );
    assert_eq!(codes(&d), ["", "E0201", "E0501", "W0203", "W0207", "W0208"]);
    assert_eq!(c.shutdown(), 0);

    // Bad flags are a usage error before any protocol.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(["lsp", "--allow", "E0001"])
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn project_and_scenario_files() {
    let (_, text) = fixture();
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("m.building.yaml"), &text).unwrap();
    let project = "building:\n  filename: m.building.yaml\n";
    let p = dir.path().join("m.project.yaml");
    std::fs::write(&p, project).unwrap();
    let scenario = "duration: 10min\nfleets:\n  - {name: tinyRobot, count: 2}\nseed: seven\n";
    let s = dir.path().join("s.scenario.yaml");
    let mut c = Client::start(&[], dir.path());
    c.initialize();
    let (puri, suri) = (file_uri(&p), file_uri(&s));
    c.open(&puri, project);
    let d = c.diagnostics(&puri, 1);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0]["severity"], 1);
    let (lf, cf) = find(project, "m.building.yaml");
    assert_eq!(d[0]["range"]["start"], pos(lf, cf));
    assert!(
        d[0]["message"]
            .as_str()
            .unwrap()
            .contains("2 error(s), 3 warning(s); the first: error[E0201] at line 14"),
        "{}",
        d[0]
    );
    let def = c.request("textDocument/definition", td(&puri, lf, cf + 2));
    assert_eq!(def["uri"], file_uri(&dir.path().join("m.building.yaml")));
    c.open(&suri, scenario);
    let d = c.diagnostics(&suri, 1);
    let mut got = codes(&d);
    got.dedup();
    assert_eq!(got, ["S0101", "S0102"]);
    let (ls, _) = find(scenario, "seed: seven");
    assert_eq!(diag(&d, "S0101")["range"]["start"]["line"], ls);
    // Other files are not served.
    c.open("file:///tmp/notes.yaml", "a: 1\n");
    let r = c.send_request("textDocument/hover", td("file:///tmp/notes.yaml", 0, 0));
    assert!(c.response(r)["error"]["message"]
        .as_str()
        .unwrap()
        .contains("is not open"));
    assert_eq!(c.shutdown(), 0);
}

#[test]
fn cancelled_and_unknown_requests() {
    let (path, text) = fixture();
    let uri = file_uri(&path);
    let dir = tempfile::tempdir().expect("tempdir");
    let mut c = Client::start(&[], dir.path());
    c.initialize();
    let unknown = c.send_request("textDocument/completion", td(&uri, 0, 0));
    assert_eq!(c.response(unknown)["error"]["code"], -32601);
    c.open(&uri, &text);
    // A request cancelled before the server reads it is answered RequestCancelled.
    let id = c.send_request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri}}),
    );
    c.notify("$/cancelRequest", json!({"id": id}));
    let r = c.response(id);
    // Both arrive together unless the server was quicker than the second write.
    assert!(
        r["error"]["code"] == -32800 || r["result"].is_array(),
        "{r}"
    );
    drop(c);
}

/// The (code, line, UTF-16 column) of each diagnostic `mapc check` finds in `text`.
fn check_positions(dir: &Path, text: &str) -> Vec<(String, u64, u64)> {
    let path = dir.join("check.building.yaml");
    std::fs::write(&path, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(["check", "--format", "json", "--max-diagnostics", "all"])
        .arg(&path)
        .output()
        .unwrap();
    let mut v: Vec<(String, u64, u64)> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|d| d["code"].is_string())
        .map(|d| {
            let start = d["location"]["byte_start"].as_u64().unwrap() as usize;
            let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
            let col = text[line_start..start].encode_utf16().count() as u64;
            let line = text[..start].matches('\n').count() as u64;
            (d["code"].as_str().unwrap().to_string(), line, col)
        })
        .collect();
    v.sort();
    v
}

/// Random incremental edits with multi-byte text (é: 2 bytes, 1 UTF-16 unit; 😀: 4 bytes,
/// 2 units), including edits spanning lines: after them, the server's diagnostics are those
/// `mapc check` gives for the text the client holds, so both hold the same text.
#[test]
fn incremental_edits_keep_the_server_in_step() {
    let (path, mut text) = fixture();
    let uri = file_uri(&path);
    let dir = tempfile::tempdir().expect("tempdir");
    let mut c = Client::start(&[], dir.path());
    c.initialize();
    c.open(&uri, &text);
    c.diagnostics(&uri, 1);
    let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
    let mut rand = |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    let mut seen = std::collections::BTreeSet::new();
    let position = |t: &str, byte: usize| {
        let line_start = t[..byte].rfind('\n').map_or(0, |i| i + 1);
        pos(
            t[..byte].matches('\n').count() as u32,
            t[line_start..byte].encode_utf16().count() as u32,
        )
    };
    let inserts = ["", "1", "é", "😀", "9", "x😀é", "0", " "];
    for version in 2..=41 {
        let boundary = |t: &str, mut b: usize| {
            while !t.is_char_boundary(b) {
                b -= 1;
            }
            b
        };
        // Entry lines (`      - [...]`): vertices, lanes, walls, doors.
        let entries: Vec<(usize, &str)> = {
            let mut off = 0;
            let mut v = Vec::new();
            for l in text.split_inclusive('\n') {
                if l.starts_with("      - [") {
                    v.push((off, l));
                }
                off += l.len();
            }
            v
        };
        let i = rand(entries.len() - 1);
        let ((a, la), (b, lb)) = (entries[i], entries[i + 1]);
        let (start, end, new) = if a + la.len() == b && rand(3) == 0 {
            // Two neighbouring entries swapped: an edit over two lines.
            (a, a + la.len() + lb.len(), format!("{lb}{la}"))
        } else {
            // Inside the brackets, before the params: indices, coordinates, names.
            let (off, line) = entries[rand(entries.len())];
            let lo = off + line.find('[').unwrap() + 1;
            let hi = off + line.find('{').or(line.find(']')).unwrap();
            let start = boundary(&text, lo + rand(hi - lo));
            // A digit may be replaced by something (an empty entry would be a YAML error);
            // anything else is an insertion.
            if text.as_bytes()[start].is_ascii_digit() && rand(2) == 0 {
                (
                    start,
                    start + 1,
                    inserts[1 + rand(inserts.len() - 2)].to_string(),
                )
            } else {
                (start, start, inserts[rand(inserts.len())].to_string())
            }
        };
        let range = json!({"start": position(&text, start), "end": position(&text, end)});
        text.replace_range(start..end, &new);
        c.notify("textDocument/didChange", json!({"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"range": range, "text": new}]}));
        if version % 10 == 1 {
            let mut got: Vec<(String, u64, u64)> = c
                .diagnostics(&uri, version)
                .iter()
                .map(|d| {
                    (
                        d["code"].as_str().unwrap_or("").to_string(),
                        d["range"]["start"]["line"].as_u64().unwrap(),
                        d["range"]["start"]["character"].as_u64().unwrap(),
                    )
                })
                .collect();
            got.sort();
            assert_eq!(
                got,
                check_positions(dir.path(), &text),
                "after edit {version}"
            );
            assert!(
                !got.iter().any(|d| d.0 == "E0001"),
                "the edits keep the YAML valid:\n{text}"
            );
            seen.extend(got.into_iter().map(|d| d.0));
        }
    }
    // The edits made the map say different things along the way.
    assert!(seen.len() >= 5, "{seen:?}");
    assert_eq!(c.shutdown(), 0);
}

#[test]
fn symbols_of_a_two_level_map_with_a_lift() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/two_level_clinic.building.yaml");
    let text = std::fs::read_to_string(&path).unwrap();
    let uri = file_uri(&path);
    let dir = tempfile::tempdir().expect("tempdir");
    let mut c = Client::start(&[], dir.path());
    c.initialize();
    c.open(&uri, &text);
    c.diagnostics(&uri, 1);
    let syms = c.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri}}),
    );
    let top: Vec<(String, u64, u64)> = syms
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["name"].as_str().unwrap().to_string(),
                s["kind"].as_u64().unwrap(),
                s["selectionRange"]["start"]["line"].as_u64().unwrap(),
            )
        })
        .collect();
    let line = |s: &str| find(&text, s).0 as u64;
    // Levels (namespace 3), then the lift (class 5), then graphs (struct 23; none here).
    assert_eq!(
        top,
        [
            ("L1".to_string(), 3, line("  L1:")),
            ("L2".to_string(), 3, line("  L2:")),
            ("lift_1".to_string(), 5, line("  lift_1:")),
        ]
    );
    let l2: Vec<&str> = syms[1]["children"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(&l2[..2], ["L2_ward_a_door", "L2_ward_b_door"]);
    assert_eq!(c.shutdown(), 0);
}

#[test]
fn bad_input_never_stops_the_server() {
    let dir = tempfile::tempdir().expect("tempdir");
    let uri = file_uri(&dir.path().join("broken.building.yaml"));
    let mut c = Client::start(&[], dir.path());
    c.initialize();
    let text = "levels: {L1: [1, 2}\n\t😀\u{0}\n";
    c.open(&uri, text);
    let d = c.diagnostics(&uri, 1);
    assert_eq!(codes(&d), ["E0001"]);
    for method in [
        "textDocument/hover",
        "textDocument/definition",
        "textDocument/references",
    ] {
        let r = c.request(method, json!({"textDocument": {"uri": uri}, "position": pos(1, 2), "context": {"includeDeclaration": true}}));
        assert!(r.is_null() || r == json!([]), "{method}: {r}");
    }
    assert_eq!(
        c.request(
            "textDocument/documentSymbol",
            json!({"textDocument": {"uri": uri}})
        ),
        json!([])
    );
    // Positions past the end, inside a surrogate pair, reversed ranges: clamped, not fatal.
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2}, "contentChanges": [
            {"range": {"start": pos(1, 2), "end": pos(1, 2)}, "text": "x"},
            {"range": {"start": pos(99, 99), "end": pos(0, 3)}, "text": "y"},
            {"range": {"start": pos(1, 1), "end": pos(1, 2)}, "text": ""}
        ]}),
    );
    c.diagnostics(&uri, 2);
    // Malformed params are an error answer, and the server goes on.
    let id = c.send_request("textDocument/hover", json!({"bogus": true}));
    assert_eq!(c.response(id)["error"]["code"], -32602);
    c.notify("textDocument/didChange", json!({"textDocument": {"uri": uri, "version": 3}, "contentChanges": [{"text": "name: ok\nlevels: {L1: {vertices: [[0, 0, 0, a]]}}\n"}]}));
    let d = c.diagnostics(&uri, 3);
    assert!(!codes(&d).contains(&"E0001".to_string()), "{d:?}");
    assert_eq!(c.shutdown(), 0);
}

/// An rmf_site `.site.json` is checked like `mapc check` checks it: walls, floors and
/// doors on the site's shared anchors are fine; the lane on a site anchor gets W0123 on
/// that anchor id; a lane edited to a missing anchor gets E0121 on the id, and document
/// symbols name the site's levels and doors.
#[test]
fn rmf_site_documents_with_site_anchors() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/sites/shared_anchors.site.json");
    let text = std::fs::read_to_string(&path).expect("fixture");
    let uri = file_uri(&path);
    let dir = tempfile::tempdir().expect("tempdir");
    let mut c = Client::start(&[], dir.path());
    c.initialize();
    c.open(&uri, &text);
    let d = c.diagnostics(&uri, 1);
    assert_eq!(codes(&d), ["W0123"], "{d:?}");
    let (line, col) = find(&text, r#""42": {"anchors": [15, 3]"#);
    let at = col + r#""42": {"anchors": [15, "#.len() as u32;
    assert_eq!(diag(&d, "W0123")["range"]["start"], pos(line, at));
    assert_eq!(diag(&d, "W0123")["severity"], 2);

    let symbols = c.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": uri}}),
    );
    let names: Vec<&str> = symbols
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"ground") && names.contains(&"upper"),
        "{names:?}"
    );

    let bad = text.replace(
        r#""40": {"anchors": [14, 15]"#,
        r#""40": {"anchors": [14, 999]"#,
    );
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": bad}]}),
    );
    let d = c.diagnostics(&uri, 2);
    // With lane 40 gone, nothing crosses `lab_door` and (15, 16) is cut off on `ground`.
    assert_eq!(codes(&d), ["E0121", "W0123", "W0208", "W0306"], "{d:?}");
    assert_eq!(diag(&d, "E0121")["range"]["start"], {
        let (l, c) = find(&bad, "999");
        pos(l, c)
    });
    assert_eq!(c.shutdown(), 0);
}
