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
    shape_distance, BodyInfo, Held, HeldPart, ObjectSet, PosedShape, StaticOwner, StaticShape, World, CONTACT_TOLERANCE,
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
    pub clearance: f64,
}

/// Reused buffers: posed robots and carried objects.
#[derive(Default)]
pub(super) struct Scratch {
    pub posed: Vec<Vec<PosedShape>>,
    pub held: Vec<Vec<HeldPart>>,
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
        Cell { world, statics, bvh, robots, clearance }
    }

    /// Every robot's shapes and what it carries, posed at this instant.
    pub fn pose(&self, at: &[RobotAt], s: &mut Scratch) {
        let w = self.world;
        s.posed.resize_with(at.len(), Vec::new);
        s.held.resize_with(at.len(), Vec::new);
        for (ri, ra) in at.iter().enumerate() {
            let flange = w.pose_shapes_bounded(RobotId(ri as u32), ra.q, ra.held, &mut s.posed[ri]);
            s.held[ri] = ra.held.map(|h| w.pose_held(h, &flange)).unwrap_or_default();
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
    use parry3d_f64::shape::SharedShape;

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
