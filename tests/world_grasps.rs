//! `selectGrasps` and the reachability report on a TX-90 with an SAH hand.

mod world_support;

use declutter::diag::FsLoader;
use declutter::resolve::{HandId, ObjectId, Pose, RobotId, Scenario, Shape};
use declutter::world::{build, report, CheckCtx, ObjectSet, WorldOptions};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use world_support::*;

const R0: RobotId = RobotId(0);

fn rot_y(deg: f64) -> Pose {
    Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_euler_angles(0.0, deg.to_radians(), 0.0))
}

fn can(name: &str, p: Pose) -> declutter::resolve::Body {
    body(name, Shape::Cylinder { radius: 0.033, length: 0.2 }, p)
}

fn cell() -> Scenario {
    let table = cuboid("table", [1.0, 1.0, 0.1], at(0.8, 0.0, 0.35));
    let p_can = at(0.7, 0.0, 0.50);
    let mut sdh_only = grasp("side_sdh", &p_can, rot_y(90.0), 0.1);
    sdh_only.hands = Some(vec![HandId(1)]);
    let grasps = vec![
        // From the robot's side: TCP +z along world +x.
        grasp("side", &p_can, rot_y(90.0), 0.1),
        // From above: TCP +z pointing down.
        grasp("top", &p_can, at(0.0, 0.0, 0.08) * rot_y(180.0), 0.1),
        sdh_only,
        // TCP 0.17 m below the can's centre, inside the table: the hand would be in it.
        grasp("under", &p_can, at(0.0, 0.0, -0.17) * rot_y(90.0), 0.1),
    ];
    let p_far = at(3.0, 0.0, 0.50);
    let objects = vec![
        object(can("can", p_can), grasps),
        object(can("far", p_far), vec![grasp("side", &p_far, rot_y(90.0), 0.1)]),
    ];
    let home = vec![0.0, 0.0, 90f64.to_radians(), 0.0, 0.0, 0.0];
    scenario(
        vec![robot("tx90", tx90(), home, Some(HandId(0)))],
        vec![hand("sah", sah(), 0.16), hand("sdh2", sdh2(), 0.18)],
        vec![table],
        objects,
    )
}

#[test]
fn reachable_grasps_with_pregrasps_at_the_stand_off() {
    let scn = cell();
    let w = build(&scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"));
    let o = ObjectId(0);
    let gs = w.select_grasps(R0, o);
    assert!(!gs.is_empty());
    assert_eq!(gs, w.select_grasps(R0, o), "deterministic");
    let names: Vec<&str> = gs.iter().map(|g| scn.objects[0].grasps[g.grasp].name.as_str()).collect();
    assert!(names.contains(&"side") && names.contains(&"top"), "{names:?}");
    assert!(!names.contains(&"side_sdh"), "grasp for another hand: {names:?}");
    assert!(!names.contains(&"under"), "grasp inside the table: {names:?}");
    for g in &gs {
        let gr = &scn.objects[0].grasps[g.grasp];
        let tcp = w.fk_tcp(R0, &g.q_grasp);
        assert!((tcp.translation.vector - gr.pose_world_tcp.translation.vector).norm() < 1e-6);
        assert!(tcp.rotation.angle_to(&gr.pose_world_tcp.rotation) < 1e-6);
        let pre = w.fk_tcp(R0, &g.q_pregrasp);
        let expect = gr.pose_world_tcp * at(0.0, 0.0, -gr.approach);
        assert!((pre.translation.vector - expect.translation.vector).norm() < 1e-6);
        // The stand-off is along the TCP's own -z.
        let back = gr.pose_world_tcp.rotation * Vector3::z();
        assert!(((gr.pose_world_tcp.translation.vector - pre.translation.vector) - back * 0.1).norm() < 1e-6);
        let ctx = CheckCtx::with_absent(ObjectSet::single(o));
        assert!(!w.check(R0, &g.q_grasp, &ctx).is_blocked());
        assert!(!w.check(R0, &g.q_pregrasp, &ctx).is_blocked());
        // The grasp and pre-grasp lie on the same IK branch: a short joint-space move.
        let dist = g.q_grasp.iter().zip(g.q_pregrasp.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(dist < 1.0, "pre-grasp far from grasp: {dist}");
    }
}

#[test]
fn report_marks_unreachable_objects() {
    let w = build(&cell(), &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"));
    let r = report(&w);
    assert_eq!(r.objects.len(), 2);
    assert!(r.objects[0].reachable());
    assert_eq!(r.objects[0].robots[0].grasps, vec!["side".to_string(), "top".to_string()]);
    let unreachable: Vec<&str> = r.unreachable().map(|o| o.name.as_str()).collect();
    assert_eq!(unreachable, vec!["far"]);
}

#[test]
fn held_can_is_not_touched_by_the_hand() {
    let scn = cell();
    let w = build(&scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"));
    let g = &w.select_grasps(R0, ObjectId(0))[0];
    // With the can present, the closed hand does not reach it at the grasp (side grasp).
    let side = w.select_grasps(R0, ObjectId(0)).into_iter().find(|g| g.grasp == 0).expect("side grasp");
    assert_eq!(w.check(R0, &side.q_grasp, &CheckCtx::new()), declutter::world::Check::free());
    let held = w.held(R0, ObjectId(0), g.grasp, &g.q_grasp);
    let ctx = CheckCtx::with_held(ObjectSet::new(), held);
    assert!(!w.check(R0, &g.q_grasp, &ctx).is_blocked());
    assert!(!w.check(R0, &g.q_pregrasp, &ctx).is_blocked());
}

#[test]
fn closed_hands_stay_clear_of_a_can_across_the_tcp() {
    use declutter::world::Check;
    for (h, tcp) in [(0u32, 0.16), (1, 0.18)] {
        let q = [0.0, 0.3, 1.2, 0.4, 0.8, -0.6];
        // Find the TCP pose, then stand a can (r 3.3 cm) across it, axis along the TCP's x or y.
        let probe = scenario(
            vec![robot("tx90", tx90(), vec![0.0; 6], Some(HandId(h)))],
            vec![hand("sah", sah(), 0.16), hand("sdh2", sdh2(), 0.18)],
            vec![],
            vec![],
        );
        let w = build(&probe, &WorldOptions::default(), &FsLoader).unwrap();
        let p_tcp = w.fk_tcp(R0, &q);
        let across_x = p_tcp
            * Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_euler_angles(0.0, 90f64.to_radians(), 0.0),
            );
        let across_y = p_tcp
            * Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_euler_angles(90f64.to_radians(), 0.0, 0.0),
            );
        let objects = vec![
            object(body("can_x", Shape::Cylinder { radius: 0.033, length: 0.3 }, across_x), vec![]),
            object(body("can_y", Shape::Cylinder { radius: 0.033, length: 0.3 }, across_y), vec![]),
        ];
        let mut scn = probe.clone();
        scn.objects = objects;
        let w = build(&scn, &WorldOptions::default(), &FsLoader).unwrap();
        assert_eq!(w.check(R0, &q, &CheckCtx::new()), Check::free(), "hand {h} (tcp {tcp} m)");
        // A can 1 cm closer to the flange does touch the hand: the clearance is real but small.
        let closer = p_tcp
            * at(0.0, 0.0, -0.012)
            * Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_euler_angles(0.0, 90f64.to_radians(), 0.0),
            );
        scn.objects = vec![object(body("can", Shape::Cylinder { radius: 0.033, length: 0.3 }, closer), vec![])];
        let w = build(&scn, &WorldOptions::default(), &FsLoader).unwrap();
        assert_eq!(w.check(R0, &q, &CheckCtx::new()), Check::Touches(ObjectSet::single(ObjectId(0))), "hand {h}");
    }
}
