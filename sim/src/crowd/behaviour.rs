//! The people's behaviour: Menge's finite state machine as the editor writes it
//! (runtime.md §6.3), compiled from `crowd_sim` with names resolved to indices. States pick
//! a goal from their goal set (weighted, weight 1 per goal, goals that still have capacity
//! first); transitions are evaluated in file order, the first satisfied wins, and their
//! weighted targets are drawn with the crowd's own seeded RNG.

use mapc_ir::{Building, Condition, CrowdSim, TimerDuration, Vec2};

pub(crate) enum Cond {
    GoalReached(f64),
    Timer(usize),
    Auto,
    And(Box<Cond>, Box<Cond>),
    Or(Box<Cond>, Box<Cond>),
    Not(Box<Cond>),
    Never,
}

pub(crate) struct Trans {
    pub cond: Cond,
    /// Next states with their weights (one with weight 1 for a plain `to`).
    pub targets: Vec<(usize, f64)>,
}

pub(crate) struct State {
    #[cfg_attr(not(test), allow(dead_code))] // tests find states by name
    pub name: String,
    pub is_final: bool,
    /// Goal indices of the state's goal set (empty: stay where you are).
    pub goals: Vec<usize>,
    pub trans: Vec<Trans>,
    /// Timers of the outgoing transitions, drawn on entry.
    pub timers: Vec<usize>,
}

pub(crate) struct Goal {
    /// Map frame.
    pub pos: Vec2,
    pub capacity: i64,
    pub population: i64,
}

pub(crate) struct Timer {
    pub duration: TimerDuration,
    pub per_agent: bool,
    /// The one duration all agents share when not per agent.
    pub shared: f64,
}

pub(crate) struct Fsm {
    pub states: Vec<State>,
    pub goals: Vec<Goal>,
    pub timers: Vec<Timer>,
}

/// Where an agent is in the machine.
#[derive(Debug, Clone, Default)]
pub(crate) struct Mind {
    pub state: usize,
    pub goal: Option<usize>,
    pub entered: f64,
    /// Fire time of each timer of the current state (by position in `State::timers`).
    pub fire_at: Vec<f64>,
}

fn draw(d: TimerDuration, rng: &mut fastrand::Rng) -> f64 {
    match d {
        TimerDuration::Const(v) => v,
        TimerDuration::Uniform { min, max } => {
            let (lo, hi) = if min <= max { (min, max) } else { (max, min) };
            lo + (hi - lo) * rng.f64()
        }
    }
}

impl Fsm {
    pub fn new(b: &Building, c: &CrowdSim, rng: &mut fastrand::Rng) -> Fsm {
        let mut goals = Vec::new();
        let mut set_goals: Vec<(i64, Vec<usize>)> = Vec::new();
        for gs in &c.goal_sets {
            let mut list = Vec::new();
            // Vertex order, as the behaviour file lists them.
            for area in &gs.set_area {
                for (_, lvl) in b.levels.iter() {
                    for &vh in &lvl.vertices {
                        let v = &b.vertices[vh];
                        if v.roles.human_goal_set_name.as_deref() == Some(area.as_str()) {
                            list.push(goals.len());
                            goals.push(Goal {
                                pos: v.pos,
                                capacity: gs.capacity,
                                population: 0,
                            });
                        }
                    }
                }
            }
            set_goals.push((gs.set_id, list));
        }
        let index = |name: &str| c.states.iter().position(|s| s.name == name);
        let mut timers = Vec::new();
        let mut states: Vec<State> = c
            .states
            .iter()
            .map(|s| State {
                name: s.name.clone(),
                is_final: s.is_final,
                goals: set_goals
                    .iter()
                    .find(|(id, _)| *id == s.goal_set && s.goal_set >= 0)
                    .map(|(_, l)| l.clone())
                    .unwrap_or_default(),
                trans: Vec::new(),
                timers: Vec::new(),
            })
            .collect();
        for t in &c.transitions {
            let Some(from) = index(&t.from) else { continue };
            let targets: Vec<(usize, f64)> = if t.targets.is_empty() {
                index(&t.to).map(|s| vec![(s, 1.0)]).unwrap_or_default()
            } else {
                t.targets
                    .iter()
                    .filter_map(|(n, w, _)| {
                        index(n)
                            .filter(|_| w.is_finite() && *w > 0.0)
                            .map(|s| (s, *w))
                    })
                    .collect()
            };
            if targets.is_empty() {
                continue;
            }
            let mut used = Vec::new();
            let cond = t
                .condition
                .as_ref()
                .map_or(Cond::Never, |c| compile(c, &mut timers, &mut used, rng));
            states[from].timers.extend(used);
            states[from].trans.push(Trans { cond, targets });
        }
        Fsm {
            states,
            goals,
            timers,
        }
    }

    /// Enters `state` at `t`: releases the old goal, picks a new one, draws the timers.
    pub fn enter(&mut self, m: &mut Mind, state: usize, t: f64, rng: &mut fastrand::Rng) {
        if let Some(g) = m.goal.take() {
            self.goals[g].population -= 1;
        }
        m.state = state;
        m.entered = t;
        let s = &self.states[state];
        m.fire_at = s
            .timers
            .iter()
            .map(|&k| {
                let tm = &self.timers[k];
                t + if tm.per_agent {
                    draw(tm.duration, rng)
                } else {
                    tm.shared
                }
            })
            .collect();
        if s.goals.is_empty() {
            return;
        }
        // Goals with room first; when every goal is full, any goal (Menge would fail).
        let free: Vec<usize> = s
            .goals
            .iter()
            .copied()
            .filter(|&g| self.goals[g].population < self.goals[g].capacity)
            .collect();
        let pool = if free.is_empty() { &s.goals } else { &free };
        let g = pool[rng.usize(..pool.len())];
        self.goals[g].population += 1;
        m.goal = Some(g);
    }

    /// The state to move to, if a transition of the current state fires.
    pub fn next(&self, m: &Mind, t: f64, goal_dist: f64, rng: &mut fastrand::Rng) -> Option<usize> {
        let s = &self.states[m.state];
        for tr in &s.trans {
            if self.holds(&tr.cond, s, m, t, goal_dist) {
                let total: f64 = tr.targets.iter().map(|x| x.1).sum();
                let mut x = rng.f64() * total;
                for &(st, w) in &tr.targets {
                    if x < w {
                        return Some(st);
                    }
                    x -= w;
                }
                return tr.targets.last().map(|x| x.0);
            }
        }
        None
    }

    fn holds(&self, c: &Cond, s: &State, m: &Mind, t: f64, goal_dist: f64) -> bool {
        match c {
            Cond::GoalReached(d) => m.goal.is_some() && goal_dist <= *d,
            Cond::Timer(k) => s
                .timers
                .iter()
                .position(|x| x == k)
                .and_then(|i| m.fire_at.get(i))
                .is_some_and(|&f| t >= f),
            Cond::Auto => true,
            Cond::And(a, b) => {
                self.holds(a, s, m, t, goal_dist) && self.holds(b, s, m, t, goal_dist)
            }
            Cond::Or(a, b) => {
                self.holds(a, s, m, t, goal_dist) || self.holds(b, s, m, t, goal_dist)
            }
            Cond::Not(a) => !self.holds(a, s, m, t, goal_dist),
            Cond::Never => false,
        }
    }
}

fn compile(
    c: &Condition,
    timers: &mut Vec<Timer>,
    used: &mut Vec<usize>,
    rng: &mut fastrand::Rng,
) -> Cond {
    let mut sub = |c: &Condition| Box::new(compile(c, timers, used, rng));
    match c {
        Condition::GoalReached { distance } => Cond::GoalReached(*distance),
        Condition::Timer(t) => {
            let k = timers.len();
            timers.push(Timer {
                duration: t.duration,
                per_agent: t.per_agent,
                shared: draw(t.duration, rng),
            });
            used.push(k);
            Cond::Timer(k)
        }
        Condition::Auto => Cond::Auto,
        Condition::And(a, b) => {
            let a = sub(a);
            Cond::And(a, sub(b))
        }
        Condition::Or(a, b) => {
            let a = sub(a);
            Cond::Or(a, sub(b))
        }
        Condition::Not(a) => Cond::Not(sub(a)),
        Condition::Other(_) => Cond::Never,
    }
}
