//! Cancelled tasks (`cancel_task_request`): a queued task leaves the queue; a task under
//! way ends where its robot is, which drops its route and takes back what it carries, as
//! after a failure; a task that has not arrived yet is cancelled when it does.

use super::*;

/// The scenario's cancels, as time brings them.
///
/// Invariant: every cancel of the scenario is in exactly one place: still to come
/// (`upcoming`, by time), due but waiting for its task to arrive (`awaiting`), or done
/// with its result in `results`. A cancel is due once; one waiting for its task is
/// tried again at every update until the task arrives. Guarantees a result per cancel
/// ([`Cancels::results`]).
pub(super) struct Cancels {
    /// Cancels still to come: (time, index in the scenario's cancels, task id), by time.
    upcoming: VecDeque<(f64, usize, String)>,
    /// Cancels due whose task has not arrived yet.
    awaiting: Vec<(usize, String)>,
    /// Per cancel of the scenario: done, or why not.
    results: Vec<Result<(), String>>,
}

impl Cancels {
    /// The scenario's cancels, none due yet.
    pub(super) fn new(scenario: &Scenario) -> Cancels {
        let mut upcoming: Vec<(f64, usize, String)> = scenario
            .cancels
            .iter()
            .enumerate()
            .map(|(k, c)| (c.at, k, c.task_id.clone()))
            .collect();
        upcoming.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        Cancels {
            upcoming: upcoming.into(),
            awaiting: Vec::new(),
            results: vec![Err(String::new()); scenario.cancels.len()],
        }
    }

    /// The cancels due at `t` and those still waiting for their task, in that order
    /// (taken: each is put back with [`Cancels::wait`] or ended with [`Cancels::done`]).
    fn take_due(&mut self, t: f64) -> Vec<(usize, String)> {
        while self.upcoming.front().is_some_and(|c| c.0 <= t) {
            if let Some((_, k, id)) = self.upcoming.pop_front() {
                self.awaiting.push((k, id));
            }
        }
        std::mem::take(&mut self.awaiting)
    }

    /// Cancel `k` waits for its task to arrive.
    fn wait(&mut self, k: usize, id: String) {
        self.awaiting.push((k, id));
    }

    /// Cancel `k` was handled: done, or why not.
    fn done(&mut self, k: usize, result: Result<(), String>) {
        self.results[k] = result;
    }

    /// When the next cancel comes.
    pub(super) fn next_at(&self) -> Option<f64> {
        self.upcoming.front().map(|c| c.0)
    }

    /// Per cancel of the scenario: done, or why not (a task that has not arrived when the
    /// run ends never does).
    fn results(&self) -> Vec<Result<(), String>> {
        let mut out = self.results.clone();
        for (k, id) in &self.awaiting {
            out[*k] = Err(format!(
                "cancel_task_request for `{id}`: no task of that id arrived before the run ended"
            ));
        }
        for (_, k, id) in &self.upcoming {
            out[*k] = Err(format!(
                "cancel_task_request for `{id}`: the run ended before the cancel arrived"
            ));
        }
        out
    }
}

impl Fleets {
    /// Handles the cancels due at `t` (and those waiting for their task to arrive).
    pub(super) fn cancel_due(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        let due = self.cancels.take_due(t);
        if due.is_empty() {
            return;
        }
        for (k, id) in due {
            match self.floor.tasks.iter().position(|tk| tk.id == id) {
                None => self.cancels.wait(k, id),
                Some(ti) => {
                    let result = self.cancel(ti, t, out);
                    self.cancels.done(k, result);
                }
            }
        }
    }

    /// Cancels task `ti` at `t`, or says why it cannot (it has already ended).
    fn cancel(&mut self, ti: usize, t: f64, out: &mut Vec<(Topic, Msg)>) -> Result<(), String> {
        if self.floor.tasks[ti].ended {
            return Err(format!(
                "cancel_task_request for `{}`: the task had already ended",
                self.floor.tasks[ti].id
            ));
        }
        const DETAIL: &str = "cancelled by cancel_task_request";
        if self.dispatcher.withdraw(ti) {
            self.floor.tasks[ti].ended = true;
            self.floor
                .event(t, ti, "cancelled", None, DETAIL.into(), out);
            return Ok(());
        }
        match self.floor.robots.iter().position(|r| r.task == Some(ti)) {
            Some(i) => {
                self.floor
                    .end_task_as(i, t, "cancelled", DETAIL.into(), out);
                Ok(())
            }
            // Every task not ended is queued or with a robot.
            None => Err(format!(
                "cancel_task_request for `{}`: the task is neither queued nor under way",
                self.floor.tasks[ti].id
            )),
        }
    }

    /// Per cancel of the scenario: done, or why not (a task that has not arrived when the
    /// run ends never does).
    pub fn cancel_results(&self) -> Vec<Result<(), String>> {
        self.cancels.results()
    }
}
