//! Lanes, matched by the waypoints they join: added, removed, and what changed (graph,
//! direction, speed limit, orientation).

use super::*;

/// A lane's properties that a change can touch.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LaneInfo {
    graph: i64,
    /// `None` two-way; `Some(true)` one-way from the lower id to the higher.
    one_way_up: Option<bool>,
    speed: Option<f64>,
    orientation: String,
    label: String,
}

pub(super) fn lane_infos(
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

pub(super) fn direction(i: &LaneInfo) -> String {
    let ends = i.label.trim_start_matches("lane ");
    let mut parts = ends.splitn(2, " – ");
    let (a, b) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    match i.one_way_up {
        None => "two-way".into(),
        Some(true) => format!("one-way {a} → {b}"),
        Some(false) => format!("one-way {b} → {a}"),
    }
}

pub(super) fn speed(s: Option<f64>) -> String {
    s.map_or("none".into(), |v| format!("{} m/s", num(v)))
}

pub(super) fn lane_text(i: &LaneInfo) -> String {
    let mut s = format!("graph {}, {}", i.graph, direction(i));
    if i.speed.is_some() {
        s.push_str(&format!(", speed limit {}", speed(i.speed)));
    }
    if !i.orientation.is_empty() {
        s.push_str(&format!(", orientation {}", i.orientation));
    }
    s
}

pub(super) fn lanes(old: &Building, new: &Building, ids: &Ids, out: &mut Vec<Change>) {
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
