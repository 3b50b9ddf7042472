//! What each diagnostic code means for the outputs: whether the user may allow it (or
//! lower it to a warning), and which outputs it blocks while it is an error. The CLI applies
//! the user's levels (`--allow`/`--warn`/`--deny`, `mapc.toml`); docs/diagnostics.md shows
//! this table for every code.

/// A set of output kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Outputs(u8);

impl Outputs {
    pub const NONE: Outputs = Outputs(0);
    /// Navigation graphs (and the door and lift requests fleet adapters derive from them).
    pub const NAV: Outputs = Outputs(1);
    /// The glTF scene.
    pub const GLTF: Outputs = Outputs(2);
    /// Level meshes (also inside every world's level models).
    pub const MESHES: Outputs = Outputs(4);
    /// Simulation worlds (gz, Ignition, classic) with their doors, lifts, models and robots.
    pub const WORLDS: Outputs = Outputs(8);
    pub const ALL: Outputs = Outputs(15);

    pub const fn union(self, o: Outputs) -> Outputs {
        Outputs(self.0 | o.0)
    }
    pub const fn intersects(self, o: Outputs) -> bool {
        self.0 & o.0 != 0
    }
    pub const fn intersection(self, o: Outputs) -> Outputs {
        Outputs(self.0 & o.0)
    }
    pub const fn without(self, o: Outputs) -> Outputs {
        Outputs(self.0 & !o.0)
    }
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Names for messages and docs: `nav`, `gltf`, `meshes`, `worlds`.
    pub fn names(self) -> Vec<&'static str> {
        [
            (Outputs::NAV, "nav"),
            (Outputs::GLTF, "gltf"),
            (Outputs::MESHES, "meshes"),
            (Outputs::WORLDS, "worlds"),
        ]
        .into_iter()
        .filter(|(o, _)| self.intersects(*o))
        .map(|(_, n)| n)
        .collect()
    }
}

/// How a code may be treated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Policy {
    /// False for errors after which no correct output can be written (unreadable input,
    /// an element dropped for a wrong type or a dangling index, no usable coordinates):
    /// they cannot be allowed or lowered to warnings.
    pub can_allow: bool,
    /// The outputs an error of this code (or a warning denied to an error) breaks; the
    /// others are still written.
    pub blocks: Outputs,
    /// The code is about doors: it breaks nav graphs only when the map has lanes (a lane's
    /// `door_name` is what door requests use).
    pub nav_only_with_lanes: bool,
}

const GEOMETRY: Outputs = Outputs::MESHES.union(Outputs::WORLDS).union(Outputs::GLTF);
const DOORS: Outputs = Outputs::WORLDS.union(Outputs::GLTF).union(Outputs::NAV);
const LIFTS: Outputs = Outputs::WORLDS.union(Outputs::GLTF).union(Outputs::NAV);

/// The policy of `code` (any code mapc reports on a map: `E`/`W` followed by 4 digits).
pub fn policy(code: &str) -> Policy {
    let allow = |blocks| Policy {
        can_allow: true,
        blocks,
        nav_only_with_lanes: false,
    };
    match code {
        // A likely typo of a known key (W0103's close cousin): the key is ignored, like an
        // unknown key, so the user may allow it or lower it to a warning (the key really is
        // an extension); while it is an error it blocks every output, as W0103 denied does.
        "E0112" => allow(Outputs::ALL),
        // Reading the file: the model itself is incomplete or wrong after these errors.
        c if c.starts_with("E00") || c.starts_with("E01") => Policy {
            can_allow: false,
            blocks: Outputs::ALL,
            nav_only_with_lanes: false,
        },
        // Frontend warnings (unknown keys, duplicate keys, alignment fallbacks, ...) may
        // change anything.
        // A site's lane or location on a site anchor, left out of the nav graphs.
        "W0123" => allow(Outputs::NAV),
        c if c.starts_with("W01") => allow(Outputs::ALL),
        // Lanes: only the nav graphs.
        c if c.starts_with("E02") || c.starts_with("W02") => allow(Outputs::NAV),
        // Doors: the worlds' door models, the glTF door nodes, and door requests.
        c if c.starts_with("E03") || c.starts_with("W03") => Policy {
            nav_only_with_lanes: true,
            ..allow(DOORS)
        },
        // Lift waypoints: what the fleet adapter reads (its parse_graph rejects them).
        "E0407" | "E0409" | "W0404" => allow(Outputs::NAV),
        c if c.starts_with("E04") || c.starts_with("W04") => allow(LIFTS),
        // Robot spawns exist only in worlds.
        "E0504" | "W0505" | "W0506" => allow(Outputs::WORLDS),
        // Names end up in file names, model names and graphs alike.
        "W0508" => allow(Outputs::ALL),
        // Control or bidi characters in a name that becomes a path or a model name: no
        // correct file can be written (nor a depfile naming it), so it cannot be allowed.
        "E0509" => Policy {
            can_allow: false,
            blocks: Outputs::ALL,
            nav_only_with_lanes: false,
        },
        c if c.starts_with("E05") || c.starts_with("W05") => allow(Outputs::NAV),
        // The scale of the whole map is in doubt.
        "W0606" => allow(Outputs::ALL),
        "W0607" => allow(LIFTS),
        "W0608" | "E0609" => allow(Outputs::WORLDS),
        c if c.starts_with("E06") || c.starts_with("W06") => allow(GEOMETRY),
        // Textures.
        c if c.starts_with("W07") => allow(GEOMETRY),
        // The crowd: the worlds' crowd plugin and Menge files (and `mapc sim`'s people).
        c if c.starts_with("E08") || c.starts_with("W08") => allow(Outputs::WORLDS),
        _ => allow(Outputs::ALL),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issues_examples() {
        assert_eq!(policy("E0407").blocks, Outputs::NAV);
        let p = policy("E0302");
        assert!(p.can_allow && p.blocks.intersects(Outputs::WORLDS) && p.nav_only_with_lanes);
        assert!(!policy("E0001").can_allow && !policy("E0103").can_allow);
        assert_eq!(policy("E0103").blocks, Outputs::ALL);
        let typo = policy("E0112");
        assert!(typo.can_allow && typo.blocks == Outputs::ALL);
        assert_eq!(
            Outputs::NAV.union(Outputs::WORLDS).names(),
            ["nav", "worlds"]
        );
    }
}
