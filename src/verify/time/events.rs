//! Actions against the trajectories: each action's waypoints are passed in order within
//! its interval, its grasp and release events happen where the robot is at the grasp
//! and at the drop, and it starts only once the objects it waits for are carried clear.
//!
//! "Carried clear": the carrying robot has reached the retreat's second waypoint, the
//! end of the straight move out from the grasp (or, with no such waypoint, released the
//! object). From then on the object is away from its place; where it still is, the
//! replay checks it as a carried object at every sample.

use super::track::state_at;
use super::{EventKind, TimeViolation, TimedAction, Timeline, Track, TIME_TOLERANCE, WAYPOINT_TOLERANCE};
use crate::resolve::{ObjectId, RobotId};
use crate::verify::{Phase, Violation};
use crate::world::{Held, World};

/// An object's life in the replay: in place until `grasp`, moving with `robot`'s hand
/// until `release`, gone after.
#[derive(Clone, Debug)]
pub(super) struct Carry {
    pub robot: RobotId,
    pub object: ObjectId,
    pub grasp: f64,
    pub release: f64,
    pub held: Held,
    /// From here to `grasp` the carrier's hand may touch the object in place: the straight
    /// move in, where the closed hand's model overlaps it.
    pub exempt_from: f64,
}

/// What the replay needs from the actions and events.
#[derive(Clone, Debug, Default)]
pub(super) struct Marks {
    pub carries: Vec<Carry>,
}

/// Checks waypoints, events and precedence; returns the carries the events describe.
pub(super) fn check_actions(world: &World, tl: &Timeline, tracks: &[&Track], out: &mut Vec<Violation>) -> Marks {
    let scn = world.scenario();
    let mut used = vec![false; tl.events.len()];
    let mut marks = Marks::default();
    // Per action: when its object is carried clear.
    let mut clear: Vec<(u32, ObjectId, f64)> = Vec::new();
    for a in &tl.actions {
        let Some(tr) = tracks.get(a.robot.index()) else { continue };
        // An unchecked action reports into a scratch list, so only its carry is kept.
        let mut quiet = Vec::new();
        let out: &mut Vec<Violation> = if a.checked { &mut *out } else { &mut quiet };
        if !(a.start >= -TIME_TOLERANCE && a.start <= a.end && a.end <= tl.makespan + TIME_TOLERANCE) {
            let v = TimeViolation::BadInterval { action: a.id, start: a.start, end: a.end };
            out.push(Violation::timed(None, v));
        }
        let times = waypoint_times(a, tr, out);
        let Some(o) = a.object else { continue };
        let object = scn.object(o).body.name.clone();
        let n = a.approach.len();
        // The approach's last waypoint is the grasp configuration.
        let Some(q_grasp) = a.approach.last() else { continue };
        if let (Some(Some(t0)), Some(Some(t1))) = (times.get(n.wrapping_sub(2)), times.get(n - 1)) {
            check_straight(a, tr, *t0, *t1, out);
        }
        let mut find = |kind: EventKind| {
            let hit = tl
                .events
                .iter()
                .enumerate()
                .find(|(k, e)| !used[*k] && e.robot == a.robot && e.object == o && e.kind == kind);
            hit.map(|(k, e)| {
                used[k] = true;
                (e.t, &e.fingers)
            })
        };
        let grasp_event = find(EventKind::Grasp);
        let release_event = find(EventKind::Release);
        // The fingers: closed as the scenario says on the object at the grasp, open at the release.
        for (kind, e, posture) in [
            (EventKind::Grasp, grasp_event, world.posture_of(a.robot, o, a.grasp)),
            (EventKind::Release, release_event, crate::world::OPEN_POSTURE),
        ] {
            let Some((t, found)) = e else { continue };
            let expected = world.finger_values(a.robot, posture);
            let same = expected.len() == found.len() && expected.iter().zip(found).all(|(x, y)| (x - y).abs() <= 1e-6);
            if !same {
                out.push(Violation::timed(
                    Some(t),
                    TimeViolation::FingersWrong {
                        action: a.id,
                        kind,
                        object: object.clone(),
                        t,
                        expected: expected.to_vec(),
                        found: found.clone(),
                    },
                ));
            }
        }
        let grasp = grasp_event.map(|e| e.0);
        let release = release_event.map(|e| e.0);
        let mut placed = |kind: EventKind, t: Option<f64>, q_at: &[f64]| {
            let Some(t) = t else {
                out.push(Violation::timed(
                    None,
                    TimeViolation::EventMissing { action: a.id, kind, object: object.clone() },
                ));
                return;
            };
            let (mut q, mut qd) = (Vec::new(), Vec::new());
            state_at(tr, t, &mut q, &mut qd);
            let distance = q.iter().zip(q_at).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            if distance > WAYPOINT_TOLERANCE || t < a.start - TIME_TOLERANCE || t > a.end + TIME_TOLERANCE {
                let v = TimeViolation::EventMisplaced { action: a.id, kind, object: object.clone(), t, distance };
                out.push(Violation::timed(Some(t), v));
            }
        };
        placed(EventKind::Grasp, grasp, q_grasp);
        placed(EventKind::Release, release, world.drop_config(a.robot));
        if let (Some(g), Some(r)) = (grasp, release) {
            if r < g {
                out.push(Violation::timed(
                    Some(r),
                    TimeViolation::ReleaseBeforeGrasp { action: a.id, object: object.clone() },
                ));
            }
        }
        // Without a grasp event the object is never picked: it stays where it is.
        if let Some(g) = grasp {
            let exempt_from = times.get(n.wrapping_sub(2)).copied().flatten().unwrap_or(g);
            let held = world.held(a.robot, o, a.grasp, q_grasp);
            let release = release.filter(|r| *r >= g).unwrap_or(f64::INFINITY);
            marks.carries.push(Carry { robot: a.robot, object: o, grasp: g, release, held, exempt_from });
        }
        // The end of the straight move out, else the release.
        let out_of_place = times.get(n).copied().flatten().filter(|_| a.retreat.len() > 1);
        if let Some(c) = out_of_place.or(release).or(grasp) {
            clear.push((a.id, o, c));
        }
    }
    for a in tl.actions.iter().filter(|a| a.checked) {
        for dep in a.after {
            if let Some((by, o, c)) = clear.iter().find(|(id, _, _)| id == dep) {
                if a.start < c - TIME_TOLERANCE {
                    let object = scn.object(*o).body.name.clone();
                    let v =
                        TimeViolation::StartsBeforeClear { action: a.id, object, by: *by, start: a.start, clear: *c };
                    out.push(Violation::timed(Some(a.start), v));
                }
            }
        }
    }
    for (k, e) in tl.events.iter().enumerate() {
        if !used[k] {
            let v = TimeViolation::UnexpectedEvent {
                robot: scn.robot(e.robot).name.clone(),
                kind: e.kind,
                object: scn.object(e.object).body.name.clone(),
                t: e.t,
            };
            out.push(Violation::timed(Some(e.t), v));
        }
    }
    marks
}

/// The time each waypoint is passed — approach, then the retreat after its first
/// waypoint (the grasp again) — in order within the action's interval; `None` where skipped.
fn waypoint_times(a: &TimedAction, tr: &Track, out: &mut Vec<Violation>) -> Vec<Option<f64>> {
    let mut times = Vec::new();
    let mut from = tr.points.partition_point(|p| p.t < a.start - TIME_TOLERANCE);
    let retreat = a.retreat.iter().enumerate().skip(1).map(|(i, q)| (Phase::Retreat, i, q));
    let approach = a.approach.iter().enumerate().map(|(i, q)| (Phase::Approach, i, q));
    for (phase, index, w) in approach.chain(retreat) {
        let hit = tr.points[from..]
            .iter()
            .take_while(|p| p.t <= a.end + TIME_TOLERANCE)
            .position(|p| near(&p.q, w))
            .map(|k| from + k);
        match hit {
            Some(k) => {
                from = k;
                times.push(Some(tr.points[k].t));
            }
            None => {
                out.push(Violation::timed(None, TimeViolation::WaypointSkipped { action: a.id, phase, index }));
                times.push(None);
            }
        }
    }
    times
}

/// Every point from `t0` to `t1` (the straight move in) lies on the joint-space line
/// between them and moves along it, so the curve between them does too.
fn check_straight(a: &TimedAction, tr: &Track, t0: f64, t1: f64, out: &mut Vec<Violation>) {
    let (Some(from), Some(to)) = (a.approach.get(a.approach.len() - 2), a.approach.last()) else { return };
    let d: Vec<f64> = to.iter().zip(from).map(|(b, a)| b - a).collect();
    let len = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    if len == 0.0 {
        return;
    }
    let u: Vec<f64> = d.iter().map(|x| x / len).collect();
    let off = |v: &[f64]| {
        let along: f64 = v.iter().zip(&u).map(|(x, y)| x * y).sum();
        v.iter().zip(&u).map(|(x, y)| (x - along * y).powi(2)).sum::<f64>().sqrt()
    };
    let mut worst: f64 = 0.0;
    for p in tr.points.iter().filter(|p| p.t >= t0 - TIME_TOLERANCE && p.t <= t1 + TIME_TOLERANCE) {
        let rel: Vec<f64> = p.q.iter().zip(from).map(|(q, a)| q - a).collect();
        worst = worst.max(off(&rel)).max(off(&p.qd));
    }
    if worst > WAYPOINT_TOLERANCE {
        out.push(Violation::timed(Some(t0), TimeViolation::LeavesApproachLine { action: a.id, deviation: worst }));
    }
}

fn near(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= WAYPOINT_TOLERANCE)
}
