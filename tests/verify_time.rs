//! The verifier's replay in time, on hand-built timelines of two planar arms facing
//! each other, and its sampling bound against hand-computed geometry.

mod world_support;

use std::f64::consts::FRAC_PI_2;

use declutter::diag::FsLoader;
use declutter::resolve::{ObjectId, RobotId, Scenario};
use declutter::verify::time::{
    replay, Event, EventKind, Obstacle, Party, RateLimits, ReplayOptions, TimeViolation, TimedAction, TimedPoint,
    Timeline, Track, SAMPLE_BOUND,
};
use declutter::verify::{Violation, ViolationKind};
use declutter::world::{build, JointReach, World, WorldOptions};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use world_support::*;

const P1: RobotId = RobotId(0);
const P2: RobotId = RobotId(1);

/// `p1` at the origin along +x, `p2` at x = `x2` turned to face it: at q = 0 both reach
/// 0.9 m, so with `x2` = 1.5 their last links overlap between x = 0.6 and 0.9.
fn facing_at(x2: f64) -> Scenario {
    let mut p2 = robot("p2", planar3(), vec![FRAC_PI_2, 0.0, 0.0], None);
    p2.pose_world_base = Isometry3::from_parts(
        Translation3::new(x2, 0.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI),
    );
    let p1 = robot("p1", planar3(), vec![FRAC_PI_2, 0.0, 0.0], None);
    // A block far off to the side, to be carried in one test.
    let block = object(cuboid("block", [0.04, 0.04, 0.04], at(0.0, -0.9, 0.0)), vec![]);
    scenario(vec![p1, p2], vec![], vec![], vec![block])
}

fn facing() -> Scenario {
    facing_at(1.5)
}

fn world(scn: &Scenario) -> World {
    let opts = WorldOptions { self_collision_samples: 0, ..WorldOptions::default() };
    build(scn, &opts, &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"))
}

/// Rest-to-rest moves of joint 1 through `(t, q1)` knots, the other joints at 0.
fn track(robot: RobotId, knots: &[(f64, f64)]) -> Track {
    Track {
        robot,
        points: knots.iter().map(|&(t, q1)| TimedPoint { t, q: vec![q1, 0.0, 0.0], qd: vec![0.0; 3] }).collect(),
    }
}

fn options(velocity: f64, acceleration: f64) -> ReplayOptions {
    ReplayOptions {
        bound: SAMPLE_BOUND,
        clearance: 0.0,
        limits: RateLimits { velocity: vec![vec![velocity; 3]; 2], acceleration: vec![vec![acceleration; 3]; 2] },
        every_step: false,
        every_pair: false,
        record_instants: false,
    }
}

/// `p1` swings in during 0..1 s and out during 2..3 s; `p2` does the same `shift` seconds later.
fn swings(shift: f64) -> Timeline<'static> {
    let up = FRAC_PI_2;
    Timeline {
        makespan: 6.0,
        tracks: vec![track(P1, &[(0.0, up), (1.0, 0.0), (2.0, 0.0), (3.0, up), (6.0, up)]), {
            let mut k = vec![(0.0, up)];
            k.extend([(shift, up), (shift + 1.0, 0.0), (shift + 2.0, 0.0), (shift + 3.0, up)]);
            k.push((6.0, up));
            k.dedup_by(|a, b| a.0 == b.0);
            track(P2, &k)
        }],
        events: vec![],
        actions: vec![],
    }
}

fn kinds(v: &[Violation]) -> Vec<&TimeViolation> {
    v.iter()
        .filter_map(|v| match &v.kind {
            ViolationKind::Time(t) => Some(t),
            _ => None,
        })
        .collect()
}

#[test]
fn arms_taking_turns_pass_and_starting_together_collide_naming_both_and_the_time() {
    let scn = facing();
    let w = world(&scn);
    let (summary, v) = replay(&w, &swings(3.0), &options(3.0, 10.0));
    assert!(v.is_empty(), "{v:#?}");
    // Apart, the arms are proved clear for long stretches; every 2 mm they would take
    // thousands of instants.
    let (every, v) = replay(&w, &swings(3.0), &ReplayOptions { every_step: true, ..options(3.0, 10.0) });
    assert!(v.is_empty(), "{v:#?}");
    assert!(every.samples > 1000 && summary.samples * 10 < every.samples, "{summary:?}, every step {every:?}");

    let (_, v) = replay(&w, &swings(0.0), &options(3.0, 10.0));
    assert!(!v.is_empty());
    let text: Vec<String> = v.iter().map(ToString::to_string).collect();
    // The first contact: both links 3 meet while swinging in, before both arrive at 1 s.
    let first = &v[0];
    let t = match first.location {
        declutter::verify::Location::At { t } => t,
        ref l => panic!("not located in time: {l:?}"),
    };
    assert!(t > 0.3 && t < 1.0, "{text:#?}");
    // Parallel bars meet along the stretch both cover, 0.6 to 0.9 m from p1: p1's links 2
    // and 3 against p2's link 3 (0.6 to 0.8 m from p1).
    match &first.kind {
        ViolationKind::Time(TimeViolation::Contact {
            a: Party::Body { robot, body },
            b: Obstacle::Moving(Party::Body { robot: other, body: other_body }),
            distance: None,
            ..
        }) => {
            assert_eq!((robot.as_str(), other.as_str()), ("p1", "p2"));
            assert!(body == "link2" || body == "link3", "{body}");
            assert_eq!(other_body, "link3");
        }
        k => panic!("{k:?}"),
    }
    assert!(
        text[0].starts_with("t = 0.9")
            && text[0].contains("robot `p1` body `link")
            && text[0].contains("touches robot `p2` body `link3`"),
        "{text:#?}"
    );
}

#[test]
fn the_contact_is_found_where_the_geometry_says() {
    // Both arms swing rest-to-rest from 90° to 0 in 1 s: q(s) = π/2 (1 − 3s² + 2s³). They are
    // point-symmetric about (0.75, 0), so their bars (0.04 wide) are parallel, each
    // 0.75 sin q from that point: they overlap deeper than the 1 mm contact tolerance once
    // 2 (0.02 − 0.75 sin q) > 0.001.
    let w = world(&facing());
    let (_, v) = replay(&w, &swings(0.0), &options(3.0, 10.0));
    let t = match v[0].location {
        declutter::verify::Location::At { t } => t,
        ref l => panic!("{l:?}"),
    };
    let q_at = |s: f64| FRAC_PI_2 * (1.0 - 3.0 * s * s + 2.0 * s * s * s);
    let t_geo = (0..1_000_000).map(|k| k as f64 * 1e-6).find(|&s| 0.75 * q_at(s).sin() < 0.02 - 5e-4).unwrap_or(1.0);
    assert!((t_geo - 0.93).abs() < 0.01, "{t_geo}");
    // The first sample past that instant: within one sample step (≈ 1 ms here).
    assert!(t >= t_geo - 1e-9 && t - t_geo < 2e-3, "replay {t}, geometry {t_geo}");
}

#[test]
fn a_segment_too_fast_and_an_acceleration_too_hard_are_named_with_joint_and_time() {
    let w = world(&facing());
    // Peak speed of the rest-to-rest swing: 1.5 · (π/2) / 1 s = 2.356 rad/s; acceleration at
    // the ends 6 · (π/2) = 9.42 rad/s².
    let (_, v) = replay(&w, &swings(3.0), &options(2.0, 10.0));
    let k = kinds(&v);
    assert!(
        k.iter().any(|v| matches!(v, TimeViolation::TooFast { robot, joint, speed, limit: 2.0 }
            if robot == "p1" && joint == "joint1" && (speed - 1.5 * FRAC_PI_2).abs() < 1e-9)),
        "{v:#?}"
    );
    let (_, v) = replay(&w, &swings(3.0), &options(3.0, 9.0));
    let k = kinds(&v);
    assert!(
        k.iter().any(|v| matches!(v, TimeViolation::TooHardAcceleration { robot, joint, acceleration, .. }
            if robot == "p2" && joint == "joint1" && (acceleration - 6.0 * FRAC_PI_2).abs() < 1e-9)),
        "{v:#?}"
    );
}

#[test]
fn a_trajectory_that_does_not_cover_the_makespan_or_goes_back_in_time_is_refused() {
    let w = world(&facing());
    let mut tl = swings(3.0);
    tl.makespan = 7.0;
    let (_, v) = replay(&w, &tl, &options(3.0, 10.0));
    assert!(kinds(&v).iter().any(|v| matches!(v, TimeViolation::DoesNotCover { .. })), "{v:#?}");
    let mut tl = swings(3.0);
    tl.tracks[0].points[2].t = 0.5;
    let (_, v) = replay(&w, &tl, &options(3.0, 10.0));
    assert!(kinds(&v).iter().any(|v| matches!(v, TimeViolation::TimeNotIncreasing { index: 2, .. })), "{v:#?}");
}

/// `p1` picks the block off to its side (joint 1 at −90° puts link 3 around it) and
/// carries it up in front of `p2`.
fn carry(grasp_t: f64, release_t: f64, p2_in: bool) -> (Vec<Vec<f64>>, Vec<Vec<f64>>, Timeline<'static>) {
    let down = -FRAC_PI_2;
    let tl = Timeline {
        makespan: 6.0,
        tracks: vec![
            track(P1, &[(0.0, FRAC_PI_2), (2.0, down), (2.5, down), (4.0, 0.0), (6.0, 0.0)]),
            if p2_in {
                track(P2, &[(0.0, FRAC_PI_2), (4.0, FRAC_PI_2), (5.0, 0.0), (6.0, 0.0)])
            } else {
                track(P2, &[(0.0, FRAC_PI_2), (6.0, FRAC_PI_2)])
            },
        ],
        events: vec![
            Event { t: grasp_t, robot: P1, kind: EventKind::Grasp, object: ObjectId(0), fingers: Vec::new() },
            Event { t: release_t, robot: P1, kind: EventKind::Release, object: ObjectId(0), fingers: Vec::new() },
        ],
        actions: vec![],
    };
    (vec![vec![FRAC_PI_2, 0.0, 0.0], vec![down, 0.0, 0.0]], vec![vec![down, 0.0, 0.0], vec![0.0, 0.0, 0.0]], tl)
}

#[test]
fn the_block_is_an_obstacle_until_grasped_and_moves_with_the_hand_after() {
    // p2 stands off so that at q = 0 its tip (x = 0.91) only reaches the block p1 holds out.
    let mut scn = facing_at(1.81);
    // p1's drop is where it ends, straight out along +x.
    scn.robots[0].drop =
        Some(declutter::resolve::JointValues { values: vec![0.0; 3], span: sp(0, 1), units: Vec::new() });
    let w = world(&scn);
    let (approach, retreat, mut tl) = carry(2.0, 6.0, false);
    let after: Vec<u32> = Vec::new();
    tl.actions = vec![TimedAction {
        id: 1,
        robot: P1,
        object: Some(ObjectId(0)),
        grasp: 0,
        after: &after,
        start: 0.0,
        end: 6.0,
        approach: &approach,
        retreat: &retreat,
        checked: true,
    }];
    // The whole approach sweeps link 3 onto the block: its last segment is the move in, where
    // the grasped object is no obstacle.
    let (_, v) = replay(&w, &tl, &options(3.0, 10.0));
    assert!(v.is_empty(), "{v:#?}");
    // With no action to explain them the events are refused, and the block, never picked,
    // is hit where it stands.
    let mut bare = tl.clone();
    bare.actions.clear();
    let (_, v) = replay(&w, &bare, &options(3.0, 10.0));
    let k = kinds(&v);
    assert!(k.iter().any(|v| matches!(v, TimeViolation::UnexpectedEvent { kind: EventKind::Grasp, .. })), "{v:#?}");
    assert!(
        k.iter()
            .any(|v| matches!(v, TimeViolation::Contact { a: Party::Body { robot, body }, b: Obstacle::Object(o), .. }
            if robot == "p1" && body == "link3" && o == "block")),
        "{v:#?}"
    );

    // An action of p2 that waits for the block to be carried clear (p1 back at its second
    // retreat waypoint, at 4 s) but starts at 1 s.
    let home2 = vec![vec![FRAC_PI_2, 0.0, 0.0]];
    let waits = vec![1u32];
    let mut early = tl.clone();
    early.actions.push(TimedAction {
        id: 2,
        robot: P2,
        object: None,
        grasp: 0,
        after: &waits,
        start: 1.0,
        end: 6.0,
        approach: &home2,
        retreat: &[],
        checked: true,
    });
    let (_, v) = replay(&w, &early, &options(3.0, 10.0));
    assert!(
        kinds(&v).iter().any(|v| matches!(v, TimeViolation::StartsBeforeClear { action: 2, by: 1, clear, .. }
            if (clear - 4.0).abs() < 1e-12)),
        "{v:#?}"
    );
    early.actions[1].start = 4.0;
    let (_, v) = replay(&w, &early, &options(3.0, 10.0));
    assert!(v.is_empty(), "{v:#?}");

    // Carried in front of p2 while p2 swings in: p2 hits the block p1 holds.
    let (_, _, mut tl2) = carry(2.0, 6.0, true);
    tl2.actions = tl.actions.clone();
    let (_, v) = replay(&w, &tl2, &options(3.0, 10.0));
    let k = kinds(&v);
    assert!(
        k.iter().any(|v| matches!(v, TimeViolation::Contact { a: Party::Held { robot: holder, object }, b: Obstacle::Moving(Party::Body { robot, .. }), .. }
            if robot == "p2" && holder == "p1" && object == "block")),
        "{v:#?}"
    );

    // The grasp event moved to before the hand is there.
    let (_, _, mut tl3) = carry(1.0, 6.0, false);
    tl3.actions = tl.actions.clone();
    let (_, v) = replay(&w, &tl3, &options(3.0, 10.0));
    assert!(
        kinds(&v).iter().any(|v| matches!(v, TimeViolation::EventMisplaced { kind: EventKind::Grasp, action: 1, .. })),
        "{v:#?}"
    );
    // The grasp event removed.
    let (_, _, mut tl4) = carry(2.0, 6.0, false);
    tl4.actions = tl.actions.clone();
    tl4.events.remove(0);
    let (_, v) = replay(&w, &tl4, &options(3.0, 10.0));
    assert!(
        kinds(&v).iter().any(|v| matches!(v, TimeViolation::EventMissing { kind: EventKind::Grasp, action: 1, .. })),
        "{v:#?}"
    );
    // A waypoint of the action that the trajectory never visits.
    let (_, _, mut tl5) = carry(2.0, 6.0, false);
    let skipped = vec![vec![FRAC_PI_2, 0.0, 0.0], vec![0.3, 0.0, 0.0], vec![-FRAC_PI_2, 0.0, 0.0]];
    tl5.actions = tl.actions.clone();
    tl5.actions[0].approach = &skipped;
    let (_, v) = replay(&w, &tl5, &options(3.0, 10.0));
    assert!(
        kinds(&v).iter().any(|v| matches!(v, TimeViolation::WaypointSkipped { action: 1, index: 1, .. })),
        "{v:#?}"
    );
}

/// Corners of the planar arm's three link boxes (link frame: x from 0 to the length, ±0.02 in y and z).
fn corners(w: &World, r: RobotId, q: &[f64]) -> Vec<Point3<f64>> {
    let lengths = [("link1", 0.4), ("link2", 0.3), ("link3", 0.2)];
    let links = w.fk_links(r, q);
    let mut out = Vec::new();
    for (name, len) in lengths {
        let pose = &links.iter().find(|(n, _)| n == name).expect("planar link").1;
        for x in [0.0, len] {
            for y in [-0.02, 0.02] {
                for z in [-0.02, 0.02] {
                    out.push(pose * Point3::new(x, y, z));
                }
            }
        }
    }
    out
}

#[test]
fn the_reach_of_the_planar_arm_is_its_hand_computed_lever() {
    let w = world(&facing());
    let reach = w.joint_reach(P1);
    // Link 3's box: centre 0.1 m out, half-diagonal √(0.1² + 0.02² + 0.02²); links 2 and 1
    // add their lengths, 0.3 and 0.4 m.
    let tip = 0.1 + (0.0108f64).sqrt();
    for (got, want) in reach.bodies.iter().zip([0.7 + tip, 0.3 + tip, tip]) {
        assert!((got - want).abs() < 1e-12, "{reach:?}");
    }
    assert_eq!(reach.flange.iter().map(|v| (v * 1e12).round() / 1e12).collect::<Vec<_>>(), vec![0.9, 0.5, 0.2]);
    assert_eq!(reach.turn, vec![1.0; 3]);
    // A point 0.1 m from the flange: joint 1 levers it at most 1.0 m per radian.
    assert!((reach.with_held(0.1)[0] - 1.0).abs() < 1e-12);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// No corner of any link moves farther than the bound says, for any start and small move.
    #[test]
    fn no_point_moves_more_than_the_reach_bound(
        q in prop::collection::vec(-2.5f64..2.5, 3),
        dq in prop::collection::vec(-0.05f64..0.05, 3),
    ) {
        let w = world(&facing());
        let reach = w.joint_reach(P1).bodies;
        let q2: Vec<f64> = q.iter().zip(&dq).map(|(a, d)| a + d).collect();
        let bound = JointReach::displacement(&reach, &dq);
        for (a, b) in corners(&w, P1, &q).iter().zip(corners(&w, P1, &q2)) {
            prop_assert!((b - a).norm() <= bound + 1e-12, "moved {} > {}", (b - a).norm(), bound);
        }
    }
}

mod time_support;

#[test]
fn the_dense_recheck_agrees_on_the_swings() {
    let w = world(&facing());
    assert!(time_support::dense_contacts(&w, &swings(3.0), SAMPLE_BOUND / 4.0).is_empty());
    let found = time_support::dense_contacts(&w, &swings(0.0), SAMPLE_BOUND / 4.0);
    assert!(found.iter().any(|(t, what)| (0.9..1.1).contains(t) && what.contains("robot 0 body link")), "{found:?}");
}

/// Three links 0.4 m long, joints 0.5 m apart turning about z within 2.9 to 3.1 rad:
/// link 2 folds back over link 1 and link 3 back over link 1 again, flat on it in every
/// configuration, so sampling prunes their pair (in contact by construction).
const THREE: &str = r#"<robot name="three"><link name="base"/>
<link name="l1"><collision><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.05 0.05"/></geometry></collision></link>
<link name="l2"><collision><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.05 0.05"/></geometry></collision></link>
<link name="l3"><collision><origin xyz="0.2 0 0"/><geometry><box size="0.4 0.05 0.05"/></geometry></collision></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="2.9" upper="3.1" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="2.9" upper="3.1" effort="1" velocity="1"/></joint>
<joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="2.9" upper="3.1" effort="1" velocity="1"/></joint>
</robot>"#;

#[test]
fn self_collision_is_checked_over_every_pair_the_sampled_pruning_dropped() {
    let loader = declutter::diag::MemLoader::new().with("/m/three.urdf", THREE.to_string());
    let scn = scenario(vec![robot("three", "/m/three.urdf", vec![3.0; 3], None)], vec![], vec![], vec![]);
    let opts = WorldOptions { self_collision_samples: 500, ..WorldOptions::default() };
    let w = build(&scn, &opts, &loader).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(w.self_collision_pairs(P1).is_empty(), "the planner's list: {:?}", w.self_collision_pairs(P1));
    let names = w.bodies(P1);
    let all: Vec<(&str, &str)> =
        w.self_pairs_unpruned(P1).iter().map(|&(a, b)| (names[a].name.as_str(), names[b].name.as_str())).collect();
    // Adjacent links are never a pair; links 1 and 3 are, whatever the sampling found.
    assert_eq!(all, vec![("l1", "l3")]);
}

/// An arm folded onto itself (link 3 crossing link 1) turning as a whole about joint 1:
/// the pair's distance never changes, so no bound on it ever runs out, and only the
/// check can see the contact: at the first instant, and in the mode that checks every
/// step at that same instant.
#[test]
fn a_pair_that_does_not_move_apart_is_checked_not_taken_as_proved_by_the_others() {
    let scn = facing_at(5.0);
    let w = world(&scn);
    // Joint 2 at 2.9 rad folds link 2 back over link 1; joint 3 at 1.815 rad points link 3
    // straight down across it (through y = 0 at x = 0.109).
    let folded = |q1: f64| TimedPoint { t: 0.0, q: vec![q1, 2.9, 1.815], qd: vec![0.0; 3] };
    let turn = Track { robot: P1, points: vec![folded(0.0), TimedPoint { t: 1.0, ..folded(1.0) }] };
    let tl = Timeline {
        makespan: 1.0,
        tracks: vec![turn, track(P2, &[(0.0, 0.0), (1.0, 0.0)])],
        events: vec![],
        actions: vec![],
    };
    for every_step in [false, true] {
        let (_, v) = replay(&w, &tl, &ReplayOptions { every_step, ..options(3.0, 10.0) });
        let text: Vec<String> = v.iter().map(ToString::to_string).collect();
        assert_eq!(v.len(), 1, "{text:#?}");
        assert_eq!(v[0].location, declutter::verify::Location::At { t: 0.0 }, "{text:#?}");
        assert!(text[0].contains("robot `p1` body `link1`") && text[0].contains("`link3`"), "{text:#?}");
    }
}

/// Points fixed to each shape of the robot: its bounding sphere's centre and six points on
/// that sphere, world frame.
fn shape_points(w: &World, r: RobotId, q: &[f64]) -> Vec<parry3d_f64::math::Vector> {
    use parry3d_f64::math::Vector as V;
    let mut posed = Vec::new();
    w.pose_shapes(r, q, None, &mut posed);
    let mut out = Vec::new();
    for s in &posed {
        let b = s.shape.0.compute_local_bounding_sphere();
        for d in [V::ZERO, V::X, V::NEG_X, V::Y, V::NEG_Y, V::Z, V::NEG_Z] {
            out.push(s.pose.transform_point(b.center + d * b.radius));
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The TX-90 with its hand: no point of any shape moves farther than the bound.
    #[test]
    fn no_point_of_the_tx90_moves_more_than_the_reach_bound(
        q in prop::collection::vec(-2.0f64..2.0, 6),
        dq in prop::collection::vec(-0.02f64..0.02, 6),
    ) {
        let scn = scenario(
            vec![robot("tx90", tx90(), vec![0.0; 6], Some(declutter::resolve::HandId(0)))],
            vec![hand("sah", sah(), 0.16)],
            vec![],
            vec![],
        );
        let w = world(&scn);
        let reach = w.joint_reach(P1).bodies;
        let q2: Vec<f64> = q.iter().zip(&dq).map(|(a, d)| a + d).collect();
        let bound = JointReach::displacement(&reach, &dq);
        for (a, b) in shape_points(&w, P1, &q).iter().zip(shape_points(&w, P1, &q2)) {
            prop_assert!((b - *a).length() <= bound + 1e-12, "moved {} > {}", (b - *a).length(), bound);
        }
    }
}

#[test]
fn a_clearance_is_a_distance_every_moving_pair_must_keep() {
    // Taking turns, the arms come no nearer than 0.58 m: a tip at x = 0.9 against the other
    // arm's side at 1.5 − 0.02, at rest.
    let w = world(&facing());
    let with = |c: f64| ReplayOptions { clearance: c, ..options(3.0, 10.0) };
    let (_, v) = replay(&w, &swings(3.0), &with(0.579));
    assert!(v.is_empty(), "{v:#?}");
    let (_, v) = replay(&w, &swings(3.0), &with(0.581));
    assert!(!v.is_empty());
    let (_, v) = replay(&w, &swings(3.0), &with(0.6));
    let k = kinds(&v);
    assert!(!k.is_empty());
    for v in &k {
        match v {
            TimeViolation::Contact {
                distance: Some(d),
                clearance,
                a: Party::Body { robot, .. },
                b: Obstacle::Moving(Party::Body { robot: other, .. }),
            } => {
                assert_eq!((robot.as_str(), other.as_str(), *clearance), ("p1", "p2", 0.6));
                // Reported where it first comes too near.
                assert!(*d >= 0.58 - 1e-9 && *d < 0.6, "{d}");
            }
            v => panic!("{v:?}"),
        }
    }
    assert!(v[0].to_string().contains("mm from robot `p2`"), "{}", v[0]);
}

/// Position of a Hermite trajectory at `t` (held at its ends), as the replay interpolates.
fn q_at(points: &[TimedPoint], t: f64) -> Vec<f64> {
    use declutter::verify::time::hermite::Cubic;
    let k = points.partition_point(|p| p.t <= t).saturating_sub(1).min(points.len() - 2);
    let (a, b) = (&points[k], &points[k + 1]);
    let h = b.t - a.t;
    let s = ((t - a.t) / h).clamp(0.0, 1.0);
    (0..a.q.len()).map(|j| Cubic::new(h, a.q[j], a.qd[j], b.q[j], b.qd[j]).position(s)).collect()
}

/// Random trajectories through `knots` (interval, configuration, velocity), at rest at
/// both ends.
fn through(knots: &[(f64, Vec<f64>, Vec<f64>)]) -> Vec<TimedPoint> {
    let mut t = 0.0;
    let last = knots.len() - 1;
    knots
        .iter()
        .enumerate()
        .map(|(i, (dt, q, qd))| {
            if i > 0 {
                t += dt;
            }
            let qd = if i == 0 || i == last { vec![0.0; q.len()] } else { qd.clone() };
            TimedPoint { t, q: q.clone(), qd }
        })
        .collect()
}

/// The instants the every-step replay samples for `p1` on `points` (any other robot
/// standing at 0).
fn instants(w: &World, points: &[TimedPoint]) -> Vec<f64> {
    let end = points.last().expect("points").t;
    let mut tracks = vec![Track { robot: P1, points: points.to_vec() }];
    for r in w.scenario().robot_ids().skip(1) {
        let z: Vec<f64> = vec![0.0; w.dof(r)];
        let (a, b) = (TimedPoint { t: 0.0, q: z.clone(), qd: z.clone() }, TimedPoint { t: end, q: z.clone(), qd: z });
        tracks.push(Track { robot: r, points: vec![a, b] });
    }
    let tl = Timeline { makespan: end, tracks, events: vec![], actions: vec![] };
    let opts = ReplayOptions { every_step: true, record_instants: true, ..options(1e3, 1e5) };
    replay(w, &tl, &opts).0.instants
}

/// The farthest any of the points `at(t)` moves from one instant of `ts` up to the next
/// (looked at `looks` times between them); an error when it is more than the bound.
fn widest_step(ts: &[f64], looks: usize, at: impl Fn(f64) -> Vec<[f64; 3]>) -> Result<f64, String> {
    if ts.len() <= 2 {
        return Err(format!("only {} instants", ts.len()));
    }
    let mut widest: f64 = 0.0;
    for pair in ts.windows(2) {
        let from = at(pair[0]);
        for i in 1..=looks {
            let t = pair[0] + (pair[1] - pair[0]) * i as f64 / looks as f64;
            for (a, b) in from.iter().zip(at(t)) {
                let moved = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
                widest = widest.max(moved);
                if moved > SAMPLE_BOUND + 1e-12 {
                    return Err(format!("{moved} between {} and {t}", pair[0]));
                }
            }
        }
    }
    Ok(widest)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Between two instants of the replay no corner of the planar arm moves more than the
    /// bound (sampled 16 times between them), on random trajectories: each window's own
    /// peak speeds step it, and the bound still holds.
    #[test]
    fn between_two_instants_no_point_of_the_planar_arm_moves_more_than_the_bound(
        knots in prop::collection::vec(
            (0.1f64..0.6, prop::collection::vec(-2.5f64..2.5, 3), prop::collection::vec(-3.0f64..3.0, 3)),
            2..5,
        ),
    ) {
        let w = world(&facing_at(5.0));
        let points = through(&knots);
        let at = |t: f64| corners(&w, P1, &q_at(&points, t)).iter().map(|p| [p.x, p.y, p.z]).collect();
        let widest = widest_step(&instants(&w, &points), 16, at).map_err(TestCaseError::fail)?;
        // Not trivially: some steps use a good part of the bound.
        prop_assert!(widest > 0.1 * SAMPLE_BOUND, "widest step {widest}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// The same for the TX-90 with its hand, whose axes are not parallel: no point of any
    /// shape moves more than the bound between two instants.
    #[test]
    fn between_two_instants_no_point_of_the_tx90_moves_more_than_the_bound(
        knots in prop::collection::vec(
            (0.2f64..0.8, prop::collection::vec(-2.0f64..2.0, 6), prop::collection::vec(-1.5f64..1.5, 6)),
            2..4,
        ),
    ) {
        let scn = scenario(
            vec![robot("tx90", tx90(), vec![0.0; 6], Some(declutter::resolve::HandId(0)))],
            vec![hand("sah", sah(), 0.16)],
            vec![],
            vec![],
        );
        let w = world(&scn);
        let points = through(&knots);
        let at = |t: f64| shape_points(&w, P1, &q_at(&points, t)).iter().map(|p| p.to_array()).collect();
        let widest = widest_step(&instants(&w, &points), 8, at).map_err(TestCaseError::fail)?;
        prop_assert!(widest > 0.1 * SAMPLE_BOUND, "widest step {widest}");
    }
}

/// Each contact's first instant and its two parties, as reported.
fn contacts(v: &[Violation]) -> Vec<(String, String)> {
    v.iter()
        .filter(|v| matches!(v.kind, ViolationKind::Time(TimeViolation::Contact { .. })))
        .map(|v| (format!("{:?}", v.location), v.to_string()))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// On random trajectories of `p1` swinging about near `p2` (each knot with a speed of
    /// its own, so that a stretch may speed up towards its end), the replay that skips
    /// ahead where its proofs allow reports every contact the replay of every step reports,
    /// at the same instant: a proof taken with the joints' fastest from its instant to its
    /// stretch's end holds to that end (a proof taken with the speeds near its instant
    /// only lets the replay skip past contacts: checked).
    #[test]
    fn skipping_reports_each_contact_at_the_instant_every_step_does(
        knots in prop::collection::vec(
            (0.1f64..0.6, prop::collection::vec(-0.4f64..1.8, 3), prop::collection::vec(-4.0f64..4.0, 3)),
            2..6,
        ),
        x2 in 1.45f64..1.9,
    ) {
        let w = world(&facing_at(x2));
        let points = through(&knots);
        let end = points.last().map_or(0.0, |p| p.t);
        let tl = Timeline {
            makespan: end,
            tracks: vec![Track { robot: P1, points }, track(P2, &[(0.0, 0.0), (end, 0.0)])],
            events: vec![],
            actions: vec![],
        };
        let (_, skipping) = replay(&w, &tl, &options(1e3, 1e5));
        let (_, every) = replay(&w, &tl, &ReplayOptions { every_step: true, ..options(1e3, 1e5) });
        prop_assert_eq!(contacts(&skipping), contacts(&every));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]

    /// One arm folding and unfolding among fixed boxes (a body's proofs against the scene
    /// take its reach from where it stands at each part of a stretch and at the stretch's
    /// end, with the drift of the joints between each axis and the body), and against
    /// itself (its first and last links fold onto each other): the replay that skips
    /// ahead reports every contact the replay of every step reports, at the same instant
    /// (with the drift left out it skips past some: checked).
    #[test]
    fn skipping_among_fixed_boxes_reports_each_contact_at_the_instant_every_step_does(
        knots in prop::collection::vec(
            (0.1f64..0.6, prop::collection::vec(-2.6f64..2.6, 3), prop::collection::vec(-4.0f64..4.0, 3)),
            2..6,
        ),
        boxes in prop::collection::vec((0.25f64..0.95, 0.5f64..5.78, 0.02f64..0.12), 1..4),
    ) {
        // Off the line the arm stands on at home (along x).
        let fixed = boxes
            .iter()
            .enumerate()
            .map(|(i, &(r, angle, size))| {
                cuboid(&format!("b{i}"), [size, size, 0.1], at(r * angle.cos(), r * angle.sin(), 0.0))
            })
            .collect();
        let scn = scenario(vec![robot("p1", planar3(), vec![0.0; 3], None)], vec![], fixed, vec![]);
        let w = world(&scn);
        let points = through(&knots);
        let end = points.last().map_or(0.0, |p| p.t);
        let tl = Timeline { makespan: end, tracks: vec![Track { robot: P1, points }], events: vec![], actions: vec![] };
        let (_, skipping) = replay(&w, &tl, &options(1e3, 1e5));
        let (_, every) = replay(&w, &tl, &ReplayOptions { every_step: true, ..options(1e3, 1e5) });
        prop_assert_eq!(contacts(&skipping), contacts(&every));
    }
}
