//! Each trajectory on its own: well-formed, covering the makespan, and inside the joint
//! position, velocity and acceleration limits everywhere between its points.

use super::hermite::Cubic;
use super::{RateLimits, TimeViolation, Timeline, Track, RATE_TOLERANCE, TIME_TOLERANCE};
use crate::resolve::RobotId;
use crate::verify::{Violation, LIMIT_TOLERANCE};
use crate::world::World;

/// True when every robot has exactly one well-formed trajectory, so it can be replayed.
/// Limit violations are reported but do not stop the replay.
pub(super) fn check_tracks(world: &World, tl: &Timeline, limits: &RateLimits, out: &mut Vec<Violation>) -> bool {
    let scn = world.scenario();
    let mut ok = true;
    for (ri, robot) in scn.robots.iter().enumerate() {
        let r = RobotId(ri as u32);
        let found = tl.tracks.iter().filter(|t| t.robot == r).count();
        if found != 1 {
            out.push(Violation::timed(None, TimeViolation::TrackCount { robot: robot.name.clone(), found }));
            ok = false;
        }
    }
    for tr in &tl.tracks {
        if !well_formed(world, tl.makespan, tr, out) {
            ok = false;
            continue;
        }
        let velocity = limits.velocity.get(tr.robot.index()).map_or(&[][..], Vec::as_slice);
        let acceleration = limits.acceleration.get(tr.robot.index()).map_or(&[][..], Vec::as_slice);
        check_rates(world, tr, velocity, acceleration, out);
    }
    ok
}

fn well_formed(world: &World, makespan: f64, tr: &Track, out: &mut Vec<Violation>) -> bool {
    let robot = world.scenario().robot(tr.robot).name.clone();
    let dof = world.dof(tr.robot);
    let (Some(first), Some(last)) = (tr.points.first(), tr.points.last()) else {
        out.push(Violation::timed(None, TimeViolation::EmptyTrack { robot }));
        return false;
    };
    let before = out.len();
    for (index, p) in tr.points.iter().enumerate() {
        for found in [p.q.len(), p.qd.len()] {
            if found != dof {
                let v = TimeViolation::TrackPointLength { robot: robot.clone(), index, expected: dof, found };
                out.push(Violation::timed(None, v));
            }
        }
        if !p.t.is_finite() || p.q.iter().chain(&p.qd).any(|v| !v.is_finite()) {
            out.push(Violation::timed(None, TimeViolation::NotFinite { robot: robot.clone(), index }));
        } else if index > 0 && p.t <= tr.points[index - 1].t {
            out.push(Violation::timed(Some(p.t), TimeViolation::TimeNotIncreasing { robot: robot.clone(), index }));
        }
    }
    if out.len() == before && (first.t.abs() > TIME_TOLERANCE || last.t < makespan - TIME_TOLERANCE) {
        let v = TimeViolation::DoesNotCover { robot, first: first.t, last: last.t, makespan };
        out.push(Violation::timed(None, v));
    }
    out.len() == before
}

/// Joint positions, speeds and accelerations over every segment, at their exact extremes.
/// One report per joint and kind: the first instant it happens.
fn check_rates(world: &World, tr: &Track, velocity: &[f64], acceleration: &[f64], out: &mut Vec<Violation>) {
    let robot = &world.scenario().robot(tr.robot).name;
    let names = world.joint_names(tr.robot);
    let limits = world.limits(tr.robot);
    let dof = world.dof(tr.robot);
    let mut reported = vec![[false; 3]; dof];
    for w in tr.points.windows(2) {
        let h = w[1].t - w[0].t;
        for j in 0..dof {
            let c = Cubic::new(h, w[0].q[j], w[0].qd[j], w[1].q[j], w[1].qd[j]);
            let at = |s: f64| w[0].t + s * h;
            let joint = names[j].clone();
            let ((lo_v, lo_s), (hi_v, hi_s)) = c.position_range();
            let (lo, hi) = limits[j];
            if !reported[j][0] && (lo_v < lo - LIMIT_TOLERANCE || hi_v > hi + LIMIT_TOLERANCE) {
                reported[j][0] = true;
                let (value, s) = if lo_v < lo - LIMIT_TOLERANCE { (lo_v, lo_s) } else { (hi_v, hi_s) };
                let v = TimeViolation::OutOfLimits { robot: robot.clone(), joint: joint.clone(), value, lo, hi };
                out.push(Violation::timed(Some(at(s)), v));
            }
            let limit = velocity.get(j).copied().unwrap_or(f64::INFINITY);
            let (speed, s) = c.max_speed();
            if !reported[j][1] && speed > limit * (1.0 + RATE_TOLERANCE) {
                reported[j][1] = true;
                let v = TimeViolation::TooFast { robot: robot.clone(), joint: joint.clone(), speed, limit };
                out.push(Violation::timed(Some(at(s)), v));
            }
            let (acc, s) = c.max_acceleration();
            let acceleration = acceleration.get(j).copied().unwrap_or(f64::INFINITY);
            if !reported[j][2] && acc > acceleration * (1.0 + RATE_TOLERANCE) {
                reported[j][2] = true;
                let v = TimeViolation::TooHardAcceleration {
                    robot: robot.clone(),
                    joint,
                    acceleration: acc,
                    limit: acceleration,
                };
                out.push(Violation::timed(Some(at(s)), v));
            }
        }
    }
}

/// Each robot's trajectory, in scenario order (call after [`check_tracks`] succeeded).
pub(super) fn by_robot<'t>(world: &World, tl: &'t Timeline) -> Vec<&'t Track> {
    (0..world.scenario().robots.len()).filter_map(|ri| tl.tracks.iter().find(|t| t.robot.index() == ri)).collect()
}

/// The segment holding `t` (the last one from the final point on; the first before 0).
pub(super) fn segment_at(tr: &Track, t: f64) -> usize {
    let n = tr.points.len();
    if n < 2 {
        return 0;
    }
    let i = tr.points.partition_point(|p| p.t <= t);
    i.saturating_sub(1).min(n - 2)
}

/// Positions and velocities at `t`; held still at the ends outside the trajectory's span.
pub(super) fn state_at(tr: &Track, t: f64, q: &mut Vec<f64>, qd: &mut Vec<f64>) {
    let pts = &tr.points;
    q.clear();
    qd.clear();
    let (Some(first), Some(last)) = (pts.first(), pts.last()) else { return };
    if pts.len() == 1 || t <= first.t || t >= last.t {
        let p = if t <= first.t { first } else { last };
        q.extend_from_slice(&p.q);
        qd.extend(p.q.iter().map(|_| 0.0));
        if t == p.t {
            qd.clear();
            qd.extend_from_slice(&p.qd);
        }
        return;
    }
    let k = segment_at(tr, t);
    let (a, b) = (&pts[k], &pts[k + 1]);
    let h = b.t - a.t;
    let s = ((t - a.t) / h).clamp(0.0, 1.0);
    for j in 0..a.q.len() {
        let c = Cubic::new(h, a.q[j], a.qd[j], b.q[j], b.qd[j]);
        q.push(c.position(s));
        qd.push(c.velocity(s));
    }
}

/// Per joint, the largest |velocity| on segment `k`.
pub(super) fn peak_speeds(tr: &Track, k: usize, out: &mut Vec<f64>) {
    segment_peaks(tr, k, None, out);
}

/// Per joint, the largest |velocity| on segment `k` between times `t0` and `t1` (taken a
/// hair wider, so that rounding the window's ends cannot miss a peak at one of them).
/// Outside the trajectory's span a joint stands still, and the segment's end speed (0 at
/// a trajectory's ends as written) bounds it.
pub(super) fn peak_speeds_between(tr: &Track, k: usize, t0: f64, t1: f64, out: &mut Vec<f64>) {
    segment_peaks(tr, k, Some((t0, t1)), out);
}

/// Per joint, the largest |velocity| on segment `k`, or on the part of it within `window`
/// (times).
fn segment_peaks(tr: &Track, k: usize, window: Option<(f64, f64)>, out: &mut Vec<f64>) {
    out.clear();
    let (Some(a), Some(b)) = (tr.points.get(k), tr.points.get(k + 1)) else {
        if let Some(p) = tr.points.first() {
            out.extend(p.q.iter().map(|_| 0.0));
        }
        return;
    };
    let h = b.t - a.t;
    let (s0, s1) = window.map_or((0.0, 1.0), |(t0, t1)| {
        (((t0 - a.t) / h - 1e-12).clamp(0.0, 1.0), ((t1 - a.t) / h + 1e-12).clamp(0.0, 1.0))
    });
    for j in 0..a.q.len() {
        out.push(Cubic::new(h, a.q[j], a.qd[j], b.q[j], b.qd[j]).max_speed_on(s0, s1));
    }
}
