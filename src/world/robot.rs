//! One robot as the world holds it: its chain, its collision bodies in link frames,
//! where it stands, and the static scene it is checked against. Every other file
//! of `world` reads this one; it reads only the chain, the shapes and the scene.

use std::ops::Range;

use parry3d_f64::math::Pose as PPose;

use super::analytic::Analytic;
use super::analytic7::Redundant;
use super::ball_pack::BallPack;
use super::chain::{Chain, FingerJoint};
use super::pair_grid::PairGrid;
use super::scene::Scene;
use super::shapes::{Obb, Placed};
use super::Config;
use crate::resolve::Pose;

/// A rigid set of collision shapes moving with one link.
pub(crate) struct RBody {
    pub name: String,
    pub link: usize,
    pub shapes: Range<usize>,
    /// False for the root link and links fixed to it: never checked against the scene.
    pub moving: bool,
    /// Rigid with the flange (the hand, the flange link): ignores a carried object.
    pub holds: bool,
}

/// One shape of a robot, posed in its link's frame.
pub(crate) struct RShape {
    pub body: usize,
    pub placed: Placed,
    /// Unturned on its link in every posture: placing it turns its offset only (see
    /// [`super::shapes::place`]).
    pub unturned: bool,
}

pub(crate) struct RobotModel {
    pub name: String,
    pub chain: Chain,
    pub pose_world_base: Pose,
    pub pose_flange_tcp: Pose,
    pub shapes: Vec<RShape>,
    pub bodies: Vec<RBody>,
    pub self_pairs: Vec<(usize, usize)>,
    /// Per self pair: its joint-space grid of distances, when it has one (see `pair_grid`).
    pub self_grids: Vec<Option<PairGrid>>,
    /// Per body: a box in its link's frame holding its shapes in every posture, so that a
    /// check can bound the body before (or without) placing its shapes.
    pub body_frames: Vec<Obb>,
    /// Per body: its balls as one pack, when it is made of balls only (see `ball_pack`).
    pub ball_packs: Vec<Option<BallPack>>,
    /// Place a body's shapes only when needed (see `check::pose_robot`); off, every shape is
    /// placed at every check and a body's box is its shapes' (the plain check, for tests).
    pub fast_check: bool,
    /// Link pairs never checked against each other: the scenario's `allow_contact` and the
    /// robot package's own filters (Drake filter groups, SRDF).
    pub allowed_pairs: Vec<(String, String)>,
    pub scene: Scene,
    pub home: Config,
    pub drop: Config,
    /// The closed-form IK solver, when the arm is of a family it knows.
    pub analytic: Option<Analytic>,
    /// The closed-form IK solver of a 7R arm (joint 7 given), when it is of that family.
    pub redundant: Option<Redundant>,
    /// The gripper's finger joints: the arm URDF's, then the hand's.
    pub fingers: Vec<FingerJoint>,
    /// Where the fingers can stand; the first is open (the hand empty).
    pub postures: Vec<Posture>,
    /// Per object, per grasp: the posture the fingers hold it in.
    pub grasp_posture: Vec<Vec<usize>>,
    /// Per posture: the postures the fingers pass through from open to it (none for open).
    pub closing: Vec<Vec<usize>>,
}

/// One stance of the fingers: their joint values, and every shape's pose in its body's
/// link frame with the fingers there (the shapes of other links as they always are).
pub(crate) struct Posture {
    pub values: Vec<f64>,
    pub poses: Vec<PPose>,
}

impl RobotModel {
    /// The packs of [`RobotModel::ball_packs`].
    pub fn ball_packs(bodies: &[RBody], shapes: &[RShape], postures: &[Posture]) -> Vec<Option<BallPack>> {
        bodies.iter().map(|b| BallPack::of(&shapes[b.shapes.clone()], b.shapes.start, postures)).collect()
    }

    /// The boxes of [`RobotModel::body_frames`].
    pub fn frame_boxes(bodies: &[RBody], shapes: &[RShape], postures: &[Posture]) -> Vec<Obb> {
        bodies
            .iter()
            .map(|b| {
                use parry3d_f64::bounding_volume::BoundingVolume as _;
                let mut aabb = parry3d_f64::bounding_volume::Aabb::new_invalid();
                for si in b.shapes.clone() {
                    let shape = &shapes[si].placed;
                    let poses = postures.iter().filter_map(|p| p.poses.get(si));
                    for pose in std::iter::once(&shape.pose).chain(poses) {
                        aabb.merge(&shape.shape.compute_aabb(pose));
                    }
                }
                Obb::of_aabb(&aabb)
            })
            .collect()
    }

    /// Shape `si`'s pose in its body's link frame with the fingers in `posture`.
    #[inline]
    pub fn shape_pose(&self, si: usize, posture: usize) -> &PPose {
        self.postures.get(posture).and_then(|p| p.poses.get(si)).unwrap_or(&self.shapes[si].placed.pose)
    }
}

/// The contract of every public method taking a configuration (documented on
/// [`World::fk_flange`]): a wrong length is the caller's bug, reported plainly here
/// rather than as an index out of bounds deep in the kinematics.
#[inline]
pub(crate) fn assert_dof(m: &RobotModel, q: &[f64]) {
    assert!(
        q.len() == m.chain.dof(),
        "configuration of robot `{}` has {} values, but the robot has {} joints",
        m.name,
        q.len(),
        m.chain.dof()
    );
}
