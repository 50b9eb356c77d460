//! What the replay in time reports: each violation names the instant, the robots and
//! bodies, and what was hit.

use std::fmt;

use crate::verify::Phase;

/// A moving thing: a robot's body, or an object a robot carries.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Party {
    Body { robot: String, body: String },
    Held { robot: String, object: String },
}

/// What a moving thing touched.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Obstacle {
    /// Another robot's body or carried object, or a body of the same robot (self-collision).
    Moving(Party),
    Fixed(String),
    /// An object still in place.
    Object(String),
}

#[derive(Clone, Debug, PartialEq)]
pub enum TimeViolation {
    /// Two things closer than allowed: overlapping (`distance` is `None`), or nearer than
    /// the demanded clearance.
    Contact {
        a: Party,
        b: Obstacle,
        distance: Option<f64>,
        clearance: f64,
    },
    /// A trajectory for a robot the scenario does not have.
    UnknownTrackRobot {
        name: String,
    },
    /// A trajectory whose joint names are not the robot's, in configuration order.
    JointNames {
        robot: String,
        expected: String,
        found: String,
    },
    /// An event naming a robot or object the scenario does not have.
    UnknownEventName {
        name: String,
        kind: EventKind,
    },
    /// No trajectory for a robot of the scenario, or two.
    TrackCount {
        robot: String,
        found: usize,
    },
    EmptyTrack {
        robot: String,
    },
    /// Point `index` has not as many values as the robot has joints.
    TrackPointLength {
        robot: String,
        index: usize,
        expected: usize,
        found: usize,
    },
    /// A time, position or velocity that is not a finite number.
    NotFinite {
        robot: String,
        index: usize,
    },
    /// Times must rise strictly from point to point.
    TimeNotIncreasing {
        robot: String,
        index: usize,
    },
    /// The trajectory must run from t = 0 to the makespan.
    DoesNotCover {
        robot: String,
        first: f64,
        last: f64,
        makespan: f64,
    },
    OutOfLimits {
        robot: String,
        joint: String,
        value: f64,
        lo: f64,
        hi: f64,
    },
    TooFast {
        robot: String,
        joint: String,
        speed: f64,
        limit: f64,
    },
    TooHardAcceleration {
        robot: String,
        joint: String,
        acceleration: f64,
        limit: f64,
    },
    /// The action's waypoint does not occur in its robot's trajectory between its start and end.
    WaypointSkipped {
        action: u32,
        phase: Phase,
        index: usize,
    },
    /// The action starts after it ends, or outside 0..makespan.
    BadInterval {
        action: u32,
        start: f64,
        end: f64,
    },
    /// The trajectory leaves the joint-space line of the straight move in to the grasp.
    LeavesApproachLine {
        action: u32,
        deviation: f64,
    },
    EventMissing {
        action: u32,
        kind: EventKind,
        object: String,
    },
    /// The event happens where the robot is not at the grasp (or the drop) configuration.
    EventMisplaced {
        action: u32,
        kind: EventKind,
        object: String,
        t: f64,
        distance: f64,
    },
    /// The event sets the fingers otherwise than the scenario closes (or opens) them.
    FingersWrong {
        action: u32,
        kind: EventKind,
        object: String,
        t: f64,
        expected: Vec<f64>,
        found: Vec<f64>,
    },
    /// An event no action explains, or a second one for the same action.
    UnexpectedEvent {
        robot: String,
        kind: EventKind,
        object: String,
        t: f64,
    },
    /// The release comes before the grasp.
    ReleaseBeforeGrasp {
        action: u32,
        object: String,
    },
    /// The action starts before an object it waits for has been carried clear.
    StartsBeforeClear {
        action: u32,
        object: String,
        by: u32,
        start: f64,
        clear: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum EventKind {
    Grasp,
    Release,
}

impl fmt::Display for EventKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            EventKind::Grasp => "grasp",
            EventKind::Release => "release",
        })
    }
}

impl fmt::Display for Party {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Party::Body { robot, body } => write!(f, "robot `{robot}` body `{body}`"),
            Party::Held { robot, object } => write!(f, "`{object}` carried by robot `{robot}`"),
        }
    }
}

impl fmt::Display for Obstacle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Obstacle::Moving(p) => p.fmt(f),
            Obstacle::Fixed(name) => write!(f, "fixed body `{name}`"),
            Obstacle::Object(name) => write!(f, "object `{name}` (still in place)"),
        }
    }
}

impl fmt::Display for TimeViolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use TimeViolation::*;
        match self {
            Contact { a, b, distance: None, .. } => write!(f, "{a} touches {b}"),
            Contact { a, b, distance: Some(d), clearance } => write!(
                f,
                "{a} is {:.2} mm from {b}; the clearance asked for is {:.2} mm",
                d.max(0.0) * 1e3,
                clearance * 1e3
            ),
            UnknownTrackRobot { name } => write!(f, "a trajectory for `{name}`, which is no robot of the scenario"),
            JointNames { robot, expected, found } => write!(
                f,
                "the trajectory of robot `{robot}` names joints [{found}]; the robot's are [{expected}], in that order"
            ),
            UnknownEventName { name, kind } => {
                write!(f, "a `{kind}` event names `{name}`, which is no robot or removable object of the scenario")
            }
            TrackCount { robot, found: 0 } => write!(f, "robot `{robot}` has no trajectory"),
            TrackCount { robot, found } => write!(f, "robot `{robot}` has {found} trajectories; one is expected"),
            EmptyTrack { robot } => write!(f, "the trajectory of robot `{robot}` has no points"),
            TrackPointLength { robot, index, expected, found } => write!(
                f,
                "point {index} of robot `{robot}`'s trajectory has {found} values; the robot has {expected} joints"
            ),
            NotFinite { robot, index } => {
                write!(f, "point {index} of robot `{robot}`'s trajectory holds a value that is not a finite number")
            }
            TimeNotIncreasing { robot, index } => {
                write!(f, "point {index} of robot `{robot}`'s trajectory is not later than the point before it")
            }
            DoesNotCover { robot, first, last, makespan } => write!(
                f,
                "the trajectory of robot `{robot}` runs from {first:.3} s to {last:.3} s; it must cover 0 to the \
                 makespan, {makespan:.3} s"
            ),
            OutOfLimits { robot, joint, value, lo, hi } => {
                write!(f, "robot `{robot}` joint `{joint}` is at {value:.6}, outside its limits [{lo:.6}, {hi:.6}]")
            }
            TooFast { robot, joint, speed, limit } => write!(
                f,
                "robot `{robot}` joint `{joint}` moves at {speed:.4}/s, above its limit {limit:.4}/s (URDF `velocity` × \
                 `speed`)"
            ),
            TooHardAcceleration { robot, joint, acceleration, limit } => write!(
                f,
                "robot `{robot}` joint `{joint}` accelerates at {acceleration:.4}/s², above the limit {limit:.4}/s² \
                 (the URDF's or the planner's `acceleration`, × `speed`)"
            ),
            WaypointSkipped { action, phase, index } => write!(
                f,
                "action {action}: {phase} waypoint {index} is not a point of the robot's trajectory between the \
                 action's start and end (in order)"
            ),
            BadInterval { action, start, end } => {
                write!(f, "action {action} runs from {start:.3} s to {end:.3} s, not within 0..makespan in order")
            }
            LeavesApproachLine { action, deviation } => write!(
                f,
                "action {action}: the trajectory strays {deviation:.2e} from the straight joint-space move in to the \
                 grasp, where the grasped object is not an obstacle"
            ),
            EventMissing { action, kind, object } => write!(f, "action {action}: no `{kind}` event for `{object}`"),
            EventMisplaced { action, kind, object, t, distance } => {
                let at = match kind {
                    EventKind::Grasp => "grasp",
                    EventKind::Release => "drop",
                };
                write!(
                    f,
                    "action {action}: the `{kind}` of `{object}` at {t:.3} s is where the robot is {distance:.2e} \
                     (joint space) away from its {at} configuration"
                )
            }
            FingersWrong { action, kind, object, t, expected, found } => {
                let list = |v: &[f64]| v.iter().map(|x| format!("{x:.4}")).collect::<Vec<_>>().join(", ");
                write!(
                    f,
                    "action {action}: the `{kind}` of `{object}` at {t:.3} s sets the fingers to [{}], but the scenario says [{}]",
                    list(found),
                    list(expected)
                )
            }
            UnexpectedEvent { robot, kind, object, t } => {
                write!(f, "the `{kind}` of `{object}` by robot `{robot}` at {t:.3} s belongs to no action")
            }
            ReleaseBeforeGrasp { action, object } => {
                write!(f, "action {action}: `{object}` is released before it is grasped")
            }
            StartsBeforeClear { action, object, by, start, clear } => write!(
                f,
                "action {action} starts at {start:.3} s, before `{object}` (removed by action {by}) is carried clear \
                 at {clear:.3} s"
            ),
        }
    }
}
