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

/// The static world one robot is checked against.
pub(crate) struct Scene {
    pub bvh: Bvh,
    pub entries: Vec<Entry>,
}

impl Scene {
    pub fn new(entries: Vec<Entry>) -> Scene {
        let aabbs: Vec<Aabb> = entries.iter().map(|e| e.aabb).collect();
        let bvh = if aabbs.is_empty() { Bvh::new() } else { Bvh::from_leaves(BvhBuildStrategy::default(), &aabbs) };
        Scene { bvh, entries }
    }
}
