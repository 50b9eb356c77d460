//! The paper's `selectGrasps` (Algorithm 2): for a robot and an object, the
//! reachable grasp configurations and their pre-grasps at the approach stand-off;
//! a configuration blocked by something fixed is discarded. Also the per-object
//! reachability report `declutter check` prints.

use nalgebra::{Translation3, UnitQuaternion};
use serde::Serialize;

use super::{ik, CheckCtx, GraspConfig, ObjectSet, World};
use crate::resolve::{ObjectId, Pose, RobotId};

/// IK solutions kept per grasp: the postures (elbow, wrist flip, a ±270° wrist joint
/// wrapped by a turn) the planner may choose among. Each one more costs IK starts on
/// every grasp; the shipped examples reach the same outcomes with 6 as with 8
/// (tests/examples.rs), a quarter faster.
const SOLUTIONS_PER_GRASP: usize = 6;

/// Seed of one IK query, from the scenario seed and the query's identity.
fn query_seed(base: u64, r: RobotId, o: ObjectId, g: usize) -> u64 {
    let mut h = base ^ 0x9e37_79b9_7f4a_7c15;
    for x in [r.0 as u64, o.0 as u64, g as u64] {
        h = (h ^ x).wrapping_mul(0x100_0000_01b3).rotate_left(29);
    }
    h
}

pub(crate) fn select(w: &World, r: RobotId, o: ObjectId) -> Vec<GraspConfig> {
    let scn = w.scenario();
    let hand = scn.robot(r).hand;
    let m = &w.robots[r.index()];
    let ctx = CheckCtx::with_absent(ObjectSet::single(o));
    let mut out = Vec::new();
    for (gi, g) in scn.object(o).grasps.iter().enumerate() {
        let allowed = match (&g.hands, hand) {
            (None, _) => true,
            (Some(hs), Some(h)) => hs.contains(&h),
            (Some(_), None) => false,
        };
        if !allowed {
            continue;
        }
        let pre_pose: Pose = g.pose_world_tcp
            * nalgebra::Isometry3::from_parts(Translation3::new(0.0, 0.0, -g.approach), UnitQuaternion::identity());
        let seed = query_seed(scn.planner.seed, r, o, gi);
        for q in w.ik(r, &g.pose_world_tcp, seed, SOLUTIONS_PER_GRASP) {
            if w.check(r, &q, &ctx).is_blocked() {
                continue;
            }
            let Some(pre) = ik::solve_near(m, &pre_pose, &q) else { continue };
            if w.check(r, &pre, &ctx).is_blocked() {
                continue;
            }
            out.push(GraspConfig { grasp: gi, q_grasp: q, q_pregrasp: pre });
        }
    }
    out
}

/// Which robots can reach which grasps of one object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObjectReach {
    pub object: ObjectId,
    pub name: String,
    pub robots: Vec<RobotReach>,
}

impl ObjectReach {
    /// True when some robot has at least one reachable grasp.
    pub fn reachable(&self) -> bool {
        self.robots.iter().any(|r| !r.grasps.is_empty())
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotReach {
    pub robot: RobotId,
    pub name: String,
    /// Names of the grasps with at least one collision-free (w.r.t. fixed bodies) configuration.
    pub grasps: Vec<String>,
}

/// Per-object, per-robot grasp reachability, in object then robot order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GraspReport {
    pub objects: Vec<ObjectReach>,
}

impl GraspReport {
    /// Objects no robot can grasp (a warning for `declutter check`).
    pub fn unreachable(&self) -> impl Iterator<Item = &ObjectReach> {
        self.objects.iter().filter(|o| !o.reachable())
    }
}

/// Runs `select_grasps` for every robot and object.
pub fn report(w: &World) -> GraspReport {
    use rayon::prelude::*;
    let scn = w.scenario();
    let objects = scn
        .object_ids()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&o| ObjectReach {
            object: o,
            name: scn.object(o).body.name.clone(),
            robots: scn
                .robot_ids()
                .map(|r| {
                    let mut grasps: Vec<usize> = w.select_grasps(r, o).iter().map(|g| g.grasp).collect();
                    grasps.dedup();
                    RobotReach {
                        robot: r,
                        name: scn.robot(r).name.clone(),
                        grasps: grasps.into_iter().map(|g| scn.object(o).grasps[g].name.clone()).collect(),
                    }
                })
                .collect(),
        })
        .collect();
    GraspReport { objects }
}
