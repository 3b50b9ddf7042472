//! What each `[type_code, value]` parameter of the format means (building_yaml.md), for
//! hover. Type codes: 1 string, 2 int, 3 double, 4 bool.

/// `(name, type, meaning)`.
const PARAMS: &[(&str, &str, &str)] = &[
    // Vertices.
    (
        "is_charger",
        "bool (4)",
        "the waypoint is a charger: idle robots of the fleet go there to charge",
    ),
    (
        "is_parking_spot",
        "bool (4)",
        "robots may park here when they have no task",
    ),
    (
        "is_holding_point",
        "bool (4)",
        "robots may wait here while the traffic schedule clears",
    ),
    (
        "is_passthrough_point",
        "bool (4)",
        "robots drive through without stopping (no waiting allowed)",
    ),
    (
        "is_cleaning_zone",
        "bool (4)",
        "the waypoint starts a cleaning zone",
    ),
    (
        "dock_name",
        "string (1)",
        "name of a docking procedure started when a robot arrives here",
    ),
    (
        "pickup_dispenser",
        "string (1)",
        "the dispenser (workcell) a delivery picks up from at this waypoint",
    ),
    (
        "dropoff_ingestor",
        "string (1)",
        "the ingestor (workcell) a delivery drops off to at this waypoint",
    ),
    (
        "spawn_robot_type",
        "string (1)",
        "model of the robot spawned here in simulation",
    ),
    (
        "spawn_robot_name",
        "string (1)",
        "name of the robot spawned here in simulation (needs spawn_robot_type)",
    ),
    (
        "mutex",
        "string (1)",
        "a mutex group: only one robot at a time in the places sharing it",
    ),
    (
        "lift_cabin",
        "string (1)",
        "the lift whose cabin this waypoint is in",
    ),
    (
        "merge_radius",
        "double (3)",
        "metres within which a robot may merge onto this waypoint",
    ),
    (
        "human_goal_set_name",
        "string (1)",
        "crowd simulation goal set this vertex belongs to",
    ),
    // Lanes.
    (
        "graph_idx",
        "int (2)",
        "the navigation graph (fleet) the lane belongs to",
    ),
    (
        "bidirectional",
        "bool (4)",
        "robots may drive the lane both ways",
    ),
    (
        "orientation",
        "string (1)",
        "`forward` or `backward`: how robots must face while driving; empty for any",
    ),
    (
        "speed_limit",
        "double (3)",
        "maximum speed on the lane, m/s; 0 for none",
    ),
    (
        "demo_mock_floor_name",
        "string (1)",
        "demo only: the level a mock lift lane leads to",
    ),
    (
        "demo_mock_lift_name",
        "string (1)",
        "demo only: the mock lift this lane stands for",
    ),
    // Doors.
    (
        "name",
        "string (1)",
        "the door's name, unique in the building (door requests use it)",
    ),
    (
        "type",
        "string (1)",
        "`hinged`, `double_hinged`, `sliding` or `double_sliding`",
    ),
    (
        "motion_axis",
        "string (1)",
        "`start` or `end`: the vertex the leaf hinges on or slides toward",
    ),
    (
        "motion_direction",
        "int (2)",
        "1 or -1: which way a hinged door swings",
    ),
    (
        "motion_degrees",
        "double (3)",
        "how far a hinged door swings open, degrees",
    ),
    (
        "right_left_ratio",
        "double (3)",
        "width of the right leaf over the left one (double doors)",
    ),
    (
        "plugin",
        "string (1)",
        "`normal` for a controlled door, `none` for a static one",
    ),
    // Walls and floors.
    (
        "texture_name",
        "string (1)",
        "texture image (`<name>.png` on the texture path)",
    ),
    (
        "texture_height",
        "double (3)",
        "height of one texture tile, metres",
    ),
    (
        "texture_width",
        "double (3)",
        "width of one texture tile, metres",
    ),
    ("texture_scale", "double (3)", "metres per texture tile"),
    (
        "texture_rotation",
        "double (3)",
        "rotation of the floor texture, degrees",
    ),
    ("alpha", "double (3)", "wall opacity, 0 to 1"),
    (
        "indoor",
        "int (2)",
        "1 for an indoor floor (gets a ceiling), 0 for outdoors",
    ),
    (
        "ceiling_texture",
        "string (1)",
        "texture of the ceiling above an indoor floor",
    ),
    (
        "ceiling_scale",
        "double (3)",
        "metres per ceiling texture tile",
    ),
    // Measurements.
    (
        "distance",
        "double (3)",
        "the real length between the two vertices, metres (sets the scale)",
    ),
    // Building.
    (
        "generate_crs",
        "string (1)",
        "the projected CRS nav graphs and worlds use, e.g. `EPSG:3414` (wgs84 maps)",
    ),
    (
        "suggested_offset_x",
        "double (3)",
        "easting subtracted so the site sits near the origin (wgs84)",
    ),
    (
        "suggested_offset_y",
        "double (3)",
        "northing subtracted so the site sits near the origin (wgs84)",
    ),
    (
        "offset_x",
        "double (3)",
        "x subtracted so the site sits near the origin (cartesian_meters)",
    ),
    (
        "offset_y",
        "double (3)",
        "y subtracted so the site sits near the origin (cartesian_meters)",
    ),
    (
        "generate_origin_vertex",
        "bool (4)",
        "add an `origin` vertex at the offset",
    ),
];

/// `(type, meaning)` of a parameter.
pub(crate) fn param(name: &str) -> Option<(&'static str, &'static str)> {
    PARAMS
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, t, m)| (*t, *m))
}
