//! The map itself: floors and holes, walls, the lanes of each graph, waypoints with their
//! names and roles, models, lifts and doors.

use super::*;

pub(super) fn lane_width_px(view: &View) -> f64 {
    (0.08 * view.k).clamp(1.5, 4.0)
}

/// The level's map (everything inside the map area), in drawing order.
pub(super) fn draw_map(
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

pub(super) fn draw_lift(
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
pub(super) fn draw_door(s: &mut Svg, b: &Building, d: Handle<mapc_ir::Door>, view: &View) {
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
