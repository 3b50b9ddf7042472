//! Doors, lifts, workcells and chargers as the fleet last heard of them: the states the
//! world published (DoorState, DoorHeartbeat, LiftState, workcell results), when each
//! dispenser's item was last ingested, and which robot has each charger.

use super::*;

#[derive(Default, Clone)]
struct DoorView {
    mode: u32,
    sessions: Vec<String>,
}

#[derive(Default, Clone)]
struct LiftView {
    current_floor: String,
    door_state: u8,
    session_id: String,
}

/// The building's devices as the task executor sees them, read only from messages.
///
/// Invariant: a door's or lift's view is the last state the world published for it (a
/// door's sessions those of the last heartbeat), a workcell request's result the last
/// final answer (never ACKNOWLEDGED) under its guid; a charger is held by at most one
/// robot. On that the gates (`Floor::gate`) rest: a robot drives through a controlled
/// door only when it is OPEN in our heartbeat session, into or out of a lift cabin only
/// when the lift is at the floor with its doors open in our session; and no two robots
/// are sent to one charger.
pub(super) struct Devices {
    doors: Vec<DoorView>,
    door_index: BTreeMap<String, usize>,
    lifts: Vec<LiftView>,
    lift_index: BTreeMap<String, usize>,
    /// Per workcell request guid: the final answer.
    results: BTreeMap<String, u8>,
    /// Per charger vertex: the robot that has it.
    chargers: BTreeMap<usize, usize>,
    /// Per dispenser, when its item was last ingested (it then goes home by itself).
    ingested: BTreeMap<String, f64>,
}

impl Devices {
    /// The doors and lifts of `nav`, nothing heard yet.
    pub(super) fn new(nav: &Nav) -> Devices {
        let mut door_index = BTreeMap::new();
        for (i, d) in nav.doors.iter().enumerate() {
            door_index.entry(d.name.clone()).or_insert(i);
        }
        let mut lift_index = BTreeMap::new();
        for (i, l) in nav.lifts.iter().enumerate() {
            lift_index.entry(l.name.clone()).or_insert(i);
        }
        Devices {
            doors: vec![DoorView::default(); nav.doors.len()],
            door_index,
            lifts: vec![LiftView::default(); nav.lifts.len()],
            lift_index,
            results: BTreeMap::new(),
            chargers: BTreeMap::new(),
            ingested: BTreeMap::new(),
        }
    }

    /// Takes in what the world published in `p`. True when it was news of a door, lift or
    /// workcell of ours (robots waiting at one look again).
    pub(super) fn hear(&mut self, p: &Published) -> bool {
        match &p.msg {
            Msg::DoorState(s) => {
                if let Some(&d) = self.door_index.get(&s.door_name) {
                    self.doors[d].mode = s.current_mode.value;
                    return true;
                }
            }
            Msg::DoorHeartbeat(h) => {
                for v in self.doors.iter_mut() {
                    v.sessions.clear();
                }
                for ds in &h.all_sessions {
                    if let Some(&d) = self.door_index.get(&ds.door_name) {
                        self.doors[d].sessions =
                            ds.sessions.iter().map(|s| s.requester_id.clone()).collect();
                    }
                }
                return true;
            }
            Msg::LiftState(s) => {
                if let Some(&l) = self.lift_index.get(&s.lift_name) {
                    self.lifts[l] = LiftView {
                        current_floor: s.current_floor.clone(),
                        door_state: s.door_state,
                        session_id: s.session_id.clone(),
                    };
                    return true;
                }
            }
            Msg::WorkcellResult(res)
                if matches!(p.topic, Topic::DispenserResults | Topic::IngestorResults)
                    && res.status != workcell_result::ACKNOWLEDGED =>
            {
                self.results.insert(res.request_guid.clone(), res.status);
                return true;
            }
            _ => {}
        }
        false
    }

    /// Door `door` is open in `robot`'s session.
    pub(super) fn door_open_for(&self, door: usize, robot: &str) -> bool {
        let v = &self.doors[door];
        v.mode == door_mode::OPEN && v.sessions.iter().any(|s| s == robot)
    }

    /// Lift `lift` is at `floor` with its doors open in `robot`'s session.
    pub(super) fn lift_ready_for(&self, lift: usize, floor: &str, robot: &str) -> bool {
        let v = &self.lifts[lift];
        v.current_floor == floor && v.door_state == lift_state::DOOR_OPEN && v.session_id == robot
    }

    /// The floor lift `lift` last said it is at.
    pub(super) fn lift_floor(&self, lift: usize) -> &str {
        &self.lifts[lift].current_floor
    }

    /// The final answer to workcell request `guid`, if one came.
    pub(super) fn result(&self, guid: &str) -> Option<u8> {
        self.results.get(guid).copied()
    }

    /// `dispenser`'s item was ingested at `t`.
    pub(super) fn ingested(&mut self, dispenser: String, t: f64) {
        self.ingested.insert(dispenser, t);
    }

    /// `dispenser`'s item was ingested lately: it is on its way home (the ingestor returns
    /// it after a few seconds).
    pub(super) fn home_soon(&self, dispenser: &str, t: f64) -> bool {
        self.ingested
            .get(dispenser)
            .is_some_and(|&at| t - at < ITEM_HOME)
    }

    /// Nobody but robot `i` has charger `v`.
    pub(super) fn charger_free_for(&self, v: usize, i: usize) -> bool {
        self.chargers.get(&v).is_none_or(|&o| o == i)
    }

    /// Robot `i` takes charger `c`.
    pub(super) fn take_charger(&mut self, c: usize, i: usize) {
        self.chargers.insert(c, i);
    }

    /// Charger `c` is free again.
    pub(super) fn free_charger(&mut self, c: usize) {
        self.chargers.remove(&c);
    }
}
