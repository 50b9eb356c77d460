//! World: a resolved [`Scenario`] turned into something the planner can query fast.
//!
//! In: a `Scenario` and a [`Loader`](crate::diag::Loader). Out: a [`World`] holding each robot's kinematic
//! chain (from its URDF), the hand attached at the flange, fixed and removable bodies
//! as parry3d shapes, and the labelled collision check PRMwO needs: "at this
//! configuration, is the robot blocked by something fixed, and which removable
//! objects does it touch?". Geometry code never sees spans; errors name ids and the
//! CLI maps them back to declarations.

mod analytic;
mod analytic7;
mod axis_reach;
mod ball_pack;
mod build;
mod chain;
mod check;
mod clear;
mod drawing;
mod error;
mod escape;
mod fingers;
mod grasps;
mod half_turn;
mod hull;
mod ik;
mod labels;
mod load;
mod lower_bound;
mod narrow;
mod pair_grid;
mod proximity;
mod robot;
mod scene;
mod segment;
pub(crate) use segment::{sample as segment_sample, steps as segment_steps};
mod self_pairs;
mod shapes;
mod srdf;
mod sweep;
#[cfg(test)]
pub(crate) mod test_arms;
mod urdf;

pub use axis_reach::{AxisReach, BodiesFarthest, Farthest, ReachScratch};
pub use build::{build, load_kinematics, overlaps, target_collides, RobotKinematics, WorldOptions};
pub use check::CheckCtx;
pub use drawing::{Drawable, DrawnBody, DrawnShape};
pub use error::WorldError;
pub use grasps::{
    report, why_ungraspable, ApproachDeviation, GraspReport, ObjectReach, RobotReach, APPROACH_ANGLE_TOLERANCE,
    APPROACH_LATERAL_TOLERANCE, APPROACH_OVERSHOOT_TOLERANCE,
};
pub use labels::{Blocker, Check, ObjectSet};
pub use lower_bound::{distance_at_least, distance_at_least_from, GjkStart, LOWER_BOUND_TOLERANCE};
pub use proximity::{aabb_gap, in_closed_form, shape_distance, turned_boxes_gap, RobotAt};
pub use shapes::{MeshMode, CONTACT_TOLERANCE};
pub use sweep::{posture_of, BodyInfo, HeldPart, JointReach, PosedShape, StaticOwner, StaticShape};
pub use urdf::DEFAULT_VELOCITY;

use std::ops::{Deref, DerefMut};

use serde::Serialize;

use crate::resolve::{ObjectId, Pose, RobotId, Scenario};

/// A scenario made queryable: kinematic chains, shapes and the labelled check.
/// Built once by [`build`]; immutable, `Send + Sync`, shared by planner threads.
pub struct World {
    scenario: Scenario,
    robots: Vec<robot::RobotModel>,
    /// Per object: its parts in the body frame, for carrying it.
    object_parts: Vec<Vec<shapes::Placed>>,
}

impl std::fmt::Debug for World {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let robots: Vec<(&str, usize, usize)> =
            self.robots.iter().map(|m| (m.name.as_str(), m.chain.dof(), m.shapes.len())).collect();
        f.debug_struct("World")
            .field("robots (name, dof, shapes)", &robots)
            .field("fixed", &self.scenario.fixed.len())
            .field("objects", &self.scenario.objects.len())
            .finish()
    }
}

impl World {
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }
    /// Number of actuated joints.
    pub fn dof(&self, r: RobotId) -> usize {
        self.robots[r.index()].chain.dof()
    }
    /// Actuated joint names, in configuration order.
    pub fn joint_names(&self, r: RobotId) -> &[String] {
        &self.robots[r.index()].chain.joint_names
    }
    /// (lower, upper) per actuated joint. Continuous joints get (-2π, 2π); revolute and
    /// prismatic joints must declare finite limits in the URDF (checked at load).
    pub fn limits(&self, r: RobotId) -> &[(f64, f64)] {
        &self.robots[r.index()].chain.limits
    }
    /// Velocity limit per actuated joint (rad/s or m/s), from the URDF's `<limit
    /// velocity>`; [`DEFAULT_VELOCITY`] where the URDF gives none or zero.
    pub fn velocity_limits(&self, r: RobotId) -> &[f64] {
        &self.robots[r.index()].chain.velocities
    }
    /// Acceleration limit per actuated joint (rad/s² or m/s²): the URDF's own
    /// (`drake:acceleration`) where it states one, else the planner's `acceleration`.
    pub fn acceleration_limits(&self, r: RobotId) -> Vec<f64> {
        let fallback = self.scenario.planner.acceleration;
        self.robots[r.index()].chain.accelerations.iter().map(|a| a.unwrap_or(fallback)).collect()
    }
    pub fn home(&self, r: RobotId) -> &Config {
        &self.robots[r.index()].home
    }
    /// The `drop` configuration, or `home` when none is given.
    pub fn drop_config(&self, r: RobotId) -> &Config {
        &self.robots[r.index()].drop
    }
    /// Name of the link the hand is attached to.
    pub fn flange_link(&self, r: RobotId) -> &str {
        let c = &self.robots[r.index()].chain;
        &c.links[c.flange].name
    }
    /// Flange pose in the world frame.
    ///
    /// # Panics
    /// If `q.len()` is not [`World::dof`] (as every method taking a configuration):
    /// configurations come from the world itself (home, limits, IK), so a wrong length
    /// is a bug in the caller, never something a scenario or URDF can cause.
    pub fn fk_flange(&self, r: RobotId, q: &[f64]) -> Pose {
        let m = self.robot_for(r, q);
        m.pose_world_base * m.chain.fk_flange(q)
    }
    /// TCP pose in the world frame (the flange when the robot has no hand).
    /// Panics if `q.len()` is not [`World::dof`].
    pub fn fk_tcp(&self, r: RobotId, q: &[f64]) -> Pose {
        let m = self.robot_for(r, q);
        m.pose_world_base * m.chain.fk_flange(q) * m.pose_flange_tcp
    }
    /// World poses of every link of the robot (URDF link names), for drawing and tests.
    /// Panics if `q.len()` is not [`World::dof`].
    pub fn fk_links(&self, r: RobotId, q: &[f64]) -> Vec<(String, Pose)> {
        let m = self.robot_for(r, q);
        let mut out = vec![Pose::identity(); m.chain.links.len()];
        m.chain.fk_into(q, &mut out);
        m.chain.links.iter().zip(out).map(|(l, p)| (l.name.clone(), m.pose_world_base * p)).collect()
    }
    /// The link pairs checked for self-collision (after removing adjacent, rigidly
    /// joined, allowed, and — when sampling — always-colliding pairs).
    pub fn self_collision_pairs(&self, r: RobotId) -> Vec<(&str, &str)> {
        let m = &self.robots[r.index()];
        m.self_pairs.iter().map(|&(a, b)| (m.bodies[a].name.as_str(), m.bodies[b].name.as_str())).collect()
    }
    /// Up to `max_solutions` distinct in-limit configurations putting the TCP at
    /// `pose_world_tcp`, deterministic for a given `seed`. For an arm with a closed
    /// form (a 6R spherical wrist, or three parallel axes) every posture at its turn
    /// nearest home comes first, nearest home first, and `seed` is not used. Takes no configuration, so
    /// it cannot panic on one; a non-finite pose simply has no solution.
    pub fn ik(&self, r: RobotId, pose_world_tcp: &Pose, seed: u64, max_solutions: usize) -> Vec<Config> {
        ik::solve(&self.robots[r.index()], pose_world_tcp, seed, max_solutions)
    }
    /// The robot's model, after checking that `q` fits it (see [`World::fk_flange`]).
    fn robot_for(&self, r: RobotId, q: &[f64]) -> &robot::RobotModel {
        let m = &self.robots[r.index()];
        robot::assert_dof(m, q);
        m
    }
    /// The paper's `selectGrasps` for one robot and object.
    pub fn select_grasps(&self, r: RobotId, o: ObjectId) -> Vec<GraspConfig> {
        grasps::select(self, r, o)
    }
    /// How the straight joint-space move `a`..`b` strays from `grasp`'s straight-in
    /// approach, sampled as [`World::check_motion`] samples it at `resolution`.
    /// Panics if `a` or `b` is not [`World::dof`] long.
    pub fn approach_deviation(
        &self,
        r: RobotId,
        grasp: &crate::resolve::Grasp,
        a: &[f64],
        b: &[f64],
        resolution: f64,
    ) -> ApproachDeviation {
        let m = &self.robots[r.index()];
        robot::assert_dof(m, a);
        robot::assert_dof(m, b);
        grasps::approach_deviation(self, r, grasp, a, b, resolution)
    }
    /// The object as carried after grasping it by its grasp `grasp` at `q_grasp`, the
    /// fingers closed as that grasp says. Panics if `q_grasp.len()` is not [`World::dof`].
    pub fn held(&self, r: RobotId, o: ObjectId, grasp: usize, q_grasp: &[f64]) -> Held {
        let pose_world_flange = self.fk_flange(r, q_grasp);
        let pose_world_object = self.scenario.object(o).body.pose_world_body;
        let posture = self.posture_of(r, o, grasp);
        Held { object: o, pose_flange_object: pose_world_flange.inverse() * pose_world_object, posture }
    }
    /// The fingers' posture holding `o` by its grasp `grasp` (open for an unknown grasp).
    pub fn posture_of(&self, r: RobotId, o: ObjectId, grasp: usize) -> usize {
        let m = &self.robots[r.index()];
        m.grasp_posture.get(o.index()).and_then(|g| g.get(grasp)).copied().unwrap_or(OPEN_POSTURE)
    }
    /// The postures the fingers pass through between open and `posture` (from open on;
    /// none for open): checked at the instant they close on an object and open again.
    pub fn closing(&self, r: RobotId, posture: usize) -> &[usize] {
        self.robots[r.index()].closing.get(posture).map_or(&[], Vec::as_slice)
    }
    /// The gripper's finger joints (the arm URDF's, then the hand's), for a controller.
    pub fn finger_names(&self, r: RobotId) -> Vec<&str> {
        self.robots[r.index()].fingers.iter().map(|f| f.name.as_str()).collect()
    }
    /// A finger joint's value as written in a scenario: an angle for one that turns, a
    /// length for one that slides.
    pub fn finger_value_text(&self, r: RobotId, finger: usize, value: f64) -> String {
        let turns = self.robots[r.index()].fingers.get(finger).is_some_and(|f| f.turns);
        if turns {
            format!("{:.1}deg", value.to_degrees())
        } else {
            format!("{:.1}mm", value * 1e3)
        }
    }
    /// The finger joints' values in a posture (0, open: the hand empty; a [`Held`]'s
    /// while carrying).
    pub fn finger_values(&self, r: RobotId, posture: usize) -> &[f64] {
        let m = &self.robots[r.index()];
        m.postures.get(posture).or(m.postures.first()).map_or(&[], |p| &p.values)
    }
    /// The labelled check of one configuration. Panics if `q.len()` is not
    /// [`World::dof`]; a value outside the limits is `Blocked(JointLimit)`, not a panic.
    pub fn check(&self, r: RobotId, q: &[f64], ctx: &CheckCtx) -> Check {
        check::check(self, r, q, ctx)
    }
    /// Whether [`World::check`] would say `Touches` with no label, sooner when it would not.
    pub fn touches_nothing(&self, r: RobotId, q: &[f64], ctx: &CheckCtx) -> bool {
        clear::touches_nothing(self, r, q, ctx)
    }
    /// Checks the straight joint-space segment `a`..`b`, no joint moving more than
    /// `step` between checked configurations, both ends included: the union of the
    /// labels, or the first block. Panics if `a` or `b` is not [`World::dof`] long.
    pub fn check_segment(&self, r: RobotId, a: &[f64], b: &[f64], step: f64, ctx: &CheckCtx) -> Check {
        segment::check_segment(self, r, a, b, step, ctx)
    }
    /// [`World::check_segment`] without the ends flagged in `known` (`a`, `b`), whose
    /// checks in `ctx` the caller has: joined with their labels (neither blocked), the
    /// same answer as `check_segment`.
    pub fn check_segment_known(
        &self,
        r: RobotId,
        ends: (&[f64], &[f64]),
        step: f64,
        known: (bool, bool),
        ctx: &CheckCtx,
    ) -> Check {
        segment::check_segment_known(self, r, ends, step, known, ctx)
    }
    /// What the carried object (`ctx.held`) adds to [`World::check_segment`] on the same
    /// samples: the robot's own bodies are not checked. The full label is this one's
    /// union with the empty-hand label of the segment, less the carried object.
    pub fn check_segment_held(&self, r: RobotId, a: &[f64], b: &[f64], step: f64, ctx: &CheckCtx) -> Check {
        segment::check_segment_held(self, r, a, b, step, ctx)
    }
    /// The labelled checks of samples `indices` of `ends` cut into `n` steps (those of
    /// [`World::check_segment`] at a step giving `n`), in turn, up to the first blocked:
    /// checked level by level, several segments of a path find a block on any of them
    /// early, and together they label each segment as `check_segment` does.
    pub fn check_samples(
        &self,
        r: RobotId,
        ends: (&[f64], &[f64]),
        n: usize,
        indices: &mut dyn Iterator<Item = usize>,
        ctx: &CheckCtx,
    ) -> Check {
        segment::label_samples(self, r, ends, n, indices, ctx, true)
    }
    /// [`World::check_samples`] of the same samples in two contexts, each up to its own
    /// first block: the hand empty (the carried object in its place, `carry.absent` less
    /// it absent) and `carry`. Where the fingers hold the object open, as they are in the
    /// empty hand, each sample is placed and the robot's own bodies checked once for
    /// both. Configurations are counted in `carry`.
    pub fn check_samples_twin(
        &self,
        r: RobotId,
        ends: (&[f64], &[f64]),
        n: usize,
        indices: &[usize],
        carry: &CheckCtx,
    ) -> (Check, Check) {
        segment::label_samples_twin(self, r, ends, n, indices, carry)
    }
    /// [`World::check_motion_rest`] of the same segment with the hand empty and in
    /// `carry`, as [`World::check_samples_twin`] takes them.
    pub fn check_motion_rest_twin(
        &self,
        r: RobotId,
        a: &[f64],
        b: &[f64],
        resolution: f64,
        carry: &CheckCtx,
    ) -> (Check, Check) {
        segment::check_motion_rest_twin(self, r, (a, b), (resolution, CERTIFY_PARTS), carry)
    }
    /// The check that certifies a motion, for the verifier and the planner alike: the
    /// planner's steps of at most `resolution`, each cut into [`CERTIFY_PARTS`], so every
    /// sample of the coarse check is among them. Panics if `a` or `b` is not
    /// [`World::dof`] long.
    pub fn check_motion(&self, r: RobotId, a: &[f64], b: &[f64], resolution: f64, ctx: &CheckCtx) -> Check {
        segment::check_motion(self, r, a, b, resolution, CERTIFY_PARTS, ctx)
    }
    /// The samples of [`World::check_motion`] that [`World::check_segment`] at the same
    /// `resolution` does not take, coarse to fine: once that coarse check of the segment
    /// (same context) found labels `l` and no block, `l` joined with these labels is
    /// `check_motion`'s answer (a block may be found at another sample than its first).
    pub fn check_motion_rest(&self, r: RobotId, a: &[f64], b: &[f64], resolution: f64, ctx: &CheckCtx) -> Check {
        segment::check_motion_rest(self, r, a, b, (resolution, CERTIFY_PARTS), ctx)
    }
}

/// The fingers' posture with the hand empty: open.
pub const OPEN_POSTURE: usize = 0;

/// Samples per planner step when a motion is certified (the verifier's "quarter of the
/// resolution").
pub const CERTIFY_PARTS: usize = 4;

/// A robot configuration: one value per actuated joint, in chain order (radians or metres).
#[derive(Clone, Debug, PartialEq, Serialize, Default)]
#[serde(transparent)]
pub struct Config(pub Vec<f64>);

impl Deref for Config {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.0
    }
}
impl DerefMut for Config {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.0
    }
}
impl From<Vec<f64>> for Config {
    fn from(v: Vec<f64>) -> Config {
        Config(v)
    }
}

/// A sequence of configurations, each segment to be moved along in a straight joint-space line.
#[derive(Clone, Debug, PartialEq, Serialize, Default)]
#[serde(transparent)]
pub struct JointPath(pub Vec<Config>);

/// An object carried by the hand: it moves rigidly with the flange.
#[derive(Clone, Debug, PartialEq)]
pub struct Held {
    pub object: ObjectId,
    /// The object's pose in the flange frame, fixed at the moment of grasping.
    pub pose_flange_object: Pose,
    /// The fingers' posture while holding it (an index into the robot's postures; 0 is open).
    pub posture: usize,
}

/// A reachable grasp of an object by one robot (the paper's `selectGrasps`).
#[derive(Clone, Debug, PartialEq)]
pub struct GraspConfig {
    /// Index into the object's `grasps`.
    pub grasp: usize,
    /// Arm configuration with the TCP at the grasp pose.
    pub q_grasp: Config,
    /// Arm configuration at the approach stand-off, from which the hand moves straight in.
    pub q_pregrasp: Config,
}
