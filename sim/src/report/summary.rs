//! The report's human summary (`mapc sim` prints it).

use super::*;

fn hms(t: f64) -> String {
    let s = t.max(0.0).round() as u64;
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, s) => format!("{s}s"),
        (0, m, s) => format!("{m}min {s}s"),
        (h, m, s) => format!("{h}h {m}min {s}s"),
    }
}

impl Report {
    /// A short human-readable summary (a few lines, for the terminal).
    pub fn summary(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let count = |r: &str| self.tasks.iter().filter(|k| k.result == r).count();
        let _ = writeln!(
            s,
            "simulated {} ({:.2} s){}",
            hms(self.end_time),
            self.end_time,
            if self.interrupted {
                ", interrupted"
            } else {
                ""
            }
        );
        let _ = writeln!(
            s,
            "tasks: {} seen, {} completed, {} failed, {} unfinished",
            self.tasks.len(),
            count("completed"),
            count("failed") + count("cancelled"),
            count("unfinished")
        );
        for f in &self.fleets {
            let reserve = if f.reserve > 0 {
                format!(" (+{} in reserve: no home on the floor)", f.reserve)
            } else {
                String::new()
            };
            // Robots idle on average while work waited: the ones the traffic did not take.
            let idle = if self.end_time > 0.0 {
                f.idle_with_work_s / self.end_time
            } else {
                0.0
            };
            let idle = if idle >= 0.05 {
                format!(", {idle:.1} robot(s) idle on average while tasks waited")
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "  fleet {}: {} robot(s){reserve}, {} completed, {} failed, {:.2} tasks/h, utilisation {:.1} %{idle}, {:.1} m driven",
                f.name,
                f.robots,
                f.tasks_completed,
                f.tasks_failed,
                f.throughput_per_hour,
                100.0 * f.utilisation,
                f.distance_m
            );
        }
        if let Some(c) = &self.crowd {
            let _ = writeln!(
                s,
                "crowd: {} people, {:.0} m walked on average at {:.2} m/s, {} near miss(es) and {} contact(s) with robots",
                c.humans, c.walked_m.mean, c.speed_m_s.mean, c.near_misses, c.contacts
            );
            for f in &c.compare {
                let _ = writeln!(
                    s,
                    "  fleet {}: {} task(s) completed ({} without people), mean task {} s ({} s without people)",
                    f.fleet,
                    f.completed,
                    f.completed_without_crowd,
                    f.mean_task_s.map_or("-".into(), |x| format!("{x:.1}")),
                    f.mean_task_s_without_crowd.map_or("-".into(), |x| format!("{x:.1}"))
                );
            }
        }
        let busy_doors: Vec<&DoorReport> =
            self.doors.iter().filter(|d| d.open_requests > 0).collect();
        let _ = writeln!(
            s,
            "doors: {} open request(s) at {} of {} door(s)",
            busy_doors.iter().map(|d| d.open_requests).sum::<usize>(),
            busy_doors.len(),
            self.doors.len()
        );
        for d in busy_doors {
            let _ = writeln!(
                s,
                "  door {}: {} request(s), wait mean {:.1} s, max {:.1} s, open {:.0} %{}",
                d.name,
                d.open_requests,
                d.wait.mean_s,
                d.wait.max_s,
                100.0 * d.utilisation,
                unserved(d.wait.unserved)
            );
        }
        for l in self.lifts.iter().filter(|l| l.sessions > 0 || l.trips > 0) {
            let _ = writeln!(
                s,
                "  lift {}: {} session(s), {} trip(s), wait mean {:.1} s, max {:.1} s, busy {:.0} %{}",
                l.name,
                l.sessions,
                l.trips,
                l.wait.mean_s,
                l.wait.max_s,
                100.0 * l.utilisation,
                unserved(l.wait.unserved)
            );
        }
        let w = &self.waits;
        let _ = writeln!(
            s,
            "task waits: traffic {}, lift {}, door {}, workcell {}, charging {}",
            hms(w.traffic_s),
            hms(w.lift_s),
            hms(w.door_s),
            hms(w.workcell_s),
            hms(w.charging_s)
        );
        if let Some(b) = &self.bottleneck {
            let _ = writeln!(
                s,
                "bottleneck: {} ({} of waiting there, {:.0} % of all task waits)",
                b.place,
                hms(b.wait_s),
                100.0 * b.share
            );
        }
        if let Some(b) = &self.throughput {
            let _ = write!(
                s,
                "throughput bound: {:.1} tasks/h, set by {}",
                b.tasks_per_hour, b.limited_by
            );
            if let Some(r) = b.resources.iter().find(|r| r.resource == b.limited_by) {
                let _ = write!(
                    s,
                    " ({} × 3600 s / {:.1} s a task at least)",
                    r.capacity, r.demand_s
                );
            }
            let _ = writeln!(
                s,
                "; this run {:.1} tasks/h ({:.0} % of it)",
                b.achieved_per_hour,
                100.0 * b.share
            );
        }
        let closest = self
            .near_misses
            .iter()
            .chain(&self.contacts)
            .min_by(|a, b| a.min_distance_m.total_cmp(&b.min_distance_m));
        let _ = write!(
            s,
            "near misses: {}, contacts: {}",
            self.near_misses.len(),
            self.contacts.len()
        );
        if let Some(c) = closest {
            let _ = write!(
                s,
                " (closest {:.2} m: {} and {} at {})",
                c.min_distance_m,
                c.robots[0],
                c.robots[1],
                hms(c.t)
            );
        }
        let _ = writeln!(s);
        // Resolved: the robot moved on (or the events stopped) well before the end.
        let unresolved = self
            .stuck
            .iter()
            .filter(|k| k.until >= self.end_time - STUCK_AFTER)
            .count();
        let _ = writeln!(
            s,
            "stuck episodes: {} ({} resolved, {unresolved} unresolved at the end)",
            self.stuck.len(),
            self.stuck.len() - unresolved
        );
        const SHOWN: usize = 10;
        for k in self.stuck.iter().take(SHOWN) {
            let _ = writeln!(
                s,
                "  {} {}..{}: {} ({})",
                k.robot,
                hms(k.t),
                hms(k.until),
                k.reason,
                k.detail
            );
        }
        if self.stuck.len() > SHOWN {
            let _ = writeln!(s, "  ... {} more in the report", self.stuck.len() - SHOWN);
        }
        s
    }
}

fn unserved(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(", {n} unserved")
    }
}
