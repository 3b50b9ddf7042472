//! `mapc crowdsim MAP CONFIG_DIR WORLD`: a drop-in for `building_crowdsim`, which
//! rmf_demos_maps' CMakeLists.txt runs for every map after the world. It writes the Menge
//! files (`behavior_file.xml`, `scene_file.xml`, `<level>_navmesh.nav`: the same bytes
//! `mapc gazebo` puts in `config_resource/`) into CONFIG_DIR, and makes WORLD hold the
//! `crowd_simulation` plugin: a world mapc wrote already does (from the same map), any
//! other gets the block inserted before `</world>`, replacing an older one, as upstream
//! does. The world is read as XML (quick-xml) to find both places; only those bytes change. A map whose crowd_sim is absent or disabled writes nothing and succeeds, like
//! upstream ("crowdsim unable to parse, not attempting to proceed").

use crate::driver::{self, output, CliError, DiagOpts, Outcome, Product, Spec};
use crate::ui::{plural, report::Style};
use mapc_backends::sdf::crowd::{crowd_files, crowd_plugin, CROWD_DIR};
use mapc_backends::OutputFile;
use mapc_ir::lints::Outputs;
use std::path::{Path, PathBuf};

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

pub(crate) fn run(args: &CrowdsimArgs) -> Result<Outcome, CliError> {
    let spec = Spec {
        name: "crowdsim",
        role: "CONFIG_DIR",
        kind: "crowd file",
        // A map without a crowd writes nothing and succeeds, like upstream.
        none: None,
        outputs: Outputs::WORLDS,
        // A drop-in for `building_crowdsim`: one line per diagnostic in build logs.
        style: Style::OneLine,
    };
    let c = driver::compile(&args.input, &args.diag, &spec, |r| {
        let b = r.require(Outputs::WORLDS);
        let files = crowd_plugin(b).map(|plugin| {
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
            (plugin.to_document(false), files)
        });
        Product {
            count: files.as_ref().map_or(0, |(_, f)| f.len()),
            files,
            diagnostics: Vec::new(),
        }
    })?;
    let Some((block, files)) = &c.files else {
        if !args.diag.quiet {
            eprintln!("{}: crowd_sim is not enabled: nothing to write", c.label);
        }
        return Ok(Outcome::Done);
    };
    let written = output::single_write(&args.output_dir, spec.role, files, spec.name, &c.label)?;
    if let Ok(world) = std::fs::read_to_string(&args.world_file) {
        let Some(new) = with_plugin(&world, block) else {
            return Err(CliError::Invalid(format!(
                "{}: no <world> element to add the crowd_simulation plugin to",
                args.world_file.display()
            )));
        };
        if new != world {
            output::write_atomic(&args.world_file, new.as_bytes())
                .map_err(|e| format!("{}: {e}", args.world_file.display()))?;
        }
    }
    if !args.diag.quiet {
        driver::finished(&c, &plural(c.count, spec.kind), &args.output_dir, written);
    }
    Ok(Outcome::Done)
}

/// Where the world's XML holds what matters: the `crowd_simulation` plugin element (byte
/// range, if any) and the start of `</world>`.
struct Places {
    plugin: Option<std::ops::Range<usize>>,
    world_end: usize,
}

/// Reads the world as XML (not by searching its text, which a comment or an attribute
/// order would fool). `None`: not XML, or no `<world>` element.
fn places(world: &str) -> Option<Places> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(world);
    let mut plugin = None;
    loop {
        let before = usize::try_from(reader.buffer_position()).ok()?;
        match reader.read_event().ok()? {
            Event::Start(e) if e.name().as_ref() == b"plugin" && is_crowd(&e) => {
                reader.read_to_end(e.name()).ok()?;
                let after = usize::try_from(reader.buffer_position()).ok()?;
                plugin.get_or_insert(before..after);
            }
            Event::Empty(e) if e.name().as_ref() == b"plugin" && is_crowd(&e) => {
                let after = usize::try_from(reader.buffer_position()).ok()?;
                plugin.get_or_insert(before..after);
            }
            Event::End(e) if e.name().as_ref() == b"world" => {
                return Some(Places {
                    plugin,
                    world_end: before,
                });
            }
            Event::Eof => return None,
            _ => {}
        }
    }
}

/// The crowd simulator's plugin: `filename="libcrowd_simulator.so"`.
fn is_crowd(e: &quick_xml::events::BytesStart) -> bool {
    e.attributes()
        .flatten()
        .any(|a| a.key.as_ref() == b"filename" && a.value.as_ref() == b"libcrowd_simulator.so")
}

/// `world` holding exactly `block` as its crowd plugin: kept when equal (but for
/// indentation), replaced when different, inserted before `</world>` when absent.
fn with_plugin(world: &str, block: &str) -> Option<String> {
    let at = places(world)?;
    let block = block.trim_end();
    if let Some(old) = at.plugin {
        // Compare ignoring indentation (mapc indents the block inside the world).
        let norm = |s: &str| s.lines().map(str::trim).collect::<Vec<_>>().join("\n");
        if norm(&world[old.clone()]) == norm(block) {
            return Some(world.to_string());
        }
        let mut out = String::with_capacity(world.len() + block.len());
        out.push_str(&world[..old.start]);
        out.push_str(block);
        out.push_str(&world[old.end..]);
        return Some(out);
    }
    let end = at.world_end;
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
        // XML, not text: a commented-out plugin is not the plugin, attributes may come in
        // any order.
        let commented = world.replace(
            "<x/>",
            "<!-- <plugin filename=\"libcrowd_simulator.so\"> -->",
        );
        let inserted = with_plugin(&commented, block).unwrap();
        assert_eq!(inserted.matches("<a>1</a>").count(), 1);
        let reordered = once.replace(
            "filename=\"libcrowd_simulator.so\" name=\"crowd_simulation\"",
            "name=\"crowd_simulation\" filename=\"libcrowd_simulator.so\"",
        );
        let replaced = with_plugin(&reordered, &other).unwrap();
        assert_eq!(replaced.matches("libcrowd_simulator").count(), 1);
        assert!(replaced.contains("<a>2</a>"));
    }
}
