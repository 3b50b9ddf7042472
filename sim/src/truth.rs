//! The truths the plugins share: what one plugin may know of the things another moves.
//!
//! The plugins (`slotcar`, `door`, `lift`, `workcell`, `crowd`) never import one another:
//! each reads and writes these types, and `world`, which owns every plugin, hands each
//! the truths it needs in every step. A slotcar is a [`Body`] that a lift carries and an
//! [`Item`] follows; a door is a [`DoorControl`] that a lift drives; the crowd is
//! [`People`] the robots stop for, and sees the robots as [`RobotTruth`]s.

/// Ground truth of a robot, for the crowd, the report (near misses) and tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotTruth {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub yaw: f64,
    /// Forward speed command (m/s).
    pub v: f64,
    pub footprint: f64,
}

/// A robot's body as the other plugins see it.
pub(crate) trait Body {
    /// `[x, y, z, yaw]` in the map frame.
    fn pose(&self) -> [f64; 4];
    /// Sets the body's vertical velocity for this step (a lift carrying it).
    fn ride(&mut self, vz: f64);
    /// Puts the body's origin at height `z` (a lift cabin that stopped at a floor sets
    /// what stands on it on the floor's elevation).
    fn settle(&mut self, z: f64);
}

/// A door as a lift drives its cabin and shaft doors.
pub(crate) trait DoorControl {
    /// Opens (`true`) or closes the door.
    fn command(&mut self, open: bool);
    /// The door's current `door_mode`.
    fn mode(&self) -> u32;
}

/// People as the robots see them: obstacles.
pub(crate) trait People {
    /// Is a person closer than `r` (3-D, to their centre) to `p` (map frame)?
    fn any_within(&self, p: [f64; 3], r: f64) -> bool;
}

/// Height at which a dispensed item sits above the robot origin (the plugin's fallback
/// when the robot's bounding box is unknown).
pub(crate) const ITEM_HEIGHT: f64 = 0.5;

/// A movable model: a dispensable item, or a cart from the map.
#[derive(Debug, Clone)]
pub(crate) struct Item {
    pub name: String,
    pub pos: [f64; 3],
    pub yaw: f64,
    pub home: [f64; 3],
    /// Robot it is fixed to, with its offset in the robot frame (x, y, z, yaw).
    pub attached: Option<(usize, [f64; 4])>,
}

impl Item {
    pub fn new(name: String, pos: [f64; 3], yaw: f64) -> Item {
        Item {
            name,
            pos,
            yaw,
            home: pos,
            attached: None,
        }
    }

    pub fn distance(&self, p: [f64; 3]) -> f64 {
        let (a, b, c) = (self.pos[0] - p[0], self.pos[1] - p[1], self.pos[2] - p[2]);
        (a * a + b * b + c * c).sqrt()
    }

    /// Fixes the item to robot `robot` at pose `p`, `yaw`, keeping its current offset.
    pub fn attach(&mut self, robot: usize, p: [f64; 3], yaw: f64) {
        let (s, c) = yaw.sin_cos();
        let (dx, dy) = (self.pos[0] - p[0], self.pos[1] - p[1]);
        let off = [
            c * dx + s * dy,
            -s * dx + c * dy,
            self.pos[2] - p[2],
            self.yaw - yaw,
        ];
        self.attached = Some((robot, off));
    }

    /// Moves an attached item with its robot.
    #[inline]
    pub fn follow(&mut self, robots: &[impl Body]) {
        if let Some((r, off)) = self.attached {
            if let Some(r) = robots.get(r) {
                let [x, y, z, yaw] = r.pose();
                let (s, c) = yaw.sin_cos();
                self.pos = [
                    x + c * off[0] - s * off[1],
                    y + s * off[0] + c * off[1],
                    z + off[2],
                ];
                self.yaw = yaw + off[3];
            }
        }
    }

    pub fn teleport(&mut self, p: [f64; 3]) {
        self.attached = None;
        self.pos = p;
    }
}
