//! The semantic difference between two buildings: what a reviewer wants to know, not
//! which lines moved. Elements have no stable ids in the format (vertices are list
//! positions), so they are matched by meaning: levels, doors and lifts by name; waypoints
//! by name on their level, then the rest by position (within 1 cm); lanes by the waypoints
//! they join; walls and floors by their corner positions.

use mapc_ir::{Building, Diagnostic, Handle, Level, Vec2, Vertex, WaypointRoles};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// Positions closer than this are the same place (and a waypoint moved less did not move).
pub(crate) const SAME_PLACE: f64 = 0.01;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Section {
    Levels,
    Waypoints,
    Lanes,
    Doors,
    Lifts,
    Walls,
    Floors,
    Connectivity,
    Diagnostics,
}

impl Section {
    pub(crate) fn title(self) -> &'static str {
        match self {
            Section::Levels => "Levels",
            Section::Waypoints => "Waypoints",
            Section::Lanes => "Lanes",
            Section::Doors => "Doors",
            Section::Lifts => "Lifts",
            Section::Walls => "Walls",
            Section::Floors => "Floors",
            Section::Connectivity => "Connectivity",
            Section::Diagnostics => "Diagnostics",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Kind {
    Added,
    Removed,
    Changed,
}

/// One change. `subject` names the element ("waypoint `lobby`"), `detail` says how.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub(crate) struct Change {
    pub(crate) section: Section,
    pub(crate) level: Option<String>,
    #[serde(rename = "change")]
    pub(crate) kind: Kind,
    pub(crate) subject: String,
    pub(crate) detail: String,
}

/// A map to compare: its building and its diagnostics (at the user's lint levels).
pub(crate) struct Side<'a> {
    pub(crate) building: &'a Building,
    pub(crate) diagnostics: &'a [Diagnostic],
}

pub(crate) fn diff(old: &Side, new: &Side) -> Vec<Change> {
    let mut out = Vec::new();
    levels(old.building, new.building, &mut out);
    let ids = Ids::match_waypoints(old.building, new.building, &mut out);
    lanes(old.building, new.building, &ids, &mut out);
    doors(old.building, new.building, &mut out);
    lifts(old.building, new.building, &mut out);
    walls(old.building, new.building, &mut out);
    floors(old.building, new.building, &mut out);
    connectivity(old.building, new.building, &ids, &mut out);
    diagnostics(old.diagnostics, new.diagnostics, &mut out);
    out.sort_by(|a, b| {
        (a.section, &a.level, a.kind, &a.subject, &a.detail)
            .cmp(&(b.section, &b.level, b.kind, &b.subject, &b.detail))
    });
    out.dedup();
    out
}

fn change(
    section: Section,
    level: Option<&str>,
    kind: Kind,
    subject: String,
    detail: String,
) -> Change {
    Change {
        section,
        level: level.map(str::to_string),
        kind,
        subject,
        detail,
    }
}

fn num(x: f64) -> String {
    // Two decimals, no `-0.00`.
    let s = format!("{x:.2}");
    if s == "-0.00" {
        "0.00".into()
    } else {
        s
    }
}

fn at(p: Vec2) -> String {
    format!("({}, {})", num(p.x), num(p.y))
}

fn level_name(b: &Building, h: Handle<Level>) -> &str {
    &b.levels[h].name
}

fn levels(old: &Building, new: &Building, out: &mut Vec<Change>) {
    let by_name = |b: &Building| -> BTreeMap<String, f64> {
        b.levels
            .iter()
            .map(|(_, l)| (l.name.clone(), l.elevation))
            .collect()
    };
    let (o, n) = (by_name(old), by_name(new));
    for (name, e) in &o {
        match n.get(name) {
            None => out.push(change(
                Section::Levels,
                None,
                Kind::Removed,
                format!("level `{name}`"),
                format!("elevation {} m", num(*e)),
            )),
            Some(e2) if (e - e2).abs() > 1e-9 => out.push(change(
                Section::Levels,
                None,
                Kind::Changed,
                format!("level `{name}`"),
                format!("elevation {} m → {} m", num(*e), num(*e2)),
            )),
            _ => {}
        }
    }
    for (name, e) in &n {
        if !o.contains_key(name) {
            out.push(change(
                Section::Levels,
                None,
                Kind::Added,
                format!("level `{name}`"),
                format!("elevation {} m", num(*e)),
            ));
        }
    }
}

/// Waypoints: vertices used by a lane or with a name.
fn waypoints(b: &Building) -> Vec<Handle<Vertex>> {
    let mut used = vec![false; b.vertices.len()];
    for (_, l) in b.lanes.iter() {
        used[l.start.index()] = true;
        used[l.end.index()] = true;
    }
    b.vertices
        .iter()
        .filter(|(h, v)| used[h.index()] || !v.name.is_empty())
        .map(|(h, _)| h)
        .collect()
}

fn waypoint_name(b: &Building, v: Handle<Vertex>) -> String {
    let vx = &b.vertices[v];
    if vx.name.is_empty() {
        format!("unnamed waypoint at {}", at(vx.pos))
    } else {
        format!("waypoint `{}`", vx.name)
    }
}

/// A shared identity for the waypoints matched between the two maps (old and new vertex
/// handles map to the same number); unmatched ones get their own.
pub(crate) struct Ids {
    old: HashMap<Handle<Vertex>, usize>,
    new: HashMap<Handle<Vertex>, usize>,
    next: usize,
}

impl Ids {
    fn id(&mut self, new_side: bool, v: Handle<Vertex>) -> usize {
        let next = &mut self.next;
        let map = if new_side {
            &mut self.new
        } else {
            &mut self.old
        };
        *map.entry(v).or_insert_with(|| {
            *next += 1;
            *next
        })
    }

    fn match_waypoints(old: &Building, new: &Building, out: &mut Vec<Change>) -> Ids {
        let mut ids = Ids {
            old: HashMap::new(),
            new: HashMap::new(),
            next: 0,
        };
        let per_level = |b: &Building| -> BTreeMap<String, Vec<Handle<Vertex>>> {
            let mut m: BTreeMap<String, Vec<Handle<Vertex>>> = BTreeMap::new();
            for v in waypoints(b) {
                m.entry(level_name(b, b.vertices[v].level).to_string())
                    .or_default()
                    .push(v);
            }
            m
        };
        let (po, pn) = (per_level(old), per_level(new));
        let names: BTreeSet<&String> = po.keys().chain(pn.keys()).collect();
        for level in names {
            let empty = Vec::new();
            let (vo, vn) = (
                po.get(level).unwrap_or(&empty),
                pn.get(level).unwrap_or(&empty),
            );
            let lvl = Some(level.as_str());
            // 1. Same name on the same level.
            let mut new_by_name: HashMap<&str, Vec<Handle<Vertex>>> = HashMap::new();
            for &v in vn {
                if !new.vertices[v].name.is_empty() {
                    new_by_name
                        .entry(&new.vertices[v].name)
                        .or_default()
                        .push(v);
                }
            }
            let mut left_old = Vec::new();
            let mut taken_new: BTreeSet<Handle<Vertex>> = BTreeSet::new();
            for &v in vo {
                let name = &old.vertices[v].name;
                let m = new_by_name
                    .get_mut(name.as_str())
                    .and_then(|c| (!c.is_empty()).then(|| c.remove(0)));
                match m {
                    Some(w) => {
                        taken_new.insert(w);
                        let id = ids.id(false, v);
                        ids.new.insert(w, id);
                        let (a, b) = (old.vertices[v].pos, new.vertices[w].pos);
                        let d = a.minus(b).norm();
                        if d > SAME_PLACE {
                            out.push(change(
                                Section::Waypoints,
                                lvl,
                                Kind::Changed,
                                waypoint_name(old, v),
                                format!("moved {} m: {} → {}", num(d), at(a), at(b)),
                            ));
                        }
                        roles_changed(old, v, new, w, lvl, out);
                    }
                    None => left_old.push(v),
                }
            }
            let left_new: Vec<Handle<Vertex>> = vn
                .iter()
                .copied()
                .filter(|w| !taken_new.contains(w))
                .collect();
            // 2. The rest by place: a new name at the same place is a rename.
            let mut grid: HashMap<(i64, i64), Vec<Handle<Vertex>>> = HashMap::new();
            let cell = |p: Vec2| {
                (
                    (p.x / SAME_PLACE).floor() as i64,
                    (p.y / SAME_PLACE).floor() as i64,
                )
            };
            for &w in &left_new {
                grid.entry(cell(new.vertices[w].pos)).or_default().push(w);
            }
            let mut matched_new: BTreeSet<Handle<Vertex>> = BTreeSet::new();
            for &v in &left_old {
                let p = old.vertices[v].pos;
                let (cx, cy) = cell(p);
                let mut best: Option<(f64, Handle<Vertex>)> = None;
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for &w in grid.get(&(cx + dx, cy + dy)).map_or(&[][..], |v| v) {
                            let d = new.vertices[w].pos.minus(p).norm();
                            if d <= SAME_PLACE
                                && !matched_new.contains(&w)
                                && best.is_none_or(|(bd, _)| d < bd)
                            {
                                best = Some((d, w));
                            }
                        }
                    }
                }
                match best {
                    Some((_, w)) => {
                        matched_new.insert(w);
                        let id = ids.id(false, v);
                        ids.new.insert(w, id);
                        let (a, b) = (&old.vertices[v].name, &new.vertices[w].name);
                        if a != b {
                            let what = |s: &str| {
                                if s.is_empty() {
                                    "(no name)".to_string()
                                } else {
                                    format!("`{s}`")
                                }
                            };
                            out.push(change(
                                Section::Waypoints,
                                lvl,
                                Kind::Changed,
                                waypoint_name(old, v),
                                format!("renamed {} → {}", what(a), what(b)),
                            ));
                        }
                        roles_changed(old, v, new, w, lvl, out);
                    }
                    None => {
                        ids.id(false, v);
                        out.push(change(
                            Section::Waypoints,
                            lvl,
                            Kind::Removed,
                            waypoint_name(old, v),
                            format!("was at {}", at(old.vertices[v].pos)),
                        ));
                    }
                }
            }
            for &w in &left_new {
                if !matched_new.contains(&w) {
                    ids.id(true, w);
                    out.push(change(
                        Section::Waypoints,
                        lvl,
                        Kind::Added,
                        waypoint_name(new, w),
                        format!("at {}", at(new.vertices[w].pos)),
                    ));
                }
            }
        }
        ids
    }
}

fn roles_text(r: &WaypointRoles) -> String {
    let v = r.describe();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

fn roles_changed(
    old: &Building,
    v: Handle<Vertex>,
    new: &Building,
    w: Handle<Vertex>,
    lvl: Option<&str>,
    out: &mut Vec<Change>,
) {
    let (a, b) = (
        roles_text(&old.vertices[v].roles),
        roles_text(&new.vertices[w].roles),
    );
    if a != b {
        out.push(change(
            Section::Waypoints,
            lvl,
            Kind::Changed,
            waypoint_name(old, v),
            format!("roles {a} → {b}"),
        ));
    }
}

/// A lane's properties that a change can touch.
#[derive(Debug, Clone, PartialEq)]
struct LaneInfo {
    graph: i64,
    /// `None` two-way; `Some(true)` one-way from the lower id to the higher.
    one_way_up: Option<bool>,
    speed: Option<f64>,
    orientation: String,
    label: String,
}

fn lane_infos(
    b: &Building,
    new_side: bool,
    ids: &mut Ids,
) -> BTreeMap<(String, usize, usize), Vec<LaneInfo>> {
    let mut m: BTreeMap<(String, usize, usize), Vec<LaneInfo>> = BTreeMap::new();
    for (_, l) in b.lanes.iter() {
        let (a, z) = (ids.id(new_side, l.start), ids.id(new_side, l.end));
        let name = |v: Handle<Vertex>| {
            let vx = &b.vertices[v];
            if vx.name.is_empty() {
                at(vx.pos)
            } else {
                format!("`{}`", vx.name)
            }
        };
        let (lo, hi) = (a.min(z), a.max(z));
        let (first, second) = if a <= z {
            (l.start, l.end)
        } else {
            (l.end, l.start)
        };
        let info = LaneInfo {
            graph: l.graph,
            one_way_up: (!l.bidirectional).then_some(a <= z),
            speed: l.speed_limit,
            orientation: l.orientation.as_str().to_string(),
            label: format!("lane {} – {}", name(first), name(second)),
        };
        m.entry((level_name(b, l.level).to_string(), lo, hi))
            .or_default()
            .push(info);
    }
    m
}

fn direction(i: &LaneInfo) -> String {
    let ends = i.label.trim_start_matches("lane ");
    let mut parts = ends.splitn(2, " – ");
    let (a, b) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    match i.one_way_up {
        None => "two-way".into(),
        Some(true) => format!("one-way {a} → {b}"),
        Some(false) => format!("one-way {b} → {a}"),
    }
}

fn speed(s: Option<f64>) -> String {
    s.map_or("none".into(), |v| format!("{} m/s", num(v)))
}

fn lane_text(i: &LaneInfo) -> String {
    let mut s = format!("graph {}, {}", i.graph, direction(i));
    if i.speed.is_some() {
        s.push_str(&format!(", speed limit {}", speed(i.speed)));
    }
    if !i.orientation.is_empty() {
        s.push_str(&format!(", orientation {}", i.orientation));
    }
    s
}

fn lanes(old: &Building, new: &Building, ids: &Ids, out: &mut Vec<Change>) {
    let mut ids = Ids {
        old: ids.old.clone(),
        new: ids.new.clone(),
        next: ids.next,
    };
    let (o, n) = (
        lane_infos(old, false, &mut ids),
        lane_infos(new, true, &mut ids),
    );
    let keys: BTreeSet<&(String, usize, usize)> = o.keys().chain(n.keys()).collect();
    for key in keys {
        let lvl = Some(key.0.as_str());
        let empty = Vec::new();
        let (lo, ln) = (o.get(key).unwrap_or(&empty), n.get(key).unwrap_or(&empty));
        // Identical lanes on both sides are no change.
        let mut lo: Vec<&LaneInfo> = lo.iter().collect();
        let mut ln: Vec<&LaneInfo> = ln
            .iter()
            .filter(|x| {
                let same = |y: &&LaneInfo| {
                    y.graph == x.graph
                        && y.one_way_up == x.one_way_up
                        && y.speed == x.speed
                        && y.orientation == x.orientation
                };
                match lo.iter().position(same) {
                    Some(i) => {
                        lo.remove(i);
                        false
                    }
                    None => true,
                }
            })
            .collect();
        // One left on each side: the same lane, changed; pair by graph first.
        while !lo.is_empty() && !ln.is_empty() {
            let i = lo
                .iter()
                .position(|a| ln.iter().any(|b| b.graph == a.graph))
                .unwrap_or(0);
            let a = lo.remove(i);
            let j = ln.iter().position(|b| b.graph == a.graph).unwrap_or(0);
            let b = ln.remove(j);
            let mut what = Vec::new();
            if a.graph != b.graph {
                what.push(format!("graph {} → {}", a.graph, b.graph));
            }
            if a.one_way_up != b.one_way_up {
                what.push(format!("{} → {}", direction(a), direction(b)));
            }
            if a.speed != b.speed {
                what.push(format!(
                    "speed limit {} → {}",
                    speed(a.speed),
                    speed(b.speed)
                ));
            }
            if a.orientation != b.orientation {
                let o = |s: &str| {
                    if s.is_empty() {
                        "any".to_string()
                    } else {
                        s.to_string()
                    }
                };
                what.push(format!(
                    "orientation {} → {}",
                    o(&a.orientation),
                    o(&b.orientation)
                ));
            }
            out.push(change(
                Section::Lanes,
                lvl,
                Kind::Changed,
                b.label.clone(),
                what.join("; "),
            ));
        }
        for a in lo {
            out.push(change(
                Section::Lanes,
                lvl,
                Kind::Removed,
                a.label.clone(),
                lane_text(a),
            ));
        }
        for b in ln {
            out.push(change(
                Section::Lanes,
                lvl,
                Kind::Added,
                b.label.clone(),
                lane_text(b),
            ));
        }
    }
}

fn doors(old: &Building, new: &Building, out: &mut Vec<Change>) {
    struct D {
        level: String,
        kind: String,
        centre: Vec2,
        width: f64,
    }
    let all = |b: &Building| -> BTreeMap<String, D> {
        b.doors
            .iter()
            .map(|(_, d)| {
                let (s, e) = (b.vertices[d.start].pos, b.vertices[d.end].pos);
                (
                    d.name.clone(),
                    D {
                        level: level_name(b, d.level).to_string(),
                        kind: d.kind.as_str().to_string(),
                        centre: s.plus(e).scale(0.5),
                        width: s.minus(e).norm(),
                    },
                )
            })
            .collect()
    };
    let (o, n) = (all(old), all(new));
    for (name, a) in &o {
        let subject = format!("door `{name}`");
        match n.get(name) {
            None => out.push(change(
                Section::Doors,
                Some(&a.level),
                Kind::Removed,
                subject,
                format!(
                    "{} door, {} m wide, at {}",
                    a.kind,
                    num(a.width),
                    at(a.centre)
                ),
            )),
            Some(b) => {
                let mut what = Vec::new();
                if a.level != b.level {
                    what.push(format!("level `{}` → `{}`", a.level, b.level));
                }
                if a.kind != b.kind {
                    what.push(format!("type {} → {}", a.kind, b.kind));
                }
                if (a.width - b.width).abs() > SAME_PLACE {
                    what.push(format!("width {} m → {} m", num(a.width), num(b.width)));
                }
                let d = a.centre.minus(b.centre).norm();
                if d > SAME_PLACE {
                    what.push(format!(
                        "moved {} m: {} → {}",
                        num(d),
                        at(a.centre),
                        at(b.centre)
                    ));
                }
                if !what.is_empty() {
                    out.push(change(
                        Section::Doors,
                        Some(&b.level),
                        Kind::Changed,
                        subject,
                        what.join("; "),
                    ));
                }
            }
        }
    }
    for (name, b) in &n {
        if !o.contains_key(name) {
            out.push(change(
                Section::Doors,
                Some(&b.level),
                Kind::Added,
                format!("door `{name}`"),
                format!(
                    "{} door, {} m wide, at {}",
                    b.kind,
                    num(b.width),
                    at(b.centre)
                ),
            ));
        }
    }
}

/// What a lift change can touch: cabin centre, width, depth, levels served, cabin doors.
type LiftInfo = (Vec2, f64, f64, Vec<String>, Vec<String>);

fn lifts(old: &Building, new: &Building, out: &mut Vec<Change>) {
    let all = |b: &Building| -> BTreeMap<String, LiftInfo> {
        b.lifts
            .iter()
            .map(|(_, l)| {
                let levels = l
                    .level_doors
                    .iter()
                    .map(|ld| level_name(b, ld.level).to_string())
                    .collect();
                let doors = l.doors.iter().map(|d| d.name.clone()).collect();
                (l.name.clone(), (l.pos, l.width, l.depth, levels, doors))
            })
            .collect()
    };
    let (o, n) = (all(old), all(new));
    let describe = |(p, w, d, levels, _): &LiftInfo| {
        format!(
            "{} × {} m cabin at {}, serving {}",
            num(*w),
            num(*d),
            at(*p),
            if levels.is_empty() {
                "no level".to_string()
            } else {
                levels.join(", ")
            }
        )
    };
    for (name, a) in &o {
        let subject = format!("lift `{name}`");
        match n.get(name) {
            None => out.push(change(
                Section::Lifts,
                None,
                Kind::Removed,
                subject,
                describe(a),
            )),
            Some(b) => {
                let mut what = Vec::new();
                let d = a.0.minus(b.0).norm();
                if d > SAME_PLACE {
                    what.push(format!("moved {} m: {} → {}", num(d), at(a.0), at(b.0)));
                }
                if (a.1 - b.1).abs() > SAME_PLACE || (a.2 - b.2).abs() > SAME_PLACE {
                    what.push(format!(
                        "cabin {} × {} m → {} × {} m",
                        num(a.1),
                        num(a.2),
                        num(b.1),
                        num(b.2)
                    ));
                }
                if a.3 != b.3 {
                    what.push(format!(
                        "levels served {} → {}",
                        a.3.join(", "),
                        b.3.join(", ")
                    ));
                }
                if a.4 != b.4 {
                    what.push(format!(
                        "cabin doors {} → {}",
                        a.4.join(", "),
                        b.4.join(", ")
                    ));
                }
                if !what.is_empty() {
                    out.push(change(
                        Section::Lifts,
                        None,
                        Kind::Changed,
                        subject,
                        what.join("; "),
                    ));
                }
            }
        }
    }
    for (name, b) in &n {
        if !o.contains_key(name) {
            out.push(change(
                Section::Lifts,
                None,
                Kind::Added,
                format!("lift `{name}`"),
                describe(b),
            ));
        }
    }
}

/// Per level name.
type PerLevel<T> = BTreeMap<String, T>;
/// A position rounded to the centimetre.
type Key = (i64, i64);
/// Wall segments (ends ordered) with their count and length.
type Segments = BTreeMap<(Key, Key), (usize, f64)>;
/// Floor polygons: canonical corners and area.
type Polygons = Vec<(Vec<Key>, f64)>;

/// A position rounded to the centimetre, as a key.
fn key(p: Vec2) -> (i64, i64) {
    (
        (p.x / SAME_PLACE).round() as i64,
        (p.y / SAME_PLACE).round() as i64,
    )
}

fn walls(old: &Building, new: &Building, out: &mut Vec<Change>) {
    // Per level: the multiset of wall segments (unordered ends), with their lengths.
    let all = |b: &Building| -> PerLevel<Segments> {
        let mut m: PerLevel<Segments> = BTreeMap::new();
        for (_, w) in b.walls.iter() {
            let (s, e) = (b.vertices[w.start].pos, b.vertices[w.end].pos);
            let (ks, ke) = (key(s), key(e));
            let k = (ks.min(ke), ks.max(ke));
            let entry = m
                .entry(level_name(b, w.level).to_string())
                .or_default()
                .entry(k)
                .or_insert((0, s.minus(e).norm()));
            entry.0 += 1;
        }
        m
    };
    let (o, n) = (all(old), all(new));
    let levels: BTreeSet<&String> = o.keys().chain(n.keys()).collect();
    let empty = BTreeMap::new();
    for level in levels {
        let (a, b) = (
            o.get(level).unwrap_or(&empty),
            n.get(level).unwrap_or(&empty),
        );
        let (mut added, mut removed, mut la, mut lr) = (0, 0, 0.0, 0.0);
        for (k, (c, len)) in a {
            let c2 = b.get(k).map_or(0, |x| x.0);
            if *c > c2 {
                removed += c - c2;
                lr += (c - c2) as f64 * len;
            }
        }
        for (k, (c, len)) in b {
            let c1 = a.get(k).map_or(0, |x| x.0);
            if *c > c1 {
                added += c - c1;
                la += (c - c1) as f64 * len;
            }
        }
        let lvl = Some(level.as_str());
        if added > 0 {
            out.push(change(
                Section::Walls,
                lvl,
                Kind::Added,
                crate::ui::plural(added, "wall"),
                format!("{} m", num(la)),
            ));
        }
        if removed > 0 {
            out.push(change(
                Section::Walls,
                lvl,
                Kind::Removed,
                crate::ui::plural(removed, "wall"),
                format!("{} m", num(lr)),
            ));
        }
    }
}

fn area(points: &[Vec2]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].cross(points[(i + 1) % n]))
        .sum::<f64>()
        .abs()
        / 2.0
}

/// A closed polygon's corners independent of start corner and direction: the smaller of
/// the two rotations that start at the lowest corner.
fn canonical(mut keys: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
    let Some(i) = keys
        .iter()
        .enumerate()
        .min_by_key(|(_, k)| **k)
        .map(|(i, _)| i)
    else {
        return keys;
    };
    keys.rotate_left(i);
    let mut rev = keys.clone();
    rev[1..].reverse();
    keys.min(rev)
}

fn floors(old: &Building, new: &Building, out: &mut Vec<Change>) {
    // A floor is its corners (from the lowest key, so the start point does not matter).
    let all = |b: &Building| -> PerLevel<Polygons> {
        let mut m: PerLevel<Polygons> = BTreeMap::new();
        for (_, f) in b.floors.iter() {
            let pts: Vec<Vec2> = f.vertices.iter().map(|&v| b.vertices[v].pos).collect();
            let keys: Vec<(i64, i64)> = pts.iter().map(|&p| key(p)).collect();
            m.entry(level_name(b, f.level).to_string())
                .or_default()
                .push((canonical(keys), area(&pts)));
        }
        m
    };
    let (o, n) = (all(old), all(new));
    let levels: BTreeSet<&String> = o.keys().chain(n.keys()).collect();
    for level in levels {
        let mut a = o.get(level).cloned().unwrap_or_default();
        let mut b = n.get(level).cloned().unwrap_or_default();
        a.retain(|x| match b.iter().position(|y| y.0 == x.0) {
            Some(i) => {
                b.remove(i);
                false
            }
            None => true,
        });
        let lvl = Some(level.as_str());
        let total = |v: &[(Vec<(i64, i64)>, f64)]| v.iter().map(|x| x.1).sum::<f64>();
        if !b.is_empty() {
            out.push(change(
                Section::Floors,
                lvl,
                Kind::Added,
                crate::ui::plural(b.len(), "floor polygon"),
                format!("{} m²", num(total(&b))),
            ));
        }
        if !a.is_empty() {
            out.push(change(
                Section::Floors,
                lvl,
                Kind::Removed,
                crate::ui::plural(a.len(), "floor polygon"),
                format!("{} m²", num(total(&a))),
            ));
        }
    }
}

/// Per graph, the waypoints in the largest connected piece (lanes as undirected edges,
/// across levels where lanes join them), by shared id.
fn main_piece(
    b: &Building,
    new_side: bool,
    ids: &mut Ids,
) -> BTreeMap<i64, (BTreeSet<usize>, HashMap<usize, String>)> {
    let mut edges: BTreeMap<i64, Vec<(usize, usize)>> = BTreeMap::new();
    let mut names: HashMap<usize, String> = HashMap::new();
    for (_, l) in b.lanes.iter() {
        let (a, z) = (ids.id(new_side, l.start), ids.id(new_side, l.end));
        names.entry(a).or_insert_with(|| waypoint_name(b, l.start));
        names.entry(z).or_insert_with(|| waypoint_name(b, l.end));
        edges.entry(l.graph).or_default().push((a, z));
    }
    let mut out = BTreeMap::new();
    for (g, es) in edges {
        let mut adj: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for &(a, z) in &es {
            adj.entry(a).or_default().push(z);
            adj.entry(z).or_default().push(a);
        }
        let mut seen: BTreeSet<usize> = BTreeSet::new();
        let mut best: BTreeSet<usize> = BTreeSet::new();
        for &start in adj.keys() {
            if seen.contains(&start) {
                continue;
            }
            let mut piece = BTreeSet::from([start]);
            let mut stack = vec![start];
            seen.insert(start);
            while let Some(v) = stack.pop() {
                for &w in &adj[&v] {
                    if seen.insert(w) {
                        piece.insert(w);
                        stack.push(w);
                    }
                }
            }
            if piece.len() > best.len() {
                best = piece;
            }
        }
        out.insert(g, (best, names.clone()));
    }
    out
}

fn connectivity(old: &Building, new: &Building, ids: &Ids, out: &mut Vec<Change>) {
    let mut ids = Ids {
        old: ids.old.clone(),
        new: ids.new.clone(),
        next: ids.next,
    };
    let (o, n) = (
        main_piece(old, false, &mut ids),
        main_piece(new, true, &mut ids),
    );
    for (g, (a, names_a)) in &o {
        let Some((b, names_b)) = n.get(g) else {
            continue;
        };
        // Waypoints on both sides whose reachability from the main piece changed.
        let all_b: BTreeSet<&usize> = names_b.keys().collect();
        let all_a: BTreeSet<&usize> = names_a.keys().collect();
        for id in a.iter().filter(|id| !b.contains(id) && all_b.contains(id)) {
            out.push(change(
                Section::Connectivity,
                None,
                Kind::Removed,
                names_b[id].clone(),
                format!("no longer reachable from the main part of graph {g}"),
            ));
        }
        for id in b.iter().filter(|id| !a.contains(id) && all_a.contains(id)) {
            out.push(change(
                Section::Connectivity,
                None,
                Kind::Added,
                names_b[id].clone(),
                format!("now reachable from the main part of graph {g}"),
            ));
        }
    }
}

/// A diagnostic as a reviewer compares it: code and message with element indices left
/// out (they shift when anything before them is inserted).
fn diag_key(d: &Diagnostic) -> (String, String) {
    let mut msg = String::new();
    let mut rest = d.message.as_str();
    while let Some(i) = rest.find("index ") {
        msg.push_str(&rest[..i]);
        let after = &rest[i + 6..];
        let digits = after.chars().take_while(char::is_ascii_digit).count();
        if digits > 0 {
            msg.push_str("index #");
            rest = &after[digits..];
        } else {
            msg.push_str("index ");
            rest = after;
        }
    }
    msg.push_str(rest);
    (d.code.to_string(), msg)
}

fn diagnostics(old: &[Diagnostic], new: &[Diagnostic], out: &mut Vec<Change>) {
    let count = |ds: &[Diagnostic]| {
        let mut m: BTreeMap<(String, String, bool), usize> = BTreeMap::new();
        for d in ds {
            let (c, msg) = diag_key(d);
            *m.entry((c, msg, d.is_error())).or_default() += 1;
        }
        m
    };
    let (o, n) = (count(old), count(new));
    let sev = |e: bool| if e { "error" } else { "warning" };
    for (k, c) in &o {
        for _ in n.get(k).copied().unwrap_or(0)..*c {
            out.push(change(
                Section::Diagnostics,
                None,
                Kind::Removed,
                format!("{}[{}]", sev(k.2), k.0),
                k.1.clone(),
            ));
        }
    }
    for (k, c) in &n {
        for _ in o.get(k).copied().unwrap_or(0)..*c {
            out.push(change(
                Section::Diagnostics,
                None,
                Kind::Added,
                format!("{}[{}]", sev(k.2), k.0),
                k.1.clone(),
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polygons_compare_whatever_their_start_and_direction() {
        let sq = vec![(0, 0), (10, 0), (10, 8), (0, 8)];
        let other_start = vec![(10, 8), (0, 8), (0, 0), (10, 0)];
        let reversed = vec![(0, 8), (10, 8), (10, 0), (0, 0)];
        assert_eq!(canonical(sq.clone()), canonical(other_start));
        assert_eq!(canonical(sq.clone()), canonical(reversed));
        assert_ne!(
            canonical(sq),
            canonical(vec![(0, 0), (10, 0), (0, 8), (10, 8)])
        );
    }

    #[test]
    fn diagnostics_compare_without_indices() {
        let span = mapc_ir::Span::UNKNOWN;
        let a = Diagnostic::error("E0201", span, "at vertex `a` (index 3 of level `L1`)");
        let b = Diagnostic::error("E0201", span, "at vertex `a` (index 12 of level `L1`)");
        assert_eq!(diag_key(&a), diag_key(&b));
        assert_eq!(diag_key(&a).1, "at vertex `a` (index # of level `L1`)");
        let c = Diagnostic::error("E0201", span, "at vertex `b` (index 3 of level `L1`)");
        assert_ne!(diag_key(&a), diag_key(&c));
    }
}
