//! How far apart two robots are, each with what it carries: the geometric fact the
//! timing stage needs to run robots at the same time.
//!
//! The planner checks each robot with the others parked at `home`; two robots moving at
//! once are only ever compared here (and, independently, by the verifier's replay).

use std::cell::RefCell;

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose as PPose;
use parry3d_f64::query;
use parry3d_f64::shape::Shape;

use super::lower_bound::{distance_at_least_below, GjkStart, LOWER_BOUND_TOLERANCE};
use super::shapes::Obb;
use super::{Held, HeldPart, PosedShape, World};
use crate::resolve::RobotId;

/// One robot at one instant: its configuration and what it holds.
#[derive(Clone, Copy, Debug)]
pub struct RobotAt<'a> {
    pub robot: RobotId,
    pub q: &'a [f64],
    pub held: Option<&'a Held>,
}

/// Reused buffers of [`World::robots_apart`]: each robot's shapes and carried parts,
/// posed, and the pairs whose boxes are near.
#[derive(Default)]
struct Apart {
    posed: [Vec<PosedShape>; 2],
    held: [Vec<HeldPart>; 2],
    near: Vec<(f64, usize, usize)>,
    /// Per shape of the first robot, its gap to the box around the second's, and its index.
    rows: Vec<(f64, usize)>,
    /// Per shape of the second robot, its gap to the box around the first's.
    cols: Vec<f64>,
}

thread_local! {
    static APART: RefCell<Apart> = RefCell::new(Apart::default());
}

/// Gap between two boxes (0 when they overlap): never more than the distance between
/// anything inside them.
pub fn aabb_gap(a: &Aabb, b: &Aabb) -> f64 {
    let d = (a.mins - b.maxs).max(b.mins - a.maxs).max(parry3d_f64::math::Vector::ZERO);
    d.length()
}

/// A lower bound on the distance between two placed shapes: the gap between their own
/// boxes (each shape's local box, turned with it) along the boxes' six face normals, at
/// least 0. Tighter than [`aabb_gap`] for turned shapes (a forearm at 45° fills a world
/// box twice its size), at the cost of a few dozen products.
pub fn turned_boxes_gap(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> f64 {
    let own = |s: &dyn Shape| Obb::of_aabb(&s.compute_local_aabb());
    own(s1).gap(p1, &own(s2), p2).max(0.0)
}

/// The distance between two placed shapes (0 when they touch), `None` when parry3d
/// cannot measure the pair. Balls against balls and boxes in closed form (a spherized
/// robot is all balls, and GJK on them was most of its replay); other convex shapes are
/// measured by GJK on their support maps:
/// parry3d's own cuboid–cuboid distance takes its closest points from the best separating
/// axis and can overstate the distance by centimetres (a test below shows 7 mm), which a
/// safety check must never do.
pub fn shape_distance(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> Option<f64> {
    match (s1.as_ball(), s2.as_ball()) {
        (Some(a), Some(b)) => return Some(((p2.translation - p1.translation).length() - a.radius - b.radius).max(0.0)),
        (Some(a), None) => {
            if let Some(c) = s2.as_cuboid() {
                return Some(ball_box_distance(p1.translation, a.radius, p2, c.half_extents));
            }
        }
        (None, Some(b)) => {
            if let Some(c) = s1.as_cuboid() {
                return Some(ball_box_distance(p2.translation, b.radius, p1, c.half_extents));
            }
        }
        (None, None) => {}
    }
    if let (Some(a), Some(b)) = (s1.as_support_map(), s2.as_support_map()) {
        return Some(query::details::distance_support_map_support_map(&p1.inv_mul(p2), a, b));
    }
    query::distance(p1, s1, p2, s2).ok().map(|d| d.distance)
}

/// Whether [`shape_distance`] measures the pair in closed form (balls against balls and
/// boxes), not by GJK.
pub fn in_closed_form(s1: &dyn Shape, s2: &dyn Shape) -> bool {
    match (s1.as_ball(), s2.as_ball()) {
        (Some(_), Some(_)) => true,
        (Some(_), None) => s2.as_cuboid().is_some(),
        (None, Some(_)) => s1.as_cuboid().is_some(),
        (None, None) => false,
    }
}

/// The distance from a ball (centre, radius) to a box (pose, half extents), 0 when they
/// touch: the centre's distance to the box, in the box's frame, less the radius.
#[inline]
fn ball_box_distance(
    centre: parry3d_f64::math::Vector,
    radius: f64,
    pose: &PPose,
    half: parry3d_f64::math::Vector,
) -> f64 {
    let local = pose.inverse_transform_point(centre);
    let outside = (local.abs() - half).max(parry3d_f64::math::Vector::ZERO).length();
    (outside - radius).max(0.0)
}

impl World {
    /// A lower bound on the distance between two robots and what they carry: within
    /// [`LOWER_BOUND_TOLERANCE`] below the shapes' own distance where two shapes' boxes
    /// are nearer than `near` (GJK's dual bound: the timing stage wants a bound from
    /// below, not parry's distance to its last digits, which cost a third of a 200-can
    /// table's compile), the boxes' gap elsewhere, and 0 when they touch. A pair of
    /// shapes parry3d cannot measure counts by its boxes' gap, which still bounds the
    /// distance from below.
    pub fn robots_apart(&self, a: RobotAt, b: RobotAt, near: f64) -> f64 {
        APART.with(|cell| {
            let mut s = cell.borrow_mut();
            let Apart { posed, held, near: pairs, rows, cols } = &mut *s;
            self.pose_both([a, b], posed, held);
            let shapes = |k: usize| shapes_of(&posed[k], &held[k]);
            // The answer is the least over all pairs of shapes of the pair's value: its
            // boxes' gap when that is at least `near`, else its distance (never below
            // the gap). So a pair whose gap is no less than the best value so far cannot
            // change the answer, and is skipped: whole rows at once where the shape's gap
            // to the box around all of the other robot's shapes (never more than its gap
            // to any one of them) already is, nearest rows first; then the near pairs are
            // measured in order of gap, stopping at the first gap no less than the best.
            // The least value is the same as over every pair, with a fraction of the work
            // (two arms with hands have hundreds of pairs).
            let union = |k: usize| shapes(k).map(|(_, _, b)| *b).reduce(|u, b| u.merged(&b));
            let (Some(ua), Some(ub)) = (union(0), union(1)) else { return f64::INFINITY };
            rows.clear();
            rows.extend(shapes(0).enumerate().map(|(i, (_, _, boxa))| (aabb_gap(boxa, &ub), i)));
            rows.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
            cols.clear();
            cols.extend(shapes(1).map(|(_, _, boxb)| aabb_gap(&ua, boxb)));
            let mut best = f64::INFINITY;
            pairs.clear();
            for &(row, i) in rows.iter() {
                if row >= best {
                    break;
                }
                let Some((_, _, boxa)) = shapes(0).nth(i) else { continue };
                for (j, (_, _, boxb)) in shapes(1).enumerate() {
                    if cols[j] >= best {
                        continue;
                    }
                    let gap = aabb_gap(boxa, boxb);
                    if gap >= best {
                        continue;
                    }
                    if gap >= near {
                        best = gap;
                    } else {
                        pairs.push((gap, i, j));
                    }
                }
            }
            pairs.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
            for &(gap, i, j) in pairs.iter() {
                if gap >= best {
                    break;
                }
                let nth = |k: usize, n: usize| match posed[k].get(n) {
                    Some(s) => (&*s.shape.0, &s.pose),
                    None => {
                        let p = &held[k][n - posed[k].len()];
                        (&*p.shape.0, &p.pose)
                    }
                };
                let ((sa, posea), (sb, poseb)) = (nth(0, i), nth(1, j));
                // GJK's bound from below, stopped once it cannot lower the best (see
                // `distance_at_least_below`), after the turned boxes' gap, which often
                // proves that already; balls and boxes in closed form.
                if !in_closed_form(sa, sb) && turned_boxes_gap(posea, sa, poseb, sb) >= best {
                    continue;
                }
                let bound = distance_at_least_below(
                    posea,
                    sa,
                    poseb,
                    sb,
                    (LOWER_BOUND_TOLERANCE, best),
                    &mut GjkStart::default(),
                );
                let d = bound.map_or(gap, |d| d.max(gap));
                best = best.min(d);
                if best <= 0.0 {
                    return 0.0;
                }
            }
            best
        })
    }

    /// Whether two robots (with what they carry) surely come nearer than `gap`: two of
    /// their shapes are, by the distance [`shape_distance`] gives, which is never less than
    /// the shapes' own (GJK closes in from above; balls in closed form). `false` proves
    /// nothing. A quick proof that two robots conflict, where [`World::robots_apart`]
    /// gives a bound from below.
    pub fn robots_within(&self, a: RobotAt, b: RobotAt, gap: f64) -> bool {
        APART.with(|cell| {
            let mut s = cell.borrow_mut();
            let Apart { posed, held, .. } = &mut *s;
            self.pose_both([a, b], posed, held);
            for (sa, pa, ba) in shapes_of(&posed[0], &held[0]) {
                for (sb, pb, bb) in shapes_of(&posed[1], &held[1]) {
                    if aabb_gap(ba, bb) < gap && shape_distance(pa, sa, pb, sb).is_some_and(|d| d < gap) {
                        return true;
                    }
                }
            }
            false
        })
    }

    /// Both robots' shapes and what each carries posed into `posed` and `held`.
    fn pose_both(&self, robots: [RobotAt; 2], posed: &mut [Vec<PosedShape>; 2], held: &mut [Vec<HeldPart>; 2]) {
        for (k, at) in robots.into_iter().enumerate() {
            let flange = self.pose_shapes(at.robot, at.q, at.held, &mut posed[k]);
            match at.held {
                Some(h) => self.pose_held_into(h, &flange, &mut held[k]),
                None => held[k].clear(),
            }
        }
    }
}

/// One robot's posed shapes and carried parts: shape, pose and box of each.
fn shapes_of<'a>(
    posed: &'a [PosedShape],
    held: &'a [HeldPart],
) -> impl Iterator<Item = (&'a dyn Shape, &'a PPose, &'a Aabb)> + Clone {
    let robot = posed.iter().map(|s| (&*s.shape.0, &s.pose, &s.aabb));
    robot.chain(held.iter().map(|p| (&*p.shape.0, &p.pose, &p.aabb)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::math::Vector;
    use parry3d_f64::shape::Cuboid;
    use parry3d_f64::shape::SharedShape;
    use proptest::prelude::*;

    /// GJK's distance on the support maps, what `shape_distance` measured balls with before.
    fn by_gjk(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> f64 {
        let (a, b) = (s1.as_support_map().expect("convex"), s2.as_support_map().expect("convex"));
        query::details::distance_support_map_support_map(&p1.inv_mul(p2), a, b)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Balls against balls and boxes, either way round: the closed form is GJK's
        /// distance to GJK's own accuracy (tens of micrometres), and never more.
        #[test]
        fn balls_are_measured_as_gjk_measures_them(
            r in 0.005f64..0.3,
            other in 0.005f64..0.3,
            half in (0.01f64..0.5, 0.01f64..0.5, 0.01f64..0.5),
            t in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            axis in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            angle in -3.2f64..3.2,
        ) {
            let axis = Vector::new(axis.0, axis.1, axis.2);
            prop_assume!(axis.length() > 1e-3);
            let rot = parry3d_f64::math::Rotation::from_axis_angle(axis.normalize(), angle);
            let ball = parry3d_f64::shape::Ball::new(r);
            let (bx, sphere) = (Cuboid::new(Vector::new(half.0, half.1, half.2)), parry3d_f64::shape::Ball::new(other));
            let p1 = PPose::from_parts(Vector::new(t.0, t.1, t.2), rot);
            let p2 = PPose::from_parts(Vector::new(0.1, -0.2, 0.3), rot.inverse());
            for (d, gjk) in [
                (shape_distance(&p1, &ball, &p2, &bx), by_gjk(&p1, &ball, &p2, &bx)),
                (shape_distance(&p2, &bx, &p1, &ball), by_gjk(&p2, &bx, &p1, &ball)),
                (shape_distance(&p1, &ball, &p2, &sphere), by_gjk(&p1, &ball, &p2, &sphere)),
            ] {
                // GJK closes in on the distance from above (its simplex's nearest point is
                // in the shapes' difference) and stops short of it: by up to 15 µm in 200 000
                // seeded placements of these sizes (0.3 % of the distance).
                let d = d.expect("measured");
                prop_assert!(d >= 0.0);
                prop_assert!(d <= gjk + 1e-12 && gjk - d <= 5e-5, "closed form {} against GJK {}", d, gjk);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// The turned boxes' gap is a lower bound: never more than GJK's distance (itself
        /// at or above the distance) for boxes, cylinders and hulls in any placement.
        #[test]
        fn turned_boxes_gap_never_exceeds_the_distance(
            half in (0.01f64..0.4, 0.01f64..0.4, 0.01f64..0.4),
            radius in 0.01f64..0.3,
            t in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            axes in ((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)),
            angles in (-3.2f64..3.2, -3.2f64..3.2),
            seed in 0u64..1_000_000,
        ) {
            let turn = |a: (f64, f64, f64), angle: f64| {
                let a = Vector::new(a.0, a.1, a.2);
                parry3d_f64::math::Rotation::from_axis_angle(if a.length() > 1e-3 { a.normalize() } else { Vector::X }, angle)
            };
            let p1 = PPose::from_parts(Vector::new(t.0, t.1, t.2), turn(axes.0, angles.0));
            let p2 = PPose::from_parts(Vector::new(0.1, -0.2, 0.05), turn(axes.1, angles.1));
            let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed);
            let cloud: Vec<Vector> = (0..20)
                .map(|_| Vector::new(rand::RngExt::random(&mut rng), rand::RngExt::random(&mut rng), rand::RngExt::random(&mut rng)) * 0.3)
                .collect();
            let hull = SharedShape::convex_hull(&cloud).expect("a hull");
            let bx = Cuboid::new(Vector::new(half.0, half.1, half.2));
            let cylinder = parry3d_f64::shape::Cylinder::new(half.2, radius);
            let shapes: [&dyn Shape; 3] = [&bx, &cylinder, &*hull.0];
            for a in shapes {
                for b in shapes {
                    let (lb, gjk) = (turned_boxes_gap(&p1, a, &p2, b), by_gjk(&p1, a, &p2, b));
                    prop_assert!(lb >= 0.0 && lb <= gjk + 1e-12, "gap {} over GJK {}", lb, gjk);
                }
            }
        }
    }

    /// Not vacuous: over seeded placements of a turned box and a turned cylinder, the
    /// turned boxes' gap is within a fifth of the distance for most apart pairs, the
    /// world boxes' gap for fewer.
    #[test]
    fn turned_boxes_gap_is_mostly_near_the_distance() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut v =
            |s: f64| Vector::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5) * s;
        let (mut apart, mut turned_near, mut world_near) = (0, 0, 0);
        for _ in 0..2000 {
            let bx = Cuboid::new(v(0.6).abs() + Vector::splat(0.01));
            let cylinder = parry3d_f64::shape::Cylinder::new(0.3, 0.05);
            let p1 = PPose::from_parts(v(2.0), parry3d_f64::math::Rotation::from_scaled_axis(v(6.0)));
            let p2 = PPose::from_parts(v(2.0), parry3d_f64::math::Rotation::from_scaled_axis(v(6.0)));
            let gjk = by_gjk(&p1, &bx, &p2, &cylinder);
            if gjk > 0.01 {
                apart += 1;
                turned_near += usize::from(turned_boxes_gap(&p1, &bx, &p2, &cylinder) > 0.8 * gjk);
                world_near += usize::from(aabb_gap(&bx.compute_aabb(&p1), &cylinder.compute_aabb(&p2)) > 0.8 * gjk);
            }
        }
        // Seed 3: 1 957 apart, the turned boxes within a fifth for 1 556, the world's for 1 095.
        assert!(
            apart > 1000 && 10 * turned_near >= 7 * apart && 10 * world_near <= 6 * apart,
            "{apart} apart: {turned_near} turned, {world_near} world boxes within a fifth"
        );
    }

    #[test]
    fn closed_forms_are_balls_against_balls_and_boxes() {
        let (ball, bx) = (parry3d_f64::shape::Ball::new(0.1), Cuboid::new(Vector::splat(0.1)));
        let cylinder = parry3d_f64::shape::Cylinder::new(0.1, 0.1);
        assert!(in_closed_form(&ball, &ball) && in_closed_form(&ball, &bx) && in_closed_form(&bx, &ball));
        assert!(!in_closed_form(&ball, &cylinder) && !in_closed_form(&bx, &bx) && !in_closed_form(&cylinder, &ball));
    }

    #[test]
    fn turned_boxes_gap_by_hand() {
        let unit = Cuboid::new(Vector::splat(0.5));
        let at = |x: f64, y: f64, z: f64| PPose::from_translation(Vector::new(x, y, z));
        // Face to face, 1 m apart.
        assert_eq!(turned_boxes_gap(&PPose::IDENTITY, &unit, &at(2.0, 0.0, 0.0), &unit), 1.0);
        // Corner to corner, (1, 1, 1) apart: the face normals see 1 of the 1.732.
        assert_eq!(turned_boxes_gap(&PPose::IDENTITY, &unit, &at(2.0, 2.0, 2.0), &unit), 1.0);
        // One turned 45° about z, 2 m off along x: it reaches 0.7071 towards the other.
        let turned = PPose::from_parts(
            Vector::new(2.0, 0.0, 0.0),
            parry3d_f64::math::Rotation::from_rotation_z(std::f64::consts::FRAC_PI_4),
        );
        let d = turned_boxes_gap(&PPose::IDENTITY, &unit, &turned, &unit);
        assert!((d - (1.5 - 0.5f64.sqrt())).abs() < 1e-12, "{d}");
        // Overlapping: 0. A box off its own centre (a cylinder's box is its own; a hull's
        // is its points'): a hull of one corner cube at (1..2)³ is 1 from the unit box.
        assert_eq!(turned_boxes_gap(&PPose::IDENTITY, &unit, &at(0.5, 0.0, 0.0), &unit), 0.0);
        let cube: Vec<Vector> =
            (0..8).map(|k| Vector::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64)).collect();
        let hull = SharedShape::convex_hull(&cube).expect("a cube");
        let d = turned_boxes_gap(&at(1.5, 0.0, -0.5), &*hull.0, &PPose::IDENTITY, &unit);
        assert!((d - 1.0).abs() < 1e-12, "{d}");
    }

    #[test]
    fn balls_measured_by_hand() {
        let at = |x: f64, y: f64, z: f64| PPose::from_translation(Vector::new(x, y, z));
        let ball = parry3d_f64::shape::Ball::new(0.1);
        let unit = Cuboid::new(Vector::splat(0.5));
        // Centre 1 m from a face: 0.5 to the face, less the radius.
        let d = shape_distance(&at(1.0, 0.0, 0.0), &ball, &PPose::IDENTITY, &unit).expect("measured");
        assert!((d - 0.4).abs() < 1e-15, "{d}");
        // Off a corner: (0.5, 0.5, 0.5) away, less the radius.
        let d = shape_distance(&PPose::IDENTITY, &unit, &at(1.0, 1.0, 1.0), &ball).expect("measured");
        assert!((d - (0.75f64.sqrt() - 0.1)).abs() < 1e-15, "{d}");
        // Inside, touching, or turned 45 degrees about z with the centre 0.8 m along x:
        // the box reaches 0.7071 that way, its edge 0.0929 from the centre less 0.1: 0.
        assert_eq!(shape_distance(&at(0.2, 0.0, 0.0), &ball, &PPose::IDENTITY, &unit), Some(0.0));
        let turned =
            PPose::from_parts(Vector::ZERO, parry3d_f64::math::Rotation::from_rotation_z(std::f64::consts::FRAC_PI_4));
        assert_eq!(shape_distance(&at(0.8, 0.0, 0.0), &ball, &turned, &unit), Some(0.0));
        let d = shape_distance(&at(0.9, 0.0, 0.0), &ball, &turned, &unit).expect("measured");
        assert!((d - (0.9 - 0.5f64.sqrt() - 0.1)).abs() < 1e-12, "{d}");
        // Two balls 1 m apart.
        let d = shape_distance(&at(0.0, 1.0, 0.0), &ball, &PPose::IDENTITY, &parry3d_f64::shape::Ball::new(0.2));
        assert!((d.expect("measured") - 0.7).abs() < 1e-15);
    }

    /// Every pair of shapes, in order, measured by parry's distance where its boxes are
    /// nearer than `near`: what `robots_apart` was before it pruned pairs and took GJK's
    /// bound from below, to the bit.
    fn every_pair(w: &World, a: RobotAt, b: RobotAt, near: f64) -> f64 {
        let posed = |at: RobotAt| {
            let mut robot = Vec::new();
            let flange = w.pose_shapes(at.robot, at.q, at.held, &mut robot);
            let mut all: Vec<(SharedShape, PPose, Aabb)> =
                robot.into_iter().map(|s| (s.shape, s.pose, s.aabb)).collect();
            if let Some(h) = at.held {
                all.extend(w.pose_held(h, &flange).into_iter().map(|p| (p.shape, p.pose, p.aabb)));
            }
            all
        };
        let (pa, pb) = (posed(a), posed(b));
        let mut best = f64::INFINITY;
        for (sa, posea, boxa) in &pa {
            for (sb, poseb, boxb) in &pb {
                let gap = aabb_gap(boxa, boxb);
                if gap >= best {
                    continue;
                }
                let d = if gap >= near {
                    gap
                } else {
                    shape_distance(posea, &*sa.0, poseb, &*sb.0).map_or(gap, |d| d.max(gap))
                };
                best = best.min(d);
                if best <= 0.0 {
                    return 0.0;
                }
            }
        }
        best
    }

    #[test]
    fn robots_apart_is_within_the_tolerance_below_the_least_over_every_pair_and_robots_within_below_a_gap() {
        use crate::resolve::{ObjectId, RobotId};
        use rand::{RngExt, SeedableRng};
        // Two arms with hands over a crate, each sometimes carrying a lid.
        let w = crate::world::test_arms::example("split_lid");
        let (r0, r1) = (RobotId(0), RobotId(1));
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(13);
        let mut draw = |r: RobotId| -> Vec<f64> {
            // Near home half the time, so that the arms come close without always touching.
            let home = w.home(r).to_vec();
            let spread = if rng.random::<bool>() { 0.3 } else { 1.0 };
            w.limits(r)
                .iter()
                .zip(&home)
                .map(|((lo, hi), h)| h + spread * (lo + rng.random::<f64>() * (hi - lo) - h))
                .collect()
        };
        let lid = |r: RobotId, q: &[f64], o: u32| w.held(r, ObjectId(o), 0, q);
        let (mut touching, mut measured, mut surely) = (0, 0, 0);
        for i in 0..400 {
            let (q0, q1) = (draw(r0), draw(r1));
            let h0 = (i % 3 == 1).then(|| lid(r0, &q0, 1));
            let h1 = (i % 4 == 2).then(|| lid(r1, &q1, 2));
            let a = RobotAt { robot: r0, q: &q0, held: h0.as_ref() };
            let b = RobotAt { robot: r1, q: &q1, held: h1.as_ref() };
            // `robots_within` is "every pair's least distance is below the gap" where
            // boxes nearer than the gap are measured, and the bound from below is below it.
            for gap in [0.005, 0.02, 0.1] {
                let within = w.robots_within(a, b, gap);
                assert_eq!(within, every_pair(&w, a, b, gap) < gap, "draw {i}, gap {gap}");
                assert!(!within || w.robots_apart(a, b, 0.1) < gap, "draw {i}, gap {gap}");
                surely += usize::from(within && gap == 0.005);
            }
            for near in [0.1, 0.02, 1.0] {
                let (fast, slow) = (w.robots_apart(a, b, near), every_pair(&w, a, b, near));
                // parry's distance is from above (to a relative 5e-8, but for rounding),
                // the bound from below.
                let within = fast <= slow + 1e-12 && fast >= slow - LOWER_BOUND_TOLERANCE - 1e-7 * slow;
                assert!(within && (slow > 0.0 || fast == 0.0), "draw {i}, near {near}: {fast} against {slow}");
                touching += usize::from(slow == 0.0);
                measured += usize::from(slow > 0.0 && slow < near);
            }
        }
        // Not vacuous: some draws touch, some are measured by distance, the rest by gap;
        // some are surely within 5 mm.
        assert!(
            touching > 10 && measured > 10 && surely > 10,
            "{touching} touching, {measured} measured, {surely} within"
        );
    }

    #[test]
    fn the_gap_of_boxes_is_the_distance_between_their_nearest_corners() {
        // Boxes [0,1]³ and [2,3]×[3,4]×[0,1]: gaps 1 and 2 on x and y, none on z: √5.
        let a = Aabb::new(Vector::new(0.0, 0.0, 0.0), Vector::new(1.0, 1.0, 1.0));
        let b = Aabb::new(Vector::new(2.0, 3.0, 0.0), Vector::new(3.0, 4.0, 1.0));
        assert!((aabb_gap(&a, &b) - 5f64.sqrt()).abs() < 1e-12);
        assert_eq!(aabb_gap(&a, &a), 0.0);
    }

    /// The least distance from points on `b`'s surface (a grid of `n` per edge) to the box
    /// `a` at the origin: an upper bound on the true distance, within the grid's spacing.
    fn sampled_distance(a: &Cuboid, pose_b: &PPose, b: &Cuboid, n: usize) -> f64 {
        let (ha, hb) = (a.half_extents, b.half_extents);
        let mut best = f64::INFINITY;
        let at = |i: usize, h: f64| -h + 2.0 * h * i as f64 / n as f64;
        for i in 0..=n {
            for j in 0..=n {
                for k in 0..=n {
                    if ![i, j, k].iter().any(|&x| x == 0 || x == n) {
                        continue;
                    }
                    let w = *pose_b * Vector::new(at(i, hb.x), at(j, hb.y), at(k, hb.z));
                    best = best.min((w - w.clamp(-ha, ha)).length());
                }
            }
        }
        best
    }

    #[test]
    fn two_boxes_are_measured_at_their_closest_points_not_their_best_separating_axis() {
        // Two links of the TX-90 met in the replay (link_2's box and link_4's second box,
        // relative pose as posed): parry3d's `query::distance` says 0.15692 m here.
        let a = Cuboid::new(Vector::new(0.126, 0.07075, 0.3245));
        let b = Cuboid::new(Vector::new(0.059, 0.087, 0.05));
        let rot = parry3d_f64::math::Rotation::from_xyzw(
            0.11217714232785986,
            0.5533872166040867,
            0.16396887429543613,
            0.8088838516750251,
        );
        let pose_b = PPose::from_parts(Vector::new(0.32187488337273096, -0.1818124384500124, 0.36468525707745253), rot);
        let d = shape_distance(&PPose::IDENTITY, &a, &pose_b, &b).expect("boxes are measured");
        let sampled = sampled_distance(&a, &pose_b, &b, 60);
        // The sampled points lie on `b`, so the distance is at most theirs; the grid's
        // spacing (b's longest edge / 60 = 2.9 mm) bounds how much nearer it can be.
        assert!(d <= sampled + 1e-9, "{d} > sampled {sampled}");
        assert!(sampled - d < 2.9e-3, "{d} far below sampled {sampled}");
        assert!((d - 0.149831).abs() < 1e-5, "{d}");
    }
}
