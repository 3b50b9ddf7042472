//! Walls and floors, matched by their corner positions (to the centimetre).

use super::*;

/// A position rounded to the centimetre, as a key.
pub(super) fn key(p: Vec2) -> (i64, i64) {
    (
        (p.x / SAME_PLACE).round() as i64,
        (p.y / SAME_PLACE).round() as i64,
    )
}

pub(super) fn walls(old: &Building, new: &Building, out: &mut Vec<Change>) {
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

pub(super) fn area(points: &[Vec2]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].cross(points[(i + 1) % n]))
        .sum::<f64>()
        .abs()
        / 2.0
}

/// A closed polygon's corners independent of start corner and direction: the smaller of
/// the two rotations that start at the lowest corner.
pub(super) fn canonical(mut keys: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
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

pub(super) fn floors(old: &Building, new: &Building, out: &mut Vec<Change>) {
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
