//! The static world one robot is checked against: fixed bodies, removable objects
//! and the other robots at home, each shape with its owner, under one BVH.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
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

/// Scenes of at most this many shapes are scanned, larger ones walked as a [`Flat`] tree
/// (see [`Scene::overlapping`]). Measured: the families' Panda and UR5 problems (6 to 9
/// shapes) gain by the scan over parry's traversal, and lose 0.3-1 % of their
/// instructions with the flat tree; the paper's examples (20 to 22 shapes, most far from
/// any one body) would lose a few percent with the scan.
const SCAN_MAX: usize = 16;

/// The static world one robot is checked against.
pub(crate) struct Scene {
    pub bvh: Bvh,
    pub entries: Vec<Entry>,
    /// Every leaf with its box, in the order the BVH's depth-first traversal meets them:
    /// scanned when the scene is small, else walked as a [`Flat`] tree.
    scan: Option<Vec<(u32, Aabb)>>,
    flat: Option<Flat>,
}

impl Scene {
    pub fn new(entries: Vec<Entry>) -> Scene {
        let aabbs: Vec<Aabb> = entries.iter().map(|e| e.aabb).collect();
        let bvh = if aabbs.is_empty() { Bvh::new() } else { Bvh::from_leaves(BvhBuildStrategy::default(), &aabbs) };
        // (An order missing a leaf would miss its shape: then parry's traversal it is.)
        let order = Some(traversal_order(&bvh)).filter(|order| order.len() == entries.len());
        let (scan, flat) = match order {
            Some(order) if order.len() <= SCAN_MAX => (Some(order), None),
            Some(order) => (None, Some(Flat::new(&order))),
            None => (None, None),
        };
        Scene { bvh, entries, scan, flat }
    }

    /// Into `out` (cleared first), the leaves whose boxes meet `aabb`, in the order of
    /// `bvh.intersect_aabb(aabb)`. A small scene's boxes are compared one after the
    /// other: for a few shapes that costs less than setting up the traversal. A leaf's
    /// box lies in each of its ancestors' (their unions), so the traversal prunes no leaf
    /// whose own box meets `aabb`: its answer is the leaves of its depth-first order that
    /// meet `aabb`, which is what the scan and the [`Flat`] tree give.
    #[inline]
    pub fn overlapping(&self, aabb: &Aabb, out: &mut Vec<u32>) {
        out.clear();
        match (&self.scan, &self.flat) {
            (Some(scan), _) => scan_meeting(scan, aabb, out),
            (None, Some(flat)) => flat.meeting(aabb, out),
            (None, None) => out.extend(self.bvh.intersect_aabb(aabb)),
        }
    }
}

/// The scene's leaves in the BVH's depth-first order under a balanced tree of their own,
/// laid out in preorder with each node's next sibling (or its ancestors') index: a query
/// walks the array forwards, skipping a subtree whose box it misses, with no stack and no
/// iterator (parry's traversal cost about 157 instructions a query on the paper's scenes
/// of 20-odd shapes). Any tree over the leaves in that order, each node's box the union
/// of its leaves', yields the leaves that meet a box in that order.
struct Flat {
    nodes: Vec<FlatNode>,
}

struct FlatNode {
    aabb: Aabb,
    /// Where the walk goes when this node's box is missed: past its subtree.
    skip: u32,
    /// The leaf, or `u32::MAX` for an inner node.
    leaf: u32,
}

impl Flat {
    fn new(order: &[(u32, Aabb)]) -> Flat {
        let mut nodes = Vec::with_capacity(2 * order.len());
        Flat::push(order, &mut nodes);
        Flat { nodes }
    }

    fn push(leaves: &[(u32, Aabb)], nodes: &mut Vec<FlatNode>) {
        let mut union = leaves[0].1;
        for (_, b) in &leaves[1..] {
            union.merge(b);
        }
        let at = nodes.len();
        let leaf = if leaves.len() == 1 { leaves[0].0 } else { u32::MAX };
        nodes.push(FlatNode { aabb: union, skip: 0, leaf });
        if leaves.len() > 1 {
            let half = leaves.len() / 2;
            Flat::push(&leaves[..half], nodes);
            Flat::push(&leaves[half..], nodes);
        }
        nodes[at].skip = nodes.len() as u32;
    }

    #[inline]
    fn meeting(&self, aabb: &Aabb, out: &mut Vec<u32>) {
        let mut i = 0;
        while let Some(n) = self.nodes.get(i) {
            if meets(&n.aabb, aabb) {
                if n.leaf != u32::MAX {
                    out.push(n.leaf);
                }
                i += 1;
            } else {
                i = n.skip as usize;
            }
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
        if meets(b, aabb) {
            out.push(*leaf);
        }
    }
}

/// `BvhNode::intersects`'s test, bounds included, with one branch, not six.
#[inline]
fn meets(b: &Aabb, q: &Aabb) -> bool {
    (b.mins.x <= q.maxs.x)
        & (b.mins.y <= q.maxs.y)
        & (b.mins.z <= q.maxs.z)
        & (b.maxs.x >= q.mins.x)
        & (b.maxs.y >= q.mins.y)
        & (b.maxs.z >= q.mins.z)
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

    /// The flat tree yields the traversal's leaves in the traversal's order, for scenes
    /// of 1 to 300 boxes (the 200-can table has 220 shapes), boxes touching included.
    #[test]
    fn the_flat_tree_meets_the_leaves_the_traversal_does_in_its_order() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let mut out = Vec::new();
        let (mut met, mut missed) = (0, 0);
        for n in (1..=40).chain([64, 100, 150, 220, 300]) {
            for _ in 0..10 {
                let size = 2.0 / (n as f64).cbrt();
                let mut boxes: Vec<Aabb> = (0..n).map(|_| random_box(&mut rng, 0.3 * size)).collect();
                let touching = Aabb::new(PVec::new(boxes[0].maxs.x, 0.0, 0.0), PVec::new(2.0, 1.2, 1.2));
                boxes.push(touching);
                let bvh = Bvh::from_leaves(BvhBuildStrategy::default(), &boxes);
                let flat = Flat::new(&traversal_order(&bvh));
                for q in (0..30).map(|_| random_box(&mut rng, 0.3)).chain([boxes[0], boxes[n / 2]]) {
                    flat.meeting(&q, &mut out);
                    let traversed: Vec<u32> = bvh.intersect_aabb(&q).collect();
                    assert_eq!(out, traversed, "{n} boxes");
                    met += out.len();
                    missed += usize::from(out.is_empty());
                    out.clear();
                }
            }
        }
        // Queries that met many boxes and queries that met none.
        assert!(met > 10_000 && missed > 1_000, "{met} {missed}");
    }
}
