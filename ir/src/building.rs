//! The building model: metres, map frame (the projected CRS for geographic maps, the
//! reference level's frame otherwise), y up, each level at its elevation.

use crate::{Arena, Handle, Params, Span};

/// A point or vector in the horizontal plane, metres.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec2 {
    pub x: f64,
    pub y: f64,
}

impl Vec2 {
    pub const fn new(x: f64, y: f64) -> Self {
        Vec2 { x, y }
    }
    pub fn minus(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
    pub fn plus(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x + o.x, self.y + o.y)
    }
    pub fn scale(self, k: f64) -> Vec2 {
        Vec2::new(self.x * k, self.y * k)
    }
    pub fn cross(self, o: Vec2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    pub fn dot(self, o: Vec2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    pub fn norm(self) -> f64 {
        self.x.hypot(self.y)
    }
    /// Counter-clockwise rotation by `theta` radians.
    pub fn rotate(self, theta: f64) -> Vec2 {
        let (s, c) = theta.sin_cos();
        Vec2::new(c * self.x - s * self.y, s * self.x + c * self.y)
    }
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoordinateSystem {
    ReferenceImage,
    CartesianMeters,
    Wgs84,
    WebMercator,
}

impl CoordinateSystem {
    pub fn as_str(self) -> &'static str {
        match self {
            CoordinateSystem::ReferenceImage => "reference_image",
            CoordinateSystem::CartesianMeters => "cartesian_meters",
            CoordinateSystem::Wgs84 => "wgs84",
            CoordinateSystem::WebMercator => "web_mercator",
        }
    }
}

/// `p_map = scale * R(rotation) * p_file' + translation`, where `p_file'` is the file
/// coordinate after the coordinate system's y flip or projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelTransform {
    pub scale: f64,
    pub rotation: f64,
    pub translation: Vec2,
}

impl Default for LevelTransform {
    fn default() -> Self {
        LevelTransform {
            scale: 1.0,
            rotation: 0.0,
            translation: Vec2::default(),
        }
    }
}

impl LevelTransform {
    pub fn apply(&self, p: Vec2) -> Vec2 {
        p.rotate(self.rotation)
            .scale(self.scale)
            .plus(self.translation)
    }

    /// The file coordinate (after the y flip) that `apply` takes to `p`, up to rounding.
    pub fn invert(&self, p: Vec2) -> Vec2 {
        p.minus(self.translation)
            .scale(1.0 / self.scale)
            .rotate(-self.rotation)
    }
}

#[derive(Debug, Clone)]
pub struct Building {
    pub name: String,
    pub coordinate_system: CoordinateSystem,
    /// Target CRS (`generate_crs`), e.g. `EPSG:3414`.
    pub crs_name: Option<String>,
    /// Offset that simulation worlds subtract so the site sits near the origin
    /// (`suggested_offset_*` for wgs84, `offset_*` for cartesian_meters). Nav graphs keep
    /// map-frame coordinates and publish the offset.
    pub offset: Vec2,
    pub reference_level: Handle<Level>,
    pub params: Params,
    pub levels: Arena<Level>,
    pub vertices: Arena<Vertex>,
    pub lanes: Arena<Lane>,
    pub walls: Arena<Wall>,
    pub measurements: Arena<Measurement>,
    pub doors: Arena<Door>,
    pub floors: Arena<Polygon>,
    pub holes: Arena<Polygon>,
    pub models: Arena<Model>,
    pub fiducials: Arena<Fiducial>,
    pub human_lanes: Arena<HumanLane>,
    pub lifts: Arena<Lift>,
    pub graphs: Vec<GraphInfo>,
    pub crowd_sim: Option<CrowdSim>,
    /// Unparsed legacy `map_version`, kept for exports.
    pub map_version: Option<String>,
    /// The file format the building was read from; a site's graphs are named, so its nav
    /// files are named after the graphs rather than numbered.
    pub format: SourceFormat,
    pub spans: BuildingSpans,
}

/// Where the building-wide keys are, for diagnostics about them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BuildingSpans {
    /// The whole document.
    pub root: Span,
    /// The `name` (or `building_name`) value.
    pub name: Span,
    /// The `coordinate_system` value, or the root when the key is absent.
    pub coordinate_system: Span,
    /// The `parameters` mapping, or the root when absent.
    pub parameters: Span,
}

#[derive(Debug, Clone, Default)]
pub struct Level {
    pub name: String,
    pub elevation: f64,
    pub drawing: Option<String>,
    pub x_meters: Option<f64>,
    pub y_meters: Option<f64>,
    pub transform: LevelTransform,
    pub vertices: Vec<Handle<Vertex>>,
    pub lanes: Vec<Handle<Lane>>,
    pub walls: Vec<Handle<Wall>>,
    pub measurements: Vec<Handle<Measurement>>,
    pub doors: Vec<Handle<Door>>,
    pub floors: Vec<Handle<Polygon>>,
    pub holes: Vec<Handle<Polygon>>,
    pub models: Vec<Handle<Model>>,
    pub fiducials: Vec<Handle<Fiducial>>,
    pub human_lanes: Vec<Handle<HumanLane>>,
    pub features: Vec<Feature>,
    pub constraints: Vec<Constraint>,
    pub layers: Vec<Layer>,
}

/// What a waypoint is for, typed from its params.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WaypointRoles {
    pub is_charger: bool,
    pub is_parking_spot: bool,
    pub is_holding_point: bool,
    pub is_passthrough_point: bool,
    pub is_cleaning_zone: bool,
    pub dock_name: Option<String>,
    pub pickup_dispenser: Option<String>,
    pub dropoff_ingestor: Option<String>,
    pub spawn_robot_type: Option<String>,
    pub spawn_robot_name: Option<String>,
    pub mutex: Option<String>,
    pub lift_cabin: Option<String>,
    pub merge_radius: Option<f64>,
    pub human_goal_set_name: Option<String>,
}

/// A waypoint's roles, kept out of line and only when it has any: most waypoints have
/// none, and a `WaypointRoles` is about 200 bytes (maps may hold 10^5 waypoints). Reads as a
/// `WaypointRoles` (`Deref`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Roles(Option<Box<WaypointRoles>>);

static NO_ROLES: WaypointRoles = WaypointRoles {
    is_charger: false,
    is_parking_spot: false,
    is_holding_point: false,
    is_passthrough_point: false,
    is_cleaning_zone: false,
    dock_name: None,
    pickup_dispenser: None,
    dropoff_ingestor: None,
    spawn_robot_type: None,
    spawn_robot_name: None,
    mutex: None,
    lift_cabin: None,
    merge_radius: None,
    human_goal_set_name: None,
};

impl From<WaypointRoles> for Roles {
    fn from(r: WaypointRoles) -> Self {
        Roles((r != NO_ROLES).then(|| Box::new(r)))
    }
}

impl std::ops::Deref for Roles {
    type Target = WaypointRoles;
    fn deref(&self) -> &WaypointRoles {
        self.0.as_deref().unwrap_or(&NO_ROLES)
    }
}

impl WaypointRoles {
    /// Roles from vertex params. Flags are true only when the bool param is true; names
    /// count only when non-empty. (The reference registers a charger for any `is_charger`
    /// key, even false; mapc does not.)
    pub fn from_params(p: &Params) -> WaypointRoles {
        let s = |k: &str| p.str(k).filter(|s| !s.is_empty()).map(str::to_string);
        WaypointRoles {
            is_charger: p.bool("is_charger").unwrap_or(false),
            is_parking_spot: p.bool("is_parking_spot").unwrap_or(false),
            is_holding_point: p.bool("is_holding_point").unwrap_or(false),
            is_passthrough_point: p.bool("is_passthrough_point").unwrap_or(false),
            is_cleaning_zone: p.bool("is_cleaning_zone").unwrap_or(false),
            dock_name: s("dock_name"),
            pickup_dispenser: s("pickup_dispenser"),
            dropoff_ingestor: s("dropoff_ingestor"),
            spawn_robot_type: s("spawn_robot_type"),
            spawn_robot_name: s("spawn_robot_name"),
            mutex: s("mutex"),
            lift_cabin: s("lift_cabin"),
            merge_radius: p.f64("merge_radius"),
            human_goal_set_name: s("human_goal_set_name"),
        }
    }

    /// The roles in words, for people (hover text, map diffs): flags, then named roles
    /// with their names in backticks.
    pub fn describe(&self) -> Vec<String> {
        let mut v: Vec<String> = Vec::new();
        for (on, what) in [
            (self.is_charger, "charger"),
            (self.is_parking_spot, "parking spot"),
            (self.is_holding_point, "holding point"),
            (self.is_passthrough_point, "passthrough point"),
            (self.is_cleaning_zone, "cleaning zone"),
        ] {
            if on {
                v.push(what.into());
            }
        }
        for (val, what) in [
            (&self.dock_name, "dock"),
            (&self.pickup_dispenser, "pickup dispenser"),
            (&self.dropoff_ingestor, "dropoff ingestor"),
            (&self.spawn_robot_name, "spawns robot"),
            (&self.lift_cabin, "in lift cabin"),
            (&self.mutex, "mutex"),
        ] {
            if let Some(s) = val {
                v.push(format!("{what} `{s}`"));
            }
        }
        v
    }
}

#[derive(Debug, Clone)]
pub struct Vertex {
    pub level: Handle<Level>,
    pub name: String,
    /// Map-frame position, metres.
    pub pos: Vec2,
    /// Coordinates as written in the file (pixels, metres or lon/lat).
    pub raw: Vec2,
    pub params: Params,
    pub roles: Roles,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Orientation {
    Any,
    Forward,
    Backward,
    /// Anything else, kept verbatim (the fleet adapter rejects it).
    Other(String),
}

impl Orientation {
    /// The constraint of the same lane driven the other way.
    pub fn reversed(&self) -> Orientation {
        match self {
            Orientation::Forward => Orientation::Backward,
            Orientation::Backward => Orientation::Forward,
            Orientation::Any => Orientation::Any,
            Orientation::Other(_) => Orientation::Any,
        }
    }
    pub fn as_str(&self) -> &str {
        match self {
            Orientation::Any => "",
            Orientation::Forward => "forward",
            Orientation::Backward => "backward",
            Orientation::Other(s) => s,
        }
    }
}

#[derive(Debug, Clone)]
pub struct Lane {
    pub level: Handle<Level>,
    pub start: Handle<Vertex>,
    pub end: Handle<Vertex>,
    /// `graph_idx`: which fleet's navigation graph the lane belongs to.
    pub graph: i64,
    pub bidirectional: bool,
    pub orientation: Orientation,
    /// Metres per second; `None` when absent or not positive.
    pub speed_limit: Option<f64>,
    pub mutex: Option<String>,
    pub demo_mock_floor_name: Option<String>,
    pub demo_mock_lift_name: Option<String>,
    /// The lane's parameters other than `graph_idx` and `bidirectional` (which are whole in
    /// `graph` and `bidirectional`); kept for their spans and for rules on free-form ones.
    pub params: Params,
}

#[derive(Debug, Clone)]
pub struct Wall {
    pub level: Handle<Level>,
    pub start: Handle<Vertex>,
    pub end: Handle<Vertex>,
    pub params: Params,
}

#[derive(Debug, Clone)]
pub struct Measurement {
    pub level: Handle<Level>,
    pub start: Handle<Vertex>,
    pub end: Handle<Vertex>,
    /// Real length in metres.
    pub distance: f64,
    pub params: Params,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DoorKind {
    Hinged,
    DoubleHinged,
    Sliding,
    DoubleSliding,
    /// Unknown type string, kept verbatim.
    Other(String),
}

impl DoorKind {
    pub fn parse(s: &str) -> DoorKind {
        match s {
            "hinged" => DoorKind::Hinged,
            "double_hinged" => DoorKind::DoubleHinged,
            "sliding" => DoorKind::Sliding,
            "double_sliding" => DoorKind::DoubleSliding,
            other => DoorKind::Other(other.to_string()),
        }
    }
    pub fn as_str(&self) -> &str {
        match self {
            DoorKind::Hinged => "hinged",
            DoorKind::DoubleHinged => "double_hinged",
            DoorKind::Sliding => "sliding",
            DoorKind::DoubleSliding => "double_sliding",
            DoorKind::Other(s) => s,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionAxis {
    Start,
    End,
}

#[derive(Debug, Clone)]
pub struct Door {
    pub level: Handle<Level>,
    pub start: Handle<Vertex>,
    pub end: Handle<Vertex>,
    pub name: String,
    pub kind: DoorKind,
    pub motion_axis: MotionAxis,
    /// +1 or -1: swing direction of hinged doors.
    pub motion_direction: i64,
    /// Swing range of hinged doors, degrees.
    pub motion_degrees: f64,
    /// Width ratio of the right (start) leaf to the left (end) leaf of double doors.
    pub right_left_ratio: f64,
    /// `plugin: none` makes a static door without a controller.
    pub plugin: bool,
    pub params: Params,
}

/// A floor or a hole: vertex handles in order.
#[derive(Debug, Clone)]
pub struct Polygon {
    pub level: Handle<Level>,
    pub vertices: Vec<Handle<Vertex>>,
    pub params: Params,
}

#[derive(Debug, Clone)]
pub struct Model {
    pub level: Handle<Level>,
    pub name: String,
    pub model_name: String,
    /// Map-frame position.
    pub pos: Vec2,
    pub raw: Vec2,
    /// Height above the level's elevation.
    pub z: f64,
    /// Map-frame yaw: the file yaw plus the level rotation.
    pub yaw: f64,
    pub is_static: bool,
    pub dispensable: bool,
}

#[derive(Debug, Clone)]
pub struct Fiducial {
    pub level: Handle<Level>,
    pub name: String,
    pub raw: Vec2,
    pub pos: Vec2,
}

#[derive(Debug, Clone)]
pub struct HumanLane {
    pub level: Handle<Level>,
    pub start: Handle<Vertex>,
    pub end: Handle<Vertex>,
    pub params: Params,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Feature {
    pub id: String,
    pub name: String,
    pub raw: Vec2,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    pub ids: Vec<String>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    pub name: String,
    pub filename: String,
    pub visible: bool,
    pub color: [f64; 4],
    pub yaw: f64,
    pub scale: f64,
    pub translation: Vec2,
    pub features: Vec<Feature>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct LiftDoor {
    pub name: String,
    /// 1 single sliding, 2 double sliding, 3 single telescope, 4 double telescope.
    pub door_type: i64,
    /// Door centre in the cabin frame, metres.
    pub pos: Vec2,
    pub width: f64,
    pub motion_axis_orientation: f64,
    pub span: Span,
}

/// Which cabin doors open on one level.
#[derive(Debug, Clone)]
pub struct LevelDoors {
    pub level: Handle<Level>,
    /// Door names as written; names missing from the lift's `doors` are kept so that
    /// validation can report them.
    pub doors: Vec<(String, Span)>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Lift {
    pub name: String,
    /// Cabin centre, map frame.
    pub pos: Vec2,
    pub raw: Vec2,
    pub yaw: f64,
    pub width: f64,
    pub depth: f64,
    pub reference_level: Handle<Level>,
    pub initial_level: Option<Handle<Level>>,
    pub lowest_level: Option<Handle<Level>>,
    pub highest_level: Option<Handle<Level>>,
    pub plugins: bool,
    pub doors: Vec<LiftDoor>,
    pub level_doors: Vec<LevelDoors>,
}

/// Margin between the cabin and the shaft on each side, metres.
pub const SHAFT_MARGIN: f64 = 0.05;

impl Lift {
    /// Shaft rectangle corners in the map frame: local (-w,+d), (-w,-d), (+w,-d), (+w,+d)
    /// with w = width/2 + margin, d = depth/2 + margin.
    pub fn shaft_corners(&self) -> [Vec2; 4] {
        let w = self.width / 2.0 + SHAFT_MARGIN;
        let d = self.depth / 2.0 + SHAFT_MARGIN;
        [
            Vec2::new(-w, d),
            Vec2::new(-w, -d),
            Vec2::new(w, -d),
            Vec2::new(w, d),
        ]
        .map(|c| c.rotate(self.yaw).plus(self.pos))
    }

    /// Is `p` inside the shaft rectangle (boundary included)?
    pub fn shaft_contains(&self, p: Vec2) -> bool {
        // Compare in the cabin frame, with a tolerance for rounding on the boundary.
        let local = self.to_cabin(p);
        let eps = 1e-9;
        local.x.abs() <= self.width / 2.0 + SHAFT_MARGIN + eps
            && local.y.abs() <= self.depth / 2.0 + SHAFT_MARGIN + eps
    }

    /// `p` in the cabin's frame: x along its width, y along its depth, from its centre.
    pub fn to_cabin(&self, p: Vec2) -> Vec2 {
        p.minus(self.pos).rotate(-self.yaw)
    }

    /// Initial floor: explicit, else the first level in `level_doors`.
    pub fn initial_floor(&self) -> Option<Handle<Level>> {
        self.initial_level
            .or_else(|| self.level_doors.first().map(|ld| ld.level))
    }
}

/// Which frontend read a building.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SourceFormat {
    /// traffic_editor's `.building.yaml` (or a legacy `.project.yaml`).
    #[default]
    BuildingYaml,
    /// rmf_site's `.site.json`.
    Site,
}

#[derive(Debug, Clone, PartialEq)]
pub struct GraphInfo {
    pub index: i64,
    pub name: String,
    pub default_lane_width: f64,
    /// Waypoints whose name and roles (a site location's) belong to other graphs only:
    /// rmf_site's locations say which graphs they are in, and its nav export names them
    /// only there. Sorted; empty for a `.building.yaml`, whose names hold in every graph.
    pub unnamed: Vec<Handle<Vertex>>,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct CrowdSim {
    pub enable: bool,
    pub update_time_step: f64,
    pub states: Vec<CrowdState>,
    pub goal_sets: Vec<GoalSet>,
    pub agent_profiles: Vec<AgentProfile>,
    pub transitions: Vec<Transition>,
    pub obstacle_set: Option<ObstacleSet>,
    pub agent_groups: Vec<AgentGroup>,
    pub model_types: Vec<ModelType>,
    /// The `crowd_sim` mapping.
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct CrowdState {
    pub name: String,
    pub goal_set: i64,
    pub navmesh_file_name: String,
    pub is_final: bool,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct GoalSet {
    pub set_id: i64,
    pub capacity: i64,
    pub set_area: Vec<String>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct AgentProfile {
    pub name: String,
    pub class: i64,
    pub max_accel: f64,
    pub max_angle_vel: f64,
    pub max_neighbors: i64,
    pub max_speed: f64,
    pub neighbor_dist: f64,
    pub obstacle_set: i64,
    pub pref_speed: f64,
    pub r: f64,
    pub orca_tau: f64,
    pub orca_tau_obst: f64,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Transition {
    pub from: String,
    pub to: String,
    /// Weighted targets (`Target`), each with the span of its entry; when present they
    /// replace `to` (Menge's `prob` target).
    pub targets: Vec<(String, f64, Span)>,
    pub condition: Option<Condition>,
    pub span: Span,
}

/// A transition condition (Menge's `Condition` types the editor writes).
#[derive(Debug, Clone, PartialEq)]
pub enum Condition {
    /// The agent is within `distance` of its goal.
    GoalReached {
        distance: f64,
    },
    /// A time after entering the state.
    Timer(Timer),
    /// Always true.
    Auto,
    And(Box<Condition>, Box<Condition>),
    Or(Box<Condition>, Box<Condition>),
    Not(Box<Condition>),
    /// A type mapc does not know (or an empty one); never true.
    Other(String),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timer {
    pub duration: TimerDuration,
    /// Each agent draws its own duration on entry; otherwise one duration is drawn once
    /// and shared by every agent.
    pub per_agent: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimerDuration {
    /// `dist: c`, `value`.
    Const(f64),
    /// `dist: u`, uniform in `[min, max]`.
    Uniform { min: f64, max: f64 },
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObstacleSet {
    pub class: i64,
    pub file_name: String,
    pub kind: String,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct AgentGroup {
    pub group_id: i64,
    pub profile_selector: String,
    pub state_selector: String,
    pub agents_number: i64,
    pub agents_name: Vec<String>,
    pub pos: Vec2,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelType {
    pub typename: String,
    pub animation: String,
    pub animation_speed: f64,
    pub model_uri: String,
    pub init_pose: Vec<f64>,
}

impl Building {
    /// An empty building. `reference_level` points at the first level, so a building
    /// handed out by the frontend always has at least one level.
    pub fn new(name: String, coordinate_system: CoordinateSystem, params: Params) -> Self {
        Building {
            name,
            coordinate_system,
            crs_name: None,
            offset: Vec2::default(),
            reference_level: Handle::new(0),
            params,
            levels: Arena::new(),
            vertices: Arena::new(),
            lanes: Arena::new(),
            walls: Arena::new(),
            measurements: Arena::new(),
            doors: Arena::new(),
            floors: Arena::new(),
            holes: Arena::new(),
            models: Arena::new(),
            fiducials: Arena::new(),
            human_lanes: Arena::new(),
            lifts: Arena::new(),
            graphs: Vec::new(),
            crowd_sim: None,
            map_version: None,
            format: SourceFormat::BuildingYaml,
            spans: BuildingSpans::default(),
        }
    }

    /// Lifts whose shaft passes through `level`: a non-empty `level_doors` and an
    /// elevation range (lowest..highest floor, unbounded when unset) containing the level.
    pub fn lifts_on_level(&self, level: Handle<Level>) -> impl Iterator<Item = Handle<Lift>> + '_ {
        let z = self.levels[level].elevation;
        self.lifts.iter().filter_map(move |(h, lift)| {
            if lift.level_doors.is_empty() {
                return None;
            }
            let lo = lift
                .lowest_level
                .map_or(f64::NEG_INFINITY, |l| self.levels[l].elevation);
            let hi = lift
                .highest_level
                .map_or(f64::INFINITY, |l| self.levels[l].elevation);
            (lo <= z && z <= hi).then_some(h)
        })
    }

    pub fn level_by_name(&self, name: &str) -> Option<Handle<Level>> {
        self.levels
            .iter()
            .find(|(_, l)| l.name == name)
            .map(|(h, _)| h)
    }

    /// Sorted, distinct graph indices that have at least one lane.
    pub fn graph_indices(&self) -> Vec<i64> {
        let mut v: Vec<i64> = self.lanes.iter().map(|(_, l)| l.graph).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}
