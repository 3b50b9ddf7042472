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
/// **What:** an element refers to an id that the site does not hold: a lane, wall, door or
/// floor anchor, a lift's reference anchor, a model's parent level, a lane's graph.
///
/// **Why it matters:** the element cannot be placed; it is left out of every output.
///
/// **Fix:** point the reference at an existing anchor (or level, graph) in rmf_site, or
/// delete the element.
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
/// **What:** a lane joins anchors of two different levels, or uses a site-wide anchor (one
/// that belongs to no level).
///
/// **Why it matters:** a nav graph lane lies on one level; robots change levels through
/// lifts, whose cabin anchors a lane may use.
///
/// **Fix:** draw the lane between anchors of one level (or a level anchor and a lift cabin
/// anchor).
///
/// **Example:** a lane from an anchor of `L1` to an anchor of `L2`.
pub const LANE_BETWEEN_LEVELS: Code = Code {
    code: "E0122",
    group: Group::Reading,
    name: "site-lane-between-levels",
    summary: "a lane joins anchors of different levels or a site anchor",
};

/// # E0123 site-location-missing-anchor
///
/// **What:** a location (a named waypoint with charger, parking or holding tags) sits on an
/// anchor that does not exist or is not on a level.
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
    summary: "a location is on an anchor that does not exist or is not on a level",
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
/// differs by direction in more than its dock, layers and features; or something only
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

/// Every site code.
pub static CODES: &[Code] = &[
    FORMAT_VERSION,
    DANGLING_ID,
    LANE_BETWEEN_LEVELS,
    LOCATION_ANCHOR,
    CABIN_ANCHOR_OUTSIDE,
    UNKNOWN_FIELD,
    NOT_CONVERTIBLE,
];
