//! How fast a robot's points can move at a configuration, joint by joint: the farthest
//! point a joint turns from its own axis *there*, not in the worst configuration.
//!
//! [`super::JointReach`] holds in every configuration: a joint's reach is the length of
//! the chain below it, stretched out. An arm seldom is: along a path through a window
//! the Panda's first joint turns its farthest point 0.36–0.58 m from the axis, not
//! 1.13 m. The replay steps its instants by
//! how far a point can move, so a bound taken at the configuration lets it take about
//! 0.6 times as many where a path runs close to something.
//!
//! Over a stretch of motion the bound must hold at every instant, not at its ends: a
//! point's distance from joint `j`'s axis changes only by the joints below `j` (the axis
//! is fixed in `j`'s own link), by at most their static reach times how far they turn.

use nalgebra::{Isometry3, Point3, Unit, Vector3};

use super::chain::Source;
use super::robot::RobotModel;
use super::urdf::Motion;
use super::World;
use crate::resolve::RobotId;

/// One link a joint value moves, and what its reach is taken over.
struct Driven {
    link: usize,
    /// The joint value's index, its multiplier (mimic) and its axis in the link's frame;
    /// `None` for a sliding joint (every point moves as fast as the slide).
    index: usize,
    mult: f64,
    axis: Option<Unit<Vector3<f64>>>,
    /// The shapes on the link and below it (indices into `AxisReach::spheres`).
    shapes: Vec<usize>,
    /// Whether the flange is the link or below it (a carried object turns with it).
    flange: bool,
    /// Per joint value: whether it moves a link strictly below this one.
    below: Vec<bool>,
}

/// A robot's joint reaches at a configuration (see the module's documentation).
pub struct AxisReach<'w> {
    model: &'w RobotModel,
    /// Per shape: its link, and a ball holding it in every finger posture (centre in the
    /// link's frame, radius).
    spheres: Vec<(usize, Point3<f64>, f64)>,
    driven: Vec<Driven>,
    /// Per shape, its body; per body, per joint value: whether the joint moves it.
    shape_body: Vec<usize>,
    moves: Vec<Vec<bool>>,
    /// Per joint value: whether it slides a link (its reach is then not about an axis).
    slides: Vec<bool>,
    /// How far from the flange origin a carried point can be.
    held_radius: f64,
}

/// Per driven link: the farthest point it turns from its axis (metres), at one configuration.
pub type Farthest = Vec<f64>;

/// Per driven link and body: the same of the body's own points (see
/// [`AxisReach::bodies_farthest`]).
pub type BodiesFarthest = Vec<f64>;

/// Reused room for [`AxisReach::farthest`]: link poses and the balls' centres.
#[derive(Default)]
pub struct ReachScratch {
    links: Vec<Isometry3<f64>>,
    centres: Vec<Vector3<f64>>,
}

impl World {
    /// [`AxisReach`] of robot `r`, a carried object's points at most `held_radius` from
    /// the flange origin (0 when it carries nothing).
    pub fn axis_reach(&self, r: RobotId, held_radius: f64) -> AxisReach<'_> {
        AxisReach::new(&self.robots[r.index()], held_radius)
    }
}

impl<'w> AxisReach<'w> {
    fn new(m: &'w RobotModel, held_radius: f64) -> AxisReach<'w> {
        let chain = &m.chain;
        let spheres = m
            .shapes
            .iter()
            .enumerate()
            .map(|(si, s)| {
                let sphere = s.placed.shape.0.compute_local_bounding_sphere();
                let centre = |p: usize| m.shape_pose(si, p).transform_point(sphere.center);
                let c0 = centre(0);
                let radius = (0..m.postures.len().max(1))
                    .map(|p| (centre(p) - c0).length() + sphere.radius)
                    .fold(sphere.radius, f64::max);
                (m.bodies[s.body].link, Point3::new(c0.x, c0.y, c0.z), radius)
            })
            .collect::<Vec<_>>();
        // Whether link `x` is `l` or below it.
        let under = |x: usize, l: usize| {
            let mut k = Some(x);
            while let Some(y) = k {
                if y == l {
                    return true;
                }
                k = chain.links[y].parent;
            }
            false
        };
        let driven: Vec<Driven> = chain
            .links
            .iter()
            .enumerate()
            .filter_map(|(l, link)| {
                let Source::Active { index, mult, .. } = link.source else { return None };
                let axis = match link.motion {
                    Motion::Rotate(axis) => Some(axis),
                    Motion::Slide(_) => None,
                    Motion::Fixed => return None,
                };
                let mut below = vec![false; chain.dof()];
                for (k, other) in chain.links.iter().enumerate() {
                    if let Source::Active { index: i, .. } = other.source {
                        if k != l && under(k, l) && other.motion != Motion::Fixed {
                            below[i] = true;
                        }
                    }
                }
                Some(Driven {
                    link: l,
                    index,
                    mult: mult.abs(),
                    axis,
                    shapes: (0..spheres.len()).filter(|&s| under(spheres[s].0, l)).collect(),
                    flange: under(chain.flange, l),
                    below,
                })
            })
            .collect();
        let shape_body = m.shapes.iter().map(|s| s.body).collect();
        let moves = m
            .bodies
            .iter()
            .map(|b| {
                let mut mask = vec![false; chain.dof()];
                for d in driven.iter().filter(|d| under(b.link, d.link)) {
                    mask[d.index] = true;
                }
                mask
            })
            .collect();
        let mut slides = vec![false; chain.dof()];
        for d in driven.iter().filter(|d| d.axis.is_none()) {
            slides[d.index] = true;
        }
        AxisReach { model: m, spheres, driven, shape_body, moves, slides, held_radius }
    }

    /// The links' poses at `q`, and each shape's ball's centre (once, not once per joint
    /// that turns it), in `scratch`.
    fn pose<'s>(&self, q: &[f64], scratch: &'s mut ReachScratch) -> (&'s [Isometry3<f64>], &'s [Vector3<f64>]) {
        let chain = &self.model.chain;
        super::robot::assert_dof(self.model, q);
        let ReachScratch { links, centres } = scratch;
        links.clear();
        links.resize(chain.links.len(), Isometry3::identity());
        chain.fk_into(q, links);
        centres.clear();
        centres.extend(self.spheres.iter().map(|(l, c, _)| (links[*l] * c).coords));
        (links, centres)
    }

    /// Per driven link, the farthest point it turns from its axis at `q` (a sliding
    /// joint's entry is unused), into `out`.
    pub fn farthest(&self, q: &[f64], scratch: &mut ReachScratch, out: &mut Farthest) {
        let chain = &self.model.chain;
        let (links, centres) = self.pose(q, scratch);
        out.clear();
        for d in &self.driven {
            let Some(axis) = d.axis else {
                out.push(0.0);
                continue;
            };
            let o = links[d.link].translation.vector;
            let a = links[d.link].rotation * axis.into_inner();
            let from_axis = |p: Vector3<f64>| (p - o).cross(&a).norm();
            let mut far = 0.0f64;
            for &s in &d.shapes {
                far = far.max(from_axis(centres[s]) + self.spheres[s].2);
            }
            if d.flange && self.held_radius > 0.0 {
                far = far.max(from_axis(links[chain.flange].translation.vector) + self.held_radius);
            }
            out.push(far);
        }
    }

    /// Per driven link and body (`link * bodies + body`), the farthest point of the body it
    /// turns from its axis at `q` (metres); `-inf` where it does not turn the body (and for
    /// a sliding joint).
    pub fn bodies_farthest(&self, q: &[f64], scratch: &mut ReachScratch, out: &mut BodiesFarthest) {
        let (links, centres) = self.pose(q, scratch);
        let bodies = self.moves.len();
        out.clear();
        out.resize(self.driven.len() * bodies, f64::NEG_INFINITY);
        for (k, d) in self.driven.iter().enumerate() {
            let Some(axis) = d.axis else { continue };
            let o = links[d.link].translation.vector;
            let a = links[d.link].rotation * axis.into_inner();
            let far = &mut out[k * bodies..(k + 1) * bodies];
            for &s in &d.shapes {
                let b = self.shape_body[s];
                far[b] = far[b].max((centres[s] - o).cross(&a).norm() + self.spheres[s].2);
            }
        }
    }

    /// Per body, per joint value: how fast the joint can move the body's own points per
    /// unit of its speed at every instant of a motion from a configuration whose
    /// [`AxisReach::bodies_farthest`] is `at_a` to one whose is `at_b`, each joint value
    /// `i` turning by at most `turn[i]` (radians; metres for a slide) on the way. A point's
    /// distance from an axis changes only by the joints between the axis and the body
    /// (the joints above it move the axis with the body), each by the body's static reach
    /// for it times its turn: at any instant it is at most the distance at either end plus
    /// that drift from there, the lesser of which is at most their mean. Never above
    /// `own`, the body's static reach ([`World::body_reach`]), which a sliding joint keeps.
    pub fn bodies_over(
        &self,
        (at_a, at_b): (&BodiesFarthest, &BodiesFarthest),
        turn: &[f64],
        own: &[Vec<f64>],
        out: &mut Vec<Vec<f64>>,
    ) {
        let bodies = self.moves.len();
        out.resize_with(own.len(), Vec::new);
        for (o, own) in out.iter_mut().zip(own) {
            o.clear();
            o.resize(own.len(), 0.0);
        }
        for (k, d) in self.driven.iter().enumerate().filter(|(_, d)| d.axis.is_some()) {
            let (far_a, far_b) = (&at_a[k * bodies..(k + 1) * bodies], &at_b[k * bodies..(k + 1) * bodies]);
            for (b, (fa, fb)) in far_a.iter().zip(far_b).enumerate().filter(|(_, (fa, _))| fa.is_finite()) {
                let drift: f64 = d
                    .below
                    .iter()
                    .zip(&self.moves[b])
                    .zip(turn)
                    .zip(&own[b])
                    .filter(|(((below, moves), _), _)| **below && **moves)
                    .map(|((_, t), o)| o * t)
                    .sum();
                out[b][d.index] += d.mult * 0.5 * (fa + fb + drift);
            }
        }
        for (o, own) in out.iter_mut().zip(own) {
            for ((o, own), slides) in o.iter_mut().zip(own).zip(&self.slides) {
                *o = if *slides { *own } else { o.min(*own) };
            }
        }
    }

    /// Per joint value, how fast a point can move per unit of its speed at every instant
    /// of a motion from a configuration whose [`AxisReach::farthest`] is `at_a` to one
    /// whose is `at_b`, given `travel[i]`: a bound on how far joint `i` moves any point
    /// on the way (its static reach times how far it turns). Never above `reach`, the
    /// bound that holds everywhere.
    pub fn over(&self, at_a: &Farthest, at_b: &Farthest, travel: &[f64], reach: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.resize(reach.len(), 0.0);
        for ((d, a), b) in self.driven.iter().zip(at_a).zip(at_b) {
            let turn = match d.axis {
                None => 1.0,
                Some(_) => {
                    // At time t the distance is at most a + D(a, t) and b + D(t, b), with
                    // D(a, t) + D(t, b) ≤ D: the lesser of the two is at most their mean.
                    let drift: f64 = d.below.iter().zip(travel).filter(|(b, _)| **b).map(|(_, t)| t).sum();
                    0.5 * (a + b + drift)
                }
            };
            out[d.index] += d.mult * turn;
        }
        for (o, r) in out.iter_mut().zip(reach) {
            *o = o.min(*r);
        }
    }
}

#[cfg(test)]
#[path = "axis_reach_tests.rs"]
mod tests;
