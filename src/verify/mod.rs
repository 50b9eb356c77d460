//! Verify: (World, Schedule) -> Ok or the list of violations.
//!
//! An independent re-check that shares only the world model with the planner and the
//! timing stage. Two parts. Each action on its own: ids 1..n, `after` naming earlier
//! actions, every waypoint inside the joint limits, home to home, the approach ending at
//! its grasp (TCP within 1 mm and 0.5°) after the straight move in (TCP within 1 cm of
//! the line from the stand-off to the grasp point, at most 2 mm past it, turned at most
//! 2°), the retreat passing the drop; the target grasped (or reached) last. Then the
//! whole cell replayed in time ([`time`]): every robot at its interpolated configuration
//! at once, sampled so that nothing moves more than [`time::SAMPLE_BOUND`] between
//! samples; contacts, joint positions, velocities and accelerations, waypoints, events
//! and precedence. The schedule must name this scenario and its target.

pub mod time;
mod violation;

pub use violation::{Location, Phase, Violation, ViolationKind};

use crate::resolve::{Grasp, ObjectId, RobotId, Target};
use crate::schedule::{target_spec, Schedule, ScheduledAction, Status, TargetSpec, SCHEDULE_VERSION};
use crate::world::{ObjectSet, World};

/// How far the approach may end from the grasp's TCP position (metres).
pub const GRASP_POSITION_TOLERANCE: f64 = 1e-3;
/// How far the approach may end from the grasp's TCP orientation (radians): 0.5°.
pub const GRASP_ANGLE_TOLERANCE: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// How far the first and last waypoints may be from `home` (radians or metres).
pub const HOME_TOLERANCE: f64 = 1e-6;
/// Slack on joint limits, for values written out and read back.
pub const LIMIT_TOLERANCE: f64 = 1e-9;

/// What a successful verification looked at.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    pub actions: usize,
    /// Seconds replayed.
    pub makespan: f64,
    /// Instants at which the whole cell was checked.
    pub samples: u64,
}

/// What `verify` demands beyond the scenario.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    /// Distance (metres) every moving thing must keep from what it must not touch; 0
    /// demands no contact only.
    pub clearance: f64,
    /// See [`time::ReplayOptions::every_step`].
    pub every_step: bool,
    /// See [`time::ReplayOptions::every_pair`].
    pub every_pair: bool,
}

/// Checks a schedule against the world it claims to solve.
pub fn verify(world: &World, schedule: &Schedule) -> Result<Summary, Vec<Violation>> {
    verify_with(world, schedule, &Options::default())
}

/// [`verify`] with options.
pub fn verify_with(world: &World, schedule: &Schedule, opts: &Options) -> Result<Summary, Vec<Violation>> {
    let scn = world.scenario();
    let mut out = Vec::new();
    let mut summary = Summary { actions: schedule.actions.len(), makespan: schedule.makespan, samples: 0 };
    if schedule.schedule_version != SCHEDULE_VERSION {
        out.push(Violation::general(ViolationKind::Version { found: schedule.schedule_version }));
        return Err(out);
    }
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
    // Actions already at fault: the replay does not judge their waypoints and events again.
    let mut broken: Vec<u32> = Vec::new();

    // Ids must be 1..=n in order: "run in id order" then means list order.
    let mut order: Vec<&ScheduledAction> = schedule.actions.iter().collect();
    order.sort_by_key(|a| a.id);
    for (i, a) in order.iter().enumerate() {
        if a.id != i as u32 + 1 {
            out.push(Violation::at(a.id, ViolationKind::BadId { expected: i as u32 + 1 }));
        }
    }

    // Objects removed by earlier actions.
    let mut gone = ObjectSet::new();
    let mut last_reached_target = false;

    for (k, a) in order.iter().enumerate() {
        let faults = out.len();
        // A reach leaves its robot at the target, where no later action is checked against it.
        if a.object.is_none() && k + 1 < order.len() {
            out.push(Violation::at(a.id, ViolationKind::ReachNotLast));
        }
        let robot = scn.robot_by_name(&a.robot);
        if robot.is_none() {
            out.push(Violation::at(a.id, ViolationKind::UnknownRobot { name: a.robot.clone() }));
        }
        // `after` must name earlier actions (the replay checks that they are carried clear in time).
        for (k, &dep) in a.after.iter().enumerate() {
            if a.after[..k].contains(&dep) {
                out.push(Violation::at(a.id, ViolationKind::DuplicateAfter { dep }));
            } else if dep >= a.id || !order.iter().any(|b| b.id == dep) {
                out.push(Violation::at(a.id, ViolationKind::BadAfter { dep }));
            }
        }

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
                check_action(world, r, object, a, resolution, &mut out);
            }
        }
        if out.len() > faults {
            broken.push(a.id);
        }

        // Even a broken action counts as done, so later actions are judged on their own
        // (a fault in one action must not reappear as collisions or a missing target later).
        if let (Some(o), true) = (object, fresh) {
            gone.insert(o);
        }
        last_reached_target = match (&scn.target, &a.object, object) {
            (Target::Object { object: t, .. }, _, Some(o)) => *t == o,
            (Target::Config { robot: t, .. }, None, _) => robot == Some(*t),
            _ => false,
        };
    }

    if !last_reached_target {
        out.push(Violation::general(ViolationKind::TargetNotLast));
    }
    let target_name = match &scn.target {
        Target::Object { object, .. } => Some(scn.object(*object).body.name.as_str()),
        Target::Config { .. } => None,
    };
    let names: Vec<&str> =
        order.iter().filter_map(|a| a.object.as_deref()).filter(|n| Some(*n) != target_name).collect();
    if schedule.removed.iter().map(String::as_str).ne(names.iter().copied()) {
        out.push(Violation::general(ViolationKind::RemovedListMismatch { expected: names.join(", ") }));
    }

    if let Some(mut tl) = time::from_schedule::timeline(world, schedule, &mut out) {
        // An action at fault is not judged again against the trajectories (its motion still is).
        for a in tl.actions.iter_mut() {
            a.checked = !broken.contains(&a.id);
        }
        let limits = time::RateLimits {
            velocity: scn
                .robot_ids()
                .map(|r| world.velocity_limits(r).iter().map(|v| v * scn.planner.speed).collect())
                .collect(),
            acceleration: scn
                .robot_ids()
                .map(|r| world.acceleration_limits(r).iter().map(|a| a * scn.planner.speed).collect())
                .collect(),
        };
        let opts = time::ReplayOptions {
            bound: time::SAMPLE_BOUND,
            clearance: opts.clearance,
            limits,
            every_step: opts.every_step,
            every_pair: opts.every_pair,
            record_instants: false,
        };
        let (replayed, found) = time::replay(world, &tl, &opts);
        summary.samples = replayed.samples;
        out.extend(found);
    }

    if out.is_empty() {
        Ok(summary)
    } else {
        Err(out)
    }
}

/// Home, grasp, drop and the straight move in of one action whose waypoints are
/// well-formed (its collisions are the replay's). `object` is `None` for the reach of a
/// configuration target.
fn check_action(
    world: &World,
    r: RobotId,
    object: Option<ObjectId>,
    a: &ScheduledAction,
    resolution: f64,
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

    // The move in: only there may the hand touch the object it grasps (the closed hand's
    // model overlaps it at the grasp), so that move must be straight.
    if let (Some(g), [.., from, to]) = (grasp, a.approach.as_slice()) {
        let d = world.approach_deviation(r, g, from, to, resolution);
        if !d.is_straight() {
            out.push(Violation::segment(
                a.id,
                Phase::Approach,
                a.approach.len() - 2,
                ViolationKind::CrookedApproach { grasp: g.name.clone(), deviation: d },
            ));
        }
    }
    if object.is_some() {
        // The object is carried up to the first waypoint at the drop configuration.
        let drop = world.drop_config(r);
        if !a.retreat.iter().skip(1).any(|q| near(q, drop)) {
            out.push(Violation::at(a.id, ViolationKind::NoDrop));
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
