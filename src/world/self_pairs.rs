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
    // not test it (the same pairs as testing every sample).
    let misses_to_keep = samples - always + 1;
    let mut misses = vec![0usize; pairs.len()];
    let mut s = Scratch::default();
    let mut q = vec![0.0; m.chain.dof()];
    let mut open = vec![false; m.bodies.len()];
    let mut live: Vec<usize> = (0..pairs.len()).collect();
    for _ in 0..samples {
        live.retain(|&k| misses[k] < misses_to_keep);
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
    pairs.into_iter().enumerate().filter(|&(k, _)| misses[k] >= misses_to_keep).map(|(_, p)| p).collect()
}

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
