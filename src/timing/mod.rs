//! Timing: planned joint paths -> timed trajectories and a timeline of actions.
//!
//! In: the world (joint limits, for the concurrent search its collision checks) and the
//! planned actions as [`Motion`]s. Out: a [`Timeline`] — each action's start, grasp,
//! release and end in seconds, and one [`Trajectory`] per robot covering 0..makespan.
//! The planner says *where*, timing says *when*; this stage never changes a path.
//!
//! The timing model: between consecutive waypoints a robot makes a synchronised
//! point-to-point move along the straight joint-space segment ([`Profile`]): all
//! joints start and stop together, the slowest joint sets the pace, each joint stays
//! within `speed ×` its URDF velocity limit and `speed × acceleration`. A robot
//! stops (q̇ = 0) at every waypoint, so a waypoint is a safe place to wait. The gripper
//! closes at the end of the approach and opens at the first retreat waypoint at the
//! drop configuration, both instantly.
//!
//! Points are the segment ends and the phase boundaries inside each segment; between
//! two consecutive points the motion is a polynomial of degree ≤ 2, so cubic Hermite
//! interpolation on (q, q̇) — what ROS's joint_trajectory_controller does with positions
//! and velocities — reproduces it exactly ([`Trajectory::at`]).

mod concurrent;
mod profile;

pub use concurrent::{SEPARATION, START_STEP};
pub use profile::{Limits, Profile};

use serde::{Deserialize, Serialize};

use crate::resolve::{ObjectId, RobotId};
use crate::world::{Config, World};

/// When actions run: one after another, or at the same time wherever that is safe.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Execution {
    /// Each action starts when the previous one has ended.
    Sequential,
    /// Actions overlap where the time-sampled check finds no contact (see `concurrent`).
    #[default]
    Concurrent,
}

/// One sample of a trajectory: `t` seconds from the start, positions and velocities.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrajPoint {
    pub t: f64,
    #[serde(serialize_with = "flow")]
    pub q: Vec<f64>,
    #[serde(serialize_with = "flow")]
    pub qd: Vec<f64>,
}

/// `[a, b, c]` on one line in YAML; a plain array in JSON.
fn flow<S: serde::Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&serde_saphyr::FlowSeq(v), s)
}

/// A robot's whole timed motion, shaped like ROS's `trajectory_msgs/JointTrajectory`.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    pub joint_names: Vec<String>,
    pub points: Vec<TrajPoint>,
}

impl Trajectory {
    /// The configuration at `t` by cubic Hermite interpolation between the points around
    /// it (held before the first point and after the last).
    pub fn at(&self, t: f64) -> Vec<f64> {
        hermite(&self.points, t)
    }
}

/// Cubic Hermite interpolation on (q, qd) of time-ordered `points` at `t`.
pub fn hermite(points: &[TrajPoint], t: f64) -> Vec<f64> {
    let (Some(first), Some(last)) = (points.first(), points.last()) else { return Vec::new() };
    if t <= first.t {
        return first.q.clone();
    }
    if t >= last.t {
        return last.q.clone();
    }
    let k = points.partition_point(|p| p.t <= t).clamp(1, points.len() - 1);
    let (p0, p1) = (&points[k - 1], &points[k]);
    let h = p1.t - p0.t;
    if h <= 0.0 {
        return p1.q.clone();
    }
    let u = (t - p0.t) / h;
    let (u2, u3) = (u * u, u * u * u);
    let (h00, h10, h01, h11) = (2.0 * u3 - 3.0 * u2 + 1.0, u3 - 2.0 * u2 + u, -2.0 * u3 + 3.0 * u2, u3 - u2);
    (0..p0.q.len()).map(|i| h00 * p0.q[i] + h10 * h * p0.qd[i] + h01 * p1.q[i] + h11 * h * p1.qd[i]).collect()
}

/// What timing needs of one robot.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotTiming {
    pub joint_names: Vec<String>,
    pub limits: Limits,
    pub home: Vec<f64>,
    pub drop: Vec<f64>,
}

impl RobotTiming {
    /// Robot `r` of a world: URDF velocities, and accelerations from the URDF where it
    /// has them (Drake's `drake:acceleration`) or the planner's `acceleration`, all
    /// scaled by the planner's `speed`.
    pub fn of(world: &World, r: RobotId) -> RobotTiming {
        let p = &world.scenario().planner;
        RobotTiming {
            joint_names: world.joint_names(r).to_vec(),
            limits: Limits {
                velocity: world.velocity_limits(r).iter().map(|v| v * p.speed).collect(),
                acceleration: world.acceleration_limits(r).iter().map(|a| a * p.speed).collect(),
            },
            home: world.home(r).0.clone(),
            drop: world.drop_config(r).0.clone(),
        }
    }
}

/// Every robot of a world, in id order.
pub fn robots(world: &World) -> Vec<RobotTiming> {
    world.scenario().robot_ids().map(|r| RobotTiming::of(world, r)).collect()
}

/// Points of a waypoint path timed from `t0`, the first waypoint included; zero-length
/// segments (repeated waypoints) take no time and add no point.
pub fn time_path(path: &[Config], lim: &Limits, t0: f64) -> Vec<TrajPoint> {
    let Some(first) = path.first() else { return Vec::new() };
    let n = first.0.len();
    let mut out = vec![TrajPoint { t: t0, q: first.0.clone(), qd: vec![0.0; n] }];
    let mut t = t0;
    for w in path.windows(2) {
        let (a, b) = (&w[0].0, &w[1].0);
        let Some(p) = Profile::between(a, b, lim) else { continue };
        for k in p.knots() {
            let (s, sd) = p.at(k);
            out.push(TrajPoint {
                t: t + k,
                q: (0..n).map(|i| a[i] + s * (b[i] - a[i])).collect(),
                qd: (0..n).map(|i| sd * (b[i] - a[i])).collect(),
            });
        }
        t += p.duration;
        out.push(TrajPoint { t, q: b.clone(), qd: vec![0.0; n] });
    }
    out
}

/// One planned action as timing sees it.
#[derive(Clone, Copy, Debug)]
pub struct Motion<'a> {
    pub robot: RobotId,
    /// The object grasped at the end of the approach (`None` for a configuration target).
    pub object: Option<ObjectId>,
    /// The grasp's index among the object's grasps.
    pub grasp: Option<usize>,
    pub approach: &'a [Config],
    pub retreat: &'a [Config],
    /// Indices of the actions that must have removed their objects first.
    pub after: &'a [usize],
}

/// An action placed in time (seconds from the schedule's start).
#[derive(Clone, Debug, PartialEq)]
pub struct TimedAction {
    pub start: f64,
    /// When the gripper closes (end of the approach), if it grasps an object.
    pub grasp: Option<f64>,
    /// When the object is put down (first retreat waypoint at the drop configuration).
    pub release: Option<f64>,
    /// When the object is clear of its resting place: the pre-grasp stand-off (the
    /// first retreat waypoint after the grasp) is reached.
    pub clear: Option<f64>,
    pub end: f64,
    /// The action's own points, absolute times.
    pub points: Vec<TrajPoint>,
}

/// Every action in time, and one trajectory per robot (robot id order).
#[derive(Clone, Debug, PartialEq)]
pub struct Timeline {
    pub execution: Execution,
    pub actions: Vec<TimedAction>,
    pub trajectories: Vec<Trajectory>,
    pub makespan: f64,
}

/// Tolerance (rad or m) for "this waypoint is the drop configuration".
const AT_DROP: f64 = 1e-9;

/// Times one action of robot `rt` from `start`.
pub fn time_action(rt: &RobotTiming, m: &Motion, start: f64) -> TimedAction {
    let lim = &rt.limits;
    let mut points = time_path(m.approach, lim, start);
    let end_approach = points.last().map_or(start, |p| p.t);
    let mut grasp = None;
    let mut release = None;
    let mut clear = None;
    if m.object.is_some() && !m.retreat.is_empty() {
        grasp = Some(end_approach);
        let drop = &rt.drop;
        let at_drop = m
            .retreat
            .iter()
            .skip(1)
            .position(|q| q.0.len() == drop.len() && q.0.iter().zip(drop).all(|(a, b)| (a - b).abs() <= AT_DROP))
            .map_or(m.retreat.len() - 1, |i| i + 1);
        // Per-waypoint arrival times of the retreat: time it piecewise.
        let mut t = end_approach;
        for (i, w) in m.retreat.windows(2).enumerate() {
            let seg = time_path(w, lim, t);
            t = seg.last().map_or(t, |p| p.t);
            points.extend(seg.into_iter().skip(1));
            if i == 0 {
                clear = Some(t);
            }
            if i + 1 == at_drop {
                release = Some(t);
            }
        }
        if m.retreat.len() == 1 {
            clear = Some(t);
            release = Some(t);
        }
    } else {
        let lim_points = time_path(m.retreat, lim, end_approach);
        points.extend(lim_points.into_iter().skip(1));
    }
    let end = points.last().map_or(start, |p| p.t);
    TimedAction { start, grasp, release, clear, end, points }
}

/// Times every action of a world: one after another, or concurrently (see `concurrent`).
pub fn timeline(world: &World, motions: &[Motion], execution: Execution) -> Timeline {
    let robots = robots(world);
    match execution {
        Execution::Sequential => sequential(&robots, motions),
        Execution::Concurrent => {
            let actions = concurrent::place(world, &robots, motions);
            assemble(&robots, motions, actions, execution)
        }
    }
}

/// Each action starts when the previous one has ended (needs no collision checks, so
/// no world: `robots` indexed by robot id).
pub fn sequential(robots: &[RobotTiming], motions: &[Motion]) -> Timeline {
    assemble(robots, motions, one_after_another(robots, motions), Execution::Sequential)
}

/// Each action timed from the end of the previous one.
fn one_after_another(robots: &[RobotTiming], motions: &[Motion]) -> Vec<TimedAction> {
    let mut t = 0.0;
    motions
        .iter()
        .map(|m| {
            let a = time_action(&robots[m.robot.index()], m, t);
            t = a.end;
            a
        })
        .collect()
}

/// Per-robot trajectories from the timed actions: each robot holds still at home
/// (or where its last action left it) between its actions, and until the makespan.
fn assemble(robots: &[RobotTiming], motions: &[Motion], actions: Vec<TimedAction>, execution: Execution) -> Timeline {
    let makespan = actions.iter().map(|a| a.end).fold(0.0, f64::max);
    let trajectories = robots
        .iter()
        .enumerate()
        .map(|(ri, rt)| {
            let n = rt.home.len();
            let mut points = vec![TrajPoint { t: 0.0, q: rt.home.clone(), qd: vec![0.0; n] }];
            let mut mine: Vec<&TimedAction> =
                motions.iter().zip(&actions).filter(|(m, _)| m.robot.index() == ri).map(|(_, a)| a).collect();
            mine.sort_by(|a, b| a.start.total_cmp(&b.start));
            for a in mine {
                let last = points.last().cloned().expect("starts with one point");
                if a.start > last.t {
                    points.push(TrajPoint { t: a.start, q: last.q, qd: vec![0.0; n] });
                }
                points.extend(a.points.iter().skip(1).cloned());
            }
            if let Some(last) = points.last().cloned() {
                if makespan > last.t {
                    points.push(TrajPoint { t: makespan, q: last.q, qd: vec![0.0; n] });
                }
            }
            Trajectory { joint_names: rt.joint_names.clone(), points }
        })
        .collect();
    Timeline { execution, actions, trajectories, makespan }
}
