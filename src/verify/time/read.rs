//! Names to ids: a timed schedule's trajectories and events as the replay reads them.

use super::{Event, EventKind, TimeViolation, TimedPoint, Track};
use crate::verify::Violation;
use crate::world::World;

/// A trajectory as written: its robot and joint names must be the scenario's and the
/// URDF's, in configuration order. `None` (with the violation in `out`) when they are not.
pub fn track(
    world: &World,
    robot: &str,
    joint_names: &[String],
    points: impl IntoIterator<Item = TimedPoint>,
    out: &mut Vec<Violation>,
) -> Option<Track> {
    let scn = world.scenario();
    let Some(r) = scn.robot_by_name(robot) else {
        out.push(Violation::timed(None, TimeViolation::UnknownTrackRobot { name: robot.to_string() }));
        return None;
    };
    let expected = world.joint_names(r);
    if joint_names != expected {
        let v = TimeViolation::JointNames {
            robot: robot.to_string(),
            expected: expected.join(", "),
            found: joint_names.join(", "),
        };
        out.push(Violation::timed(None, v));
        return None;
    }
    Some(Track { robot: r, points: points.into_iter().collect() })
}

/// An event as written; `None` (with the violation in `out`) when a name is unknown.
pub fn event(
    world: &World,
    t: f64,
    robot: &str,
    kind: EventKind,
    object: &str,
    fingers: &[f64],
    out: &mut Vec<Violation>,
) -> Option<Event> {
    let scn = world.scenario();
    let (r, o) = (scn.robot_by_name(robot), scn.object_by_name(object));
    for (name, known) in [(robot, r.is_some()), (object, o.is_some())] {
        if !known {
            out.push(Violation::timed(Some(t), TimeViolation::UnknownEventName { name: name.to_string(), kind }));
        }
    }
    Some(Event { t, robot: r?, kind, object: o?, fingers: fingers.to_vec() })
}
