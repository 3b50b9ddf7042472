//! Navigation graphs of the fleets, derived from the IR the way backends/src/nav.rs derives
//! the nav graph RMF fleet adapters read (lanes of the fleet's `graph_idx`, both directions
//! for bidirectional lanes, doors crossed by a lane, lift cabins), plus lift edges between
//! the cabin vertices of one lift on different levels. One vertex table serves all fleets so
//! that traffic reservations of robots of different fleets share one resource space.

use mapc_ir::{Building, Handle, Lane, Level, Orientation, Vec2, Vertex, WaypointRoles};
use std::cmp::Ordering;
use std::collections::{BTreeMap, BinaryHeap};

/// Fixed time charged for a door on a lane (open + close wait), seconds.
pub const DOOR_COST: f64 = 8.0;
/// Time charged on every lift ride for its messages: the lift's state, which tells the
/// fleet the cabin has come, comes once a second, and so may the request that sends it.
pub const LIFT_MESSAGES: f64 = 2.0;
/// Time lost stopping at a waypoint (the slotcar stops at every waypoint), seconds.
pub const STOP_COST: f64 = 1.0;

#[derive(Debug, Clone)]
pub struct NavVertex {
    pub name: String,
    pub pos: Vec2,
    pub level: Handle<Level>,
    pub level_name: String,
    pub elevation: f64,
    /// Index into `Nav::lifts` when the vertex lies in a lift cabin.
    pub lift: Option<usize>,
    pub roles: WaypointRoles,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EdgeKind {
    Lane,
    /// A ride in lift `Nav::lifts[i]` between two cabin vertices.
    Lift(usize),
}

#[derive(Debug, Clone)]
pub struct NavEdge {
    /// Slot in `Nav::graphs`.
    pub graph: usize,
    pub from: usize,
    pub to: usize,
    pub kind: EdgeKind,
    /// IR lane index (for lane resources).
    pub lane: Option<usize>,
    pub length: f64,
    pub speed_limit: Option<f64>,
    /// Index into `Nav::doors` of the door the lane crosses.
    pub door: Option<usize>,
    pub mutex: Option<String>,
    pub orientation: Orientation,
    /// The lift that could carry a robot driving this lane (it crosses the lift's shaft on
    /// a floor the lift serves).
    pub carried_by: Option<usize>,
}

#[derive(Debug, Clone)]
pub struct NavLift {
    pub name: String,
    /// Longest ride between two of its floors (s, as `edge_cost` counts it): how long a
    /// call may take for the cabin to come.
    pub call: f64,
    /// How long its slowest door takes to open or close (s), as the world moves it.
    pub doors: f64,
}

#[derive(Debug, Clone)]
pub struct NavDoor {
    pub name: String,
    /// Doors with `plugin: none` have no controller: nothing to request.
    pub controlled: bool,
}

/// All fleets' graphs over one vertex table.
#[derive(Debug, Clone, Default)]
pub struct Nav {
    pub vertices: Vec<NavVertex>,
    pub edges: Vec<NavEdge>,
    pub lifts: Vec<NavLift>,
    pub doors: Vec<NavDoor>,
    /// Graph index (`graph_idx`) of each slot.
    pub graphs: Vec<i64>,
    /// Per graph slot, per vertex: outgoing edges (in edge order).
    pub out: Vec<Vec<Vec<usize>>>,
    /// Per graph slot: vertices that the graph uses, ascending.
    pub members: Vec<Vec<usize>>,
    /// Number of IR lanes (lane resources follow the vertices).
    pub ir_lanes: usize,
    /// Per graph slot: which vertices reach which (empty for a graph not built here).
    reach: Vec<reach::Reach>,
}

mod reach;

impl Nav {
    /// Builds the graphs `graphs` (graph indices) of `b`.
    pub fn build(b: &Building, graphs: &[i64]) -> Nav {
        let mut nav = Nav {
            graphs: graphs.to_vec(),
            ir_lanes: b.lanes.len(),
            ..Nav::default()
        };
        for (_, l) in b.lifts.iter() {
            // Each leaf of a lift door slides half its width (world.rs).
            let p = crate::door::LIFT_DOOR.limits;
            let doors = l
                .doors
                .iter()
                .map(|d| crate::profile::trapezoid_time(d.width / 2.0, p.v_max, p.a_nom))
                .fold(0.0, f64::max);
            nav.lifts.push(NavLift {
                name: l.name.clone(),
                call: 0.0,
                doors,
            });
        }
        for (_, d) in b.doors.iter() {
            nav.doors.push(NavDoor {
                name: d.name.clone(),
                controlled: d.plugin,
            });
        }
        let floors_z = crate::levels::elevations(b);
        let mut index: BTreeMap<Handle<Vertex>, usize> = BTreeMap::new();
        let mut add_vertex = |nav: &mut Nav, vh: Handle<Vertex>| -> usize {
            *index.entry(vh).or_insert_with(|| {
                let v = &b.vertices[vh];
                let level = &b.levels[v.level];
                let lift = b
                    .lifts_on_level(v.level)
                    .find(|&lh| {
                        let l = &b.lifts[lh];
                        l.shaft_contains(v.pos) || v.roles.lift_cabin.as_deref() == Some(&l.name)
                    })
                    .map(|lh| lh.index());
                nav.vertices.push(NavVertex {
                    name: v.name.clone(),
                    pos: v.pos,
                    level: v.level,
                    level_name: level.name.clone(),
                    elevation: floors_z[v.level.index()],
                    lift,
                    roles: (*v.roles).clone(),
                });
                nav.vertices.len() - 1
            })
        };
        // The levels each lift serves (has doors on). The nav graph marks cabin waypoints on
        // every level the shaft passes, as the reference does, but the cabin stops only where
        // it has doors: a robot driving into the shaft elsewhere, or riding there, would wait
        // for a cabin that never comes (W0411 says so when checking the map). Such waypoints
        // get no lanes and no rides.
        let served: Vec<Vec<Handle<Level>>> = b
            .lifts
            .iter()
            .map(|(_, l)| l.level_doors.iter().map(|d| d.level).collect())
            .collect();
        let dead_shaft = |nav: &Nav, v: usize| {
            let x = &nav.vertices[v];
            x.lift.is_some_and(|l| !served[l].contains(&x.level))
        };
        let mut per_graph_lanes: Vec<Vec<(Handle<Lane>, &Lane)>> = vec![Vec::new(); graphs.len()];
        for (lh, lane) in b.lanes.iter() {
            if let Some(slot) = graphs.iter().position(|&g| g == lane.graph) {
                per_graph_lanes[slot].push((lh, lane));
            }
        }
        for (slot, lanes) in per_graph_lanes.iter().enumerate() {
            for &(lh, lane) in lanes {
                let s = add_vertex(&mut nav, lane.start);
                let e = add_vertex(&mut nav, lane.end);
                if dead_shaft(&nav, s) || dead_shaft(&nav, e) {
                    continue;
                }
                let dirs: &[bool] = if lane.bidirectional {
                    &[false, true]
                } else {
                    &[false]
                };
                for &rev in dirs {
                    let (from, to) = if rev { (e, s) } else { (s, e) };
                    let (a, z) = (nav.vertices[from].pos, nav.vertices[to].pos);
                    let door = b.crossed_door(lane.level, a, z).map(|d| d.index());
                    let carried_by = b
                        .lifts_on_level(lane.level)
                        .find(|&lh| crosses_shaft(&b.lifts[lh], a, z))
                        .map(|lh| lh.index());
                    nav.edges.push(NavEdge {
                        graph: slot,
                        from,
                        to,
                        kind: EdgeKind::Lane,
                        lane: Some(lh.index()),
                        length: z.minus(a).norm(),
                        speed_limit: lane.speed_limit,
                        door,
                        mutex: lane.mutex.clone(),
                        orientation: if rev {
                            lane.orientation.reversed()
                        } else {
                            lane.orientation.clone()
                        },
                        carried_by,
                    });
                }
            }
        }
        nav.members = vec![Vec::new(); graphs.len()];
        for e in &nav.edges {
            nav.members[e.graph].push(e.from);
            nav.members[e.graph].push(e.to);
        }
        for m in &mut nav.members {
            m.sort_unstable();
            m.dedup();
        }
        // Lift rides: every pair of cabin vertices of one lift on different levels that it
        // serves (see `served`).
        for slot in 0..graphs.len() {
            let cabins: Vec<usize> = nav.members[slot]
                .iter()
                .copied()
                .filter(|&v| nav.vertices[v].lift.is_some())
                .collect();
            for &a in &cabins {
                for &z in &cabins {
                    let (va, vz) = (&nav.vertices[a], &nav.vertices[z]);
                    if a == z || va.lift != vz.lift || va.level == vz.level {
                        continue;
                    }
                    let Some(l) = va.lift else { continue };
                    if !(served[l].contains(&va.level) && served[l].contains(&vz.level)) {
                        continue;
                    }
                    nav.edges.push(NavEdge {
                        graph: slot,
                        from: a,
                        to: z,
                        kind: EdgeKind::Lift(l),
                        lane: None,
                        length: (vz.elevation - va.elevation).abs(),
                        speed_limit: None,
                        door: None,
                        mutex: None,
                        orientation: Orientation::Any,
                        carried_by: Some(l),
                    });
                }
            }
        }
        nav.out = vec![vec![Vec::new(); nav.vertices.len()]; graphs.len()];
        for (i, e) in nav.edges.iter().enumerate() {
            nav.out[e.graph][e.from].push(i);
        }
        nav.reach = (0..graphs.len())
            .map(|slot| {
                let edges: Vec<(usize, usize)> = nav
                    .edges
                    .iter()
                    .filter(|e| e.graph == slot)
                    .map(|e| (e.from, e.to))
                    .collect();
                reach::Reach::build(nav.vertices.len(), &edges)
            })
            .collect();
        for e in 0..nav.edges.len() {
            if let EdgeKind::Lift(l) = nav.edges[e].kind {
                let c = nav.edge_cost(e, 1.0);
                nav.lifts[l].call = nav.lifts[l].call.max(c);
            }
        }
        nav
    }

    pub fn slot(&self, graph: i64) -> Option<usize> {
        self.graphs.iter().position(|&g| g == graph)
    }

    /// The vertex called `name` in graph slot `slot` (first in vertex order).
    pub fn find(&self, slot: usize, name: &str) -> Option<usize> {
        if name.is_empty() {
            return None;
        }
        self.members
            .get(slot)?
            .iter()
            .copied()
            .find(|&v| self.vertices[v].name == name)
    }

    /// Travel time estimate of an edge at nominal speed `speed`.
    pub fn edge_cost(&self, e: usize, speed: f64) -> f64 {
        let edge = &self.edges[e];
        match edge.kind {
            EdgeKind::Lane => {
                let v = edge.speed_limit.map_or(speed, |l| l.min(speed)).max(0.05);
                let door = if edge.door.is_some_and(|d| self.doors[d].controlled) {
                    DOOR_COST
                } else {
                    0.0
                };
                edge.length / v + STOP_COST + door
            }
            // The world's ride: the doors close, the cabin travels at its profile, the
            // doors open. (It was 20 s plus the travel at 0.5 m/s, a quarter of the
            // cabin's speed: on 8 floors, every entry waited for a 76 s call, the plans
            // booked the lift for 300 s per trip and robots were refused every task.)
            EdgeKind::Lift(l) => {
                let c = crate::lift::CABIN;
                2.0 * self.lifts[l].doors
                    + crate::profile::trapezoid_time(edge.length, c.v_max, c.a_nom)
                    + LIFT_MESSAGES
            }
        }
    }

    /// Shortest-time route from `from` to `to` on graph slot `slot`: (time, edges).
    /// Dijkstra with ties broken by vertex index, so routes are deterministic.
    pub fn plan(
        &self,
        slot: usize,
        from: usize,
        to: usize,
        speed: f64,
    ) -> Option<(f64, Vec<usize>)> {
        self.plan_avoiding(slot, from, to, speed, &[])
    }

    /// Like [`Nav::plan`], never entering the vertices in `avoid` (except `to`).
    pub fn plan_avoiding(
        &self,
        slot: usize,
        from: usize,
        to: usize,
        speed: f64,
        avoid: &[usize],
    ) -> Option<(f64, Vec<usize>)> {
        self.plan_with(slot, from, to, speed, &|e| {
            let w = self.edges[e].to;
            w == to || !avoid.contains(&w)
        })
    }

    /// Like [`Nav::plan`], using only the edges `allow` accepts.
    pub fn plan_with(
        &self,
        slot: usize,
        from: usize,
        to: usize,
        speed: f64,
        allow: &dyn Fn(usize) -> bool,
    ) -> Option<(f64, Vec<usize>)> {
        let out = self.out.get(slot)?;
        let n = self.vertices.len();
        if from >= n || to >= n {
            return None;
        }
        if from == to {
            return Some((0.0, Vec::new()));
        }
        let mut dist = vec![f64::INFINITY; n];
        let mut prev: Vec<Option<usize>> = vec![None; n];
        let mut heap = BinaryHeap::new();
        dist[from] = 0.0;
        heap.push(QItem(0.0, from));
        while let Some(QItem(d, v)) = heap.pop() {
            if d > dist[v] {
                continue;
            }
            if v == to {
                break;
            }
            for &e in &out[v] {
                let w = self.edges[e].to;
                if !allow(e) {
                    continue;
                }
                let nd = d + self.edge_cost(e, speed);
                if nd < dist[w] {
                    dist[w] = nd;
                    prev[w] = Some(e);
                    heap.push(QItem(nd, w));
                }
            }
        }
        if !dist[to].is_finite() {
            return None;
        }
        let mut edges = Vec::new();
        let mut v = to;
        while v != from {
            let e = prev[v]?;
            edges.push(e);
            v = self.edges[e].from;
        }
        edges.reverse();
        Some((dist[to], edges))
    }

    /// Whether `to` can be reached from `from` on graph slot `slot`.
    pub fn times_reachable(&self, slot: usize, from: usize, to: usize) -> bool {
        self.reachable_from_any(slot, &[from], to)
    }

    /// Whether `to` can be reached from one of `starts` on graph slot `slot`.
    pub fn reachable_from_any(&self, slot: usize, starts: &[usize], to: usize) -> bool {
        let n = self.vertices.len();
        let Some(out) = self.out.get(slot) else {
            return false;
        };
        if to >= n {
            return false;
        }
        let known = self
            .reach
            .get(slot)
            .and_then(|r| r.reached_from_any(&mut starts.iter().copied().filter(|&s| s < n), to));
        if let Some(known) = known {
            return known;
        }
        // A search from all of them at once.
        let mut seen = vec![false; n];
        let mut stack: Vec<usize> = starts.iter().copied().filter(|&s| s < n).collect();
        while let Some(v) = stack.pop() {
            if v == to {
                return true;
            }
            if std::mem::replace(&mut seen[v], true) {
                continue;
            }
            for &e in &out[v] {
                stack.push(self.edges[e].to);
            }
        }
        false
    }

    /// Travel times from `from` to every vertex of slot `slot` (Dijkstra).
    pub fn times_from(&self, slot: usize, from: usize, speed: f64) -> Vec<f64> {
        self.tree_from(slot, from, speed).0
    }

    /// Travel times to `to` from every vertex of slot `slot` (Dijkstra on the reversed
    /// edges): one search serves every robot going there.
    pub fn times_to(&self, slot: usize, to: usize, speed: f64) -> Vec<f64> {
        let n = self.vertices.len();
        if slot >= self.graphs.len() {
            return vec![f64::INFINITY; n];
        }
        let mut inn: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (e, edge) in self.edges.iter().enumerate() {
            if edge.graph == slot {
                inn[edge.to].push(e);
            }
        }
        self.dijkstra(&inn, &[to], &|e| self.edge_cost(e, speed), true, &|_| true)
            .0
    }

    /// Travel times from `from` to every vertex of slot `slot`, and the edge each vertex is
    /// reached by on a shortest route (ties broken as in [`Nav::plan`]).
    pub fn tree_from(
        &self,
        slot: usize,
        from: usize,
        speed: f64,
    ) -> (Vec<f64>, Vec<Option<usize>>) {
        self.tree_with(slot, from, speed, &|_| true)
    }

    /// Like [`Nav::tree_from`], using only the edges `allow` accepts.
    pub fn tree_with(
        &self,
        slot: usize,
        from: usize,
        speed: f64,
        allow: &dyn Fn(usize) -> bool,
    ) -> (Vec<f64>, Vec<Option<usize>>) {
        match self.out.get(slot) {
            Some(out) => self.dijkstra(out, &[from], &|e| self.edge_cost(e, speed), false, allow),
            None => {
                let n = self.vertices.len();
                (vec![f64::INFINITY; n], vec![None; n])
            }
        }
    }

    /// Like [`Nav::tree_from`] from the nearest of `from`, with each edge's time from
    /// `cost`, using only the edges `allow` accepts.
    pub fn tree_costed(
        &self,
        slot: usize,
        from: &[usize],
        cost: &dyn Fn(usize) -> f64,
        allow: &dyn Fn(usize) -> bool,
    ) -> (Vec<f64>, Vec<Option<usize>>) {
        match self.out.get(slot) {
            Some(out) => self.dijkstra(out, from, cost, false, allow),
            None => {
                let n = self.vertices.len();
                (vec![f64::INFINITY; n], vec![None; n])
            }
        }
    }

    /// Dijkstra from the vertices `starts` over the edges `adj` lists per vertex (leaving
    /// it, or with `reversed` arriving at it), each edge taking `cost(e)`, using only the
    /// edges `allow` accepts: times, and the edge each vertex is reached by. Ties are
    /// broken by vertex index.
    fn dijkstra(
        &self,
        adj: &[Vec<usize>],
        starts: &[usize],
        cost: &dyn Fn(usize) -> f64,
        reversed: bool,
        allow: &dyn Fn(usize) -> bool,
    ) -> (Vec<f64>, Vec<Option<usize>>) {
        let n = self.vertices.len();
        let mut dist = vec![f64::INFINITY; n];
        let mut prev: Vec<Option<usize>> = vec![None; n];
        let mut heap = BinaryHeap::new();
        for &start in starts.iter().filter(|&&s| s < n) {
            dist[start] = 0.0;
            heap.push(QItem(0.0, start));
        }
        while let Some(QItem(d, v)) = heap.pop() {
            if d > dist[v] {
                continue;
            }
            for &e in &adj[v] {
                if !allow(e) {
                    continue;
                }
                let w = if reversed {
                    self.edges[e].from
                } else {
                    self.edges[e].to
                };
                let nd = d + cost(e);
                if nd < dist[w] {
                    dist[w] = nd;
                    prev[w] = Some(e);
                    heap.push(QItem(nd, w));
                }
            }
        }
        (dist, prev)
    }
}

/// Min-heap item: smaller time first, then smaller vertex index.
#[derive(Debug, Clone, Copy, PartialEq)]
struct QItem(f64, usize);
impl Eq for QItem {}
impl Ord for QItem {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then_with(|| o.1.cmp(&self.1))
    }
}
impl PartialOrd for QItem {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Distance from `p` to segment `a→b`.
/// Whether segment `a`–`z` meets the box `[x_min, x_max, y_min, y_max]` (slab clipping).
/// Whether the segment `a→z` crosses the shaft of lift `l` (where a robot could be carried).
fn crosses_shaft(l: &mapc_ir::Lift, a: Vec2, z: Vec2) -> bool {
    let (w, d) = (
        l.width / 2.0 + mapc_ir::SHAFT_MARGIN,
        l.depth / 2.0 + mapc_ir::SHAFT_MARGIN,
    );
    segment_crosses_box(l.to_cabin(a), l.to_cabin(z), [-w, w, -d, d])
}

fn segment_crosses_box(a: Vec2, z: Vec2, [x0, x1, y0, y1]: [f64; 4]) -> bool {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for (p, d, min, max) in [(a.x, z.x - a.x, x0, x1), (a.y, z.y - a.y, y0, y1)] {
        if d.abs() < 1e-12 {
            if p < min || p > max {
                return false;
            }
        } else {
            let (t0, t1) = ((min - p) / d, (max - p) / d);
            lo = lo.max(t0.min(t1));
            hi = hi.min(t0.max(t1));
        }
    }
    lo <= hi
}

pub fn point_segment(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let ab = b.minus(a);
    let l2 = ab.dot(ab);
    if l2 <= 1e-18 {
        return p.minus(a).norm();
    }
    let t = (p.minus(a).dot(ab) / l2).clamp(0.0, 1.0);
    p.minus(a.plus(ab.scale(t))).norm()
}

/// Distance between segments `a→b` and `p→q` (0 when they cross).
pub fn segment_segment(a: Vec2, b: Vec2, p: Vec2, q: Vec2) -> f64 {
    if mapc_ir::segment_intersection(a, b, p, q).is_some() {
        return 0.0;
    }
    point_segment(a, p, q)
        .min(point_segment(b, p, q))
        .min(point_segment(p, a, b))
        .min(point_segment(q, a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three levels; the lift's shaft passes all three but it has doors on L1 and L2 only.
    const THREE_LEVELS: &str = r#"coordinate_system: cartesian_meters
name: shaft
graphs:
  0: {name: g, default_lane_width: 0.5}
levels:
  L1:
    elevation: 0
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
    vertices:
      - [4, 5, 0, lobby_1]
      - [10, 5, 0, cabin_1, {lift_cabin: [1, lift_1]}]
  L2:
    elevation: 3.5
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
    vertices:
      - [4, 5, 0, lobby_2]
      - [10, 5, 0, cabin_2, {lift_cabin: [1, lift_1]}]
  L3:
    elevation: 7
    lanes:
      - [0, 1, {bidirectional: [4, true], graph_idx: [2, 0]}]
    vertices:
      - [4, 5, 0, lobby_3]
      - [10, 5, 0, cabin_3, {lift_cabin: [1, lift_1]}]
lifts:
  lift_1:
    depth: 2
    width: 2
    x: 10
    y: 5
    yaw: 0
    doors:
      front: {door_type: 2, motion_axis_orientation: 1.5708, width: 1, x: -1, y: 0}
    level_doors:
      L1: [front]
      L2: [front]
    plugins: true
    reference_floor_name: L1
reference_level_name: L1
"#;

    #[test]
    fn lifts_ride_only_between_the_floors_they_have_doors_on() {
        let parsed = mapc_frontend::parse_str("shaft.building.yaml", THREE_LEVELS);
        let b = parsed.valid_building().expect("map loads");
        let nav = Nav::build(b, &[0]);
        let v = |n: &str| nav.find(0, n).unwrap_or_else(|| panic!("{n}"));
        let rides: Vec<(usize, usize)> = nav
            .edges
            .iter()
            .filter(|e| matches!(e.kind, EdgeKind::Lift(_)))
            .map(|e| (e.from, e.to))
            .collect();
        let (c1, c2) = (v("cabin_1"), v("cabin_2"));
        assert_eq!(rides, vec![(c1, c2), (c2, c1)]);
        // The cabin waypoint on L3 is in the shaft where the cabin never stops: no lane leads
        // into it, so neither it nor the lobby only it reaches is on the graph.
        assert_eq!(nav.find(0, "cabin_3"), None);
        assert_eq!(nav.find(0, "lobby_3"), None);
        assert!(nav.times_reachable(0, v("lobby_1"), v("lobby_2")));
    }
}
