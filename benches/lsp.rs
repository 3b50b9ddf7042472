//! Keystroke to diagnostics in `mapc lsp`: the time from sending a `didChange` that moves one
//! vertex of clinic (`../shared/maps/clinic`, 274 kB; the two-level clinic fixture when
//! ../shared is absent) to receiving the `publishDiagnostics` for that version. This is the
//! whole path an editor waits for: JSON-RPC in, the edit applied, parse, lower, transform,
//! every validation pass, lint levels, conversion to LSP ranges, JSON-RPC out.
//!
//! Run with `cargo bench --bench lsp`.

#[path = "../tests/support/lsp_client.rs"]
mod lsp_client;

use lsp_client::{file_uri, Client};
use serde_json::json;
use std::path::{Path, PathBuf};

fn main() {
    divan::main();
}

fn map() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let clinic = root.join("../shared/maps/clinic/clinic.building.yaml");
    if clinic.is_file() {
        clinic
    } else {
        eprintln!("skipped: ../shared not found (benchmarking the two-level clinic fixture)");
        root.join("fixtures/two_level_clinic.building.yaml")
    }
}

/// The line and UTF-16 columns of the first vertex's x coordinate.
fn first_vertex_x(text: &str) -> (u32, u32, u32, f64) {
    let mut in_vertices = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_end().ends_with("vertices:") {
            in_vertices = true;
            continue;
        }
        if in_vertices {
            if let Some(start) = line.find("- [") {
                let s = start + 3;
                let len = line[s..].find(',').expect("x,");
                let x: f64 = line[s..s + len].trim().parse().expect("x is a number");
                return (i as u32, s as u32, (s + len) as u32, x);
            }
        }
    }
    panic!("no vertex");
}

#[divan::bench(sample_count = 200)]
fn change_one_vertex_to_diagnostics(bencher: divan::Bencher) {
    let path = map();
    let text = std::fs::read_to_string(&path).expect("map");
    let uri = file_uri(&path);
    let dir = std::env::temp_dir();
    let mut c = Client::start(&[], &dir);
    c.initialize();
    c.open(&uri, &text);
    c.diagnostics(&uri, 1);
    let (line, start, end, x) = first_vertex_x(&text);
    let mut version = 1;
    let mut width = end - start;
    bencher.bench_local(|| {
        version += 1;
        // Moves the vertex by 0.5 (file units) and back, one edit per keystroke.
        let new = format!("{}", if version % 2 == 0 { x + 0.5 } else { x });
        c.notify(
            "textDocument/didChange",
            json!({"textDocument": {"uri": uri, "version": version},
                   "contentChanges": [{"range": {"start": {"line": line, "character": start},
                                                 "end": {"line": line, "character": start + width}},
                                       "text": new}]}),
        );
        width = new.len() as u32;
        divan::black_box(c.diagnostics(&uri, version));
    });
}
