//! `mapc crowdsim MAP CONFIG_DIR WORLD`: a drop-in for `building_crowdsim`, which
//! rmf_demos_maps' CMakeLists.txt runs for every map after the world. It writes the Menge
//! files (`behavior_file.xml`, `scene_file.xml`, `<level>_navmesh.nav`: the same bytes
//! `mapc gazebo` puts in `config_resource/`) into CONFIG_DIR, and makes WORLD hold the
//! `crowd_simulation` plugin: a world mapc wrote already does (from the same map), any
//! other gets the block inserted before `</world>`, replacing an older one, as upstream
//! does. A map whose crowd_sim is absent or disabled writes nothing and succeeds, like
//! upstream ("crowdsim unable to parse, not attempting to proceed").

use crate::{emit, load_and_check, not_written, output, summary_line, DiagOpts, Format};
use mapc_backends::sdf::crowd::{crowd_files, crowd_plugin, CROWD_DIR};
use mapc_backends::OutputFile;
use mapc_ir::lints::Outputs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct CrowdsimArgs {
    /// The .building.yaml (or legacy .project.yaml) to read.
    input: PathBuf,
    /// Directory for the Menge files (MENGE_RESOURCE_PATH); created if missing.
    output_dir: PathBuf,
    /// The world file that gets the crowd_simulation plugin (left alone if missing).
    world_file: PathBuf,
    /// Accepted and ignored: building_crowdsim's free-form options.
    #[arg(short = 'o', long = "options", value_name = "OPT", num_args = 0..)]
    _options: Vec<String>,
    #[command(flatten)]
    diag: DiagOpts,
}

pub(crate) fn run(args: &CrowdsimArgs) -> ExitCode {
    let wanted = Outputs::WORLDS;
    let checked = match load_and_check(&args.input, &args.diag.lints) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    emit(&checked, &args.diag, crate::report::Style::OneLine);
    if args.diag.format == Format::Human {
        summary_line(&args.input, &checked);
    }
    if !checked.blocked(wanted).is_empty() {
        not_written(&args.input, &checked, wanted, wanted);
        return ExitCode::from(1);
    }
    let Some(b) = checked.parsed.building.as_ref() else {
        return ExitCode::from(1);
    };
    let label = crate::build::map_name(&args.input);
    let Some(plugin) = crowd_plugin(b) else {
        if !args.diag.quiet {
            eprintln!("{label}: crowd_sim is not enabled: nothing to write");
        }
        return ExitCode::SUCCESS;
    };
    let files: Vec<OutputFile> = crowd_files(b)
        .into_iter()
        .map(|f| OutputFile {
            path: f
                .path
                .strip_prefix(CROWD_DIR)
                .map(Path::to_path_buf)
                .unwrap_or(f.path),
            contents: f.contents,
        })
        .collect();
    let written =
        match output::single_write(&args.output_dir, "CONFIG_DIR", &files, "crowdsim", &label) {
            Ok(w) => w,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
    if let Ok(world) = std::fs::read_to_string(&args.world_file) {
        let block = plugin.to_document(false);
        if let Some(new) = with_plugin(&world, &block) {
            if new != world {
                if let Err(e) = output::write_atomic(&args.world_file, new.as_bytes()) {
                    eprintln!("error: {}: {e}", args.world_file.display());
                    return ExitCode::from(2);
                }
            }
        } else {
            eprintln!(
                "error: {}: no <world> element to add the crowd_simulation plugin to",
                args.world_file.display()
            );
            return ExitCode::from(1);
        }
    }
    if !args.diag.quiet {
        crate::success_line(
            &label,
            &crate::plural(files.len(), "crowd file"),
            &args.output_dir,
            written,
            checked.diagnostics.len(),
        );
    }
    ExitCode::SUCCESS
}

/// `world` with exactly one crowd_simulation plugin, `block`, as the last child of its
/// `<world>`: an existing block equal to `block` is kept as is; a different one is
/// replaced. `None` when the text has no `</world>`.
fn with_plugin(world: &str, block: &str) -> Option<String> {
    let end = world.rfind("</world>")?;
    let block = block.trim_end();
    if let Some(start) = world.find("<plugin filename=\"libcrowd_simulator.so\"") {
        let close = world[start..].find("</plugin>")? + start + "</plugin>".len();
        let old = &world[start..close];
        // Compare ignoring indentation (mapc indents the block inside the world).
        let norm = |s: &str| s.lines().map(str::trim).collect::<Vec<_>>().join("\n");
        if norm(old) == norm(block) {
            return Some(world.to_string());
        }
        let mut out = String::with_capacity(world.len() + block.len());
        out.push_str(&world[..start]);
        out.push_str(block);
        out.push_str(&world[close..]);
        return Some(out);
    }
    let line_start = world[..end].rfind('\n').map_or(0, |i| i + 1);
    let indent = &world[line_start..end];
    let mut out = String::with_capacity(world.len() + block.len() + 64);
    out.push_str(&world[..end]);
    for l in block.lines() {
        out.push_str("  ");
        out.push_str(l);
        out.push('\n');
        out.push_str(indent);
    }
    out.push_str(&world[end..]);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::with_plugin;

    #[test]
    fn inserts_keeps_or_replaces_the_block() {
        let block = "<plugin filename=\"libcrowd_simulator.so\" name=\"crowd_simulation\">\n  <a>1</a>\n</plugin>\n";
        let world = "<sdf>\n  <world name=\"w\">\n    <x/>\n  </world>\n</sdf>\n";
        let once = with_plugin(world, block).unwrap();
        assert!(once.contains("<a>1</a>") && once.ends_with("</world>\n</sdf>\n"));
        assert_eq!(with_plugin(&once, block).unwrap(), once);
        let other = block.replace("<a>1</a>", "<a>2</a>");
        let twice = with_plugin(&once, &other).unwrap();
        assert_eq!(twice.matches("libcrowd_simulator").count(), 1);
        assert!(twice.contains("<a>2</a>"));
        assert!(with_plugin("<sdf/>", block).is_none());
    }
}
