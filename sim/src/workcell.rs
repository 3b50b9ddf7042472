//! TeleportDispenser and TeleportIngestor (runtime spec §5), and the items they move.
//!
//! Differences from the plugins (their quirks, §5), intended behaviour:
//! - A workcell keeps only the requests addressed to it (upstream copies every request,
//!   so a request for another workcell can overwrite a pending one's guid and
//!   transporter type).
//! - An ingestor that is still holding the previous item (≤ 5 s after a success) keeps a
//!   new request pending and serves it once the item went home (upstream ignores it
//!   silently).
//! - The ingestor's payload is the nearest *item* within 1 m of the robot (upstream: any
//!   non-static model, which could be another robot).
//! - Each dispenser starts filled with its own item `<dispenser>_item`; a dispensed item
//!   is attached to the robot (0.5 m above its origin, the plugin's fallback height) and
//!   moves with it, lift rides included, until ingested.

use crate::msgs::{
    workcell_mode, workcell_result, Msg, Published, Time, Topic, WorkcellRequest, WorkcellResult,
    WorkcellState,
};
use crate::scenario::WorkcellKind;
use crate::slotcar::Slotcar;
use std::collections::BTreeMap;

const VICINITY: f64 = 0.05;
const STATE_PERIOD: i64 = 2;
const RETURN_DELAY: i64 = 5;
const PAYLOAD_RADIUS: f64 = 1.0;

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
    pub fn follow(&mut self, robots: &[Slotcar]) {
        if let Some((r, off)) = self.attached {
            if let Some(r) = robots.get(r) {
                let (s, c) = r.yaw.sin_cos();
                self.pos = [
                    r.x + c * off[0] - s * off[1],
                    r.y + s * off[0] + c * off[1],
                    r.z + off[2],
                ];
                self.yaw = r.yaw + off[3];
            }
        }
    }

    fn teleport(&mut self, p: [f64; 3]) {
        self.attached = None;
        self.pos = p;
    }
}

#[derive(Debug)]
pub(crate) struct Workcell {
    pub name: String,
    pub kind: WorkcellKind,
    pub pos: [f64; 3],
    /// Dispenser: its item. Ingestor: the item it holds.
    item: Option<usize>,
    filled: bool,
    last_pub: i64,
    pending: Option<WorkcellRequest>,
    results: BTreeMap<String, bool>,
    /// Ingestor: integer second of the last ingestion while holding an item.
    holding_since: Option<i64>,
}

/// Results of one request, sent in the same step.
fn result(t: f64, tsec: i64, req: &str, source: &str, status: u8, kind: WorkcellKind) -> Published {
    Published {
        t,
        topic: match kind {
            WorkcellKind::Dispenser => Topic::DispenserResults,
            WorkcellKind::Ingestor => Topic::IngestorResults,
        },
        msg: Msg::WorkcellResult(WorkcellResult {
            time: Time {
                sec: tsec as i32,
                nanosec: 0,
            },
            request_guid: req.to_string(),
            source_guid: source.to_string(),
            status,
        }),
    }
}

impl Workcell {
    pub fn new(name: String, kind: WorkcellKind, pos: [f64; 3], item: Option<usize>) -> Self {
        Workcell {
            name,
            kind,
            pos,
            filled: item.is_some() && kind == WorkcellKind::Dispenser,
            item,
            last_pub: 0,
            pending: None,
            results: BTreeMap::new(),
            holding_since: None,
        }
    }

    /// A request on this workcell's topic (callback, §5.1/§5.2).
    pub fn request(&mut self, t: f64, msg: &WorkcellRequest, out: &mut Vec<Published>) {
        if msg.target_guid != self.name {
            return;
        }
        if let Some(&ok) = self.results.get(&msg.request_guid) {
            let status = if ok {
                workcell_result::SUCCESS
            } else {
                workcell_result::FAILED
            };
            let tsec = t.floor() as i64;
            out.push(result(
                t,
                tsec,
                &msg.request_guid,
                &self.name,
                status,
                self.kind,
            ));
            return;
        }
        self.pending = Some(msg.clone());
    }

    fn in_vicinity(&self, p: [f64; 3]) -> bool {
        (0..3).all(|k| (p[k] - self.pos[k]).abs() <= VICINITY)
    }

    /// One update at `t` (§5.1/§5.2 per-step behaviour). `fleets`: robot indices per
    /// fleet name from the last `/fleet_states`.
    pub fn update(
        &mut self,
        t: f64,
        robots: &[Slotcar],
        items: &mut [Item],
        fleets: &BTreeMap<String, Vec<usize>>,
        out: &mut Vec<Published>,
    ) {
        let tsec = t.floor() as i64;
        let due = tsec - self.last_pub >= STATE_PERIOD;
        if !due && self.pending.is_none() && self.holding_since.is_none() {
            return;
        }
        let dispenser = self.kind == WorkcellKind::Dispenser;
        if dispenser && due && !self.filled {
            if let Some(it) = self.item.and_then(|i| items.get(i)) {
                if it.attached.is_none() && self.in_vicinity(it.pos) {
                    self.filled = true;
                }
            }
        }
        // Ingestor: a request waits while the previous item is still held.
        let serve = self.pending.is_some() && (dispenser || self.holding_since.is_none());
        if due || self.pending.is_some() {
            self.last_pub = tsec;
            let queue: Vec<String> = self
                .pending
                .iter()
                .map(|p| p.request_guid.clone())
                .collect();
            out.push(Published {
                t,
                topic: match self.kind {
                    WorkcellKind::Dispenser => Topic::DispenserStates,
                    WorkcellKind::Ingestor => Topic::IngestorStates,
                },
                msg: Msg::WorkcellState(WorkcellState {
                    time: Time {
                        sec: tsec as i32,
                        nanosec: 0,
                    },
                    guid: self.name.clone(),
                    mode: if queue.is_empty() {
                        workcell_mode::IDLE
                    } else {
                        workcell_mode::BUSY
                    },
                    request_guid_queue: queue,
                    seconds_remaining: 0.0,
                }),
            });
        }
        if serve {
            if let Some(req) = self.pending.take() {
                out.push(result(
                    t,
                    tsec,
                    &req.request_guid,
                    &self.name,
                    workcell_result::ACKNOWLEDGED,
                    self.kind,
                ));
                let ok = if dispenser {
                    self.dispense(&req, robots, items, fleets)
                } else {
                    self.ingest(tsec, &req, robots, items, fleets)
                };
                let status = if ok {
                    workcell_result::SUCCESS
                } else {
                    workcell_result::FAILED
                };
                out.push(result(
                    t,
                    tsec,
                    &req.request_guid,
                    &self.name,
                    status,
                    self.kind,
                ));
                self.results.insert(req.request_guid, ok);
            }
        }
        if let Some(since) = self.holding_since {
            if tsec - since >= RETURN_DELAY {
                if let Some(it) = self.item.take().and_then(|i| items.get_mut(i)) {
                    let home = it.home;
                    it.teleport(home);
                }
                self.holding_since = None;
            }
        }
    }

    /// The nearest robot of the transporter's fleet, at any distance.
    fn nearest_robot(
        &self,
        req: &WorkcellRequest,
        robots: &[Slotcar],
        fleets: &BTreeMap<String, Vec<usize>>,
    ) -> Option<usize> {
        let members = fleets.get(&req.transporter_type)?;
        members
            .iter()
            .filter_map(|&i| robots.get(i).map(|r| (i, r)))
            .map(|(i, r)| {
                let (a, b, c) = (r.x - self.pos[0], r.y - self.pos[1], r.z - self.pos[2]);
                (i, a * a + b * b + c * c)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }

    fn dispense(
        &mut self,
        req: &WorkcellRequest,
        robots: &[Slotcar],
        items: &mut [Item],
        fleets: &BTreeMap<String, Vec<usize>>,
    ) -> bool {
        if !self.filled {
            return false;
        }
        let Some(ri) = self.nearest_robot(req, robots, fleets) else {
            return false;
        };
        let (Some(r), Some(it)) = (robots.get(ri), self.item.and_then(|i| items.get_mut(i))) else {
            return false;
        };
        it.teleport([r.x, r.y, r.z + crate::slotcar::ITEM_HEIGHT]);
        it.yaw = r.yaw;
        it.attach(ri, [r.x, r.y, r.z], r.yaw);
        self.filled = false;
        true
    }

    fn ingest(
        &mut self,
        tsec: i64,
        req: &WorkcellRequest,
        robots: &[Slotcar],
        items: &mut [Item],
        fleets: &BTreeMap<String, Vec<usize>>,
    ) -> bool {
        let Some(ri) = self.nearest_robot(req, robots, fleets) else {
            return false;
        };
        let Some(r) = robots.get(ri) else {
            return false;
        };
        let p = [r.x, r.y, r.z];
        let nearest = items
            .iter()
            .enumerate()
            .map(|(i, it)| (i, it.distance(p)))
            .filter(|(_, d)| *d < PAYLOAD_RADIUS)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((ii, _)) = nearest else {
            return false;
        };
        if let Some(it) = items.get_mut(ii) {
            it.teleport(self.pos);
        }
        self.item = Some(ii);
        self.holding_since = Some(tsec);
        true
    }
}
