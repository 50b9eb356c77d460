//! A lower bound on the distance between two placed shapes, from GJK's dual bound: what
//! the verifier's conservative advancement needs (a distance from above, as parry3d's
//! own distance gives, could let it step past a contact by its error), and cheap when a
//! pair is measured again and again in small steps.

use parry3d_f64::math::{Pose as PPose, Vector as PVec};
use parry3d_f64::query::gjk::{CsoPoint, VoronoiSimplex};
use parry3d_f64::shape::Shape;

use super::proximity::{in_closed_form, shape_distance};

/// How far below the distance [`distance_at_least`] may stop: 10 µm.
pub const LOWER_BOUND_TOLERANCE: f64 = 1e-5;

/// A lower bound on the distance between two placed shapes, within `tol` of it (0 when
/// they touch), `None` when parry3d cannot measure the pair. Balls against balls and
/// boxes are measured exactly, as [`shape_distance`] does. Other convex pairs run GJK
/// on their support maps, keeping its dual bound: for any unit direction `n`, no point
/// of the shapes' Minkowski difference lies nearer the origin than `-n · s(n)`, `s(n)`
/// the difference's support point along `n`; the search stops once that bound is
/// within `tol` of its nearest point found (the distance lies between them). parry3d's
/// distance instead runs on to a relative precision of 5e-8 and returns that nearest
/// point, from above: a conservative replay wants the bound from below, and on a mesh
/// arm's hulls against boxes the last digits took most of the iterations. A search that
/// stalls returns the best bound it has, looser but still below the distance.
pub fn distance_at_least(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, tol: f64) -> Option<f64> {
    distance_at_least_from(p1, s1, p2, s2, tol, &mut GjkStart::default())
}

/// What [`distance_at_least_from`] leaves for the next measure of the same pair: the
/// points its last simplex was spanned by, each shape's in its own frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct GjkStart {
    points: [(PVec, PVec); 4],
    n: usize,
}

/// [`distance_at_least`] starting from the simplex `start` left by the pair's last measure
/// (its points where the shapes now stand: still points of the shapes' Minkowski
/// difference, so the bounds hold whatever they were; in a replay of small steps they
/// span the nearest features, and GJK ends in a step or two), leaving its own there.
pub fn distance_at_least_from(
    p1: &PPose,
    s1: &dyn Shape,
    p2: &PPose,
    s2: &dyn Shape,
    tol: f64,
    start: &mut GjkStart,
) -> Option<f64> {
    distance_at_least_below(p1, s1, p2, s2, (tol, f64::INFINITY), start)
}

/// [`distance_at_least_from`] where only a distance below `limit` matters: the search
/// also stops once its bound reaches `limit` (the shapes are at least that far apart).
pub fn distance_at_least_below(
    p1: &PPose,
    s1: &dyn Shape,
    p2: &PPose,
    s2: &dyn Shape,
    (tol, limit): (f64, f64),
    start: &mut GjkStart,
) -> Option<f64> {
    if in_closed_form(s1, s2) {
        return shape_distance(p1, s1, p2, s2);
    }
    let (Some(a), Some(b)) = (s1.as_support_map(), s2.as_support_map()) else {
        return shape_distance(p1, s1, p2, s2);
    };
    let pos12 = p1.inv_mul(p2);
    let mut simplex = VoronoiSimplex::new();
    match start.points[..start.n].split_first() {
        Some((&(o1, o2), rest)) => {
            simplex.reset(CsoPoint::new(o1, pos12 * o2));
            for &(o1, o2) in rest {
                if simplex.dimension() < 3 {
                    simplex.add_point(CsoPoint::new(o1, pos12 * o2));
                }
            }
        }
        None => {
            let dir = -pos12.translation;
            let dir = if dir.length_squared() > 1e-24 { dir.normalize() } else { PVec::X };
            simplex.reset(CsoPoint::from_shapes(&pos12, a, b, dir));
        }
    }
    let mut lower = 0.0_f64;
    // GJK gains a point of the difference per step; 64 steps are far more than a pair of
    // convex shapes needs (a stall ends sooner).
    for _ in 0..64 {
        let nearest = simplex.project_origin_and_reduce();
        let upper = nearest.length();
        // (A simplex left with four points holds the origin: the shapes overlap.)
        if upper <= lower + tol || simplex.dimension() == 3 {
            break;
        }
        let n = -nearest / upper;
        let s = CsoPoint::from_shapes(&pos12, a, b, n);
        lower = lower.max(-n.dot(s.point));
        if upper <= lower + tol || lower >= limit || !simplex.add_point(s) {
            break;
        }
    }
    let back = pos12.inverse();
    start.n = simplex.dimension() + 1;
    for i in 0..start.n {
        let p = simplex.point(i);
        start.points[i] = (p.orig1, back * p.orig2);
    }
    Some(lower)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::hull::hull_shape;
    use parry3d_f64::math::Rotation;
    use parry3d_f64::query;
    use parry3d_f64::shape::{Ball, Cuboid, Cylinder};
    use proptest::prelude::*;

    fn turn(a: (f64, f64, f64), angle: f64) -> Rotation {
        let a = PVec::new(a.0, a.1, a.2);
        Rotation::from_axis_angle(if a.length() > 1e-3 { a.normalize() } else { PVec::X }, angle)
    }

    /// The distance from a ball to a cylinder (parry's: axis y, `half` its half height),
    /// in closed form: the centre's distance to the solid cylinder, less the radius.
    fn ball_cylinder(centre: PVec, r: f64, pose: &PPose, radius: f64, half: f64) -> f64 {
        let c = pose.inverse_transform_point(centre);
        let radial = (c.x * c.x + c.z * c.z).sqrt();
        let (out_r, out_h) = ((radial - radius).max(0.0), (c.y.abs() - half).max(0.0));
        ((out_r * out_r + out_h * out_h).sqrt() - r).max(0.0)
    }

    const TOL: f64 = LOWER_BOUND_TOLERANCE;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// Against distances known exactly (a ball and a turned cylinder: GJK, not the
        /// closed forms of `shape_distance`; two unturned boxes: their boxes' gap), from a
        /// cold start and along 30 small steps each started from the last simplex: never
        /// above the distance, never more than the tolerance below it. (Returning GJK's
        /// nearest point, as parry's distance does, fails the first.)
        #[test]
        fn never_above_the_distance_nor_more_than_the_tolerance_below(
            r in 0.005f64..0.3,
            (radius, half) in (0.01f64..0.4, 0.01f64..0.5),
            t in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            axis in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            angle in -3.2f64..3.2,
            step in (-0.01f64..0.01, -0.01f64..0.01, -0.01f64..0.01, -0.05f64..0.05),
            boxes in ((0.01f64..0.4, 0.01f64..0.4, 0.01f64..0.4), (0.01f64..0.4, 0.01f64..0.4, 0.01f64..0.4)),
        ) {
            let (ball, cyl) = (Ball::new(r), Cylinder::new(half, radius));
            let (b1, b2) = (Cuboid::new(PVec::new(boxes.0.0, boxes.0.1, boxes.0.2)), Cuboid::new(PVec::new(boxes.1.0, boxes.1.1, boxes.1.2)));
            let (mut warm_cyl, mut warm_box) = (GjkStart::default(), GjkStart::default());
            for i in 0..30 {
                let k = i as f64;
                let centre = PVec::new(t.0 + k * step.0, t.1 + k * step.1, t.2 + k * step.2);
                let p1 = PPose::from_parts(centre, turn(axis, angle + k * step.3));
                let p2 = PPose::from_parts(PVec::new(0.1, -0.2, 0.3), turn((axis.1, axis.2, axis.0), -angle));
                let exact = ball_cylinder(centre, r, &p2, radius, half);
                for got in [
                    distance_at_least(&p1, &ball, &p2, &cyl, TOL),
                    distance_at_least_from(&p1, &ball, &p2, &cyl, TOL, &mut warm_cyl),
                    distance_at_least(&p2, &cyl, &p1, &ball, TOL),
                ] {
                    let got = got.expect("convex");
                    prop_assert!(got <= exact + 1e-12 && got >= exact - TOL - 1e-12, "{} against {}", got, exact);
                }
                let (q1, q2) = (PPose::from_translation(centre), PPose::from_translation(PVec::new(0.1, -0.2, 0.3)));
                let gap = crate::world::aabb_gap(&b1.aabb(&q1), &b2.aabb(&q2));
                for got in [
                    distance_at_least(&q1, &b1, &q2, &b2, TOL),
                    distance_at_least_from(&q1, &b1, &q2, &b2, TOL, &mut warm_box),
                ] {
                    let got = got.expect("convex");
                    prop_assert!(got <= gap + 1e-12 && got >= gap - TOL - 1e-12, "{} against {}", got, gap);
                }
            }
        }
    }

    /// Hulls (random point clouds) against turned boxes and each other, cold and warm,
    /// moved in small steps through contact and apart: within the tolerance below
    /// parry3d's distance (itself at most tens of micrometres above the distance), never
    /// above it, and 0 exactly where parry3d finds them intersecting.
    #[test]
    fn hulls_and_boxes_against_parrys_distance() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let (mut near, mut overlapping) = (0, 0);
        for _ in 0..200 {
            let cloud = |rng: &mut rand_chacha::ChaCha8Rng| {
                let pts: Vec<PVec> = (0..40)
                    .map(|_| {
                        PVec::new(
                            rng.random_range(-0.1..0.1),
                            rng.random_range(-0.05..0.05),
                            rng.random_range(-0.2..0.2),
                        )
                    })
                    .collect();
                hull_shape(&pts).expect("a hull")
            };
            let (h1, h2) = (cloud(&mut rng), cloud(&mut rng));
            let cube = Cuboid::new(PVec::new(0.1, 0.2, 0.05));
            let start =
                PVec::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
            let dir = -start.normalize() * 0.02;
            let (axis, angle) = ((rng.random(), rng.random(), rng.random()), rng.random_range(-3.0..3.0));
            let (mut w1, mut w2) = (GjkStart::default(), GjkStart::default());
            for i in 0..60 {
                let p1 = PPose::from_parts(start + dir * i as f64, turn(axis, angle + 0.01 * i as f64));
                let p2 = PPose::from_parts(PVec::ZERO, turn((0.3, 0.1, 0.9), 0.7));
                for (s2, warm) in [(&cube as &dyn Shape, &mut w1), (&*h2.0, &mut w2)] {
                    let parry = query::distance(&p1, &*h1.0, &p2, s2).expect("convex").distance;
                    let hit = query::intersection_test(&p1, &*h1.0, &p2, s2).expect("convex").intersecting;
                    for got in [
                        distance_at_least(&p1, &*h1.0, &p2, s2, TOL).expect("convex"),
                        distance_at_least_from(&p1, &*h1.0, &p2, s2, TOL, warm).expect("convex"),
                    ] {
                        assert!(got <= parry + 1e-12 && got >= parry - TOL - 5e-5, "{got} against parry {parry}");
                        if hit {
                            assert_eq!(got, 0.0, "intersecting");
                        }
                    }
                    near += usize::from(!hit && parry < 0.02);
                    overlapping += usize::from(hit);
                }
            }
        }
        assert!(near > 200 && overlapping > 1000, "{near} near, {overlapping} overlapping");
    }
}
