//! `faults:` entries: a robot, a door or a lift out of service for a while ("what if the
//! lift stops for ten minutes?"). The world applies them (`crate::world`): a paused robot
//! stops where it is, a door or a lift answers no request and stays as it is.

use super::{codes, P};
use mapc_frontend::yaml_tree::Node;
use mapc_ir::Span;

pub(super) const FAULT_KEYS: &[&str] = &["at", "for", "robot", "door", "lift"];

/// One thing out of service from `at` for `duration` seconds.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultSpec {
    pub at: f64,
    pub duration: f64,
    pub target: FaultTarget,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum FaultTarget {
    /// Paused where it is (as a pause request would); it goes on afterwards.
    Robot(String),
    /// Answers no open or close request; stays as it is.
    Door(String),
    /// Answers no request (it finishes a ride under way); stays at its floor.
    Lift(String),
}

impl FaultTarget {
    pub fn name(&self) -> &str {
        match self {
            FaultTarget::Robot(n) | FaultTarget::Door(n) | FaultTarget::Lift(n) => n,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            FaultTarget::Robot(_) => "robot",
            FaultTarget::Door(_) => "door",
            FaultTarget::Lift(_) => "lift",
        }
    }
}

impl P<'_> {
    pub(super) fn fault(&mut self, v: &Node, duration: Option<f64>) -> Option<FaultSpec> {
        let e = self.entries(v, "a fault", Some((FAULT_KEYS, codes::UNKNOWN_KEY)))?;
        let at = match e.get("at") {
            None => Some(0.0),
            Some(a) => self.duration(a, "`at`"),
        };
        let length = self.required(&e, "for", "a fault").and_then(|n| {
            self.duration(n, "`for`")
                .and_then(|x| self.positive(n, x, "`for`"))
        });
        let mut targets = Vec::new();
        for key in ["robot", "door", "lift"] {
            if let Some(n) = e.get(key) {
                targets.push((key, n));
            }
        }
        let target = match targets.as_slice() {
            [(key, n)] => self.name(n, &format!("`{key}`")).map(|name| match *key {
                "robot" => FaultTarget::Robot(name),
                "door" => FaultTarget::Door(name),
                _ => FaultTarget::Lift(name),
            }),
            [] => {
                self.error(
                    codes::FAULT_TARGET,
                    v.span,
                    "the fault names no `robot`, `door` or `lift`",
                );
                self.help("add one of `robot: <name>`, `door: <name>`, `lift: <name>`");
                None
            }
            _ => {
                self.error(
                    codes::FAULT_TARGET,
                    v.span,
                    "the fault names more than one of `robot`, `door` and `lift`",
                );
                self.help("write one fault for each thing out of service");
                None
            }
        };
        if let (Some(a), Some(d), Some(n)) = (at, duration, e.get("at")) {
            if a >= d {
                self.warning(
                    codes::TASK_AFTER_END,
                    n.span,
                    format!("the fault starts at {a} s, at or after the end of the run ({d} s)"),
                );
                self.help("start it earlier or lengthen `duration`; it changes nothing");
            }
        }
        Some(FaultSpec {
            at: at?,
            duration: length?,
            target: target?,
            span: v.span,
        })
    }
}
