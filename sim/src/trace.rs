//! The trace: one JSON object per published message, `{"t":..,"topic":..,"msg":{..}}`.
//!
//! Keys come in a fixed order (struct field order), floats in serde_json's shortest
//! round-trip form, so identical runs give byte-identical traces.

use crate::msgs::{Msg, Published, Topic};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::io::{self, Write};

/// Which messages the trace keeps: a set of topics (all when `None`), and state topics at
/// most once per `state_period` seconds per publisher (a robot, door, lift or workcell), so
/// an 8 h trace need not hold every 10 Hz state. The report always sees every message.
#[derive(Debug, Default)]
pub struct TraceFilter {
    pub topics: Option<BTreeSet<Topic>>,
    /// 0: every state message.
    pub state_period: f64,
    last: BTreeMap<(Topic, String), f64>,
}

impl TraceFilter {
    pub fn new(topics: Option<BTreeSet<Topic>>, state_period: f64) -> TraceFilter {
        TraceFilter {
            topics,
            state_period,
            last: BTreeMap::new(),
        }
    }

    /// Whether `p` goes to the trace (and, when it does, remembers it for the rate limit).
    pub fn accepts(&mut self, p: &Published) -> bool {
        if self.topics.as_ref().is_some_and(|t| !t.contains(&p.topic)) {
            return false;
        }
        if self.state_period <= 0.0 || !p.topic.is_state() {
            return true;
        }
        let who = match &p.msg {
            Msg::RobotState(s) => s.name.clone(),
            Msg::FleetState(s) => s.name.clone(),
            Msg::DoorState(s) => s.door_name.clone(),
            Msg::LiftState(s) => s.lift_name.clone(),
            Msg::WorkcellState(s) => s.guid.clone(),
            _ => String::new(),
        };
        let key = (p.topic, who);
        // A small tolerance: publish times are sums of steps.
        if self
            .last
            .get(&key)
            .is_some_and(|&t| p.t - t < self.state_period - 1e-9)
        {
            return false;
        }
        self.last.insert(key, p.t);
        true
    }
}

#[derive(Serialize)]
struct Line<'a> {
    t: f64,
    topic: &'static str,
    msg: &'a Msg,
}

/// Writes one line for `p` (callers should hand in a buffered writer: serde_json issues
/// many small writes).
pub fn write(w: &mut dyn Write, p: &Published) -> io::Result<()> {
    let line = Line {
        t: p.t,
        topic: p.topic.name(),
        msg: &p.msg,
    };
    serde_json::to_writer(&mut *w, &line).map_err(io::Error::from)?;
    w.write_all(b"\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msgs::{door_mode, DoorMode, DoorState, Time, Topic};

    fn door(t: f64, mode: u32) -> Published {
        Published {
            t,
            topic: Topic::DoorStates,
            msg: Msg::DoorState(DoorState {
                door_time: Time::from_secs(t),
                door_name: "main \"door\"".into(),
                current_mode: DoorMode { value: mode },
            }),
        }
    }

    #[test]
    fn one_json_object_per_line_in_fixed_key_order() {
        let mut out = Vec::new();
        write(&mut out, &door(12.34, door_mode::OPEN)).unwrap();
        write(&mut out, &door(0.1 + 0.2, door_mode::CLOSED)).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2);
        assert!(text.ends_with('\n'));
        // 12.34 s = 12 s + 340,000,000 ns; the name is JSON-escaped.
        assert_eq!(
            lines[0],
            r#"{"t":12.34,"topic":"/door_states","msg":{"door_time":{"sec":12,"nanosec":340000000},"door_name":"main \"door\"","current_mode":{"value":2}}}"#
        );
        // Shortest round-trip float: 0.1 + 0.2 prints as 0.30000000000000004 and reads back
        // to the same f64.
        let v: serde_json::Value = serde_json::from_str(lines[1]).unwrap();
        assert_eq!(v["t"].as_f64().unwrap(), 0.1 + 0.2);
        assert!(lines[1].starts_with(r#"{"t":0.30000000000000004,"topic":"/door_states","msg":{"#));
    }

    #[test]
    fn identical_input_gives_identical_bytes() {
        let run = || {
            let mut out = Vec::new();
            for i in 0..100 {
                write(&mut out, &door(i as f64 * 0.01, (i % 3) as u32)).unwrap();
            }
            out
        };
        assert_eq!(run(), run());
    }
}
