//! The fast YAML reader must build exactly the general reader's tree whenever it accepts
//! an input (and must never accept input the general reader rejects).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Err(e) = mapc_frontend::fuzzing::yaml_differential(text) {
            panic!("{e}");
        }
    }
});
