//! Tasks and task generators: the kinds (`loop`, `delivery`, `clean`, `go_to_place`) and the
//! fleet a task names.

use super::*;

impl P<'_> {
    /// The task kind among a task's or generator's keys (`plain` are the other known keys).
    pub(super) fn kind(&mut self, e: &Entries, plain: &[&str], what: &str) -> Option<TaskKind> {
        let kinds: Vec<_> = e.items.iter().filter(|i| KINDS.contains(&i.0)).collect();
        let others: Vec<_> = e
            .items
            .iter()
            .filter(|i| !KINDS.contains(&i.0) && !plain.contains(&i.0))
            .collect();
        for (n, (key, k, _)) in others.iter().enumerate() {
            if n == 0 && kinds.is_empty() {
                self.error(
                    codes::UNKNOWN_TASK_KIND,
                    k.span,
                    format!("`{key}` is not a task kind"),
                );
                let hint = closest(key, KINDS.iter().copied())
                    .map(|c| format!("did you mean `{c}`? "))
                    .unwrap_or_default();
                self.help(format!("{hint}kinds: {}", list(KINDS)));
            } else {
                self.warning(
                    codes::UNKNOWN_KEY,
                    k.span,
                    format!("unknown key `{key}` in {what}; it is ignored"),
                );
                let mut known: Vec<&str> = plain.to_vec();
                known.extend(KINDS);
                if let Some(c) = closest(key, known.iter().copied()) {
                    self.help(format!("did you mean `{c}`?"));
                }
            }
        }
        match kinds.as_slice() {
            [] => {
                if others.is_empty() {
                    self.error(codes::MISSING_KEY, e.span, format!("{what} has no kind"));
                    self.help(format!("add one of {}", list(KINDS)));
                }
                None
            }
            [(key, _, v)] => self.kind_body(key, v),
            [_, (key, k, _), ..] => {
                self.error(
                    codes::SEVERAL_TASK_KINDS,
                    k.span,
                    format!("{what} has more than one kind (`{key}` is the second)"),
                );
                self.help("one request is one task; split it into several tasks");
                None
            }
        }
    }

    pub(super) fn kind_body(&mut self, key: &str, v: &Node) -> Option<TaskKind> {
        // `go_to_place: lobby` and `clean: zone_1` are short forms.
        if v.as_map().is_none() && matches!(key, "go_to_place" | "clean") {
            let n = self.name(v, &format!("`{key}`"))?;
            return Some(if key == "clean" {
                TaskKind::Clean { zone: n }
            } else {
                TaskKind::GoToPlace { place: n }
            });
        }
        let what = format!("`{key}`");
        let fields: &[&str] = match key {
            "loop" => &["start", "finish", "loops"],
            "delivery" => &["pickup", "dropoff", "dispenser", "ingestor"],
            "clean" => &["zone"],
            _ => &["place"],
        };
        let e = self.entries(v, &what, Some((fields, codes::UNKNOWN_KEY)))?;
        let req = |p: &mut Self, f: &str| {
            p.required(&e, f, &what)
                .and_then(|n| p.name(n, &format!("`{key}.{f}`")))
        };
        Some(match key {
            "loop" => {
                let start = req(self, "start");
                let finish = req(self, "finish");
                let loops = match e.get("loops") {
                    None => Some(1),
                    Some(n) => self.int(n, "`loops`").and_then(|i| {
                        if i <= 0 {
                            self.error(
                                codes::NOT_POSITIVE,
                                n.span,
                                "`loops` must be greater than 0",
                            );
                            None
                        } else if i as f64 > MAX_TASKS {
                            self.error(
                                codes::TOO_LARGE,
                                n.span,
                                format!("`loops` must be at most {MAX_TASKS}"),
                            );
                            None
                        } else {
                            Some(i as u32)
                        }
                    }),
                };
                TaskKind::Loop {
                    start: start?,
                    finish: finish?,
                    loops: loops?,
                }
            }
            "delivery" => {
                let pickup = req(self, "pickup");
                let dropoff = req(self, "dropoff");
                let opt = |p: &mut Self, f: &str| match e.get(f) {
                    None => Some(None),
                    Some(n) => p.name(n, &format!("`delivery.{f}`")).map(Some),
                };
                let dispenser = opt(self, "dispenser");
                let ingestor = opt(self, "ingestor");
                TaskKind::Delivery {
                    pickup: pickup?,
                    dropoff: dropoff?,
                    dispenser: dispenser?,
                    ingestor: ingestor?,
                }
            }
            "clean" => TaskKind::Clean {
                zone: req(self, "zone")?,
            },
            _ => TaskKind::GoToPlace {
                place: req(self, "place")?,
            },
        })
    }

    pub(super) fn fleet_ref(&mut self, e: &Entries) -> Option<Option<String>> {
        match e.get("fleet") {
            None => Some(None),
            Some(f) if f.is_null() => Some(None),
            Some(f) => self.name(f, "`fleet`").map(Some),
        }
    }

    pub(super) fn task(&mut self, v: &Node, duration: Option<f64>) -> Option<TaskSpec> {
        let e = self.entries(v, "a task", None)?;
        let at = match e.get("at") {
            None => Some(0.0),
            Some(a) => self.duration(a, "`at`"),
        };
        let kind = self.kind(&e, TASK_KEYS, "a task");
        let fleet = self.fleet_ref(&e);
        if let (Some(a), Some(d), Some(n)) = (at, duration, e.get("at")) {
            if a >= d {
                self.warning(
                    codes::TASK_AFTER_END,
                    n.span,
                    format!(
                        "the task is requested at {a} s, at or after the end of the run ({d} s)"
                    ),
                );
                self.help("request it earlier or lengthen `duration`; it is never requested");
            }
        }
        Some(TaskSpec {
            at: at?,
            kind: kind?,
            fleet: fleet?,
            robot: None,
            priority: 0,
            span: v.span,
        })
    }

    pub(super) fn generator(&mut self, v: &Node, duration: Option<f64>) -> Option<GeneratorSpec> {
        let e = self.entries(v, "a generator", None)?;
        let every = self.required(&e, "every", "a generator").and_then(|n| {
            self.duration(n, "`every`")
                .and_then(|x| self.positive(n, x, "`every`"))
        });
        let start = match e.get("start") {
            None => Some(0.0),
            Some(n) => self.duration(n, "`start`"),
        };
        let end = match e.get("end") {
            None => Some(None),
            Some(n) if n.is_null() => Some(None),
            Some(n) => self.duration(n, "`end`").map(Some),
        };
        if let (Some(s), Some(Some(en)), Some(n)) = (start, end, e.get("end")) {
            if en < s {
                self.error(
                    codes::OUT_OF_RANGE,
                    n.span,
                    format!("`end` ({en} s) comes before `start` ({s} s)"),
                );
                return None;
            }
        }
        if let (Some(s), Some(d)) = (start, duration) {
            if s >= d {
                self.warning(
                    codes::TASK_AFTER_END,
                    e.get("start").map_or(v.span, |n| n.span),
                    format!(
                        "the generator starts at {s} s, at or after the end of the run ({d} s)"
                    ),
                );
                self.help("start it earlier or lengthen `duration`; it generates nothing");
            }
        }
        let kind = self.kind(&e, GENERATOR_KEYS, "a generator");
        let fleet = self.fleet_ref(&e);
        Some(GeneratorSpec {
            every: every?,
            start: start?,
            end: end?,
            kind: kind?,
            fleet: fleet?,
            span: v.span,
        })
    }
}
