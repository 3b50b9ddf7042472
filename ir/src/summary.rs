//! A compact, deterministic text rendering of a building, for snapshot tests and
//! `mapc check --summary`-style reports. Numbers are rounded to 1e-4 so snapshots are
//! stable across platforms' last-bit differences.

use crate::*;
use std::fmt::Write;

fn r(x: f64) -> String {
    let v = (x * 1e4).round() / 1e4;
    // Avoid "-0".
    let v = if v == 0.0 { 0.0 } else { v };
    format!("{v}")
}

fn p(v: Vec2) -> String {
    format!("({}, {})", r(v.x), r(v.y))
}

fn roles(ro: &WaypointRoles) -> String {
    let mut out = Vec::new();
    for (flag, name) in [
        (ro.is_charger, "charger"),
        (ro.is_parking_spot, "parking"),
        (ro.is_holding_point, "holding"),
        (ro.is_passthrough_point, "passthrough"),
        (ro.is_cleaning_zone, "cleaning_zone"),
    ] {
        if flag {
            out.push(name.to_string());
        }
    }
    for (v, name) in [
        (&ro.dock_name, "dock"),
        (&ro.pickup_dispenser, "pickup"),
        (&ro.dropoff_ingestor, "dropoff"),
        (&ro.spawn_robot_type, "spawn_type"),
        (&ro.spawn_robot_name, "spawn_name"),
        (&ro.mutex, "mutex"),
        (&ro.lift_cabin, "lift_cabin"),
        (&ro.human_goal_set_name, "goal_set"),
    ] {
        if let Some(v) = v {
            out.push(format!("{name}={v}"));
        }
    }
    if let Some(m) = ro.merge_radius {
        out.push(format!("merge_radius={}", r(m)));
    }
    out.join(" ")
}

/// Renders the building as indented text.
pub fn summary(b: &Building) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "building {} ({}) reference_level={}",
        b.name,
        b.coordinate_system.as_str(),
        b.levels[b.reference_level].name
    );
    if let Some(crs) = &b.crs_name {
        let _ = writeln!(s, "crs {crs} offset {}", p(b.offset));
    }
    for (lh, l) in b.levels.iter() {
        let t = l.transform;
        let _ = writeln!(
            s,
            "level {} elevation={} scale={} rotation={} translation={}",
            l.name,
            r(l.elevation),
            format_args!("{:.6}", t.scale),
            r(t.rotation),
            p(t.translation)
        );
        let _ = writeln!(
            s,
            "  counts: vertices={} lanes={} walls={} doors={} floors={} holes={} models={} fiducials={} measurements={} human_lanes={} features={} layers={}",
            l.vertices.len(),
            l.lanes.len(),
            l.walls.len(),
            l.doors.len(),
            l.floors.len(),
            l.holes.len(),
            l.models.len(),
            l.fiducials.len(),
            l.measurements.len(),
            l.human_lanes.len(),
            l.features.len(),
            l.layers.len()
        );
        for (i, &vh) in l.vertices.iter().enumerate() {
            let v = &b.vertices[vh];
            let ro = roles(&v.roles);
            let _ = writeln!(
                s,
                "  v{i} {} {}{}{}",
                if v.name.is_empty() { "-" } else { &v.name },
                p(v.pos),
                if ro.is_empty() { "" } else { " " },
                ro
            );
        }
        let idx = |h: Handle<Vertex>| {
            l.vertices
                .iter()
                .position(|&x| x == h)
                .unwrap_or(usize::MAX)
        };
        for &lh2 in &l.lanes {
            let lane = &b.lanes[lh2];
            let mut extra = Vec::new();
            if lane.orientation != Orientation::Any {
                extra.push(format!("orientation={}", lane.orientation.as_str()));
            }
            if let Some(v) = lane.speed_limit {
                extra.push(format!("speed_limit={}", r(v)));
            }
            if let Some(m) = &lane.mutex {
                extra.push(format!("mutex={m}"));
            }
            if let Some(m) = &lane.demo_mock_floor_name {
                extra.push(format!("mock_floor={m}"));
            }
            if let Some(m) = &lane.demo_mock_lift_name {
                extra.push(format!("mock_lift={m}"));
            }
            let _ = writeln!(
                s,
                "  lane g{} v{} {} v{}{}{}",
                lane.graph,
                idx(lane.start),
                if lane.bidirectional { "<->" } else { "->" },
                idx(lane.end),
                if extra.is_empty() { "" } else { " " },
                extra.join(" ")
            );
        }
        for &dh in &l.doors {
            let d = &b.doors[dh];
            let _ = writeln!(
                s,
                "  door {} {} v{}-v{} width={} direction={} degrees={} ratio={} plugin={}",
                d.name,
                d.kind.as_str(),
                idx(d.start),
                idx(d.end),
                r(b.vertices[d.start].pos.minus(b.vertices[d.end].pos).norm()),
                d.motion_direction,
                r(d.motion_degrees),
                r(d.right_left_ratio),
                d.plugin
            );
        }
        for &mh in &l.models {
            let m = &b.models[mh];
            let _ = writeln!(
                s,
                "  model {} ({}) at {} z={} yaw={} static={} dispensable={}",
                m.name,
                m.model_name,
                p(m.pos),
                r(m.z),
                r(m.yaw),
                m.is_static,
                m.dispensable
            );
        }
        for &fh in &l.fiducials {
            let f = &b.fiducials[fh];
            let _ = writeln!(s, "  fiducial {} at {}", f.name, p(f.pos));
        }
        let lifts: Vec<&str> = b
            .lifts_on_level(lh)
            .map(|h| b.lifts[h].name.as_str())
            .collect();
        if !lifts.is_empty() {
            let _ = writeln!(s, "  lifts: {}", lifts.join(", "));
        }
    }
    for (_, l) in b.lifts.iter() {
        let _ = writeln!(
            s,
            "lift {} at {} yaw={} size={}x{} reference={} initial={} plugins={}",
            l.name,
            p(l.pos),
            r(l.yaw),
            r(l.width),
            r(l.depth),
            b.levels[l.reference_level].name,
            l.initial_floor().map_or("-", |h| b.levels[h].name.as_str()),
            l.plugins
        );
        for d in &l.doors {
            let _ = writeln!(
                s,
                "  door {} type={} at {} width={} axis={}",
                d.name,
                d.door_type,
                p(d.pos),
                r(d.width),
                r(d.motion_axis_orientation)
            );
        }
        for ld in &l.level_doors {
            let names: Vec<&str> = ld.doors.iter().map(|(n, _)| n.as_str()).collect();
            let _ = writeln!(s, "  on {}: {}", b.levels[ld.level].name, names.join(", "));
        }
    }
    for g in &b.graphs {
        let _ = writeln!(
            s,
            "graph {} {:?} lane_width={}",
            g.index,
            g.name,
            r(g.default_lane_width)
        );
    }
    if let Some(c) = &b.crowd_sim {
        let _ = writeln!(
            s,
            "crowd_sim enable={} states={} goal_sets={} profiles={} transitions={} groups={} model_types={}",
            c.enable,
            c.states.len(),
            c.goal_sets.len(),
            c.agent_profiles.len(),
            c.transitions.len(),
            c.agent_groups.len(),
            c.model_types.len()
        );
    }
    s
}
