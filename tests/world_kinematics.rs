//! Forward and inverse kinematics of the shipped models, against hand-computed poses.

mod world_support;

use declutter::diag::FsLoader;
use declutter::resolve::{HandId, RobotId};
use declutter::world::{build, WorldOptions};
use nalgebra::{Matrix3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use world_support::*;

const R0: RobotId = RobotId(0);

fn opts() -> WorldOptions {
    WorldOptions { self_collision_samples: 0, ..WorldOptions::default() }
}

fn d(x: f64) -> f64 {
    x.to_radians()
}

#[test]
fn tx90_flange_matches_hand_computed_poses() {
    let scn = scenario(vec![robot("tx90", tx90(), vec![0.0; 6], None)], vec![], vec![], vec![]);
    let w = build(&scn, &opts(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(w.dof(R0), 6);
    assert_eq!(w.joint_names(R0), ["joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"]);
    let i = Matrix3::identity();
    let ry90 = Matrix3::new(0.0, 0.0, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0);
    let rz90 = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let ry90_rz90 = Matrix3::new(0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let rz90_ry90 = Matrix3::new(0.0, -1.0, 0.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0);
    // (q in degrees, flange position, flange rotation), worked out from the joint offsets:
    // j1 at z 0.478; j2 +x 0.05; j3 +(0, 0.05, 0.425); j5 +z 0.425; flange +z 0.1.
    let cases: [([f64; 6], [f64; 3], Matrix3<f64>); 7] = [
        ([0.0; 6], [0.05, 0.05, 1.428], i),
        ([90.0, 0.0, 0.0, 0.0, 0.0, 0.0], [-0.05, 0.05, 1.428], rz90),
        ([0.0, 90.0, 0.0, 0.0, 0.0, 0.0], [1.0, 0.05, 0.478], ry90),
        ([0.0, 0.0, 90.0, 0.0, 0.0, 0.0], [0.575, 0.05, 0.903], ry90),
        ([0.0, 0.0, 0.0, 0.0, 90.0, 90.0], [0.15, 0.05, 1.328], ry90_rz90),
        ([0.0, 0.0, 0.0, 90.0, 90.0, 0.0], [0.05, 0.15, 1.328], rz90_ry90),
        ([0.0, -90.0, 90.0, 0.0, 0.0, 0.0], [-0.375, 0.05, 1.003], i),
    ];
    for (q, p, r) in cases {
        let q: Vec<f64> = q.iter().map(|x| d(*x)).collect();
        let f = w.fk_flange(R0, &q);
        let dp = (f.translation.vector - Vector3::from(p)).norm();
        assert!(dp < 1e-9, "q {q:?}: flange at {:?}, expected {p:?}", f.translation.vector);
        let dr = (f.rotation.to_rotation_matrix().into_inner() - r).norm();
        assert!(dr < 1e-9, "q {q:?}: rotation {} expected {r}", f.rotation.to_rotation_matrix().into_inner());
    }
}

#[test]
fn tcp_is_flange_times_hand_tcp_and_base_pose_applies() {
    let mut r = robot("tx90", tx90(), vec![0.0; 6], Some(HandId(0)));
    r.pose_world_base = at(1.0, 2.0, 0.5);
    let scn = scenario(vec![r], vec![hand("sah", sah(), 0.16)], vec![], vec![]);
    let w = build(&scn, &opts(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    let q = [0.0, 0.0, 0.0, 0.0, d(90.0), 0.0];
    // Wrist bent 90° about y: the tool points along +x, 0.1 + 0.16 m beyond joint 5.
    let tcp = w.fk_tcp(R0, &q);
    let expect = Vector3::new(1.0 + 0.05 + 0.26, 2.05, 0.5 + 1.328);
    assert!((tcp.translation.vector - expect).norm() < 1e-9, "{:?}", tcp.translation.vector);
}

#[test]
fn planar3_limits_and_fk() {
    let scn = scenario(vec![robot("p", planar3(), vec![0.0; 3], None)], vec![], vec![], vec![]);
    let w = build(&scn, &opts(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(w.limits(R0), [(-d(170.0), d(170.0)); 3].map(|(a, b)| (a, b)));
    let f = w.fk_flange(R0, &[d(90.0), d(-90.0), 0.0]);
    assert!((f.translation.vector - Vector3::new(0.5, 0.4, 0.0)).norm() < 1e-12);
}

#[test]
fn tx90_ik_round_trip() {
    let scn = scenario(
        vec![robot("tx90", tx90(), vec![0.0; 6], Some(HandId(0)))],
        vec![hand("sah", sah(), 0.16)],
        vec![],
        vec![],
    );
    let w = build(&scn, &opts(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let lim = w.limits(R0).to_vec();
    let n = 1000;
    let mut ok = 0;
    for i in 0..n {
        let q: Vec<f64> = lim.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
        let target = w.fk_tcp(R0, &q);
        let sols = w.ik(R0, &target, i, 1);
        if let Some(s) = sols.first() {
            assert!(s.iter().zip(&lim).all(|(v, (lo, hi))| v >= lo && v <= hi));
            let got = w.fk_tcp(R0, s);
            let dp = (got.translation.vector - target.translation.vector).norm();
            let dr = got.rotation.angle_to(&target.rotation);
            if dp < 1e-6 && dr < 1e-6 {
                ok += 1;
            }
        }
    }
    println!("IK round trip: {ok}/{n}");
    assert!(ok * 100 >= n as usize * 99, "only {ok}/{n} recovered");
}

#[test]
fn ik_is_deterministic_and_solutions_distinct() {
    let scn = scenario(vec![robot("tx90", tx90(), vec![0.0; 6], None)], vec![], vec![], vec![]);
    let w = build(&scn, &opts(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    let q = [0.3, 0.4, 0.9, 0.2, 0.7, -0.5];
    let target = w.fk_tcp(R0, &q);
    let a = w.ik(R0, &target, 7, 4);
    let b = w.ik(R0, &target, 7, 4);
    assert_eq!(a, b);
    assert!(a.len() >= 2, "a 6R arm has several solutions here, got {}", a.len());
    for (i, x) in a.iter().enumerate() {
        for y in &a[i + 1..] {
            assert!(x.iter().zip(y.iter()).any(|(u, v)| (u - v).abs() > 1e-4));
        }
    }
}

#[test]
fn tx90_with_hand_self_collision_pairs() {
    let scn = scenario(
        vec![robot("tx90", tx90(), vec![0.0; 6], Some(HandId(0)))],
        vec![hand("sah", sah(), 0.16)],
        vec![],
        vec![],
    );
    let w = build(&scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    let pairs = w.self_collision_pairs(R0);
    println!("{pairs:?}");
    // Adjacent links and the hand against the flange link are never checked.
    for (a, b) in &pairs {
        assert!(!(a == &"link_5" && b == &"sah"), "{a} {b}");
        assert!(!(a == &"link_2" && b == &"link_3"), "{a} {b}");
    }
    // The hand can hit the upper arm and the forearm: those pairs stay.
    assert!(pairs.contains(&("link_2", "sah")) && pairs.contains(&("link_4", "sah")), "{pairs:?}");
    // Exactly the pairs that testing every one of the 2000 samples kept (637bb0f): the
    // sampling may stop testing a decided pair, never decide it differently.
    let pinned = [
        ("base_link", "link_2"),
        ("base_link", "link_3"),
        ("base_link", "link_4"),
        ("base_link", "link_5"),
        ("base_link", "link_6"),
        ("base_link", "sah"),
        ("link_1", "link_3"),
        ("link_1", "link_4"),
        ("link_1", "link_5"),
        ("link_1", "link_6"),
        ("link_1", "sah"),
        ("link_2", "link_4"),
        ("link_2", "link_5"),
        ("link_2", "link_6"),
        ("link_2", "sah"),
        ("link_3", "link_5"),
        ("link_3", "link_6"),
        ("link_3", "sah"),
        ("link_4", "link_6"),
        ("link_4", "sah"),
    ];
    assert_eq!(pairs, pinned);
}

/// A slider carrying a revolute joint whose mimic twin follows at twice the angle plus 0.1.
const MIMIC: &str = r#"<robot name="m">
<link name="base"/><link name="carriage"/><link name="arm"/><link name="twin"/><link name="tip"/>
<transmission name="t"><type>transmission_interface/SimpleTransmission</type></transmission>
<gazebo><plugin name="x" filename="libx.so"/></gazebo>
<joint name="slide" type="prismatic"><parent link="base"/><child link="carriage"/><axis xyz="1 0 0"/>
  <limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>
<joint name="turn" type="revolute"><parent link="carriage"/><child link="arm"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
  <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<joint name="follow" type="revolute"><parent link="arm"/><child link="twin"/><origin xyz="0.2 0 0"/><axis xyz="0 0 1"/>
  <mimic joint="turn" multiplier="2" offset="0.1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="tool" type="fixed"><parent link="twin"/><child link="tip"/><origin xyz="0.1 0 0"/></joint>
</robot>"#;

#[test]
fn prismatic_mimic_fixed_and_ignored_tags() {
    let loader = declutter::diag::MemLoader::new().with("/m/m.urdf", MIMIC);
    let scn = scenario(vec![robot("m", "/m/m.urdf", vec![0.0, 0.0], None)], vec![], vec![], vec![]);
    let w = build(&scn, &opts(), &loader).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(w.joint_names(R0), ["slide", "turn"]);
    assert_eq!(w.limits(R0), [(-0.5, 0.5), (-1.0, 1.0)]);
    assert_eq!(w.flange_link(R0), "tip");
    let (s, t) = (0.3, 0.4);
    let f = w.fk_flange(R0, &[s, t]);
    // The arm turns by t about z at (s, 0, 0.1); the twin by a further 2t + 0.1 at 0.2 along the arm.
    let a1 = t;
    let a2 = t + 2.0 * t + 0.1;
    let expect = Vector3::new(s + 0.2 * a1.cos() + 0.1 * a2.cos(), 0.2 * a1.sin() + 0.1 * a2.sin(), 0.1);
    assert!((f.translation.vector - expect).norm() < 1e-12, "{:?} vs {expect:?}", f.translation.vector);
    assert!((f.rotation.angle() - a2).abs() < 1e-12);
    // IK on this 2-joint arm: the position-and-orientation target of a reachable pose.
    let sols = w.ik(R0, &f, 3, 4);
    assert!(!sols.is_empty());
    for q in &sols {
        assert!((w.fk_flange(R0, q).translation.vector - expect).norm() < 1e-9);
    }
}

/// The planar arm's world, for the wrong-length contract below.
fn planar_world() -> declutter::world::World {
    let scn = scenario(vec![robot("p", planar3(), vec![0.0; 3], None)], vec![], vec![], vec![]);
    build(&scn, &opts(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"))
}

// A configuration of the wrong length is a caller's bug: a plain panic naming the
// lengths, not an index out of bounds somewhere inside (documented on `World::fk_flange`).
#[test]
#[should_panic(expected = "configuration of robot `p` has 2 values, but the robot has 3 joints")]
fn check_with_a_short_configuration_panics_plainly() {
    planar_world().check(R0, &[0.0, 0.0], &declutter::world::CheckCtx::new());
}

#[test]
#[should_panic(expected = "configuration of robot `p` has 4 values, but the robot has 3 joints")]
fn fk_links_with_a_long_configuration_panics_plainly() {
    planar_world().fk_links(R0, &[0.0; 4]);
}

#[test]
#[should_panic(expected = "configuration of robot `p` has 2 values, but the robot has 3 joints")]
fn segment_with_a_short_end_panics_plainly() {
    planar_world().check_segment(R0, &[0.0; 3], &[0.0; 2], 0.1, &declutter::world::CheckCtx::new());
}

#[test]
fn ik_of_a_non_finite_pose_has_no_solution() {
    let mut pose = at(0.5, 0.0, 0.0);
    pose.translation.vector.x = f64::NAN;
    assert!(planar_world().ik(R0, &pose, 1, 4).is_empty());
}

/// Three links 0.4 m long in a row, joints 0.5 m apart turning about z, each joint
/// limited to ±`limit` rad.
fn three_links(limit: f64) -> String {
    three_links_within(-limit, limit)
}

/// [`three_links`], each joint limited to `lower..upper` rad.
fn three_links_within(lower: f64, upper: f64) -> String {
    let link = |n: &str| {
        format!(
            r#"<link name="{n}"><collision><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.05 0.05"/></geometry></collision></link>"#
        )
    };
    let joint = |n: &str, p: &str, c: &str, x: f64| {
        format!(
            r#"<joint name="{n}" type="revolute"><parent link="{p}"/><child link="{c}"/><origin xyz="{x} 0 0"/><axis xyz="0 0 1"/><limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/></joint>"#
        )
    };
    format!(
        r#"<robot name="three"><link name="base"/>{}{}{}{}{}{}</robot>"#,
        link("l1"),
        link("l2"),
        link("l3"),
        joint("j1", "base", "l1", 0.0),
        joint("j2", "l1", "l2", 0.5),
        joint("j3", "l2", "l3", 0.5)
    )
}

fn pairs_of(urdf: &str, samples: usize) -> Vec<(String, String)> {
    pairs_at_home(urdf, samples, vec![0.0; 3])
}

fn pairs_at_home(urdf: &str, samples: usize, home: Vec<f64>) -> Vec<(String, String)> {
    let loader = declutter::diag::MemLoader::new().with("/m/three.urdf", urdf.to_string());
    let scn = scenario(vec![robot("three", "/m/three.urdf", home, None)], vec![], vec![], vec![]);
    let opts = WorldOptions { self_collision_samples: samples, ..WorldOptions::default() };
    let w = build(&scn, &opts, &loader).unwrap_or_else(|e| panic!("{e:?}"));
    w.self_collision_pairs(R0).into_iter().map(|(a, b)| (a.to_string(), b.to_string())).collect()
}

#[test]
fn a_pair_colliding_in_nearly_every_sample_is_pruned_and_the_others_are_kept() {
    let l1_l3 = vec![("l1".to_string(), "l3".to_string())];
    // 2.9 to 3.1 rad: l2 folds back over l1 and l3 back over l1 again, flat on it in
    // every configuration: in contact by construction, pruned (MoveIt's "always" rule).
    assert_eq!(pairs_at_home(&three_links_within(2.9, 3.1), 500, vec![3.0; 3]), Vec::<(String, String)>::new());
    // ±2.9 rad: l2 folds back over l1 and l3 with it now and then: the pair is checked.
    assert_eq!(pairs_of(&three_links(2.9), 500), l1_l3);
    // ±0.3 rad: l3 starts at least 0.5 + 0.5·cos(0.3) ≈ 0.98 m out, l1 ends at 0.4 m: never
    // near, and kept all the same (its boxes apart answer each check at once; proving it
    // stays apart would take every sample).
    assert_eq!(pairs_of(&three_links(0.3), 500), l1_l3);
    // Without sampling nothing is pruned but adjacent pairs.
    assert_eq!(pairs_of(&three_links(0.3), 0), l1_l3);
}
