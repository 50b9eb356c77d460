//! The paper's `selectGrasps` (Algorithm 2): for a robot and an object, the
//! reachable grasp configurations and their pre-grasps at the approach stand-off;
//! a configuration blocked by something fixed is discarded. Also the per-object
//! reachability report `declutter check` prints.

use nalgebra::{Translation3, UnitQuaternion};
use serde::Serialize;

use super::{check, ik, segment, Check, CheckCtx, GraspConfig, ObjectSet, World, CERTIFY_PARTS};
use crate::resolve::{Grasp, ObjectId, Pose, RobotId};

/// How far the TCP may stray from the approach line on the final move in, where the
/// grasped object is not an obstacle (metres). A straight joint-space move between two
/// IK solutions bends a little: the shipped examples stray at most 5.5 mm over 14 cm.
pub const APPROACH_LATERAL_TOLERANCE: f64 = 0.01;
/// How far the TCP may go past the grasp point on the move in (metres).
pub const APPROACH_OVERSHOOT_TOLERANCE: f64 = 0.002;
/// How far the TCP may turn from the grasp orientation on the move in (radians): 2°.
pub const APPROACH_ANGLE_TOLERANCE: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// How a straight joint-space move strays from a grasp's straight approach: the TCP
/// should slide along the grasp's +z, from the stand-off to the grasp, without turning.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ApproachDeviation {
    /// Largest distance of the TCP from the approach segment (stand-off to grasp point).
    pub off_line: f64,
    /// Largest distance the TCP goes past the grasp point along +z.
    pub overshoot: f64,
    /// Largest angle between the TCP's orientation and the grasp's.
    pub angle: f64,
}

impl ApproachDeviation {
    /// Within [`APPROACH_LATERAL_TOLERANCE`], [`APPROACH_OVERSHOOT_TOLERANCE`] and
    /// [`APPROACH_ANGLE_TOLERANCE`]. NaN is never straight.
    pub fn is_straight(&self) -> bool {
        self.off_line <= APPROACH_LATERAL_TOLERANCE
            && self.overshoot <= APPROACH_OVERSHOOT_TOLERANCE
            && self.angle <= APPROACH_ANGLE_TOLERANCE
    }
}

/// The deviation of the straight joint-space move `a`..`b` from `grasp`'s approach, on
/// the samples of [`World::check_motion`] at `resolution`.
pub(crate) fn approach_deviation(
    w: &World,
    r: RobotId,
    grasp: &Grasp,
    a: &[f64],
    b: &[f64],
    resolution: f64,
) -> ApproachDeviation {
    let n = segment::steps(a, b, resolution, CERTIFY_PARTS);
    deviation_over(w, r, grasp, (a, b), n, 0..=n, false)
}

/// `approach_deviation(..).is_straight()`, the samples visited coarse to fine and the
/// first out of tolerance ending it: the same verdict (the largest deviation is within
/// a tolerance exactly when every sample's is). A pre-grasp in another posture strays
/// most mid-way, and such a move, hundreds of samples long, was most of the grasp
/// selection's forward kinematics on the paper's Example 3.
fn approach_is_straight(w: &World, r: RobotId, grasp: &Grasp, a: &[f64], b: &[f64], resolution: f64) -> bool {
    let n = segment::steps(a, b, resolution, CERTIFY_PARTS);
    deviation_over(w, r, grasp, (a, b), n, segment::coarse_to_fine(n), true).is_straight()
}

/// The deviation over samples `indices` of `n` on `a`..`b`; with `stop`, as soon as
/// it is out of tolerance.
fn deviation_over(
    w: &World,
    r: RobotId,
    grasp: &Grasp,
    (a, b): (&[f64], &[f64]),
    n: usize,
    indices: impl Iterator<Item = usize>,
    stop: bool,
) -> ApproachDeviation {
    let to_grasp = grasp.pose_world_tcp.inverse();
    let mut q = a.to_vec();
    let mut d = ApproachDeviation::default();
    // f64::max drops NaN; a NaN sample must make the move crooked, not straight.
    let worst = |acc: f64, v: f64| if v.is_nan() || acc.is_nan() { f64::NAN } else { acc.max(v) };
    for i in indices {
        segment::sample(a, b, i, n, &mut q);
        // The TCP in the grasp frame: the approach runs from z = -approach to z = 0.
        let rel = to_grasp * w.fk_tcp(r, &q);
        let p = rel.translation.vector;
        let along = p.z.clamp(-grasp.approach.max(0.0), 0.0);
        let off = (p.x * p.x + p.y * p.y + (p.z - along) * (p.z - along)).sqrt();
        d.off_line = worst(d.off_line, off);
        d.overshoot = worst(d.overshoot, p.z.max(0.0));
        d.angle = worst(d.angle, rel.rotation.angle());
        if stop && !d.is_straight() {
            break;
        }
    }
    d
}

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
            // A pre-grasp in another posture swings the hand through the object on the
            // way in, where the object is no obstacle: the verifier refuses that move.
            if !approach_is_straight(w, r, g, &pre, &q, scn.planner.resolution) {
                continue;
            }
            out.push(GraspConfig { grasp: gi, q_grasp: q, q_pregrasp: pre });
        }
    }
    out
}

/// Why one robot has no usable grasp of an object, for `check` to say (the first cause
/// that holds for every grasp, in the order the grasp selection meets them).
pub fn why_ungraspable(w: &World, r: RobotId, o: ObjectId) -> String {
    let scn = w.scenario();
    let hand = scn.robot(r).hand;
    let m = &w.robots[r.index()];
    let grasps: Vec<(usize, &Grasp)> = scn
        .object(o)
        .grasps
        .iter()
        .enumerate()
        .filter(|(_, g)| match (&g.hands, hand) {
            (None, _) => true,
            (Some(hs), Some(h)) => hs.contains(&h),
            (Some(_), None) => false,
        })
        .collect();
    if grasps.is_empty() {
        return "no grasp is for its hand".to_string();
    }
    let ctx = CheckCtx::with_absent(ObjectSet::single(o));
    let mut blocked_at_grasp = None;
    let mut blocked_on_approach = None;
    for &(gi, g) in &grasps {
        let seed = query_seed(scn.planner.seed, r, o, gi);
        for q in w.ik(r, &g.pose_world_tcp, seed, SOLUTIONS_PER_GRASP) {
            if let Check::Blocked(b) = w.check(r, &q, &ctx) {
                blocked_at_grasp.get_or_insert_with(|| check::describe(w, r, &b));
                continue;
            }
            let pre_pose: Pose = g.pose_world_tcp
                * nalgebra::Isometry3::from_parts(Translation3::new(0.0, 0.0, -g.approach), UnitQuaternion::identity());
            match ik::solve_near(m, &pre_pose, &q).map(|pre| w.check(r, &pre, &ctx)) {
                Some(Check::Blocked(b)) => {
                    blocked_on_approach.get_or_insert_with(|| check::describe(w, r, &b));
                }
                _ => {
                    blocked_on_approach
                        .get_or_insert_with(|| "the stand-off is not reached by a straight move in".into());
                }
            }
        }
    }
    if let Some(why) = blocked_on_approach {
        return format!("every approach is blocked ({why})");
    }
    if let Some(why) = blocked_at_grasp {
        return format!("every inverse-kinematics solution collides ({why})");
    }
    // No solution at all: say how far the grasps are against the arm's reach.
    let base = m.pose_world_base.translation.vector;
    let distance =
        grasps.iter().map(|(_, g)| (g.pose_world_tcp.translation.vector - base).norm()).fold(f64::INFINITY, f64::min);
    let reach: f64 = m.chain.links.iter().map(|l| l.pose_parent_joint.translation.vector.norm()).sum::<f64>()
        + m.pose_flange_tcp.translation.vector.norm();
    if distance > reach {
        format!(
            "out of reach: the nearest grasp is {distance:.2} m from its base, the arm reaches at most {reach:.2} m"
        )
    } else {
        format!(
            "no inverse-kinematics solution within the joint limits (the nearest grasp is {distance:.2} m from its base, within the arm's {reach:.2} m)"
        )
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// On the paper's Example 3, every grasp's IK solutions against every pre-grasp found
    /// near each of them (a pre-grasp near another solution makes a crooked move): the
    /// early-ending verdict is the full deviation's. Of the 684 moves 114 are straight and
    /// 570 crooked, so a verdict that ignored the samples would fail it.
    #[test]
    fn a_move_in_is_straight_exactly_when_its_deviation_says_so() {
        let w = crate::world::test_arms::example("cans_5");
        let scn = w.scenario();
        let (mut straight, mut crooked) = (0, 0);
        for ri in 0..scn.robots.len() {
            let r = RobotId(ri as u32);
            let m = &w.robots[ri];
            for o in scn.object_ids() {
                for (gi, g) in scn.object(o).grasps.iter().enumerate().step_by(3) {
                    let pre_pose: Pose = g.pose_world_tcp
                        * nalgebra::Isometry3::from_parts(
                            Translation3::new(0.0, 0.0, -g.approach),
                            UnitQuaternion::identity(),
                        );
                    let sols = w.ik(r, &g.pose_world_tcp, query_seed(7, r, o, gi), SOLUTIONS_PER_GRASP);
                    let pres: Vec<_> = sols.iter().filter_map(|q| ik::solve_near(m, &pre_pose, q)).collect();
                    for q in &sols {
                        for pre in &pres {
                            let res = scn.planner.resolution;
                            let full = approach_deviation(&w, r, g, pre, q, res).is_straight();
                            assert_eq!(approach_is_straight(&w, r, g, pre, q, res), full, "{}", g.name);
                            if full {
                                straight += 1;
                            } else {
                                crooked += 1;
                            }
                        }
                    }
                }
            }
        }
        assert_eq!((straight, crooked), (114, 570));
    }
}
