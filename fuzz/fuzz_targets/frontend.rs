//! Frontend + validation passes + nav backend on arbitrary bytes: must never panic or hang.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let parsed = mapc_frontend::parse_str("fuzz.building.yaml", text);
    if let Some(b) = &parsed.building {
        let diags = mapc_ir::validate(b);
        if !parsed.has_errors() && !mapc_ir::has_errors(&diags) {
            let _ = mapc_backends::nav_graphs(b);
        }
    }
});
