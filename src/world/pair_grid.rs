//! A fast first answer for the self-collision pairs that turn on one to three joints: a
//! wrist's forearm and hand (joints 5 and 6, or 4 to 6), an elbow's two links (joints 3
//! and 4), a base and an upper arm (1 and 2). On the paper's examples those few pairs are
//! nearly every self-pair test that reaches the exact one: their boxes overlap in almost
//! every configuration, yet they are rarely closer than a centimetre.
//!
//! Such a pair's distance depends on those joints only, so a grid over them can hold it:
//! each cell remembers a lower bound `d(c)` on the distance at its centre `c` (within 10 µm
//! of it, from GJK's dual bound). A joint turned by `δ` moves the
//! body beyond it by at most `ρ·|δ|`, `ρ` the body's reach from the joint's axis (a sum of
//! the chain's fixed lengths, so valid whatever the other joints do); the same pair with
//! the other body turned back by `δ` instead is the same pair rigidly moved, at the same
//! distance, so `ρ` is the nearer body's reach (the UR5's pan turns its upper arm's far
//! end half a metre from the axis, its base 14 cm at most). So at `q` the pair
//! is at least `d(c) − Σ ρ_i |q_i − c_i|` apart: when that is positive the exact test
//! would say "free", and is skipped. Anything nearer goes to the exact test, so verdicts
//! never change (`tests/fast_check.rs` compares both on 100 000 configurations per robot).
//!
//! Cells are measured when first visited, by whichever thread comes first, GJK starting
//! from that thread's last simplex for the pair: the value may differ in its last
//! micrometres with the thread, but it is a lower bound either way and decides only
//! whether the exact test runs, so verdicts do not depend on it (a race only measures a
//! cell twice).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::math::{Pose as PPose, Vector as PVec};

use super::chain::{Chain, Source};
use super::lower_bound::{distance_at_least_below, GjkStart, LOWER_BOUND_TOLERANCE};
use super::robot::RobotModel;
use super::shapes::{place, to_ppose, Boxed, Placed};
use super::urdf::Motion;
use super::OPEN_POSTURE as OPEN;

/// Cells per pair at most (8 bytes each), allocated when the pair first needs one.
const MAX_CELLS: usize = 4096;

/// Joints a grid spans at most.
const MAX_JOINTS: usize = 3;

/// No finer than this (metres): the most a cell's offset can add to the bound per joint.
const MIN_HALF_WIDTH: f64 = 0.001;

/// What the centre's distance must beat the bound by (metres): GJK's own tolerance and
/// the rounding of forward kinematics are orders of magnitude below it.
const SLACK: f64 = 1e-4;

/// Cell value: not measured yet.
const UNKNOWN: u64 = 0;

/// One joint of the grid.
#[derive(Debug, Clone)]
struct Dim {
    /// Index into the configuration.
    index: usize,
    lo: f64,
    width: f64,
    cells: usize,
    /// How far the bodies' points can move per radian of this joint (metres).
    reach: f64,
}

pub(crate) struct PairGrid {
    dims: Vec<Dim>,
    /// The fingers' posture changes neither body: the grid holds for every posture.
    any_posture: bool,
    /// A centre this far apart decides its whole cell: no need to measure it closer.
    enough: f64,
    cells: OnceLock<Box<[AtomicU64]>>,
}

impl PairGrid {
    /// The grid of body pair `(a, b)`, when their relative pose turns on one to three
    /// revolute joints with finite limits and every shape is convex.
    pub fn new(m: &RobotModel, a: usize, b: usize) -> Option<PairGrid> {
        let chain = &m.chain;
        // Turning a joint moves the pair's two sides about its axis relative to each
        // other; turning the other side back instead is the same pair, rigidly moved, at
        // the same distance: the nearer side's reach bounds the change.
        let mut reach: Vec<(usize, f64)> = Vec::new();
        for t in pair_joints(m, a, b)? {
            let rho = t.mult.abs() * t.own.min(t.theirs);
            match reach.iter_mut().find(|(i, _)| *i == t.index) {
                Some((_, r)) => *r += rho,
                None => reach.push((t.index, rho)),
            }
        }
        if reach.is_empty() || reach.len() > MAX_JOINTS {
            return None;
        }
        let shapes = || m.bodies[a].shapes.clone().chain(m.bodies[b].shapes.clone());
        if shapes().any(|si| m.shapes[si].placed.shape.as_support_map().is_none()) {
            return None;
        }
        let ranges: Vec<f64> = reach.iter().map(|&(i, _)| chain.limits[i].1 - chain.limits[i].0).collect();
        if ranges.iter().any(|r| !(r.is_finite() && *r > 0.0)) || reach.iter().any(|(_, r)| !r.is_finite()) {
            return None;
        }
        // Cells sized so that each joint adds about the same to the bound: half-width h
        // with Π (ρ_i·range_i / 2h) = MAX_CELLS.
        let k = reach.len() as i32;
        let spans: Vec<f64> = reach.iter().zip(&ranges).map(|(&(_, r), w)| r * w).collect();
        let product: f64 = spans.iter().map(|s| s.max(1e-12)).product();
        let h = (product / (2f64.powi(k) * MAX_CELLS as f64)).powf(1.0 / k as f64).max(MIN_HALF_WIDTH);
        let dims: Vec<Dim> = reach
            .iter()
            .zip(&ranges)
            .zip(&spans)
            .map(|((&(index, r), &range), &span)| {
                let cells = ((span / (2.0 * h)).ceil() as usize).clamp(1, MAX_CELLS);
                Dim { index, lo: chain.limits[index].0, width: range / cells as f64, cells, reach: r }
            })
            .collect();
        let same = |si: usize| m.postures.iter().all(|p| p.poses.get(si).is_none_or(|x| *x == *m.shape_pose(si, OPEN)));
        let any_posture = shapes().all(same);
        let enough = dims.iter().map(|d| d.reach * d.width / 2.0).sum::<f64>() + 2.0 * SLACK;
        Some(PairGrid { dims, any_posture, enough, cells: OnceLock::new() })
    }

    /// Whether the grid may answer for the fingers in `posture`.
    #[inline]
    pub fn holds_for(&self, posture: usize) -> bool {
        posture == OPEN || self.any_posture
    }

    /// True when the pair is provably apart at `q`. `measure` gets `q` with the grid's
    /// joints at a cell's centre and returns a lower bound on the pair's distance there,
    /// within the tolerance of it below the second argument (`None`: cannot say).
    #[inline]
    pub fn apart(&self, q: &[f64], measure: impl FnOnce(&[(usize, f64)], f64) -> Option<f64>) -> bool {
        let mut cell = 0;
        let mut bound = 0.0;
        let mut centre = [(0, 0.0); MAX_JOINTS];
        for (k, d) in self.dims.iter().enumerate() {
            let v = q[d.index];
            // Clamped: a value a rounding outside the limits still uses the edge cell. The
            // cast truncates and saturates, so it is `floor().max(0.0)` for every value
            // (NaN too: 0) without the call `floor` is on a baseline x86-64.
            let t = (((v - d.lo) / d.width) as usize).min(d.cells - 1);
            let c = d.lo + (t as f64 + 0.5) * d.width;
            bound += d.reach * (v - c).abs();
            cell = cell * d.cells + t;
            centre[k] = (d.index, c);
        }
        let cells = self.cells.get_or_init(|| {
            let n = self.dims.iter().map(|d| d.cells).product();
            (0..n).map(|_| AtomicU64::new(UNKNOWN)).collect()
        });
        let mut bits = cells[cell].load(Ordering::Relaxed);
        if bits == UNKNOWN {
            let d = measure(&centre[..self.dims.len()], self.enough).filter(|d| *d > 0.0).unwrap_or(-1.0);
            bits = d.to_bits();
            cells[cell].store(bits, Ordering::Relaxed);
        }
        f64::from_bits(bits) - bound > SLACK
    }

    /// The joints of the grid and their reach (metres per radian), for tests.
    #[cfg(test)]
    pub fn reaches(&self) -> Vec<(usize, f64)> {
        self.dims.iter().map(|d| (d.index, d.reach)).collect()
    }
}

/// A joint that turns one body of a pair relative to the other, and how far from its
/// axis each body can be (metres, whatever the joints do). The link and bodies are read
/// by the tests, which measure the reaches against forward kinematics.
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) struct PairJoint {
    /// The link the joint turns, and the configuration's value that drives it (times `mult`).
    pub link: usize,
    pub index: usize,
    pub mult: f64,
    /// The body on the joint's side, its reach from the axis; the other body, and its.
    pub body: usize,
    pub own: f64,
    pub other: usize,
    pub theirs: f64,
}

/// The joints between bodies `a` and `b` (every link on the way from either up to their
/// common ancestor), `None` when one slides or a reach cannot be bounded.
pub(crate) fn pair_joints(m: &RobotModel, a: usize, b: usize) -> Option<Vec<PairJoint>> {
    let chain = &m.chain;
    let (la, lb) = (m.bodies[a].link, m.bodies[b].link);
    let (side_a, side_b) = (links_up_to_common(chain, la, lb), links_up_to_common(chain, lb, la));
    let mut joints = Vec::new();
    for (side, body, (other_side, other)) in [(&side_a, a, (&side_b, b)), (&side_b, b, (&side_a, a))] {
        // `side` runs from the body's link up towards the common ancestor.
        for (k, &l) in side.iter().enumerate() {
            let link = &chain.links[l];
            let (index, mult, axis) = match (link.source, link.motion) {
                (Source::Fixed | Source::Frozen(_), _) => continue,
                (Source::Active { index, mult, .. }, Motion::Rotate(axis)) => (index, mult, axis),
                // A sliding joint changes the chain's lengths: no grid.
                _ => return None,
            };
            let below: Vec<usize> = side[..k].iter().rev().copied().collect();
            let own = reach_from_axis(m, chain, &axis, &below, body)?;
            let theirs = reach_across(m, chain, (&axis, &side[k..]), other_side, other)?;
            joints.push(PairJoint { link: l, index, mult, body, own, other, theirs });
        }
    }
    Some(joints)
}

/// Links from `from` up to (not including) the common ancestor of `from` and `other`.
fn links_up_to_common(chain: &Chain, from: usize, other: usize) -> Vec<usize> {
    let ancestors = |mut l: usize| {
        let mut out = vec![l];
        while let Some(p) = chain.links[l].parent {
            out.push(p);
            l = p;
        }
        out
    };
    let theirs = ancestors(other);
    ancestors(from).into_iter().take_while(|l| !theirs.contains(l)).collect()
}

/// How far from `axis` (through the origin of the link whose joint it is, in that link's
/// frame) the shapes of `body` can be, whatever the joints of `below` (the links from that
/// link's child down to the body's link, in order) do. The first link's offset is fixed
/// in the joint's frame, so only its part across the axis counts; every later offset and
/// the body's own reach can point anywhere.
fn reach_from_axis(m: &RobotModel, chain: &Chain, axis: &Vector3<f64>, below: &[usize], body: usize) -> Option<f64> {
    let spheres = body_spheres(m, body);
    let r = match below.split_first() {
        None => spheres.map(|(c, r)| across(axis, c) + r).fold(0.0, f64::max),
        Some((first, rest)) => {
            let offset = |l: usize| link_offset(chain, l);
            let along: f64 = rest.iter().map(|&l| offset(l).norm()).sum();
            across(axis, offset(*first)) + along + spheres.map(|(c, r)| c.norm() + r).fold(0.0, f64::max)
        }
    };
    r.is_finite().then_some(r)
}

/// How far from the axis of the joint of `up[0]` (`axis` in that joint's frame) the shapes
/// of `body` on the pair's other side can be, whatever the joints do. `up`: the links
/// from the joint's up to (not including) the pair's common ancestor; `other_side`: the
/// links from `body`'s up to it. Through the ancestor's origin, each link's offset
/// from its parent counted at full length; when the joint hangs from the ancestor and the
/// body is the ancestor's own, the axis is fixed in the body's frame and only the part
/// across it counts.
fn reach_across(
    m: &RobotModel,
    chain: &Chain,
    (axis, up): (&Vector3<f64>, &[usize]),
    other_side: &[usize],
    body: usize,
) -> Option<f64> {
    let spheres = body_spheres(m, body);
    let r = match (up, other_side) {
        ([joint], []) => {
            let pose = &chain.links[*joint].pose_parent_joint;
            let (origin, axis) = (pose.translation.vector, pose.rotation * axis);
            spheres.map(|(c, r)| across(&axis, c - origin) + r).fold(0.0, f64::max)
        }
        _ => {
            let path: f64 = up.iter().chain(other_side).map(|&l| link_offset(chain, l).norm()).sum();
            path + spheres.map(|(c, r)| c.norm() + r).fold(0.0, f64::max)
        }
    };
    r.is_finite().then_some(r)
}

/// A body's shapes' bounding spheres (centre in the body's link frame, radius), the
/// fingers open.
fn body_spheres(m: &RobotModel, body: usize) -> impl Iterator<Item = (Vector3<f64>, f64)> + '_ {
    m.bodies[body].shapes.clone().map(|si| {
        let (centre, radius) = bounding_sphere(&m.shapes[si].placed);
        let c = *m.shape_pose(si, OPEN) * centre;
        (Vector3::new(c.x, c.y, c.z), radius)
    })
}

/// The part of `v` across the unit `axis` (its distance from the axis through the origin).
fn across(axis: &Vector3<f64>, v: Vector3<f64>) -> f64 {
    (v - axis * axis.dot(&v)).norm()
}

/// The offset of a link's origin from its parent's (a frozen slide, an open finger, moves
/// it by a constant).
fn link_offset(chain: &Chain, l: usize) -> Vector3<f64> {
    let link = &chain.links[l];
    match (link.source, link.motion) {
        (Source::Frozen(v), Motion::Slide(axis)) => {
            link.pose_parent_joint.translation.vector + link.pose_parent_joint.rotation * (axis.into_inner() * v)
        }
        _ => link.pose_parent_joint.translation.vector,
    }
}

/// A sphere around a placed shape, in the shape's own frame: a ball's own, else the one
/// around its local box.
fn bounding_sphere(p: &Placed) -> (PVec, f64) {
    match p.boxed {
        Boxed::Ball(r) => (PVec::ZERO, r),
        _ => (p.obb.centre.translation, p.obb.cuboid.half_extents.length()),
    }
}

/// Reused buffers of [`body_distance`].
#[derive(Default)]
pub(crate) struct Measure {
    /// The configuration with the grid's joints at a cell's centre.
    pub q: Vec<f64>,
    links: Vec<Isometry3<f64>>,
    /// Per body: each shape's index, pose, bounding sphere's centre and radius.
    posed: [Vec<(usize, PPose, PVec, f64)>; 2],
    /// Per pair of shapes measured by GJK, the simplex it ended with: the cells a planner
    /// visits along a motion are next to each other, and GJK from the last one's simplex
    /// ends in a step or two (the bound holds from any start).
    starts: std::collections::HashMap<(usize, usize), GjkStart>,
    /// Two bodies' balls placed, when both are balls only.
    packed: [super::ball_pack::PlacedBalls; 2],
}

/// A lower bound on the distance between bodies `a` and `b` (fingers open) at `s.q`, within
/// [`LOWER_BOUND_TOLERANCE`] of it where it is below `enough` (GJK's dual bound, which is
/// all a grid needs: see [`PairGrid::apart`]). `None` when a pair of their shapes cannot be
/// measured. Each pair of shapes is first bounded by its bounding spheres and, when those
/// are nearer than `enough` and than the nearest pair so far, by its bounding boxes, and
/// only then measured.
pub(crate) fn body_distance(m: &RobotModel, a: usize, b: usize, enough: f64, s: &mut Measure) -> Option<f64> {
    let Measure { q, links, posed, starts, packed } = s;
    links.resize(m.chain.links.len(), Isometry3::identity());
    m.chain.fk_upto(q, m.bodies[a].link.max(m.bodies[b].link), links);
    // Two bodies of balls: their least gap, every pair of balls at once.
    if let (Some(pa), Some(pb)) = (&m.ball_packs[a], &m.ball_packs[b]) {
        let [wa, wb] = packed;
        pa.place(OPEN, &to_ppose(&links[m.bodies[a].link]), wa);
        pb.place(OPEN, &to_ppose(&links[m.bodies[b].link]), wb);
        // Past `enough` any value past it will do (see below).
        return Some(pa.least_gap(wa, pb, wb, enough));
    }
    for (k, body) in [a, b].into_iter().enumerate() {
        let link = to_ppose(&links[m.bodies[body].link]);
        posed[k].clear();
        posed[k].extend(m.bodies[body].shapes.clone().map(|si| {
            let pose = place(&link, m.shape_pose(si, OPEN), m.shapes[si].unturned);
            let (centre, radius) = bounding_sphere(&m.shapes[si].placed);
            (si, pose, pose * centre, radius)
        }));
    }
    let mut best = f64::INFINITY;
    for (si, pi, ci, ri) in &posed[0] {
        for (sj, pj, cj, rj) in &posed[1] {
            // Each pair's value is at most its distance; a pair cannot lower the least
            // once its bound is past it (or past `enough`).
            let mut gap = ci.distance(*cj) - ri - rj;
            let (pa, pb) = (&m.shapes[*si].placed, &m.shapes[*sj].placed);
            if gap >= best.min(enough) || matches!((pa.boxed, pb.boxed), (Boxed::Ball(_), Boxed::Ball(_))) {
                // Two balls' gap is their distance.
                best = best.min(gap);
                continue;
            }
            gap = gap.max(pa.obb.gap(pi, &pb.obb, pj));
            if gap < best.min(enough) {
                // Beyond the least so far or `enough`, any value past it will do.
                let start = starts.entry((*si, *sj)).or_default();
                let within = (LOWER_BOUND_TOLERANCE, best.min(enough));
                gap = distance_at_least_below(pi, &*pa.shape.0, pj, &*pb.shape.0, within, start)?;
            }
            best = best.min(gap);
        }
    }
    Some(best)
}

#[cfg(test)]
#[path = "pair_grid_tests.rs"]
mod tests;
