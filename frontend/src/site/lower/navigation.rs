//! Navigation graphs: their properties, lanes (motion, speed limit, dock), locations and the
//! graphs each is on.

use super::*;

impl<'d, 'n, 's> SiteLower<'d, 'n, 's> {
    pub(super) fn graphs(&mut self, root: &Node, b: &mut Building) {
        let Some(g) = root.get("navigation").and_then(|n| n.get("guided")) else {
            return;
        };
        let list: Vec<(u32, String, Span)> = self
            .entries(g, "graphs", "`navigation.guided`")
            .into_iter()
            .map(|(id, v, s)| (id, self.name(v, "a graph"), s))
            .collect();
        // A graph named by an integer keeps it as its index (what `mapc convert` writes
        // for a `.building.yaml`'s graph_idx); the others take the next free ones.
        let mut taken = std::collections::BTreeSet::new();
        for (id, name, _) in &list {
            if let Ok(i) = name.trim().parse::<i64>() {
                if i >= 0 && taken.insert(i) {
                    self.graphs.insert(*id, i);
                }
            }
        }
        let mut next = 0;
        for (id, _, _) in &list {
            if self.graphs.contains_key(id) {
                continue;
            }
            while taken.contains(&next) {
                next += 1;
            }
            taken.insert(next);
            self.graphs.insert(*id, next);
        }
        for (id, name, _) in list {
            b.graphs.push(GraphInfo {
                index: self.graphs[&id],
                name,
                default_lane_width: 1.0,
                unnamed: Vec::new(),
            });
        }
        b.graphs.sort_by_key(|g| g.index);
    }

    pub(super) fn motion(
        &mut self,
        n: Option<&Node>,
    ) -> (Orientation, Option<f64>, Option<String>) {
        let Some(n) = n else {
            return (Orientation::Any, None, None);
        };
        self.unknown(n, MOTION_KEYS, "a lane motion");
        let orientation = match n.get("orientation_constraint").and_then(variant) {
            Some(("Forwards", _)) => Orientation::Forward,
            Some(("Backwards", _)) => Orientation::Backward,
            Some(("None", _)) | None => Orientation::Any,
            Some((other, _)) => {
                let span = n.get("orientation_constraint").map_or(n.span, |c| c.span);
                self.l.warn(
                    "W0121",
                    span,
                    format!("orientation constraint `{other}` has no equivalent in RMF nav graphs; it is ignored"),
                    "use Forwards, Backwards or None",
                );
                Orientation::Any
            }
        };
        let speed = n
            .get("speed_limit")
            .and_then(|s| s.as_f64())
            .filter(|s| *s > 0.0);
        let dock = n
            .get("dock")
            .and_then(|d| d.get("name"))
            .and_then(|d| d.key_text())
            .filter(|d| !d.is_empty())
            .map(str::to_string);
        (orientation, speed, dock)
    }

    pub(super) fn lane(
        &mut self,
        b: &mut Building,
        id: u32,
        n: &Node,
        span: Span,
        ext_lanes: Option<&Node>,
    ) {
        if self.l.map(n, "a lane").is_none() {
            return;
        }
        self.unknown(n, LANE_KEYS, "a lane");
        let Some(a) = self.anchor_pair(n, span, "a lane") else {
            return;
        };
        let mut ends = [None, None];
        for (i, node) in a.iter().enumerate() {
            let Some(aid) = ref_of(node) else {
                self.l
                    .wrong_type(node, "an anchor id", "an unsigned integer");
                return;
            };
            match self.anchors.get(&aid) {
                Some(x) => ends[i] = Some((aid, *x, node.span)),
                None => {
                    self.l.err(
                        "E0121",
                        node.span,
                        format!("lane {id} refers to anchor {aid}, which the site does not have"),
                        "point the lane at an existing anchor, or delete the lane",
                    );
                    return;
                }
            }
        }
        let [Some(s), Some(e)] = ends else { return };
        // rmf_site's nav export (`NavGraph::from_site`) makes waypoints of level anchors
        // and cabin anchors only, and leaves out a lane on a site anchor ("not
        // supported"); mapc's nav graphs are the same, and say so.
        if let Some((aid, _, aspan)) = [s, e]
            .into_iter()
            .find(|(_, x, _)| matches!(x, Anchor::Site(..)))
        {
            self.l.warn(
                "W0123",
                aspan,
                format!("lane {id} uses site anchor {aid}; it is left out of the nav graphs, as rmf_site's own nav export leaves it out"),
                "in rmf_site, draw the lane to an anchor of the level (a new anchor at the same place), not to the site anchor",
            );
            return;
        }
        let level_of = |x: &Anchor| match x {
            Anchor::Level(l, _) => Some(*l),
            _ => None,
        };
        let lh = match (level_of(&s.1), level_of(&e.1)) {
            (Some(l1), Some(l2)) if l1 != l2 => {
                self.l.err(
                    "E0122",
                    span,
                    format!(
                        "lane {id} joins level `{}` and level `{}`",
                        b.levels[l1].name, b.levels[l2].name
                    ),
                    "a lane lies on one level; use a lift to change levels",
                );
                return;
            }
            (Some(l), _) | (None, Some(l)) => l,
            (None, None) => {
                self.l.err(
                    "E0122",
                    span,
                    format!("lane {id} has no end on a level anchor"),
                    "draw the lane from an anchor of a level",
                );
                return;
            }
        };
        let mut vs = [None, None];
        for (i, (aid, x, aspan)) in [s, e].into_iter().enumerate() {
            vs[i] = match x {
                Anchor::Level(_, v) => Some(v),
                Anchor::Cabin(lift, p) => self.cabin_vertex(b, aid, lift, p, lh, aspan),
                Anchor::Site(..) => None,
            };
        }
        let [Some(sv), Some(ev)] = vs else { return };

        let (orientation, speed_limit, fdock) = self.motion(n.get("forward"));
        let reverse = n.get("reverse");
        let (bidirectional, back) = match reverse.and_then(variant) {
            None | Some(("Same", _)) => (true, None),
            Some(("Disable", _)) => (false, None),
            Some(("Different", m)) => (true, Some(self.motion(m))),
            Some((other, _)) => {
                self.l.wrong_type(
                    reverse.unwrap_or(n),
                    &format!("lane reverse `{other}`"),
                    "Same, Disable or Different",
                );
                (true, None)
            }
        };
        let mutex = n
            .get("mutex")
            .and_then(ref_of)
            .and_then(|m| self.mutexes.get(&m).cloned())
            .filter(|m| !m.is_empty());
        let graphs = self.graph_set(n, &format!("lane {id}"));
        let lext = ext_lanes.and_then(|e| e.get(&id.to_string()));
        let ext_str = |k: &str| {
            lext.and_then(|e| e.get(k))
                .and_then(|v| v.key_text())
                .map(str::to_string)
        };
        let (demo_floor, demo_lift) = (
            ext_str("demo_mock_floor_name"),
            ext_str("demo_mock_lift_name"),
        );
        let orientation = match ext_str("orientation") {
            Some(o) if !o.is_empty() => Orientation::Other(o),
            _ => orientation,
        };

        // Docks are vertex properties in RMF nav graphs: a lane into a vertex docks there.
        let set_dock = |b: &mut Building, v: Handle<Vertex>, d: &str| {
            b.vertices[v].params.insert(Param {
                name: "dock_name".into(),
                value: ParamValue::String(d.to_string()),
                span,
            });
        };
        if let Some(d) = &fdock {
            set_dock(b, ev, d);
        }
        // A reverse motion that differs in more than its dock: two one-way lanes.
        let split = match &back {
            Some((o, sl, d)) => {
                if let Some(d) = d {
                    set_dock(b, sv, d);
                }
                *o != orientation.reversed() || *sl != speed_limit
            }
            None => false,
        };
        let push = |b: &mut Building, s, e, bidi, o: Orientation, sl| {
            for &g in &graphs {
                let h = b.lanes.append(
                    Lane {
                        level: lh,
                        start: s,
                        end: e,
                        graph: g,
                        bidirectional: bidi,
                        orientation: o.clone(),
                        speed_limit: sl,
                        mutex: mutex.clone(),
                        demo_mock_floor_name: demo_floor.clone(),
                        demo_mock_lift_name: demo_lift.clone(),
                        params: Params::default(),
                    },
                    span,
                );
                b.levels[lh].lanes.push(h);
            }
        };
        if split {
            push(b, sv, ev, false, orientation, speed_limit);
            let (o, sl, _) = back.unwrap_or((Orientation::Any, None, None));
            push(b, ev, sv, false, o, sl);
        } else {
            push(b, sv, ev, bidirectional, orientation, speed_limit);
        }
    }

    /// The IR graph indices of a lane's or location's `graphs` (`what` names it).
    pub(super) fn graph_set(&mut self, n: &Node, what: &str) -> Vec<i64> {
        let all: Vec<(u32, i64)> = self.graphs.iter().map(|(k, v)| (*k, *v)).collect();
        let set = |s: &mut Self, v: Option<&Node>| -> Vec<u32> {
            let mut out = Vec::new();
            for g in v.and_then(|v| v.as_seq()).unwrap_or(&[]) {
                match ref_of(g) {
                    Some(gid) if s.graphs.contains_key(&gid) => out.push(gid),
                    Some(gid) => s.l.err(
                        "E0121",
                        g.span,
                        format!("{what} refers to graph {gid}, which the site does not have"),
                        "point it at an existing graph",
                    ),
                    None => s.l.wrong_type(g, "a graph id", "an unsigned integer"),
                }
            }
            out
        };
        let mut out: Vec<i64> = match n.get("graphs").and_then(variant) {
            Some(("All", _)) | None => all.iter().map(|(_, i)| *i).collect(),
            Some(("Only", v)) => set(self, v).iter().map(|g| self.graphs[g]).collect(),
            Some(("AllExcept", v)) => {
                let ex = set(self, v);
                all.iter()
                    .filter(|(g, _)| !ex.contains(g))
                    .map(|(_, i)| *i)
                    .collect()
            }
            Some((other, _)) => {
                let span = n.get("graphs").map_or(n.span, |g| g.span);
                self.l.err(
                    "E0101",
                    span,
                    format!("unknown graphs `{other}` of {what}"),
                    "use All, Only or AllExcept",
                );
                Vec::new()
            }
        };
        out.sort_unstable();
        out.dedup();
        out
    }

    pub(super) fn location(&mut self, b: &mut Building, n: &Node, span: Span) {
        if self.l.map(n, "a location").is_none() {
            return;
        }
        self.unknown(n, LOCATION_KEYS, "a location");
        let name = self.name(n, "a location");
        let aid = n.get("anchor").and_then(ref_of);
        let targets: Vec<Handle<Vertex>> = match aid.and_then(|a| self.anchors.get(&a).copied()) {
            Some(Anchor::Level(_, v)) => vec![v],
            // A cabin anchor has one vertex per level a lane uses it from.
            Some(Anchor::Cabin(..)) => self
                .cabin_vertices
                .iter()
                .filter(|((a, _), _)| Some(*a) == aid)
                .map(|(_, v)| *v)
                .collect(),
            Some(Anchor::Site(..)) => {
                let at = n.get("anchor").map_or(span, |a| a.span);
                self.l.warn(
                    "W0123",
                    at,
                    format!(
                        "location `{name}` is on site anchor {}; no nav graph has a waypoint there, as rmf_site's own nav export has none",
                        aid.map_or("?".into(), |a| a.to_string())
                    ),
                    "in rmf_site, put the location on an anchor of a level",
                );
                return;
            }
            _ => {
                let at = n.get("anchor").map_or(span, |a| a.span);
                self.l.err(
                    "E0123",
                    at,
                    format!(
                        "location `{name}` is on anchor {}, which the site does not have on a level or lift",
                        aid.map_or("?".into(), |a| a.to_string())
                    ),
                    "move the location onto an anchor of a level",
                );
                return;
            }
        };
        let mut flags = Vec::new();
        for t in n.get("tags").and_then(|t| t.as_seq()).unwrap_or(&[]) {
            // Warnings point at the variant's name.
            let at = t
                .as_map()
                .and_then(|m| m.first())
                .map_or(t.span, |(k, _)| k.span);
            match variant(t) {
                Some(("Charger", _)) => flags.push(("is_charger", t.span)),
                Some(("ParkingSpot", _)) => flags.push(("is_parking_spot", t.span)),
                Some(("HoldingPoint", _)) => flags.push(("is_holding_point", t.span)),
                Some(("Workcell", w)) => {
                    // mapc's extension says which dispenser or ingestor a workcell it
                    // wrote is; a workcell drawn in rmf_site says neither.
                    let role = |v: &Handle<Vertex>| {
                        let p = &b.vertices[*v].params;
                        p.param("pickup_dispenser").is_some()
                            || p.param("dropoff_ingestor").is_some()
                    };
                    if !targets.iter().any(role) {
                        let cell = w
                            .and_then(|w| w.get("name"))
                            .and_then(|n| n.key_text())
                            .unwrap_or("");
                        self.l.warn(
                            "W0121",
                            at,
                            format!("workcell `{cell}` at location `{name}` is kept as a named place only: rmf_site does not say whether it is a dispenser or an ingestor"),
                            "give the waypoint `pickup_dispenser` or `dropoff_ingestor` in the converted .building.yaml if tasks use it",
                        );
                    }
                }
                _ => {
                    let tag = variant(t).map_or("?", |(v, _)| v);
                    self.l.warn(
                        "W0121",
                        at,
                        format!("location tag `{tag}` of `{name}` is not one rmf_site_format 0.0.2 defines; it is ignored"),
                        "use Charger, ParkingSpot, HoldingPoint or Workcell",
                    );
                }
            }
        }
        let mutex = n
            .get("mutex")
            .and_then(ref_of)
            .and_then(|m| self.mutexes.get(&m))
            .filter(|m| !m.is_empty())
            .cloned();
        // The graphs the location is not in keep the waypoint, unnamed.
        let graphs = self.graph_set(n, &format!("location `{name}`"));
        for g in b.graphs.iter_mut().filter(|g| !graphs.contains(&g.index)) {
            g.unnamed.extend(&targets);
            g.unnamed.sort_unstable();
            g.unnamed.dedup();
        }
        for v in targets {
            let vx = &mut b.vertices[v];
            vx.name = name.clone();
            for (flag, at) in &flags {
                vx.params.insert(Param {
                    name: (*flag).into(),
                    value: ParamValue::Bool(true),
                    span: *at,
                });
            }
            if let Some(m) = &mutex {
                vx.params.insert(Param {
                    name: "mutex".into(),
                    value: ParamValue::String(m.clone()),
                    span,
                });
            }
        }
    }
}
