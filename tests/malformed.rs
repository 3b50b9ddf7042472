//! Malformed inputs: every one must be rejected with a located, coded diagnostic — never a
//! panic (exit 101), never a partial output.
//!
//! Each case is run twice:
//! * through the real binary (`mapc nav <file> <outdir>`): exit code, the one-line
//!   `file:LINE:COL: error[CODE]: ...` of the drop-in in stderr, and an output directory left
//!   untouched;
//! * in process (`mapc_frontend::parse_str`, or `load` for non-UTF-8 bytes): `has_errors()`,
//!   the code and the span, and a time bound.
//!
//! Expected locations are computed from the inline input text (the position of a needle),
//! so they stay right if a case is edited.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// Where the diagnostic must point.
#[derive(Clone, Copy, Debug)]
enum At {
    /// The first occurrence of this text in the input.
    Start(&'static [u8]),
    /// Just after the first occurrence of this text.
    After(&'static [u8]),
    /// The end of the input (an unterminated construct).
    End,
    /// Any column of this 1-based line (for resource limits, whose exact trigger point
    /// depends on the limit's value).
    Line(u32),
}

struct Case {
    name: &'static str,
    input: Vec<u8>,
    /// 0 for warning-only inputs, 1 for invalid maps.
    exit: i32,
    code: &'static str,
    at: At,
}

fn case(name: &'static str, input: impl Into<Vec<u8>>, code: &'static str, at: At) -> Case {
    Case {
        name,
        input: input.into(),
        exit: 1,
        code,
        at,
    }
}

/// Two vertices on level L1, followed by `rest` (indented for the level's mapping).
fn two_vertices(rest: &str) -> String {
    format!("name: x\nlevels:\n  L1:\n    vertices:\n      - [0, 0, 0, a]\n      - [10, 0, 0, b]\n{rest}")
}

fn alias_bomb() -> String {
    // "Billion laughs": 9 levels of 9 aliases each, ~387 million nodes if expanded.
    let mut s = String::from("name: x\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a]]\n");
    s.push_str("a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol]\n");
    for i in 1..10 {
        let refs = vec![format!("*a{}", i - 1); 9].join(", ");
        s.push_str(&format!("a{i}: &a{i} [{refs}]\n"));
    }
    s
}

fn deep_flow() -> String {
    format!(
        "name: x\nlevels:\n  L1:\n    vertices: {}{}\n",
        "[".repeat(200),
        "]".repeat(200)
    )
}

fn deep_block() -> String {
    let mut s = String::from("name: x\nlevels:\n");
    for i in 0..200 {
        s.push_str(&format!("{}k{i}:\n", "  ".repeat(i + 1)));
    }
    s
}

fn cases() -> Vec<Case> {
    vec![
        // --- not YAML at all ---
        case(
            "binary_junk_png_header",
            &b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\x01\0"[..],
            "E0003",
            At::Start(b"\x89"),
        ),
        case(
            "binary_junk_nul_bytes",
            &b"\0\0PK\x03\x04\x14\0\x06\0"[..],
            "E0001",
            At::Start(b"\0"),
        ),
        case(
            "unbalanced_open_brackets",
            "name: x\nlevels: {L1: {vertices: [[1, 2, 0, a]]\n",
            "E0001",
            At::End,
        ),
        case(
            "unbalanced_close_bracket",
            "name: x\nlevels: ]\n",
            "E0001",
            At::Start(b"]"),
        ),
        case(
            "tab_indentation",
            "name: x\nlevels:\n\tL1: {}\n",
            "E0001",
            At::After(b"\n\t"),
        ),
        case(
            "two_documents",
            "name: x\nlevels: {L1: {}}\n---\nname: y\n",
            "E0001",
            At::Start(b"---"),
        ),
        case(
            "unknown_alias",
            "name: x\nlevels: *nowhere\n",
            "E0001",
            At::Start(b"*nowhere"),
        ),
        case(
            "non_utf8_bytes",
            &b"name: x\nlevels:\n  L1:\n    vertices:\n      - [0, 0, 0, caf\xe9]\n"[..],
            "E0003",
            At::Start(b"\xe9"),
        ),
        // --- wrong document shape ---
        case("empty_file", "", "E0102", At::End),
        case(
            "comment_only",
            "# nothing here\n",
            "E0102",
            At::Start(b"#"),
        ),
        case(
            "root_is_a_list",
            "- name: x\n- levels: {}\n",
            "E0101",
            At::Start(b"- name"),
        ),
        case(
            "root_is_a_scalar",
            "just some words\n",
            "E0101",
            At::Start(b"just"),
        ),
        case(
            "missing_name",
            "levels:\n  L1:\n    vertices: [[0, 0, 0, a]]\n",
            "E0102",
            At::Start(b"levels"),
        ),
        case(
            "missing_levels",
            "name: x\nlifts: {}\n",
            "E0102",
            At::Start(b"name"),
        ),
        case(
            "levels_empty_map",
            "name: x\nlevels: {}\n",
            "E0110",
            At::Start(b"{}"),
        ),
        case(
            "levels_is_a_list",
            "name: x\nlevels: [L1, L2]\n",
            "E0101",
            At::Start(b"[L1"),
        ),
        // --- vertices ---
        case(
            "vertex_with_3_elements",
            "name: x\nlevels:\n  L1:\n    vertices:\n      - [0, 0, 0, a]\n      - [1, 2, 0]\n",
            "E0101",
            At::Start(b"[1, 2, 0]"),
        ),
        case(
            "vertex_coordinate_is_a_string",
            "name: x\nlevels:\n  L1:\n    vertices:\n      - [0, 0, 0, a]\n      - [\"12.5m\", 2, 0, b]\n",
            "E0101",
            At::Start(b"\"12.5m\""),
        ),
        case(
            "vertex_coordinate_nan",
            "name: x\nlevels:\n  L1:\n    vertices:\n      - [0, .nan, 0, a]\n",
            "E0104",
            At::Start(b".nan"),
        ),
        case(
            "vertex_coordinate_inf",
            "name: x\nlevels:\n  L1:\n    vertices:\n      - [-.inf, 0, 0, a]\n",
            "E0104",
            At::Start(b"-.inf"),
        ),
        case(
            "vertex_coordinate_overflows_to_inf",
            "name: x\nlevels:\n  L1:\n    vertices:\n      - [0, 0, 0, a]\n      - [1e999, 0, 0, b]\n",
            "E0104",
            At::Start(b"1e999"),
        ),
        // --- edges and parameters ---
        case(
            "lane_index_out_of_range",
            two_vertices("    lanes:\n      - [0, 7, {graph_idx: [2, 0]}]\n"),
            "E0103",
            At::Start(b"7,"),
        ),
        case(
            "lane_index_negative",
            two_vertices("    lanes:\n      - [-1, 1, {graph_idx: [2, 0]}]\n"),
            "E0103",
            At::Start(b"-1"),
        ),
        case(
            "lane_index_not_an_integer",
            two_vertices("    lanes:\n      - [0, 0.5, {graph_idx: [2, 0]}]\n"),
            "E0101",
            At::Start(b"0.5"),
        ),
        case(
            "lane_without_graph_idx",
            two_vertices("    lanes:\n      - [0, 1, {bidirectional: [4, true]}]\n"),
            "E0102",
            At::Start(b"[0, 1, {bid"),
        ),
        case(
            "lane_with_one_element",
            two_vertices("    lanes:\n      - [0]\n"),
            "E0101",
            At::Start(b"[0]"),
        ),
        case(
            "lanes_is_a_mapping",
            two_vertices("    lanes: {a: b}\n"),
            "E0101",
            At::Start(b"{a: b}"),
        ),
        case(
            "param_not_a_pair",
            two_vertices("    lanes:\n      - [0, 1, {graph_idx: 0}]\n"),
            "E0105",
            At::After(b"graph_idx: "),
        ),
        case(
            "param_bool_with_string_code",
            two_vertices(
                "    lanes:\n      - [0, 1, {graph_idx: [2, 0], bidirectional: [1, yes]}]\n",
            ),
            "E0105",
            At::Start(b"[1, yes]"),
        ),
        case(
            "param_int_code_with_string_value",
            two_vertices("    lanes:\n      - [0, 1, {graph_idx: [2, \"0\"]}]\n"),
            "E0105",
            At::Start(b"\"0\""),
        ),
        case(
            "param_unknown_type_code",
            two_vertices("    lanes:\n      - [0, 1, {graph_idx: [7, 0]}]\n"),
            "E0105",
            At::After(b"graph_idx: ["),
        ),
        case(
            "vertex_param_not_a_pair",
            "name: x\nlevels:\n  L1:\n    vertices:\n      - [0, 0, 0, a, {is_charger: true}]\n",
            "E0105",
            At::Start(b"true"),
        ),
        case(
            "door_without_name",
            two_vertices("    doors:\n      - [0, 1, {type: [1, hinged]}]\n"),
            "E0102",
            At::Start(b"[0, 1, {type"),
        ),
        case(
            "zero_length_measurement",
            two_vertices("    measurements:\n      - [0, 0, {distance: [3, 2.0]}]\n"),
            "E0109",
            At::Start(b"[0, 0, {dist"),
        ),
        case(
            "measurement_without_distance",
            two_vertices("    measurements:\n      - [0, 1, {}]\n"),
            "E0102",
            At::Start(b"[0, 1, {}]"),
        ),
        // --- building-level references ---
        case(
            "unknown_coordinate_system",
            "name: x\ncoordinate_system: lat_lon\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a]]\n",
            "E0106",
            At::Start(b"lat_lon"),
        ),
        case(
            "wgs84_without_generate_crs",
            "name: x\ncoordinate_system: wgs84\nlevels:\n  L1:\n    vertices: [[103.8, 1.3, 0, a]]\n",
            "E0108",
            At::Start(b"wgs84"),
        ),
        case(
            "wgs84_unknown_crs",
            "name: x\ncoordinate_system: wgs84\nparameters:\n  generate_crs: [1, \"EPSG:99999\"]\nlevels:\n  L1:\n    vertices: [[103.8, 1.3, 0, a]]\n",
            "E0108",
            At::Start(b"[1, \"EPSG"),
        ),
        case(
            "reference_level_name_missing_level",
            "name: x\nreference_level_name: L2\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a]]\n",
            "E0107",
            At::Start(b"L2"),
        ),
        case(
            "lift_level_doors_missing_level",
            "name: x\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a]]\nlifts:\n  LA:\n    x: 1\n    y: 2\n    yaw: 0\n    width: 2\n    depth: 2\n    level_doors:\n      L9: [door1]\n",
            "E0107",
            At::Start(b"L9"),
        ),
        case(
            "lift_reference_floor_missing_level",
            "name: x\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a]]\nlifts:\n  LA: {x: 1, y: 2, yaw: 0, width: 2, depth: 2, reference_floor_name: B3}\n",
            "E0107",
            At::Start(b"B3"),
        ),
        case(
            "lift_missing_width",
            "name: x\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a]]\nlifts:\n  LA:\n    x: 1\n    y: 2\n    yaw: 0\n    depth: 2\n",
            "E0102",
            At::Start(b"x: 1"),
        ),
        // --- resource limits ---
        case("alias_bomb", alias_bomb(), "E0002", At::Line(0)),
        case("deep_flow_nesting", deep_flow(), "E0002", At::Line(4)),
        case("deep_block_nesting", deep_block(), "E0002", At::Line(0)),
        // --- warnings only: the map is still compiled ---
        Case {
            exit: 0,
            ..case(
                "duplicate_keys_warn_only",
                two_vertices("    lanes:\n      - [0, 1, {graph_idx: [2, 0]}]\nname: y\n"),
                "W0102",
                At::Start(b"name: y"),
            )
        },
    ]
}

/// 1-based (line, column in characters) of byte offset `off`, as codespan prints it.
fn line_col(text: &[u8], off: usize) -> (u32, u32) {
    let before = &text[..off];
    let line = before.iter().filter(|&&c| c == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&c| c == b'\n')
        .map_or(0, |i| i + 1);
    let col = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    (line as u32, col as u32)
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// The expected (line, Some(col)), or (line, None) for any column. `Line(0)` means "any
/// line" (the limits' own test checks the range).
fn expected(c: &Case) -> (u32, Option<u32>) {
    let pos = |off: usize| {
        let (l, col) = line_col(&c.input, off);
        (l, Some(col))
    };
    match c.at {
        At::Start(n) => pos(find(&c.input, n).unwrap_or_else(|| panic!("{}: needle", c.name))),
        At::After(n) => {
            pos(find(&c.input, n).unwrap_or_else(|| panic!("{}: needle", c.name)) + n.len())
        }
        At::End => pos(c.input.len()),
        At::Line(l) => (l, None),
    }
}

/// The `(line, col)` that `mapc nav` printed for `file` in each one-line diagnostic with
/// `code` (`file:LINE:COL: error[CODE]: ...`).
fn positions_of(stderr: &str, code: &str, file: &str) -> Vec<(u32, u32)> {
    let header = format!("[{code}]: ");
    let mut out = Vec::new();
    for l in stderr.lines() {
        let Some(rest) = l.strip_prefix(file).and_then(|r| r.strip_prefix(':')) else {
            continue;
        };
        let mut it = rest.splitn(3, ':');
        if let (Some(Ok(line)), Some(Ok(col)), Some(tail)) = (
            it.next().map(str::parse::<u32>),
            it.next().map(str::parse::<u32>),
            it.next(),
        ) {
            if tail.contains(&header) {
                out.push((line, col));
            }
        }
    }
    out
}

fn mapc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_mapc"))
}

fn run_nav(input: &Path, out: &Path) -> Output {
    mapc()
        .arg("nav")
        .arg(input)
        .arg(out)
        .output()
        .expect("run mapc")
}

fn exit_code(o: &Output) -> i32 {
    o.status.code().unwrap_or(-1)
}

fn dir_entries(dir: &Path) -> Vec<PathBuf> {
    match std::fs::read_dir(dir) {
        Ok(rd) => rd.map(|e| e.unwrap().path()).collect(),
        Err(_) => Vec::new(),
    }
}

/// Checks one case through the binary; returns the problems found.
fn check_cli(c: &Case, tmp: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    let input = tmp.join(format!("{}.building.yaml", c.name));
    std::fs::write(&input, &c.input).unwrap();
    let out = tmp.join(format!("{}-out", c.name));
    let o = run_nav(&input, &out);
    let code = exit_code(&o);
    let stderr = String::from_utf8_lossy(&o.stderr);
    let file = input.display().to_string();
    if code == 101 {
        problems.push(format!("PANIC (exit 101):\n{stderr}"));
        return problems;
    }
    if code != c.exit {
        problems.push(format!("exit code {code}, expected {}", c.exit));
    }
    if !stderr.contains(&format!("[{}]", c.code)) {
        problems.push(format!("no diagnostic [{}] in stderr:\n{stderr}", c.code));
        return problems;
    }
    let (line, col) = expected(c);
    let found = positions_of(&stderr, c.code, &file);
    let ok = found
        .iter()
        .any(|&(l, cc)| (line == 0 || l == line) && col.is_none_or(|col| cc == col));
    if !ok {
        problems.push(format!(
            "[{}] should point at {file}:{line}:{} (found {found:?}); stderr:\n{stderr}",
            c.code,
            col.map_or("*".to_string(), |c| c.to_string())
        ));
    }
    if c.exit == 0 {
        if !out.join("0.yaml").is_file() {
            problems.push("a warning-only map must still be compiled (0.yaml missing)".into());
        }
    } else {
        if !stderr.contains("nothing written") {
            problems.push("stderr does not say `nothing written`".into());
        }
        let written = dir_entries(&out);
        if !written.is_empty() {
            problems.push(format!("files written for an invalid map: {written:?}"));
        }
    }
    problems
}

#[test]
fn cli_rejects_malformed_inputs_with_located_coded_diagnostics() {
    let tmp = tempfile::tempdir().unwrap();
    let all = cases();
    assert!(all.len() >= 20);
    let mut failures = Vec::new();
    for c in &all {
        let problems = check_cli(c, tmp.path());
        if !problems.is_empty() {
            failures.push(format!("--- case `{}`:\n{}", c.name, problems.join("\n")));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        all.len(),
        failures.join("\n")
    );
}

/// Runs `f` and returns its result and duration; when it exceeds `budget`, runs it once
/// more (a loaded CI machine can stall a process) and reports the faster run.
fn timed<T>(budget: Duration, mut f: impl FnMut() -> T) -> (T, Duration) {
    let t = Instant::now();
    let r = f();
    let d = t.elapsed();
    if d <= budget {
        return (r, d);
    }
    let t = Instant::now();
    let r2 = f();
    let d2 = t.elapsed();
    (r2, d.min(d2))
}

#[test]
fn in_process_parse_rejects_every_case_quickly() {
    let tmp = tempfile::tempdir().unwrap();
    let budget = Duration::from_secs(2);
    let mut failures = Vec::new();
    let mut slowest = (Duration::ZERO, "");
    for c in cases() {
        let name = format!("{}.building.yaml", c.name);
        let (parsed, took) = timed(budget, || match std::str::from_utf8(&c.input) {
            Ok(text) => mapc_frontend::parse_str(&name, text),
            // Not UTF-8: only the file loader can see these bytes.
            Err(_) => {
                let p = tmp.path().join(&name);
                std::fs::write(&p, &c.input).unwrap();
                mapc_frontend::load(&p).expect("readable file")
            }
        });
        let mut problems = Vec::new();
        if took > slowest.0 {
            slowest = (took, c.name);
        }
        if took > budget {
            problems.push(format!("took {took:?} (budget {budget:?})"));
        }
        if parsed.has_errors() != (c.exit != 0) {
            problems.push(format!(
                "has_errors() = {}, expected {}",
                parsed.has_errors(),
                c.exit != 0
            ));
        }
        if c.exit != 0 && parsed.valid_building().is_some() {
            problems.push("valid_building() is Some for an invalid map".into());
        }
        let (line, col) = expected(&c);
        let matches = parsed.diagnostics.iter().any(|d| {
            d.code == c.code
                && d.span.is_known()
                && (line == 0 || d.span.line == line)
                && col.is_none_or(|col| d.span.col == col)
        });
        if !matches {
            problems.push(format!(
                "no [{}] at {line}:{col:?} among {:?}",
                c.code,
                parsed
                    .diagnostics
                    .iter()
                    .map(|d| (d.code, d.span.line, d.span.col))
                    .collect::<Vec<_>>()
            ));
        }
        if !problems.is_empty() {
            failures.push(format!("--- case `{}`:\n{}", c.name, problems.join("\n")));
        }
    }
    eprintln!("slowest case: {} in {:?}", slowest.1, slowest.0);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Limits report somewhere inside the offending construct.
#[test]
fn resource_limits_point_into_the_construct() {
    let bomb = alias_bomb();
    let p = mapc_frontend::parse_str("bomb.building.yaml", &bomb);
    let d = p.diagnostics.iter().find(|d| d.code == "E0002").unwrap();
    let first_anchor = line_col(bomb.as_bytes(), find(bomb.as_bytes(), b"a1:").unwrap()).0;
    let last_line = bomb.lines().count() as u32;
    assert!(
        (first_anchor..=last_line).contains(&d.span.line),
        "{:?}",
        d.span
    );

    let deep = deep_block();
    let p = mapc_frontend::parse_str("deep.building.yaml", &deep);
    let d = p.diagnostics.iter().find(|d| d.code == "E0002").unwrap();
    // The depth limit is reached well inside the 200 nested keys (lines 3..=202).
    assert!((3..=202).contains(&d.span.line), "{:?}", d.span);
}

#[test]
fn multiple_errors_are_all_reported() {
    let text = "name: x\n\
                coordinate_system: lat_lon\n\
                levels:\n  \
                  L1:\n    \
                    vertices:\n      \
                      - [0, 0, 0, a]\n      \
                      - [5, 5, 0, b]\n      \
                      - [\"oops\", 0, 0, c]\n    \
                    lanes:\n      \
                      - [0, 9, {graph_idx: [2, 0]}]\n    \
                    doors:\n      \
                      - [0, 1, {type: [1, hinged]}]\n";
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("many.building.yaml");
    std::fs::write(&input, text).unwrap();
    let out = tmp.path().join("out");
    let o = run_nav(&input, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(exit_code(&o), 1, "{stderr}");
    let file = input.display().to_string();
    let at = |needle: &str| {
        let (l, c) = line_col(text.as_bytes(), text.find(needle).unwrap());
        format!("{file}:{l}:{c}")
    };
    let expected = [
        ("E0106", at("lat_lon")),
        ("E0101", at("\"oops\"")),
        ("E0103", at("9, {graph")),
        ("E0102", at("[0, 1, {type")),
    ];
    for (code, pos) in &expected {
        assert!(stderr.contains(&format!("[{code}]")), "{code}\n{stderr}");
        assert!(stderr.contains(pos.as_str()), "{pos}\n{stderr}");
    }
    // At least these four (validation passes may add more about the same defects).
    let errors = stderr.lines().filter(|l| l.contains(": error[")).count();
    assert!(errors >= 4, "expected at least 4 errors:\n{stderr}");
    assert!(dir_entries(&out).is_empty());
}

#[test]
fn failed_run_keeps_existing_output_byte_identical() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let old = b"# produced by an earlier, good run\nbuilding_name: keep_me\n\xff binary tail\n";
    std::fs::write(out.join("0.yaml"), old).unwrap();
    // Valid enough to reach lane 0 in graph 0, but with one error elsewhere.
    let input = tmp.path().join("bad.building.yaml");
    std::fs::write(
        &input,
        two_vertices(
            "    lanes:\n      - [0, 1, {graph_idx: [2, 0]}]\n      - [0, 5, {graph_idx: [2, 0]}]\n",
        ),
    )
    .unwrap();
    let o = run_nav(&input, &out);
    assert_eq!(exit_code(&o), 1, "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read(out.join("0.yaml")).unwrap(), old);
    assert_eq!(
        dir_entries(&out),
        vec![out.join("0.yaml")],
        "no stray files"
    );
}

#[test]
fn missing_input_file_is_an_io_error() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("no_such_map.building.yaml");
    let out = tmp.path().join("out");
    let o = run_nav(&input, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(exit_code(&o), 2, "{stderr}");
    assert!(stderr.contains(&input.display().to_string()), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn input_that_is_a_directory_is_an_io_error() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("dir.building.yaml");
    std::fs::create_dir(&input).unwrap();
    let out = tmp.path().join("out");
    let o = run_nav(&input, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(exit_code(&o), 2, "{stderr}");
    assert!(stderr.contains(&input.display().to_string()), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn output_dir_that_is_a_file_is_an_io_error() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("ok.building.yaml");
    std::fs::write(
        &input,
        two_vertices("    lanes:\n      - [0, 1, {graph_idx: [2, 0]}]\n"),
    )
    .unwrap();
    let out = tmp.path().join("out");
    std::fs::write(&out, "not a directory").unwrap();
    let o = run_nav(&input, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(exit_code(&o), 2, "{stderr}");
    assert_eq!(std::fs::read(&out).unwrap(), b"not a directory");
}

/// The harness itself: a valid map passes `check_cli`'s checks only as a warning case, and
/// a wrong expected position is detected (so the tests above can fail).
#[test]
fn harness_detects_wrong_expectations() {
    let tmp = tempfile::tempdir().unwrap();
    let bad_pos = case(
        "harness_wrong_position",
        "name: x\nlevels: {}\n",
        "E0110",
        At::Start(b"name"),
    );
    assert!(!check_cli(&bad_pos, tmp.path()).is_empty());
    let bad_code = case(
        "harness_wrong_code",
        "name: x\nlevels: {}\n",
        "E0999",
        At::Start(b"{}"),
    );
    assert!(!check_cli(&bad_code, tmp.path()).is_empty());
    let valid = case(
        "harness_valid_map",
        two_vertices("    lanes:\n      - [0, 1, {graph_idx: [2, 0]}]\n"),
        "W0106",
        At::Start(b"L1"),
    );
    // Expected exit 1, but the map is valid: must be flagged.
    assert!(!check_cli(&valid, tmp.path()).is_empty());
    let good = Case { exit: 0, ..valid };
    assert_eq!(check_cli(&good, tmp.path()), Vec::<String>::new());
}
