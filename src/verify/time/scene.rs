//! The whole cell at one instant: every robot posed, carried objects in their hands,
//! objects in place or gone. Its own contact test on the world's shapes (parry queries),
//! not the planner's labelled check.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose as PPose;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::query;
use parry3d_f64::shape::{Shape, SharedShape};

use super::{Obstacle, Party};
use crate::resolve::{ObjectId, RobotId};
use crate::world::{BodyInfo, Held, ObjectSet, PosedShape, StaticOwner, StaticShape, World, CONTACT_TOLERANCE};

/// One robot at the instant.
pub(super) struct RobotAt<'a> {
    pub q: &'a [f64],
    pub held: Option<&'a Held>,
    /// An object in place this robot's hand may touch (on its straight move in).
    pub exempt: Option<ObjectId>,
}

/// Two things too close: overlapping (`None`) or nearer than the clearance.
pub(super) type Finding = (Party, Obstacle, Option<f64>);

struct RobotGeo {
    name: String,
    bodies: Vec<BodyInfo>,
    self_pairs: Vec<(usize, usize)>,
}

/// What stays the same across instants.
pub(super) struct Cell<'w> {
    world: &'w World,
    statics: Vec<StaticShape>,
    bvh: Bvh,
    robots: Vec<RobotGeo>,
    clearance: f64,
}

/// Reused buffers: posed robots and carried objects.
#[derive(Default)]
pub(super) struct Scratch {
    posed: Vec<Vec<PosedShape>>,
    held: Vec<Vec<(SharedShape, PPose, Aabb)>>,
}

impl<'w> Cell<'w> {
    pub fn new(world: &'w World, clearance: f64) -> Cell<'w> {
        let statics = world.static_shapes();
        let aabbs: Vec<Aabb> = statics.iter().map(|s| s.aabb.loosened(clearance)).collect();
        let bvh = if aabbs.is_empty() { Bvh::new() } else { Bvh::from_leaves(BvhBuildStrategy::default(), &aabbs) };
        let robots = (0..world.scenario().robots.len())
            .map(|ri| {
                let r = RobotId(ri as u32);
                RobotGeo {
                    name: world.scenario().robot(r).name.clone(),
                    bodies: world.bodies(r),
                    self_pairs: world.self_pairs_unpruned(r),
                }
            })
            .collect();
        Cell { world, statics, bvh, robots, clearance }
    }

    /// Everything too close at this instant. `present`: objects in place.
    pub fn check(&self, at: &[RobotAt], present: &ObjectSet, s: &mut Scratch, found: &mut Vec<Finding>) {
        let w = self.world;
        let c = self.clearance;
        s.posed.resize_with(at.len(), Vec::new);
        s.held.resize_with(at.len(), Vec::new);
        for (ri, ra) in at.iter().enumerate() {
            let flange = w.pose_shapes(RobotId(ri as u32), ra.q, &mut s.posed[ri]);
            s.held[ri] = ra.held.map(|h| w.pose_held(h, &flange)).unwrap_or_default();
        }
        for (ri, ra) in at.iter().enumerate() {
            let g = &self.robots[ri];
            let body = |b: usize| Party::Body { robot: g.name.clone(), body: g.bodies[b].name.clone() };
            let carried = |h: &Held| Party::Held {
                robot: g.name.clone(),
                object: w.scenario().object(h.object).body.name.clone(),
            };
            // Moving bodies against the scene, with the clearance.
            for ps in s.posed[ri].iter().filter(|ps| g.bodies[ps.body].moving) {
                let skip = |o: ObjectId| {
                    !present.contains(o) || Some(o) == ra.exempt || ra.held.is_some_and(|h| h.object == o)
                };
                if let Some((obs, d)) = self.against_statics(&ps.aabb, &ps.pose, &*ps.shape.0, c, skip) {
                    push(found, body(ps.body), obs, d);
                }
            }
            // Self-collision over the unpruned pairs: contact only.
            for &(a, b) in &g.self_pairs {
                let hit = s.posed[ri]
                    .iter()
                    .filter(|x| x.body == a)
                    .any(|x| s.posed[ri].iter().filter(|y| y.body == b).any(|y| too_close(x, y, 0.0).is_some()));
                if hit {
                    push(found, body(a), Obstacle::Moving(body(b)), None);
                }
            }
            // The carried object: against the scene and its carrier's own links, contact only.
            if let Some(h) = ra.held {
                for (shape, pose, aabb) in &s.held[ri] {
                    let skip = |o: ObjectId| !present.contains(o) || o == h.object;
                    if let Some((obs, d)) = self.against_statics(aabb, pose, &*shape.0, 0.0, skip) {
                        push(found, carried(h), obs, d);
                    }
                    for ps in s.posed[ri].iter().filter(|ps| !g.bodies[ps.body].holds) {
                        if aabb.intersects(&ps.aabb) && pair(pose, &**shape, &ps.pose, &*ps.shape.0, 0.0).is_some() {
                            push(found, carried(h), Obstacle::Moving(body(ps.body)), None);
                            break;
                        }
                    }
                }
            }
            // Against every later robot and what it carries, with the clearance.
            for (rj, rb) in at.iter().enumerate().skip(ri + 1) {
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
                        if let Some(d) = too_close(x, y, c) {
                            push(found, body(x.body), Obstacle::Moving(other(y.body)), d);
                        }
                    }
                    if let Some(h) = rb.held {
                        for (shape, pose, aabb) in &s.held[rj] {
                            if let Some(d) = near_aabb(&x.aabb, aabb, c)
                                .then(|| pair(&x.pose, &*x.shape, pose, &**shape, c))
                                .flatten()
                            {
                                push(found, body(x.body), Obstacle::Moving(other_carried(h)), d);
                            }
                        }
                    }
                }
                if let Some(h) = ra.held {
                    for (shape, pose, aabb) in &s.held[ri] {
                        for y in &s.posed[rj] {
                            if let Some(d) = near_aabb(aabb, &y.aabb, c)
                                .then(|| pair(pose, &**shape, &y.pose, &*y.shape, c))
                                .flatten()
                            {
                                push(found, carried(h), Obstacle::Moving(other(y.body)), d);
                            }
                        }
                        if let Some(hj) = rb.held {
                            for (shape2, pose2, aabb2) in &s.held[rj] {
                                if let Some(d) = near_aabb(aabb, aabb2, c)
                                    .then(|| pair(pose, &**shape, pose2, &**shape2, c))
                                    .flatten()
                                {
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
        aabb: &Aabb,
        pose: &PPose,
        shape: &dyn Shape,
        clearance: f64,
        skip: impl Fn(ObjectId) -> bool,
    ) -> Option<(Obstacle, Option<f64>)> {
        let scn = self.world.scenario();
        for leaf in self.bvh.intersect_aabb(aabb) {
            let e = &self.statics[leaf as usize];
            if let StaticOwner::Object(o) = e.owner {
                if skip(o) {
                    continue;
                }
            }
            if !near_aabb(aabb, &e.aabb, clearance) {
                continue;
            }
            if let Some(d) = pair(pose, shape, &e.pose, &*e.shape.0, clearance) {
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

fn push(found: &mut Vec<Finding>, a: Party, b: Obstacle, d: Option<f64>) {
    if !found.iter().any(|(x, y, _)| *x == a && *y == b) {
        found.push((a, b, d));
    }
}

fn near_aabb(a: &Aabb, b: &Aabb, clearance: f64) -> bool {
    a.loosened(clearance).intersects(b)
}

fn too_close(x: &PosedShape, y: &PosedShape, clearance: f64) -> Option<Option<f64>> {
    if !near_aabb(&x.aabb, &y.aabb, clearance) {
        return None;
    }
    pair(&x.pose, &*x.shape.0, &y.pose, &*y.shape.0, clearance)
}

/// `Some(None)`: overlapping deeper than the contact tolerance (no clearance asked);
/// `Some(Some(d))`: nearer than the clearance, at distance `d`; `None`: fine.
fn pair(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, clearance: f64) -> Option<Option<f64>> {
    if clearance > 0.0 {
        // A pair parry cannot measure counts as touching: never pass what was not checked.
        let d = query::distance(p1, s1, p2, s2).map_or(0.0, |d| d.distance);
        return (d < clearance).then_some(Some(d));
    }
    let touching = match query::intersection_test(p1, s1, p2, s2) {
        Ok(i) if !i.intersecting => false,
        _ => match query::contact(p1, s1, p2, s2, 0.0) {
            Ok(Some(c)) => c.dist < -CONTACT_TOLERANCE,
            Ok(None) => false,
            Err(_) => true,
        },
    };
    touching.then_some(None)
}
