//! The verifier against schedules the planner really produced, and against tampered
//! copies of them: each kind of tampering must be caught with the right violation.

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::schedule::{self, Schedule};
use declutter::verify::time::{Obstacle, Party, TimeViolation};
use declutter::verify::{self, Phase, ViolationKind};
use declutter::world::{self, World, WorldOptions};

fn compiled(file: &str) -> (World, Schedule) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(Path::new(file), &FsLoader, &mut sources).expect("example resolves");
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("example world builds");
    let planned = declutter::driver::plan_verified(&w, &|_| {}).unwrap_or_else(|v| panic!("{v:#?}"));
    (w, planned.schedule)
}

fn kinds(w: &World, s: &Schedule) -> Vec<ViolationKind> {
    match verify::verify(w, s) {
        Ok(_) => Vec::new(),
        Err(v) => v.into_iter().map(|v| v.kind).collect(),
    }
}

#[test]
fn planned_box_lid_schedule_verifies_and_survives_a_yaml_round_trip() {
    let (w, s) = compiled("examples/box_lid.dcl");
    assert_eq!(s.removed, vec!["lid"]);
    let summary = verify::verify(&w, &s).expect("the planner's schedule verifies");
    assert_eq!(summary.actions, 2);
    assert!(summary.samples > 0);
    let yaml = schedule::to_yaml(&s).unwrap();
    let back: Schedule = declutter::driver::parse_schedule(&yaml).unwrap();
    assert_eq!(back, s);
    assert!(verify::verify(&w, &back).is_ok());
}

#[test]
fn swapping_two_dependent_actions_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    // Run the can's grasp first: the lid is still on, and `after` now points forwards.
    s.actions.swap(0, 1);
    s.actions[0].id = 1;
    s.actions[1].id = 2;
    let k = kinds(&w, &s);
    assert!(k.iter().any(|k| matches!(k, ViolationKind::BadAfter { dep: 1 })), "{k:?}");
    assert!(k.contains(&ViolationKind::TargetNotLast), "{k:?}");
}

#[test]
fn dropping_a_removal_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    s.actions.remove(0);
    s.actions[0].id = 1;
    s.actions[0].after.clear();
    s.removed.remove(0);
    // The lid's grasp and release are left without an action.
    let k = kinds(&w, &s);
    assert!(
        k.iter().any(
            |k| matches!(k, ViolationKind::Time(TimeViolation::UnexpectedEvent { object, .. }) if object == "lid")
        ),
        "{k:?}"
    );
}

#[test]
fn a_trajectory_point_moved_into_the_table_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    // Shoulder far forward and elbow stretched: the arm lies on the table.
    let robot = s.actions[0].robot.clone();
    let tr = s.trajectories.iter_mut().find(|t| t.robot == robot).expect("trajectory");
    let mid = tr.points.iter().position(|p| p.qd.iter().any(|v| *v != 0.0)).expect("a moving point");
    tr.points[mid].q = vec![0.0, 2.2, 0.3, 0.0, 0.0, 0.0];
    let v = verify::verify(&w, &s).expect_err("a point in the table must not verify");
    let hit = v.iter().find(|v| {
        matches!(&v.kind, ViolationKind::Time(TimeViolation::Contact { a: Party::Body { robot: r, .. }, b: Obstacle::Fixed(f), .. })
            if *r == robot && f == "table")
    });
    let hit = hit.unwrap_or_else(|| panic!("no table hit in {v:#?}"));
    assert!(matches!(hit.location, verify::Location::At { .. }));
}

#[test]
fn changing_the_grasp_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    let original = s.actions[1].grasp.clone().unwrap();
    let other = ["top#0", "top#1", "top#2", "top#3"].into_iter().find(|g| *g != original).unwrap();
    s.actions[1].grasp = Some(other.to_string());
    let k = kinds(&w, &s);
    assert!(k.iter().any(|k| matches!(k, ViolationKind::MissesGrasp { grasp, .. } if grasp == other)), "{k:?}");
    s.actions[1].grasp = Some("bottom".to_string());
    let k = kinds(&w, &s);
    assert!(k.iter().any(|k| matches!(k, ViolationKind::UnknownGrasp { .. })), "{k:?}");
}

#[test]
fn a_waypoint_outside_the_limits_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    s.actions[0].approach[1][2] = 3.0; // joint 3 is limited to ±145°
    let k = kinds(&w, &s);
    assert!(k.iter().any(|k| matches!(k, ViolationKind::OutOfLimits { joint, .. } if joint == "joint_3")), "{k:?}");
}

#[test]
fn a_retreat_that_skips_the_drop_configuration_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    // Action 1 is r2 taking the lid away; r2 has its own `drop` configuration.
    assert_eq!(s.actions[0].robot, "r2");
    let r2 = w.scenario().robot_by_name("r2").unwrap();
    let drop = w.drop_config(r2).0.clone();
    let before = s.actions[0].retreat.len();
    s.actions[0].retreat.retain(|q| q.iter().zip(&drop).any(|(a, b)| (a - b).abs() > 1e-6));
    assert_eq!(s.actions[0].retreat.len(), before - 1, "exactly one waypoint was the drop configuration");
    let k = kinds(&w, &s);
    assert!(k.contains(&ViolationKind::NoDrop), "{k:?}");
}

/// Every violation, as `declutter verify` prints it (without the `violation: ` prefix).
fn messages(w: &World, s: &Schedule) -> Vec<String> {
    match verify::verify(w, s) {
        Ok(_) => Vec::new(),
        Err(v) => v.iter().map(ToString::to_string).collect(),
    }
}

#[test]
fn a_reach_with_a_retreat_through_the_table_is_caught() {
    let (w, mut s) = compiled("examples/reach_pose.dcl");
    assert!(verify::verify(&w, &s).is_ok());
    assert_eq!(s.actions[1].object, None, "action 2 is the reach of the target configuration");
    assert!(s.actions[1].retreat.is_empty(), "the planner writes no retreat for a reach");
    s.actions[1].retreat = vec![vec![0.0, 2.2, 0.3, 0.0, 0.0, 0.0], vec![0.0, -2.2, 0.3, 0.0, 0.0, 0.0]];
    assert_eq!(
        messages(&w, &s),
        ["action 2, retreat waypoint 0: a reach of the target configuration has retreat waypoints; it must end there"]
    );
}

#[test]
fn a_grasp_on_a_reach_is_caught() {
    let (w, mut s) = compiled("examples/reach_pose.dcl");
    s.actions[1].grasp = Some("whatever".to_string());
    assert_eq!(
        messages(&w, &s),
        ["action 2: names grasp `whatever`, but a reach of the target configuration grasps nothing"]
    );
}

#[test]
fn a_schedule_of_another_scenario_or_target_is_caught() {
    let (w, mut s) = compiled("examples/reach_pose.dcl");
    s.scenario = "box-lid".to_string();
    assert_eq!(messages(&w, &s), ["schedule: is for scenario `box-lid`, not `reach-pose`"]);
    s.scenario = "reach-pose".to_string();
    if let schedule::TargetSpec::Config { q, .. } = &mut s.target {
        q[0] = 0.0;
    }
    assert_eq!(
        messages(&w, &s),
        ["schedule: its target is robot `r1` at [0.000000, 1.047198, 1.221730, 0.000000, 0.872665, 0.000000]; \
          the scenario's is robot `r1` at [0.349066, 1.047198, 1.221730, 0.000000, 0.872665, 0.000000]"]
    );
    let (w, mut s) = compiled("examples/box_lid.dcl");
    s.target = schedule::TargetSpec::Object("lid".to_string());
    assert_eq!(messages(&w, &s), ["schedule: its target is object `lid`; the scenario's is object `can`"]);
}

#[test]
fn an_infeasible_schedule_does_not_verify() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    s.status = schedule::Status::Infeasible;
    assert_eq!(messages(&w, &s), ["schedule: the schedule is not solved (status is not `solved`)"]);
}

#[test]
fn a_broken_waypoint_is_reported_once_without_follow_on_violations() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    let mut nan = s.clone();
    nan.actions[0].approach[1][1] = f64::NAN;
    // Not also "action 2 … touches `lid`": action 1 still counts as removing the lid.
    assert_eq!(
        messages(&w, &nan),
        ["action 1, approach waypoint 1: joint `joint_2` is NaN, outside its limits [-2.268928, 2.574361]"]
    );
    // Not also "the last action does not grasp the target": action 2 still grasps it.
    s.actions[1].approach[1].push(0.0);
    assert_eq!(messages(&w, &s), ["action 2, approach waypoint 1: has 7 joint values; the robot has 6 joints"]);
}

/// The index of the pre-grasp (the last approach waypoint but one) of action `i`.
fn pre_grasp(s: &Schedule, i: usize) -> usize {
    s.actions[i].approach.len() - 2
}

#[test]
fn a_sideways_swing_into_the_grasp_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    assert_eq!(s.actions[1].object.as_deref(), Some("can"));
    // Swing the base joint 0.3 rad at the pre-grasp: the hand then sweeps sideways
    // through the can's place on its last segment, where the can is ignored.
    let p = pre_grasp(&s, 1);
    s.actions[1].approach[p][0] += 0.3;
    s.actions[1].retreat[1][0] += 0.3;
    let v = verify::verify(&w, &s).expect_err("the swing must not verify");
    let crooked: Vec<_> = v
        .iter()
        .filter_map(|v| match &v.kind {
            ViolationKind::CrookedApproach { deviation, .. } => Some((v.location.clone(), *deviation)),
            _ => None,
        })
        .collect();
    assert_eq!(crooked.len(), 1, "{v:?}");
    assert_eq!(crooked[0].0, verify::Location::Segment { action: 2, phase: Phase::Approach, index: p });
    // The TCP is about 0.55 m from the base axis: a 0.3 rad swing moves it ~16 cm aside.
    assert!(crooked[0].1.off_line > 0.10, "{:?}", crooked[0].1);
}

#[test]
fn turning_the_hand_on_the_move_in_is_caught_beyond_two_degrees() {
    let (w, s) = compiled("examples/box_lid.dcl");
    let p = pre_grasp(&s, 1);
    // Joint 6 turns the hand about the TCP's own z axis (the TCP lies on that axis): the
    // TCP does not move, it only turns by the joint's change.
    let turned = |deg: f64| {
        let mut t = s.clone();
        t.actions[1].approach[p][5] += deg.to_radians();
        t.actions[1].retreat[1][5] += deg.to_radians();
        t
    };
    let (ok, bad) = (turned(1.9), turned(2.1));
    // The trajectory still runs through the original waypoints: only the replay objects.
    let k = kinds(&w, &ok);
    assert!(k.iter().all(|k| matches!(k, ViolationKind::Time(TimeViolation::WaypointSkipped { .. }))), "{k:?}");
    let v = verify::verify(&w, &bad).expect_err("2.1° is past the 2° allowed");
    assert_eq!(v.len(), 1, "{v:?}");
    let ViolationKind::CrookedApproach { grasp, deviation } = &v[0].kind else { panic!("{v:?}") };
    assert_eq!(grasp, "top#2");
    assert!((deviation.angle.to_degrees() - 2.1).abs() < 0.01, "{deviation:?}");
    assert!(deviation.off_line < 2e-3, "{deviation:?}");
    assert_eq!(
        v[0].to_string(),
        format!(
            "action 2, approach segment {p}→{}: is not the straight move in to grasp `top#2`: the TCP strays \
             {:.2} mm from the approach line, goes {:.2} mm past the grasp and turns 2.100° (allowed: 10 mm, \
             2 mm, 2°); the object is an obstacle everywhere else",
            p + 1,
            deviation.off_line * 1e3,
            deviation.overshoot * 1e3,
        )
    );
}

#[test]
fn every_planned_move_in_is_straight() {
    for file in ["examples/box_lid.dcl", "examples/cans_3.dcl", "examples/single_arm.dcl"] {
        let (w, s) = compiled(file);
        let scn = w.scenario();
        for a in &s.actions {
            let (Some(o), Some(g)) = (&a.object, &a.grasp) else { continue };
            let grasp = scn.object(scn.object_by_name(o).unwrap()).grasps.iter().find(|x| &x.name == g).unwrap();
            let r = scn.robot_by_name(&a.robot).unwrap();
            let n = a.approach.len();
            let d = w.approach_deviation(r, grasp, &a.approach[n - 2], &a.approach[n - 1], scn.planner.resolution);
            assert!(d.is_straight(), "{file}, action {}: {d:?}", a.id);
            // It starts at the stand-off: the TCP covers the whole approach distance.
            let start = grasp.pose_world_tcp.inverse() * w.fk_tcp(r, &a.approach[n - 2]);
            assert!((start.translation.vector.z + grasp.approach).abs() < 1e-3, "{file}, action {}", a.id);
        }
    }
}

#[test]
fn a_reach_before_the_last_action_is_caught() {
    let (w, mut s) = compiled("examples/reach_pose.dcl");
    let reach = s.actions[1].clone();
    let mut again = reach.clone();
    again.id = 3;
    s.actions.push(again);
    assert_eq!(messages(&w, &s), ["action 2: a reach of the target configuration must be the last action"]);
}

#[test]
fn an_action_waited_for_twice_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    assert_eq!(s.actions[1].after, [1]);
    s.actions[1].after.push(1);
    assert_eq!(messages(&w, &s), ["action 2: lists action 1 twice in `after`"]);
}

#[test]
fn a_huge_joint_value_is_printed_in_one_short_line() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    s.actions[0].approach[1][1] = 1e300;
    assert_eq!(
        messages(&w, &s),
        ["action 1, approach waypoint 1: joint `joint_2` is 1.000000e300, outside its limits [-2.268928, 2.574361]"]
    );
}
