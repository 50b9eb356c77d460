//! A plain RRT-Connect (Kuffner and LaValle, 2000) in joint space, over the world's exact
//! check and nothing of the planner: the "standard planner" a user would compare against,
//! used to establish that a generated problem has a path at all. A configuration counts
//! as free only when it is blocked by nothing and touches no removable object, and a
//! motion is checked every [`STEP`] of the joint that moves most, as the planner
//! certifies its own paths (a quarter of the default 2° resolution).
#![allow(dead_code)]

use declutter::resolve::RobotId;
use declutter::world::{Check, CheckCtx, World};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Largest joint change between two checked configurations of a motion (radians).
pub const STEP: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Longest extension towards a random sample (joint space, Euclidean, radians).
const REACH: f64 = 0.3;

struct Tree {
    dof: usize,
    qs: Vec<f64>,
    parent: Vec<usize>,
}

impl Tree {
    fn new(root: &[f64]) -> Tree {
        Tree { dof: root.len(), qs: root.to_vec(), parent: vec![usize::MAX] }
    }
    fn q(&self, i: usize) -> &[f64] {
        &self.qs[i * self.dof..(i + 1) * self.dof]
    }
    fn nearest(&self, q: &[f64]) -> usize {
        (0..self.parent.len())
            .map(|i| (self.q(i).iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum::<f64>(), i))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map_or(0, |(_, i)| i)
    }
    fn add(&mut self, q: &[f64], parent: usize) -> usize {
        self.qs.extend_from_slice(q);
        self.parent.push(parent);
        self.parent.len() - 1
    }
    /// The configurations from the root to node `i`.
    fn path_to(&self, mut i: usize) -> Vec<Vec<f64>> {
        let mut out = vec![self.q(i).to_vec()];
        while self.parent[i] != usize::MAX {
            i = self.parent[i];
            out.push(self.q(i).to_vec());
        }
        out.reverse();
        out
    }
}

/// Free: blocked by nothing, touching no removable object.
pub fn free(w: &World, r: RobotId, q: &[f64]) -> bool {
    w.check(r, q, &CheckCtx::new()) == Check::free()
}

/// Every configuration of the straight motion a → b, a excluded, `STEP` apart, free.
pub fn motion_free(w: &World, r: RobotId, a: &[f64], b: &[f64]) -> bool {
    let span = a.iter().zip(b).map(|(x, y)| (y - x).abs()).fold(0.0, f64::max);
    let n = (span / STEP).ceil().max(1.0) as usize;
    let mut q = a.to_vec();
    (1..=n).all(|i| {
        let t = i as f64 / n as f64;
        for (k, v) in q.iter_mut().enumerate() {
            *v = a[k] + (b[k] - a[k]) * t;
        }
        free(w, r, &q)
    })
}

enum Grew {
    Reached(usize),
    Advanced(usize),
    Trapped,
}

fn extend(w: &World, r: RobotId, t: &mut Tree, target: &[f64]) -> Grew {
    let near = t.nearest(target);
    let from = t.q(near).to_vec();
    let d = from.iter().zip(target).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    let (to, reached) = if d <= REACH {
        (target.to_vec(), true)
    } else {
        (from.iter().zip(target).map(|(a, b)| a + (b - a) * REACH / d).collect(), false)
    };
    if !motion_free(w, r, &from, &to) {
        return Grew::Trapped;
    }
    let i = t.add(&to, near);
    if reached {
        Grew::Reached(i)
    } else {
        Grew::Advanced(i)
    }
}

/// A free path from `start` to `goal` (both included), or `None` after `iterations`.
pub fn rrt_connect(
    w: &World,
    r: RobotId,
    start: &[f64],
    goal: &[f64],
    iterations: usize,
    seed: u64,
) -> Option<Vec<Vec<f64>>> {
    if !free(w, r, start) || !free(w, r, goal) {
        return None;
    }
    let limits = w.limits(r).to_vec();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut a, mut b) = (Tree::new(start), Tree::new(goal));
    // `a` grows from the start while this is false.
    let mut swapped = false;
    for _ in 0..iterations {
        let q: Vec<f64> = limits.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
        let new = match extend(w, r, &mut a, &q) {
            Grew::Trapped => None,
            Grew::Reached(i) | Grew::Advanced(i) => Some(i),
        };
        if let Some(i) = new {
            let target = a.q(i).to_vec();
            // Connect: `b` grows towards the new node until it reaches it or is stopped.
            loop {
                match extend(w, r, &mut b, &target) {
                    Grew::Advanced(_) => continue,
                    Grew::Trapped => break,
                    Grew::Reached(j) => {
                        let (mut from_a, from_b) = (a.path_to(i), b.path_to(j));
                        from_a.extend(from_b.into_iter().rev().skip(1));
                        if swapped {
                            from_a.reverse();
                        }
                        return Some(from_a);
                    }
                }
            }
        }
        std::mem::swap(&mut a, &mut b);
        swapped = !swapped;
    }
    None
}
