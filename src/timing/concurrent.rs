//! Concurrent placement of actions in time: list scheduling with a swept-distance check.
//!
//! Actions are placed in plan order (a topological order of `after`). Each one starts
//! at the earliest time, on a grid of [`START_STEP`] from its lower bound, at which
//! - its robot has finished its previous action,
//! - every action it waits for has carried its object clear (reached the first retreat
//!   waypoint after the grasp, the pre-grasp stand-off), and
//! - for as long as it overlaps an action of another robot already placed, the two
//!   robots, each with what it carries, stay at least [`SEPARATION`] apart at every
//!   instant.
//!
//! The last point is proved, not sampled: at an instant where the two are `d` apart,
//! neither can close more than the distance its points can travel, bounded per stretch
//! between trajectory points by `Σ reach_j · max |q̇_j|` ([`JointReach`]; between two
//! points q̇ is linear, so its largest magnitude is at an end). The check jumps ahead
//! by the time that bound needs to use up `d − SEPARATION` and measures again, and
//! calls a conflict when `d < SEPARATION + MIN_ADVANCE` (so each jump covers at least
//! `MIN_ADVANCE` of closing distance). A start is first looked at near where the start
//! before it met the other action: where the two are surely nearer than `SEPARATION` (by
//! a distance from above) no proof can pass, so that instant alone rules the start out.
//!
//! A robot outside its actions is at `home` (every action but a configuration target's
//! ends there), where the planner already checked every other robot's motion against
//! it; so only overlapping actions are compared. A configuration target's action keeps
//! its robot at the target afterwards: it overlaps everything after its start.
//!
//! What it does not do: it never changes a path or makes a robot wait inside an action,
//! and it keeps the planner's choice of robot per action; the makespan is not optimal.
//! If some action finds no safe start (which the planner's checks rule out), every
//! action is placed one after another instead.
//!
//! [`JointReach`]: crate::world::JointReach

use super::{hermite, one_after_another, time_action, Motion, RobotTiming, TimedAction, TrajPoint};
use crate::resolve::RobotId;
use crate::world::{Held, RobotAt, World};

/// Distance (metres) two robots, and what they carry, keep at every instant while both
/// are in an action.
pub const SEPARATION: f64 = 0.005;

/// A sample nearer than `SEPARATION + MIN_ADVANCE` is a conflict (see the module docs).
const MIN_ADVANCE: f64 = 0.002;

/// Start times tried, in seconds after an action's lower bound.
pub const START_STEP: f64 = 1.0 / STARTS_PER_SECOND;
/// `k / 20` is exact where `k * 0.05` is not (1.2, not 1.2000000000000002).
const STARTS_PER_SECOND: f64 = 20.0;

/// Shapes' boxes nearer than this get an exact distance.
const NEAR: f64 = 0.1;

/// Tolerance for "this configuration is home".
const AT_HOME: f64 = 1e-9;

/// One action as placed, in absolute time.
struct Run {
    robot: RobotId,
    start: f64,
    /// When its robot is back home; infinite when it stays away (configuration target).
    until: f64,
    points: Vec<TrajPoint>,
    /// Grasp to release, and the object as carried.
    hold: Option<(f64, f64, Held)>,
    /// Displacement bound per unit joint motion, empty- and full-handed.
    reach: Vec<f64>,
    reach_held: Vec<f64>,
}

impl Run {
    fn q_at(&self, t: f64) -> Vec<f64> {
        hermite(&self.points, t)
    }

    fn held_at(&self, t: f64) -> Option<&Held> {
        self.hold.as_ref().filter(|(g, r, _)| *g <= t && t < *r).map(|(_, _, h)| h)
    }

    /// The bound on how fast any point moves in the stretch between points that holds
    /// `t`, and when that stretch ends (infinite after the last point: at rest).
    fn speed(&self, t: f64) -> (f64, f64) {
        let k = self.points.partition_point(|p| p.t <= t);
        if k == 0 || k >= self.points.len() {
            let next = self.points.get(k).map_or(f64::INFINITY, |p| p.t);
            return (0.0, next);
        }
        let (a, b) = (&self.points[k - 1], &self.points[k]);
        let carrying = self.hold.as_ref().is_some_and(|(g, r, _)| *g < b.t && a.t < *r);
        let reach = if carrying { &self.reach_held } else { &self.reach };
        let v = reach.iter().enumerate().map(|(j, rj)| rj * a.qd[j].abs().max(b.qd[j].abs())).sum();
        (v, b.t)
    }

    /// Times after `t` at which what it holds changes.
    fn next_event(&self, t: f64) -> f64 {
        match &self.hold {
            Some((g, r, _)) if *g > t => *g,
            Some((_, r, _)) if *r > t => *r,
            _ => f64::INFINITY,
        }
    }
}

/// The first instant in the overlap of `x` and `y` at which the two robots come nearer
/// than allowed, if any.
fn conflict(world: &World, x: &Run, y: &Run) -> Option<f64> {
    let lo = x.start.max(y.start);
    let hi = x.until.min(y.until);
    if lo >= hi {
        return None;
    }
    let mut t = lo;
    loop {
        let (qx, qy) = (x.q_at(t), y.q_at(t));
        let d = world.robots_apart(
            RobotAt { robot: x.robot, q: &qx, held: x.held_at(t) },
            RobotAt { robot: y.robot, q: &qy, held: y.held_at(t) },
            NEAR,
        );
        if d < SEPARATION + MIN_ADVANCE {
            return Some(t);
        }
        let mut budget = d - SEPARATION;
        // Advance until the closing bound has used up the budget, stopping early to
        // measure again where what either robot holds changes.
        loop {
            let (vx, ex) = x.speed(t);
            let (vy, ey) = y.speed(t);
            let event = x.next_event(t).min(y.next_event(t));
            let end = ex.min(ey).min(event).min(hi);
            let v = vx + vy;
            if v * (end - t) >= budget {
                t += budget / v;
                break;
            }
            if !end.is_finite() {
                return None;
            }
            budget -= v * (end - t);
            t = end;
            if t >= hi {
                return None;
            }
            if t == event {
                break;
            }
        }
    }
}

/// Whether `x` and `y` surely come nearer than [`SEPARATION`] at `t`, within their
/// overlap: then [`conflict`] finds a conflict too (no bound it proves from its instants
/// can cover `t`, where the two are nearer), so a start that met one there is tried
/// there first. Within [`SURELY`] of `SEPARATION` it says nothing.
fn surely_near(world: &World, x: &Run, y: &Run, t: f64) -> bool {
    if !(x.start.max(y.start) <= t && t < x.until.min(y.until)) {
        return false;
    }
    let (qx, qy) = (x.q_at(t), y.q_at(t));
    world.robots_within(
        RobotAt { robot: x.robot, q: &qx, held: x.held_at(t) },
        RobotAt { robot: y.robot, q: &qy, held: y.held_at(t) },
        SEPARATION - SURELY,
    )
}

/// Where a start is first looked at, in steps of [`START_STEP`] from the instant the start
/// before it met a placed action: first where it now stands as it stood then.
const NEAR_STEPS: [f64; 8] = [1.0, 0.0, 2.0, 3.0, 4.0, 5.0, 6.0, -1.0];

/// What [`surely_near`] leaves to the rounding of the bounds (metres).
const SURELY: f64 = 1e-6;

/// Places the actions as the module docs say.
pub(super) fn place(world: &World, robots: &[RobotTiming], motions: &[Motion]) -> Vec<TimedAction> {
    let relative: Vec<TimedAction> = motions.iter().map(|m| time_action(&robots[m.robot.index()], m, 0.0)).collect();
    let reach: Vec<_> = world.scenario().robot_ids().map(|r| world.joint_reach(r)).collect();
    let mut placed: Vec<(TimedAction, Run)> = Vec::with_capacity(motions.len());
    for (i, m) in motions.iter().enumerate() {
        let r = m.robot.index();
        let rel = &relative[i];
        let own_free = placed.iter().filter(|(_, run)| run.robot == m.robot).map(|(a, _)| a.end).fold(0.0, f64::max);
        let deps_clear =
            m.after.iter().filter_map(|&j| placed.get(j)).map(|(a, _)| a.clear.unwrap_or(a.end)).fold(0.0, f64::max);
        let lower = own_free.max(deps_clear);
        let others_done =
            placed.iter().filter(|(_, run)| run.robot != m.robot).map(|(a, _)| a.end).fold(lower, f64::max);
        let held = match (m.object, m.approach.last()) {
            (Some(o), Some(q)) if rel.grasp.is_some() => {
                Some(world.held(m.robot, o, m.grasp.unwrap_or(usize::MAX), &q.0))
            }
            _ => None,
        };
        let held_radius = held.as_ref().map_or(0.0, |h| world.held_radius(h));
        let last = m.retreat.last().or(m.approach.last());
        let ends_home = last.is_none_or(|q| {
            let home = &robots[r].home;
            q.0.len() == home.len() && q.0.iter().zip(home).all(|(a, b)| (a - b).abs() <= AT_HOME)
        });
        let make_run = |start: f64| {
            let shifted = shift(rel, start);
            let run = Run {
                robot: m.robot,
                start,
                until: if ends_home { shifted.end } else { f64::INFINITY },
                points: shifted.points.clone(),
                hold: match (&held, shifted.grasp, shifted.release) {
                    (Some(h), Some(g), Some(rl)) => Some((g, rl, h.clone())),
                    _ => None,
                },
                reach: reach[r].bodies.clone(),
                reach_held: reach[r].with_held(held_radius),
            };
            (shifted, run)
        };
        // Per placed action: where the last start tried met it. The next start, a step
        // later, mostly meets it there again, a few steps on or at the instant itself
        // (`NEAR_STEPS`), and one such instant proves it (`surely_near`); a conflict found
        // from the overlap's start costs tens of measures (on the 200-can table the
        // timing stage's instructions fell from 910 to 200 M). Either way the same starts
        // are found unsafe.
        let mut met: Vec<Option<f64>> = vec![None; placed.len()];
        let mut safe = |run: &Run| {
            let others = placed.iter().enumerate().filter(|(_, (_, other))| other.robot != m.robot);
            for (j, (_, other)) in others.clone() {
                let near = |t: f64| NEAR_STEPS.iter().any(|&k| surely_near(world, run, other, t + k * START_STEP));
                if met[j].is_some_and(near) {
                    return false;
                }
            }
            for (j, (_, other)) in others {
                if let Some(t) = conflict(world, run, other) {
                    met[j] = Some(t);
                    return false;
                }
            }
            true
        };
        let mut k = 0u32;
        let chosen = loop {
            let start = lower + f64::from(k) / STARTS_PER_SECOND;
            if start >= others_done {
                let (a, run) = make_run(others_done);
                if safe(&run) {
                    break Some((a, run));
                }
                break None;
            }
            let (a, run) = make_run(start);
            if safe(&run) {
                break Some((a, run));
            }
            k += 1;
        };
        match chosen {
            Some(c) => placed.push(c),
            None => return one_after_another(robots, motions),
        }
    }
    placed.into_iter().map(|(a, _)| a).collect()
}

/// The action timed from `start` instead of 0 (the same profile, shifted).
fn shift(a: &TimedAction, start: f64) -> TimedAction {
    let s = |t: f64| t + start;
    TimedAction {
        start: s(a.start),
        grasp: a.grasp.map(s),
        release: a.release.map(s),
        clear: a.clear.map(s),
        end: s(a.end),
        points: a.points.iter().map(|p| TrajPoint { t: s(p.t), q: p.q.clone(), qd: p.qd.clone() }).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resolve::ObjectId;
    use rand::{RngExt, SeedableRng};

    /// A run of robot `r` from `a` to `b` over `[start, start + 1]`, at rest at both ends,
    /// at a constant acceleration each half (as the timing stage's profiles are: the speed
    /// linear between points), carrying `held` throughout.
    fn run(w: &World, r: RobotId, (a, b): (Vec<f64>, Vec<f64>), start: f64, held: Option<Held>) -> Run {
        let rest = vec![0.0; a.len()];
        let mid: Vec<f64> = a.iter().zip(&b).map(|(a, b)| 0.5 * (a + b)).collect();
        let peak: Vec<f64> = a.iter().zip(&b).map(|(a, b)| 2.0 * (b - a)).collect();
        let reach = w.joint_reach(r);
        let radius = held.as_ref().map_or(0.0, |h| w.held_radius(h));
        Run {
            robot: r,
            start,
            until: start + 1.0,
            points: vec![
                TrajPoint { t: start, q: a, qd: rest.clone() },
                TrajPoint { t: start + 0.5, q: mid, qd: peak },
                TrajPoint { t: start + 1.0, q: b, qd: rest },
            ],
            hold: held.map(|h| (start, start + 1.0, h)),
            reach: reach.bodies.clone(),
            reach_held: reach.with_held(radius),
        }
    }

    /// Wherever `surely_near` says two runs come nearer than the separation, the walk of
    /// `conflict` finds a conflict too, no later: the starts it rules out are the ones the
    /// walk rules out. Two arms over a crate moving between random configurations near
    /// home, sometimes carrying a lid.
    #[test]
    fn an_instant_surely_near_is_a_conflict_the_walk_finds() {
        let w = crate::world::test_arms::example("split_lid");
        let (r0, r1) = (RobotId(0), RobotId(1));
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut draw = |r: RobotId| -> Vec<f64> {
            let home = w.home(r).to_vec();
            w.limits(r)
                .iter()
                .zip(&home)
                .map(|((lo, hi), h)| h + 0.4 * (lo + rng.random::<f64>() * (hi - lo) - h))
                .collect()
        };
        let (mut near, mut not_near, mut walked_into) = (0, 0, 0);
        for i in 0..150 {
            let (a0, b0, a1, b1) = (draw(r0), draw(r0), draw(r1), draw(r1));
            let h0 = (i % 3 == 1).then(|| w.held(r0, ObjectId(1), 0, &a0));
            let h1 = (i % 4 == 2).then(|| w.held(r1, ObjectId(2), 0, &a1));
            let x = run(&w, r0, (a0, b0), 0.0, h0);
            let y = run(&w, r1, (a1, b1), f64::from(i % 5) * 0.1 - 0.2, h1);
            let found = conflict(&w, &x, &y);
            walked_into += usize::from(found.is_some());
            for k in 0..24 {
                let t = -0.2 + 1.4 * f64::from(k) / 24.0;
                if surely_near(&w, &x, &y, t) {
                    near += 1;
                    assert!(found.is_some_and(|c| c <= t), "draw {i}: surely near at {t}, the walk found {found:?}");
                } else {
                    not_near += 1;
                }
            }
        }
        // Not vacuous: instants of both kinds, and walks that find nothing.
        assert!(
            near > 50 && not_near > 50 && walked_into < 150,
            "{near} near, {not_near} not, {walked_into} conflicts"
        );
    }
}
