//! Labelled collision checks on hand-built scenes.

mod world_support;

use declutter::diag::FsLoader;
use declutter::resolve::{FixedId, HandId, ObjectId, RobotId};
use declutter::world::{build, Blocker, Check, CheckCtx, ObjectSet, World, WorldOptions, CONTACT_TOLERANCE};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use world_support::*;

const R0: RobotId = RobotId(0);

fn d(x: f64) -> f64 {
    x.to_radians()
}

fn set(ids: &[u32]) -> ObjectSet {
    ids.iter().map(|&i| ObjectId(i)).collect()
}

fn opts(samples: usize) -> WorldOptions {
    WorldOptions { self_collision_samples: samples, ..WorldOptions::default() }
}

fn make(scn: &declutter::resolve::Scenario, samples: usize) -> World {
    build(scn, &opts(samples), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"))
}

/// The planar arm lies along +x at q = 0: link boxes from x 0 to 0.9, |y|, |z| <= 0.02.
fn planar_scene(home: Vec<f64>) -> declutter::resolve::Scenario {
    let t = CONTACT_TOLERANCE;
    let fixed = vec![
        // A table whose top reaches 0.5 mm into the arm's underside: a touch, not a collision.
        cuboid("table", [2.0, 2.0, 0.1], at(0.0, 0.0, -0.02 - 0.05 + t / 2.0)),
        cuboid("wall", [0.1, 0.1, 0.1], at(-0.6, 0.07, 0.0)),
    ];
    let objects = vec![
        object(cuboid("a", [0.05, 0.05, 0.05], at(0.2, 0.0, 0.0)), vec![]),
        object(cuboid("b", [0.05, 0.05, 0.05], at(0.2, 0.3, 0.0)), vec![]),
        object(cuboid("c", [0.05, 0.05, 0.05], at(0.75, 0.0, 0.0)), vec![]),
        // Reaches 0.5 mm into link 2's side: within the tolerance.
        object(cuboid("d", [0.05, 0.05, 0.05], at(0.55, 0.02 + 0.025 - t / 2.0, 0.0)), vec![]),
        // Mid-way along a sweep to q1 = 90°.
        object(cuboid("e", [0.05, 0.05, 0.05], at(0.45, 0.45, 0.0)), vec![]),
    ];
    scenario(vec![robot("p", planar3(), home, None)], vec![], fixed, objects)
}

#[test]
fn touching_a_and_c_returns_exactly_a_and_c() {
    let w = make(&planar_scene(vec![d(90.0), 0.0, 0.0]), 0);
    assert_eq!(w.check(R0, &[0.0, 0.0, 0.0], &CheckCtx::new()), Check::Touches(set(&[0, 2])));
    // Removed objects are not there.
    assert_eq!(w.check(R0, &[0.0, 0.0, 0.0], &CheckCtx::with_absent(set(&[0]))), Check::Touches(set(&[2])));
    // Pointing up (+y) the arm touches nothing but the table, which it only grazes.
    assert_eq!(w.check(R0, &[d(90.0), 0.0, 0.0], &CheckCtx::new()), Check::free());
}

#[test]
fn hitting_a_fixed_body_is_blocked_naming_body_and_link() {
    let w = make(&planar_scene(vec![d(90.0), 0.0, 0.0]), 0);
    // Link 1 at 170° ends at (-0.394, 0.069); link 2 continues along -x at y 0.069 into the wall.
    let c = w.check(R0, &[d(170.0), d(10.0), 0.0], &CheckCtx::new());
    assert_eq!(c, Check::Blocked(Blocker::Fixed { body: FixedId(1), link: "link2".into() }));
}

#[test]
fn tx90_touching_the_table_is_blocked_naming_the_table() {
    let table = cuboid("table", [1.0, 1.0, 0.1], at(0.9, 0.0, 0.40));
    let scn = scenario(
        vec![robot("tx90", tx90(), vec![0.0; 6], Some(HandId(0)))],
        vec![hand("sah", sah(), 0.16)],
        vec![table],
        vec![],
    );
    let w = make(&scn, 500);
    assert_eq!(w.check(R0, &[0.0; 6], &CheckCtx::new()), Check::free());
    // Shoulder at 90°: the upper arm lies horizontally at z 0.478, into the table top at 0.45.
    let c = w.check(R0, &[0.0, d(90.0), 0.0, 0.0, 0.0, 0.0], &CheckCtx::new());
    assert_eq!(c, Check::Blocked(Blocker::Fixed { body: FixedId(0), link: "link_2".into() }));
    // The base stands on the floor, but links that never move are not checked against fixed bodies.
    let floor = cuboid("floor", [3.0, 3.0, 0.1], at(0.0, 0.0, -0.045));
    let scn = scenario(vec![robot("tx90", tx90(), vec![0.0; 6], None)], vec![], vec![floor], vec![]);
    let w = make(&scn, 0);
    assert_eq!(w.check(R0, &[0.0; 6], &CheckCtx::new()), Check::free());
}

#[test]
fn self_collision_is_detected_with_and_without_sampling() {
    for samples in [0, 2000] {
        let w = make(&planar_scene(vec![d(90.0), 0.0, 0.0]), samples);
        // Folded twice: link 3 crosses back over link 1.
        let c = w.check(R0, &[d(90.0), d(170.0), d(170.0)], &CheckCtx::new());
        assert_eq!(
            c,
            Check::Blocked(Blocker::SelfCollision { link_a: "link1".into(), link_b: "link3".into() }),
            "samples {samples}"
        );
        // Adjacent links overlapping at a joint never count.
        assert!(!w.check(R0, &[d(90.0), d(170.0), 0.0], &CheckCtx::new()).is_blocked());
    }
}

#[test]
fn allow_contact_overrides_self_collision() {
    let mut scn = planar_scene(vec![d(90.0), 0.0, 0.0]);
    scn.robots[0].allow_contact.push(declutter::resolve::LinkPair {
        a: "link3".into(),
        b: "link1".into(),
        span: sp(0, 1),
    });
    let w = make(&scn, 0);
    assert!(!w.check(R0, &[d(90.0), d(170.0), d(170.0)], &CheckCtx::new()).is_blocked());
}

#[test]
fn joint_limits_block() {
    let w = make(&planar_scene(vec![d(90.0), 0.0, 0.0]), 0);
    let c = w.check(R0, &[d(90.0), d(175.0), 0.0], &CheckCtx::new());
    assert_eq!(c, Check::Blocked(Blocker::JointLimit { joint: "joint2".into(), value: d(175.0) }));
}

fn held_scene() -> declutter::resolve::Scenario {
    let fixed = vec![cuboid("table", [0.1, 0.1, 0.1], at(0.0, 0.97, 0.0))];
    let objects = vec![
        object(cuboid("crate", [0.08, 0.08, 0.08], at(0.95, 0.0, 0.0)), vec![]),
        object(cuboid("box", [0.08, 0.08, 0.08], at(-0.95, 0.0, 0.0)), vec![]),
    ];
    scenario(vec![robot("p", planar3(), vec![0.0, d(90.0), 0.0], None)], vec![], fixed, objects)
}

#[test]
fn held_object_hitting_the_table_is_blocked() {
    let w = make(&held_scene(), 0);
    let held = w.held(R0, ObjectId(0), 0, &[0.0, 0.0, 0.0]);
    let p = held.pose_flange_object.translation.vector;
    assert!((p - Vector3::new(0.05, 0.0, 0.0)).norm() < 1e-12);
    let ctx = CheckCtx::with_held(ObjectSet::new(), held.clone());
    // Pointing at +y, the crate in the hand (y 0.91..0.99) goes into the table (y 0.92..1.02).
    let c = w.check(R0, &[d(90.0), 0.0, 0.0], &ctx);
    assert_eq!(c, Check::Blocked(Blocker::HeldFixed { object: ObjectId(0), body: FixedId(0) }));
    // The crate's old place does not count while it is carried; the arm at q = 0 holds it there.
    assert_eq!(w.check(R0, &[0.0, 0.0, 0.0], &ctx), Check::free());
    // Carried into another removable object: that object is touched.
    let q_back = [d(180.0 - 10.0), d(10.0), 0.0];
    let tip = w.fk_flange(R0, &q_back).translation.vector;
    let c = w.check(R0, &q_back, &ctx);
    assert_eq!(c, Check::Touches(set(&[1])), "tip at {tip:?}");
    // Folding the last link back over link 2 brings the crate onto the arm itself.
    let c = w.check(R0, &[0.0, 0.0, d(170.0)], &ctx);
    assert_eq!(c, Check::Blocked(Blocker::HeldSelf { object: ObjectId(0), link: "link2".into() }));
}

#[test]
fn segment_unions_labels_and_counts_checks() {
    let w = make(&planar_scene(vec![d(90.0), 0.0, 0.0]), 0);
    let ctx = CheckCtx::with_absent(set(&[0, 2]));
    let c = w.check_segment(R0, &[0.0, 0.0, 0.0], &[d(90.0), 0.0, 0.0], d(2.0), &ctx);
    // Sweeping q1 from 0 to 90°: d is grazed then crossed by link 2, b (0.2, 0.3) and e
    // (0.45, 0.45) lie on the swept quarter disc.
    assert_eq!(c, Check::Touches(set(&[1, 3, 4])));
    assert_eq!(ctx.checks.get(), 46);
    assert_eq!(w.check(R0, &[0.0, 0.0, 0.0], &ctx), Check::free());
    // A segment that ends in the wall stops there.
    let c = w.check_segment(R0, &[d(90.0), 0.0, 0.0], &[d(170.0), d(10.0), 0.0], d(2.0), &CheckCtx::new());
    assert!(matches!(c, Check::Blocked(Blocker::Fixed { body: FixedId(1), .. })), "{c:?}");
}

#[test]
fn other_robots_stand_at_home() {
    let a = robot("a", planar3(), vec![d(90.0), 0.0, 0.0], None);
    let mut b = robot("b", planar3(), vec![0.0, 0.0, 0.0], None);
    // Robot b's base at x 1.2, turned to point along -x: its links cover x 0.8..1.2,
    // 0.5..0.8 and 0.3..0.5, so robot a's link 1 (x 0..0.4) meets b's link 3.
    b.pose_world_base =
        Isometry3::from_parts(Translation3::new(1.2, 0.0, 0.0), UnitQuaternion::from_euler_angles(0.0, 0.0, d(180.0)));
    let w = make(&scenario(vec![a, b], vec![], vec![], vec![]), 0);
    let c = w.check(R0, &[0.0, 0.0, 0.0], &CheckCtx::new());
    assert_eq!(
        c,
        Check::Blocked(Blocker::Robot { other: RobotId(1), link: "link1".into(), other_link: "link3".into() })
    );
}

#[test]
fn world_is_send_and_sync() {
    fn is<T: Send + Sync>() {}
    is::<World>();
}

#[test]
fn tolerance_boundary_is_the_same_for_boxes_and_cylinders() {
    let t = CONTACT_TOLERANCE;
    // Link 1 (box, |y| <= 0.02) along +x; objects beside it reaching into it by 0.5 t or 1.5 t.
    let objects = vec![
        object(cuboid("box_shallow", [0.05, 0.05, 0.05], at(0.1, 0.02 + 0.025 - 0.5 * t, 0.0)), vec![]),
        object(cuboid("box_deep", [0.05, 0.05, 0.05], at(0.3, -0.02 - 0.025 + 1.5 * t, 0.0)), vec![]),
        object(
            body(
                "can_shallow",
                declutter::resolve::Shape::Cylinder { radius: 0.03, length: 0.1 },
                at(0.5, 0.05 - 0.5 * t, 0.0),
            ),
            vec![],
        ),
        object(
            body(
                "can_deep",
                declutter::resolve::Shape::Cylinder { radius: 0.03, length: 0.1 },
                at(0.6, -0.05 + 1.5 * t, 0.0),
            ),
            vec![],
        ),
    ];
    let scn = scenario(vec![robot("p", planar3(), vec![0.0, 0.0, 0.0], None)], vec![], vec![], objects);
    let w = make(&scn, 0);
    assert_eq!(w.check(R0, &[0.0, 0.0, 0.0], &CheckCtx::new()), Check::Touches(set(&[1, 3])));
}

/// Three links turning about the same z axis; links 1 and 3 are boxes around the axis,
/// so they overlap at every configuration though they are not adjacent.
const ALWAYS: &str = r#"<robot name="stack">
<link name="base"/>
<link name="l1"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
<link name="l2"/>
<link name="l3"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><axis xyz="0 0 1"/></joint>
<joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>"#;

#[test]
fn pairs_always_in_collision_are_found_by_sampling() {
    let loader = declutter::diag::MemLoader::new().with("/m/stack.urdf", ALWAYS);
    let scn = scenario(vec![robot("s", "/m/stack.urdf", vec![0.0; 3], None)], vec![], vec![], vec![]);
    // Without sampling, l1 and l3 collide at home: an error.
    let errs = build(&scn, &opts(0), &loader).expect_err("home collides");
    assert!(errs[0].to_string().contains("`l1` and `l3` collide"), "{}", errs[0]);
    // Sampling finds them in collision everywhere and stops checking the pair.
    let w = build(&scn, &opts(200), &loader).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(w.limits(R0)[1], (-std::f64::consts::TAU, std::f64::consts::TAU), "continuous joint");
    assert_eq!(w.check(R0, &[1.0, 2.0, -1.0], &CheckCtx::new()), Check::free());
}

/// The planar arm, and (when `post`) a post of 4 mm radius at 5°, 0.85 m out.
fn arm_beside_a_post(post: bool) -> World {
    let a = 5f64.to_radians();
    let post = post.then(|| {
        body("post", declutter::resolve::Shape::Sphere { radius: 0.004 }, at(0.85 * a.cos(), 0.85 * a.sin(), 0.0))
    });
    make(&scenario(vec![robot("arm", planar3(), vec![0.0; 3], None)], vec![], post.into_iter().collect(), vec![]), 0)
}

#[test]
fn a_thin_post_between_planner_steps_is_caught_by_the_certifying_check() {
    // The straight arm (x from 0 to 0.9) turns 20° about the base in steps of 10°: the
    // planner's check looks at 0°, 10° and 20°. A post of 4 mm radius stands at 5°, 0.85 m
    // out: 0.85·sin 5° = 74 mm from the arm's axis at 0° and at 10°, 50 mm clear of the
    // 20 mm half-width. Only the certifying check, at a quarter step, sees it.
    let w = arm_beside_a_post(true);
    let (from, to, step) = ([0.0, 0.0, 0.0], [d(20.0), 0.0, 0.0], d(10.0));
    let ctx = CheckCtx::new();
    assert_eq!(w.check_segment(R0, &from, &to, step, &ctx), Check::Touches(ObjectSet::new()));
    assert_eq!(ctx.checks.get(), 3, "0°, 10° and 20°");
    let ctx = CheckCtx::new();
    let c = w.check_motion(R0, &from, &to, step, &ctx);
    assert!(matches!(&c, Check::Blocked(Blocker::Fixed { body: FixedId(0), .. })), "{c:?}");
    // Blocked at 5°, the third sample of 0°, 2.5°, 5°, … (it stops at the first block).
    assert_eq!(ctx.checks.get(), 3);
}

#[test]
fn the_rest_of_a_certifying_check_skips_the_coarse_samples_and_finds_the_post() {
    // As above: the coarse check takes 0°, 10° and 20°; the rest takes the six quarter
    // steps between them, the midpoints (5°, 15°) first, and stops at the post at 5°.
    let w = arm_beside_a_post(true);
    let (from, to, step) = ([0.0, 0.0, 0.0], [d(20.0), 0.0, 0.0], d(10.0));
    let ctx = CheckCtx::new();
    let c = w.check_motion_rest(R0, &from, &to, step, &ctx);
    assert!(matches!(&c, Check::Blocked(Blocker::Fixed { body: FixedId(0), .. })), "{c:?}");
    assert_eq!(ctx.checks.get(), 1, "5° first");
    // Without the post: every one of the six, none of the coarse three.
    let w = arm_beside_a_post(false);
    let ctx = CheckCtx::new();
    assert_eq!(w.check_motion_rest(R0, &from, &to, step, &ctx), Check::free());
    assert_eq!(ctx.checks.get(), 6);
}

mod rest_of_certifying_check {
    use super::*;
    use proptest::prelude::*;

    fn world() -> &'static World {
        static W: std::sync::OnceLock<World> = std::sync::OnceLock::new();
        W.get_or_init(|| make(&planar_scene(vec![d(90.0), 0.0, 0.0]), 0))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// Coarse check and rest together answer as the certifying check: the same labels,
        /// blocked alike, and the two take the certifying check's samples between them
        /// exactly once each (when nothing blocks).
        #[test]
        fn coarse_and_rest_are_the_certifying_check(
            a in proptest::array::uniform3(-3.0f64..3.0),
            b in proptest::array::uniform3(-3.0f64..3.0),
            step in 0.02f64..0.6,
            absent in 0u32..8,
        ) {
            let w = world();
            let ctx = || CheckCtx::with_absent((0..5).filter(|o| absent & (1 << o) != 0).map(ObjectId).collect());
            let (c1, c2, c3) = (ctx(), ctx(), ctx());
            let whole = w.check_motion(R0, &a, &b, step, &c1);
            let coarse = w.check_segment(R0, &a, &b, step, &c2);
            let joined = match coarse {
                Check::Touches(l) => match w.check_motion_rest(R0, &a, &b, step, &c3) {
                    Check::Touches(r) => Check::Touches(l.union(&r)),
                    blocked => blocked,
                },
                blocked => blocked,
            };
            prop_assert_eq!(whole.is_blocked(), joined.is_blocked());
            if let (Check::Touches(x), Check::Touches(y)) = (&whole, &joined) {
                prop_assert_eq!(x, y);
                prop_assert_eq!(c1.checks.get(), c2.checks.get() + c3.checks.get());
            }
        }

        /// From a configuration that touches nothing, a segment checked without its first
        /// sample answers as the whole coarse check (labels, block), one check fewer; and
        /// without both ends, where the far end is not blocked, its label joined with the
        /// far end's answers so too, two checks fewer.
        #[test]
        fn leaving_a_clear_configuration_skips_it_alone(
            a in proptest::array::uniform3(-3.0f64..3.0),
            b in proptest::array::uniform3(-3.0f64..3.0),
            step in 0.02f64..0.6,
        ) {
            let w = world();
            let ctx = CheckCtx::new();
            prop_assume!(w.check(R0, &a, &ctx) == Check::free());
            let (whole, leaving) = (CheckCtx::new(), CheckCtx::new());
            let c1 = w.check_segment(R0, &a, &b, step, &whole);
            let c2 = w.check_segment_known(R0, (&a, &b), step, (true, false), &leaving);
            prop_assert_eq!(c1.is_blocked(), c2.is_blocked());
            if let (Check::Touches(x), Check::Touches(y)) = (&c1, &c2) {
                prop_assert_eq!(x, y);
                prop_assert_eq!(whole.checks.get(), leaving.checks.get() + 1);
            }
            if let Check::Touches(lb) = w.check(R0, &b, &ctx) {
                let inside = CheckCtx::new();
                let c3 = w.check_segment_known(R0, (&a, &b), step, (true, true), &inside);
                prop_assert_eq!(c1.is_blocked(), c3.is_blocked());
                if let (Check::Touches(x), Check::Touches(y)) = (&c1, &c3) {
                    prop_assert_eq!(x, &y.union(&lb));
                    prop_assert_eq!(whole.checks.get(), inside.checks.get() + 2);
                }
            }
        }
    }
}
