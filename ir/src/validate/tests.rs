//! Helpers for rule unit tests: build small buildings in code.
#![allow(dead_code)] // Helpers are shared by rule tests; not every rule uses every one.

use crate::*;

/// A one-level building under construction (`L1` at elevation 0; `level2()` adds `L2`).
pub struct TestMap {
    pub b: Building,
    pub level: Handle<Level>,
}

fn span(line: u32) -> Span {
    Span {
        file: FileId(0),
        start: line * 10,
        end: line * 10 + 5,
        line,
        col: 1,
    }
}

impl TestMap {
    pub fn new() -> Self {
        let mut b = Building::new(
            "test".into(),
            CoordinateSystem::CartesianMeters,
            Params::default(),
        );
        let level = b.levels.append(
            Level {
                name: "L1".into(),
                ..Level::default()
            },
            span(1),
        );
        TestMap { b, level }
    }

    /// Adds a level at `elevation` and makes it the current one.
    pub fn level(&mut self, name: &str, elevation: f64) -> Handle<Level> {
        let n = self.b.levels.len() as u32;
        self.level = self.b.levels.append(
            Level {
                name: name.into(),
                elevation,
                ..Level::default()
            },
            span(100 + n),
        );
        self.level
    }

    pub fn vertex(&mut self, name: &str, x: f64, y: f64) -> Handle<Vertex> {
        self.vertex_with(name, x, y, Params::default())
    }

    pub fn vertex_with(&mut self, name: &str, x: f64, y: f64, params: Params) -> Handle<Vertex> {
        let roles = WaypointRoles::from_params(&params);
        let line = 1000 + self.b.vertices.len() as u32;
        let h = self.b.vertices.append(
            Vertex {
                level: self.level,
                name: name.into(),
                pos: Vec2::new(x, y),
                raw: Vec2::new(x, y),
                params,
                roles: roles.into(),
            },
            span(line),
        );
        self.b.levels[self.level].vertices.push(h);
        h
    }

    pub fn lane(
        &mut self,
        s: Handle<Vertex>,
        e: Handle<Vertex>,
        graph: i64,
        bidirectional: bool,
    ) -> Handle<Lane> {
        let line = 2000 + self.b.lanes.len() as u32;
        let level = self.b.vertices[s].level;
        let h = self.b.lanes.append(
            Lane {
                level,
                start: s,
                end: e,
                graph,
                bidirectional,
                orientation: Orientation::Any,
                speed_limit: None,
                mutex: None,
                demo_mock_floor_name: None,
                demo_mock_lift_name: None,
                params: Params::default(),
            },
            span(line),
        );
        self.b.levels[level].lanes.push(h);
        h
    }

    /// A human lane of `width` metres.
    pub fn human_lane(&mut self, s: Handle<Vertex>, e: Handle<Vertex>, width: f64) {
        let line = 2500 + self.b.human_lanes.len() as u32;
        let level = self.b.vertices[s].level;
        let h = self.b.human_lanes.append(
            HumanLane {
                level,
                start: s,
                end: e,
                params: params(vec![param("width", ParamValue::Double(width))]),
            },
            span(line),
        );
        self.b.levels[level].human_lanes.push(h);
    }

    pub fn wall(&mut self, s: Handle<Vertex>, e: Handle<Vertex>) -> Handle<Wall> {
        let line = 3000 + self.b.walls.len() as u32;
        let level = self.b.vertices[s].level;
        let h = self.b.walls.append(
            Wall {
                level,
                start: s,
                end: e,
                params: Params::default(),
            },
            span(line),
        );
        self.b.levels[level].walls.push(h);
        h
    }

    pub fn door(
        &mut self,
        name: &str,
        kind: DoorKind,
        s: Handle<Vertex>,
        e: Handle<Vertex>,
    ) -> Handle<Door> {
        let line = 4000 + self.b.doors.len() as u32;
        let level = self.b.vertices[s].level;
        let h = self.b.doors.append(
            Door {
                level,
                start: s,
                end: e,
                name: name.into(),
                kind,
                motion_axis: MotionAxis::Start,
                motion_direction: 1,
                motion_degrees: 90.0,
                right_left_ratio: 1.0,
                plugin: true,
                params: Params::default(),
            },
            span(line),
        );
        self.b.levels[level].doors.push(h);
        h
    }

    pub fn floor(&mut self, vertices: &[Handle<Vertex>]) -> Handle<Polygon> {
        let line = 5000 + self.b.floors.len() as u32;
        let h = self.b.floors.append(
            Polygon {
                level: self.level,
                vertices: vertices.to_vec(),
                params: Params::default(),
            },
            span(line),
        );
        self.b.levels[self.level].floors.push(h);
        h
    }

    pub fn hole(&mut self, vertices: &[Handle<Vertex>]) -> Handle<Polygon> {
        let line = 6000 + self.b.holes.len() as u32;
        let h = self.b.holes.append(
            Polygon {
                level: self.level,
                vertices: vertices.to_vec(),
                params: Params::default(),
            },
            span(line),
        );
        self.b.levels[self.level].holes.push(h);
        h
    }

    /// A lift of `w`×`d` at `pos` with one door `door` at (0, -d/2) serving `levels`.
    pub fn lift(
        &mut self,
        name: &str,
        pos: Vec2,
        w: f64,
        d: f64,
        levels: &[Handle<Level>],
    ) -> Handle<Lift> {
        let line = 7000 + self.b.lifts.len() as u32;
        let door = LiftDoor {
            name: "door".into(),
            door_type: 2,
            pos: Vec2::new(0.0, -d / 2.0),
            width: w * 0.6,
            motion_axis_orientation: 0.0,
            span: span(line),
        };
        self.b.lifts.append(
            Lift {
                name: name.into(),
                pos,
                raw: pos,
                yaw: 0.0,
                width: w,
                depth: d,
                reference_level: levels[0],
                initial_level: None,
                lowest_level: None,
                highest_level: None,
                plugins: true,
                doors: vec![door],
                level_doors: levels
                    .iter()
                    .map(|&l| LevelDoors {
                        level: l,
                        doors: vec![("door".into(), span(line))],
                        span: span(line),
                    })
                    .collect(),
            },
            span(line),
        )
    }
}

pub fn param(name: &str, value: ParamValue) -> Param {
    Param {
        name: name.into(),
        value,
        span: span(9000),
    }
}

pub fn params(list: Vec<Param>) -> Params {
    Params(list)
}

/// A level with vertices `v0..vN` at x = 0, 2, 4, ... and the given lanes
/// `(start, end, graph, bidirectional)`.
pub fn lanes_map(lanes: &[(usize, usize, i64, bool)]) -> Building {
    let mut m = TestMap::new();
    let n = lanes.iter().map(|l| l.0.max(l.1)).max().unwrap_or(0) + 1;
    let vs: Vec<_> = (0..n)
        .map(|i| m.vertex(&format!("v{i}"), 2.0 * i as f64, 0.0))
        .collect();
    for &(s, e, g, bi) in lanes {
        m.lane(vs[s], vs[e], g, bi);
    }
    m.b
}

/// Codes of all diagnostics of `validate(b)`.
pub fn codes_of(b: &Building) -> Vec<&'static str> {
    crate::validate(b).into_iter().map(|d| d.code).collect()
}
