//! Doors and lifts, matched by name: added, removed, and what changed (level, type, size,
//! place).

use super::*;

pub(super) fn doors(old: &Building, new: &Building, out: &mut Vec<Change>) {
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

pub(super) fn lifts(old: &Building, new: &Building, out: &mut Vec<Change>) {
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
