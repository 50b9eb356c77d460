//! The planner's memory of the robot's own part of its checks: at a configuration, what
//! the arm's bodies meet (blocked, or which objects), whatever is absent or carried.
//!
//! The labelled check has two parts: the robot's bodies against the scene and each other,
//! then what it carries. The first depends only on the configuration and the fingers'
//! posture: an absent object only drops out of its labels, and the carried object is
//! absent from the scene. The planner asks for the same configuration in many contexts
//! (an edge is labelled with the hand empty and again carrying each object it may carry;
//! every query's paths start at home): on the paper's Example 3, 9 621 of the 11 346
//! checks made while carrying had the robot's part at that configuration already. So the
//! robot's part is kept per configuration, taken with nothing absent, and each check
//! takes its absent objects out of it, then checks only what is carried. Only the planner
//! keeps one (see [`super::CheckCtx::memo`]): the verifier checks everything itself.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::Mutex;

use super::Check;
use crate::resolve::RobotId;

/// Answers kept at most; beyond that new ones are not kept (about 120 bytes an answer:
/// a long search's memory stays bounded).
const KEPT: usize = 1 << 20;

/// Joints a kept configuration may have (a longer arm is never remembered).
const JOINTS: usize = 9;

/// A multiply-rotate hash of the key's words (the keys are ours, not an adversary's, and
/// the standard SipHash would cost a good part of what a hit saves).
#[derive(Default)]
struct WordHasher(u64);

impl Hasher for WordHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    fn write_u8(&mut self, x: u8) {
        self.write_u64(u64::from(x));
    }
}

/// Robot, posture, and the joint values to the bit.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct Key {
    robot: u32,
    posture: u32,
    joints: u8,
    q: [u64; JOINTS],
}

impl Key {
    fn new(r: RobotId, q: &[f64], posture: usize) -> Option<Key> {
        if q.len() > JOINTS {
            return None;
        }
        let mut bits = [0; JOINTS];
        for (b, v) in bits.iter_mut().zip(q) {
            *b = v.to_bits();
        }
        Some(Key { robot: r.0, posture: u32::try_from(posture).ok()?, joints: q.len() as u8, q: bits })
    }
}

/// The robot's part of checks at configurations asked about before (shared by the
/// planner's threads).
#[derive(Default)]
pub struct CheckMemo {
    answers: Mutex<HashMap<Key, Check, BuildHasherDefault<WordHasher>>>,
}

impl std::fmt::Debug for CheckMemo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kept = self.answers.lock().map_or(0, |a| a.len());
        f.debug_struct("CheckMemo").field("kept", &kept).finish()
    }
}

impl CheckMemo {
    /// The robot's part at `q` in `posture` (everything there), if kept.
    pub(super) fn robot_part(&self, r: RobotId, q: &[f64], posture: usize) -> Option<Check> {
        let key = Key::new(r, q, posture)?;
        // A poisoned lock (a panic elsewhere) only costs the memory, never an answer.
        self.answers.lock().ok()?.get(&key).cloned()
    }

    /// Keeps the robot's part at `q` in `posture`.
    pub(super) fn keep(&self, r: RobotId, q: &[f64], posture: usize, part: &Check) {
        let Some(key) = Key::new(r, q, posture) else { return };
        if let Ok(mut answers) = self.answers.lock() {
            if answers.len() < KEPT {
                answers.insert(key, part.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::resolve::ObjectId;
    use crate::world::check::check_parts;
    use crate::world::test_arms::example;
    use crate::world::{CheckCtx, ObjectSet};

    /// On shipped examples with objects (the gripper's fingers close on what they carry),
    /// configurations near grasps (where objects are touched) and anywhere (where the
    /// table and the arm itself block), each asked four times in random contexts: objects
    /// absent, one carried (in its grasp's posture), the robot's part or the carried
    /// object's alone. A check with the memory answers as one without it every time, the
    /// block included. Of the 2 256 checks 1 333 take the robot's part from memory, 813 are
    /// blocked and 549 touch objects (a memory keyed without the posture, or one that kept
    /// the labels of absent objects, fails it: checked).
    #[test]
    fn a_check_with_the_robots_part_remembered_is_the_check() {
        let (mut remembered, mut blocked, mut touching) = (0, 0, 0);
        for name in ["cans_5", "box_lid", "gripper"] {
            let w = example(name);
            let objects = w.scenario().objects.len() as u32;
            let memo = Arc::new(CheckMemo::default());
            let mut rng = ChaCha8Rng::seed_from_u64(5);
            for ri in 0..w.scenario().robots.len() {
                let r = RobotId(ri as u32);
                let limits = w.limits(r).to_vec();
                let grasps: Vec<_> = (0..objects)
                    .flat_map(|o| w.select_grasps(r, ObjectId(o)).into_iter().map(move |g| (o, g)))
                    .collect();
                let helds: Vec<_> =
                    grasps.iter().step_by(5).map(|(o, g)| w.held(r, ObjectId(*o), g.grasp, &g.q_grasp)).collect();
                for k in 0..120 {
                    let q: Vec<f64> = match grasps.get(k % 7 * 3) {
                        Some((_, g)) if k % 2 == 0 => {
                            g.q_grasp.iter().map(|v| v + rng.random_range(-0.05..=0.05)).collect()
                        }
                        _ => limits.iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect(),
                    };
                    for _ in 0..4 {
                        let mut absent = ObjectSet::new();
                        if objects > 0 && rng.random_bool(0.5) {
                            absent.insert(ObjectId(rng.random_range(0..objects)));
                        }
                        let held = match helds.is_empty() || rng.random_bool(0.5) {
                            true => None,
                            false => helds.get(rng.random_range(0..helds.len())).cloned(),
                        };
                        let robot_part = held.is_none() || rng.random_bool(0.7);
                        let posture = held.as_ref().map_or(crate::world::OPEN_POSTURE, |h| h.posture);
                        remembered += usize::from(robot_part && memo.robot_part(r, &q, posture).is_some());
                        let plain = CheckCtx { absent: absent.clone(), held: held.clone(), ..CheckCtx::default() };
                        let with = CheckCtx { absent, held, memo: Some(memo.clone()), ..CheckCtx::default() };
                        let expected = check_parts(&w, r, &q, &plain, robot_part);
                        assert_eq!(check_parts(&w, r, &q, &with, robot_part), expected, "{name}: {q:?}");
                        match expected {
                            Check::Blocked(_) => blocked += 1,
                            Check::Touches(l) => touching += usize::from(!l.is_empty()),
                        }
                    }
                }
            }
        }
        assert!(remembered > 1000 && blocked > 200 && touching > 200, "{remembered} {blocked} {touching}");
    }
}
