//! The premises of the replay's skipping ahead, on the shipped arms: a measured distance
//! is never more than the true one, and between two configurations a pair of shapes
//! comes closer by at most what the joints' reach bounds allow (against the scene, the
//! joints that move the body, each by the body's own reach; against the robot's own links,
//! only the joints that move one and not the other, each by the reach of the body it moves).

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::RobotId;
use declutter::world::{self, shape_distance, JointReach, PosedShape, World, WorldOptions};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn world_of(path: &str) -> World {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(std::path::Path::new(path), &FsLoader, &mut sources).expect("resolves");
    world::build(&scn, &WorldOptions::default(), &FsLoader).expect("builds")
}

fn distance(a: &PosedShape, b: &PosedShape) -> f64 {
    shape_distance(&a.pose, &*a.shape.0, &b.pose, &*b.shape.0).expect("primitives are measured")
}

/// Over random configurations and small random moves from them: how much closer any
/// pair came, against the bound; returns the largest ratio seen against the scene and
/// between the robot's own links.
fn worst_ratio(w: &World, r: RobotId, moves: usize, seed: u64) -> (f64, f64) {
    let reach = w.joint_reach(r).with_held(0.0);
    let body_reach = w.body_reach(r);
    let (moved_by, _) = w.body_joints(r);
    let pairs = w.self_pairs_unpruned(r);
    let statics = w.static_shapes();
    let limits = w.limits(r).to_vec();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut before, mut after) = (Vec::new(), Vec::new());
    let (mut worst, mut worst_self) = (0.0f64, 0.0f64);
    for _ in 0..moves {
        let q0: Vec<f64> = limits.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
        let q1: Vec<f64> = q0.iter().map(|v| v + rng.random_range(-0.05..0.05)).collect();
        let dq: Vec<f64> = q0.iter().zip(&q1).map(|(a, b)| b - a).collect();
        w.pose_shapes(r, &q0, None, &mut before);
        w.pose_shapes(r, &q1, None, &mut after);
        let judge = |worst: &mut f64, closer: f64, bound: f64| {
            assert!(closer <= bound + 1e-9, "came {closer} m closer, bound {bound} m (q0 {q0:?}, q1 {q1:?})");
            *worst = worst.max(closer / bound.max(1e-12));
        };
        // Against the scene: the joints that move the body, each by the body's own reach
        // (never more than the whole robot's bound).
        let all = JointReach::displacement(&reach, &dq);
        for (x0, x1) in before.iter().zip(&after) {
            let own: f64 = (0..dq.len()).map(|j| body_reach[x0.body][j] * dq[j].abs()).sum();
            assert!(own <= all + 1e-12, "body {}: {own} against the robot's {all}", x0.body);
            for e in &statics {
                let d0 = shape_distance(&x0.pose, &*x0.shape.0, &e.pose, &*e.shape.0).expect("measured");
                let d1 = shape_distance(&x1.pose, &*x1.shape.0, &e.pose, &*e.shape.0).expect("measured");
                judge(&mut worst, d0 - d1, own);
            }
        }
        // Against its own links: the joints between them only, each by the reach of the
        // body it moves (never more than the whole robot's).
        for &(a, b) in &pairs {
            let apart: f64 = (0..dq.len())
                .filter(|&j| moved_by[a][j] != moved_by[b][j])
                .map(|j| {
                    let moved = if moved_by[a][j] { a } else { b };
                    assert!(body_reach[moved][j] <= reach[j] + 1e-12, "body {moved} joint {j}");
                    body_reach[moved][j] * dq[j].abs()
                })
                .sum();
            for i in (0..before.len()).filter(|&i| before[i].body == a) {
                for k in (0..before.len()).filter(|&k| before[k].body == b) {
                    judge(&mut worst_self, distance(&before[i], &before[k]) - distance(&after[i], &after[k]), apart);
                }
            }
        }
    }
    (worst, worst_self)
}

#[test]
fn pairs_come_closer_no_faster_than_the_reach_bounds_allow() {
    // The TX-90 with its hand among clutter, and the arm with a parallel gripper. With
    // parry3d's own cuboid–cuboid distance the TX-90's links 2 and 4 broke this bound.
    for (path, robots) in [("examples/clutter.dcl", 2), ("examples/gripper.dcl", 1)] {
        let w = world_of(path);
        for r in 0..robots {
            let (worst, worst_self) = worst_ratio(&w, RobotId(r), 300, 7 + r as u64);
            // Not vacuous: some pair comes close to its bound, on both kinds.
            assert!(worst > 0.2, "{path} robot {r}: the bound is never approached ({worst})");
            assert!(worst_self > 0.2, "{path} robot {r}: the links' bound is never approached ({worst_self})");
        }
    }
}
