//! How far apart two robots are, each with what it carries: the geometric fact the
//! timing stage needs to run robots at the same time.
//!
//! The planner checks each robot with the others parked at `home`; two robots moving at
//! once are only ever compared here (and, independently, by the verifier's replay).

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose as PPose;
use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;

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
                    query::distance(posea, &*sa.0, poseb, &*sb.0).map_or(gap, |d| d.distance.max(gap))
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

    #[test]
    fn the_gap_of_boxes_is_the_distance_between_their_nearest_corners() {
        // Boxes [0,1]³ and [2,3]×[3,4]×[0,1]: gaps 1 and 2 on x and y, none on z: √5.
        let a = Aabb::new(Vector::new(0.0, 0.0, 0.0), Vector::new(1.0, 1.0, 1.0));
        let b = Aabb::new(Vector::new(2.0, 3.0, 0.0), Vector::new(3.0, 4.0, 1.0));
        assert!((aabb_gap(&a, &b) - 5f64.sqrt()).abs() < 1e-12);
        assert_eq!(aabb_gap(&a, &a), 0.0);
    }
}
