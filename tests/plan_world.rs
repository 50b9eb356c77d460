//! The planner on real worlds: the box-and-lid cell built by hand with two TX-90s and
//! the SAH/SDH2 hands from examples/ (the same scene as examples/box_lid.dcl, which is
//! written on another branch; `box_lid_dcl` runs the file itself once it exists), and
//! the planar arm from examples/robots/planar3.urdf.

mod world_support;

use declutter::diag::FsLoader;
use declutter::plan::{Goal, Oracle, Planner};
use declutter::resolve::{HandId, ObjectId, Objective, Pose, RobotId, Scenario, Shape};
use declutter::world::{build, Check, CheckCtx, ObjectSet, World, WorldOptions};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use world_support::*;

fn rot_y(deg: f64) -> Pose {
    Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_euler_angles(0.0, deg.to_radians(), 0.0))
}
fn rot_z(deg: f64) -> Pose {
    Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_euler_angles(0.0, 0.0, deg.to_radians()))
}

/// A table between two TX-90s; on it a fixed open box holding a can, closed by a lid.
pub fn box_lid() -> Scenario {
    let (cx, top) = (0.75, 0.2);
    let mut fixed = vec![cuboid("table", [0.6, 1.0, 0.1], at(cx, 0.0, top - 0.05))];
    let (inner, wall, h) = (0.24, 0.01, 0.12);
    let off = inner / 2.0 + wall / 2.0;
    for (n, x, y, sx, sy) in [
        ("wall_n", 0.0, off, inner + 2.0 * wall, wall),
        ("wall_s", 0.0, -off, inner + 2.0 * wall, wall),
        ("wall_e", off, 0.0, wall, inner),
        ("wall_w", -off, 0.0, wall, inner),
    ] {
        fixed.push(cuboid(n, [sx, sy, h], at(cx + x, y, top + h / 2.0)));
    }
    let p_can = at(cx, 0.0, top + 0.05);
    let can = body("can", Shape::Cylinder { radius: 0.033, length: 0.1 }, p_can);
    let p_lid = at(cx, 0.0, top + h + 0.005);
    let lid = cuboid("lid", [inner + 2.0 * wall + 0.02, inner + 2.0 * wall + 0.02, 0.01], p_lid);
    let down = |z: f64, turn: f64| at(0.0, 0.0, z) * rot_z(turn) * rot_y(180.0);
    let can_grasps = vec![grasp("top", &p_can, down(0.03, 0.0), 0.1), grasp("top#2", &p_can, down(0.03, 90.0), 0.1)];
    let lid_grasps = vec![grasp("top", &p_lid, down(0.0, 0.0), 0.1), grasp("top#2", &p_lid, down(0.0, 90.0), 0.1)];
    let home = vec![0.0, 0.0, 90f64.to_radians(), 0.0, 0.0, 0.0];
    let a = robot("left", tx90(), home.clone(), Some(HandId(0)));
    let mut b = robot("right", tx90(), home, Some(HandId(1)));
    b.pose_world_base = at(2.0 * cx, 0.0, 0.0) * rot_z(180.0);
    scenario(
        vec![a, b],
        vec![hand("sah", sah(), 0.16), hand("sdh2", sdh2(), 0.18)],
        fixed,
        vec![object(can, can_grasps), object(lid, lid_grasps)],
    )
}

fn world(scn: &Scenario) -> World {
    build(scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"))
}

fn free_along(w: &World, r: RobotId, path: &[declutter::world::Config], ctx: &CheckCtx) -> bool {
    path.windows(2).all(|s| w.check_segment(r, &s[0], &s[1], 2f64.to_radians(), ctx) == Check::free())
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn box_lid_can_needs_the_lid_removed_and_the_lid_is_free() {
    let scn = box_lid();
    let w = world(&scn);
    let planner = Planner::new(&w, &scn.planner);
    let (can, lid) = (ObjectId(0), ObjectId(1));
    for r in scn.robot_ids() {
        let a = planner.find_path(r, &Goal::Grasp(lid));
        eprintln!("{:?}", a.stats);
        let f = a.result.unwrap_or_else(|e| panic!("{}: lid {e:?}", scn.robot(r).name));
        assert_eq!(f.removals, ObjectSet::new(), "{}: lid", scn.robot(r).name);
        let n = f.approach.0.len();
        assert!(free_along(&w, r, &f.approach.0[..n - 1], &CheckCtx::new()));
        let held = w.held(r, lid, &f.retreat.0[0]);
        assert!(free_along(&w, r, &f.retreat.0, &CheckCtx::with_held(ObjectSet::single(lid), held)));

        let a = planner.find_path(r, &Goal::Grasp(can));
        eprintln!("{:?}", a.stats);
        let f = a.result.unwrap_or_else(|e| panic!("{}: can {e:?}", scn.robot(r).name));
        assert_eq!(f.removals, ObjectSet::single(lid), "{}: can", scn.robot(r).name);
        let gone = ObjectSet::single(lid);
        assert!(free_along(&w, r, &f.approach.0[..f.approach.0.len() - 1], &CheckCtx::with_absent(gone.clone())));
        let mut absent = gone.clone();
        absent.insert(can);
        let held = w.held(r, can, &f.retreat.0[0]);
        assert!(free_along(&w, r, &f.retreat.0, &CheckCtx::with_held(absent, held)));
        assert!(a.stats.reused_vertices > 0);
        // Both objectives on the same roadmap.
        let v = planner.find_path_with(r, &Goal::Grasp(can), Objective::FewestVertices);
        assert!(v.result.is_ok());
    }
}

#[test]
fn planar3_reach_through_world() {
    let objects = vec![object(cuboid("box", [0.1, 0.1, 0.1], at(0.5, 0.0, 0.0)), vec![])];
    let fixed = vec![cuboid("wall", [0.1, 0.6, 0.1], at(-0.6, 0.0, 0.0))];
    let scn = scenario(vec![robot("p", planar3(), vec![1.5, 0.0, 0.0], None)], vec![], fixed, objects);
    let w = world(&scn);
    let planner = Planner::new(&w, &scn.planner);
    let r = RobotId(0);
    // Pointing along +x the arm passes through the box; pointing along -x, the wall.
    let a = planner.find_path(r, &Goal::Reach(vec![0.0, 0.0, 0.0].into()));
    assert_eq!(a.result.expect("path").removals, ObjectSet::single(ObjectId(0)));
    assert_eq!(a.stats.robot, "p");
    let b = planner.find_path(r, &Goal::Reach(vec![3.0, 0.0, 0.0].into()));
    assert!(b.result.is_err());
    let c = planner.find_path(r, &Goal::Reach(vec![0.0, 0.0, 0.0].into()));
    assert_eq!(c.stats.samples, 0, "answered from the reused roadmap");
}
