//! How far apart two robots are, each with what it carries: the geometric fact the
//! timing stage needs to run robots at the same time.
//!
//! The planner checks each robot with the others parked at `home`; two robots moving at
//! once are only ever compared here (and, independently, by the verifier's replay).

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose as PPose;
use parry3d_f64::query;
use parry3d_f64::shape::{Shape, SharedShape};

use super::{Held, World};
use crate::resolve::RobotId;

/// One robot at one instant: its configuration and what it holds.
#[derive(Clone, Copy, Debug)]
pub struct RobotAt<'a> {
    pub robot: RobotId,
    pub q: &'a [f64],
    pub held: Option<&'a Held>,
}

/// Every shape of a robot at an instant, posed in the world frame.
struct Posed {
    shapes: Vec<(SharedShape, PPose, Aabb)>,
}

/// Gap between two boxes (0 when they overlap): never more than the distance between
/// anything inside them.
pub fn aabb_gap(a: &Aabb, b: &Aabb) -> f64 {
    let d = (a.mins - b.maxs).max(b.mins - a.maxs).max(parry3d_f64::math::Vector::ZERO);
    d.length()
}

/// The distance between two placed shapes (0 when they touch), `None` when parry3d
/// cannot measure the pair. Two convex shapes are measured by GJK on their support maps:
/// parry3d's own cuboid–cuboid distance takes its closest points from the best separating
/// axis and can overstate the distance by centimetres (a test below shows 7 mm), which a
/// safety check must never do.
pub fn shape_distance(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> Option<f64> {
    if let (Some(a), Some(b)) = (s1.as_support_map(), s2.as_support_map()) {
        return Some(query::details::distance_support_map_support_map(&p1.inv_mul(p2), a, b));
    }
    query::distance(p1, s1, p2, s2).ok().map(|d| d.distance)
}

impl World {
    fn posed(&self, at: RobotAt) -> Posed {
        let mut shapes = Vec::new();
        let mut out = Vec::new();
        let flange = self.pose_shapes(at.robot, at.q, at.held, &mut out);
        shapes.extend(out.into_iter().map(|s| (s.shape, s.pose, s.aabb)));
        if let Some(h) = at.held {
            shapes.extend(self.pose_held(h, &flange).into_iter().map(|p| (p.shape, p.pose, p.aabb)));
        }
        Posed { shapes }
    }

    /// A lower bound on the distance between two robots and what they carry: exact (the
    /// shapes' own distance) where two shapes' boxes are nearer than `near`, the boxes'
    /// gap elsewhere, and 0 when they touch. A pair of shapes parry3d cannot measure
    /// counts by its boxes' gap, which still bounds the distance from below.
    pub fn robots_apart(&self, a: RobotAt, b: RobotAt, near: f64) -> f64 {
        let (pa, pb) = (self.posed(a), self.posed(b));
        let mut best = f64::INFINITY;
        for (sa, posea, boxa) in &pa.shapes {
            for (sb, poseb, boxb) in &pb.shapes {
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::math::Vector;
    use parry3d_f64::shape::Cuboid;

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
