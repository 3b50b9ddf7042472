//! Every diagnostic code mapc reports, in one list: the frontends', the validation rules',
//! the backends', the scenario runtime's and the sweep's. The CLI finds a code's name and
//! the user's `--allow CODE` here; nothing below this module imports from the rest of
//! `src/`.

pub(crate) mod sweep;

/// Stable name of a diagnostic code (`""` for a code no table lists).
pub(crate) fn code_name(code: &str) -> &'static str {
    mapc_frontend::CODES
        .iter()
        .chain(mapc_frontend::site::codes::CODES)
        .find(|c| c.code == code)
        .map(|c| c.name)
        .or_else(|| mapc_ir::rule(code).map(|r| r.name))
        .or_else(|| {
            mapc_backends::CODES
                .iter()
                .find(|c| c.code == code)
                .map(|c| c.name)
        })
        .or_else(|| {
            mapc_sim::codes::CODES
                .iter()
                .chain(sweep::CODES)
                .find(|c| c.code == code)
                .map(|c| c.name)
        })
        .unwrap_or("")
}
