//! A level's vertices and the elements between two of them: lanes (with their graph and
//! speed limit) and doors.

use super::*;

impl Lower<'_> {
    pub(super) fn coord_pair(&mut self, x: &Node, y: &Node, what: &str) -> Option<Vec2> {
        let x = self.f64(x, format_args!("the x coordinate of {what}"));
        let y = self.f64(y, format_args!("the y coordinate of {what}"));
        Some(Vec2::new(x?, y?))
    }

    pub(super) fn vertex(&mut self, level: Handle<Level>, node: &Node) -> Option<Vertex> {
        let Some(items) = node.as_seq() else {
            self.wrong_type(node, "a vertex", "a sequence `[x, y, z, name, {params}]`");
            return None;
        };
        if items.len() < 4 {
            self.err(
                "E0101",
                node.span,
                format!(
                    "a vertex must have at least 4 elements `[x, y, z, name]`, found {}",
                    items.len()
                ),
                "write the vertex as `[x, y, z, name]` (name may be \"\")",
            );
            return None;
        }
        let raw = self.coord_pair(&items[0], &items[1], "a vertex")?;
        // items[2] (z) is a placeholder the generator ignores; check it is a number anyway.
        self.f64(&items[2], "the z of a vertex");
        let name = self.string(&items[3], "a vertex name")?;
        let params = match items.get(4) {
            Some(p) => {
                self.misspelled_params(p, format_args!("vertex `{name}`"));
                self.params(p, format_args!("vertex `{name}`"))
            }
            None => Params::default(),
        };
        if items.len() > 5 {
            self.warn(
                "W0103",
                items[5].span,
                "extra elements after the vertex parameters are ignored",
                "remove them",
            );
        }
        let roles = WaypointRoles::from_params(&params);
        Some(Vertex {
            level,
            name,
            pos: raw,
            raw,
            params,
            roles: roles.into(),
        })
    }

    pub(super) fn edge(
        &mut self,
        b: &Building,
        level: Handle<Level>,
        node: &Node,
        key: &str,
        slots: &VertexSlots,
    ) -> Option<Edge> {
        let Some(items) = node.as_seq() else {
            self.wrong_type(
                node,
                &format!("an entry of `{key}`"),
                "a sequence `[start, end, {params}]`",
            );
            return None;
        };
        if items.len() < 2 {
            self.err(
                "E0101",
                node.span,
                format!(
                    "an entry of `{key}` needs two vertex indices, found {} elements",
                    items.len()
                ),
                "write it as `[start_index, end_index, {params}]`",
            );
            return None;
        }
        let s = self.vertex_index(b, level, &items[0], slots);
        let e = self.vertex_index(b, level, &items[1], slots);
        // Parameters are checked even when an index failed: their problems are their own.
        let (params, invalid) = match items.get(2) {
            Some(p) => self.params_checked(p, format_args!("an entry of `{key}`")),
            None => Default::default(),
        };
        Some(Edge {
            start: s?,
            end: e?,
            params,
            invalid,
            span: node.span,
        })
    }

    /// The vertex at file position `n` of the level. Out of range is E0103, counted against
    /// the file's `vertices` list; a vertex that failed to lower gives `None` without a
    /// further diagnostic (it has its own).
    pub(super) fn vertex_index(
        &mut self,
        b: &Building,
        level: Handle<Level>,
        n: &Node,
        slots: &VertexSlots,
    ) -> Option<Handle<Vertex>> {
        let i = self.i64(n, "a vertex index")?;
        let nverts = slots.len();
        if i < 0 || i as u64 >= nverts as u64 {
            self.err(
                "E0103",
                n.span,
                format!(
                    "vertex index {i} is out of range: level `{}` has {nverts} vertices (0..{})",
                    b.levels[level].name,
                    nverts.saturating_sub(1)
                ),
                "use the 0-based index of a vertex in this level's `vertices` list",
            );
            return None;
        }
        slots[i as usize]
    }

    pub(super) fn lane(&mut self, level: Handle<Level>, edge: Edge) -> Option<Lane> {
        let graph_idx_invalid = edge.is_invalid("graph_idx");
        let Edge {
            start,
            end,
            params,
            span,
            ..
        } = edge;
        let graph = match params.get("graph_idx") {
            // Present but malformed: already reported as E0105.
            None if graph_idx_invalid => return None,
            None => {
                self.err(
                    "E0102",
                    span,
                    "lane has no `graph_idx` parameter",
                    "add `graph_idx: [2, <fleet graph number>]` to the lane",
                );
                return None;
            }
            Some(ParamValue::Int(i)) if *i >= 0 => *i,
            Some(v) => {
                let span = params.param("graph_idx").map_or(span, |p| p.span);
                self.err(
                    "E0105",
                    span,
                    format!(
                        "lane `graph_idx` must be a non-negative int, found {}",
                        match v {
                            ParamValue::Int(i) => i.to_string(),
                            other => other.type_name().to_string(),
                        }
                    ),
                    "write `graph_idx: [2, 0]` (type code 2, a graph number from 0)",
                );
                return None;
            }
        };
        let bidirectional = match params.get("bidirectional") {
            None => false,
            Some(ParamValue::Bool(b)) => *b,
            Some(v) => {
                self.err(
                    "E0105",
                    params.param("bidirectional").map_or(span, |p| p.span),
                    format!(
                        "lane `bidirectional` must be a bool, found {}",
                        v.type_name()
                    ),
                    "write `bidirectional: [4, true]` or `[4, false]`",
                );
                return None;
            }
        };
        let orientation = match params.str("orientation").unwrap_or("") {
            "" => Orientation::Any,
            "forward" => Orientation::Forward,
            "backward" => Orientation::Backward,
            other => Orientation::Other(other.to_string()),
        };
        let speed_limit = match params.get("speed_limit") {
            None => None,
            Some(v) => match v.as_f64() {
                Some(s) => (s > 0.0).then_some(s),
                None => {
                    self.err(
                        "E0105",
                        params.param("speed_limit").map_or(span, |p| p.span),
                        "lane `speed_limit` must be a number",
                        "write `speed_limit: [3, <metres per second>]` (0 for none)",
                    );
                    None
                }
            },
        };
        let s = |k: &str| params.str(k).filter(|s| !s.is_empty()).map(str::to_string);
        let (mutex, demo_mock_floor_name, demo_mock_lift_name) = (
            s("mutex"),
            s("demo_mock_floor_name"),
            s("demo_mock_lift_name"),
        );
        // `graph_idx` and `bidirectional` are whole in their fields; nearly every lane has
        // both, and as parameters they took more memory than the rest of the lane.
        let mut params = params;
        params
            .0
            .retain(|p| p.name != "graph_idx" && p.name != "bidirectional");
        params.0.shrink_to_fit();
        Some(Lane {
            level,
            start,
            end,
            graph,
            bidirectional,
            orientation,
            speed_limit,
            mutex,
            demo_mock_floor_name,
            demo_mock_lift_name,
            params,
        })
    }

    pub(super) fn door(&mut self, level: Handle<Level>, edge: Edge) -> Option<Door> {
        let (name_invalid, type_invalid) = (edge.is_invalid("name"), edge.is_invalid("type"));
        let Edge {
            start,
            end,
            params,
            span,
            ..
        } = edge;
        let Some(name) = params.str("name").map(str::to_string) else {
            // Present but malformed: already reported as E0105.
            if name_invalid {
                return None;
            }
            self.err(
                "E0102",
                span,
                "door has no `name` parameter of type string",
                "add `name: [1, <door name>]` to the door",
            );
            return None;
        };
        let kind = match params.str("type") {
            Some(t) => DoorKind::parse(t),
            None if type_invalid => return None,
            None => {
                self.err(
                    "E0102",
                    span,
                    format!("door `{name}` has no `type` parameter of type string"),
                    "add `type: [1, hinged]` (or double_hinged, sliding, double_sliding)",
                );
                return None;
            }
        };
        let motion_axis = match params.str("motion_axis") {
            Some("end") => MotionAxis::End,
            _ => MotionAxis::Start,
        };
        Some(Door {
            level,
            start,
            end,
            motion_axis,
            // Read as a number: files write both `[2, -1]` and `[3, -1.0]`.
            motion_direction: params
                .f64("motion_direction")
                .map_or(1, |v| v.round() as i64),
            motion_degrees: params.f64("motion_degrees").unwrap_or(90.0),
            right_left_ratio: params.f64("right_left_ratio").unwrap_or(1.0),
            plugin: params.str("plugin") != Some("none"),
            name,
            kind,
            params,
        })
    }
}
