#[derive(clap::Args)]
pub(crate) struct DiffArgs {}
pub(crate) fn run(_: &DiffArgs) -> std::process::ExitCode { std::process::ExitCode::from(2) }
