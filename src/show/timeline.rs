//! When each robot is where: the schedule's own trajectories and events, read for the
//! page. This is the one place that knows where time comes from; the keyframe sampler
//! only asks a [`Timeline`] for `q(t)`.
//!
//! Between two points of a trajectory the motion is the cubic Hermite curve through
//! their positions and velocities ([`timing::hermite`]), as the schedule format says and
//! a ROS controller plays it; robots move at once wherever the schedule has them do so.
//! A point the robot cannot take (wrong length, not finite) is left out: `verify`
//! reports it, and the page shows its report.

use crate::resolve::{ObjectId, RobotId};
pub use crate::schedule::EventKind;
use crate::schedule::Schedule;
use crate::timing::{self, TrajPoint};
use crate::verify::Phase;
use crate::world::World;

/// A robot's motion: still before the first point and after the last.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    pub points: Vec<TrajPoint>,
}

impl Track {
    /// Joint values at `t`.
    pub fn sample(&self, t: f64) -> Vec<f64> {
        timing::hermite(&self.points, t)
    }
}

/// A schedule's event with its robot and object resolved in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    pub t: f64,
    pub robot: RobotId,
    pub kind: EventKind,
    pub object: ObjectId,
}

/// When one action runs, and when each of its waypoints is reached.
#[derive(Clone, Debug, PartialEq)]
pub struct ActionSpan {
    pub id: u32,
    pub robot: Option<RobotId>,
    pub start: f64,
    pub end: f64,
    pub approach_t: Vec<f64>,
    pub retreat_t: Vec<f64>,
}

impl ActionSpan {
    /// The time of a waypoint, if the action has it and its trajectory passes it.
    pub fn waypoint_t(&self, phase: Phase, index: usize) -> Option<f64> {
        match phase {
            Phase::Approach => self.approach_t.get(index).copied(),
            Phase::Retreat => self.retreat_t.get(index).copied(),
        }
        .filter(|t| t.is_finite())
    }
}

/// Every robot's motion over the whole schedule.
#[derive(Clone, Debug, PartialEq)]
pub struct Timeline {
    /// One per robot, in scenario order; a robot without a trajectory stays at home.
    pub tracks: Vec<Track>,
    pub events: Vec<Event>,
    pub actions: Vec<ActionSpan>,
    pub duration: f64,
}

/// How close (joint space, max over joints) a trajectory point must be to a waypoint to
/// be where the robot reaches it.
const AT_WAYPOINT: f64 = 1e-6;

fn near(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= AT_WAYPOINT)
}

/// The timeline a schedule states; without a schedule, every robot at home.
pub fn timeline(world: &World, schedule: Option<&Schedule>) -> Timeline {
    let scn = world.scenario();
    let home = |r: RobotId| Track {
        points: vec![TrajPoint { t: 0.0, q: world.home(r).to_vec(), qd: vec![0.0; world.dof(r)] }],
    };
    let Some(s) = schedule else {
        return Timeline {
            tracks: scn.robot_ids().map(home).collect(),
            events: Vec::new(),
            actions: Vec::new(),
            duration: 0.0,
        };
    };
    let tracks: Vec<Track> = scn
        .robot_ids()
        .map(|r| {
            let dof = world.dof(r);
            let usable = |p: &&TrajPoint| {
                p.t.is_finite()
                    && p.q.len() == dof
                    && p.qd.len() == dof
                    && p.q.iter().chain(&p.qd).all(|v| v.is_finite())
            };
            let name = &scn.robot(r).name;
            let points: Vec<TrajPoint> = s
                .trajectories
                .iter()
                .find(|tr| &tr.robot == name)
                .map(|tr| tr.points.iter().filter(usable).cloned().collect())
                .unwrap_or_default();
            if points.is_empty() {
                home(r)
            } else {
                Track { points }
            }
        })
        .collect();
    let events = s
        .events
        .iter()
        .filter_map(|e| {
            Some(Event {
                t: e.t,
                robot: scn.robot_by_name(&e.robot)?,
                kind: e.kind,
                object: scn.object_by_name(&e.object)?,
            })
        })
        .filter(|e| e.t.is_finite())
        .collect();
    let actions = s
        .actions
        .iter()
        .map(|a| {
            let robot = scn.robot_by_name(&a.robot);
            // Each waypoint at the first point, from the action's start on, that is at it.
            let mut from = a.start;
            let mut times = |waypoints: &[Vec<f64>]| -> Vec<f64> {
                waypoints
                    .iter()
                    .map(|w| {
                        let hit = robot.and_then(|r| {
                            tracks[r.index()]
                                .points
                                .iter()
                                .find(|p| p.t >= from - 1e-9 && p.t <= a.end + 1e-9 && near(&p.q, w))
                        });
                        match hit {
                            Some(p) => {
                                from = p.t;
                                p.t
                            }
                            None => f64::NAN,
                        }
                    })
                    .collect()
            };
            let approach_t = times(&a.approach);
            let retreat_t = times(&a.retreat);
            ActionSpan { id: a.id, robot, start: a.start, end: a.end, approach_t, retreat_t }
        })
        .collect();
    let last_point = tracks.iter().filter_map(|tr| tr.points.last()).map(|p| p.t).fold(0.0, f64::max);
    let duration = if s.makespan.is_finite() && s.makespan >= 0.0 { s.makespan.max(last_point) } else { last_point };
    Timeline { tracks, events, actions, duration }
}
