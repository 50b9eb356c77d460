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
