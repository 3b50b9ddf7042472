//! Cancelled tasks (`cancel_task_request`): a queued task leaves the queue; a task under
//! way ends where its robot is, which drops its route and takes back what it carries, as
//! after a failure; a task that has not arrived yet is cancelled when it does.

use super::*;

impl Fleets {
    /// Handles the cancels due at `t` (and those waiting for their task to arrive).
    pub(super) fn cancel_due(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        while self.cancels.front().is_some_and(|c| c.0 <= t) {
            if let Some((_, k, id)) = self.cancels.pop_front() {
                self.awaiting_cancel.push((k, id));
            }
        }
        if self.awaiting_cancel.is_empty() {
            return;
        }
        for (k, id) in std::mem::take(&mut self.awaiting_cancel) {
            match self.tasks.iter().position(|tk| tk.id == id) {
                None => self.awaiting_cancel.push((k, id)),
                Some(ti) => self.cancel_results[k] = self.cancel(ti, t, out),
            }
        }
    }

    /// Cancels task `ti` at `t`, or says why it cannot (it has already ended).
    fn cancel(&mut self, ti: usize, t: f64, out: &mut Vec<(Topic, Msg)>) -> Result<(), String> {
        if self.tasks[ti].ended {
            return Err(format!(
                "cancel_task_request for `{}`: the task had already ended",
                self.tasks[ti].id
            ));
        }
        const DETAIL: &str = "cancelled by cancel_task_request";
        if let Some(k) = self.pending.iter().position(|p| p.task == ti) {
            self.pending.remove(k);
            self.tasks[ti].ended = true;
            self.event(t, ti, "cancelled", None, DETAIL.into(), out);
            return Ok(());
        }
        match self.robots.iter().position(|r| r.task == Some(ti)) {
            Some(i) => {
                self.end_task_as(i, t, "cancelled", DETAIL.into(), out);
                Ok(())
            }
            // Every task not ended is queued or with a robot.
            None => Err(format!(
                "cancel_task_request for `{}`: the task is neither queued nor under way",
                self.tasks[ti].id
            )),
        }
    }

    /// Per cancel of the scenario: done, or why not (a task that has not arrived when the
    /// run ends never does).
    pub fn cancel_results(&self) -> Vec<Result<(), String>> {
        let mut out = self.cancel_results.clone();
        for (k, id) in &self.awaiting_cancel {
            out[*k] = Err(format!(
                "cancel_task_request for `{id}`: no task of that id arrived before the run ended"
            ));
        }
        for (_, k, id) in &self.cancels {
            out[*k] = Err(format!(
                "cancel_task_request for `{id}`: the run ended before the cancel arrived"
            ));
        }
        out
    }
}
