//! Whether a configuration touches nothing at all: the labelled check's verdict when that
//! is `Touches(∅)`, found sooner when it is not. A free-space tree's step in a narrow
//! passage mostly ends inside something, and mostly inside what the step before ended
//! in: the last few moving bodies and scene entries that met are tried first, then the
//! labelled check's scan in body order. Trying a pair first changes no verdict (a pair
//! that meets is a contact whichever finds it), so the answer is the scan's, whatever
//! the thread checked before.

use parry3d_f64::bounding_volume::BoundingVolume;

use super::check::{
    body_meets_entry, check_posed, count_placed, count_within_limits, pose_robot, size_separating, CheckCtx, Scratch,
    SCRATCH,
};
use super::robot::RobotModel;
use super::scene::Owner;
use super::OPEN_POSTURE as OPEN;
use super::{Check, World};
use crate::resolve::RobotId;

/// How many pairs are tried first: six took 1.6–1.9 % off the Panda's and the UR5's
/// `narrow_gap` median problems against three (with three, a third of the configurations
/// the scan found blocked were blocked by a fixed body none of the three named); ten no
/// more.
const RECENT: usize = 6;

/// The (moving body, scene entry) pairs that met last, the latest first. Left from whatever
/// robot or world the thread checked before, a pair is only tried where it names a moving
/// body and an entry of this robot's scene that the check would test.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Recent {
    pairs: [(usize, u32); RECENT],
    len: usize,
}

impl Recent {
    /// `pair` to the front, the others kept in order.
    fn touch(&mut self, pair: (usize, u32)) {
        let at = self.pairs[..self.len].iter().position(|p| *p == pair).unwrap_or_else(|| {
            self.len = (self.len + 1).min(RECENT);
            self.len - 1
        });
        self.pairs.copy_within(0..at, 1);
        self.pairs[0] = pair;
    }
}

/// Whether robot `r` at `q` touches nothing: no object (not absent), fixed body, other
/// robot or itself, nor does what it carries; exactly when [`super::check::check`] says
/// `Touches` with no label. Counts one check in `ctx`.
pub(crate) fn touches_nothing(w: &World, r: RobotId, q: &[f64], ctx: &CheckCtx) -> bool {
    answer(w, r, q, ctx).0
}

/// [`touches_nothing`], and whether a recent pair gave the answer.
fn answer(w: &World, r: RobotId, q: &[f64], ctx: &CheckCtx) -> (bool, bool) {
    let m = &w.robots[r.index()];
    if count_within_limits(m, q, ctx).is_some() {
        return (false, false);
    }
    SCRATCH.with(|cell| {
        let mut s = cell.borrow_mut();
        let posture = ctx.held.as_ref().map_or(OPEN, |h| h.posture);
        pose_robot(m, q, posture, &mut s);
        size_separating(m, &mut s);
        let recent = s.recent;
        for &(bi, leaf) in &recent.pairs[..recent.len] {
            if tested(m, ctx, &s, bi, leaf) && body_meets_entry(m, &mut s, bi, leaf, &ctx.inner_proved) {
                s.recent.touch((bi, leaf));
                count_placed(ctx, &s);
                return (false, true);
            }
        }
        let check = check_posed(w, m, ctx, &mut s, true, (q, posture));
        if let Some(hit) = s.hit {
            s.recent.touch(hit);
        }
        count_placed(ctx, &s);
        (matches!(check, Check::Touches(l) if l.is_empty()), false)
    })
}

/// Whether the labelled check tests moving body `bi` against scene entry `leaf` at this
/// configuration (their boxes meet, and the entry is not an object absent or carried).
fn tested(m: &RobotModel, ctx: &CheckCtx, s: &Scratch, bi: usize, leaf: u32) -> bool {
    let (Some(b), Some(e)) = (m.bodies.get(bi), m.scene.entries.get(leaf as usize)) else { return false };
    if !b.moving {
        return false;
    }
    if let Owner::Object(o) = e.owner {
        if ctx.not_there(o) {
            return false;
        }
    }
    s.body_aabb.get(bi).is_some_and(|a| a.intersects(&e.aabb))
}

#[cfg(test)]
mod tests {
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::resolve::ObjectId;
    use crate::world::test_arms::example;
    use crate::world::ObjectSet;

    /// On shipped examples with objects, walks of configurations each near the one
    /// before (so the same pairs meet again), a new random set of objects absent at each:
    /// the answer is the labelled check's, and over a third of the blocked ones (988 of
    /// 2 214) are answered by a recent pair. A pair tried without the check's rules (an
    /// absent object tried) fails it.
    #[test]
    fn the_answer_is_the_labelled_checks_and_recent_pairs_give_many() {
        let (mut blocked, mut early) = (0, 0);
        for name in ["cans_5", "clutter", "shelf", "walled", "three_arm"] {
            let w = example(name);
            let objects = w.scenario().objects.len();
            let mut rng = ChaCha8Rng::seed_from_u64(7);
            for ri in 0..w.scenario().robots.len() {
                let r = RobotId(ri as u32);
                let limits = w.limits(r).to_vec();
                let mut q: Vec<f64> = limits.iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect();
                for _ in 0..400 {
                    for (v, (lo, hi)) in q.iter_mut().zip(&limits) {
                        *v = (*v + rng.random_range(-0.15..=0.15)).clamp(*lo, *hi);
                    }
                    let mut absent = ObjectSet::new();
                    for o in 0..objects {
                        if rng.random_bool(0.3) {
                            absent.insert(ObjectId(o as u32));
                        }
                    }
                    let ctx = CheckCtx::with_absent(absent.clone());
                    let labelled = matches!(w.check(r, &q, &ctx), Check::Touches(l) if l.is_empty());
                    let (clear, by_recent) = answer(&w, r, &q, &CheckCtx::with_absent(absent));
                    assert_eq!(clear, labelled, "{name}, robot {ri} at {q:?}");
                    blocked += usize::from(!clear);
                    early += usize::from(by_recent);
                }
            }
        }
        assert!(blocked > 1000 && early * 3 > blocked, "{early} of {blocked} blocked answered early");
    }

    /// The latest first, each pair once, the oldest dropped past [`RECENT`].
    #[test]
    fn the_latest_pair_comes_first_and_the_oldest_goes() {
        let mut r = Recent::default();
        r.touch((1, 10));
        r.touch((2, 20));
        r.touch((1, 10));
        assert_eq!(&r.pairs[..r.len], &[(1, 10), (2, 20)]);
        for k in 3..RECENT + 3 {
            r.touch((k, 10 * k as u32));
        }
        // Pairs 1 and 2 are the oldest: gone; the rest latest first.
        let kept: Vec<(usize, u32)> = (3..RECENT + 3).rev().map(|k| (k, 10 * k as u32)).collect();
        assert_eq!(&r.pairs[..r.len], &kept[..]);
        r.touch((4, 40));
        assert_eq!(r.pairs[0], (4, 40));
        assert_eq!(&r.pairs[1..r.len], &kept.iter().copied().filter(|p| *p != (4, 40)).collect::<Vec<_>>()[..]);
    }
}
