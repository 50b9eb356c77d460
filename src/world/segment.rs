//! The segment checks: the configurations a straight joint-space motion is checked at,
//! and the order they are visited in (coarse to fine for the planner, every one in order
//! for the certifying check), each by the labelled check of [`super::check`].

use super::check::{check, check_parts, check_twin, CheckCtx};
use super::robot::assert_dof;
use super::{Check, ObjectSet, World, OPEN_POSTURE};
use crate::resolve::RobotId;

/// The planner's coarse segment check: the samples of `check_motion(.., 1, ..)`,
/// visited coarse-to-fine (ends, middle, quarters, ...) so a blocked segment, the
/// common case for long roadmap edges, is found after a few samples. The labels are
/// the same in any order; only which blocker is reported may differ.
pub(crate) fn check_segment(w: &World, r: RobotId, a: &[f64], b: &[f64], step: f64, ctx: &CheckCtx) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, 1), ctx, (true, (false, false)))
}

/// [`check_segment`] without the samples of its ends flagged in `known` (`a`, `b`),
/// whose checks the caller already has: their labels are the caller's to join.
pub(crate) fn check_segment_known(
    w: &World,
    r: RobotId,
    (a, b): (&[f64], &[f64]),
    step: f64,
    known: (bool, bool),
    ctx: &CheckCtx,
) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, 1), ctx, (true, known))
}

/// The samples of [`check_segment`], checking only the carried object (see
/// [`check_posed`]).
pub(crate) fn check_segment_held(w: &World, r: RobotId, a: &[f64], b: &[f64], step: f64, ctx: &CheckCtx) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, 1), ctx, (false, (false, false)))
}

/// The samples of `check_motion(.., step, parts, ..)` that [`check_segment`] at `step`
/// does not take (every `parts`-th is one of its: the same fractions of the segment,
/// hence the same configurations), coarse to fine. After a coarse check of the same
/// segment and context found labels `l` and no block, `l` joined with this one's labels
/// is `check_motion`'s answer, without checking the coarse samples twice.
pub(crate) fn check_motion_rest(
    w: &World,
    r: RobotId,
    a: &[f64],
    b: &[f64],
    (step, parts): (f64, usize),
    ctx: &CheckCtx,
) -> Check {
    segment_coarse_to_fine(w, r, a, b, (step, parts.max(2)), ctx, (true, (false, false)))
}

/// [`check_motion_rest`] of the same samples with the hand empty and in `carry` (see
/// [`label_samples_twin`]).
pub(crate) fn check_motion_rest_twin(
    w: &World,
    r: RobotId,
    (a, b): (&[f64], &[f64]),
    (step, parts): (f64, usize),
    carry: &CheckCtx,
) -> (Check, Check) {
    let parts = parts.max(2);
    let n = steps(a, b, step, parts);
    let indices: Vec<usize> = coarse_to_fine(n).filter(|&i| i % parts != 0).collect();
    label_samples_twin(w, r, (a, b), n, &indices, carry)
}

/// Sample `i` of `steps(a, b, step, parts) + 1` is skipped when `parts > 1` and `i` is a
/// multiple of `parts` (see [`check_motion_rest`]), and sample 0 or `n` (`a` or `b`) when
/// flagged in `known` (see [`check_segment_known`]).
fn segment_coarse_to_fine(
    w: &World,
    r: RobotId,
    a: &[f64],
    b: &[f64],
    (step, parts): (f64, usize),
    ctx: &CheckCtx,
    (robot_part, (known_a, known_b)): (bool, (bool, bool)),
) -> Check {
    let n = steps(a, b, step, parts);
    let indices =
        coarse_to_fine(n).filter(|&i| !((parts > 1 && i % parts == 0) || (known_a && i == 0) || (known_b && i == n)));
    label_samples(w, r, (a, b), n, indices, ctx, robot_part)
}

/// `0..=n` coarse to fine: sample 0 first (a non-finite end is blocked by the limits
/// check at once), then, per power of two from the least at or above `n` down, its
/// multiples not already visited as multiples of twice it (`n = 6`: 0, 4, 2, 6, 1, 3, 5).
pub(super) fn coarse_to_fine(n: usize) -> impl Iterator<Item = usize> {
    let top = n.checked_next_power_of_two().unwrap_or(usize::MAX / 2 + 1);
    let strides = std::iter::successors(Some(top), |&s| (s > 1).then_some(s / 2));
    strides.flat_map(move |s| match s == top {
        true => (0..=n).step_by(s),
        false => (s..=n).step_by(2 * s),
    })
}

/// The checks (the robot's own bodies too when `robot_part`) of samples `indices` of a ->
/// b cut into `n` steps, in turn, up to the first blocked: their labels' union or that block.
pub(super) fn label_samples(
    w: &World,
    r: RobotId,
    (a, b): (&[f64], &[f64]),
    n: usize,
    indices: impl Iterator<Item = usize>,
    ctx: &CheckCtx,
    robot_part: bool,
) -> Check {
    let m = &w.robots[r.index()];
    assert_dof(m, a);
    assert_dof(m, b);
    let mut q = a.to_vec();
    let mut out = ObjectSet::new();
    for i in indices {
        sample(a, b, i, n, &mut q);
        match check_parts(w, r, &q, ctx, robot_part) {
            Check::Blocked(bl) => return Check::Blocked(bl),
            Check::Touches(l) => out.union_with(&l),
        }
    }
    Check::Touches(out)
}

/// [`label_samples`] of the same samples with the hand empty and carrying `carry.held`,
/// each up to its own first block: the empty hand's check has the carried object in its
/// place and `carry.absent` less it absent. Where the fingers hold the object as they are
/// with the hand empty (open), the robot is placed and its own bodies checked once per
/// sample for both (see [`check_twin`]). Configurations are counted in `carry`.
pub(super) fn label_samples_twin(
    w: &World,
    r: RobotId,
    ends: (&[f64], &[f64]),
    n: usize,
    indices: &[usize],
    carry: &CheckCtx,
) -> (Check, Check) {
    let mut empty = CheckCtx::with_absent(carry.absent.clone());
    let out = match &carry.held {
        Some(held) => {
            empty.absent.remove(held.object);
            match held.posture == OPEN_POSTURE {
                true => twin_samples(w, r, ends, n, indices, (&empty, carry)),
                false => (
                    label_samples(w, r, ends, n, indices.iter().copied(), &empty, true),
                    label_samples(w, r, ends, n, indices.iter().copied(), carry, true),
                ),
            }
        }
        None => {
            let c = label_samples(w, r, ends, n, indices.iter().copied(), carry, true);
            (c.clone(), c)
        }
    };
    carry.add_counts(&empty);
    out
}

/// [`label_samples_twin`] with the fingers open: one [`check_twin`] per sample while
/// neither is blocked, then the empty hand's check alone.
fn twin_samples(
    w: &World,
    r: RobotId,
    (a, b): (&[f64], &[f64]),
    n: usize,
    indices: &[usize],
    (empty, carry): (&CheckCtx, &CheckCtx),
) -> (Check, Check) {
    let m = &w.robots[r.index()];
    assert_dof(m, a);
    assert_dof(m, b);
    let mut q = a.to_vec();
    let (mut own, mut with) = (ObjectSet::new(), ObjectSet::new());
    for (k, &i) in indices.iter().enumerate() {
        sample(a, b, i, n, &mut q);
        match check_twin(w, r, &q, empty, carry) {
            (Check::Touches(e), Check::Touches(c)) => {
                own.union_with(&e);
                with.union_with(&c);
            }
            // Carrying stops here; the empty hand goes on.
            (Check::Touches(e), blocked) => {
                own.union_with(&e);
                let rest = label_samples(w, r, (a, b), n, indices[k + 1..].iter().copied(), empty, true);
                return match rest {
                    Check::Touches(l) => (Check::Touches(own.union(&l)), blocked),
                    rest => (rest, blocked),
                };
            }
            both => return both,
        }
    }
    (Check::Touches(own), Check::Touches(with))
}

/// Samples of a segment with steps of at most `step`, each cut into `parts`.
pub(crate) fn steps(a: &[f64], b: &[f64], step: f64, parts: usize) -> usize {
    let span = a.iter().zip(b).map(|(x, y)| (y - x).abs()).fold(0.0, f64::max);
    // Saturating: a NaN or infinite span must not overflow (the limits check blocks it).
    (if step > 0.0 { (span / step).ceil().max(1.0) as usize } else { 1 }).saturating_mul(parts.max(1))
}

/// Sample `i` of `n` on a -> b; the last is `b` exactly. Interpolated from whichever end
/// comes first in a fixed order (see [`from_a`]), so that sample `i` of a -> b and sample
/// `n - i` of b -> a are the same configuration to the bit: a segment's labels do not
/// depend on the way it was walked, and a check of one way can complete a check of the other.
#[inline]
pub(crate) fn sample(a: &[f64], b: &[f64], i: usize, n: usize, q: &mut [f64]) {
    let (from, to, k) = if from_a(a, b) { (a, b, i) } else { (b, a, n - i) };
    let t = k as f64 / n as f64;
    for (j, v) in q.iter_mut().enumerate() {
        *v = if k == n { to[j] } else { from[j] + (to[j] - from[j]) * t };
    }
}

/// Whether `a` is first of the two (by the first joint where they differ, in
/// `f64::total_cmp`'s order; `a` when they are equal).
#[inline]
fn from_a(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).map(|(x, y)| x.total_cmp(y)).find(|o| o.is_ne()) != Some(std::cmp::Ordering::Greater)
}

/// Steps of at most `step`, each cut into `parts`: the samples include those of
/// `parts = 1`, so the labels found can only grow with `parts`.
pub(crate) fn check_motion(
    w: &World,
    r: RobotId,
    a: &[f64],
    b: &[f64],
    step: f64,
    parts: usize,
    ctx: &CheckCtx,
) -> Check {
    let m = &w.robots[r.index()];
    assert_dof(m, a);
    assert_dof(m, b);
    let n = steps(a, b, step, parts);
    let mut q = a.to_vec();
    let mut out = ObjectSet::new();
    for i in 0..=n {
        sample(a, b, i, n, &mut q);
        match check(w, r, &q, ctx) {
            Check::Blocked(bl) => return Check::Blocked(bl),
            Check::Touches(l) => out.union_with(&l),
        }
    }
    Check::Touches(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4000))]
        /// Sample `i` of a -> b is sample `n - i` of b -> a, to the bit, ends included (the
        /// certification of an edge walked one way completes a coarse check walked the other).
        #[test]
        fn a_segment_and_its_reverse_take_the_same_samples(
            a in proptest::collection::vec(-1e3f64..1e3, 1..8),
            d in proptest::collection::vec(-4.0f64..4.0, 8),
            tie in 0usize..8,
            n in 1usize..300,
        ) {
            // Ends that agree on their first joints, so the order looks past them.
            let b: Vec<f64> = a.iter().zip(&d).enumerate().map(|(k, (x, y))| if k < tie { *x } else { x + y }).collect();
            let (mut p, mut q) = (vec![0.0; a.len()], vec![0.0; a.len()]);
            for i in 0..=n {
                sample(&a, &b, i, n, &mut p);
                sample(&b, &a, n - i, n, &mut q);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                proptest::prop_assert_eq!(bits(&p), bits(&q), "sample {} of {}", i, n);
            }
            sample(&a, &b, 0, n, &mut p);
            proptest::prop_assert_eq!(&p, &a);
            sample(&a, &b, n, n, &mut p);
            proptest::prop_assert_eq!(&p, &b);
        }
    }

    /// Coarse to fine visits `0..=n` each once, 0 first, then halves, quarters, ...
    #[test]
    fn coarse_to_fine_visits_every_sample_once() {
        for n in (1..=300).chain([1023, 1024, 1025]) {
            let order: Vec<usize> = coarse_to_fine(n).collect();
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..=n).collect::<Vec<_>>(), "n = {n}");
            assert_eq!(order[0], 0);
        }
        assert_eq!(coarse_to_fine(6).collect::<Vec<_>>(), [0, 4, 2, 6, 1, 3, 5]);
        assert_eq!(coarse_to_fine(8).collect::<Vec<_>>(), [0, 8, 4, 2, 6, 1, 3, 5, 7]);
    }

    /// On shipped examples with objects, random segments with random objects absent: the
    /// checks of every sample of the segment, in a shuffled order and a few at a time (as
    /// the lazy search walks a path's edges level by level), come to `check_segment`'s
    /// answer, blocked or the same labels. Of the 360 cases 171 are blocked, 29 touch
    /// objects and 160 touch nothing, so each kind of answer is compared (leaving out
    /// the union of the samples' labels fails it: checked).
    #[test]
    fn samples_checked_in_any_order_label_the_segment_as_its_check() {
        use rand::seq::SliceRandom;
        use rand::{RngExt, SeedableRng};
        let (mut blocked, mut touching, mut free) = (0, 0, 0);
        for name in ["cans_5", "clutter", "shelf"] {
            let w = crate::world::test_arms::example(name);
            let objects = w.scenario().objects.len();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
            for ri in 0..w.scenario().robots.len() {
                let r = RobotId(ri as u32);
                let limits = w.limits(r).to_vec();
                for case in 0..60 {
                    // Every other segment starts where the arm touches an object (found by
                    // drawing): random configurations mostly hit the table or nothing.
                    let draw = |rng: &mut rand_chacha::ChaCha8Rng| -> Vec<f64> {
                        limits.iter().map(|(lo, hi)| rng.random_range(*lo..=*hi)).collect()
                    };
                    let mut a = draw(&mut rng);
                    for _ in 0..400 {
                        if case % 2 == 1
                            || matches!(w.check(r, &a, &CheckCtx::new()), Check::Touches(l) if !l.is_empty())
                        {
                            break;
                        }
                        a = draw(&mut rng);
                    }
                    let b: Vec<f64> = a
                        .iter()
                        .zip(&limits)
                        .map(|(v, (lo, hi))| (v + rng.random_range(-0.3..=0.3)).clamp(*lo, *hi))
                        .collect();
                    let mut absent = ObjectSet::new();
                    for o in 0..objects {
                        if rng.random_bool(0.3) {
                            absent.insert(crate::resolve::ObjectId(o as u32));
                        }
                    }
                    let ctx = CheckCtx::with_absent(absent);
                    let step = 2f64.to_radians();
                    let whole = w.check_segment(r, &a, &b, step, &ctx);
                    let n = steps(&a, &b, step, 1);
                    let mut order: Vec<usize> = (0..=n).collect();
                    order.shuffle(&mut rng);
                    let mut label = ObjectSet::new();
                    let mut any_blocked = false;
                    for part in order.chunks(5) {
                        match w.check_samples(r, (&a, &b), n, &mut part.iter().copied(), &ctx) {
                            Check::Touches(l) => label.union_with(&l),
                            Check::Blocked(_) => {
                                any_blocked = true;
                                break;
                            }
                        }
                    }
                    match whole {
                        Check::Blocked(_) => {
                            assert!(any_blocked, "{name}: {a:?} -> {b:?}");
                            blocked += 1;
                        }
                        Check::Touches(l) => {
                            assert!(!any_blocked, "{name}: {a:?} -> {b:?}");
                            assert_eq!(label, l, "{name}: {a:?} -> {b:?}");
                            if l.is_empty() {
                                free += 1;
                            } else {
                                touching += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(blocked > 20 && touching > 10 && free > 20, "{blocked} blocked, {touching} touching, {free} free");
    }
}
