//! How far a point of a robot can move per unit of joint motion *at one configuration*:
//! [`JointReach`] bounds it in every configuration (the chain's link offsets added end to
//! end, as if the arm stood stretched out from every joint), this measures the distance
//! from each joint's axis to what it moves as the arm stands.
//!
//! [`JointReach`]: super::JointReach

use nalgebra::{Isometry3, Point3};

use super::chain::Source;
use super::robot::RobotModel;
use super::sweep::{link_step, own_radii};
use super::urdf::Motion;
use super::World;
use crate::resolve::RobotId;

/// One link driven by a joint value, and where to measure from.
struct Driven {
    link: usize,
    index: usize,
    /// `|mult|` of a turning joint; `None` for a sliding one (it moves every point by its travel).
    turn: Option<f64>,
    /// The links below it (itself included) whose origins are measured: itself and every
    /// link driven by a joint value; the others hang from one of them rigidly or by a
    /// frozen joint, and are covered by that one's `tail`.
    anchors: Vec<usize>,
    /// Whether the flange is below it (a carried object moves with it).
    flange: bool,
}

/// See the module: built once per robot, then asked at each configuration.
pub struct ReachAt<'w> {
    model: &'w RobotModel,
    driven: Vec<Driven>,
    /// Per link: how far from its origin a point of it, or of the links hanging from it by
    /// joints no joint value drives, can be (in every finger posture).
    tail: Vec<f64>,
}

impl World {
    /// The robot's [`ReachAt`].
    pub fn reach_at(&self, r: RobotId) -> ReachAt<'_> {
        let m = &self.robots[r.index()];
        let links = &m.chain.links;
        let own = own_radii(m);
        let active = |l: usize| matches!(links[l].source, Source::Active { .. });
        // Children before parents: each link's tail takes its undriven children's.
        let mut tail = own;
        for l in (1..links.len()).rev() {
            if let Some(p) = links[l].parent {
                if !active(l) {
                    tail[p] = tail[p].max(link_step(m, l) + tail[l]);
                }
            }
        }
        let below = |l: usize, k: usize| {
            let mut at = Some(k);
            while let Some(x) = at {
                if x == l {
                    return true;
                }
                at = links[x].parent;
            }
            false
        };
        let driven = (0..links.len())
            .filter_map(|l| match links[l].source {
                Source::Active { index, mult, .. } => {
                    let turn = match links[l].motion {
                        Motion::Rotate(_) => Some(mult.abs()),
                        Motion::Slide(_) => None,
                        Motion::Fixed => return None,
                    };
                    let anchors = (0..links.len()).filter(|&k| (k == l || active(k)) && below(l, k)).collect();
                    Some(Driven { link: l, index, turn, anchors, flange: below(l, m.chain.flange) })
                }
                _ => None,
            })
            .collect();
        ReachAt { model: m, driven, tail }
    }
}

impl ReachAt<'_> {
    /// Per actuated joint at `q`: the distance from its axis to the farthest point it
    /// moves (times `|mult|` for each link it drives; 1 for a sliding joint), counting an
    /// object carried within `held_radius` of the flange's origin. `links` is scratch.
    pub fn at(&self, q: &[f64], held_radius: f64, links: &mut Vec<Isometry3<f64>>, out: &mut Vec<f64>) {
        let chain = &self.model.chain;
        links.clear();
        links.resize(chain.links.len(), Isometry3::identity());
        chain.fk_into(q, links);
        out.clear();
        out.resize(chain.dof(), 0.0);
        for d in &self.driven {
            let Some(turn) = d.turn else {
                out[d.index] += 1.0;
                continue;
            };
            let Motion::Rotate(axis) = chain.links[d.link].motion else { continue };
            // The joint turns its link about `axis` through the link's origin; turning
            // leaves both where they are.
            let pose = &links[d.link];
            let (origin, u) = (pose.translation.vector, pose.rotation * axis.into_inner());
            let from_axis = |p: &Point3<f64>| {
                let v = p.coords - origin;
                (v - u * v.dot(&u)).norm()
            };
            let mut far = 0.0f64;
            for &a in &d.anchors {
                far = far.max(from_axis(&Point3::from(links[a].translation.vector)) + self.tail[a]);
            }
            if d.flange {
                far = far.max(from_axis(&Point3::from(links[chain.flange].translation.vector)) + held_radius);
            }
            out[d.index] += turn * far;
        }
    }
}
