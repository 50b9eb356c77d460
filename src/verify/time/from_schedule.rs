//! A timed schedule (format version 2) as the replay reads it.

use super::read;
use super::{EventKind, TimedAction, TimedPoint, Timeline};
use crate::schedule::{self, Schedule};
use crate::verify::Violation;
use crate::world::World;

/// The schedule's trajectories, events and actions by id; `None` when a trajectory or an
/// event names something the scenario lacks (reported in `out`): the replay would check
/// a different cell. Actions with unknown names are left out (the action checks report them).
pub fn timeline<'s>(world: &World, s: &'s Schedule, out: &mut Vec<Violation>) -> Option<Timeline<'s>> {
    let scn = world.scenario();
    let before = out.len();
    let tracks: Vec<_> = s
        .trajectories
        .iter()
        .filter_map(|tr| {
            let points = tr.points.iter().map(|p| TimedPoint { t: p.t, q: p.q.clone(), qd: p.qd.clone() });
            read::track(world, &tr.robot, &tr.joint_names, points, out)
        })
        .collect();
    let events: Vec<_> = s
        .events
        .iter()
        .filter_map(|e| {
            let kind = match e.kind {
                schedule::EventKind::Grasp => EventKind::Grasp,
                schedule::EventKind::Release => EventKind::Release,
            };
            read::event(world, e.t, &e.robot, kind, &e.object, &e.fingers, out)
        })
        .collect();
    if out.len() > before {
        return None;
    }
    let actions = s
        .actions
        .iter()
        .filter_map(|a| {
            let robot = scn.robot_by_name(&a.robot)?;
            let object = match &a.object {
                Some(name) => Some(scn.object_by_name(name)?),
                None => None,
            };
            // An unknown grasp is reported by the action checks; it holds with the fingers open.
            let grasp =
                object.zip(a.grasp.as_deref()).and_then(|(o, g)| scn.object(o).grasp_index(g)).unwrap_or(usize::MAX);
            Some(TimedAction {
                id: a.id,
                robot,
                object,
                grasp,
                after: &a.after,
                start: a.start,
                end: a.end,
                approach: &a.approach,
                retreat: &a.retreat,
                checked: true,
            })
        })
        .collect();
    Some(Timeline { makespan: s.makespan, tracks, events, actions })
}
