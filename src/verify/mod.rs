//! Verify: (World, Schedule) -> Ok or the list of violations.
//!
//! An independent re-check that shares only the world model with the planner. Actions
//! run in `id` order; each must wait (through `after`) for the removals its motion
//! relies on. Every waypoint must lie inside the joint limits, every segment —
//! interpolated at a quarter of the planner's resolution — must be free of fixed
//! bodies, of the other robots at home and of objects not yet removed, with the
//! carried object attached on the way back until the drop configuration; each approach
//! must end at its grasp (TCP within 1 mm and 0.5°). The grasped object is no obstacle
//! on the approach's last segment only, and only if that segment is the straight move
//! in: the TCP within 1 cm of the line from the stand-off to the grasp point, at most
//! 2 mm past it, turned at most 2° from the grasp. The last action must grasp the target
//! object or reach the target configuration; a reach has no grasp and no retreat and
//! comes last. The schedule must name this scenario and its target.

pub mod time;
mod violation;

pub use violation::{Location, Phase, Violation, ViolationKind};

use crate::resolve::{Grasp, ObjectId, RobotId, Target};
use crate::schedule::{target_spec, Schedule, ScheduledAction, Status, TargetSpec};
use crate::world::{Check, CheckCtx, ObjectSet, World};

/// How far the approach may end from the grasp's TCP position (metres).
pub const GRASP_POSITION_TOLERANCE: f64 = 1e-3;
/// How far the approach may end from the grasp's TCP orientation (radians): 0.5°.
pub const GRASP_ANGLE_TOLERANCE: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// How far the first and last waypoints may be from `home` (radians or metres).
pub const HOME_TOLERANCE: f64 = 1e-6;
/// Slack on joint limits, for values written out and read back.
pub const LIMIT_TOLERANCE: f64 = 1e-9;

/// What a successful verification looked at.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Summary {
    pub actions: usize,
    pub segments: usize,
    /// Configurations collision-checked.
    pub checks: u64,
}

/// Checks a schedule against the world it claims to solve.
pub fn verify(world: &World, schedule: &Schedule) -> Result<Summary, Vec<Violation>> {
    let scn = world.scenario();
    let mut out = Vec::new();
    let mut summary = Summary { actions: schedule.actions.len(), ..Summary::default() };
    // A schedule of another scenario, or of another target, may verify by accident.
    let name = crate::schedule::scenario_name(scn);
    if schedule.scenario != name {
        out.push(Violation::general(ViolationKind::ScenarioMismatch {
            expected: name,
            found: schedule.scenario.clone(),
        }));
    }
    let target = target_spec(scn);
    if !same_target(&target, &schedule.target) {
        out.push(Violation::general(ViolationKind::TargetMismatch {
            expected: target.to_string(),
            found: schedule.target.to_string(),
        }));
    }
    if schedule.status != Status::Solved {
        out.push(Violation::general(ViolationKind::NotSolved));
        return Err(out);
    }
    let resolution = scn.planner.resolution;

    // Ids must be 1..=n in order: "run in id order" then means list order.
    let mut order: Vec<&ScheduledAction> = schedule.actions.iter().collect();
    order.sort_by_key(|a| a.id);
    for (i, a) in order.iter().enumerate() {
        if a.id != i as u32 + 1 {
            out.push(Violation::at(a.id, ViolationKind::BadId { expected: i as u32 + 1 }));
        }
    }

    // Objects removed by each finished action, for `after` bookkeeping.
    let mut removed_by: Vec<(u32, ObjectId)> = Vec::new();
    let mut closure: Vec<(u32, Vec<u32>)> = Vec::new();
    let mut last_reached_target = false;

    for (k, a) in order.iter().enumerate() {
        // A reach leaves its robot at the target, where no later action is checked against it.
        if a.object.is_none() && k + 1 < order.len() {
            out.push(Violation::at(a.id, ViolationKind::ReachNotLast));
        }
        let robot = scn.robot_by_name(&a.robot);
        if robot.is_none() {
            out.push(Violation::at(a.id, ViolationKind::UnknownRobot { name: a.robot.clone() }));
        }
        // `after` must name earlier actions; its transitive closure is what this action may rely on.
        let mut waits: Vec<u32> = Vec::new();
        for (k, &dep) in a.after.iter().enumerate() {
            if a.after[..k].contains(&dep) {
                out.push(Violation::at(a.id, ViolationKind::DuplicateAfter { dep }));
            } else if dep >= a.id || !order.iter().any(|b| b.id == dep) {
                out.push(Violation::at(a.id, ViolationKind::BadAfter { dep }));
            } else {
                waits.push(dep);
                if let Some((_, deps)) = closure.iter().find(|(id, _)| *id == dep) {
                    waits.extend(deps.iter().copied());
                }
            }
        }
        waits.sort_unstable();
        waits.dedup();
        let relied: ObjectSet = removed_by.iter().filter(|(id, _)| waits.contains(id)).map(|(_, o)| *o).collect();
        let gone: ObjectSet = removed_by.iter().map(|(_, o)| *o).collect();

        // `fresh`: the object is known and still in place, so this action removes it.
        let (object, fresh) = match &a.object {
            Some(name) => match scn.object_by_name(name) {
                Some(o) if gone.contains(o) => {
                    out.push(Violation::at(a.id, ViolationKind::AlreadyRemoved { object: name.clone() }));
                    (Some(o), false)
                }
                Some(o) => (Some(o), true),
                None => {
                    out.push(Violation::at(a.id, ViolationKind::UnknownObject { name: name.clone() }));
                    (None, false)
                }
            },
            None => (None, true),
        };

        if let (Some(r), true) = (robot, fresh) {
            let before = out.len();
            check_waypoints(world, r, a, &mut out);
            // Motions between broken waypoints are not checked: they would only repeat the fault.
            if out.len() == before {
                let scope = Scope { relied: &relied, gone: &gone, removed_by: &removed_by, resolution };
                check_action(world, r, object, a, &scope, &mut summary, &mut out);
            }
        }

        // Even a broken action counts as done, so later actions are judged on their own
        // (a fault in one action must not reappear as collisions or a missing target later).
        if let (Some(o), true) = (object, fresh) {
            removed_by.push((a.id, o));
        }
        closure.push((a.id, waits));
        last_reached_target = match (&scn.target, &a.object, object) {
            (Target::Object { object: t, .. }, _, Some(o)) => *t == o,
            (Target::Config { robot: t, .. }, None, _) => robot == Some(*t),
            _ => false,
        };
    }

    if !last_reached_target {
        out.push(Violation::general(ViolationKind::TargetNotLast));
    }
    let names: Vec<&str> = order.iter().filter_map(|a| a.object.as_deref()).collect();
    if schedule.removed.iter().map(String::as_str).ne(names.iter().copied()) {
        out.push(Violation::general(ViolationKind::RemovedListMismatch { expected: names.join(", ") }));
    }

    if out.is_empty() {
        Ok(summary)
    } else {
        Err(out)
    }
}

/// What the scene holds while one action runs.
struct Scope<'a> {
    /// Removed by actions this one waits for: absent.
    relied: &'a ObjectSet,
    /// Removed by any earlier action: touching one of these means a missing `after`.
    gone: &'a ObjectSet,
    removed_by: &'a [(u32, ObjectId)],
    resolution: f64,
}

/// Home, grasp, drop and every segment of one action whose waypoints are well-formed.
/// `object` is `None` for the reach of a configuration target.
fn check_action(
    world: &World,
    r: RobotId,
    object: Option<ObjectId>,
    a: &ScheduledAction,
    scope: &Scope,
    summary: &mut Summary,
    out: &mut Vec<Violation>,
) {
    let scn = world.scenario();
    let home = world.home(r);
    if let Some(first) = a.approach.first() {
        if !near(first, home) {
            out.push(Violation::waypoint(a.id, Phase::Approach, 0, ViolationKind::NotAtHome));
        }
    }
    let end_of_approach = a.approach.last();
    let mut grasp = None;
    match (object, end_of_approach) {
        (_, None) => out.push(Violation::at(a.id, ViolationKind::EmptyApproach)),
        (Some(o), Some(q_grasp)) => grasp = check_grasp(world, r, o, a, q_grasp, out),
        (None, Some(q_end)) => match &scn.target {
            Target::Config { robot, q, .. } if *robot == r && near(q_end, &q.values) => {}
            _ => out.push(Violation::at(a.id, ViolationKind::ReachNotTarget)),
        },
    }
    if object.is_some() {
        match (a.retreat.first(), end_of_approach) {
            (Some(first), Some(q_grasp)) if !near(first, q_grasp) => {
                out.push(Violation::waypoint(a.id, Phase::Retreat, 0, ViolationKind::RetreatNotFromGrasp));
            }
            (None, _) => out.push(Violation::at(a.id, ViolationKind::EmptyRetreat)),
            _ => {}
        }
        if let Some(last) = a.retreat.last() {
            if !near(last, home) {
                out.push(Violation::waypoint(a.id, Phase::Retreat, a.retreat.len() - 1, ViolationKind::NotAtHome));
            }
        }
    } else {
        // A reach ends the schedule at the target and stays there (the planner writes no
        // retreat and no grasp); anything else would be motion this verifier never checks.
        if let Some(grasp) = &a.grasp {
            out.push(Violation::at(a.id, ViolationKind::GraspOnReach { grasp: grasp.clone() }));
        }
        if !a.retreat.is_empty() {
            out.push(Violation::waypoint(a.id, Phase::Retreat, 0, ViolationKind::RetreatOnReach));
        }
    }

    // Collisions. The scene holds every object not removed by an action this one
    // waits for; a touched object that an earlier action did remove means a missing
    // `after`, any other touched object is a collision.
    let absent = |extra: Option<ObjectId>| {
        let mut absent = scope.relied.clone();
        if let Some(o) = extra {
            absent.insert(o);
        }
        absent
    };
    let n_approach = a.approach.len();
    for (i, w) in a.approach.windows(2).enumerate() {
        // The grasped object is not an obstacle on the final straight approach only (the
        // closed hand's model overlaps it at the grasp), so that move must be straight.
        let last = i + 2 == n_approach;
        if let (true, Some(g)) = (last, grasp) {
            let d = world.approach_deviation(r, g, &w[0], &w[1], scope.resolution);
            if !d.is_straight() {
                out.push(Violation::segment(
                    a.id,
                    Phase::Approach,
                    i,
                    ViolationKind::CrookedApproach { grasp: g.name.clone(), deviation: d },
                ));
            }
        }
        let ctx = CheckCtx::with_absent(absent(if last { object } else { None }));
        let res = world.check_motion(r, &w[0], &w[1], scope.resolution, &ctx);
        summary.checks += ctx.checks.get();
        summary.segments += 1;
        report(scn, a.id, Phase::Approach, i, res, scope, out);
    }
    if let (Some(o), Some(q_grasp)) = (object, end_of_approach) {
        let held = world.held(r, o, q_grasp);
        // The object is carried up to the first waypoint at the drop configuration and
        // released there; the rest of the way home is empty-handed.
        let drop = world.drop_config(r);
        let released = a.retreat.iter().skip(1).position(|q| near(q, drop)).map(|i| i + 1);
        if released.is_none() {
            out.push(Violation::at(a.id, ViolationKind::NoDrop));
        }
        let released = released.unwrap_or(a.retreat.len());
        for (i, w) in a.retreat.windows(2).enumerate() {
            let mut ctx = CheckCtx::with_absent(absent(Some(o)));
            if i < released {
                ctx.held = Some(held.clone());
            }
            let res = world.check_motion(r, &w[0], &w[1], scope.resolution, &ctx);
            summary.checks += ctx.checks.get();
            summary.segments += 1;
            report(scn, a.id, Phase::Retreat, i, res, scope, out);
        }
    }
}

/// Same target; joint values compared with the home tolerance (they are written exactly).
fn same_target(a: &TargetSpec, b: &TargetSpec) -> bool {
    match (a, b) {
        (TargetSpec::Object(x), TargetSpec::Object(y)) => x == y,
        (TargetSpec::Config { robot: r, q }, TargetSpec::Config { robot: s, q: p }) => r == s && near(q, p),
        _ => false,
    }
}

fn near(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= HOME_TOLERANCE)
}

/// Length, finiteness and joint limits of every waypoint.
fn check_waypoints(world: &World, r: RobotId, a: &ScheduledAction, out: &mut Vec<Violation>) {
    let dof = world.dof(r);
    let limits = world.limits(r);
    let names = world.joint_names(r);
    for (phase, path) in [(Phase::Approach, &a.approach), (Phase::Retreat, &a.retreat)] {
        for (i, q) in path.iter().enumerate() {
            if q.len() != dof {
                out.push(Violation::waypoint(
                    a.id,
                    phase,
                    i,
                    ViolationKind::WrongLength { expected: dof, found: q.len() },
                ));
                continue;
            }
            for (j, (&v, &(lo, hi))) in q.iter().zip(limits).enumerate() {
                if !v.is_finite() || v < lo - LIMIT_TOLERANCE || v > hi + LIMIT_TOLERANCE {
                    let joint = names.get(j).cloned().unwrap_or_else(|| format!("#{j}"));
                    out.push(Violation::waypoint(
                        a.id,
                        phase,
                        i,
                        ViolationKind::OutOfLimits { joint, value: v, lo, hi },
                    ));
                }
            }
        }
    }
}

/// The approach must end with the TCP at the named grasp, which this robot's hand may
/// use. Returns the grasp when it exists.
fn check_grasp<'w>(
    world: &'w World,
    r: RobotId,
    o: ObjectId,
    a: &ScheduledAction,
    q: &[f64],
    out: &mut Vec<Violation>,
) -> Option<&'w Grasp> {
    let scn = world.scenario();
    let obj = scn.object(o);
    let Some(name) = &a.grasp else {
        out.push(Violation::at(a.id, ViolationKind::MissingGrasp));
        return None;
    };
    let Some(grasp) = obj.grasps.iter().find(|g| &g.name == name) else {
        out.push(Violation::at(
            a.id,
            ViolationKind::UnknownGrasp { name: name.clone(), object: obj.body.name.clone() },
        ));
        return None;
    };
    let hand = scn.robot(r).hand;
    if let (Some(allowed), Some(h)) = (&grasp.hands, hand) {
        if !allowed.contains(&h) {
            out.push(Violation::at(a.id, ViolationKind::GraspNotForHand { grasp: name.clone() }));
        }
    }
    let tcp = world.fk_tcp(r, q);
    let dist = (tcp.translation.vector - grasp.pose_world_tcp.translation.vector).norm();
    let angle = tcp.rotation.angle_to(&grasp.pose_world_tcp.rotation);
    if dist > GRASP_POSITION_TOLERANCE || angle > GRASP_ANGLE_TOLERANCE {
        out.push(Violation::waypoint(
            a.id,
            Phase::Approach,
            a.approach.len() - 1,
            ViolationKind::MissesGrasp { grasp: name.clone(), distance: dist, angle },
        ));
    }
    Some(grasp)
}

fn report(
    scn: &crate::resolve::Scenario,
    action: u32,
    phase: Phase,
    segment: usize,
    res: Check,
    scope: &Scope,
    out: &mut Vec<Violation>,
) {
    match res {
        Check::Blocked(b) => out.push(Violation::segment(
            action,
            phase,
            segment,
            ViolationKind::Blocked(violation::describe_blocker(scn, &b)),
        )),
        Check::Touches(set) => {
            for o in set.iter() {
                let object = scn.object(o).body.name.clone();
                let kind = if scope.gone.contains(o) {
                    let by = scope.removed_by.iter().find(|(_, x)| *x == o).map_or(0, |(id, _)| *id);
                    ViolationKind::MissingAfter { object, by }
                } else {
                    ViolationKind::HitsObject { object }
                };
                out.push(Violation::segment(action, phase, segment, kind));
            }
        }
    }
}
