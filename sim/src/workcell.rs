//! TeleportDispenser and TeleportIngestor (runtime spec §5), and the items they move.
//!
//! Differences from the plugins (their quirks, §5), intended behaviour:
//! - A workcell keeps only the requests addressed to it (upstream copies every request,
//!   so a request for another workcell can overwrite a pending one's guid and
//!   transporter type).
//! - An ingestor that is still holding the previous item (≤ 5 s after a success) keeps a
//!   new request pending and serves it once the item went home (upstream ignores it
//!   silently).
//! - The ingestor's payload is the item the robot carries, else the nearest *item* within
//!   1 m of the robot (upstream: the nearest non-static model within 1 m, which could be
//!   another robot, or a dispenser's item waiting at the same place: then the carried item
//!   stayed on the robot for good and its dispenser was never refilled).
//! - Each dispenser starts filled with its own item `<dispenser>_item`; a dispensed item
//!   is attached to the robot (0.5 m above its origin, the plugin's fallback height) and
//!   moves with it, lift rides included, until ingested.

use crate::msgs::{
    workcell_mode, workcell_result, Msg, Published, Time, Topic, WorkcellRequest, WorkcellResult,
    WorkcellState,
};
use crate::scenario::WorkcellKind;
use crate::truth::{Body, Item, ITEM_HEIGHT};
use std::collections::BTreeMap;

const VICINITY: f64 = 0.05;
const STATE_PERIOD: i64 = 2;
const RETURN_DELAY: i64 = 5;
const PAYLOAD_RADIUS: f64 = 1.0;

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
    /// The pending request has been listed in a state message.
    announced: bool,
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
            announced: false,
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
        self.announced = false;
    }

    fn in_vicinity(&self, p: [f64; 3]) -> bool {
        (0..3).all(|k| (p[k] - self.pos[k]).abs() <= VICINITY)
    }

    /// One update at `t` (§5.1/§5.2 per-step behaviour). `fleets`: robot indices per
    /// fleet name from the last `/fleet_states`.
    pub fn update(
        &mut self,
        t: f64,
        robots: &[impl Body],
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
        // A new request is announced at once; one waiting for the held item only at the
        // regular period.
        let fresh = self.pending.is_some() && !self.announced;
        if due || fresh {
            self.last_pub = tsec;
            self.announced = self.pending.is_some();
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
        robots: &[impl Body],
        fleets: &BTreeMap<String, Vec<usize>>,
    ) -> Option<usize> {
        let members = fleets.get(&req.transporter_type)?;
        members
            .iter()
            .filter_map(|&i| robots.get(i).map(|r| (i, r)))
            .map(|(i, r)| {
                let [x, y, z, _] = r.pose();
                let (a, b, c) = (x - self.pos[0], y - self.pos[1], z - self.pos[2]);
                (i, a * a + b * b + c * c)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }

    fn dispense(
        &mut self,
        req: &WorkcellRequest,
        robots: &[impl Body],
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
        let [x, y, z, yaw] = r.pose();
        it.teleport([x, y, z + ITEM_HEIGHT]);
        it.yaw = yaw;
        it.attach(ri, [x, y, z], yaw);
        self.filled = false;
        true
    }

    fn ingest(
        &mut self,
        tsec: i64,
        req: &WorkcellRequest,
        robots: &[impl Body],
        items: &mut [Item],
        fleets: &BTreeMap<String, Vec<usize>>,
    ) -> bool {
        let Some(ri) = self.nearest_robot(req, robots, fleets) else {
            return false;
        };
        let Some(r) = robots.get(ri) else {
            return false;
        };
        let [x, y, z, _] = r.pose();
        let p = [x, y, z];
        let carried = items
            .iter()
            .position(|it| it.attached.is_some_and(|(r, _)| r == ri));
        let nearest = || {
            items
                .iter()
                .enumerate()
                .map(|(i, it)| (i, it.distance(p)))
                .filter(|(_, d)| *d < PAYLOAD_RADIUS)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| i)
        };
        let Some(ii) = carried.or_else(nearest) else {
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
