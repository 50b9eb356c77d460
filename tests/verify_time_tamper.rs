//! Tampering with timed schedules the compiler really produced: each kind is caught, one
//! test each, and the shifted start of the shelf's second arm names both robots, their
//! bodies and the time.

mod time_support;

use declutter::schedule::{EventKind, Schedule};
use declutter::verify::time::{Obstacle, Party, TimeViolation};
use declutter::verify::{self, Location, ViolationKind};
use declutter::world::World;
use time_support::{compiled, shift_earlier};

/// The violations found in time.
fn timed(w: &World, s: &Schedule) -> Vec<(Location, TimeViolation)> {
    match verify::verify(w, s) {
        Ok(_) => Vec::new(),
        Err(v) => v
            .into_iter()
            .filter_map(|v| match v.kind {
                ViolationKind::Time(t) => Some((v.location, t)),
                _ => None,
            })
            .collect(),
    }
}

#[test]
fn the_shelf_concurrent_schedule_verifies_and_both_arms_started_at_once_collide() {
    let (w, mut s) = compiled("examples/shelf.dcl");
    assert!(verify::verify(&w, &s).is_ok());
    // The arm whose first action waits.
    let first = |r: &str| s.actions.iter().filter(|a| a.robot == r).map(|a| a.start).fold(f64::INFINITY, f64::min);
    let (late, wait) = if first("r2") > first("r1") { ("r2", first("r2")) } else { ("r1", first("r1")) };
    assert!(wait > 0.0, "one arm waits for the other");
    shift_earlier(&mut s, late, wait, wait);
    let found = timed(&w, &s);
    let hit = found.iter().find_map(|(loc, v)| match (loc, v) {
        (
            Location::At { t },
            TimeViolation::Contact {
                a: Party::Body { robot: a, body: ab } | Party::Held { robot: a, object: ab },
                b: Obstacle::Moving(Party::Body { robot: b, body: bb } | Party::Held { robot: b, object: bb }),
                ..
            },
        ) if a != b => Some((*t, a.clone(), ab.clone(), b.clone(), bb.clone())),
        _ => None,
    });
    let (t, a, ab, b, bb) = hit.unwrap_or_else(|| panic!("no contact between the arms: {found:#?}"));
    assert_eq!((a.as_str(), b.as_str()), ("r1", "r2"));
    assert!(!ab.is_empty() && !bb.is_empty() && t > 0.0 && t < s.makespan);
}

#[test]
fn an_action_started_before_the_object_it_needs_is_clear_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    // Action 2 (the can) waits for action 1 (the lid).
    assert_eq!(s.actions[1].after, vec![1]);
    let (robot, start) = (s.actions[1].robot.clone(), s.actions[1].start);
    // The lid is grasped, not yet lifted clear.
    let lid_clear = s.events.iter().find(|e| e.object == "lid" && e.kind == EventKind::Grasp).expect("a grasp").t;
    assert!(start > lid_clear);
    // Its robot idles until then; move the whole action earlier, to mid-way through action 1.
    let idle_from = s.actions.iter().filter(|a| a.robot == robot && a.end <= start).map(|a| a.end).fold(0.0, f64::max);
    let by = (start - lid_clear).min(start - idle_from);
    shift_earlier(&mut s, &robot, start, by);
    let found = timed(&w, &s);
    assert!(
        found.iter().any(
            |(_, v)| matches!(v, TimeViolation::StartsBeforeClear { action: 2, by: 1, object, .. } if object == "lid")
        ),
        "{found:#?}"
    );
}

/// Squeezes the stretch of `robot`'s trajectory between points `from` and `to` into
/// `factor` of its time (velocities scaled by 1/`factor`); later points move earlier, and
/// the robot holds its last configuration to the makespan.
fn squeeze(s: &mut Schedule, robot: &str, from: usize, to: usize, factor: f64) {
    let tr = s.trajectories.iter_mut().find(|t| t.robot == robot).expect("trajectory");
    let t0 = tr.points[from].t;
    let saved = (tr.points[to].t - t0) * (1.0 - factor);
    for (i, p) in tr.points.iter_mut().enumerate().skip(from) {
        if i <= to {
            p.t = t0 + (p.t - t0) * factor;
            p.qd.iter_mut().for_each(|v| *v /= factor);
        } else {
            p.t -= saved;
        }
    }
    let mut last = tr.points.last().cloned().expect("points");
    last.t += saved;
    tr.points.push(last);
}

/// The first motion of `robot` between two rest points: (first point, last point) indices.
fn first_move(s: &Schedule, robot: &str) -> (usize, usize) {
    let tr = s.trajectories.iter().find(|t| t.robot == robot).expect("trajectory");
    let at_rest = |i: usize| tr.points[i].qd.iter().all(|v| *v == 0.0);
    let from = (0..tr.points.len() - 1).find(|&i| at_rest(i) && tr.points[i + 1].q != tr.points[i].q).expect("a move");
    let to = (from + 1..tr.points.len()).find(|&i| at_rest(i)).expect("a stop");
    (from, to)
}

#[test]
fn a_move_squeezed_past_a_velocity_limit_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    let robot = s.actions[0].robot.clone();
    let (from, to) = first_move(&s, &robot);
    // Squeezed to half the time it would take at the limit of its busiest joint.
    let r = w.scenario().robot_by_name(&robot).expect("robot");
    let limits: Vec<f64> = w.velocity_limits(r).iter().map(|v| v * w.scenario().planner.speed).collect();
    let tr = s.trajectories.iter().find(|t| t.robot == robot).expect("trajectory");
    let busiest = tr.points[from..=to]
        .iter()
        .flat_map(|p| p.qd.iter().zip(&limits).map(|(v, l)| v.abs() / l))
        .fold(0.0, f64::max);
    squeeze(&mut s, &robot, from, to, 0.5 * busiest);
    let found = timed(&w, &s);
    assert!(
        found.iter().any(|(_, v)| matches!(v, TimeViolation::TooFast { robot: r, .. } if *r == robot)),
        "{found:#?}"
    );
}

#[test]
fn a_move_squeezed_past_the_acceleration_limit_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    let robot = s.actions[0].robot.clone();
    let (from, to) = first_move(&s, &robot);
    // Squeezed by 5 %: the profile accelerates at the limit, now at 1/0.95² of it.
    squeeze(&mut s, &robot, from, to, 0.95);
    let found = timed(&w, &s);
    assert!(
        found.iter().any(|(_, v)| matches!(v, TimeViolation::TooHardAcceleration { robot: r, .. } if *r == robot)),
        "{found:#?}"
    );
}

#[test]
fn a_grasp_event_removed_or_moved_is_caught() {
    let (w, s) = compiled("examples/box_lid.dcl");
    let k = s.events.iter().position(|e| e.kind == EventKind::Grasp).expect("a grasp");
    let mut gone = s.clone();
    gone.events.remove(k);
    let found = timed(&w, &gone);
    assert!(found.iter().any(|(_, v)| matches!(v, TimeViolation::EventMissing { action: 1, .. })), "{found:#?}");
    let mut moved = s.clone();
    moved.events[k].t -= 0.5;
    let found = timed(&w, &moved);
    assert!(found.iter().any(|(_, v)| matches!(v, TimeViolation::EventMisplaced { action: 1, .. })), "{found:#?}");
}

#[test]
fn a_trajectory_that_skips_a_waypoint_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    let a = &s.actions[0];
    assert!(a.approach.len() >= 3, "an approach with a waypoint between home and the grasp");
    let (robot, skipped) = (a.robot.clone(), a.approach[1].clone());
    let tr = s.trajectories.iter_mut().find(|t| t.robot == robot).expect("trajectory");
    let at = tr.points.iter().position(|p| p.q == skipped).expect("the waypoint is a point");
    let next = (at + 1..tr.points.len()).find(|&i| tr.points[i].qd.iter().all(|v| *v == 0.0)).expect("a stop");
    let prev = (0..at).rev().find(|&i| tr.points[i].qd.iter().all(|v| *v == 0.0)).expect("a stop");
    // Straight from the waypoint before to the one after, in the same time.
    tr.points.drain(prev + 1..next);
    let found = timed(&w, &s);
    assert!(found.iter().any(|(_, v)| matches!(v, TimeViolation::WaypointSkipped { action: 1, .. })), "{found:#?}");
}
