//! The schedule: order kept per resource, grants in that order, retiming, releases.

use super::*;
use crate::traffic::test_map::{conflicts, e, nav, v};

fn step(nav: &crate::graph::Nav, edge: usize, start: f64, dur: f64) -> Step {
    Step {
        edge,
        from: nav.edges[edge].from,
        to: nav.edges[edge].to,
        dur,
        hold: 0.0,
        start,
        end: start + dur,
    }
}

/// Robot 0 at a drives a→b→p1 over [0, 20); robot 1 at p2 drives p2→c→b→a after it.
fn two_robots() -> (crate::graph::Nav, Schedule) {
    let nav = nav();
    let mut s = standing(&nav);
    plan_two(&nav, &mut s, 0);
    plan_two(&nav, &mut s, 1);
    (nav, s)
}

/// Robots 0 and 1 standing at a and p2.
fn standing(nav: &crate::graph::Nav) -> Schedule {
    Schedule::new(conflicts(nav), &[v(nav, "a"), v(nav, "p2")], 0.0)
}

/// Installs robot `r`'s plan of [`two_robots`].
fn plan_two(nav: &crate::graph::Nav, s: &mut Schedule, r: usize) {
    let steps = if r == 0 {
        vec![
            step(nav, e(nav, "a", "b"), 0.0, 10.0),
            step(nav, e(nav, "b", "p1"), 10.0, 10.0),
        ]
    } else {
        vec![
            step(nav, e(nav, "p2", "c"), 0.0, 5.0),
            step(nav, e(nav, "c", "b"), 30.0, 10.0),
            step(nav, e(nav, "b", "a"), 40.0, 10.0),
        ]
    };
    s.install(r, 0, &steps, 0.0, None);
}

#[test]
fn grants_follow_the_planned_order() {
    let (_, mut s) = two_robots();
    assert!(s.check(0.0).is_ok(), "{:?}", s.check(0.0));
    assert!(s.granted(0, 0));
    // Robot 1's p2→c is 4 m from anything robot 0 drives: it goes at once (lanes conflict
    // only with the lanes near them, not with those near a lane near them).
    assert!(s.granted(1, 0));
    s.begin(1, 1, 0.0);
    s.complete_front(1, 5.0);
    // Its c→b needs b, which robot 0 passes first: it waits for it.
    assert!(!s.granted(1, 0));
    assert_eq!(s.waits_for(1, 0), vec![0]);
    s.begin(0, 1, 0.0);
    s.complete_front(0, 12.0);
    assert!(!s.granted(1, 0), "robot 0 still at b");
    s.begin(0, 1, 12.0);
    s.complete_front(0, 23.0);
    assert!(s.granted(1, 0), "free once robot 0 is in p1");
    assert_eq!(s.end_vertex(0), s.itinerary(0).at);
}

#[test]
fn retiming_pushes_the_later_robot_back_by_the_delay() {
    let (nav, mut s) = two_robots();
    // Robot 0 begins a→b at 0 but is still on it at 25 s (10 s planned): its b→p1 starts
    // at 25 at the earliest, ends at 35; robot 1's c→b needs b: starts at 35, not 30.
    s.begin(0, 1, 0.0);
    s.retime(25.0).expect("acyclic");
    let it0 = s.itinerary(0);
    assert_eq!((it0.travs[0].start, it0.travs[0].end), (0.0, 25.0));
    assert_eq!((it0.travs[1].start, it0.travs[1].end), (25.0, 35.0));
    // Robot 1: p2→c depends on nobody (from now: 25-30), c→b waits for b (from 35 and
    // the headway on, for 10 s), then b→a (10 s).
    let it1 = s.itinerary(1);
    let times: Vec<(f64, f64)> = it1.travs.iter().map(|t| (t.start, t.end)).collect();
    let h = super::retime::HEADWAY;
    assert_eq!(
        times,
        [
            (25.0, 30.0),
            (35.0 + h, 35.0 + h + 10.0),
            (35.0 + h + 10.0, 35.0 + h + 20.0)
        ]
    );
    let _ = nav;
}

#[test]
fn replanning_drops_the_old_spans_and_keeps_the_standing_set() {
    let (nav, mut s) = two_robots();
    // Robot 1 gives up its plan before starting: it stays at p2 for good.
    s.install(1, 0, &[], 0.0, None);
    assert!(s.check(0.0).is_ok());
    assert!(s.itinerary(1).travs.is_empty());
    // Nobody else holds b's resources now, and p2's are robot 1's for good.
    for &x in &s.conf().vertex[v(&nav, "b")] {
        assert_eq!(s.busy(x, 0, false).count(), 0);
    }
    for &x in &s.conf().vertex[v(&nav, "p2")] {
        assert_eq!(
            s.busy(x, 0, false).collect::<Vec<_>>(),
            vec![(f64::NEG_INFINITY, f64::INFINITY)]
        );
    }
}

#[test]
fn a_broken_order_is_reported_as_a_cycle() {
    let (nav, mut s) = two_robots();
    // On b, robot 1 now comes first (its c→b..b→a span) while on the lane a-b robot 0
    // (a→b) still comes before robot 1's b→a: each waits for the other.
    let x = s.conf().vertex[v(&nav, "b")][0] as usize;
    s.queues[x].swap(0, 1);
    let err = s.check(0.0).expect_err("a cycle");
    assert!(err.contains("cycle"), "{err}");
    assert!(s.clone().retime(0.0).is_err());
}

#[test]
fn a_robot_that_sets_off_early_makes_the_estimates_stale_until_retimed() {
    let nav = nav();
    let conf = conflicts(&nav);
    let mut s = Schedule::new(conf, &[v(&nav, "a"), v(&nav, "d")], 0.0);
    s.retime(0.0).expect("acyclic");
    assert!(!s.stale());
    // Robot 0 was planned to drive a→b→p1 from 100 s, but it is granted now and sets off
    // at once (execution keeps the order, not the times).
    s.install(
        0,
        0,
        &[
            step(&nav, e(&nav, "a", "b"), 100.0, 10.0),
            step(&nav, e(&nav, "b", "p1"), 110.0, 10.0),
        ],
        0.0,
        None,
    );
    assert!(!s.stale(), "a plan alone changes no estimate");
    assert!(s.granted(0, 0));
    s.begin(0, 1, 0.0);
    // Its spans still say 100 s: a plan made now would fit another robot through b
    // before it. The schedule says so, and retiming puts b's spans at now.
    assert!(s.stale());
    let b = v(&nav, "b");
    let first_busy = |s: &Schedule| {
        s.conf().vertex[b]
            .iter()
            .flat_map(|&x| s.busy(x, 1, false).map(|(a, _)| a).collect::<Vec<_>>())
            .fold(f64::INFINITY, f64::min)
    };
    assert_eq!(first_busy(&s), 100.0);
    s.retime(0.0).expect("acyclic");
    assert!(!s.stale());
    assert_eq!(first_busy(&s), 0.0);
    let it0 = s.itinerary(0);
    assert_eq!((it0.travs[1].start, it0.travs[1].end), (10.0, 20.0));
}

#[test]
fn a_span_whose_first_traversal_is_done_is_busy_from_now() {
    // Robot 0 planned to leave a at 50 s, goes early (granted at once) and is past b's first
    // traversal by 11 s: the spans it holds at b are busy from now to the end of b→p1, not
    // from the old estimate of 50 s (which once hid them from the planner: a plan through
    // them was put after them in one queue and before them in another, a cycle).
    let nav = nav();
    let conf = conflicts(&nav);
    let b = v(&nav, "b");
    let at_b = conf.vertex[b].clone();
    let mut s = Schedule::new(conf, &[v(&nav, "a"), v(&nav, "p2")], 0.0);
    s.install(
        0,
        0,
        &[
            step(&nav, e(&nav, "a", "b"), 50.0, 10.0),
            step(&nav, e(&nav, "b", "p1"), 60.0, 10.0),
        ],
        50.0,
        None,
    );
    s.retime(0.0).expect("acyclic");
    s.begin(0, 1, 1.0);
    s.complete_front(0, 11.0);
    s.retime(11.0).expect("acyclic");
    let mut seen = 0;
    for &x in &at_b {
        for (start, end) in s.busy(x, 1, false) {
            seen += 1;
            assert!(start <= 11.0 && start <= end, "busy [{start}, {end}) at b");
        }
    }
    assert!(seen > 0, "robot 0 holds b's resources");
}

/// Robot 0 at a on its way to e, sent along a→b, then along b→c and c→d together
/// (granted: a moving robot drives on without asking again), and at b after 2 s instead of
/// the estimated 10.
fn sent_together_and_early(nav: &crate::graph::Nav) -> Schedule {
    let conf = conflicts(nav);
    let mut s = Schedule::new(conf, &[v(nav, "a"), v(nav, "p2")], 0.0);
    s.install(
        0,
        0,
        &[
            step(nav, e(nav, "a", "b"), 0.0, 10.0),
            step(nav, e(nav, "b", "c"), 10.0, 10.0),
            step(nav, e(nav, "c", "d"), 20.0, 10.0),
            step(nav, e(nav, "d", "e"), 30.0, 10.0),
        ],
        0.0,
        None,
    );
    s.begin(0, 1, 0.0);
    assert!(s.granted(0, 1) && s.granted(0, 2));
    s.begin(0, 3, 0.0);
    s.complete_front(0, 2.0);
    s
}

#[test]
fn traversals_sent_together_are_held_and_busy_from_now() {
    let nav = nav();
    let mut s = sent_together_and_early(&nav);
    s.retime(2.0).expect("acyclic");
    // Robot 0 drives b→c now and c→d straight after: the estimates of when it was sent
    // (10-20, 20-30) no longer hold.
    let it0 = s.itinerary(0);
    let times: Vec<(f64, f64)> = it0.travs.iter().map(|t| (t.start, t.end)).collect();
    assert_eq!(times, [(2.0, 12.0), (12.0, 22.0), (22.0, 32.0)]);
    // Every resource of either traversal is busy for others from now: they are robot
    // 0's, whatever the estimates (once, a plan fitted before c→d's old estimate).
    for tr in it0.travs.iter().take(2) {
        for &x in &s.conf().trav[tr.edge] {
            for (start, _) in s.busy(x, 1, false) {
                assert!(start <= 2.0, "resource {x} busy from {start}");
            }
        }
    }
}

#[test]
fn a_plan_never_goes_before_traversals_sent_together() {
    let nav = nav();
    let mut s = sent_together_and_early(&nav);
    // Robot 1 at p2 to d and back, timed as if robot 0 were still due at c at 10 and at
    // d at 20 (the estimates of when it was sent). On c, robot 0 (driving b→c) holds it;
    // on what only c→d needs, robot 1 must not go first either: robot 0 was sent along
    // c→d. Once that put robot 1 after robot 0 on c and before it on d: a cycle (seen
    // with 1,000 robots in a warehouse).
    s.install(
        1,
        0,
        &[
            step(&nav, e(&nav, "p2", "c"), 2.0, 3.0),
            step(&nav, e(&nav, "c", "d"), 5.0, 4.0),
            step(&nav, e(&nav, "d", "c"), 9.0, 4.0),
            step(&nav, e(&nav, "c", "p2"), 13.0, 3.0),
        ],
        2.0,
        None,
    );
    s.check(2.0).expect("acyclic");
}

/// Robot 0 at a goes to its last place b, then (soft) b→c→p2 to park over [10, 30).
fn with_a_soft_way_to_parking(nav: &crate::graph::Nav, starts: &[&str]) -> Schedule {
    let conf = conflicts(nav);
    let starts: Vec<usize> = starts.iter().map(|n| v(nav, n)).collect();
    let mut s = Schedule::new(conf, &starts, 0.0);
    let jumped = s.install(
        0,
        0,
        &[
            step(nav, e(nav, "a", "b"), 0.0, 10.0),
            step(nav, e(nav, "b", "c"), 10.0, 10.0),
            step(nav, e(nav, "c", "p2"), 20.0, 10.0),
        ],
        0.0,
        Some(1),
    );
    assert!(jumped.is_empty());
    s
}

#[test]
fn a_way_to_parking_is_soft_until_the_task_is_done() {
    let nav = nav();
    let mut s = with_a_soft_way_to_parking(&nav, &["a", "d"]);
    assert_eq!(s.soft_keep(0), Some(1), "soft after its first traversal");
    let at_c = s.conf().vertex[v(&nav, "c")].clone();
    let at_p2 = s.conf().vertex[v(&nav, "p2")].clone();
    // A task plan (soft) does not see robot 0 at c or its stay at p2; others do.
    for &x in &at_c {
        assert!(s.soft_passing(x, 1));
        assert_eq!(s.busy(x, 1, true).count(), 0);
        assert!(s.busy(x, 1, false).count() > 0);
    }
    // At p2 its soft way ends: a task plan may end there (robot 0 then parks elsewhere).
    for &x in &at_p2 {
        assert_eq!(s.held_for_good(x, 1, false), Some(0));
        assert_eq!(s.held_for_good(x, 1, true), None);
        assert!(!s.soft_passing(x, 1));
    }
    // Robot 0's last place is hard: its span at b began with its task's traversal.
    for &x in &s.conf().vertex[v(&nav, "b")] {
        assert!(!s.soft_passing(x, 1));
    }
    // Robot 1 at d, planned through c over [0, 16) (overlapping robot 0's soft span
    // there): it goes before robot 0 at c, and says so.
    let jumped = s.install(
        1,
        0,
        &[
            step(&nav, e(&nav, "d", "c"), 0.0, 8.0),
            step(&nav, e(&nav, "c", "d"), 8.0, 8.0),
        ],
        0.0,
        None,
    );
    assert_eq!(jumped, vec![0]);
    s.retime(0.0).expect("acyclic");
    let it0 = s.itinerary(0);
    assert_eq!(
        it0.travs[1].start,
        16.0 + super::retime::HEADWAY,
        "robot 0 leaves b after robot 1 left c"
    );
    // Its task done, robot 0's way to parking is hard: everybody plans around it.
    s.harden(0);
    assert_eq!(s.soft_keep(0), None);
    for &x in &at_c {
        assert!(!s.soft_passing(x, 1));
        assert!(s.busy(x, 1, true).count() > 0);
    }
}

#[test]
fn a_plan_that_fits_goes_before_nobody() {
    let nav = nav();
    let mut s = with_a_soft_way_to_parking(&nav, &["a", "d"]);
    // Robot 1 through c after robot 0 is parked at p2 (30 s): nobody's plan is broken.
    let jumped = s.install(
        1,
        0,
        &[
            step(&nav, e(&nav, "d", "c"), 40.0, 8.0),
            step(&nav, e(&nav, "c", "d"), 48.0, 8.0),
        ],
        40.0,
        None,
    );
    assert!(jumped.is_empty());
    s.check(0.0).expect("consistent");
    // Once robot 0 sets off on its way to parking, the way is hard.
    s.begin(0, 1, 0.0);
    s.complete_front(0, 10.0);
    s.begin(0, 1, 10.0);
    assert_eq!(s.soft_keep(0), None);
    for &x in &s.conf().vertex[v(&nav, "c")] {
        assert!(!s.soft_passing(x, 1));
    }
}

/// What `busy` says of every resource, for each robot left out and with or without soft
/// spans.
fn busy_everywhere(s: &Schedule) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    for x in 0..s.conf().n_res as Res {
        for r in 0..2 {
            for soft in [false, true] {
                out.push(s.busy(x, r, soft).collect());
            }
        }
    }
    out
}

/// Checks that every resource whose `busy` changed in `op` is stamped as changed since
/// before it (what the planner's kept intervals rely on), and that some did change.
fn stamps_follow(s: &mut Schedule, what: &str, op: impl FnOnce(&mut Schedule)) {
    let (before, at) = (busy_everywhere(s), s.stamp());
    op(s);
    let after = busy_everywhere(s);
    let per = 4; // 2 robots × soft or not
    let mut moved = 0;
    for x in 0..s.conf().n_res {
        let changed = (0..per).any(|k| before[x * per + k] != after[x * per + k]);
        if changed {
            moved += 1;
            assert!(
                s.changed_since(&[x as Res], at),
                "{what}: resource {x} changed but was not stamped"
            );
        }
    }
    assert!(
        moved > 0,
        "{what}: nothing changed (the test would prove nothing)"
    );
}

#[test]
fn every_change_of_what_busy_says_is_stamped() {
    let (nav, mut s) = two_robots();
    stamps_follow(&mut s, "retime", |s| {
        s.retime(0.0).expect("acyclic");
    });
    stamps_follow(&mut s, "begin and complete", |s| {
        s.begin(1, 1, 0.0);
        s.complete_front(1, 5.0);
    });
    stamps_follow(&mut s, "late retime", |s| {
        s.begin(0, 1, 0.0);
        s.retime(25.0).expect("acyclic");
    });
    // Robot 0 gets a way on from p1 whose part after b is soft (a way to parking).
    stamps_follow(&mut s, "install with soft steps", |s| {
        s.install(
            0,
            1,
            &[
                step(&nav, e(&nav, "b", "p1"), 25.0, 10.0),
                step(&nav, e(&nav, "p1", "b"), 60.0, 10.0),
            ],
            25.0,
            Some(1),
        );
    });
    stamps_follow(&mut s, "harden", |s| s.harden(0));
}

/// Everything a plan sees of a schedule: every resource's busy intervals (hard and soft
/// alike, for a robot that is nobody) and every itinerary.
fn seen(s: &Schedule) -> String {
    let busy: Vec<Vec<(f64, f64)>> = (0..s.conf().n_res)
        .map(|x| s.busy(x as Res, usize::MAX, false).collect())
        .collect();
    let its: Vec<String> = (0..2).map(|r| format!("{:?}", s.itinerary(r))).collect();
    format!("{busy:?} {its:?}")
}

#[test]
fn a_rolled_back_transaction_leaves_the_schedule_as_it_was() {
    let (nav, mut s) = two_robots();
    s.retime(0.0).expect("acyclic");
    let before = seen(&s);
    let stamp = s.stamp();
    s.open_tx();
    // Robot 1 goes another way: p2→c→d.
    s.install(1, 1, &[step(&nav, e(&nav, "c", "d"), 5.0, 10.0)], 5.0, None);
    s.harden(0);
    s.compute(0.0).expect("acyclic");
    assert_ne!(seen(&s), before);
    s.rollback();
    assert_eq!(seen(&s), before);
    // What was computed from the queues put back is stale.
    let set = &s.conf().trav[e(&nav, "c", "d")];
    assert!(s.changed_since(set, stamp));
    // A committed one keeps its change, and applies the computed times.
    s.open_tx();
    s.install(1, 1, &[step(&nav, e(&nav, "c", "d"), 5.0, 10.0)], 5.0, None);
    s.compute(0.0).expect("acyclic");
    assert_eq!(s.computed_end(1, 1), Some(15.0));
    s.commit();
    s.apply(0.0);
    assert_eq!(s.end_vertex(1), v(&nav, "d"));
    assert_eq!(s.itinerary(1).travs[1].end, 15.0);
    assert!(s.check(0.0).is_ok());
}

/// Intervals, per robot or per resource.
type Intervals = Vec<Vec<(f64, f64)>>;

/// Every traversal's times and what `busy` says everywhere.
fn times(s: &Schedule) -> (Intervals, Intervals) {
    let travs = (0..2)
        .map(|r| {
            s.itinerary(r)
                .travs
                .iter()
                .map(|t| (t.start, t.end))
                .collect()
        })
        .collect();
    (travs, busy_everywhere(s))
}

#[test]
fn a_retime_that_reads_only_what_changed_equals_a_full_one() {
    // Robot 1 arrives at c early and waits there for robot 0, which is late; then both go
    // on, robot 1 sent along two traversals at once. After every step, the schedule
    // retimed in place (which reads again only the queues changed since its last retime)
    // has the times of a copy retimed from nothing.
    let nav = nav();
    let mut s = standing(&nav);
    let mut retimes = 0;
    let mut check = |s: &mut Schedule, now: f64, what: &str| {
        let mut full = s.clone();
        let kept = s.retime(now);
        assert!(kept.is_ok(), "{what}: {kept:?}");
        full.retime(now).expect("acyclic");
        assert!(
            times(s) == times(&full),
            "{what} at {now}: kept and full retimes differ"
        );
        retimes += 1;
    };
    check(&mut s, 0.0, "standing");
    // The plans of `two_robots`, each after a retime: the second's queues are read again.
    plan_two(&nav, &mut s, 0);
    check(&mut s, 0.0, "robot 0 planned");
    plan_two(&nav, &mut s, 1);
    check(&mut s, 0.0, "robot 1 planned");
    s.begin(1, 1, 0.0);
    s.complete_front(1, 3.0);
    check(&mut s, 3.0, "robot 1 at c");
    check(&mut s, 6.0, "robot 1 waits");
    s.begin(0, 1, 2.0);
    check(&mut s, 7.0, "robot 0 set off late");
    check(&mut s, 15.0, "robot 0 overdue");
    s.complete_front(0, 16.0);
    check(&mut s, 16.0, "robot 0 at b");
    check(&mut s, 17.0, "robot 0 waits at b");
    s.begin(0, 1, 17.0);
    s.complete_front(0, 29.0);
    check(&mut s, 29.0, "robot 0 parked");
    assert!(s.granted(1, 0), "robot 1 goes on");
    s.begin(1, 2, 29.0);
    check(&mut s, 30.0, "robot 1 sent along two");
    s.complete_front(1, 39.0);
    check(&mut s, 45.0, "robot 1 at b, late");
    assert_eq!(retimes, 12);
    // The retimes at the time of the last one (after each plan at 0) followed the
    // changes only; the others were full passes.
    assert_eq!((s.bufs.followed, s.bufs.full), (2, 10));
}

/// A plan that starts with work where its robot stands (charging, say: the first step's
/// hold) leaves after the work, in the retime too: robots planned later against the
/// schedule see it standing there until then (it used to leave at once, and a robot
/// planned behind a charging one waited for hours).
#[test]
fn work_where_a_robot_stands_holds_its_first_traversal_back() {
    let nav = nav();
    let mut s = standing(&nav);
    let mut first = step(&nav, e(&nav, "a", "b"), 3600.0, 10.0);
    first.hold = 3600.0;
    s.install(0, 0, &[first], 0.0, None);
    s.retime(5.0).expect("acyclic");
    let it = s.itinerary(0);
    assert_eq!(it.ready, 3600.0);
    assert_eq!((it.travs[0].start, it.travs[0].end), (3600.0, 3610.0));
}
