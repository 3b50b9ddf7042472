//! [`Building::append_levels`]: levels lowered on their own, moved after a building's own.
//!
//! Why: the frontend lowers the levels of a large map on two threads, the later ones into a
//! building of their own (handles from 0), and appends it. The patterns below name every
//! field, so that a handle added to an element later cannot be forgotten here silently.

use crate::{
    Building, Door, Fiducial, Handle, HumanLane, Lane, Level, Measurement, Model, Polygon, Vertex,
    Wall,
};

/// How far the handles of each kind move: the lengths of the arenas appended to.
struct Shift {
    level: usize,
    vertex: usize,
    lane: usize,
    wall: usize,
    measurement: usize,
    door: usize,
    floor: usize,
    hole: usize,
    model: usize,
    fiducial: usize,
    human_lane: usize,
}

fn shift_all<T>(handles: &mut [Handle<T>], by: usize) {
    for h in handles {
        *h = h.shifted(by);
    }
}

impl Building {
    /// Moves the levels of `other` and everything on them after this building's own, each
    /// handle shifted past this building's elements: the result is exactly that of lowering
    /// all the levels into this building one after the other. Only level contents move:
    /// `other`'s lifts, graphs, crowd and building-wide fields are dropped (a building
    /// made only to hold levels has none).
    pub fn append_levels(&mut self, other: Building) {
        let Building {
            name: _,
            coordinate_system: _,
            crs_name: _,
            offset: _,
            reference_level: _,
            params: _,
            levels,
            vertices,
            lanes,
            walls,
            measurements,
            doors,
            floors,
            holes,
            models,
            fiducials,
            human_lanes,
            lifts,
            graphs,
            crowd_sim,
            map_version: _,
            format: _,
            spans: _,
        } = other;
        debug_assert!(lifts.is_empty() && graphs.is_empty() && crowd_sim.is_none());
        let by = Shift {
            level: self.levels.len(),
            vertex: self.vertices.len(),
            lane: self.lanes.len(),
            wall: self.walls.len(),
            measurement: self.measurements.len(),
            door: self.doors.len(),
            floor: self.floors.len(),
            hole: self.holes.len(),
            model: self.models.len(),
            fiducial: self.fiducials.len(),
            human_lane: self.human_lanes.len(),
        };
        let on = |level: &mut Handle<Level>| *level = level.shifted(by.level);
        let ends = |start: &mut Handle<Vertex>, end: &mut Handle<Vertex>| {
            *start = start.shifted(by.vertex);
            *end = end.shifted(by.vertex);
        };
        self.vertices.append_arena(vertices, |v| {
            let Vertex {
                level,
                name: _,
                pos: _,
                raw: _,
                params: _,
                roles: _,
            } = v;
            on(level);
        });
        self.lanes.append_arena(lanes, |l| {
            let Lane {
                level,
                start,
                end,
                graph: _,
                bidirectional: _,
                orientation: _,
                speed_limit: _,
                mutex: _,
                demo_mock_floor_name: _,
                demo_mock_lift_name: _,
                params: _,
            } = l;
            on(level);
            ends(start, end);
        });
        self.walls.append_arena(walls, |w| {
            let Wall {
                level,
                start,
                end,
                params: _,
            } = w;
            on(level);
            ends(start, end);
        });
        self.measurements.append_arena(measurements, |m| {
            let Measurement {
                level,
                start,
                end,
                distance: _,
                params: _,
            } = m;
            on(level);
            ends(start, end);
        });
        self.doors.append_arena(doors, |d| {
            let Door {
                level,
                start,
                end,
                name: _,
                kind: _,
                motion_axis: _,
                motion_direction: _,
                motion_degrees: _,
                right_left_ratio: _,
                plugin: _,
                params: _,
            } = d;
            on(level);
            ends(start, end);
        });
        let polygon = |p: &mut Polygon| {
            let Polygon {
                level,
                vertices,
                params: _,
            } = p;
            on(level);
            shift_all(vertices, by.vertex);
        };
        self.floors.append_arena(floors, polygon);
        self.holes.append_arena(holes, polygon);
        self.models.append_arena(models, |m| {
            let Model {
                level,
                name: _,
                model_name: _,
                pos: _,
                raw: _,
                z: _,
                yaw: _,
                is_static: _,
                dispensable: _,
            } = m;
            on(level);
        });
        self.fiducials.append_arena(fiducials, |f| {
            let Fiducial {
                level,
                name: _,
                raw: _,
                pos: _,
            } = f;
            on(level);
        });
        self.human_lanes.append_arena(human_lanes, |h| {
            let HumanLane {
                level,
                start,
                end,
                params: _,
            } = h;
            on(level);
            ends(start, end);
        });
        self.levels.append_arena(levels, |l| {
            let Level {
                name: _,
                elevation: _,
                drawing: _,
                x_meters: _,
                y_meters: _,
                transform: _,
                vertices,
                lanes,
                walls,
                measurements,
                doors,
                floors,
                holes,
                models,
                fiducials,
                human_lanes,
                features: _,
                constraints: _,
                layers: _,
            } = l;
            shift_all(vertices, by.vertex);
            shift_all(lanes, by.lane);
            shift_all(walls, by.wall);
            shift_all(measurements, by.measurement);
            shift_all(doors, by.door);
            shift_all(floors, by.floor);
            shift_all(holes, by.hole);
            shift_all(models, by.model);
            shift_all(fiducials, by.fiducial);
            shift_all(human_lanes, by.human_lane);
        });
    }
}
