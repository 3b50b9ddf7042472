//! Inputs that once crashed or hung mapc (found by fuzzing, see fuzz/README.md), plus the
//! invalid fixtures and our own maps: each must go through the frontend, every validation
//! pass and the nav backend without a panic, in under 2 s.

use std::path::Path;
use std::time::{Duration, Instant};

fn run(path: &Path) {
    let bytes = std::fs::read(path).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    let start = Instant::now();
    let result = std::panic::catch_unwind(|| {
        let parsed = mapc_frontend::parse_str("input.building.yaml", &text);
        if let Some(b) = &parsed.building {
            let diags = mapc_ir::validate(b);
            if !parsed.has_errors() && !mapc_ir::has_errors(&diags) {
                let _ = mapc_backends::nav_graphs(b);
            }
        }
    });
    assert!(result.is_ok(), "{} panicked", path.display());
    let took = start.elapsed();
    assert!(
        took < Duration::from_secs(2),
        "{} took {took:?}",
        path.display()
    );
}

#[test]
fn regression_inputs_and_fixtures_never_panic() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    for dir in ["tests/fuzz_regressions", "fixtures/invalid", "fixtures"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.is_file() && p.extension().is_some_and(|x| x == "yaml") {
                run(&p);
                n += 1;
            }
        }
    }
    assert!(n >= 20, "only {n} inputs");
}
