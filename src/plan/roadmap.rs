//! One robot's PRMwO roadmap: vertices are sampled configurations that hit nothing
//! fixed, labelled with the removable objects they touch; edges join each sample to
//! its k nearest neighbours and are labelled lazily, when a search first wants them.
//!
//! The roadmap grows in rounds. Round r draws its samples from a ChaCha RNG seeded by
//! (scenario seed, robot, r), and the cumulative sample count doubles each round, so
//! the roadmap after round r is a pure function of the seed: queries that share it see
//! the same graph whatever order they run in, and a query that stops at round r sees
//! only the prefix of rounds 1..=r.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::knn::{dist2, KdTree};
use super::space::{Mode, Space};
use crate::world::{Check, ObjectSet};

/// Where each round ended.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RoundEnd {
    pub verts: usize,
    pub edges: usize,
    /// Samples drawn up to this round (valid or not).
    pub samples: u64,
}

/// The roadmap of one robot.
pub(crate) struct Roadmap {
    pub dof: usize,
    /// Vertex configurations, flat. Vertex 0 is home when home hits nothing fixed.
    pub qs: Vec<f64>,
    /// Empty-hand labels of the vertices.
    pub vlab: Vec<ObjectSet>,
    pub edges: Vec<(u32, u32)>,
    pub elen: Vec<f64>,
    /// `rounds[0]` is round 0 (home only); `rounds[r]` ends round r.
    pub rounds: Vec<RoundEnd>,
    /// One k-d tree per round over that round's prefix, for connecting goals.
    pub trees: Vec<KdTree>,
    pub home_ok: bool,
}

/// A round computed away from the lock, to be appended if still missing.
pub(crate) struct Round {
    pub index: usize,
    pub qs: Vec<f64>,
    pub vlab: Vec<ObjectSet>,
    pub edges: Vec<(u32, u32)>,
    pub elen: Vec<f64>,
    pub tree: KdTree,
    pub samples: u64,
    pub checks: u64,
}

/// The seed stream of the Gaussian companions of a round's samples.
const NEAR_STREAM: u64 = 0x6e65_6172;
/// Their step: a normal deviate times this fraction of each joint's range.
const NEAR_SIGMA: f64 = 0.02;

/// A standard normal deviate (Box-Muller), from two uniform draws.
pub(crate) fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// Neighbours per vertex on a roadmap of `n` vertices: PRM*'s k = e (1 + 1/d) ln n,
/// which keeps the roadmap connected as it grows, and never fewer than the setting.
pub(crate) fn neighbours(setting: usize, dof: usize, n: usize) -> usize {
    let d = dof.max(1) as f64;
    let k = (std::f64::consts::E * (1.0 + 1.0 / d) * (n.max(2) as f64).ln()).ceil() as usize;
    k.max(setting)
}

/// Sample-count schedule: round r (r >= 1) ends with `first << (r-1)` samples, capped.
pub(crate) fn samples_at(round: usize, first: usize, max: usize) -> u64 {
    let n = (first as u64).saturating_mul(1u64 << (round - 1).min(40));
    n.min(max as u64)
}

/// Mixes the seed, the robot and the round into one RNG seed (splitmix64 steps).
pub(crate) fn mix(parts: &[u64]) -> u64 {
    let mut h = 0x9E37_79B9_7F4A_7C15u64;
    for &p in parts {
        h ^= p;
        h = h.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h = z ^ (z >> 31);
    }
    h
}

impl Roadmap {
    /// Round 0: the home configuration alone.
    pub(crate) fn new<S: Space>(space: &S, checks: &mut u64) -> Roadmap {
        let dof = space.dof();
        let home = space.home().to_vec();
        let mut map = Roadmap {
            dof,
            qs: Vec::new(),
            vlab: Vec::new(),
            edges: Vec::new(),
            elen: Vec::new(),
            rounds: Vec::new(),
            trees: Vec::new(),
            home_ok: false,
        };
        if let Check::Touches(l) = space.check(&home, &Mode::default(), checks) {
            map.qs = home;
            map.vlab.push(l);
            map.home_ok = true;
        }
        map.trees.push(KdTree::build(dof, &map.qs, map.vlab.len()));
        map.rounds.push(RoundEnd { verts: map.vlab.len(), edges: 0, samples: 0 });
        map
    }

    pub(crate) fn rounds_done(&self) -> usize {
        self.rounds.len() - 1
    }

    pub(crate) fn q(&self, v: u32) -> &[f64] {
        &self.qs[v as usize * self.dof..(v as usize + 1) * self.dof]
    }

    /// What computing the next round needs, copied out so the lock can be released.
    pub(crate) fn snapshot(&self) -> Snapshot {
        Snapshot {
            dof: self.dof,
            qs: self.qs.clone(),
            n: self.vlab.len(),
            index: self.rounds_done() + 1,
            samples: self.rounds[self.rounds_done()].samples,
        }
    }
}

/// The roadmap's points and round counter at one moment.
pub(crate) struct Snapshot {
    dof: usize,
    qs: Vec<f64>,
    n: usize,
    index: usize,
    /// Samples drawn before the next round.
    pub samples: u64,
}

impl Snapshot {
    /// Computes the next round without changing the roadmap. Pure in the roadmap, the
    /// seed and the settings, so racing callers compute the same round.
    pub(crate) fn next_round<S: Space>(&self, space: &S, seed: u64, first: usize, max: usize, k: usize) -> Round {
        let (index, before, dof) = (self.index, self.samples, self.dof);
        let target = samples_at(index, first, max);
        let n_new = target.saturating_sub(before) as usize;
        let limits = space.limits();
        let mut rng = ChaCha8Rng::seed_from_u64(mix(&[seed, index as u64]));
        let mut cand = Vec::with_capacity(n_new * dof);
        for _ in 0..n_new {
            for &(lo, hi) in limits.iter().take(dof) {
                let u: f64 = rng.random();
                cand.push(lo + u * (hi - lo));
            }
        }
        // Narrow passages (Gaussian sampling): beside every uniform sample, a second one
        // a short normal step away, from a stream of its own so the uniform samples stay
        // those of the seed. The pair is kept when exactly one of the two hits something
        // fixed: the free one then lies near an obstacle's surface, where gaps are.
        let mut near_rng = ChaCha8Rng::seed_from_u64(mix(&[seed, index as u64, NEAR_STREAM]));
        let near: Vec<f64> = cand
            .chunks(dof.max(1))
            .flat_map(|q| {
                let step: Vec<f64> = (0..dof).map(|_| normal(&mut near_rng)).collect();
                q.iter()
                    .zip(limits)
                    .zip(step)
                    .map(|((v, (lo, hi)), z)| (v + z * NEAR_SIGMA * (hi - lo)).clamp(*lo, *hi))
                    .collect::<Vec<_>>()
            })
            .collect();
        let label = |q: &[f64]| {
            let mut c = 0;
            let l = match space.check(q, &Mode::default(), &mut c) {
                Check::Touches(l) => Some(l),
                Check::Blocked(_) => None,
            };
            (l, c)
        };
        let labelled: Vec<(Option<ObjectSet>, u64)> = cand.par_chunks(dof.max(1)).map(label).collect();
        let near_labelled: Vec<(Option<ObjectSet>, u64)> = near.par_chunks(dof.max(1)).map(label).collect();
        let mut qs = Vec::new();
        let mut vlab = Vec::new();
        let mut checks = 0;
        let pairs = cand.chunks(dof.max(1)).zip(labelled).zip(near.chunks(dof.max(1)).zip(near_labelled));
        for ((q, (l, c)), (qn, (ln, cn))) in pairs {
            checks += c + cn;
            let near_kept = l.is_none() && ln.is_some();
            if let Some(l) = l {
                qs.extend_from_slice(q);
                vlab.push(l);
            }
            if near_kept {
                qs.extend_from_slice(qn);
                vlab.push(ln.unwrap_or_default());
            }
        }
        let old = self.n;
        let mut all = self.qs.clone();
        all.extend_from_slice(&qs);
        let total = old + vlab.len();
        let tree = KdTree::build(dof, &all, total);
        let k = neighbours(k, dof, total);
        let mut edges: Vec<(u32, u32)> = (old..total)
            .into_par_iter()
            .flat_map_iter(|i| {
                let q = &all[i * dof..(i + 1) * dof];
                let i = i as u32;
                tree.nearest(q, k, |j| j == i).into_iter().map(move |(_, j)| (i.min(j), i.max(j)))
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let elen = edges
            .iter()
            .map(|&(a, b)| dist2(&all[a as usize * dof..][..dof], &all[b as usize * dof..][..dof]).sqrt())
            .collect();
        Round { index, qs, vlab, edges, elen, tree, samples: target, checks }
    }
}

impl Roadmap {
    /// Appends a round computed by [`Roadmap::next_round`]; ignored if already present.
    pub(crate) fn append(&mut self, r: Round) -> bool {
        if r.index != self.rounds_done() + 1 {
            return false;
        }
        self.qs.extend_from_slice(&r.qs);
        self.vlab.extend(r.vlab);
        self.edges.extend_from_slice(&r.edges);
        self.elen.extend_from_slice(&r.elen);
        self.trees.push(r.tree);
        self.rounds.push(RoundEnd { verts: self.vlab.len(), edges: self.edges.len(), samples: r.samples });
        true
    }

    /// The last round worth growing to under `max` samples.
    pub(crate) fn max_rounds(first: usize, max: usize) -> usize {
        let mut r = 1;
        while samples_at(r, first, max) < max as u64 {
            r += 1;
        }
        if max == 0 {
            0
        } else {
            r
        }
    }
}
