//! What each diagnostic code means for the outputs: whether the user may allow it (or
//! lower it to a warning), and which outputs it blocks while it is an error. Each code
//! declares its [`Group`] where it is declared; the group gives the [`Policy`]. The CLI
//! applies the user's levels (`--allow`/`--warn`/`--deny`, `mapc.toml`);
//! docs/diagnostics.md shows the policy of every code.

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

/// The lint group of a diagnostic code: every code declares one beside its name (`Code`,
/// `Rule`), and the group says what an error of the code breaks and whether the user may
/// allow it. A new code picks a group; a new kind of consequence is a new group here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// Reading the file (E00xx, E01xx): the model itself is incomplete or wrong.
    Reading,
    /// A likely typo of a known key (E0112): the key is ignored, like an unknown key, so
    /// it may be allowed (the key really is an extension); as an error it blocks every
    /// output, as W0103 denied does.
    Typo,
    /// Frontend warnings (unknown keys, duplicate keys, alignment fallbacks, ...) may
    /// change anything.
    Frontend,
    /// Lanes: only the nav graphs.
    Lanes,
    /// Doors: the worlds' door models, the glTF door nodes, and door requests (nav graphs
    /// only when the map has lanes: a lane's `door_name` is what door requests use).
    Doors,
    /// Lift waypoints: what the fleet adapter reads (its parse_graph rejects them).
    LiftWaypoints,
    /// Lifts: the worlds' and glTF's cabins and the lift requests.
    Lifts,
    /// Robot spawns exist only in worlds.
    Spawns,
    /// Names and roles in the nav graphs.
    Names,
    /// Names that end up in file names, model names and graphs alike.
    FileNames,
    /// Control or bidi characters in a name that becomes a path or a model name: no
    /// correct file can be written (nor a depfile naming it).
    UnsafeNames,
    /// The scale of the whole map is in doubt.
    Scale,
    /// Lift geometry.
    LiftGeometry,
    /// Geometry only worlds use.
    WorldGeometry,
    /// Floors, walls and holes: every mesh.
    Geometry,
    /// Textures: every mesh.
    Textures,
    /// The crowd: the worlds' crowd plugin and Menge files (and `mapc sim`'s people).
    Crowd,
    /// Scenario and sweep files (S codes): they break the run, not a map's outputs.
    Scenario,
}

impl Group {
    /// How codes of the group may be treated.
    pub const fn policy(self) -> Policy {
        let (can_allow, blocks, nav_only_with_lanes) = match self {
            Group::Reading | Group::UnsafeNames => (false, Outputs::ALL, false),
            Group::Typo | Group::Frontend | Group::FileNames | Group::Scale => {
                (true, Outputs::ALL, false)
            }
            Group::Scenario => (true, Outputs::ALL, false),
            Group::Lanes | Group::LiftWaypoints | Group::Names => (true, Outputs::NAV, false),
            Group::Doors => (true, DOORS, true),
            Group::Lifts | Group::LiftGeometry => (true, LIFTS, false),
            Group::Spawns | Group::WorldGeometry | Group::Crowd => (true, Outputs::WORLDS, false),
            Group::Geometry | Group::Textures => (true, GEOMETRY, false),
        };
        Policy {
            can_allow,
            blocks,
            nav_only_with_lanes,
        }
    }
}

/// The policy of a code no table declares: allowed, and blocking everything while an
/// error (what it breaks is unknown).
pub const UNKNOWN_CODE: Policy = Policy {
    can_allow: true,
    blocks: Outputs::ALL,
    nav_only_with_lanes: false,
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issues_examples() {
        assert_eq!(Group::LiftWaypoints.policy().blocks, Outputs::NAV);
        let p = Group::Doors.policy();
        assert!(p.can_allow && p.blocks.intersects(Outputs::WORLDS) && p.nav_only_with_lanes);
        assert!(!Group::Reading.policy().can_allow);
        assert_eq!(Group::Reading.policy().blocks, Outputs::ALL);
        let typo = Group::Typo.policy();
        assert!(typo.can_allow && typo.blocks == Outputs::ALL);
        assert_eq!(
            Outputs::NAV.union(Outputs::WORLDS).names(),
            ["nav", "worlds"]
        );
    }
}
