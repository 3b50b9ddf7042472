//! Diagnostic codes of sweep files (`mapc sweep`, S04xx). Each `///` block is gathered into
//! docs/diagnostics.md by tests/docs.rs. All are errors: a sweep with any of them runs
//! nothing.

use mapc_ir::lints::Group;
pub use mapc_ir::Code;

/// # S0401 sweep-invalid
///
/// **What:** the sweep file is not well-formed YAML, or its structure is wrong: no
/// `scenario`, an unknown top-level key, `runs` or `zip` that is not a mapping, an axis
/// whose values are not a non-empty list, a value written over several lines, or axes
/// whose product is more than 100,000 runs.
///
/// **Why it matters:** nothing can be planned from a file that cannot be read; a misspelt
/// key would silently drop an axis.
///
/// **Fix:** follow docs/sweep.md: `scenario: FILE`, then `runs:` with one `path: [values]`
/// entry per axis (values in flow style, on one line).
///
/// **Example:**
/// ```yaml
/// scenario: base.scenario.yaml
/// runs:
///   seed: 3          # S0401: an axis needs a list of values, e.g. [1, 2, 3]
/// ```
pub const SWEEP_INVALID: Code = Code {
    code: "S0401",
    group: Group::Scenario,
    name: "sweep-invalid",
    summary: "the sweep file is not valid YAML or not shaped like a sweep",
};

/// # S0402 unknown-axis
///
/// **What:** an axis (or a `set` entry) names a place that the base scenario does not have:
/// a fleet, workcell or generator that is neither a `name` nor an index of its list, a key
/// below a value that is not a mapping, a key the scenario format does not know, or a
/// mapping the base scenario does not contain.
///
/// **Why it matters:** the axis would change nothing (or something else), and every run of
/// the sweep would be the same scenario under different labels.
///
/// **Fix:** write the path as the scenario spells it: `fleets.<name or index>.count`,
/// `generators.<index>.every`, `seed`, `duration`, `options.clean_duration`. A mapping
/// that the base scenario lacks (`options`) must be added to it first.
///
/// **Example:**
/// ```yaml
/// runs:
///   fleets.tinyRobots.count: [2, 4]   # S0402: the fleet is called tinyRobot
/// ```
pub const UNKNOWN_AXIS: Code = Code {
    code: "S0402",
    group: Group::Scenario,
    name: "unknown-axis",
    summary: "an axis path does not name a place in the base scenario",
};

/// # S0403 axis-value-invalid
///
/// **What:** a value of an axis makes the scenario invalid: a value of the wrong type (a
/// string where a count is expected), out of range, or one that does not fit the map (more
/// robots than spawn points, a waypoint the fleet's graph lacks). The message quotes the
/// scenario's own diagnostic.
///
/// **Why it matters:** that run could not be simulated; the sweep is checked whole before
/// anything runs so that an hour-long study does not stop in the middle.
///
/// **Fix:** change the value (the diagnostic points at it in the sweep file).
///
/// **Example:**
/// ```yaml
/// runs:
///   fleets.tinyRobot.count: [2, four]   # S0403: `count` must be an integer
/// ```
pub const AXIS_VALUE: Code = Code {
    code: "S0403",
    group: Group::Scenario,
    name: "axis-value-invalid",
    summary: "an axis value makes the scenario invalid",
};

/// # S0404 overlapping-axes
///
/// **What:** two axes (or an axis and a `set` entry) change the same place of the scenario,
/// or one changes a value inside the other's.
///
/// **Why it matters:** only one of them could take effect, so the table would show values
/// that were not simulated.
///
/// **Fix:** keep one of them; to vary two values together use a `zip` group.
///
/// **Example:**
/// ```yaml
/// runs:
///   fleets.tinyRobot.count: [2, 4]
///   fleets.0.count: [1, 3]   # S0404: fleet 0 is tinyRobot
/// ```
pub const OVERLAPPING_AXES: Code = Code {
    code: "S0404",
    group: Group::Scenario,
    name: "overlapping-axes",
    summary: "two axes change the same place of the scenario",
};

/// # S0405 zip-length-mismatch
///
/// **What:** the axes of the `zip` group have lists of different lengths.
///
/// **Why it matters:** zipped axes take their i-th values together; with unequal lengths
/// some values would have no partner.
///
/// **Fix:** give every zipped axis the same number of values.
///
/// **Example:**
/// ```yaml
/// zip:
///   fleets.tinyRobot.count: [2, 4, 8]
///   generators.0.every: [10min, 5min]   # S0405: 2 values, the group has 3
/// ```
pub const ZIP_LENGTH: Code = Code {
    code: "S0405",
    group: Group::Scenario,
    name: "zip-length-mismatch",
    summary: "the zipped axes have lists of different lengths",
};

pub const CODES: &[Code] = &[
    SWEEP_INVALID,
    UNKNOWN_AXIS,
    AXIS_VALUE,
    OVERLAPPING_AXES,
    ZIP_LENGTH,
];
