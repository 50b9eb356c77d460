//! When each robot is where: the schedule as joint values over time, and the moments
//! objects are grasped and released. This is the one place that knows where time comes
//! from; the sampler in `keyframes` only asks a [`Timeline`] for `q(t)`.
//!
//! Today's schedules carry no time, so [`untimed`] gives one: actions one after another
//! in id order, each segment taking as long as its largest joint move at
//! [`NOMINAL_SPEED`]. A timed schedule will fill the same struct from its trajectories.

use crate::resolve::{ObjectId, RobotId, Target};
use crate::schedule::{Schedule, ScheduledAction};
use crate::verify::Phase;
use crate::world::World;

/// Joint speed of the nominal timing (rad/s, or m/s for a sliding joint).
pub const NOMINAL_SPEED: f64 = 1.0;
/// Pause at a grasp and at a release, so the moment can be seen.
const DWELL: f64 = 0.3;
/// No segment is shorter than this, so a tiny move still shows.
const MIN_SEGMENT: f64 = 0.05;

/// One robot's joint values at a time.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub t: f64,
    pub q: Vec<f64>,
}

/// A robot's motion: straight joint-space moves between points, still before the first
/// and after the last.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    pub points: Vec<Point>,
}

impl Track {
    /// Joint values at `t`, interpolated.
    pub fn sample(&self, t: f64) -> Vec<f64> {
        let p = &self.points;
        let k = p.partition_point(|x| x.t <= t);
        if k == 0 {
            return p[0].q.clone();
        }
        if k == p.len() {
            return p[k - 1].q.clone();
        }
        let (a, b) = (&p[k - 1], &p[k]);
        let s = if b.t > a.t { (t - a.t) / (b.t - a.t) } else { 1.0 };
        a.q.iter().zip(&b.q).map(|(x, y)| x + (y - x) * s).collect()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventKind {
    Grasp,
    Release,
}

/// The hand closes on, or lets go of, an object.
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
    /// The time of a waypoint, if the action has it.
    pub fn waypoint_t(&self, phase: Phase, index: usize) -> Option<f64> {
        match phase {
            Phase::Approach => self.approach_t.get(index).copied(),
            Phase::Retreat => self.retreat_t.get(index).copied(),
        }
    }
}

/// Every robot's motion over the whole schedule.
#[derive(Clone, Debug, PartialEq)]
pub struct Timeline {
    /// One per robot, in scenario order; a robot that never moves stays at home.
    pub tracks: Vec<Track>,
    pub events: Vec<Event>,
    pub actions: Vec<ActionSpan>,
    pub duration: f64,
}

/// True when `q` can be put through the robot's kinematics.
fn usable(world: &World, r: RobotId, q: &[f64]) -> bool {
    q.len() == world.dof(r) && q.iter().all(|v| v.is_finite())
}

fn near(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-6)
}

/// The timeline of a schedule without time: actions in id order, one after another.
/// Waypoints the robot cannot take (wrong length, not finite) are skipped: `verify`
/// reports them, and the page shows its report.
pub fn untimed(world: &World, schedule: Option<&Schedule>) -> Timeline {
    let scn = world.scenario();
    let mut tracks: Vec<Track> =
        scn.robot_ids().map(|r| Track { points: vec![Point { t: 0.0, q: world.home(r).to_vec() }] }).collect();
    let mut events = Vec::new();
    let mut spans = Vec::new();
    let mut t = 0.0;
    let mut order: Vec<&ScheduledAction> = schedule.map(|s| s.actions.iter().collect()).unwrap_or_default();
    order.sort_by_key(|a| a.id);
    let target = match scn.target {
        Target::Object { object, .. } => Some(object),
        Target::Config { .. } => None,
    };
    for a in order {
        let start = t;
        let robot = scn.robot_by_name(&a.robot);
        let mut times = [Vec::new(), Vec::new()];
        if let Some(r) = robot {
            let object = a.object.as_deref().and_then(|n| scn.object_by_name(n));
            let track = &mut tracks[r.index()];
            // Where the object is let go: the first retreat waypoint at `drop`, else the last.
            let drop = world.drop_config(r);
            let release = a.retreat.iter().position(|q| near(q, drop)).unwrap_or(a.retreat.len().saturating_sub(1));
            for (phase, waypoints) in [a.approach.as_slice(), a.retreat.as_slice()].into_iter().enumerate() {
                for (i, q) in waypoints.iter().enumerate() {
                    if usable(world, r, q) {
                        let last = &track.points[track.points.len() - 1];
                        let step = last.q.iter().zip(q).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
                        t += (step / NOMINAL_SPEED).max(MIN_SEGMENT);
                        track.points.push(Point { t, q: q.clone() });
                    }
                    times[phase].push(t);
                    let at_grasp = phase == 0 && i + 1 == waypoints.len();
                    let at_release = phase == 1 && i == release && object != target;
                    if let (Some(o), true) = (object, at_grasp || at_release) {
                        let kind = if at_grasp { EventKind::Grasp } else { EventKind::Release };
                        events.push(Event { t, robot: r, kind, object: o });
                        // Hold still for a moment.
                        let q = track.points[track.points.len() - 1].q.clone();
                        t += DWELL;
                        track.points.push(Point { t, q });
                    }
                }
            }
        }
        let [approach_t, retreat_t] = times;
        spans.push(ActionSpan { id: a.id, robot, start, end: t, approach_t, retreat_t });
    }
    Timeline { tracks, events, actions: spans, duration: t }
}
