//! The labelled collision check: at a configuration, is the robot blocked by
//! something fixed, and which removable objects does it touch?
//!
//! Broad phase: the AABB of each moving body against a parry BVH of everything
//! static for that robot (fixed bodies, removable objects, other robots at home).
//! Narrow phase ([`super::narrow`]): overlaps shallower than the contact tolerance are
//! not collisions, so a can standing on the table does not touch it; a ball against a
//! fixed box is decided by its centre's distance (`ball_meets_box`), a spherized body's
//! balls all at once (`ball_pack`). The segment checks are in [`super::segment`].

use std::cell::{Cell, RefCell};

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Pose as PPose, Vector as PVec};

use super::narrow::{collide_moving, no_start};
use super::pair_grid::{body_distance, Measure};
use super::robot::{assert_dof, RobotModel};
use super::scene::Owner;
use super::shapes::{aabb_of, ball_meets_box, place, to_ppose, Boxed, Placed};
use super::OPEN_POSTURE as OPEN;
use super::{Blocker, Check, Held, ObjectSet, World};
use crate::resolve::{ObjectId, RobotId};

/// Joint values this far outside a limit still count as inside (rounding of written degrees).
pub(crate) const LIMIT_SLACK: f64 = 1e-9;

/// What one query holds constant across its checks.
#[derive(Debug, Default, Clone)]
pub struct CheckCtx {
    /// Objects treated as not there (removed, or the one being grasped on the approach).
    pub absent: ObjectSet,
    /// The object carried in the hand, if any.
    pub held: Option<Held>,
    /// Incremented once per configuration checked.
    pub checks: Cell<u64>,
    /// Self-collision pair tests the joint-space grids answered (the exact test skipped).
    pub grid_apart: Cell<u64>,
    /// Bodies whose shapes were placed, over all checks (every moving one, without the
    /// fast check).
    pub bodies_placed: Cell<u64>,
    /// Contacts with a box a ball inside a hull proved (the exact test skipped).
    pub inner_proved: Cell<u64>,
}

impl CheckCtx {
    pub fn new() -> Self {
        CheckCtx::default()
    }
    pub fn with_absent(absent: ObjectSet) -> Self {
        CheckCtx { absent, ..CheckCtx::default() }
    }
    pub fn with_held(absent: ObjectSet, held: Held) -> Self {
        CheckCtx { absent, held: Some(held), ..CheckCtx::default() }
    }
    /// Configurations checked so far.
    pub fn count(&self) -> u64 {
        self.checks.get()
    }
    /// Adds `other`'s counts to this one's.
    pub(super) fn add_counts(&self, other: &CheckCtx) {
        for (to, from) in [
            (&self.checks, &other.checks),
            (&self.grid_apart, &other.grid_apart),
            (&self.bodies_placed, &other.bodies_placed),
            (&self.inner_proved, &other.inner_proved),
        ] {
            to.set(to.get() + from.get());
        }
    }
    /// Whether object `o` is left out of the check: absent, or the one carried.
    pub(super) fn not_there(&self, o: ObjectId) -> bool {
        self.absent.contains(o) || self.held.as_ref().is_some_and(|h| h.object == o)
    }
}

/// Per-thread buffers, so a check allocates nothing once warm.
#[derive(Default)]
pub(super) struct Scratch {
    links: Vec<Isometry3<f64>>,
    link_pose: Vec<PPose>,
    shape_pose: Vec<PPose>,
    shape_aabb: Vec<Aabb>,
    pub(super) body_aabb: Vec<Aabb>,
    /// Per body: its shapes' entries are this check's (see [`pose_robot`]).
    body_posed: Vec<bool>,
    /// The fingers' posture of this check.
    posture: usize,
    held_pose: Vec<PPose>,
    held_aabb: Vec<Aabb>,
    /// The scene's leaves near one body or carried part (see `Scene::overlapping`).
    leaves: Vec<u32>,
    /// The self-collision grids' measurements (see `pair_grid`).
    grid: Measure,
    /// Per robot shape and scene entry (`shape * entries + entry`), the direction that last
    /// separated them (see [`collide_from`]); zero when none yet. Left from whatever robot
    /// or world the thread checked before, it is only a start: verdicts do not depend on it.
    separating: Vec<PVec>,
    /// The same per pair of the robot's own shapes (`first * shapes + second`, in the
    /// order [`bodies_collide`] tests them).
    self_separating: Vec<PVec>,
    /// Two bodies' balls placed (see [`bodies_collide`]).
    packed: [super::ball_pack::PlacedBalls; 2],
    /// The moving body and scene entry of the last contact this check's scan found (a
    /// fixed body's ends the scan), if any.
    pub(super) hit: Option<(usize, u32)>,
    /// The pairs [`super::clear`] tries first (see there).
    pub(super) recent: super::clear::Recent,
}

thread_local! {
    pub(super) static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The world box of a moving shape. A mesh hull's own box visits every vertex (half of a
/// mesh robot's check went there); its local box, turned, is looser but costs a cuboid's.
/// Only a broad-phase filter: the exact tests after it decide, so verdicts do not change.
#[inline]
pub(crate) fn moving_aabb(p: &Placed, pose: &PPose) -> Aabb {
    match p.boxed {
        Boxed::Hull => p.obb.world_aabb(pose),
        // parry's `Ball::aabb`, without asking the shape what it is.
        Boxed::Ball(r) => Aabb::new(pose.translation + PVec::splat(-r), pose.translation + PVec::splat(r)),
        Boxed::Other => aabb_of(&*p.shape.0, pose),
    }
}

/// The robot's links at `q` and a box around each body (its frame box turned, world
/// frame), the fingers in `posture`. A body's shapes are placed only when a test needs
/// them ([`pose_body`]): most bodies of most checks are near nothing, and their boxes
/// (one per body, not one per shape) say so. The boxes are broad-phase filters only:
/// every verdict still comes from the shapes' own boxes and the exact tests.
pub(super) fn pose_robot(m: &RobotModel, q: &[f64], posture: usize, s: &mut Scratch) {
    start_posing(m, q, posture, s);
    s.body_aabb.clear();
    if !m.fast_check {
        for (bi, b) in m.bodies.iter().enumerate() {
            pose_body(m, s, bi);
            s.body_aabb.push(body_box(s, b));
        }
        return;
    }
    for (b, frame) in m.bodies.iter().zip(&m.body_frames) {
        s.body_aabb.push(frame.world_aabb(&s.link_pose[b.link]));
    }
}

/// The links at `q`, the fingers in `posture`, and no body's shapes placed yet.
pub(super) fn start_posing(m: &RobotModel, q: &[f64], posture: usize, s: &mut Scratch) {
    start_posing_upto(m, q, m.chain.links.len(), posture, s);
}

/// [`start_posing`] with the first `links` links placed only (a link's parent comes before
/// it): enough for the bodies on them; the other links' poses are left as they were.
pub(super) fn start_posing_upto(m: &RobotModel, q: &[f64], links: usize, posture: usize, s: &mut Scratch) {
    pose_links(m, q, links, s);
    s.posture = posture;
    s.shape_pose.resize(m.shapes.len(), PPose::IDENTITY);
    s.shape_aabb.resize(m.shapes.len(), Aabb::new_invalid());
    s.body_posed.clear();
    s.body_posed.resize(m.bodies.len(), false);
}

/// Places the shapes of body `bi` for this check, once.
#[inline]
pub(super) fn pose_body(m: &RobotModel, s: &mut Scratch, bi: usize) {
    if std::mem::replace(&mut s.body_posed[bi], true) {
        return;
    }
    let b = &m.bodies[bi];
    for si in b.shapes.clone() {
        let pose = place(&s.link_pose[b.link], m.shape_pose(si, s.posture), m.shapes[si].unturned);
        s.shape_aabb[si] = moving_aabb(&m.shapes[si].placed, &pose);
        s.shape_pose[si] = pose;
    }
}

/// World poses of the robot's first `n` links at `q`.
fn pose_links(m: &RobotModel, q: &[f64], n: usize, s: &mut Scratch) {
    let all = m.chain.links.len();
    s.links.resize(all, Isometry3::identity());
    m.chain.fk_prefix(&m.pose_world_base, q, n.min(all), &mut s.links);
    s.link_pose.resize(all, PPose::IDENTITY);
    for (to, from) in s.link_pose.iter_mut().zip(&s.links).take(n) {
        *to = to_ppose(from);
    }
}

pub(super) fn body_box(s: &Scratch, b: &super::robot::RBody) -> Aabb {
    let mut aabb = s.shape_aabb[b.shapes.start];
    for a in &s.shape_aabb[b.shapes.clone()] {
        aabb.merge(a);
    }
    aabb
}

pub(crate) fn check(w: &World, r: RobotId, q: &[f64], ctx: &CheckCtx) -> Check {
    check_parts(w, r, q, ctx, true)
}

pub(super) fn check_parts(w: &World, r: RobotId, q: &[f64], ctx: &CheckCtx, robot_part: bool) -> Check {
    let m = &w.robots[r.index()];
    if let Some(blocked) = count_within_limits(m, q, ctx) {
        return blocked;
    }
    SCRATCH.with(|cell| {
        let mut s = cell.borrow_mut();
        let posture = ctx.held.as_ref().map_or(OPEN, |h| h.posture);
        pose_robot(m, q, posture, &mut s);
        let check = check_posed(w, m, ctx, &mut s, robot_part, (q, posture));
        count_placed(ctx, &s);
        check
    })
}

/// The checks of `q` with the hand empty (in `empty`) and carrying (in `carry`, fingers
/// open as in the empty hand) on one placing of the robot: its own bodies meet the same
/// things in both, less the carried object and `carry.absent`, so they are checked once
/// (in `empty`, the carried object in place) and only the carried object besides. Each
/// answer is the one [`check`] gives in its context; the carrying one is blocked with the
/// empty hand's block.
pub(super) fn check_twin(w: &World, r: RobotId, q: &[f64], empty: &CheckCtx, carry: &CheckCtx) -> (Check, Check) {
    let m = &w.robots[r.index()];
    if let Some(blocked) = count_within_limits(m, q, empty) {
        return (blocked.clone(), blocked);
    }
    SCRATCH.with(|cell| {
        let mut s = cell.borrow_mut();
        pose_robot(m, q, OPEN, &mut s);
        let own = check_posed(w, m, empty, &mut s, true, (q, OPEN));
        let carrying = match &own {
            Check::Touches(l) => match check_posed(w, m, carry, &mut s, false, (q, OPEN)) {
                Check::Touches(mut h) => {
                    let mut own = l.clone();
                    own.subtract(&carry.absent);
                    if let Some(held) = &carry.held {
                        own.remove(held.object);
                    }
                    h.union_with(&own);
                    Check::Touches(h)
                }
                blocked => blocked,
            },
            blocked => blocked.clone(),
        };
        count_placed(empty, &s);
        (own, carrying)
    })
}

/// Counts one configuration checked; the block when a joint is outside its limits.
pub(super) fn count_within_limits(m: &RobotModel, q: &[f64], ctx: &CheckCtx) -> Option<Check> {
    ctx.checks.set(ctx.checks.get() + 1);
    assert_dof(m, q);
    for ((v, (lo, hi)), name) in q.iter().zip(&m.chain.limits).zip(&m.chain.joint_names) {
        if !(*v >= lo - LIMIT_SLACK && *v <= hi + LIMIT_SLACK) {
            return Some(Check::Blocked(Blocker::JointLimit { joint: name.clone(), value: *v }));
        }
    }
    None
}

pub(super) fn count_placed(ctx: &CheckCtx, s: &Scratch) {
    let placed = s.body_posed.iter().filter(|p| **p).count() as u64;
    ctx.bodies_placed.set(ctx.bodies_placed.get() + placed);
}

/// `robot_part: false` leaves out the robot's own bodies (against the scene and each
/// other) and checks only the carried object: what carrying adds to a configuration
/// whose empty-hand check is already known.
pub(super) fn check_posed(
    w: &World,
    m: &RobotModel,
    ctx: &CheckCtx,
    s: &mut Scratch,
    robot_part: bool,
    (q, posture): (&[f64], usize),
) -> Check {
    let mut labels = ObjectSet::new();
    s.hit = None;
    if robot_part {
        // Robot bodies against the static scene.
        size_separating(m, s);
        for (bi, b) in m.bodies.iter().enumerate() {
            if !b.moving {
                continue;
            }
            m.scene.overlapping(&s.body_aabb[bi], &mut s.leaves);
            for k in 0..s.leaves.len() {
                let leaf = s.leaves[k];
                let e = &m.scene.entries[leaf as usize];
                if let Owner::Object(o) = e.owner {
                    if ctx.not_there(o) || labels.contains(o) {
                        continue;
                    }
                }
                if body_meets_entry(m, s, bi, leaf, &ctx.inner_proved) {
                    s.hit = Some((bi, leaf));
                    match e.owner {
                        Owner::Fixed(body) => return Check::Blocked(Blocker::Fixed { body, link: b.name.clone() }),
                        Owner::Robot(other, ob) => {
                            return Check::Blocked(Blocker::Robot {
                                other,
                                link: b.name.clone(),
                                other_link: w.robots[other.index()].bodies[ob].name.clone(),
                            })
                        }
                        Owner::Object(o) => labels.insert(o),
                    }
                }
            }
        }
        // Self-collision.
        for (&(a, b), grid) in m.self_pairs.iter().zip(&m.self_grids) {
            if !s.body_aabb[a].intersects(&s.body_aabb[b]) {
                continue;
            }
            if let Some(g) = grid.as_ref().filter(|g| g.holds_for(posture)) {
                let grid = &mut s.grid;
                let apart = g.apart(q, |centre, enough| {
                    grid.q.clear();
                    grid.q.extend_from_slice(q);
                    for &(i, v) in centre {
                        grid.q[i] = v;
                    }
                    body_distance(m, a, b, enough, grid)
                });
                if apart {
                    ctx.grid_apart.set(ctx.grid_apart.get() + 1);
                    continue;
                }
            }
            if bodies_collide(m, s, a, b) {
                return Check::Blocked(Blocker::SelfCollision {
                    link_a: m.bodies[a].name.clone(),
                    link_b: m.bodies[b].name.clone(),
                });
            }
        }
    }
    // The carried object.
    if let Some(h) = &ctx.held {
        let parts = &w.object_parts[h.object.index()];
        let flange = s.link_pose[m.chain.flange] * to_ppose(&h.pose_flange_object);
        s.held_pose.clear();
        s.held_aabb.clear();
        for p in parts {
            let pose = flange * p.pose;
            s.held_aabb.push(moving_aabb(p, &pose));
            s.held_pose.push(pose);
        }
        for (pi, p) in parts.iter().enumerate() {
            m.scene.overlapping(&s.held_aabb[pi], &mut s.leaves);
            for k in 0..s.leaves.len() {
                let leaf = s.leaves[k];
                let e = &m.scene.entries[leaf as usize];
                if let Owner::Object(o) = e.owner {
                    if ctx.not_there(o) || labels.contains(o) {
                        continue;
                    }
                }
                let (mover, other) = ((&s.held_pose[pi], p, m.fast_check), (&e.pose, &*e.shape.0, &e.obb));
                if !collide_moving(mover, other, &mut no_start(), &ctx.inner_proved) {
                    continue;
                }
                match e.owner {
                    Owner::Fixed(body) => return Check::Blocked(Blocker::HeldFixed { object: h.object, body }),
                    Owner::Robot(other, ob) => {
                        return Check::Blocked(Blocker::HeldRobot {
                            object: h.object,
                            other,
                            other_link: w.robots[other.index()].bodies[ob].name.clone(),
                        })
                    }
                    Owner::Object(o) => labels.insert(o),
                }
            }
            for (bi, b) in m.bodies.iter().enumerate() {
                if b.holds || !s.body_aabb[bi].intersects(&s.held_aabb[pi]) {
                    continue;
                }
                pose_body(m, s, bi);
                let hit = b.shapes.clone().any(|si| {
                    let other = &m.shapes[si].placed;
                    let (mover, other) =
                        ((&s.held_pose[pi], p, m.fast_check), (&s.shape_pose[si], &*other.shape.0, &other.obb));
                    collide_moving(mover, other, &mut no_start(), &ctx.inner_proved)
                });
                if hit {
                    return Check::Blocked(Blocker::HeldSelf { object: h.object, link: b.name.clone() });
                }
            }
        }
    }
    Check::Touches(labels)
}

/// Sizes the scratch's separating directions for `m`'s shapes and scene entries.
pub(super) fn size_separating(m: &RobotModel, s: &mut Scratch) {
    let n = m.shapes.len() * m.scene.entries.len();
    if s.separating.len() != n {
        s.separating.clear();
        s.separating.resize(n, PVec::ZERO);
    }
}

/// Whether moving body `bi`, posed in `s` (see [`pose_robot`]), meets scene entry
/// `leaf` deeper than the tolerance; `s.separating` sized by [`size_separating`].
pub(super) fn body_meets_entry(
    m: &RobotModel,
    s: &mut Scratch,
    bi: usize,
    leaf: u32,
    inner_proved: &Cell<u64>,
) -> bool {
    let b = &m.bodies[bi];
    let e = &m.scene.entries[leaf as usize];
    let entries = m.scene.entries.len();
    // A body of balls against a box: all its balls at once, unplaced.
    let pack = m.ball_packs[bi].as_ref().filter(|_| m.fast_check && e.obb.exact);
    let packed = pack.and_then(|p| p.meets_box(s.posture, &s.link_pose[b.link], &e.pose, e.obb.cuboid.half_extents));
    packed.unwrap_or_else(|| {
        pose_body(m, s, bi);
        b.shapes.clone().any(|si| {
            let placed = &m.shapes[si].placed;
            let ball = placed.eroded_ball.filter(|_| m.fast_check && e.obb.exact);
            s.shape_aabb[si].intersects(&e.aabb)
                && ball
                    .and_then(|r| ball_meets_box(s.shape_pose[si].translation, r, &e.pose, e.obb.cuboid.half_extents))
                    .unwrap_or_else(|| {
                        let dir = &mut s.separating[si * entries + leaf as usize];
                        let (mover, other) =
                            ((&s.shape_pose[si], placed, m.fast_check), (&e.pose, &*e.shape.0, &e.obb));
                        collide_moving(mover, other, dir, inner_proved)
                    })
        })
    })
}

pub(super) fn bodies_collide(m: &RobotModel, s: &mut Scratch, a: usize, b: usize) -> bool {
    // Two bodies of balls: every pair of their balls at once, unplaced.
    if let (Some(pa), Some(pb), true) = (&m.ball_packs[a], &m.ball_packs[b], m.fast_check) {
        let [wa, wb] = &mut s.packed;
        pa.place(s.posture, &s.link_pose[m.bodies[a].link], wa);
        pb.place(s.posture, &s.link_pose[m.bodies[b].link], wb);
        if let Some(meets) = pa.meets(wa, pb, wb) {
            return meets;
        }
    }
    pose_body(m, s, a);
    pose_body(m, s, b);
    let n = m.shapes.len();
    if s.self_separating.len() != n * n {
        s.self_separating.clear();
        s.self_separating.resize(n * n, PVec::ZERO);
    }
    // No balls tried: a robot's shapes are hulls against hulls (balls against balls, tried
    // on the UR5, cost more than they proved).
    let unseen = Cell::new(0);
    m.bodies[a].shapes.clone().any(|i| {
        m.bodies[b].shapes.clone().any(|j| {
            let (pa, pb) = (&m.shapes[i].placed, &m.shapes[j].placed);
            s.shape_aabb[i].intersects(&s.shape_aabb[j])
                && if pa.eroded.is_some() || pb.eroded.is_none() {
                    let dir = &mut s.self_separating[i * n + j];
                    collide_moving(
                        (&s.shape_pose[i], pa, false),
                        (&s.shape_pose[j], &*pb.shape.0, &pb.obb),
                        dir,
                        &unseen,
                    )
                } else {
                    let dir = &mut s.self_separating[j * n + i];
                    collide_moving(
                        (&s.shape_pose[j], pb, false),
                        (&s.shape_pose[i], &*pa.shape.0, &pa.obb),
                        dir,
                        &unseen,
                    )
                }
        })
    })
}

/// A one-line account of a block, for error messages.
pub(crate) fn describe(w: &World, r: RobotId, b: &Blocker) -> String {
    let scn = w.scenario();
    let _ = r;
    match b {
        Blocker::Fixed { body, link } => format!("link `{link}` hits fixed body `{}`", scn.fixed[body.index()].name),
        Blocker::HeldFixed { object, body } => format!(
            "carried object `{}` hits fixed body `{}`",
            scn.object(*object).body.name,
            scn.fixed[body.index()].name
        ),
        Blocker::Robot { other, link, other_link } => {
            format!("link `{link}` hits link `{other_link}` of robot `{}` (at its home)", scn.robot(*other).name)
        }
        Blocker::HeldRobot { object, other, other_link } => format!(
            "carried object `{}` hits link `{other_link}` of robot `{}`",
            scn.object(*object).body.name,
            scn.robot(*other).name
        ),
        Blocker::SelfCollision { link_a, link_b } => format!("links `{link_a}` and `{link_b}` collide"),
        Blocker::HeldSelf { object, link } => {
            format!("carried object `{}` hits link `{link}`", scn.object(*object).body.name)
        }
        Blocker::JointLimit { joint, value } => format!("joint `{joint}` = {value} is outside its limits"),
    }
}

#[cfg(test)]
#[path = "check_tests.rs"]
mod tests;
