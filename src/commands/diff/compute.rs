//! The semantic difference between two buildings: what a reviewer wants to know, not
//! which lines moved. Elements have no stable ids in the format (vertices are list
//! positions), so they are matched by meaning: levels, doors and lifts by name; waypoints
//! by name on their level, then the rest by position (within 1 cm); lanes by the waypoints
//! they join; walls and floors by their corner positions.

use mapc_ir::{Building, Diagnostic, Handle, Level, Vec2, Vertex, WaypointRoles};
use std::collections::{BTreeMap, BTreeSet, HashMap};

mod connectivity;
mod devices;
mod diagnostics;
mod lanes;
mod outlines;

use connectivity::connectivity;
use devices::{doors, lifts};
use diagnostics::diagnostics;
use lanes::lanes;
use outlines::{floors, walls};

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

/// What a lift change can touch: cabin centre, width, depth, levels served, cabin doors.
type LiftInfo = (Vec2, f64, f64, Vec<String>, Vec<String>);

/// Per level name.
type PerLevel<T> = BTreeMap<String, T>;
/// A position rounded to the centimetre.
type Key = (i64, i64);
/// Wall segments (ends ordered) with their count and length.
type Segments = BTreeMap<(Key, Key), (usize, f64)>;
/// Floor polygons: canonical corners and area.
type Polygons = Vec<(Vec<Key>, f64)>;

#[cfg(test)]
mod tests {
    use super::diagnostics::diag_key;
    use super::outlines::canonical;
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
