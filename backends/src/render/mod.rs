//! Pictures of levels: `render_level` draws one level of a building as an SVG document
//! (floors and holes, walls, doors, lifts, the lanes of each graph, waypoints with their
//! names and roles, models, a legend, a scale bar and the level name; optionally the
//! diagnostics at their places). `png` rasterises such a document (resvg, embedded font).
//!
//! Pure: no I/O, and the same building gives the same bytes. Picture coordinates are
//! pixels; [`View`] maps map-frame metres to them (y down), and is public so that other
//! drawings (the replay page) can place things on the same picture.

mod locate;
mod png;

pub use locate::{locate, Located};
pub use png::svg_to_png;

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

fn lane_width_px(view: &View) -> f64 {
    (0.08 * view.k).clamp(1.5, 4.0)
}

/// The level's map (everything inside the map area), in drawing order.
fn draw_map(
    s: &mut Svg,
    b: &Building,
    level: Handle<Level>,
    view: &View,
    graphs: Option<&[i64]>,
) -> Present {
    let l = &b.levels[level];
    let mut present = Present::default();
    let vpx = |h: Handle<mapc_ir::Vertex>| view.px(b.vertices[h].pos);

    // Floors, then holes over them.
    s.open(r#"g class="floors""#);
    for &f in &l.floors {
        let pts: Vec<_> = b.floors[f].vertices.iter().map(|&v| vpx(v)).collect();
        if pts.len() >= 3 {
            present.floors = true;
            s.polygon(
                &pts,
                &format!(
                    r#"fill="{}" stroke="{}" stroke-width="1""#,
                    colours::FLOOR,
                    colours::FLOOR_EDGE
                ),
            );
        }
    }
    for &f in &l.holes {
        let pts: Vec<_> = b.holes[f].vertices.iter().map(|&v| vpx(v)).collect();
        if pts.len() >= 3 {
            present.holes = true;
            s.polygon(
                &pts,
                &format!(
                    r##"fill="{}" stroke="#888888" stroke-width="1" stroke-dasharray="4 3""##,
                    colours::HOLE
                ),
            );
        }
    }
    s.close("g");

    // Models: a small square footprint turned by the yaw, with a tick for the heading.
    s.open(r#"g class="models""#);
    for &m in &l.models {
        let m = &b.models[m];
        present.models = true;
        let half = 0.3;
        let corners = [(-half, -half), (half, -half), (half, half), (-half, half)]
            .map(|(x, y)| view.px(Vec2::new(x, y).rotate(m.yaw).plus(m.pos)));
        let mut a = format!(
            r#"fill="{}" fill-opacity="0.35" stroke="{}" stroke-width="1""#,
            colours::MODEL,
            colours::MODEL
        );
        a.push_str(&format!(r#" data-model="{}""#, esc(&m.model_name)));
        s.polygon(&corners, &a);
        s.line(
            view.px(m.pos),
            view.px(Vec2::new(half, 0.0).rotate(m.yaw).plus(m.pos)),
            &format!(r#"stroke="{}" stroke-width="1""#, colours::MODEL),
        );
    }
    s.close("g");

    // Walls.
    let wall_w = (0.15 * view.k).clamp(2.0, 6.0);
    s.open(&format!(
        r#"g class="walls" stroke="{}" stroke-width="{}" stroke-linecap="square""#,
        colours::WALL,
        num(wall_w)
    ));
    for &w in &l.walls {
        let w = &b.walls[w];
        present.walls = true;
        s.line(vpx(w.start), vpx(w.end), "");
    }
    s.close("g");

    // Lifts serving this level: shaft, cabin, and the cabin doors that open here.
    s.open(r#"g class="lifts""#);
    for h in b.lifts_on_level(level) {
        present.lifts = true;
        draw_lift(s, b, h, level, view);
    }
    s.close("g");

    // Doors.
    s.open(r#"g class="doors""#);
    for &d in &l.doors {
        present.doors = true;
        draw_door(s, b, d, view);
    }
    s.close("g");

    // Lanes per graph (offset side by side where graphs share a lane), then waypoints.
    let level_graphs: Vec<i64> = {
        let mut g: Vec<i64> = l
            .lanes
            .iter()
            .map(|&h| b.lanes[h].graph)
            .filter(|g| graphs.is_none_or(|s| s.contains(g)))
            .collect();
        g.sort_unstable();
        g.dedup();
        g
    };
    let lw = lane_width_px(view);
    let mut on_lane = vec![false; b.vertices.len()];
    for (rank, &g) in level_graphs.iter().enumerate() {
        let colour = graph_colour(b, g);
        let shift = (rank as f64 - (level_graphs.len() as f64 - 1.0) / 2.0) * (lw + 1.0);
        s.open(&format!(
            r#"g class="lanes" data-graph="{g}" stroke="{colour}" fill="{colour}""#
        ));
        for &h in &l.lanes {
            let lane = &b.lanes[h];
            if lane.graph != g {
                continue;
            }
            on_lane[lane.start.index()] = true;
            on_lane[lane.end.index()] = true;
            let (a, z) = (vpx(lane.start), vpx(lane.end));
            let (dx, dy) = (z.0 - a.0, z.1 - a.1);
            let len = dx.hypot(dy);
            let (ux, uy) = if len > 0.0 {
                (dx / len, dy / len)
            } else {
                (1.0, 0.0)
            };
            // The same side for a lane and its reverse, so graphs sharing it stay apart.
            let flip = if (ux, uy) < (0.0, 0.0) { -1.0 } else { 1.0 };
            let (nx, ny) = (-uy * shift * flip, ux * shift * flip);
            let a = (a.0 + nx, a.1 + ny);
            let z = (z.0 + nx, z.1 + ny);
            s.line(
                a,
                z,
                &format!(r#"stroke-width="{}" stroke-opacity="0.85""#, num(lw)),
            );
            if !lane.bidirectional && len > 0.0 {
                present.one_way = true;
                let m = ((a.0 + z.0) / 2.0, (a.1 + z.1) / 2.0);
                let size = (3.0 * lw + 3.0).min(len / 2.0);
                let tip = (m.0 + ux * size / 2.0, m.1 + uy * size / 2.0);
                let back = (m.0 - ux * size / 2.0, m.1 - uy * size / 2.0);
                let side = (-uy * size * 0.45, ux * size * 0.45);
                s.polygon(
                    &[
                        tip,
                        (back.0 + side.0, back.1 + side.1),
                        (back.0 - side.0, back.1 - side.1),
                    ],
                    r#"stroke="none" class="one-way""#,
                );
            }
            if let Some(v) = lane.speed_limit {
                present.speed_limit = true;
                let p = (a.0 + dx * 0.3, a.1 + dy * 0.3);
                s.circle(
                    p,
                    lw + 2.5,
                    r##"fill="#ffffff" stroke-width="1.5" class="speed-limit""##,
                );
                s.text(
                    (p.0 + lw + 4.0, p.1 - lw - 3.0),
                    9.0,
                    r#"stroke="none""#,
                    &format!("{} m/s", num(v)),
                );
            }
        }
        s.close("g");
    }
    present.graphs = level_graphs;

    // Waypoints: vertices on a drawn lane, or with a role.
    s.open(r#"g class="waypoints""#);
    for &v in &l.vertices {
        let vx = &b.vertices[v];
        let roles = roles_of(&vx.roles);
        let has_role = roles.iter().any(|&r| r);
        if !on_lane[v.index()] && !has_role {
            continue;
        }
        present.waypoints = true;
        let p = view.px(vx.pos);
        s.circle(
            p,
            lw + 1.0,
            &format!(
                r##"fill="{}" stroke="#ffffff" stroke-width="0.8""##,
                colours::WAYPOINT
            ),
        );
        let mut x = p.0 - 4.0;
        for (i, _) in roles.iter().enumerate().filter(|(_, &r)| r) {
            present.roles[i] = true;
            let (_, letter, colour) = ROLES[i];
            x -= 12.0;
            s.rect(
                x,
                p.1 - 15.0,
                11.0,
                11.0,
                &format!(r#"fill="{colour}" rx="2""#),
            );
            s.text(
                (x + 5.5, p.1 - 6.3),
                9.0,
                r##"fill="#ffffff" text-anchor="middle" font-weight="bold""##,
                letter,
            );
        }
        if !vx.name.is_empty() {
            s.text(
                (p.0 + 4.0, p.1 - 4.0),
                10.0,
                r##"fill="#222222" stroke="#ffffff" stroke-width="2.5" stroke-opacity="0.8" paint-order="stroke" class="wp-name""##,
                &vx.name,
            );
        }
    }
    s.close("g");
    present
}

fn draw_lift(
    s: &mut Svg,
    b: &Building,
    h: Handle<mapc_ir::Lift>,
    level: Handle<Level>,
    view: &View,
) {
    let lift = &b.lifts[h];
    let shaft: Vec<_> = lift.shaft_corners().iter().map(|&c| view.px(c)).collect();
    s.polygon(
        &shaft,
        &format!(
            r##"fill="{}" stroke="#555555" stroke-width="1.5" data-lift="{}" class="shaft""##,
            colours::SHAFT,
            esc(&lift.name)
        ),
    );
    let (w, d) = (lift.width / 2.0, lift.depth / 2.0);
    let cabin: Vec<_> = [(-w, d), (-w, -d), (w, -d), (w, d)]
        .iter()
        .map(|&(x, y)| view.px(Vec2::new(x, y).rotate(lift.yaw).plus(lift.pos)))
        .collect();
    s.raw(&format!(
        "<g class=\"lift-cabin\" data-lift=\"{}\">\n",
        esc(&lift.name)
    ));
    s.polygon(
        &cabin,
        &format!(
            r##"fill="{}" stroke="#444444" stroke-width="1""##,
            colours::CABIN
        ),
    );
    s.close("g");
    // Cabin doors that open on this level: a thick line across the door's width.
    let here: Vec<&str> = lift
        .level_doors
        .iter()
        .filter(|ld| ld.level == level)
        .flat_map(|ld| ld.doors.iter().map(|(n, _)| n.as_str()))
        .collect();
    for door in lift
        .doors
        .iter()
        .filter(|d| here.contains(&d.name.as_str()))
    {
        let axis = Vec2::new(1.0, 0.0).rotate(door.motion_axis_orientation);
        let half = axis.scale(door.width / 2.0);
        let a = door.pos.minus(half).rotate(lift.yaw).plus(lift.pos);
        let z = door.pos.plus(half).rotate(lift.yaw).plus(lift.pos);
        s.line(
            view.px(a),
            view.px(z),
            &format!(
                r#"stroke="{}" stroke-width="{}" class="lift-door" data-lift="{}" data-door="{}""#,
                colours::LIFT_DOOR,
                num((0.12 * view.k).clamp(3.0, 6.0)),
                esc(&lift.name),
                esc(&door.name)
            ),
        );
    }
    // The name above the shaft, clear of the waypoint in the cabin.
    let top = shaft.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let c = view.px(lift.pos);
    s.text(
        (c.0, top - 4.0),
        11.0,
        r##"fill="#222222" text-anchor="middle" font-weight="bold" stroke="#ffffff" stroke-width="3" paint-order="stroke""##,
        &lift.name,
    );
}

/// A door: its closed leaves (`closed-leaf`), the open leaves (`open-leaf`), the swing arcs
/// of hinged doors and the slide path of sliding ones; the replay page shows one state.
fn draw_door(s: &mut Svg, b: &Building, d: Handle<mapc_ir::Door>, view: &View) {
    let door = &b.doors[d];
    let p0 = b.vertices[door.start].pos;
    let p1 = b.vertices[door.end].pos;
    let leaf_w = (0.1 * view.k).clamp(2.0, 5.0);
    s.raw(&format!(
        "<g class=\"door\" data-door=\"{}\" stroke=\"{}\" fill=\"none\">\n",
        esc(&door.name),
        colours::DOOR
    ));
    // Open leaves are drawn thin, as in architectural plans (the replay thickens them
    // while the door is open).
    let leaf = |s: &mut Svg, a: Vec2, z: Vec2, class: &str| {
        let w = if class == "open-leaf" { 1.5 } else { leaf_w };
        s.line(
            view.px(a),
            view.px(z),
            &format!(
                r#"stroke-width="{}" stroke-linecap="butt" class="{class}""#,
                num(w)
            ),
        );
    };
    let dir = if door.motion_direction < 0 { -1.0 } else { 1.0 };
    let swing = |s: &mut Svg, hinge: Vec2, tip: Vec2, sign: f64| {
        // Open leaf and the arc its tip sweeps.
        let angle = sign * door.motion_degrees.clamp(0.0, 180.0).to_radians();
        let r = tip.minus(hinge);
        let open = hinge.plus(r.rotate(angle));
        leaf(s, hinge, open, "open-leaf");
        let (a, z) = (view.px(tip), view.px(open));
        let radius = r.norm() * view.k;
        // Picture y points down: a counter-clockwise turn in the map is clockwise here.
        let sweep = if angle > 0.0 { 0 } else { 1 };
        let large = if angle.abs() > std::f64::consts::PI {
            1
        } else {
            0
        };
        s.path(
            &format!(
                "M{} {} A{} {} 0 {large} {sweep} {} {}",
                num(a.0),
                num(a.1),
                num(radius),
                num(radius),
                num(z.0),
                num(z.1)
            ),
            r#"stroke-width="1" stroke-dasharray="3 2" class="swing""#,
        );
    };
    match door.kind {
        DoorKind::Hinged => {
            let (hinge, tip) = match door.motion_axis {
                mapc_ir::MotionAxis::Start => (p0, p1),
                mapc_ir::MotionAxis::End => (p1, p0),
            };
            leaf(s, hinge, tip, "closed-leaf");
            let sign = if door.motion_axis == mapc_ir::MotionAxis::Start {
                dir
            } else {
                -dir
            };
            swing(s, hinge, tip, sign);
        }
        DoorKind::DoubleHinged => {
            let r = door.right_left_ratio.max(0.0);
            let m = p0.plus(p1.minus(p0).scale(r / (1.0 + r)));
            leaf(s, p0, m, "closed-leaf");
            leaf(s, p1, m, "closed-leaf");
            swing(s, p0, m, dir);
            swing(s, p1, m, -dir);
        }
        DoorKind::Sliding | DoorKind::DoubleSliding | DoorKind::Other(_) => {
            // Panels a little beside the opening; open, they sit beside it along the wall.
            let along = p1.minus(p0);
            let n = Vec2::new(-along.y, along.x).scale(0.06 / along.norm().max(1e-9));
            let (a, z) = (p0.plus(n), p1.plus(n));
            if door.kind == DoorKind::DoubleSliding {
                let m = a.plus(z.minus(a).scale(0.5));
                leaf(s, a, m, "closed-leaf");
                leaf(s, m, z, "closed-leaf");
                let half = along.scale(0.5);
                leaf(s, a.minus(half), a, "open-leaf");
                leaf(s, z, z.plus(half), "open-leaf");
            } else {
                leaf(s, a, z, "closed-leaf");
                leaf(s, z, z.plus(along), "open-leaf");
            }
            s.line(
                view.px(p0),
                view.px(p1),
                r#"stroke-width="1" stroke-dasharray="3 2" class="swing""#,
            );
        }
    }
    s.close("g");
}

/// The scale bar under the map: a round length about a fifth of the map's width.
fn draw_scale_bar(s: &mut Svg, view: &View) {
    let target = view.width / 5.0 / view.k;
    let mag = 10f64.powf(target.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|f| f * mag)
        .rfind(|&l| l <= target)
        .unwrap_or(mag);
    let x = view.left;
    let y = view.top + view.height + 22.0;
    let px = len * view.k;
    s.open(r#"g class="scale-bar""#);
    for i in 0..4 {
        let fill = if i % 2 == 0 { "#222222" } else { "#ffffff" };
        s.rect(
            x + px * i as f64 / 4.0,
            y,
            px / 4.0,
            6.0,
            &format!(r##"fill="{fill}" stroke="#222222" stroke-width="1""##),
        );
    }
    s.text((x, y + 20.0), 11.0, r##"fill="#222222""##, "0");
    s.text(
        (x + px, y + 20.0),
        11.0,
        r##"fill="#222222" text-anchor="middle""##,
        &format!("{} m", num(len)),
    );
    s.close("g");
}

/// The legend (translated to the legend column); returns its height.
fn draw_legend(s: &mut Svg, b: &Building, p: &Present, diags: &[(&Diagnostic, Located)]) -> f64 {
    let mut y = 16.0;
    s.text(
        (0.0, y),
        14.0,
        r##"font-weight="bold" fill="#222222""##,
        "Legend",
    );
    y += 10.0;
    let label = |s: &mut Svg, y: f64, text: &str| {
        s.text((34.0, y + 4.0), 11.0, r##"fill="#222222""##, text);
    };
    let mut item = |s: &mut Svg, draw: &dyn Fn(&mut Svg, f64), text: &str| {
        y += 18.0;
        draw(s, y);
        label(s, y, text);
    };
    if p.floors {
        item(
            s,
            &|s, y| {
                s.rect(
                    2.0,
                    y - 6.0,
                    24.0,
                    12.0,
                    &format!(
                        r#"fill="{}" stroke="{}""#,
                        colours::FLOOR,
                        colours::FLOOR_EDGE
                    ),
                )
            },
            "floor",
        );
    }
    if p.holes {
        item(
            s,
            &|s, y| {
                s.rect(
                    2.0,
                    y - 6.0,
                    24.0,
                    12.0,
                    r##"fill="#ffffff" stroke="#888888" stroke-dasharray="4 3""##,
                )
            },
            "hole",
        );
    }
    if p.walls {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    &format!(r#"stroke="{}" stroke-width="4""#, colours::WALL),
                )
            },
            "wall",
        );
    }
    if p.doors {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y + 5.0),
                    (26.0, y + 5.0),
                    &format!(r#"stroke="{}" stroke-width="3""#, colours::DOOR),
                );
                s.path(
                    &format!("M26 {} A24 12 0 0 0 2 {}", num(y + 5.0), num(y - 7.0)),
                    &format!(
                        r#"stroke="{}" fill="none" stroke-dasharray="3 2""#,
                        colours::DOOR
                    ),
                );
            },
            "door (swing / slide)",
        );
    }
    if p.lifts {
        item(
            s,
            &|s, y| {
                s.rect(
                    2.0,
                    y - 7.0,
                    24.0,
                    14.0,
                    &format!(r##"fill="{}" stroke="#555555""##, colours::SHAFT),
                );
                s.rect(
                    6.0,
                    y - 4.0,
                    16.0,
                    8.0,
                    &format!(r##"fill="{}" stroke="#444444""##, colours::CABIN),
                );
                s.line(
                    (26.0, y - 4.0),
                    (26.0, y + 4.0),
                    &format!(r#"stroke="{}" stroke-width="3""#, colours::LIFT_DOOR),
                );
            },
            "lift: shaft, cabin, door",
        );
    }
    if p.models {
        item(
            s,
            &|s, y| {
                s.rect(
                    8.0,
                    y - 6.0,
                    12.0,
                    12.0,
                    &format!(
                        r#"fill="{}" fill-opacity="0.35" stroke="{}""#,
                        colours::MODEL,
                        colours::MODEL
                    ),
                )
            },
            "model",
        );
    }
    for &g in &p.graphs {
        let colour = graph_colour(b, g);
        let name = b
            .graphs
            .iter()
            .find(|i| i.index == g)
            .map(|i| i.name.as_str())
            .filter(|n| !n.is_empty());
        let text = match name {
            Some(n) => format!("lanes of graph {g} ({n})"),
            None => format!("lanes of graph {g}"),
        };
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    &format!(r#"stroke="{colour}" stroke-width="3""#),
                )
            },
            &text,
        );
    }
    if p.one_way {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    r##"stroke="#555555" stroke-width="2""##,
                );
                s.polygon(
                    &[(20.0, y), (10.0, y - 5.0), (10.0, y + 5.0)],
                    r##"fill="#555555""##,
                );
            },
            "one-way lane",
        );
    }
    if p.speed_limit {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    r##"stroke="#555555" stroke-width="2""##,
                );
                s.circle(
                    (14.0, y),
                    4.5,
                    r##"fill="#ffffff" stroke="#555555" stroke-width="1.5""##,
                );
            },
            "speed limit (m/s)",
        );
    }
    if p.waypoints {
        item(
            s,
            &|s, y| s.circle((14.0, y), 3.5, &format!(r#"fill="{}""#, colours::WAYPOINT)),
            "waypoint",
        );
    }
    for (i, &(text, letter, colour)) in ROLES.iter().enumerate() {
        if p.roles[i] {
            item(
                s,
                &|s, y| {
                    s.rect(
                        8.0,
                        y - 6.0,
                        12.0,
                        12.0,
                        &format!(r#"fill="{colour}" rx="2""#),
                    );
                    s.text(
                        (14.0, y + 3.5),
                        9.0,
                        r##"fill="#ffffff" text-anchor="middle" font-weight="bold""##,
                        letter,
                    );
                },
                text,
            );
        }
    }
    let severities = [
        (Severity::Error, "error", colours::ERROR),
        (Severity::Warning, "warning", colours::WARNING),
    ];
    for (sev, text, colour) in severities {
        if diags.iter().any(|(d, _)| d.severity == sev) {
            item(
                s,
                &|s, y| {
                    s.circle(
                        (14.0, y),
                        6.0,
                        &format!(r#"fill="{colour}" fill-opacity="0.25" stroke="{colour}" stroke-width="2""#),
                    )
                },
                &format!("diagnostic: {text}"),
            );
        }
    }
    y + 12.0
}

fn severity_colour(s: Severity) -> &'static str {
    match s {
        Severity::Error => colours::ERROR,
        Severity::Warning => colours::WARNING,
    }
}

fn draw_diagnostic_marks(s: &mut Svg, diags: &[(&Diagnostic, Located)], view: &View) {
    s.open(r#"g class="diagnostics""#);
    for (i, (d, at)) in diags.iter().enumerate() {
        let Some(p) = at.at else { continue };
        let colour = severity_colour(d.severity);
        let c = view.px(p);
        for &q in &at.labels {
            let lq = view.px(q);
            s.line(
                c,
                lq,
                &format!(r#"stroke="{colour}" stroke-width="1.5" stroke-dasharray="4 3""#),
            );
            s.circle(
                lq,
                6.0,
                &format!(r#"fill="none" stroke="{colour}" stroke-width="2""#),
            );
        }
        s.circle(
            c,
            9.0,
            &format!(r#"fill="{colour}" fill-opacity="0.25" stroke="{colour}" stroke-width="2.5""#),
        );
        s.text(
            (c.0 + 11.0, c.1 + 14.0),
            11.0,
            &format!(
                r##"fill="{colour}" font-weight="bold" stroke="#ffffff" stroke-width="3" paint-order="stroke""##
            ),
            &format!("{} {}", i + 1, d.code),
        );
    }
    s.close("g");
}

fn draw_diagnostic_list(s: &mut Svg, diags: &[(&Diagnostic, Located)], top: f64, width: f64) {
    s.open(r#"g class="diagnostic-list""#);
    s.text(
        (MARGIN, top + LINE_H - 2.0),
        13.0,
        r##"font-weight="bold" fill="#222222""##,
        &format!("Diagnostics ({})", diags.len()),
    );
    let max_chars = ((width - 2.0 * MARGIN) / 6.2).max(20.0) as usize;
    for (i, (d, at)) in diags.iter().enumerate() {
        let sev = match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let place = if at.at.is_some() {
            ""
        } else {
            " (no place on the map)"
        };
        let mut line = format!(
            "{}. {} {sev} [{}:{}] {}{place}",
            i + 1,
            d.code,
            d.span.line,
            d.span.col,
            d.message
        );
        if line.chars().count() > max_chars {
            line = line.chars().take(max_chars - 1).collect::<String>() + "…";
        }
        s.text(
            (MARGIN, top + LINE_H * (i as f64 + 2.0) - 2.0),
            11.0,
            &format!(r#"fill="{}""#, severity_colour(d.severity)),
            &line,
        );
    }
    s.close("g");
}

#[cfg(test)]
mod tests;
