//! Pictures of levels: `render_level` draws one level of a building as an SVG document
//! (floors and holes, walls, doors, lifts, the lanes of each graph, waypoints with their
//! names and roles, models, a legend, a scale bar and the level name; optionally the
//! diagnostics at their places). `png` rasterises such a document (resvg, embedded font).
//!
//! Pure: no I/O, and the same building gives the same bytes. Picture coordinates are
//! pixels; [`View`] maps map-frame metres to them (y down), and is public so that other
//! drawings (the replay page) can place things on the same picture.

mod legend;
mod locate;
mod map;
mod marks;
mod png;

pub use locate::{locate, Located};
pub use png::svg_to_png;

use legend::{draw_legend, draw_scale_bar};
use map::draw_map;
use marks::{draw_diagnostic_list, draw_diagnostic_marks};

use crate::svg::{esc, num, Svg};
use crate::OutputFile;
use mapc_ir::{Building, Diagnostic, DoorKind, Handle, Level, Severity, Vec2};

/// What to draw besides the map itself.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderOptions<'a> {
    /// Only the lanes (and their waypoints) of these graph indices; `None`: every graph.
    pub graphs: Option<&'a [i64]>,
    /// Draw these diagnostics at their places and list them below the map.
    pub diagnostics: Option<&'a [Diagnostic]>,
}

/// Colours, shared with the replay page and the tests.
pub mod colours {
    pub const BACKGROUND: &str = "#ffffff";
    pub const FLOOR: &str = "#f1ede4";
    pub const FLOOR_EDGE: &str = "#d9d1c0";
    pub const HOLE: &str = "#ffffff";
    pub const WALL: &str = "#2b2b2b";
    pub const DOOR: &str = "#b8860b";
    pub const SHAFT: &str = "#dcdce6";
    pub const CABIN: &str = "#b9b9cc";
    pub const LIFT_DOOR: &str = "#3056b0";
    pub const MODEL: &str = "#8a8a8a";
    pub const WAYPOINT: &str = "#333333";
    pub const ERROR: &str = "#e00000";
    pub const WARNING: &str = "#f08c00";
    /// One colour per graph, by the graph's rank among the building's graph indices.
    pub const GRAPHS: [&str; 8] = [
        "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#e377c2", "#4b6584",
    ];
}

/// The colour of graph `index` in `b` (by rank among the graphs that have lanes).
pub fn graph_colour(b: &Building, index: i64) -> &'static str {
    let rank = b
        .graph_indices()
        .iter()
        .position(|&g| g == index)
        .unwrap_or(0);
    colours::GRAPHS[rank % colours::GRAPHS.len()]
}

/// Waypoint roles in legend order: (label, letter, colour).
pub const ROLES: [(&str, &str, &str); 7] = [
    ("charger", "C", "#2e7d32"),
    ("parking spot", "P", "#1565c0"),
    ("holding point", "H", "#6a1b9a"),
    ("dispenser (pickup)", "D", "#e65100"),
    ("ingestor (dropoff)", "I", "#00838f"),
    ("cleaning zone", "Z", "#827717"),
    ("robot spawn", "S", "#c2185b"),
];

fn roles_of(r: &mapc_ir::WaypointRoles) -> [bool; 7] {
    [
        r.is_charger,
        r.is_parking_spot,
        r.is_holding_point,
        r.pickup_dispenser.is_some(),
        r.dropoff_ingestor.is_some(),
        r.is_cleaning_zone,
        r.spawn_robot_type.is_some() || r.spawn_robot_name.is_some(),
    ]
}

const MARGIN: f64 = 20.0;
const TITLE_H: f64 = 44.0;
const LEGEND_W: f64 = 250.0;
const SCALE_H: f64 = 48.0;
const LINE_H: f64 = 16.0;
/// The longest side of the map area, pixels (smaller for small levels: at most
/// `MAX_PX_PER_M` pixels per metre).
const MAP_PX: f64 = 1400.0;
const MAX_PX_PER_M: f64 = 60.0;
const MIN_PX_PER_M: f64 = 10.0;
const NAME_ROOM: f64 = 110.0;
const MAX_MAP_PX: f64 = 3000.0;

/// Where map-frame metres land on the picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Pixels per metre.
    pub k: f64,
    /// Map-frame corner drawn at the map area's top left: (min x, max y).
    pub min_x: f64,
    pub max_y: f64,
    /// The map area's top-left corner and size, pixels.
    pub left: f64,
    pub top: f64,
    pub width: f64,
    pub height: f64,
}

impl View {
    pub fn px(&self, p: Vec2) -> (f64, f64) {
        (
            self.left + (p.x - self.min_x) * self.k,
            self.top + (self.max_y - p.y) * self.k,
        )
    }
}

/// Bounding box of what is on `level`: vertices, models, shafts of the lifts serving it.
fn bounds(b: &Building, level: Handle<Level>) -> (Vec2, Vec2) {
    let l = &b.levels[level];
    // What is drawn: the vertices of walls, doors, lanes, floors and holes, waypoints with
    // roles (not stray vertices such as measurement ends far outside the building).
    let mut used = vec![false; b.vertices.len()];
    let mut mark = |v: Handle<mapc_ir::Vertex>| used[v.index()] = true;
    for &h in &l.walls {
        mark(b.walls[h].start);
        mark(b.walls[h].end);
    }
    for &h in &l.doors {
        mark(b.doors[h].start);
        mark(b.doors[h].end);
    }
    for &h in &l.lanes {
        mark(b.lanes[h].start);
        mark(b.lanes[h].end);
    }
    let floors = l.floors.iter().map(|&h| &b.floors[h]);
    for poly in floors.chain(l.holes.iter().map(|&h| &b.holes[h])) {
        poly.vertices.iter().for_each(|&v| mark(v));
    }
    for &v in &l.vertices {
        if roles_of(&b.vertices[v].roles).iter().any(|&r| r) {
            mark(v);
        }
    }
    let mut pts: Vec<Vec2> = l
        .vertices
        .iter()
        .filter(|v| used[v.index()])
        .map(|&v| b.vertices[v].pos)
        .collect();
    if pts.is_empty() {
        pts.extend(l.vertices.iter().map(|&v| b.vertices[v].pos));
    }
    pts.extend(l.models.iter().map(|&m| b.models[m].pos));
    for h in b.lifts_on_level(level) {
        pts.extend(b.lifts[h].shaft_corners());
    }
    let pts: Vec<Vec2> = pts.into_iter().filter(|p| p.is_finite()).collect();
    if pts.is_empty() {
        return (Vec2::new(-5.0, -5.0), Vec2::new(5.0, 5.0));
    }
    let mut lo = pts[0];
    let mut hi = pts[0];
    for p in &pts {
        lo.x = lo.x.min(p.x);
        lo.y = lo.y.min(p.y);
        hi.x = hi.x.max(p.x);
        hi.y = hi.y.max(p.y);
    }
    (lo, hi)
}

/// The view of `level`: its contents with a margin, the longest side about 1400 px.
pub fn level_view(b: &Building, level: Handle<Level>) -> View {
    let (lo, hi) = bounds(b, level);
    let extent = (hi.x - lo.x).max(hi.y - lo.y).max(1.0);
    let m = (0.04 * extent).max(1.0);
    let (w, h) = (hi.x - lo.x + 2.0 * m, hi.y - lo.y + 2.0 * m);
    // Large sites get more pixels (names stay legible), up to MAX_MAP_PX.
    let k = (MAP_PX / w.max(h))
        .max(MIN_PX_PER_M.min(MAX_MAP_PX / w.max(h)))
        .min(MAX_PX_PER_M);
    View {
        k,
        min_x: lo.x - m,
        max_y: hi.y + m,
        left: MARGIN,
        top: TITLE_H,
        // Room on the right for the names of the easternmost waypoints.
        width: (w * k + NAME_ROOM).ceil(),
        height: (h * k).ceil(),
    }
}

/// `<building>_<level>` as one safe file name.
pub fn picture_stem(b: &Building, level: Handle<Level>) -> String {
    let s: String = format!("{}_{}", b.name, b.levels[level].name)
        .chars()
        .map(|c| {
            if c == '/' || c == '\\' || c == ':' || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    if s.starts_with('.') {
        format!("_{s}")
    } else {
        s
    }
}

/// One SVG per level in `levels`: `<building>_<level>.svg`.
pub fn render_svgs(
    b: &Building,
    levels: &[Handle<Level>],
    opts: &RenderOptions<'_>,
) -> Vec<OutputFile> {
    levels
        .iter()
        .map(|&l| OutputFile {
            path: format!("{}.svg", picture_stem(b, l)).into(),
            contents: render_level(b, l, opts).into_bytes(),
        })
        .collect()
}

/// The diagnostics that belong on `level`'s picture: those located on it, and those
/// located nowhere that lie in the level's part of the file or in no level at all.
fn level_diagnostics<'d>(
    b: &Building,
    level: Handle<Level>,
    diags: &'d [Diagnostic],
) -> Vec<(&'d Diagnostic, Located)> {
    diags
        .iter()
        .filter_map(|d| {
            let at = locate(b, d);
            let mine = match at.level {
                Some(l) => l == level,
                None => {
                    // Not at an element: on the picture of the level whose text holds it,
                    // or on every picture when it is about the building.
                    let in_level = b.levels.iter().find(|(h, _)| {
                        let s = b.levels.span(*h);
                        s.is_known()
                            && s.file == d.span.file
                            && s.start <= d.span.start
                            && d.span.end <= s.end
                    });
                    in_level.is_none_or(|(h, _)| h == level)
                }
            };
            mine.then_some((d, at))
        })
        .collect()
}

/// Draws `level` of `b` as a complete SVG document.
pub fn render_level(b: &Building, level: Handle<Level>, opts: &RenderOptions<'_>) -> String {
    let view = level_view(b, level);
    let diags = opts
        .diagnostics
        .map(|d| level_diagnostics(b, level, d))
        .unwrap_or_default();
    let mut map = Svg::default();
    let present = draw_map(&mut map, b, level, &view, opts.graphs);

    let mut legend = Svg::default();
    let legend_h = draw_legend(&mut legend, b, &present, &diags);

    let map_bottom = view.top + view.height;
    let list_top = map_bottom.max(view.top + legend_h) + SCALE_H;
    let width = view.left + view.width + MARGIN + LEGEND_W;
    let list_h = if diags.is_empty() {
        0.0
    } else {
        LINE_H * (diags.len() as f64 + 1.0) + MARGIN
    };
    let height = list_top + list_h;

    let mut s = Svg::default();
    s.raw(&format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"DejaVu Sans, Verdana, sans-serif\">\n",
        w = num(width.ceil()),
        h = num(height.ceil())
    ));
    let l = &b.levels[level];
    s.raw(&format!(
        "<title>{} level {}</title>\n",
        esc(&b.name),
        esc(&l.name)
    ));
    s.rect(
        0.0,
        0.0,
        width.ceil(),
        height.ceil(),
        &format!(r#"fill="{}""#, colours::BACKGROUND),
    );
    s.text(
        (MARGIN, 30.0),
        20.0,
        r##"font-weight="bold" fill="#222" class="title""##,
        &format!("{}: level {}", b.name, l.name),
    );
    s.text(
        (view.left + view.width, 30.0),
        12.0,
        r##"text-anchor="end" fill="#555""##,
        &format!(
            "elevation {} m, {}",
            num(l.elevation),
            b.coordinate_system.as_str()
        ),
    );
    // The map, clipped to its area so that nothing spills into the legend.
    s.raw(&format!(
        "<clipPath id=\"map-area\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>\n",
        num(view.left),
        num(view.top),
        num(view.width),
        num(view.height)
    ));
    s.rect(
        view.left,
        view.top,
        view.width,
        view.height,
        r##"fill="none" stroke="#bbbbbb" stroke-width="1""##,
    );
    s.raw("<g clip-path=\"url(#map-area)\" class=\"map\">\n");
    s.raw(&map.out);
    if !diags.is_empty() {
        draw_diagnostic_marks(&mut s, &diags, &view);
    }
    s.raw("</g>\n");
    draw_scale_bar(&mut s, &view);
    s.raw(&format!(
        "<g class=\"legend\" transform=\"translate({},{})\">\n",
        num(view.left + view.width + MARGIN),
        num(view.top)
    ));
    s.raw(&legend.out);
    s.raw("</g>\n");
    if !diags.is_empty() {
        draw_diagnostic_list(&mut s, &diags, list_top, width);
    }
    s.raw("</svg>\n");
    s.out
}

/// What a level's map shows, for the legend.
#[derive(Default)]
struct Present {
    floors: bool,
    holes: bool,
    walls: bool,
    doors: bool,
    lifts: bool,
    models: bool,
    waypoints: bool,
    one_way: bool,
    speed_limit: bool,
    graphs: Vec<i64>,
    roles: [bool; 7],
}
