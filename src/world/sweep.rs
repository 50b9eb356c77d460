//! The world model as the time-replaying verifier reads it: every collision shape
//! posed in the world, the self-collision pairs before any sampled pruning, and how
//! far a point of a robot can move per unit of joint motion.
//!
//! Nothing here is used by the planner; the labelled check ([`super::check`]) stays
//! its only collision test.

use std::cell::RefCell;
use std::sync::Arc;

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose as PPose;
use parry3d_f64::shape::SharedShape;

use super::chain::Source;
use super::check;
use super::robot::RobotModel;
use super::scene::Owner;
use super::self_pairs;
use super::shapes::{aabb_of, place, to_ppose, Placed};
use super::urdf::Motion;
use super::{Held, World};
use crate::resolve::{FixedId, ObjectId, RobotId};

/// One collision body of a robot: the link it rides on (or the hand).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BodyInfo {
    pub name: String,
    /// False for the base and what is rigidly fixed to it.
    pub moving: bool,
    /// Rigid with the flange (the hand): a carried object may touch it.
    pub holds: bool,
}

/// A robot's collision shape posed in the world frame.
#[derive(Clone)]
pub struct PosedShape {
    /// Index into [`World::bodies`].
    pub body: usize,
    pub shape: SharedShape,
    /// For a primitive, the shape shrunk by [`CONTACT_TOLERANCE`]: two shapes overlap deeper
    /// than the tolerance exactly when this one meets the other (the world's contact rule).
    ///
    /// [`CONTACT_TOLERANCE`]: super::CONTACT_TOLERANCE
    pub eroded: Option<SharedShape>,
    pub pose: PPose,
    pub aabb: Aabb,
}

/// A part of a carried object, posed in the world frame (`eroded` as for [`PosedShape`]).
#[derive(Clone)]
pub struct HeldPart {
    pub shape: SharedShape,
    pub eroded: Option<SharedShape>,
    pub pose: PPose,
    pub aabb: Aabb,
}

/// What a static shape of the scene belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StaticOwner {
    Fixed(FixedId),
    /// A removable object at its place in the scenario.
    Object(ObjectId),
}

/// A fixed body's or an object's shape, posed in the world frame.
#[derive(Clone)]
pub struct StaticShape {
    pub owner: StaticOwner,
    pub shape: SharedShape,
    pub pose: PPose,
    pub aabb: Aabb,
}

/// Per actuated joint, bounds (metres per unit of joint motion) on how fast a point
/// moves: a point at distance `d` from a revolute axis turned by `Δθ` moves at most
/// `d·Δθ`, a sliding joint moves it by its travel. Summed over joints, `Σ reach_j·|Δq_j|`
/// bounds the displacement of every point, in every configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct JointReach {
    /// For the robot's own bodies (links and hand).
    pub bodies: Vec<f64>,
    /// For the flange's origin.
    pub flange: Vec<f64>,
    /// Σ |mimic multiplier| of the revolute joints this value turns between base and flange:
    /// a carried object's point at distance `ρ` from the flange origin adds `turn·ρ`.
    pub turn: Vec<f64>,
}

impl JointReach {
    /// The bound per joint for every point of the robot and of an object carried at most
    /// `held_radius` from the flange origin.
    pub fn with_held(&self, held_radius: f64) -> Vec<f64> {
        (0..self.bodies.len()).map(|j| self.bodies[j].max(self.flange[j] + self.turn[j] * held_radius)).collect()
    }
    /// The bound on any point's displacement for joint displacements `dq`.
    pub fn displacement(reach: &[f64], dq: &[f64]) -> f64 {
        reach.iter().zip(dq).map(|(r, d)| r * d.abs()).sum()
    }
}

impl World {
    /// The robot's collision bodies, indexed as [`PosedShape::body`].
    pub fn bodies(&self, r: RobotId) -> Vec<BodyInfo> {
        let m = &self.robots[r.index()];
        m.bodies.iter().map(|b| BodyInfo { name: b.name.clone(), moving: b.moving, holds: b.holds }).collect()
    }

    /// Every collision shape of the robot at `q`, in the world frame, the fingers closed
    /// as they hold `held` (open when empty), written into `out`; returns the flange pose.
    /// Panics if `q.len()` is not [`World::dof`].
    pub fn pose_shapes(&self, r: RobotId, q: &[f64], held: Option<&Held>, out: &mut Vec<PosedShape>) -> Isometry3<f64> {
        let m = &self.robots[r.index()];
        self.shape_slots(r, out);
        WORLD_LINKS.with(|cell| {
            let mut world = cell.borrow_mut();
            let flange = self.pose_links(r, q, &mut world);
            let posture = posture_of(held);
            for (si, o) in out.iter_mut().enumerate() {
                pose_shape(m, &world, si, posture, true, &mut o.pose, &mut o.aabb);
            }
            flange
        })
    }

    /// `out` holding robot `r`'s shapes in order, for [`World::pose_shape_on`]: kept when
    /// it already does (their poses and boxes then as they were).
    pub fn shape_slots(&self, r: RobotId, out: &mut Vec<PosedShape>) {
        let m = &self.robots[r.index()];
        // The replay poses the same robot at every instant: when `out` already holds its
        // shapes, only their poses and boxes change (no reference counting).
        if !(out.len() == m.shapes.len() && out.iter().zip(&m.shapes).all(|(o, s)| same_shape(o, s.body, &s.placed))) {
            out.clear();
            out.extend(m.shapes.iter().map(|s| PosedShape {
                body: s.body,
                shape: s.placed.shape.clone(),
                eroded: s.placed.eroded.clone(),
                pose: PPose::IDENTITY,
                aabb: Aabb::new_invalid(),
            }));
        }
    }

    /// The first half of posing a robot for a replay that poses only the shapes it asks
    /// about: every link's world pose at `q` into `links`; returns the flange pose. Panics
    /// if `q.len()` is not [`World::dof`].
    pub fn pose_links(&self, r: RobotId, q: &[f64], links: &mut Vec<PPose>) -> Isometry3<f64> {
        let m = &self.robots[r.index()];
        super::robot::assert_dof(m, q);
        LINKS.with(|cell| {
            let mut from_base = cell.borrow_mut();
            from_base.clear();
            from_base.resize(m.chain.links.len(), Isometry3::identity());
            // Each link's world pose once, not once per shape on it, from the base's pose in
            // the world (no second product per link, as the check poses them).
            m.chain.fk_from(&m.pose_world_base, q, &mut from_base);
            links.clear();
            links.extend(from_base.iter().map(to_ppose));
            from_base[m.chain.flange]
        })
    }

    /// The second half: shape `si` of robot `r` (in the order of [`World::shape_slots`])
    /// placed on `links` (from [`World::pose_links`]) with the fingers in `posture` (see
    /// [`posture_of`]), its box a mesh hull's local box turned (looser, a cuboid's cost)
    /// instead of its exact world box (a walk over its vertices: 15 % of a mesh robot's
    /// whole compile was there). For the replay, whose boxes are only broad-phase filters
    /// and lower bounds on distances, never a verdict.
    pub fn pose_shape_on(&self, r: RobotId, links: &[PPose], si: usize, posture: usize, out: &mut PosedShape) {
        pose_shape(&self.robots[r.index()], links, si, posture, false, &mut out.pose, &mut out.aabb);
    }

    /// The fixed bodies and every removable object at its scenario pose.
    pub fn static_shapes(&self) -> Vec<StaticShape> {
        // Every robot's scene holds the same fixed bodies and objects; the first is enough.
        let Some(m) = self.robots.first() else { return Vec::new() };
        m.scene
            .entries
            .iter()
            .filter_map(|e| {
                let owner = match e.owner {
                    Owner::Fixed(f) => StaticOwner::Fixed(f),
                    Owner::Object(o) => StaticOwner::Object(o),
                    Owner::Robot(..) => return None,
                };
                Some(StaticShape { owner, shape: e.shape.clone(), pose: e.pose, aabb: e.aabb })
            })
            .collect()
    }

    /// The carried object's shapes in the world frame, the flange at `pose_world_flange`.
    pub fn pose_held(&self, held: &Held, pose_world_flange: &Isometry3<f64>) -> Vec<HeldPart> {
        let mut out = Vec::new();
        self.pose_held_into(held, pose_world_flange, &mut out);
        out
    }

    /// [`World::pose_held`] into `out`, reusing its room.
    pub fn pose_held_into(&self, held: &Held, pose_world_flange: &Isometry3<f64>, out: &mut Vec<HeldPart>) {
        let base = to_ppose(&(pose_world_flange * held.pose_flange_object));
        out.clear();
        out.extend(self.object_parts[held.object.index()].iter().map(|p| {
            let pose = base * p.pose;
            HeldPart { shape: p.shape.clone(), eroded: p.eroded.clone(), pose, aabb: aabb_of(&*p.shape.0, &pose) }
        }));
    }

    /// How far from the flange origin a point of the carried object can be.
    pub fn held_radius(&self, held: &Held) -> f64 {
        let base = to_ppose(&held.pose_flange_object);
        self.object_parts[held.object.index()].iter().map(|p| radius_about_origin(&base, p)).fold(0.0, f64::max)
    }

    /// Body pairs checked for self-collision with no sampled pruning: every pair with a
    /// moving body except those rigidly joined, adjacent in the URDF, named in
    /// `allow_contact`, or excluded by the robot package's own filters (Drake filter
    /// groups, SRDF).
    pub fn self_pairs_unpruned(&self, r: RobotId) -> Vec<(usize, usize)> {
        let m = &self.robots[r.index()];
        self_pairs::self_pairs(m, &m.allowed_pairs, 0, 0)
    }

    /// Per collision body (indexed as [`World::bodies`]), then for the flange: which joint
    /// values move it (a mimic follower's leader too). Two bodies of one robot move
    /// relative to each other only by the joints that move one and not the other.
    pub fn body_joints(&self, r: RobotId) -> (Vec<Vec<bool>>, Vec<bool>) {
        let m = &self.robots[r.index()];
        let chain = &m.chain;
        let moved_by = |link: usize| {
            let mut mask = vec![false; chain.dof()];
            let mut l = Some(link);
            while let Some(k) = l {
                if let Source::Active { index, .. } = chain.links[k].source {
                    mask[index] = true;
                }
                l = chain.links[k].parent;
            }
            mask
        };
        (m.bodies.iter().map(|b| moved_by(b.link)).collect(), moved_by(chain.flange))
    }

    /// See [`JointReach`]: from the URDF's link offsets and each shape's bounding sphere,
    /// so it holds in every configuration.
    pub fn joint_reach(&self, r: RobotId) -> JointReach {
        joint_reach(&self.robots[r.index()])
    }

    /// Per body of [`World::bodies`], per joint: how far the body's own points can move per
    /// unit of the joint (radian or metre), whatever the other joints do; 0 for a joint that
    /// does not move it. [`JointReach::bodies`] bounds every body a joint moves at once; two
    /// bodies of one robot close in no faster than the joints that move one and not the
    /// other move that one, which this bounds body by body.
    pub fn body_reach(&self, r: RobotId) -> Vec<Vec<f64>> {
        let m = &self.robots[r.index()];
        let links = &m.chain.links;
        let own = own_radii(m);
        m.bodies
            .iter()
            .map(|b| {
                let mut reach = vec![0.0; m.chain.dof()];
                // Bound on the distance from link `l`'s origin to the body's points.
                let mut dist = own[b.link];
                let mut l = Some(b.link);
                while let Some(k) = l {
                    if let Source::Active { index, mult, .. } = links[k].source {
                        match links[k].motion {
                            Motion::Rotate(_) => reach[index] += mult.abs() * dist,
                            Motion::Slide(_) => reach[index] += mult.abs(),
                            Motion::Fixed => {}
                        }
                    }
                    dist += link_step(m, k);
                    l = links[k].parent;
                }
                reach
            })
            .collect()
    }
}

thread_local! {
    /// Link poses for [`World::pose_links`], reused across calls.
    static LINKS: RefCell<Vec<Isometry3<f64>>> = const { RefCell::new(Vec::new()) };
    /// The links' world poses for [`World::pose_shapes`], reused across calls.
    static WORLD_LINKS: RefCell<Vec<PPose>> = const { RefCell::new(Vec::new()) };
}

/// The fingers' posture of a robot holding `held` (open when it holds nothing).
pub fn posture_of(held: Option<&Held>) -> usize {
    held.map_or(super::OPEN_POSTURE, |h| h.posture)
}

/// Shape `si` of `m` placed on its link (`links`: the links' world poses) with the
/// fingers in `posture`, and its box: exact, or (for the replay) the cheaper bound of
/// [`check::moving_aabb`]. Written in place: the replay poses every shape at every
/// instant, and a pose and box returned by value were copied twice.
#[inline(always)]
fn pose_shape(
    m: &RobotModel,
    links: &[PPose],
    si: usize,
    posture: usize,
    exact: bool,
    pose: &mut PPose,
    aabb: &mut Aabb,
) {
    let s = &m.shapes[si];
    *pose = place(&links[m.bodies[s.body].link], m.shape_pose(si, posture), s.unturned);
    *aabb = if exact { aabb_of(&*s.placed.shape.0, pose) } else { check::moving_aabb(&s.placed, pose) };
}

/// Whether a posed shape is this body's `placed` (the same shared shapes, not equal ones).
fn same_shape(o: &PosedShape, body: usize, placed: &Placed) -> bool {
    let ptr = |s: &SharedShape| Arc::as_ptr(&s.0) as *const ();
    o.body == body
        && ptr(&o.shape) == ptr(&placed.shape)
        && o.eroded.as_ref().map(ptr) == placed.eroded.as_ref().map(ptr)
}

/// Distance from the frame's origin to the farthest point of a shape placed in it by `pose`.
fn radius_about_origin(pose: &PPose, p: &Placed) -> f64 {
    radius_at(&(*pose * p.pose), &p.shape)
}

/// Distance from the frame's origin to the farthest point of `shape` at `pose` in it.
fn radius_at(pose: &PPose, shape: &SharedShape) -> f64 {
    let sphere = shape.0.compute_local_bounding_sphere();
    pose.transform_point(sphere.center).length() + sphere.radius
}

/// How far link `l`'s origin can be from its parent's: the fixed offset plus, for a
/// sliding joint, its travel.
fn link_step(m: &RobotModel, l: usize) -> f64 {
    let link = &m.chain.links[l];
    let offset = link.pose_parent_joint.translation.vector.norm();
    let travel = match (link.motion, link.source) {
        (Motion::Slide(_), Source::Active { index, mult, offset: o }) => {
            let (lo, hi) = m.chain.limits[index];
            (lo * mult + o).abs().max((hi * mult + o).abs())
        }
        (Motion::Slide(_), Source::Frozen(v)) => v.abs(),
        _ => 0.0,
    };
    offset + travel
}

/// Per link: the farthest shape point from its own origin, in every finger posture.
fn own_radii(m: &RobotModel) -> Vec<f64> {
    let mut own = vec![0.0f64; m.chain.links.len()];
    for (si, s) in m.shapes.iter().enumerate() {
        let l = m.bodies[s.body].link;
        for p in 0..m.postures.len().max(1) {
            own[l] = own[l].max(radius_at(m.shape_pose(si, p), &s.placed.shape));
        }
    }
    own
}

fn joint_reach(m: &RobotModel) -> JointReach {
    let links = &m.chain.links;
    let n = links.len();
    let dof = m.chain.dof();
    let step = |l: usize| link_step(m, l);
    let own = own_radii(m);
    // Farthest point of the subtree below each link, from that link's origin. Parents
    // come before children, so a reverse pass sees every child first.
    let mut below = own.clone();
    for l in (1..n).rev() {
        if let Some(p) = links[l].parent {
            below[p] = below[p].max(step(l) + below[l]);
        }
    }
    let mut reach = JointReach { bodies: vec![0.0; dof], flange: vec![0.0; dof], turn: vec![0.0; dof] };
    // Distance bound from each link's origin down to the flange's origin, on the path.
    let path = &m.chain.path;
    for (k, &l) in path.iter().enumerate() {
        let to_flange: f64 = path[k + 1..].iter().map(|&c| step(c)).sum();
        if let Source::Active { index, mult, .. } = links[l].source {
            match links[l].motion {
                Motion::Rotate(_) => {
                    reach.flange[index] += mult.abs() * to_flange;
                    reach.turn[index] += mult.abs();
                }
                Motion::Slide(_) => reach.flange[index] += mult.abs(),
                Motion::Fixed => {}
            }
        }
    }
    // Every link a joint value drives (mimic followers off the path too) adds its subtree.
    for (l, link) in links.iter().enumerate() {
        if let Source::Active { index, mult, .. } = link.source {
            match link.motion {
                Motion::Rotate(_) => reach.bodies[index] += mult.abs() * below[l],
                Motion::Slide(_) => reach.bodies[index] += mult.abs(),
                Motion::Fixed => {}
            }
        }
    }
    reach
}
