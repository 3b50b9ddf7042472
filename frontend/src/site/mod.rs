//! rmf_site's `.site.json` into the mapc IR.
//!
//! The file is read with the frontend's located tree reader (JSON is a subset of YAML
//! 1.2, and the reader keeps the line and column of every value), so every element of a
//! site has a span like the elements of a `.building.yaml`. `lower.rs` then maps the site
//! model (one site-wide id space, anchors, site-wide lanes, locations and graphs, lifts
//! on site anchors with cabin-frame anchors) onto the IR the rules and backends share.
//! docs/sites.md says what maps to what.

pub mod codes;
mod lower;

use mapc_ir::{Building, Diagnostic, FileId};

/// The major `format_version` mapc reads (rmf_site_format 0.0.2 writes "0.1").
pub const FORMAT_MAJOR: u32 = 0;
/// Key of mapc's own data in the site's `extensions.data`: what a `.building.yaml` says
/// and rmf_site has no field for (vertex parameters, door plugins, lift floor ranges, the
/// coordinate system), so that a conversion round trip keeps it.
pub const EXTENSION_KEY: &str = "mapc";

/// Is `name` a site file (by its extension)?
pub fn is_site_file(name: &str) -> bool {
    name.ends_with(".site.json")
}

pub(crate) fn parse_into(
    file: FileId,
    text: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<Building> {
    let root = match crate::yaml::parse(text, file) {
        Ok(r) => r,
        Err(mut d) => {
            if d.code == "E0001" {
                d.message = d.message.replace("YAML", "JSON");
            }
            diags.push(d);
            return None;
        }
    };
    lower::SiteLower::new(diags).site(&root)
}
