//! The reach that makes a grid sound: moving a pair's joints never changes its distance
//! by more than Σ ρ_i |δ_i|, and that bound is not vacuous; each body's reach from each
//! joint holds against forward kinematics; a box gap never overstates.

use parry3d_f64::math::{Pose as PPose, Rotation, Vector as PVec};
use parry3d_f64::shape::SharedShape;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{body_distance, bounding_sphere, pair_joints, Measure};
use crate::world::lower_bound::LOWER_BOUND_TOLERANCE;
use crate::world::proximity::shape_distance;
use crate::world::shapes::Obb;
use crate::world::test_arms::{example, shared_arms};
use crate::world::urdf::Motion;

#[test]
fn a_pairs_distance_moves_no_faster_than_its_reach_allows() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut grids, mut measured, mut three, mut tight) = (0, 0, 0, 0);
    let worlds = ["box_lid", "gripper"].map(|n| (n.to_string(), example(n)));
    for (name, w) in worlds.into_iter().chain(shared_arms()) {
        for m in &w.robots {
            for (&(a, b), g) in m.self_pairs.iter().zip(&m.self_grids) {
                let Some(g) = g else { continue };
                grids += 1;
                three += usize::from(g.reaches().len() == 3);
                let mut s = Measure::default();
                let mut tightest = 0.0f64;
                for _ in 0..2000 {
                    let q: Vec<f64> = m.chain.limits.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
                    let mut moved = q.clone();
                    let mut bound = 0.0;
                    for (i, reach) in g.reaches() {
                        let (lo, hi) = m.chain.limits[i];
                        moved[i] = (q[i] + rng.random_range(-0.3..0.3)).clamp(lo, hi);
                        bound += reach * (moved[i] - q[i]).abs();
                    }
                    s.q = q;
                    let d0 = body_distance(m, a, b, f64::INFINITY, &mut s).expect("convex shapes");
                    // A lower bound within GJK's dual bound's tolerance of the distance (two
                    // bodies of balls: their balls' least gap, exact, see `ball_pack`'s tests).
                    let balls = m.ball_packs[a].is_some() && m.ball_packs[b].is_some();
                    let exact = if balls {
                        d0
                    } else {
                        s.posed[0]
                            .iter()
                            .flat_map(|(i, pi, _, _)| s.posed[1].iter().map(move |(j, pj, _, _)| (*i, *pi, *j, *pj)))
                            .map(|(i, pi, j, pj)| {
                                let (si, sj) = (&*m.shapes[i].placed.shape.0, &*m.shapes[j].placed.shape.0);
                                shape_distance(&pi, si, &pj, sj).expect("convex")
                            })
                            .fold(f64::INFINITY, f64::min)
                    };
                    assert!(d0 <= exact + 1e-9 && d0 >= exact - LOWER_BOUND_TOLERANCE - 1e-9, "{d0} against {exact}");
                    measured += usize::from(exact > 0.0);
                    s.q = moved;
                    let d1 = body_distance(m, a, b, f64::INFINITY, &mut s).expect("convex shapes");
                    let change = (d1 - d0).abs();
                    // Each measure within the tolerance below the distance.
                    assert!(
                        change <= bound + LOWER_BOUND_TOLERANCE + 1e-7,
                        "{name} {}-{}: {change} > {bound}",
                        m.bodies[a].name,
                        m.bodies[b].name
                    );
                    if bound > 1e-3 {
                        tightest = tightest.max(change / bound);
                    }
                }
                // Not a bound so loose that any grid would be useless (a pair nearly
                // symmetric about its joints, the UR5's base and upper arm, changes little;
                // the Panda of spheres' first and third links, balls on the axes, not at all).
                assert!(
                    !(1e-9..=0.05).contains(&tightest),
                    "{name} {}-{}: at most {tightest} of the bound",
                    m.bodies[a].name,
                    m.bodies[b].name
                );
                tight += usize::from(tightest > 0.25);
            }
        }
    }
    assert!(grids >= 8 && measured > 1000, "only {grids} pairs have grids, {measured} measured apart");
    assert!(three >= 2, "only {three} grids span three joints");
    assert!(tight * 10 >= grids * 8, "only {tight} of {grids} grids' bounds are within 4 times a change");
}

#[test]
fn a_box_gap_never_overstates_the_distance() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let shapes = [SharedShape::cuboid(0.1, 0.02, 0.05), SharedShape::cylinder(0.08, 0.03), SharedShape::ball(0.04)];
    let mut apart = 0;
    for k in 0..20_000 {
        let (s1, s2) = (&shapes[k % 3], &shapes[(k / 3) % 3]);
        let mut pose = |spread: f64| {
            let axis = PVec::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
            let at = PVec::new(rng.random::<f64>(), rng.random::<f64>(), rng.random::<f64>()) * spread;
            PPose::from_parts(at, Rotation::from_scaled_axis(axis * 6.0))
        };
        let (p1, p2) = (pose(0.3), pose(0.3));
        let (o1, o2) = (Obb::of(&*s1.0), Obb::of(&*s2.0));
        let gap = o1.gap(&p1, &o2, &p2);
        let d = shape_distance(&p1, &*s1.0, &p2, &*s2.0).expect("convex");
        assert!(gap <= d + 1e-9, "gap {gap} > distance {d}");
        if gap > 0.5 * d && d > 0.01 {
            apart += 1;
        }
    }
    // Not vacuous: the gap is often a good part of the distance.
    assert!(apart > 2000, "{apart}");
}

/// The UR5's base against its upper arm turns on the shoulder's pan and lift. Turning the
/// pan swings the upper arm's far end half a metre from the axis, but the base, turned
/// back instead, stays within its own 9 cm radius (a box of half-diagonal under 14 cm
/// around its hull): the grid takes the nearer side's reach.
#[test]
fn a_grid_takes_the_nearer_sides_reach() {
    let Some((_, w)) = shared_arms().into_iter().find(|(n, _)| n == "ur5") else { return };
    let m = &w.robots[0];
    let body = |name: &str| m.bodies.iter().position(|b| b.name == name).expect("a body of the UR5");
    let (base, upper) = (body("base_link"), body("upper_arm_link"));
    let k = m.self_pairs.iter().position(|&p| p == (base, upper)).expect("a self-collision pair");
    let grid = m.self_grids[k].as_ref().expect("a grid");
    let pan = grid.reaches().into_iter().find(|(i, _)| *i == 0).expect("the pan joint").1;
    assert!(pan < 0.14, "the pan joint's reach is {pan} m");
}

/// Each side's reach from each joint of every self-collision pair, against forward
/// kinematics: at random configurations, no shape's bounding sphere of either body
/// reaches farther from the joint's axis than that body's reach says (the bound the grid
/// takes is the lesser of the two).
#[test]
fn each_sides_reach_holds_at_random_configurations() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut joints, mut nearer, mut tightest) = (0, 0, 0.0f64);
    let worlds = ["box_lid", "gripper"].map(|n| (n.to_string(), example(n)));
    for (name, w) in worlds.into_iter().chain(shared_arms()) {
        for m in &w.robots {
            let mut links = vec![nalgebra::Isometry3::identity(); m.chain.links.len()];
            for &(a, b) in &m.self_pairs {
                let Some(pair) = pair_joints(m, a, b) else { continue };
                for _ in 0..200 {
                    let q: Vec<f64> = m.chain.limits.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
                    m.chain.fk_into(&q, &mut links);
                    for j in &pair {
                        let Motion::Rotate(axis) = m.chain.links[j.link].motion else { panic!("a turning joint") };
                        let pose = links[j.link];
                        let (origin, axis) = (pose.translation.vector, pose.rotation * axis.into_inner());
                        let farthest = |body: usize| {
                            m.bodies[body]
                                .shapes
                                .clone()
                                .map(|si| {
                                    let (c, r) = bounding_sphere(&m.shapes[si].placed);
                                    let c = *m.shape_pose(si, crate::world::OPEN_POSTURE) * c;
                                    let c = links[m.bodies[body].link] * nalgebra::Point3::new(c.x, c.y, c.z);
                                    let v = c.coords - origin;
                                    (v - axis * axis.dot(&v)).norm() + r
                                })
                                .fold(0.0, f64::max)
                        };
                        let (own, theirs) = (farthest(j.body), farthest(j.other));
                        let what = format!("{name} {}-{} joint {}", m.bodies[a].name, m.bodies[b].name, j.index);
                        assert!(own <= j.own + 1e-9, "{what}: its own side {own} beyond {}", j.own);
                        assert!(theirs <= j.theirs + 1e-9, "{what}: the other side {theirs} beyond {}", j.theirs);
                        tightest = tightest.max(theirs / j.theirs);
                    }
                }
                joints += pair.len();
                nearer += pair.iter().filter(|j| j.theirs < j.own).count();
            }
        }
    }
    // The other side is the nearer for some joints, and its reach is not far above what
    // the configurations show.
    assert!(joints > 50 && nearer >= 10, "{nearer} of {joints} joints nearer on the other side");
    assert!(tightest > 0.9, "the other side reaches {tightest} of its bound at most");
}
