//! The static world one robot is checked against: fixed bodies, removable objects
//! and the other robots at home, each shape with its owner, under one BVH.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose as PPose;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::shape::SharedShape;

use super::shapes::{aabb_of, Obb, Placed};
use crate::resolve::{FixedId, ObjectId, RobotId};

/// Who a static shape belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Owner {
    Fixed(FixedId),
    Object(ObjectId),
    /// Another robot's body, at that robot's home.
    Robot(RobotId, usize),
}

#[derive(Clone)]
pub(crate) struct Entry {
    pub owner: Owner,
    pub shape: SharedShape,
    pub pose: PPose,
    pub aabb: Aabb,
    pub obb: Obb,
}

impl Entry {
    pub fn new(owner: Owner, p: Placed) -> Entry {
        let aabb = aabb_of(&*p.shape.0, &p.pose);
        Entry { owner, shape: p.shape, pose: p.pose, aabb, obb: p.obb }
    }
}

/// Scenes of at most this many shapes are scanned, not traversed (see
/// [`Scene::overlapping`]). Measured: the families' Panda and UR5 problems (6 to 9
/// shapes) gain; the paper's examples (20 to 22 shapes, most far from any one body)
/// would lose a few percent.
const SCAN_MAX: usize = 16;

/// The static world one robot is checked against.
pub(crate) struct Scene {
    pub bvh: Bvh,
    pub entries: Vec<Entry>,
    /// When the scene is small: every leaf with its box, in the order the BVH's
    /// depth-first traversal meets them.
    scan: Option<Vec<(u32, Aabb)>>,
}

impl Scene {
    pub fn new(entries: Vec<Entry>) -> Scene {
        let aabbs: Vec<Aabb> = entries.iter().map(|e| e.aabb).collect();
        let bvh = if aabbs.is_empty() { Bvh::new() } else { Bvh::from_leaves(BvhBuildStrategy::default(), &aabbs) };
        // (A scan missing a leaf would miss its shape: then the traversal it is.)
        let scan =
            (entries.len() <= SCAN_MAX).then(|| traversal_order(&bvh)).filter(|scan| scan.len() == entries.len());
        Scene { bvh, entries, scan }
    }

    /// Into `out` (cleared first), the leaves whose boxes meet `aabb`, in the order of
    /// `bvh.intersect_aabb(aabb)`. A small scene's boxes are compared one after the
    /// other: for a few shapes that costs less than setting up the traversal. A leaf's
    /// box lies in each of its ancestors' (their unions), so the traversal prunes no leaf
    /// whose own box meets `aabb`: the same leaves in the same order.
    #[inline]
    pub fn overlapping(&self, aabb: &Aabb, out: &mut Vec<u32>) {
        out.clear();
        match &self.scan {
            Some(scan) => scan_meeting(scan, aabb, out),
            None => out.extend(self.bvh.intersect_aabb(aabb)),
        }
    }
}

/// Every leaf of `bvh` with its box, in depth-first order (left child first).
fn traversal_order(bvh: &Bvh) -> Vec<(u32, Aabb)> {
    let leaves: Vec<u32> = bvh.leaves(|_| true).collect();
    leaves.iter().filter_map(|&l| bvh.leaf_node(l).map(|n| (l, n.aabb()))).collect()
}

#[inline]
fn scan_meeting(scan: &[(u32, Aabb)], aabb: &Aabb, out: &mut Vec<u32>) {
    for (leaf, b) in scan {
        // `BvhNode::intersects`'s test, bounds included.
        if b.mins.cmple(aabb.maxs).all() && b.maxs.cmpge(aabb.mins).all() {
            out.push(*leaf);
        }
    }
}

#[cfg(test)]
mod tests {
    use parry3d_f64::math::Vector as PVec;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    fn random_box(rng: &mut ChaCha8Rng, size: f64) -> Aabb {
        let mut v = || rng.random::<f64>();
        let lo = PVec::new(v(), v(), v());
        Aabb::new(lo, lo + PVec::new(v(), v(), v()) * size)
    }

    /// The scan yields the traversal's leaves in the traversal's order, for scenes of
    /// every size the scan is used at and beyond, boxes touching included.
    #[test]
    fn a_scan_meets_the_leaves_the_traversal_does_in_its_order() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut out = Vec::new();
        let mut met = 0;
        for n in 1..=40 {
            for _ in 0..20 {
                let mut boxes: Vec<Aabb> = (0..n).map(|_| random_box(&mut rng, 0.2)).collect();
                // A box touching another's face: bounds count as meeting.
                let touching = Aabb::new(PVec::new(boxes[0].maxs.x, 0.0, 0.0), PVec::new(2.0, 1.2, 1.2));
                boxes.push(touching);
                let bvh = Bvh::from_leaves(BvhBuildStrategy::default(), &boxes);
                let scan = traversal_order(&bvh);
                assert_eq!(scan.len(), boxes.len());
                for q in (0..30).map(|_| random_box(&mut rng, 0.4)).chain([boxes[0]]) {
                    scan_meeting(&scan, &q, &mut out);
                    let traversed: Vec<u32> = bvh.intersect_aabb(&q).collect();
                    assert_eq!(out, traversed, "{n} boxes");
                    met += out.len();
                    out.clear();
                }
            }
        }
        // Not a vacuous comparison: the queries met boxes.
        assert!(met > 10_000, "{met}");
    }
}
