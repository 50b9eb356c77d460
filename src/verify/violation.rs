//! What `verify` reports: one violation per broken rule, located by action, phase and
//! waypoint or segment.

use std::fmt;

use crate::world::ApproachDeviation;

/// Which half of an action a waypoint or segment belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Approach,
    Retreat,
}

impl fmt::Display for Phase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Phase::Approach => "approach",
            Phase::Retreat => "retreat",
        })
    }
}

/// Where in the schedule a violation is.
#[derive(Clone, Debug, PartialEq)]
pub enum Location {
    Schedule,
    Action(u32),
    Waypoint {
        action: u32,
        phase: Phase,
        index: usize,
    },
    /// Segment `index` runs from waypoint `index` to waypoint `index + 1`.
    Segment {
        action: u32,
        phase: Phase,
        index: usize,
    },
    /// An instant of the timed schedule (seconds from its start).
    At {
        t: f64,
    },
}

/// One broken rule.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    pub location: Location,
    pub kind: ViolationKind,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ViolationKind {
    NotSolved,
    /// A schedule of another format version.
    Version {
        found: u32,
    },
    /// The schedule's `scenario` is not this scenario's name.
    ScenarioMismatch {
        expected: String,
        found: String,
    },
    /// The schedule's `target` is not this scenario's target.
    TargetMismatch {
        expected: String,
        found: String,
    },
    BadId {
        expected: u32,
    },
    BadAfter {
        dep: u32,
    },
    /// `after` names the same action twice.
    DuplicateAfter {
        dep: u32,
    },
    UnknownRobot {
        name: String,
    },
    UnknownObject {
        name: String,
    },
    AlreadyRemoved {
        object: String,
    },
    WrongLength {
        expected: usize,
        found: usize,
    },
    OutOfLimits {
        joint: String,
        value: f64,
        lo: f64,
        hi: f64,
    },
    NotAtHome,
    EmptyApproach,
    EmptyRetreat,
    RetreatNotFromGrasp,
    /// The retreat never passes the robot's drop configuration, so the object is never released.
    NoDrop,
    MissingGrasp,
    UnknownGrasp {
        name: String,
        object: String,
    },
    GraspNotForHand {
        grasp: String,
    },
    MissesGrasp {
        grasp: String,
        distance: f64,
        angle: f64,
    },
    ReachNotTarget,
    /// A reach of the target configuration followed by other actions.
    ReachNotLast,
    /// The approach's last segment, where the grasped object is ignored, is not the
    /// straight move in.
    CrookedApproach {
        grasp: String,
        deviation: ApproachDeviation,
    },
    /// A reach (no object) that names a grasp.
    GraspOnReach {
        grasp: String,
    },
    /// A reach (no object) with retreat waypoints: it ends at the target.
    RetreatOnReach,
    TargetNotLast,
    RemovedListMismatch {
        expected: String,
    },
    /// Found by replaying the schedule in time.
    Time(super::time::TimeViolation),
}

impl Violation {
    pub fn general(kind: ViolationKind) -> Violation {
        Violation { location: Location::Schedule, kind }
    }
    pub fn at(action: u32, kind: ViolationKind) -> Violation {
        Violation { location: Location::Action(action), kind }
    }
    pub fn waypoint(action: u32, phase: Phase, index: usize, kind: ViolationKind) -> Violation {
        Violation { location: Location::Waypoint { action, phase, index }, kind }
    }
    pub fn segment(action: u32, phase: Phase, index: usize, kind: ViolationKind) -> Violation {
        Violation { location: Location::Segment { action, phase, index }, kind }
    }
    /// Found by the replay in time: at instant `t`, or for the whole schedule when `None`.
    pub fn timed(t: Option<f64>, v: super::time::TimeViolation) -> Violation {
        let location = t.map_or(Location::Schedule, |t| Location::At { t });
        Violation { location, kind: ViolationKind::Time(v) }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Schedule => f.write_str("schedule"),
            Location::Action(a) => write!(f, "action {a}"),
            Location::Waypoint { action, phase, index } => write!(f, "action {action}, {phase} waypoint {index}"),
            Location::Segment { action, phase, index } => {
                write!(f, "action {action}, {phase} segment {index}→{}", index + 1)
            }
            Location::At { t } => write!(f, "t = {t:.3} s"),
        }
    }
}

impl fmt::Display for ViolationKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ViolationKind::*;
        match self {
            NotSolved => f.write_str("the schedule is not solved (status is not `solved`)"),
            Version { found } => write!(
                f,
                "is of format version {found}; this declutter verifies version {}",
                crate::schedule::SCHEDULE_VERSION
            ),
            ScenarioMismatch { expected, found } => {
                write!(f, "is for scenario `{found}`, not `{expected}`")
            }
            TargetMismatch { expected, found } => write!(f, "its target is {found}; the scenario's is {expected}"),
            BadId { expected } => write!(f, "ids must run 1, 2, 3, … in order; expected {expected}"),
            BadAfter { dep } => write!(f, "waits for action {dep}, which does not run before it"),
            DuplicateAfter { dep } => write!(f, "lists action {dep} twice in `after`"),
            UnknownRobot { name } => write!(f, "no robot named `{name}` in the scenario"),
            UnknownObject { name } => write!(f, "no removable object named `{name}` in the scenario"),
            AlreadyRemoved { object } => write!(f, "`{object}` was already removed by an earlier action"),
            WrongLength { expected, found } => write!(f, "has {found} joint values; the robot has {expected} joints"),
            OutOfLimits { joint, value, lo, hi } => {
                write!(f, "joint `{joint}` is {}, outside its limits [{lo:.6}, {hi:.6}]", Value(*value))
            }
            NotAtHome => f.write_str("is not the robot's home configuration"),
            EmptyApproach => f.write_str("has no approach waypoints"),
            EmptyRetreat => f.write_str("has no retreat waypoints"),
            RetreatNotFromGrasp => f.write_str("the retreat does not start where the approach ends"),
            NoDrop => {
                f.write_str("the retreat never reaches the robot's drop configuration, where the object is released")
            }
            MissingGrasp => f.write_str("names no grasp"),
            UnknownGrasp { name, object } => write!(f, "object `{object}` has no grasp `{name}`"),
            GraspNotForHand { grasp } => write!(f, "grasp `{grasp}` is not for this robot's hand"),
            MissesGrasp { grasp, distance, angle } => write!(
                f,
                "the approach ends {:.2} mm and {:.3}° away from grasp `{grasp}` (allowed: 1 mm, 0.5°)",
                distance * 1e3,
                angle.to_degrees()
            ),
            ReachNotTarget => f.write_str("a reach action that does not end at the target configuration"),
            ReachNotLast => f.write_str("a reach of the target configuration must be the last action"),
            CrookedApproach { grasp, deviation: d } => write!(
                f,
                "is not the straight move in to grasp `{grasp}`: the TCP strays {:.2} mm from the approach line, \
                 goes {:.2} mm past the grasp and turns {:.3}° (allowed: {} mm, {} mm, {}°); the object is an \
                 obstacle everywhere else",
                d.off_line * 1e3,
                d.overshoot * 1e3,
                d.angle.to_degrees(),
                crate::world::APPROACH_LATERAL_TOLERANCE * 1e3,
                crate::world::APPROACH_OVERSHOOT_TOLERANCE * 1e3,
                crate::world::APPROACH_ANGLE_TOLERANCE.to_degrees().round(),
            ),
            GraspOnReach { grasp } => {
                write!(f, "names grasp `{grasp}`, but a reach of the target configuration grasps nothing")
            }
            RetreatOnReach => {
                f.write_str("a reach of the target configuration has retreat waypoints; it must end there")
            }
            TargetNotLast => f.write_str("the last action does not grasp (or reach) the target"),
            RemovedListMismatch { expected } => {
                write!(f, "`removed` does not list the grasped objects but the target in action order ({expected})")
            }
            Time(v) => v.fmt(f),
        }
    }
}

/// A joint value as read from a schedule: six decimals, or scientific notation when
/// huge, so a wild value stays one readable line.
struct Value(f64);

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.abs() >= 1e6 {
            write!(f, "{:.6e}", self.0)
        } else {
            write!(f, "{:.6}", self.0)
        }
    }
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.kind)
    }
}
