//! Diagnostic codes of rmf_site `.site.json` input and of conversions between the two map
//! formats. Gathered into docs/diagnostics.md like the other code lists (tests/docs.rs).

use mapc_ir::lints::Group;
pub use mapc_ir::Code;

/// # E0120 site-format-version
///
/// **What:** the site's `format_version` is missing, is not `"MAJOR.MINOR"`, or has a
/// major version newer than the one mapc reads (0, rmf_site_format 0.0.2's "0.1").
///
/// **Why it matters:** a new major version changes what mandatory fields mean; reading it
/// as the old format would build a wrong map silently.
///
/// **Fix:** write the site with an rmf_site that saves format 0.x, or update mapc.
///
/// **Example:**
/// ```json
/// {"format_version": "1.0", "properties": {"name": "s"}, "levels": {}}
/// ```
pub const FORMAT_VERSION: Code = Code {
    code: "E0120",
    group: Group::Reading,
    name: "site-format-version",
    summary: "the site's format_version is missing or newer than mapc reads",
};

/// # E0121 site-dangling-id
///
/// **What:** an element refers to an id that the site does not hold (a lane, wall, door or
/// floor anchor, a lift's reference anchor, a model's parent level, a lane's graph), or a
/// wall, door or floor of one level uses an anchor of another level or a lift's cabin
/// anchor. A level's elements may use the level's own anchors and the site's anchors
/// (the site's `anchors`, shared by all levels), as rmf_site resolves them.
///
/// **Why it matters:** the element cannot be placed; it is left out of every output.
///
/// **Fix:** point the reference at an existing anchor of the element's level or of the
/// site (or an existing level, graph) in rmf_site, or delete the element.
///
/// **Example:**
/// ```json
/// "lanes": {"20": {"anchors": [3, 99], "graphs": "All"}}
/// ```
pub const DANGLING_ID: Code = Code {
    code: "E0121",
    group: Group::Reading,
    name: "site-dangling-id",
    summary: "a reference to an anchor, level or graph id that does not exist",
};

/// # E0122 site-lane-between-levels
///
/// **What:** a lane joins anchors of two different levels, or has no end on a level
/// anchor (both ends on lift cabin anchors).
///
/// **Why it matters:** a nav graph lane lies on one level; robots change levels through
/// lifts, whose cabin anchors a lane may use together with an anchor of a level.
///
/// **Fix:** draw the lane between anchors of one level (or a level anchor and a lift cabin
/// anchor).
///
/// **Example:** a lane from an anchor of `L1` to an anchor of `L2`.
pub const LANE_BETWEEN_LEVELS: Code = Code {
    code: "E0122",
    group: Group::Reading,
    name: "site-lane-between-levels",
    summary: "a lane joins anchors of different levels, or only cabin anchors",
};

/// # E0123 site-location-missing-anchor
///
/// **What:** a location (a named waypoint with charger, parking or holding tags) sits on an
/// anchor that the site does not have on a level or a lift (a missing id, or a drawing's
/// anchor). One on a site anchor is W0123.
///
/// **Why it matters:** the waypoint's name and roles would vanish from the nav graph.
///
/// **Fix:** move the location onto an anchor of a level.
///
/// **Example:**
/// ```json
/// "locations": {"30": {"anchor": 77, "tags": ["Charger"], "name": "c1", "graphs": "All"}}
/// ```
pub const LOCATION_ANCHOR: Code = Code {
    code: "E0123",
    group: Group::Reading,
    name: "site-location-missing-anchor",
    summary: "a location is on an anchor that does not exist on a level or lift",
};

/// # W0120 site-cabin-anchor-outside
///
/// **What:** a lift's cabin anchor lies outside the cabin rectangle.
///
/// **Why it matters:** the anchor moves with the cabin; a waypoint outside it is not
/// reachable by the lift, and nav graphs mark it as a lift waypoint anyway.
///
/// **Fix:** move the anchor inside the cabin, or make it a level anchor.
///
/// **Example:** a 1.5 × 1.65 m cabin with a cabin anchor at `[3.0, 0.0]`.
pub const CABIN_ANCHOR_OUTSIDE: Code = Code {
    code: "W0120",
    group: Group::Frontend,
    name: "site-cabin-anchor-outside",
    summary: "a lift cabin anchor lies outside the cabin",
};

/// # W0121 site-unknown-field
///
/// **What:** a field or location tag that rmf_site_format 0.0.2 does not define, or a
/// site element mapc reads but does not use (lights, cameras, tasks, scenarios that hide
/// or move a model instance, model instances not on a level, ...), or a `Workcell` location tag that does not say
/// whether the place is a dispenser or an ingestor (kept as a named place).
///
/// **Why it matters:** mapc ignores it; if it came from a newer rmf_site it may carry
/// meaning the outputs then lack.
///
/// **Fix:** check the spelling; otherwise nothing to do (allow it with `--allow W0121`).
///
/// **Example:**
/// ```json
/// "properties": {"name": "L1", "elevation": 0.0, "elevaton": 3.0}
/// ```
pub const UNKNOWN_FIELD: Code = Code {
    code: "W0121",
    group: Group::Frontend,
    name: "site-unknown-field",
    summary: "a site field mapc does not know or does not use",
};

/// # W0122 not-convertible
///
/// **What:** `mapc convert` met something the target format cannot say: a telescope lift
/// door or a door model in a `.site.json`, a yaw orientation constraint, a lane that
/// differs by direction in more than its dock, layers and features, a site location in
/// some graphs only (a `.building.yaml` names a waypoint in every graph); or something only
/// mapc's extension data in the site keeps (`crowd_sim`, human lanes, floor holes), which
/// rmf_site neither shows nor edits. It names the element.
///
/// **Why it matters:** that part is left out of (or simplified in) the converted file, or
/// survives only a conversion back by mapc.
///
/// **Fix:** nothing, or edit the converted map by hand; the message says what was dropped.
///
/// **Example:** converting a map with `crowd_sim` to `.site.json`.
pub const NOT_CONVERTIBLE: Code = Code {
    code: "W0122",
    group: Group::Frontend,
    name: "not-convertible",
    summary: "the target format of `mapc convert` cannot say this",
};

/// # W0123 site-anchor-off-nav-graph
///
/// **What:** a lane or a location uses a site anchor (one of the site's `anchors`, shared
/// by all levels, such as a lift's reference anchor). rmf_site's editor draws it, but its
/// nav graph export (`NavGraph::from_site`) makes waypoints only of level anchors and lift
/// cabin anchors, and leaves such a lane out ("not supported") and such a location
/// unnamed. mapc's nav graphs are the same as rmf_site's: the lane or location is left
/// out of them.
///
/// **Why it matters:** robots cannot drive that lane, or stop at that place by its name,
/// though the editor shows it.
///
/// **Fix:** in rmf_site, draw the lane to (or put the location on) an anchor of the
/// level: a new anchor at the same place. Walls, floors and doors may keep using site
/// anchors.
///
/// **Example:**
/// ```json
/// "lanes": {"20": {"anchors": [3, 48], "graphs": "All"}}
/// ```
/// with 48 in the site's top-level `anchors`.
pub const SITE_ANCHOR_OFF_NAV: Code = Code {
    code: "W0123",
    // Only the nav graphs lose the lane or location.
    group: Group::Lanes,
    name: "site-anchor-off-nav-graph",
    summary: "a lane or location on a site anchor is left out of nav graphs, as rmf_site does",
};

/// Every site code.
pub static CODES: &[Code] = &[
    FORMAT_VERSION,
    DANGLING_ID,
    LANE_BETWEEN_LEVELS,
    LOCATION_ANCHOR,
    CABIN_ANCHOR_OUTSIDE,
    UNKNOWN_FIELD,
    NOT_CONVERTIBLE,
    SITE_ANCHOR_OFF_NAV,
];
