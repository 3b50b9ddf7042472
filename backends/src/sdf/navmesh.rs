//! Menge navigation meshes (`.nav`, runtime.md §6.3) from a level's human lanes, for the
//! crowd simulator's `nav_mesh` obstacle set and velocity components. The polygons are
//! `mapc_ir::human_navmesh`'s (the runtime's crowd walks on the same ones); this module only
//! writes them in Menge's format. Nodes are planes at the level's elevation.

use crate::py_float;
use mapc_ir::{Building, Handle, Level, Vec2};
use std::collections::BTreeMap;
use std::fmt::Write;

/// The default human lane width, metres, when the lane has none.
pub const DEFAULT_WIDTH: f64 = mapc_ir::DEFAULT_HUMAN_LANE_WIDTH;

/// The `.nav` text of `level`'s human lanes, or `None` when it has none usable
/// (zero-length lanes are skipped).
pub fn level_navmesh(b: &Building, level: Handle<Level>) -> Option<String> {
    let lvl = &b.levels[level];
    let mesh = mapc_ir::human_navmesh(b, level, b.offset)?;
    let (verts, nodes, edges, obstacles) = (&mesh.verts, &mesh.nodes, &mesh.edges, &mesh.obstacles);
    let mut node_edges: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (k, e) in edges.iter().enumerate() {
        node_edges[e.2].push(k);
        node_edges[e.3].push(k);
    }
    let mut node_obst: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (k, o) in obstacles.iter().enumerate() {
        node_obst[o.2].push(k);
    }
    // Next obstacle: the one starting where this one ends.
    let starts: BTreeMap<usize, usize> = obstacles
        .iter()
        .enumerate()
        .map(|(k, o)| (o.0, k))
        .collect();

    let f = py_float;
    let elev = f(lvl.elevation);
    let mut out = String::new();
    let _ = writeln!(out, "{}", verts.len());
    for v in verts {
        let _ = writeln!(out, "{} {}", f(v.x), f(v.y));
    }
    let _ = writeln!(out, "{}", edges.len());
    for (a, b, n0, n1) in edges {
        let _ = writeln!(out, "{a} {b} {n0} {n1}");
    }
    let _ = writeln!(out, "{}", obstacles.len());
    for (a, b, n) in obstacles {
        let next = starts.get(b).map_or(-1, |&k| k as i64);
        let _ = writeln!(out, "{a} {b} {n} {next}");
    }
    let _ = writeln!(out, "walkable");
    let _ = writeln!(out, "{}", nodes.len());
    for (n, ring) in nodes.iter().enumerate() {
        let c = ring
            .iter()
            .fold(Vec2::default(), |s, &i| s.plus(verts[i]))
            .scale(1.0 / ring.len() as f64);
        let list = |v: &[usize]| {
            let mut s = v.len().to_string();
            for x in v {
                let _ = write!(s, " {x}");
            }
            s
        };
        let _ = writeln!(out, "{} {}", f(c.x), f(c.y));
        let _ = writeln!(out, "{}", list(ring));
        let _ = writeln!(out, "0.0 0.0 {elev}");
        let _ = writeln!(out, "{}", list(&node_edges[n]));
        let _ = writeln!(out, "{}", list(&node_obst[n]));
        out.push('\n');
    }
    Some(out)
}

/// `<level>_navmesh.nav`, the name the editor gives a level's navmesh.
pub fn navmesh_file_name(b: &Building, level: Handle<Level>) -> String {
    format!("{}_navmesh.nav", b.levels[level].name)
}
