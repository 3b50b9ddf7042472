//! The IR as a traffic_editor `.building.yaml` (`mapc convert SITE BUILDING`).
//!
//! A `reference_image` building (a map converted to a site and back) is written in its
//! pixels: every element at its file coordinates, with the measurements and fiducials that
//! give each level its transform, so that reading it again gives the same map frame and
//! the same nav graphs and worlds. Anything else is written as `cartesian_meters` at
//! map-frame positions; a map with an offset or a CRS (converted from wgs84) keeps them as
//! `offset_x`/`offset_y` and `generate_crs`, so its nav graphs carry the same coordinates,
//! CRS and offset. What the format cannot say is a W0122 warning.

use crate::yaml::{to_string, Yaml};
use mapc_ir::*;
use std::collections::HashMap;

fn param(v: &ParamValue) -> Yaml {
    let (code, val) = match v {
        ParamValue::String(s) => (1, Yaml::str(s)),
        ParamValue::Int(i) => (2, Yaml::Int(*i)),
        ParamValue::Double(d) => (3, Yaml::Float(*d)),
        ParamValue::Bool(b) => (4, Yaml::Bool(*b)),
    };
    Yaml::Flow(Box::new(Yaml::Seq(vec![Yaml::Int(code), val])))
}

fn params(p: &Params) -> Yaml {
    Yaml::Map(
        p.iter()
            .map(|p| (p.name.clone(), param(&p.value)))
            .collect(),
    )
}

fn flow(items: Vec<Yaml>) -> Yaml {
    Yaml::Flow(Box::new(Yaml::Seq(items)))
}

fn p_str(s: &str) -> Yaml {
    param(&ParamValue::String(s.to_string()))
}

/// The file yaw of a yaw the frontend turned by a level's rotation (`file + theta`):
/// `yaw - theta` reads back as the same `yaw` (tests below).
fn unrotate(yaw: f64, theta: f64) -> f64 {
    yaw - theta
}

/// The `.building.yaml` text of `b` and the warnings about what it leaves out.
pub fn building_yaml(b: &Building) -> (String, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let mut root = Vec::new();
    let pixels = b.coordinate_system == CoordinateSystem::ReferenceImage;
    root.push(("name".to_string(), Yaml::str(&b.name)));
    root.push((
        "coordinate_system".into(),
        Yaml::str(if pixels {
            "reference_image"
        } else {
            "cartesian_meters"
        }),
    ));
    if b.levels.iter().next().map(|(h, _)| h) != Some(b.reference_level) {
        root.push((
            "reference_level_name".into(),
            Yaml::str(&b.levels[b.reference_level].name),
        ));
    }
    // Where an element is written: its file coordinates in pixels, or the map frame.
    let at = |raw: Vec2, pos: Vec2| if pixels { raw } else { pos };

    // Building parameters, with the offset and CRS of the map frame.
    let mut bp: Vec<(String, Yaml)> = b
        .params
        .iter()
        .filter(|p| {
            !matches!(
                p.name.as_str(),
                "offset_x"
                    | "offset_y"
                    | "suggested_offset_x"
                    | "suggested_offset_y"
                    | "generate_crs"
            )
        })
        .map(|p| (p.name.clone(), param(&p.value)))
        .collect();
    if b.offset != Vec2::default() {
        bp.push(("offset_x".into(), param(&ParamValue::Double(b.offset.x))));
        bp.push(("offset_y".into(), param(&ParamValue::Double(b.offset.y))));
    }
    if let Some(c) = &b.crs_name {
        bp.push(("generate_crs".into(), p_str(c)));
    }
    if !bp.is_empty() {
        root.push(("parameters".into(), Yaml::Map(bp)));
    }

    if let Some(c) = &b.crowd_sim {
        root.push(("crowd_sim".into(), crate::crowd_doc::crowd_sim(c)));
    }

    let mut graphs = Vec::new();
    for g in &b.graphs {
        graphs.push((
            g.index.to_string(),
            Yaml::Map(vec![
                (
                    "default_lane_width".into(),
                    Yaml::Float(g.default_lane_width),
                ),
                ("name".into(), Yaml::str(&g.name)),
            ]),
        ));
    }
    if !graphs.is_empty() {
        root.push(("graphs".into(), Yaml::Map(graphs)));
    }
    // A site location in some graphs only: a building names a waypoint in every graph.
    let mut partial: Vec<Handle<Vertex>> = b
        .graphs
        .iter()
        .flat_map(|g| g.unnamed.iter().copied())
        .collect();
    partial.sort_unstable();
    partial.dedup();
    for v in partial {
        diags.push(
            Diagnostic::warning(
                "W0122",
                b.vertices.span(v),
                format!(
                    "waypoint `{}` is a named place in some graphs only; the .building.yaml names it in every graph",
                    b.vertices[v].name
                ),
            )
            .with_help("nothing, or give the other graphs' fleets a waypoint of their own"),
        );
    }

    let mut levels = Vec::new();
    for (_, level) in b.levels.iter() {
        let index: HashMap<Handle<Vertex>, usize> = level
            .vertices
            .iter()
            .enumerate()
            .map(|(i, v)| (*v, i))
            .collect();
        let mut l = vec![("elevation".to_string(), Yaml::Float(level.elevation))];
        if let Some(d) = &level.drawing {
            l.push((
                "drawing".into(),
                Yaml::Map(vec![("filename".into(), Yaml::str(d))]),
            ));
        }
        let vertices = level
            .vertices
            .iter()
            .map(|&vh| {
                let v = &b.vertices[vh];
                let p = at(v.raw, v.pos);
                flow(vec![
                    Yaml::Float(p.x),
                    Yaml::Float(p.y),
                    Yaml::Float(0.0),
                    Yaml::str(&v.name),
                    params(&v.params),
                ])
            })
            .collect();
        l.push(("vertices".into(), Yaml::Seq(vertices)));
        let edge = |s: Handle<Vertex>, e: Handle<Vertex>, p: Vec<(String, Yaml)>| {
            flow(vec![
                Yaml::Int(index[&s] as i64),
                Yaml::Int(index[&e] as i64),
                Yaml::Map(p),
            ])
        };
        let lanes = level
            .lanes
            .iter()
            .map(|&h| {
                let lane = &b.lanes[h];
                let mut p = vec![
                    (
                        "bidirectional".to_string(),
                        param(&ParamValue::Bool(lane.bidirectional)),
                    ),
                    ("graph_idx".into(), param(&ParamValue::Int(lane.graph))),
                    ("orientation".into(), p_str(lane.orientation.as_str())),
                ];
                if let Some(s) = lane.speed_limit {
                    p.push(("speed_limit".into(), param(&ParamValue::Double(s))));
                }
                for (k, v) in [
                    ("mutex", &lane.mutex),
                    ("demo_mock_floor_name", &lane.demo_mock_floor_name),
                    ("demo_mock_lift_name", &lane.demo_mock_lift_name),
                ] {
                    if let Some(v) = v {
                        p.push((k.into(), p_str(v)));
                    }
                }
                edge(lane.start, lane.end, p)
            })
            .collect();
        l.push(("lanes".into(), Yaml::Seq(lanes)));
        let walls = level
            .walls
            .iter()
            .map(|&h| {
                let w = &b.walls[h];
                edge(
                    w.start,
                    w.end,
                    w.params
                        .iter()
                        .map(|p| (p.name.clone(), param(&p.value)))
                        .collect(),
                )
            })
            .collect();
        l.push(("walls".into(), Yaml::Seq(walls)));
        if !level.human_lanes.is_empty() {
            let hs = level
                .human_lanes
                .iter()
                .map(|&h| {
                    let l = &b.human_lanes[h];
                    let p = l
                        .params
                        .iter()
                        .map(|p| (p.name.clone(), param(&p.value)))
                        .collect();
                    edge(l.start, l.end, p)
                })
                .collect();
            l.push(("human_lanes".into(), Yaml::Seq(hs)));
        }
        if !level.measurements.is_empty() {
            let ms = level
                .measurements
                .iter()
                .map(|&h| {
                    let m = &b.measurements[h];
                    let p = m
                        .params
                        .iter()
                        .map(|p| (p.name.clone(), param(&p.value)))
                        .collect();
                    edge(m.start, m.end, p)
                })
                .collect();
            l.push(("measurements".into(), Yaml::Seq(ms)));
        }
        let doors = level
            .doors
            .iter()
            .map(|&h| {
                let d = &b.doors[h];
                let mut p: Vec<(String, Yaml)> = d
                    .params
                    .iter()
                    .filter(|p| {
                        !matches!(
                            p.name.as_str(),
                            "name"
                                | "type"
                                | "motion_axis"
                                | "motion_degrees"
                                | "motion_direction"
                                | "right_left_ratio"
                                | "plugin"
                        )
                    })
                    .map(|p| (p.name.clone(), param(&p.value)))
                    .collect();
                p.push(("name".into(), p_str(&d.name)));
                p.push(("type".into(), p_str(d.kind.as_str())));
                let axis = if d.motion_axis == MotionAxis::Start {
                    "start"
                } else {
                    "end"
                };
                p.push(("motion_axis".into(), p_str(axis)));
                p.push((
                    "motion_degrees".into(),
                    param(&ParamValue::Double(d.motion_degrees)),
                ));
                p.push((
                    "motion_direction".into(),
                    param(&ParamValue::Int(d.motion_direction)),
                ));
                p.push((
                    "right_left_ratio".into(),
                    param(&ParamValue::Double(d.right_left_ratio)),
                ));
                if !d.plugin {
                    p.push(("plugin".into(), p_str("none")));
                }
                edge(d.start, d.end, p)
            })
            .collect();
        l.push(("doors".into(), Yaml::Seq(doors)));
        let polys = |hs: &[Handle<Polygon>], arena: &Arena<Polygon>| -> Yaml {
            Yaml::Seq(
                hs.iter()
                    .map(|&h| {
                        let f = &arena[h];
                        Yaml::Map(vec![
                            ("parameters".into(), params(&f.params)),
                            (
                                "vertices".into(),
                                flow(
                                    f.vertices
                                        .iter()
                                        .map(|v| Yaml::Int(index[v] as i64))
                                        .collect(),
                                ),
                            ),
                        ])
                    })
                    .collect(),
            )
        };
        l.push(("floors".into(), polys(&level.floors, &b.floors)));
        if !level.holes.is_empty() {
            l.push(("holes".into(), polys(&level.holes, &b.holes)));
        }
        let models = level
            .models
            .iter()
            .map(|&h| {
                let m = &b.models[h];
                let p = at(m.raw, m.pos);
                let yaw = if pixels {
                    unrotate(m.yaw, level.transform.rotation)
                } else {
                    m.yaw
                };
                Yaml::Flow(Box::new(Yaml::Map(vec![
                    ("dispensable".into(), Yaml::Bool(m.dispensable)),
                    ("model_name".into(), Yaml::str(&m.model_name)),
                    ("name".into(), Yaml::str(&m.name)),
                    ("static".into(), Yaml::Bool(m.is_static)),
                    ("x".into(), Yaml::Float(p.x)),
                    ("y".into(), Yaml::Float(p.y)),
                    ("yaw".into(), Yaml::Float(yaw)),
                    ("z".into(), Yaml::Float(m.z)),
                ])))
            })
            .collect();
        l.push(("models".into(), Yaml::Seq(models)));
        if !level.fiducials.is_empty() {
            let f = level
                .fiducials
                .iter()
                .map(|&h| {
                    let f = &b.fiducials[h];
                    let p = at(f.raw, f.pos);
                    flow(vec![Yaml::Float(p.x), Yaml::Float(p.y), Yaml::str(&f.name)])
                })
                .collect();
            l.push(("fiducials".into(), Yaml::Seq(f)));
        }
        levels.push((level.name.clone(), Yaml::Map(l)));
    }
    root.push(("levels".into(), Yaml::Map(levels)));

    let mut lifts = Vec::new();
    for (_, lift) in b.lifts.iter() {
        let name = |h: Handle<Level>| Yaml::str(&b.levels[h].name);
        let p = at(lift.raw, lift.pos);
        let yaw = if pixels {
            unrotate(lift.yaw, b.levels[lift.reference_level].transform.rotation)
        } else {
            lift.yaw
        };
        let mut l = vec![
            ("x".to_string(), Yaml::Float(p.x)),
            ("y".into(), Yaml::Float(p.y)),
            ("yaw".into(), Yaml::Float(yaw)),
            ("width".into(), Yaml::Float(lift.width)),
            ("depth".into(), Yaml::Float(lift.depth)),
            ("reference_floor_name".into(), name(lift.reference_level)),
            ("plugins".into(), Yaml::Bool(lift.plugins)),
        ];
        for (k, v) in [
            ("initial_floor_name", lift.initial_level),
            ("lowest_floor", lift.lowest_level),
            ("highest_floor", lift.highest_level),
        ] {
            if let Some(h) = v {
                l.push((k.into(), name(h)));
            }
        }
        let doors = lift
            .doors
            .iter()
            .map(|d| {
                (
                    d.name.clone(),
                    Yaml::Map(vec![
                        ("door_type".into(), Yaml::Int(d.door_type)),
                        (
                            "motion_axis_orientation".into(),
                            Yaml::Float(d.motion_axis_orientation),
                        ),
                        ("width".into(), Yaml::Float(d.width)),
                        ("x".into(), Yaml::Float(d.pos.x)),
                        ("y".into(), Yaml::Float(d.pos.y)),
                    ]),
                )
            })
            .collect();
        l.push(("doors".into(), Yaml::Map(doors)));
        let ld = lift
            .level_doors
            .iter()
            .map(|ld| {
                (
                    b.levels[ld.level].name.clone(),
                    flow(ld.doors.iter().map(|(n, _)| Yaml::str(n)).collect()),
                )
            })
            .collect();
        l.push(("level_doors".into(), Yaml::Map(ld)));
        lifts.push((lift.name.clone(), Yaml::Map(l)));
    }
    if !lifts.is_empty() {
        root.push(("lifts".into(), Yaml::Map(lifts)));
    }
    (to_string(&Yaml::Map(root)), diags)
}

#[cfg(test)]
mod tests {
    use super::unrotate;

    /// A yaw the frontend turned by a level's rotation (`raw + theta`), written back less
    /// the rotation, reads as the same number: over magnitudes from 1e-6 to 10 rad.
    #[test]
    fn unrotated_yaws_read_back_exactly() {
        for i in 0..400 {
            for j in 0..200 {
                let raw = 10.0 * (i as f64 * 1.3).sin() * 10f64.powi(-(i % 7));
                let theta = 3.0 * (j as f64 * 0.77).cos() * 10f64.powi(-(j % 7));
                let yaw = raw + theta;
                let r = unrotate(yaw, theta);
                assert_eq!(r + theta, yaw, "raw {raw} theta {theta}");
            }
        }
    }
}
