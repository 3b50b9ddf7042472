//! Facts several rules need, computed once per validation run.

use crate::*;
use std::collections::BTreeMap;

/// Precomputed indexes over a building.
pub struct Context<'a> {
    pub b: &'a Building,
    /// Graph indices with at least one lane, sorted.
    pub graphs: Vec<i64>,
    /// Lanes of each graph, in document order.
    pub lanes_by_graph: BTreeMap<i64, Vec<Handle<Lane>>>,
    /// For each vertex (by arena index): the lanes that start or end at it.
    pub lanes_at_vertex: Vec<Vec<Handle<Lane>>>,
    /// For each vertex (by arena index): the lift whose shaft contains it on its level.
    pub lift_of_vertex: Vec<Option<Handle<Lift>>>,
    /// For each vertex (by arena index): its index in its level's `vertices` list.
    pub index_in_level: Vec<u32>,
}

impl<'a> Context<'a> {
    pub fn new(b: &'a Building) -> Self {
        let mut lanes_by_graph: BTreeMap<i64, Vec<Handle<Lane>>> = BTreeMap::new();
        let mut lanes_at_vertex = vec![Vec::new(); b.vertices.len()];
        for (h, lane) in b.lanes.iter() {
            lanes_by_graph.entry(lane.graph).or_default().push(h);
            lanes_at_vertex[lane.start.index()].push(h);
            if lane.end != lane.start {
                lanes_at_vertex[lane.end.index()].push(h);
            }
        }
        let mut lift_of_vertex = vec![None; b.vertices.len()];
        let mut index_in_level = vec![0u32; b.vertices.len()];
        for (_, level) in b.levels.iter() {
            for (i, &vh) in level.vertices.iter().enumerate() {
                index_in_level[vh.index()] = i as u32;
            }
        }
        for (lh, level) in b.levels.iter() {
            let lifts: Vec<Handle<Lift>> = b.lifts_on_level(lh).collect();
            if lifts.is_empty() {
                continue;
            }
            // The shafts' bounding boxes in a grid: each vertex meets only the shafts near it.
            let boxes: Vec<(Vec2, Vec2)> = lifts
                .iter()
                .map(|&l| {
                    let c = b.lifts[l].shaft_corners();
                    let lo = c
                        .iter()
                        .fold(c[0], |m, p| Vec2::new(m.x.min(p.x), m.y.min(p.y)));
                    let hi = c
                        .iter()
                        .fold(c[0], |m, p| Vec2::new(m.x.max(p.x), m.y.max(p.y)));
                    let eps = Vec2::new(1e-6, 1e-6);
                    (lo.minus(eps), hi.plus(eps))
                })
                .collect();
            let mut grid = super::grid::BoxGrid::new(&boxes);
            for &vh in &level.vertices {
                let p = b.vertices[vh].pos;
                lift_of_vertex[vh.index()] = grid
                    .candidates(p, p)
                    .into_iter()
                    .map(|i| lifts[i as usize])
                    .find(|&l| b.lifts[l].shaft_contains(p));
            }
        }
        Context {
            b,
            graphs: lanes_by_graph.keys().copied().collect(),
            lanes_by_graph,
            lanes_at_vertex,
            lift_of_vertex,
            index_in_level,
        }
    }

    pub fn vertex_span(&self, v: Handle<Vertex>) -> Span {
        self.b.vertices.span(v)
    }
    pub fn lane_span(&self, l: Handle<Lane>) -> Span {
        self.b.lanes.span(l)
    }
    pub fn level_name(&self, l: Handle<Level>) -> &str {
        &self.b.levels[l].name
    }
    /// `name` or a description for unnamed vertices.
    pub fn vertex_label(&self, v: Handle<Vertex>) -> String {
        let vx = &self.b.vertices[v];
        let idx = self.index_in_level[v.index()];
        if vx.name.is_empty() {
            format!("vertex {idx} of level `{}`", self.level_name(vx.level))
        } else {
            format!(
                "vertex `{}` (index {idx} of level `{}`)",
                vx.name,
                self.level_name(vx.level)
            )
        }
    }
    pub fn lift_of(&self, v: Handle<Vertex>) -> Option<Handle<Lift>> {
        self.lift_of_vertex[v.index()]
    }
}
