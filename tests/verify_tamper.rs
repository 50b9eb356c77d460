//! The verifier against schedules the planner really produced, and against tampered
//! copies of them: each kind of tampering must be caught with the right violation.

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::plan::{andor, Planner};
use declutter::schedule::{self, Schedule};
use declutter::verify::{self, Phase, ViolationKind};
use declutter::world::{self, World, WorldOptions};

fn compiled(file: &str) -> (World, Schedule) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(Path::new(file), &FsLoader, &mut sources).expect("example resolves");
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("example world builds");
    let planner = Planner::new(&w, &w.scenario().planner);
    let sol = andor::solve(w.scenario(), &planner);
    let s = schedule::build(w.scenario(), &sol);
    (w, s)
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
    assert_eq!(s.removed, vec!["lid", "can"]);
    let summary = verify::verify(&w, &s).expect("the planner's schedule verifies");
    assert_eq!(summary.actions, 2);
    assert!(summary.checks > 0);
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
    assert!(k.iter().any(|k| matches!(k, ViolationKind::HitsObject { object } if object == "lid")), "{k:?}");
    assert!(k.contains(&ViolationKind::TargetNotLast), "{k:?}");
}

#[test]
fn dropping_a_removal_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    s.actions.remove(0);
    s.actions[0].id = 1;
    s.actions[0].after.clear();
    s.removed.remove(0);
    let k = kinds(&w, &s);
    assert!(!k.is_empty());
    assert!(k.iter().all(|k| matches!(k, ViolationKind::HitsObject { object } if object == "lid")), "{k:?}");
}

#[test]
fn forgetting_to_wait_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    s.actions[1].after.clear();
    let k = kinds(&w, &s);
    assert!(k.iter().any(|k| matches!(k, ViolationKind::MissingAfter { object, by: 1 } if object == "lid")), "{k:?}");
}

#[test]
fn a_waypoint_moved_into_the_table_is_caught() {
    let (w, mut s) = compiled("examples/box_lid.dcl");
    // Shoulder far forward and elbow stretched: the arm lies on the table.
    let q = vec![0.0, 2.2, 0.3, 0.0, 0.0, 0.0];
    s.actions[0].approach.insert(1, q);
    let v = verify::verify(&w, &s).expect_err("a waypoint in the table must not verify");
    let hit = v.iter().find(|v| matches!(&v.kind, ViolationKind::Blocked(what) if what.contains("`table`")));
    let hit = hit.unwrap_or_else(|| panic!("no table hit in {v:?}"));
    assert!(matches!(hit.location, verify::Location::Segment { action: 1, phase: Phase::Approach, .. }));
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
