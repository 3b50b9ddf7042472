//! Rules about names and waypoint roles (E05xx).

use super::{Context, Rule};
use crate::{Handle, Lane, Vertex};

mod duplicate_dock;
mod duplicate_spawn;
mod duplicate_waypoint;
mod role_off_graph;
mod spawn_name_without_type;
mod spawn_without_name;
mod unnamed_role;
mod unsafe_characters;
mod unsafe_name;

pub(super) static RULES: &[&Rule] = &[
    &duplicate_waypoint::RULE,
    &duplicate_dock::RULE,
    &role_off_graph::RULE,
    &spawn_without_name::RULE,
    &spawn_name_without_type::RULE,
    &duplicate_spawn::RULE,
    &unnamed_role::RULE,
    &unsafe_name::RULE,
    &unsafe_characters::RULE,
];

/// The vertices that lanes of one graph use (the nav graph's waypoints), in document order.
fn graph_vertices(ctx: &Context, lanes: &[Handle<Lane>]) -> Vec<Handle<Vertex>> {
    let mut v: Vec<Handle<Vertex>> = lanes
        .iter()
        .flat_map(|&l| [ctx.b.lanes[l].start, ctx.b.lanes[l].end])
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// For each graph, the vertices whose `key` equals that of an earlier vertex of the graph:
/// `(later, earlier) -> graphs`, so that a pair shared by several graphs is reported once.
fn duplicates_per_graph<'a>(
    ctx: &'a Context,
    key: impl Fn(Handle<Vertex>) -> Option<&'a str>,
) -> std::collections::BTreeMap<(Handle<Vertex>, Handle<Vertex>), Vec<i64>> {
    let mut out: std::collections::BTreeMap<_, Vec<i64>> = std::collections::BTreeMap::new();
    for (&graph, lanes) in &ctx.lanes_by_graph {
        let mut first: std::collections::HashMap<&str, Handle<Vertex>> =
            std::collections::HashMap::new();
        for v in graph_vertices(ctx, lanes) {
            let Some(k) = key(v) else { continue };
            match first.get(k) {
                Some(&earlier) => out.entry((v, earlier)).or_default().push(graph),
                None => {
                    first.insert(k, v);
                }
            }
        }
    }
    out
}

/// "graph 0" or "graphs 0, 1".
fn graphs_text(graphs: &[i64]) -> String {
    let list: Vec<String> = graphs.iter().map(|g| g.to_string()).collect();
    if list.len() == 1 {
        format!("graph {}", list[0])
    } else {
        format!("graphs {}", list.join(", "))
    }
}
