//! Which link pairs of a robot its checks test for self-collision: every pair that is not
//! rigidly joined, adjacent or allowed, less (when sampling, as MoveIt's setup assistant
//! does) the pairs that collide in nearly every sample.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::check::{bodies_collide, body_box, pose_body, start_posing_upto, Scratch};
use super::robot::RobotModel;
use super::OPEN_POSTURE as OPEN;

/// Body pairs worth checking for self-collision: not both static, not rigidly
/// joined, not adjacent, not allowed by the scenario, and (when sampling) not colliding
/// in nearly every sample. A pair that never comes near is kept: proving it stays apart
/// took every sample of the arm (the Panda's base and second link: 6 % of a
/// `narrow_gap` problem's compile), while checking it costs one test of two boxes the
/// check has anyway, and a collision confined to a region the samples missed is caught.
pub(crate) fn self_pairs(
    m: &RobotModel,
    allowed: &[(String, String)],
    samples: usize,
    seed: u64,
) -> Vec<(usize, usize)> {
    sampled_pairs(m, allowed, samples, seed, true)
}

/// [`self_pairs`]; `early`: a pair may be kept before its misses reach the rule's count.
fn sampled_pairs(
    m: &RobotModel,
    allowed: &[(String, String)],
    samples: usize,
    seed: u64,
    early: bool,
) -> Vec<(usize, usize)> {
    let links = &m.chain.links;
    let group = |b: usize| links[m.bodies[b].link].group;
    let adjacent = |ga: usize, gb: usize| {
        links[gb].parent.map(|p| links[p].group) == Some(ga) || links[ga].parent.map(|p| links[p].group) == Some(gb)
    };
    let is_allowed = |a: &str, b: &str| allowed.iter().any(|(x, y)| (x == a && y == b) || (x == b && y == a));
    let mut pairs = Vec::new();
    for a in 0..m.bodies.len() {
        for b in a + 1..m.bodies.len() {
            let (ga, gb) = (group(a), group(b));
            if (!m.bodies[a].moving && !m.bodies[b].moving) || ga == gb || adjacent(ga, gb) {
                continue;
            }
            if is_allowed(&m.bodies[a].name, &m.bodies[b].name) {
                continue;
            }
            pairs.push((a, b));
        }
    }
    if samples == 0 || pairs.is_empty() {
        return pairs;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0x5e1f_c011 ^ seed);
    let always = (ALWAYS_FRACTION_NUM * samples as f64).ceil() as usize;
    // A pair is kept once it has missed collision in more than `samples - always`
    // samples: it can no longer be "always" colliding, so the rest of the samples need
    // not test it (the same pairs as testing every sample); or sooner, once its misses
    // so far would be too many for a pair that is (see `plainly_not_always`).
    let misses_to_keep = samples - always + 1;
    let mut misses = vec![0usize; pairs.len()];
    let mut kept = vec![false; pairs.len()];
    let mut s = Scratch::default();
    let mut q = vec![0.0; m.chain.dof()];
    let mut open = vec![false; m.bodies.len()];
    let mut live: Vec<usize> = (0..pairs.len()).collect();
    for n in 0..samples {
        for &k in &live {
            kept[k] = misses[k] >= misses_to_keep || (early && plainly_not_always(misses[k], n));
        }
        live.retain(|&k| !kept[k]);
        if live.is_empty() {
            break;
        }
        for (v, (lo, hi)) in q.iter_mut().zip(&m.chain.limits) {
            *v = super::chain::sample_in(&mut rng, *lo, *hi);
        }
        open.fill(false);
        for &k in &live {
            let (a, b) = pairs[k];
            (open[a], open[b]) = (true, true);
        }
        pose_bodies(m, &q, &open, &mut s);
        for &k in &live {
            let (a, b) = pairs[k];
            if !(s.body_aabb[a].intersects(&s.body_aabb[b]) && bodies_collide(m, &mut s, a, b)) {
                misses[k] += 1;
            }
        }
    }
    pairs.into_iter().enumerate().filter(|&(k, _)| kept[k] || misses[k] >= misses_to_keep).map(|(_, p)| p).collect()
}

/// Whether `misses` in `n` samples are too many for a pair in contact in at least
/// [`ALWAYS_FRACTION_NUM`] of configurations: by Chernoff's bound, such a pair misses
/// that often with a probability under `exp(-n KL(misses/n || 1 - fraction))`, kept under
/// e^-23 (about 1e-10; summed over 2 000 samples, 2e-7). The UR5's pair that misses least
/// misses in 71 % of samples: its pairs were settled after 142 samples, 6 % of the
/// instructions of its median `narrow_gap` problem's compile (7.9 M), now after about 20
/// (1.1 M). A pair colliding in 95 % of samples or more is still sampled to the end, as
/// the rule says.
fn plainly_not_always(misses: usize, n: usize) -> bool {
    let p = 1.0 - ALWAYS_FRACTION_NUM;
    if n == 0 || misses as f64 <= p * n as f64 {
        return false;
    }
    let a = misses as f64 / n as f64;
    let kl = a * (a / p).ln() + if a < 1.0 { (1.0 - a) * ((1.0 - a) / (1.0 - p)).ln() } else { 0.0 };
    n as f64 * kl > EARLY_KEEP_LOG_ODDS
}

/// See [`plainly_not_always`].
const EARLY_KEEP_LOG_ODDS: f64 = 23.0;

/// A pair is "always in collision" at this fraction of samples (MoveIt's default).
const ALWAYS_FRACTION_NUM: f64 = 0.95;

/// `check::pose_robot` for the bodies marked only, the fingers open: the others' entries are
/// left as they were. The self-collision sampling, once most pairs are settled, poses
/// the few bodies still in question, and the links up to theirs only (a pair that collides
/// in most samples keeps the sampling going).
fn pose_bodies(m: &RobotModel, q: &[f64], bodies: &[bool], s: &mut Scratch) {
    let links = m.bodies.iter().zip(bodies).filter(|(_, open)| **open).map(|(b, _)| b.link + 1).max().unwrap_or(0);
    start_posing_upto(m, q, links, OPEN, s);
    s.body_aabb.resize(m.bodies.len(), Aabb::new_invalid());
    for (bi, b) in m.bodies.iter().enumerate().filter(|(bi, _)| bodies[*bi]) {
        pose_body(m, s, bi);
        s.body_aabb[bi] = body_box(s, b);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_arms::{example, shared_arms};
    use super::*;
    use rand::RngExt;

    /// Kept early or at the rule's count, the pairs are the same on the shipped arms
    /// (the TX-90 with its hand, the two arms of `cans_3`, the three-arm cell) and the shared
    /// ones (the UR5, both Pandas), at several seeds.
    #[test]
    fn keeping_a_pair_early_keeps_the_pairs_the_rule_keeps() {
        let mut worlds: Vec<(String, super::super::World)> =
            ["box_lid", "cans_3", "three_arm"].iter().map(|n| (n.to_string(), example(n))).collect();
        worlds.extend(shared_arms());
        let mut compared = 0;
        for (name, w) in &worlds {
            for m in &w.robots {
                for seed in 0..3 {
                    let full = sampled_pairs(m, &m.allowed_pairs, 2000, seed, false);
                    assert_eq!(sampled_pairs(m, &m.allowed_pairs, 2000, seed, true), full, "{name} at seed {seed}");
                    compared += full.len();
                }
            }
        }
        assert!(compared > 50, "{compared} pairs compared");
    }

    /// A pair in contact in 95 % of samples is never kept early over 2 000 samples (400
    /// runs); one missing in 70 % of them is kept within 40, one missing in every sample
    /// within 10.
    #[test]
    fn only_plainly_frequent_misses_keep_a_pair_early() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let first_keep = |rng: &mut rand_chacha::ChaCha8Rng, miss: f64| {
            let mut misses = 0;
            for n in 0..2000 {
                if plainly_not_always(misses, n) {
                    return Some(n);
                }
                misses += usize::from(rng.random::<f64>() < miss);
            }
            None
        };
        for _ in 0..400 {
            let k = first_keep(&mut rng, 0.05);
            assert_eq!(k, None);
        }
        for _ in 0..100 {
            let k = first_keep(&mut rng, 0.7);
            assert!(k.is_some_and(|n| n <= 40), "{k:?}");
        }
        assert!(first_keep(&mut rng, 1.0).is_some_and(|n| n <= 10));
    }
}
