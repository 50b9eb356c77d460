//! The labelled collision check: at a configuration, is the robot blocked by
//! something fixed, and which removable objects does it touch?
//!
//! Broad phase: the AABB of each moving body against a parry BVH of everything
//! static for that robot (fixed bodies, removable objects, other robots at home).
//! Narrow phase: overlaps shallower than [`CONTACT_TOLERANCE`] are not collisions,
//! so a can standing on the table does not touch it. A moving primitive (box,
//! cylinder, capsule, sphere) is eroded by the tolerance once at build time and
//! tested with one `intersection_test` (a box against a box by the fifteen-axis
//! separating test, `boxes_intersect`; a ball against a fixed box by its centre's
//! distance, `ball_meets_box`); a mesh hull is tested with GJK, then
//! `contact` measures the depth of pairs that intersect, unless GJK's last simplex or a
//! box shrunk by twice the tolerance already proves them that deep (no measure).

use std::cell::{Cell, RefCell};

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Pose as PPose, Vector as PVec};
use parry3d_f64::query;
use parry3d_f64::query::gjk::VoronoiSimplex;
use parry3d_f64::shape::{Cuboid, Shape};

use super::hull::Ball;
use super::pair_grid::{body_distance, Measure};
use super::robot::{assert_dof, RobotModel};
use super::scene::Owner;
use super::shapes::{aabb_of, ball_meets_box, boxes_intersect, place, to_ppose, Boxed, Obb, Placed, CONTACT_TOLERANCE};
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
    /// Whether object `o` is left out of the check: absent, or the one carried.
    pub(super) fn not_there(&self, o: ObjectId) -> bool {
        self.absent.contains(o) || self.held.as_ref().is_some_and(|h| h.object == o)
    }
}

/// True when the shapes overlap deeper than the tolerance.
#[cfg(test)]
fn collide(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> bool {
    collide_from(p1, s1, p2, s2, &mut no_start())
}

/// No separating direction known (see [`collide_from`]): GJK starts where parry's would.
#[inline]
fn no_start() -> PVec {
    PVec::ZERO
}

/// [`collide`], GJK started along `dir` (in `s1`'s frame) unless it is zero, and `dir`
/// left at the separating direction GJK ends with when the shapes are apart. A planner's
/// checks along a motion ask of each pair nearly the same question again, and the last
/// separating direction usually separates again at once. The verdict does not depend on
/// where GJK starts: apart means a separating plane was found; an overlap it finds is
/// proved deep by its simplex or measured by EPA, and one within GJK's tolerance of
/// touching, whichever GJK says of it, is not deeper than the contact tolerance.
#[inline]
fn collide_from(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, dir: &mut PVec) -> bool {
    let meet = match gjk_meet(p1, s1, p2, s2, dir) {
        Some(m) => m,
        None => match query::intersection_test(p1, s1, p2, s2) {
            Ok(i) if !i.intersecting => Meet::Apart,
            _ => Meet::Overlap,
        },
    };
    match meet {
        Meet::Apart => false,
        Meet::Deep => true,
        Meet::Overlap if surely_deeper(p1, s1, p2, s2) => true,
        Meet::Overlap => match query::contact(p1, s1, p2, s2, 0.0) {
            Ok(Some(c)) if c.dist < -CONTACT_TOLERANCE => true,
            // EPA says shallower than the tolerance: proved when moving the second shape
            // that far along EPA's normal parts them. EPA can fall short (a hull 2.4 mm
            // into a thin box, read as 0.7 mm): unproved is a contact.
            Ok(Some(c)) => !parted_by(p1, s1, p2, s2, c.normal1 * CONTACT_TOLERANCE),
            Ok(None) => false,
            // No depth query for this pair: trust the intersection test.
            Err(_) => true,
        },
    }
}

/// Whether the shapes are apart once the second is moved by `shift`: then no more than
/// `|shift|` separates them where they stand.
fn parted_by(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, shift: PVec) -> bool {
    let moved = PPose::from_parts(p2.translation + shift, p2.rotation);
    query::intersection_test(p1, s1, &moved, s2).is_ok_and(|i| !i.intersecting)
}

/// What an intersection test found.
enum Meet {
    Apart,
    /// Overlapping by more than the contact tolerance.
    Deep,
    /// Overlapping, by how much unknown.
    Overlap,
}

/// parry's own intersection test of two convex shapes it tests with GJK (neither a ball,
/// not two boxes, no triangle: the pairs its dispatcher sends there), keeping GJK's last
/// simplex: `None` for other pairs. Four points of the shapes' Minkowski difference
/// enclosing the origin span a tetrahedron inside it; when the origin lies [`DEEP`]
/// inside each of its faces, no move shorter than that separates the shapes, and the
/// overlap is deeper than the tolerance without EPA (most overlaps of a mesh arm's
/// self-collision samples are centimetres deep).
fn gjk_meet(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, dir: &mut PVec) -> Option<Meet> {
    let other = |s: &dyn Shape| s.as_ball().is_some() || s.as_triangle().is_some();
    if other(s1) || other(s2) || (s1.as_cuboid().is_some() && s2.as_cuboid().is_some()) {
        return None;
    }
    let (g1, g2) = (s1.as_support_map()?, s2.as_support_map()?);
    let mut simplex = VoronoiSimplex::new();
    let pos12 = p1.inv_mul(p2);
    let start = (*dir != PVec::ZERO).then_some(*dir);
    let (hit, apart) =
        query::details::intersection_test_support_map_support_map_with_params(&pos12, g1, g2, &mut simplex, start);
    if !hit {
        *dir = apart;
    }
    Some(match hit {
        false => Meet::Apart,
        true if origin_deep_in(&simplex, DEEP) => Meet::Deep,
        true => Meet::Overlap,
    })
}

/// Whether `simplex` is a tetrahedron with the origin at least `depth` inside each face.
fn origin_deep_in(simplex: &VoronoiSimplex, depth: f64) -> bool {
    if simplex.dimension() != 3 {
        return false;
    }
    let p: [PVec; 4] = std::array::from_fn(|i| simplex.point(i).point);
    [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)].into_iter().all(|(i, j, k, l)| {
        let n = (p[j] - p[i]).cross(p[k] - p[i]);
        let len = n.length();
        // The face's normal turned away from the fourth point; the origin's depth
        // behind the face is the plane's offset along it.
        let side = n.dot(p[l] - p[i]);
        len > 0.0 && side != 0.0 && -side.signum() * n.dot(p[i]) / len >= depth
    })
}

/// Twice [`CONTACT_TOLERANCE`]: how far inside a box [`surely_deeper`] looks.
const DEEP: f64 = 2.0 * CONTACT_TOLERANCE;

/// Whether two shapes overlap deeper than the tolerance, where one intersection test can
/// prove it: one is a box, the other convex and meeting the box shrunk by [`DEEP`]. A
/// point that deep in the box stays in it however the two are moved apart by less than
/// that, so their penetration depth is at least [`DEEP`]. `false` when not proved (the
/// caller then measures the depth); most planner samples in a cage of bars are deep in one,
/// and this spares EPA.
fn surely_deeper(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> bool {
    let shrunk = |s: &dyn Shape| {
        let c = s.as_cuboid()?;
        (c.half_extents.min_element() > DEEP).then(|| Cuboid::new(c.half_extents - PVec::splat(DEEP)))
    };
    let meets = |p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape| {
        query::intersection_test(p1, s1, p2, s2).is_ok_and(|i| i.intersecting)
    };
    match (shrunk(s2), s1.as_support_map().is_some(), shrunk(s1), s2.as_support_map().is_some()) {
        (Some(b), true, _, _) => meets(p1, s1, p2, &b),
        (_, _, Some(a), true) => meets(p1, &a, p2, s2),
        _ => false,
    }
}

/// Collision of a moving shape (robot or carried) with another: by its eroded
/// primitive when it has one (one intersection test), else by contact depth. `balls`:
/// whether to try the balls inside the moving shape first against a box (`false` for
/// the plain check); `proved` counts the contacts they proved.
#[inline]
fn collide_moving(
    (p1, moving, balls): (&PPose, &Placed, bool),
    (p2, s2, obb2): (&PPose, &dyn Shape, &Obb),
    dir: &mut PVec,
    proved: &Cell<u64>,
) -> bool {
    if !moving.eroded_obb.as_ref().unwrap_or(&moving.obb).may_touch(p1, obb2, p2) {
        return false;
    }
    if balls && obb2.exact && inner_ball_meets(p1, moving.inner(), &obb2.placed(p2), obb2.cuboid.half_extents) {
        proved.set(proved.get() + 1);
        return true;
    }
    match &moving.eroded {
        Some(e) => match (e.as_cuboid(), s2.as_cuboid()) {
            (Some(c1), Some(c2)) => boxes_intersect(c1.half_extents, c2.half_extents, &p1.inv_mul(p2)),
            _ => query::intersection_test(p1, &*e.0, p2, s2).map_or(true, |i| i.intersecting),
        },
        None => collide_from(p1, &*moving.shape.0, p2, s2, dir),
    }
}

/// Whether one of `inner` (balls inside a shape, in its frame at `p1`), eroded by the
/// contact tolerance, meets the box of half extents `he` at `p2`: a contact deeper than
/// the tolerance. Unsure (within parry's margin of touching) is not a proof, nor is a
/// ball no larger than the tolerance.
#[inline]
fn inner_ball_meets(p1: &PPose, inner: &[Ball], p2: &PPose, he: PVec) -> bool {
    inner.iter().any(|&(c, r)| ball_meets_box(*p1 * c, r - CONTACT_TOLERANCE, p2, he) == Some(true))
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

fn check_parts(w: &World, r: RobotId, q: &[f64], ctx: &CheckCtx, robot_part: bool) -> Check {
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

/// The planner's coarse segment check: the samples of `check_motion(.., 1, ..)`,
/// visited coarse-to-fine (ends, middle, quarters, ...) so a blocked segment, the
/// common case for long roadmap edges, is found after a few samples. The labels are
/// the same in any order; only which blocker is reported may differ.
pub(crate) fn check_segment(w: &World, r: RobotId, a: &[f64], b: &[f64], step: f64, ctx: &CheckCtx) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, 1), ctx, (true, (false, false)))
}

/// [`check_segment`] without the samples of its ends flagged in `known` (`a`, `b`),
/// whose checks the caller already has: their labels are the caller's to join.
pub(crate) fn check_segment_known(
    w: &World,
    r: RobotId,
    (a, b): (&[f64], &[f64]),
    step: f64,
    known: (bool, bool),
    ctx: &CheckCtx,
) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, 1), ctx, (true, known))
}

/// The samples of [`check_segment`], checking only the carried object (see
/// [`check_posed`]).
pub(crate) fn check_segment_held(w: &World, r: RobotId, a: &[f64], b: &[f64], step: f64, ctx: &CheckCtx) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, 1), ctx, (false, (false, false)))
}

/// The samples of `check_motion(.., step, parts, ..)` that [`check_segment`] at `step`
/// does not take (every `parts`-th is one of its: the same fractions of the segment,
/// hence the same configurations), coarse to fine. After a coarse check of the same
/// segment and context found labels `l` and no block, `l` joined with this one's labels
/// is `check_motion`'s answer, without checking the coarse samples twice.
pub(crate) fn check_motion_rest(
    w: &World,
    r: RobotId,
    a: &[f64],
    b: &[f64],
    (step, parts): (f64, usize),
    ctx: &CheckCtx,
) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, parts.max(2)), ctx, (true, (false, false)))
}

/// Sample `i` of `steps(a, b, step, parts) + 1` is skipped when `parts > 1` and `i` is a
/// multiple of `parts` (see [`check_motion_rest`]), and sample 0 or `n` (`a` or `b`) when
/// flagged in `known` (see [`check_segment_known`]).
fn segment_coarse_to_fine(
    w: &World,
    r: RobotId,
    a: &[f64],
    b: &[f64],
    (step, parts): (f64, usize),
    ctx: &CheckCtx,
    (robot_part, (known_a, known_b)): (bool, (bool, bool)),
) -> Check {
    let m = &w.robots[r.index()];
    assert_dof(m, a);
    assert_dof(m, b);
    let n = steps(a, b, step, parts);
    let mut q = a.to_vec();
    let mut out = ObjectSet::new();
    // Sample 0 comes first: a non-finite end is blocked by the limits check at once.
    let top = n.checked_next_power_of_two().unwrap_or(usize::MAX / 2 + 1);
    let mut stride = top;
    while stride > 0 {
        // Multiples of `stride` not already visited as multiples of `2 * stride`.
        let first = if stride == top { 0 } else { stride };
        let by = if stride == top { stride } else { 2 * stride };
        for i in (first..=n).step_by(by) {
            if (parts > 1 && i % parts == 0) || (known_a && i == 0) || (known_b && i == n) {
                continue;
            }
            sample(a, b, i, n, &mut q);
            match check_parts(w, r, &q, ctx, robot_part) {
                Check::Blocked(bl) => return Check::Blocked(bl),
                Check::Touches(l) => out.union_with(&l),
            }
        }
        stride /= 2;
    }
    Check::Touches(out)
}

/// Samples of a segment with steps of at most `step`, each cut into `parts`.
pub(crate) fn steps(a: &[f64], b: &[f64], step: f64, parts: usize) -> usize {
    let span = a.iter().zip(b).map(|(x, y)| (y - x).abs()).fold(0.0, f64::max);
    // Saturating: a NaN or infinite span must not overflow (the limits check blocks it).
    (if step > 0.0 { (span / step).ceil().max(1.0) as usize } else { 1 }).saturating_mul(parts.max(1))
}

/// Sample `i` of `n` on a -> b; the last is `b` exactly. Interpolated from whichever end
/// comes first in a fixed order (see [`from_a`]), so that sample `i` of a -> b and sample
/// `n - i` of b -> a are the same configuration to the bit: a segment's labels do not
/// depend on the way it was walked, and a check of one way can complete a check of the other.
#[inline]
pub(crate) fn sample(a: &[f64], b: &[f64], i: usize, n: usize, q: &mut [f64]) {
    let (from, to, k) = if from_a(a, b) { (a, b, i) } else { (b, a, n - i) };
    let t = k as f64 / n as f64;
    for (j, v) in q.iter_mut().enumerate() {
        *v = if k == n { to[j] } else { from[j] + (to[j] - from[j]) * t };
    }
}

/// Whether `a` is first of the two (by the first joint where they differ, in
/// `f64::total_cmp`'s order; `a` when they are equal).
#[inline]
fn from_a(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).map(|(x, y)| x.total_cmp(y)).find(|o| o.is_ne()) != Some(std::cmp::Ordering::Greater)
}

/// Steps of at most `step`, each cut into `parts`: the samples include those of
/// `parts = 1`, so the labels found can only grow with `parts`.
pub(crate) fn check_motion(
    w: &World,
    r: RobotId,
    a: &[f64],
    b: &[f64],
    step: f64,
    parts: usize,
    ctx: &CheckCtx,
) -> Check {
    let m = &w.robots[r.index()];
    assert_dof(m, a);
    assert_dof(m, b);
    let n = steps(a, b, step, parts);
    let mut q = a.to_vec();
    let mut out = ObjectSet::new();
    for i in 0..=n {
        sample(a, b, i, n, &mut q);
        match check(w, r, &q, ctx) {
            Check::Blocked(bl) => return Check::Blocked(bl),
            Check::Touches(l) => out.union_with(&l),
        }
    }
    Check::Touches(out)
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
