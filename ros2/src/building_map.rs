//! The `/map` message (rmf_building_map_msgs/BuildingMap) of a building, as
//! building_map_server publishes it: per level its doors and one nav graph per graph index
//! (the level's waypoints on that graph's lanes, edges in lane order, one-way lanes as
//! unidirectional edges), and the lifts. Coordinates are map-frame metres, as in the nav
//! graphs. Images and wall graphs are left empty (viewers draw from the graphs and doors).

use crate::msgs::rmf_building_map_msgs::{
    door_type, BuildingMap, Door, Graph, GraphEdge, GraphNode, Level, Lift, Param,
    EDGE_TYPE_BIDIRECTIONAL, EDGE_TYPE_UNIDIRECTIONAL,
};
use mapc_ir::{Building, DoorKind, Handle, Vertex};
use std::collections::BTreeMap;

pub fn building_map(b: &Building) -> BuildingMap {
    let levels = b
        .levels
        .iter()
        .map(|(lh, level)| {
            let doors = level
                .doors
                .iter()
                .map(|&d| {
                    let d = &b.doors[d];
                    let (v1, v2) = (b.vertices[d.start].pos, b.vertices[d.end].pos);
                    Door {
                        name: d.name.clone(),
                        v1_x: v1.x as f32,
                        v1_y: v1.y as f32,
                        v2_x: v2.x as f32,
                        v2_y: v2.y as f32,
                        door_type: match d.kind {
                            DoorKind::Hinged => door_type::SINGLE_SWING,
                            DoorKind::DoubleHinged => door_type::DOUBLE_SWING,
                            DoorKind::Sliding => door_type::SINGLE_SLIDING,
                            DoorKind::DoubleSliding => door_type::DOUBLE_SLIDING,
                            DoorKind::Other(_) => 0,
                        },
                        motion_range: d.motion_degrees.to_radians() as f32,
                        motion_direction: d.motion_direction as i32,
                    }
                })
                .collect();
            let nav_graphs = b
                .graph_indices()
                .into_iter()
                .map(|g| nav_graph(b, &level.lanes, g))
                .collect();
            let _ = lh;
            Level {
                name: level.name.clone(),
                elevation: level.elevation as f32,
                doors,
                nav_graphs,
                ..Level::default()
            }
        })
        .collect();
    let lifts = b
        .lifts
        .iter()
        .map(|(_, l)| Lift {
            name: l.name.clone(),
            levels: l
                .level_doors
                .iter()
                .map(|ld| b.levels[ld.level].name.clone())
                .collect(),
            ref_x: l.pos.x as f32,
            ref_y: l.pos.y as f32,
            ref_yaw: l.yaw as f32,
            width: l.width as f32,
            depth: l.depth as f32,
            ..Lift::default()
        })
        .collect();
    BuildingMap {
        name: b.name.clone(),
        levels,
        lifts,
    }
}

fn nav_graph(b: &Building, lanes: &[Handle<mapc_ir::Lane>], graph: i64) -> Graph {
    let mut index: BTreeMap<Handle<Vertex>, u32> = BTreeMap::new();
    let mut vertices = Vec::new();
    let mut edges = Vec::new();
    let mut id = |v: Handle<Vertex>, vertices: &mut Vec<GraphNode>| {
        *index.entry(v).or_insert_with(|| {
            let vx = &b.vertices[v];
            vertices.push(GraphNode {
                x: vx.pos.x as f32,
                y: vx.pos.y as f32,
                name: vx.name.clone(),
                params: Vec::<Param>::new(),
            });
            (vertices.len() - 1) as u32
        })
    };
    for &lh in lanes {
        let lane = &b.lanes[lh];
        if lane.graph != graph {
            continue;
        }
        let v1_idx = id(lane.start, &mut vertices);
        let v2_idx = id(lane.end, &mut vertices);
        edges.push(GraphEdge {
            v1_idx,
            v2_idx,
            params: Vec::new(),
            edge_type: if lane.bidirectional {
                EDGE_TYPE_BIDIRECTIONAL
            } else {
                EDGE_TYPE_UNIDIRECTIONAL
            },
        });
    }
    Graph {
        name: graph.to_string(),
        vertices,
        edges,
        params: Vec::new(),
    }
}
