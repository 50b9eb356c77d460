//! The whole cell at one instant: every robot posed, carried objects in their hands,
//! objects in place or gone. Its own contact test on the world's shapes (parry queries),
//! not the planner's labelled check.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose as PPose;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::query;
use parry3d_f64::shape::Shape;

use super::{Obstacle, Party};
use crate::resolve::{ObjectId, RobotId};
use crate::world::{
    distance_at_least, posture_of, shape_distance, AxisReach, BodyInfo, Held, HeldPart, ObjectSet, PosedShape,
    StaticOwner, StaticShape, World, CONTACT_TOLERANCE, LOWER_BOUND_TOLERANCE,
};

/// One robot at the instant.
pub(super) struct RobotAt<'a> {
    pub q: &'a [f64],
    pub held: Option<&'a Held>,
    /// An object in place this robot's hand may touch (on its straight move in).
    pub exempt: Option<ObjectId>,
}

/// Two things too close: overlapping (`None`) or nearer than the clearance.
pub(super) type Finding = (Party, Obstacle, Option<f64>);

pub(super) struct RobotGeo {
    name: String,
    pub bodies: Vec<BodyInfo>,
    pub self_pairs: Vec<(usize, usize)>,
    /// Per body, then for the flange (and what it carries): the joints that move it.
    pub body_joints: Vec<Vec<bool>>,
    pub flange_joints: Vec<bool>,
    /// Per body, per joint: how far the body's own points move per unit of the joint.
    pub body_reach: Vec<Vec<f64>>,
}

/// What stays the same across instants.
pub(super) struct Cell<'w> {
    world: &'w World,
    pub statics: Vec<StaticShape>,
    bvh: Bvh,
    pub robots: Vec<RobotGeo>,
    /// Per robot: its bodies' reach where they stand (see `AxisReach::bodies_over`).
    pub axes: Vec<AxisReach<'w>>,
    pub clearance: f64,
}

/// Reused buffers: posed robots and carried objects.
#[derive(Default)]
pub(super) struct Scratch {
    /// Per robot, its shapes; one is posed at this instant once `fresh` says so (see
    /// [`Cell::pose`]).
    pub posed: Vec<Vec<PosedShape>>,
    pub held: Vec<Vec<HeldPart>>,
    /// Per robot: its links' world poses and its fingers' posture at this instant, and per
    /// shape whether `posed` has it posed there yet.
    links: Vec<Vec<PPose>>,
    posture: Vec<usize>,
    fresh: Vec<Vec<bool>>,
}

impl<'w> Cell<'w> {
    pub fn new(world: &'w World, clearance: f64) -> Cell<'w> {
        let statics = world.static_shapes();
        let aabbs: Vec<Aabb> = statics.iter().map(|s| s.aabb.loosened(clearance)).collect();
        let bvh = if aabbs.is_empty() { Bvh::new() } else { Bvh::from_leaves(BvhBuildStrategy::default(), &aabbs) };
        let robots = (0..world.scenario().robots.len())
            .map(|ri| {
                let r = RobotId(ri as u32);
                let (body_joints, flange_joints) = world.body_joints(r);
                RobotGeo {
                    name: world.scenario().robot(r).name.clone(),
                    bodies: world.bodies(r),
                    self_pairs: world.self_pairs_unpruned(r),
                    body_joints,
                    flange_joints,
                    body_reach: world.body_reach(r),
                }
            })
            .collect();
        let axes = (0..world.scenario().robots.len()).map(|ri| world.axis_reach(RobotId(ri as u32), 0.0)).collect();
        Cell { world, statics, bvh, robots, axes, clearance }
    }

    /// Every robot's links and what it carries, posed at this instant; its shapes are
    /// posed when first asked for ([`Cell::pose_shapes`], [`Cell::pose_all`]): most
    /// instants of a replay measure a few pairs, and posing every shape of a Panda of
    /// spheres at every instant was a seventh of a `narrow_gap` problem's compile.
    pub fn pose(&self, at: &[RobotAt], s: &mut Scratch) {
        let w = self.world;
        s.posed.resize_with(at.len(), Vec::new);
        s.held.resize_with(at.len(), Vec::new);
        s.links.resize_with(at.len(), Vec::new);
        s.fresh.resize_with(at.len(), Vec::new);
        s.posture.resize(at.len(), 0);
        for (ri, ra) in at.iter().enumerate() {
            let r = RobotId(ri as u32);
            // The same robot's shapes at every instant: their list is made once.
            if s.posed[ri].is_empty() {
                w.shape_slots(r, &mut s.posed[ri]);
            }
            let flange = w.pose_links(r, ra.q, &mut s.links[ri]);
            s.posture[ri] = posture_of(ra.held);
            s.fresh[ri].clear();
            s.fresh[ri].resize(s.posed[ri].len(), false);
            s.held[ri] = ra.held.map(|h| w.pose_held(h, &flange)).unwrap_or_default();
        }
    }

    /// Robot `ri`'s `shapes` posed at this instant.
    pub fn pose_shapes(&self, s: &mut Scratch, ri: usize, shapes: &[usize]) {
        for &si in shapes {
            self.pose_shape(s, ri, si);
        }
    }

    /// Every robot's shapes posed at this instant.
    pub fn pose_all(&self, s: &mut Scratch) {
        for ri in 0..s.posed.len() {
            for si in 0..s.posed[ri].len() {
                self.pose_shape(s, ri, si);
            }
        }
    }

    fn pose_shape(&self, s: &mut Scratch, ri: usize, si: usize) {
        if !s.fresh[ri][si] {
            self.world.pose_shape_on(RobotId(ri as u32), &s.links[ri], si, s.posture[ri], &mut s.posed[ri][si]);
            s.fresh[ri][si] = true;
        }
    }

    /// Everything too close at this instant, posed in `s` by [`Cell::pose`]. `present`:
    /// objects in place. `still[r]`: robot `r` stands, holds and may touch exactly as at
    /// the previous instant sampled,
    /// and no object has appeared since; its checks against the scene and itself would
    /// find what they found then, so they are skipped (as is a pair of two such robots).
    pub fn check(&self, at: &[RobotAt], present: &ObjectSet, still: &[bool], s: &Scratch, found: &mut Vec<Finding>) {
        let w = self.world;
        let c = self.clearance;
        for (ri, ra) in at.iter().enumerate() {
            let g = &self.robots[ri];
            let body = |b: usize| Party::Body { robot: g.name.clone(), body: g.bodies[b].name.clone() };
            let carried = |h: &Held| Party::Held {
                robot: g.name.clone(),
                object: w.scenario().object(h.object).body.name.clone(),
            };
            let again = still.get(ri).copied().unwrap_or(false);
            // Moving bodies against the scene, with the clearance.
            for ps in s.posed[ri].iter().filter(|ps| !again && g.bodies[ps.body].moving) {
                let skip = |o: ObjectId| {
                    !present.contains(o) || Some(o) == ra.exempt || ra.held.is_some_and(|h| h.object == o)
                };
                if let Some((obs, d)) = self.against_statics(Side::of(ps), c, skip) {
                    push(found, body(ps.body), obs, d);
                }
            }
            // Self-collision over the unpruned pairs: contact only. A body's shapes, in
            // order: those of its run of the posed list when each body's are one run (as
            // posed by the world), else of the whole list.
            let posed = &s.posed[ri];
            let runs = if again || g.self_pairs.is_empty() { None } else { body_runs(posed, g.bodies.len()) };
            let of = |k: usize| {
                let within = runs.as_ref().map_or(0..posed.len(), |r| r[k].clone());
                posed[within].iter().filter(move |x| x.body == k)
            };
            for &(a, b) in g.self_pairs.iter().filter(|_| !again) {
                if of(a).any(|x| of(b).any(|y| near(Side::of(x), Side::of(y), 0.0).is_some())) {
                    push(found, body(a), Obstacle::Moving(body(b)), None);
                }
            }
            // The carried object: against the scene and its carrier's own links, contact only.
            if let Some(h) = ra.held.filter(|_| !again) {
                for part in &s.held[ri] {
                    let skip = |o: ObjectId| !present.contains(o) || o == h.object;
                    if let Some((obs, d)) = self.against_statics(Side::held(part), 0.0, skip) {
                        push(found, carried(h), obs, d);
                    }
                    let own = s.posed[ri].iter().filter(|ps| !g.bodies[ps.body].holds);
                    for ps in own {
                        if near(Side::held(part), Side::of(ps), 0.0).is_some() {
                            push(found, carried(h), Obstacle::Moving(body(ps.body)), None);
                        }
                    }
                }
            }
            // Against every later robot and what it carries, with the clearance.
            for (rj, rb) in at.iter().enumerate().skip(ri + 1) {
                if again && still.get(rj).copied().unwrap_or(false) {
                    continue;
                }
                let gj = &self.robots[rj];
                let other = |b: usize| Party::Body { robot: gj.name.clone(), body: gj.bodies[b].name.clone() };
                let other_carried = |h: &Held| Party::Held {
                    robot: gj.name.clone(),
                    object: w.scenario().object(h.object).body.name.clone(),
                };
                for x in &s.posed[ri] {
                    for y in &s.posed[rj] {
                        if !g.bodies[x.body].moving && !gj.bodies[y.body].moving {
                            continue;
                        }
                        if let Some(d) = near(Side::of(x), Side::of(y), c) {
                            push(found, body(x.body), Obstacle::Moving(other(y.body)), d);
                        }
                    }
                    if let Some(h) = rb.held {
                        for part in &s.held[rj] {
                            if let Some(d) = near(Side::of(x), Side::held(part), c) {
                                push(found, body(x.body), Obstacle::Moving(other_carried(h)), d);
                            }
                        }
                    }
                }
                if let Some(h) = ra.held {
                    for part in &s.held[ri] {
                        for y in &s.posed[rj] {
                            if let Some(d) = near(Side::held(part), Side::of(y), c) {
                                push(found, carried(h), Obstacle::Moving(other(y.body)), d);
                            }
                        }
                        if let Some(hj) = rb.held {
                            for part2 in &s.held[rj] {
                                if let Some(d) = near(Side::held(part), Side::held(part2), c) {
                                    push(found, carried(h), Obstacle::Moving(other_carried(hj)), d);
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// The first static shape (not skipped) too close to a moving one.
    fn against_statics(
        &self,
        moving: Side,
        clearance: f64,
        skip: impl Fn(ObjectId) -> bool,
    ) -> Option<(Obstacle, Option<f64>)> {
        let scn = self.world.scenario();
        for leaf in self.bvh.intersect_aabb(moving.aabb) {
            let e = &self.statics[leaf as usize];
            if let StaticOwner::Object(o) = e.owner {
                if skip(o) {
                    continue;
                }
            }
            let fixed = Side { pose: &e.pose, shape: &*e.shape.0, eroded: None, aabb: &e.aabb };
            if let Some(d) = near(moving, fixed, clearance) {
                let obs = match e.owner {
                    StaticOwner::Fixed(f) => Obstacle::Fixed(scn.fixed[f.index()].name.clone()),
                    StaticOwner::Object(o) => Obstacle::Object(scn.object(o).body.name.clone()),
                };
                return Some((obs, d));
            }
        }
        None
    }
}

/// One shape of a pair: posed, with its eroded form when it is a primitive.
#[derive(Clone, Copy)]
pub(super) struct Side<'a> {
    pub pose: &'a PPose,
    pub shape: &'a dyn Shape,
    eroded: Option<&'a dyn Shape>,
    pub aabb: &'a Aabb,
}

impl<'a> Side<'a> {
    pub fn of(p: &'a PosedShape) -> Side<'a> {
        Side { pose: &p.pose, shape: &*p.shape.0, eroded: p.eroded.as_ref().map(|e| &*e.0), aabb: &p.aabb }
    }
    pub fn fixed(e: &'a StaticShape) -> Side<'a> {
        Side { pose: &e.pose, shape: &*e.shape.0, eroded: None, aabb: &e.aabb }
    }
    pub fn held(p: &'a HeldPart) -> Side<'a> {
        Side { pose: &p.pose, shape: &*p.shape.0, eroded: p.eroded.as_ref().map(|e| &*e.0), aabb: &p.aabb }
    }
}

fn push(found: &mut Vec<Finding>, a: Party, b: Obstacle, d: Option<f64>) {
    if !found.iter().any(|(x, y, _)| *x == a && *y == b) {
        found.push((a, b, d));
    }
}

/// `Some(None)`: overlapping deeper than the world's contact tolerance (no clearance
/// asked): by the eroded primitive when either side has one, as the world model defines
/// contact, else by parry's contact depth. `Some(Some(d))`: nearer than the clearance, at
/// distance `d`. `None`: fine.
fn near(a: Side, b: Side, clearance: f64) -> Option<Option<f64>> {
    if !a.aabb.loosened(clearance).intersects(b.aabb) {
        return None;
    }
    if clearance > 0.0 {
        // A pair parry cannot measure counts as touching: never pass what was not checked.
        let d = shape_distance(a.pose, a.shape, b.pose, b.shape).unwrap_or(0.0);
        return (d < clearance).then_some(Some(d));
    }
    let touching = match (a.eroded, b.eroded) {
        (Some(e), _) => query::intersection_test(a.pose, e, b.pose, b.shape).map_or(true, |i| i.intersecting),
        (None, Some(e)) => query::intersection_test(b.pose, e, a.pose, a.shape).map_or(true, |i| i.intersecting),
        (None, None) => match query::intersection_test(a.pose, a.shape, b.pose, b.shape) {
            Ok(i) if !i.intersecting => false,
            _ => match query::contact(a.pose, a.shape, b.pose, b.shape, 0.0) {
                Ok(Some(c)) => c.dist < -CONTACT_TOLERANCE,
                Ok(None) => false,
                Err(_) => true,
            },
        },
    };
    touching.then_some(None)
}

/// What [`depth_slack`] keeps back from the depth [`near`] allows: more than GJK's and
/// EPA's errors on the two measures it stands between (its own now, the check's later).
const DEPTH_MARGIN: f64 = 1e-4;

/// Two shapes that touch, checked for contact only ([`near`] without clearance): a lower
/// bound on how far their points may yet move towards each other before [`near`] reports
/// them, or `None` when it cannot say (0 is then the pair's slack). [`near`] reports an
/// overlap deeper than the tolerance: a primitive side's eroded form meeting the other
/// side (either way round: the least of both is taken, whichever side [`near`] erodes),
/// else, for two convex shapes, a penetration depth beyond the tolerance. Both measures
/// shrink no faster than the points move (a point of one side inside the other as deep as
/// the depth stays inside while it moves less), so the replay bounds them as it bounds a
/// distance. A grasp pose or a goal may touch within the tolerance, and without this its
/// pairs would prove nothing for as long as they touch: the replay checked the whole
/// cell at every step there.
pub(super) fn depth_slack(a: Side, b: Side) -> Option<f64> {
    let eroded_gap = |p: &PPose, e: &dyn Shape, q: &PPose, other: &dyn Shape| {
        distance_at_least(p, e, q, other, LOWER_BOUND_TOLERANCE)
    };
    let slack = match (a.eroded, b.eroded) {
        (Some(ea), Some(eb)) => eroded_gap(a.pose, ea, b.pose, b.shape)?.min(eroded_gap(b.pose, eb, a.pose, a.shape)?),
        (Some(e), None) => eroded_gap(a.pose, e, b.pose, b.shape)?,
        (None, Some(e)) => eroded_gap(b.pose, e, a.pose, a.shape)?,
        (None, None) if a.shape.is_convex() && b.shape.is_convex() => {
            match query::contact(a.pose, a.shape, b.pose, b.shape, 0.0) {
                Ok(Some(c)) => CONTACT_TOLERANCE + c.dist,
                _ => return None,
            }
        }
        (None, None) => return None,
    };
    Some(slack - DEPTH_MARGIN).filter(|s| *s > 0.0)
}

/// Per body, the run of `posed` holding its shapes; `None` unless each body's shapes are
/// one run (empty for a body without shapes).
fn body_runs(posed: &[PosedShape], bodies: usize) -> Option<Vec<std::ops::Range<usize>>> {
    let mut runs = vec![0..0; bodies];
    let mut i = 0;
    while i < posed.len() {
        let b = posed[i].body;
        let start = i;
        while i < posed.len() && posed[i].body == b {
            i += 1;
        }
        let run = runs.get_mut(b)?;
        // Set before: its shapes are in two runs.
        if run.end != 0 {
            return None;
        }
        *run = start..i;
    }
    Some(runs)
}

#[cfg(test)]
mod tests {
    use parry3d_f64::math::{Rotation, Vector};
    use parry3d_f64::shape::SharedShape;
    use proptest::prelude::*;

    use super::*;

    fn posed(bodies: &[usize]) -> Vec<PosedShape> {
        let one = |body| PosedShape {
            body,
            shape: SharedShape::ball(0.1),
            eroded: None,
            pose: PPose::IDENTITY,
            aabb: Aabb::new_invalid(),
        };
        bodies.iter().map(|&b| one(b)).collect()
    }

    /// A shape placed for a test, its eroded form (a primitive's, as the world erodes it)
    /// placed with it.
    struct Placed {
        shape: SharedShape,
        eroded: Option<SharedShape>,
        pose: PPose,
        aabb: Aabb,
    }

    fn placed(shape: SharedShape, eroded: Option<SharedShape>, pose: PPose) -> Placed {
        let aabb = shape.compute_aabb(&pose);
        Placed { shape, eroded, pose, aabb }
    }

    fn side(p: &Placed) -> Side<'_> {
        Side { pose: &p.pose, shape: &*p.shape.0, eroded: p.eroded.as_ref().map(|e| &*e.0), aabb: &p.aabb }
    }

    fn up(z: f64) -> PPose {
        PPose::from_parts(Vector::new(0.0, 0.0, z), Rotation::IDENTITY)
    }

    /// The corners of a box of half extents `h`.
    fn corners(h: Vector) -> Vec<Vector> {
        (0..8).map(|i| Vector::new(h.x * sign(i, 1), h.y * sign(i, 2), h.z * sign(i, 4))).collect()
    }

    fn sign(i: usize, bit: usize) -> f64 {
        if i & bit == 0 {
            -1.0
        } else {
            1.0
        }
    }

    fn hull_box(h: Vector) -> SharedShape {
        SharedShape::convex_hull(&corners(h)).expect("a box's hull")
    }

    /// A wall 10 cm thick, its top face at z = 0.05.
    fn wall() -> Placed {
        placed(SharedShape::cuboid(0.5, 0.5, 0.05), None, PPose::IDENTITY)
    }

    fn assert_near(got: Option<f64>, want: f64) {
        match got {
            Some(g) => assert!((g - want).abs() < 1e-9, "{g} against {want}"),
            None => panic!("no slack, {want} expected"),
        }
    }

    /// By hand: a ball of 5 cm (eroded to 4.9 cm) 0.4 mm into a wall has its eroded form
    /// 0.6 mm off it; a hull 0.3 mm in may go 0.7 mm deeper; each less the margin, either
    /// way round. Too deep, or too near the tolerance to leave more than the margin, or a
    /// shape that is not convex: nothing to say.
    #[test]
    fn the_depth_slack_is_what_the_tolerance_leaves_of_the_overlap() {
        let wall = wall();
        let ball = placed(SharedShape::ball(0.05), Some(SharedShape::ball(0.049)), up(0.0996));
        assert_near(depth_slack(side(&ball), side(&wall)), 0.0006 - DEPTH_MARGIN);
        assert_near(depth_slack(side(&wall), side(&ball)), 0.0006 - DEPTH_MARGIN);
        let cube = |depth: f64| placed(hull_box(Vector::splat(0.05)), None, up(0.1 - depth));
        assert_near(depth_slack(side(&cube(0.0003)), side(&wall)), 0.0007 - DEPTH_MARGIN);
        assert_near(depth_slack(side(&wall), side(&cube(0.0003))), 0.0007 - DEPTH_MARGIN);
        assert_eq!(depth_slack(side(&cube(0.00095)), side(&wall)), None);
        assert_eq!(depth_slack(side(&cube(0.0012)), side(&wall)), None);
        // Two primitives with eroded forms: a box 0.2 mm into the ball, the box eroded by 1 mm
        // and the ball by 1 mm; the least of the two eroded gaps (0.8 mm each).
        let block =
            placed(SharedShape::cuboid(0.05, 0.05, 0.05), Some(SharedShape::cuboid(0.049, 0.049, 0.049)), up(0.0));
        let on_top = placed(SharedShape::ball(0.05), Some(SharedShape::ball(0.049)), up(0.0998));
        assert_near(depth_slack(side(&block), side(&on_top)), 0.0008 - DEPTH_MARGIN);
        let pair = SharedShape::compound(vec![
            (PPose::IDENTITY, SharedShape::cuboid(0.05, 0.05, 0.05)),
            (up(0.2), SharedShape::cuboid(0.05, 0.05, 0.05)),
        ]);
        assert_eq!(depth_slack(side(&placed(pair, None, up(0.0997))), side(&wall)), None);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Whatever rigid motion moves no point of a touching shape by its depth slack or more
        /// leaves the pair clear as [`near`] sees contact: a ball or a box with their eroded
        /// forms, or a hull, turned any way, into a wall or a hull block by up to 1.2 mm.
        #[test]
        fn moving_less_than_the_depth_slack_never_makes_contact(
            kind in 0usize..3,
            block in any::<bool>(),
            depth in 0.0f64..0.0012,
            turn in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            axis in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            centre in (-0.1f64..0.1, -0.1f64..0.1, -0.1f64..0.1),
            shift in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
            spin in 0.0f64..1.0,
            fraction in 0.0f64..0.999,
        ) {
            let fixed = match block {
                false => wall(),
                true => placed(hull_box(Vector::new(0.3, 0.3, 0.05)), None, PPose::IDENTITY),
            };
            let (shape, eroded) = match kind {
                0 => (SharedShape::ball(0.05), Some(SharedShape::ball(0.049))),
                1 => (SharedShape::cuboid(0.04, 0.06, 0.05), Some(SharedShape::cuboid(0.039, 0.059, 0.049))),
                _ => (
                    SharedShape::convex_hull(&[
                        Vector::new(0.06, 0.0, -0.03), Vector::new(-0.04, 0.05, -0.02), Vector::new(-0.03, -0.05, 0.0),
                        Vector::new(0.0, 0.01, 0.07), Vector::new(0.02, -0.02, -0.05),
                    ])
                    .expect("a hull"),
                    None,
                ),
            };
            let direction = |v: (f64, f64, f64)| {
                let v = Vector::new(v.0, v.1, v.2);
                if v.length() > 1e-3 { v.normalize() } else { Vector::X }
            };
            let rotation = Rotation::from_axis_angle(direction(turn), 3.0 * Vector::new(turn.0, turn.1, turn.2).length());
            // Its lowest point `depth` below the top face at z = 0.05.
            let lowest = shape.compute_aabb(&PPose::from_parts(Vector::ZERO, rotation)).mins.z;
            let start = PPose::from_parts(Vector::new(0.0, 0.0, 0.05 - depth - lowest), rotation);
            let moving = placed(shape.clone(), eroded.clone(), start);
            let slack = depth_slack(side(&moving), side(&fixed));
            prop_assume!(slack.is_some());
            let slack = slack.unwrap_or(0.0);
            // Turn by `angle` about an axis through `c`, then shift by `v`: no point within
            // `reach` of `c` moves more than angle · reach + |v|.
            let c = start.translation + Vector::new(centre.0, centre.1, centre.2);
            let reach = (start.translation - c).length() + shape.compute_local_bounding_sphere().radius;
            let (angle, v) = (spin, Vector::new(shift.0, shift.1, shift.2));
            let scale = fraction * slack / (angle * reach + v.length()).max(1e-12);
            let about = PPose::from_parts(c, Rotation::from_axis_angle(direction(axis), angle * scale));
            let motion = PPose::from_parts(v * scale, Rotation::IDENTITY) * about * PPose::from_parts(-c, Rotation::IDENTITY);
            let moved = placed(shape, eroded, motion * start);
            prop_assert!(
                near(side(&moved), side(&fixed), 0.0).is_none(),
                "slack {} moved up to {}: contact", slack, fraction * slack
            );
        }
    }

    /// Runs are each body's shapes in order; a body in two runs, or one the robot does not
    /// have, leaves the walk to find them.
    #[test]
    fn each_bodys_shapes_are_its_run_or_there_are_no_runs() {
        assert_eq!(body_runs(&posed(&[0, 0, 2, 2, 2, 3]), 5), Some(vec![0..2, 0..0, 2..5, 5..6, 0..0]));
        assert_eq!(body_runs(&posed(&[]), 2), Some(vec![0..0, 0..0]));
        assert_eq!(body_runs(&posed(&[0, 1, 0]), 2), None);
        assert_eq!(body_runs(&posed(&[0, 2]), 2), None);
    }
}
