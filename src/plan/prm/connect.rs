//! A query's second search: RRT-Connect (Kuffner and LaValle, 2000) through free
//! space, beside the roadmap's rounds once the first ones found no path touching
//! nothing (`free` strings its legs together for a grasp).
//!
//! The lazy roadmap grows uniformly and its goal tree from the goal alone; in a narrow
//! passage whose goal sits in a pocket (the forearm through a window) it can run out of
//! samples where two trees pulling towards each other get through. A path found here
//! touches nothing, so it removes nothing: the fewest removals there are. Each round
//! grows the two trees by [`PER_SAMPLE_NONE`] extension attempts per roadmap sample the
//! round draws while the query has no path at all (in rounds 1 and 2 of a scene with
//! objects only once the round's small roadmap found none, and then before the goal
//! trees; without objects from round 1, before the roadmap's search), and from the
//! third on by [`PER_SAMPLE_FEWER`] while it has one with removals (so `max_samples`
//! bounds them too, and a query with an answer pays less for a better one), continuing from
//! where the last round stopped, with its own seeded stream: the trees are a function
//! of the seed, the goal and the round, as the roadmap is. As the goal trees do, half
//! the extensions aim near a node of the growing tree, half at a uniform sample. Near a
//! node of the goals' tree the aim follows the spread of the node's neighbours (see
//! [`Tree::spread`]): a tree in a pocket grows along the few directions it has found
//! free, the way out among them (Dalibard and Laumond's principal-component sampling,
//! 2011), where aims spread alike in every joint mostly swing the forearm into the
//! window's sides.
//!
//! As the roadmap's edges and the goal trees' are, a step is first checked at the
//! planner's resolution only; the rest of the certifying check (four times as many
//! samples) runs once the trees meet, on the steps of their path that its shortcut keeps,
//! and a step that fails it is taken out of its tree with everything grown from it
//! (Bohlin and Kavraki's lazy evaluation). Most steps never lie on the path (the Panda's
//! `narrow_gap` problems spent about half their checks certifying them), and most of a
//! path's steps are dropped by its shortcut.

use std::time::Instant;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::super::knn::{dist2, GrowingIndex};
use super::super::roadmap::{mix, normal};
use super::super::space::{Mode, Space};
use super::goals::{TREE_LOCAL, TREE_SIGMA, TREE_STEP};
use super::RobotPlanner;
use crate::world::ObjectSet;

/// Extension attempts (each followed by a connect) per roadmap sample while the query
/// has no path: without them it gives up. (With 64 the Panda's `narrow_gap` 13 was solved
/// at 1 of seeds 1..9 within the default 5 000 samples; with 128 at 7 of them, in about
/// 3 s. With 128 the UR5's `narrow_gap` 97 gave up at seed 1, 640 000 attempts; with 256
/// it is solved at 4 096 samples, and a family's problems spend less on the roadmap
/// before the trees meet, so that its median fell: UR5 `narrow_gap` 11.6 -> 10.1 ms.)
pub(super) const PER_SAMPLE_NONE: u64 = 256;
/// The same while it has a path with removals: they can only make it remove fewer.
pub(super) const PER_SAMPLE_FEWER: u64 = 16;
/// The trees take turns extending, as in RRT-Connect, until one holds more than this
/// many times the other's nodes; then the smaller one extends (and the larger marches
/// towards it) until they are back within it. A goal in a pocket (the hand through a
/// window) grows a tree of tens of nodes while the start's grows thousands, and
/// extensions from the pocket are what get out of it: LaValle's balanced bidirectional
/// search, kept for lopsided trees only (alike trees taking turns did better on the
/// slit tests, 47 of 64 seeds against 42 with strict balance). With aims along the
/// spread (see [`SPREAD_SCALE`]) the goals' tree grows where it used to be trapped, and
/// 2 did better than 4 or 3 (the UR5's `narrow_gap` at seeds 1-3: checks' 95th
/// percentile 74 k against 115 k and 122 k) and about as well as 1 (74 k).
const BALANCE: usize = 2;
/// Nodes whose spread shapes a local aim of the goals' tree (see [`Tree::spread`]).
const SPREAD_NEIGHBOURS: usize = 16;
/// A local aim of the goals' tree: its node plus this many times a normal draw from its
/// neighbours' spread, plus [`SPREAD_JITTER`] times a standard normal per joint (so
/// that a tree whose nodes lie in a plane can still leave it). The step is `TREE_STEP`
/// whatever the aim's distance: the scale sets how much the spread outweighs the
/// jitter. UR5 `narrow_gap`, seeds 1-3, balance 2: checks' median 2 412 / 2 182 / 2 208
/// and 95th percentile 74 k / 54 k / 34 k at 6 / 8 / 12 (isotropic aims: 3 964 and
/// 128 k).
const SPREAD_SCALE: f64 = 12.0;
const SPREAD_JITTER: f64 = 0.1;
/// A goals' tree of fewer nodes aims as the start's does (no spread to follow yet).
const SPREAD_MIN_NODES: usize = 4;
/// Extension attempts after which the goals' tree grows along the escape lines of its
/// roots (see [`FreeConnect::escape`]): a search that meets before never pays for them.
const ESCAPE_AFTER: u64 = 64;
/// The seed stream of this search.
const STREAM: u64 = 0x636f_6e6e;

/// One tree: flat configurations, each node's parent, and a k-d index of the older nodes.
/// A node is added once the coarse samples of its step touch nothing; the rest of the
/// certifying check waits until the step is on a path between the trees (`sure`), and a
/// step that fails it takes its node and every node grown from it out of the tree (`dead`).
struct Tree {
    dof: usize,
    qs: Vec<f64>,
    parent: Vec<u32>,
    /// Per node: the step from its parent passed the whole certifying check (roots: true).
    sure: Vec<bool>,
    /// Per node: it or an ancestor's step failed that check; never a nearest node again.
    dead: Vec<bool>,
    index: GrowingIndex,
    /// Per node, once asked: see [`Tree::spread`].
    spread: Vec<Option<Box<[f64]>>>,
}

impl Tree {
    /// A tree of one root per configuration (a forest: several goals).
    fn new(roots: &[&[f64]]) -> Tree {
        let dof = roots.first().map_or(0, |r| r.len());
        let qs = roots.iter().flat_map(|r| r.iter().copied()).collect();
        let n = roots.len();
        Tree {
            dof,
            qs,
            parent: vec![u32::MAX; n],
            sure: vec![true; n],
            dead: vec![false; n],
            index: GrowingIndex::default(),
            spread: Vec::new(),
        }
    }
    fn len(&self) -> usize {
        self.parent.len()
    }
    fn q(&self, i: usize) -> &[f64] {
        &self.qs[i * self.dof..(i + 1) * self.dof]
    }
    /// The live node nearest `q`; ties go to the older node. `seed`: a node likely near
    /// `q` (see [`GrowingIndex::nearest`]).
    fn nearest(&mut self, q: &[f64], seed: Option<usize>) -> usize {
        let (dim, qs, dead) = (self.dof, &self.qs, &self.dead);
        self.index.nearest(dim, self.parent.len(), |i| &qs[i * dim..(i + 1) * dim], q, |i| dead[i as usize], seed)
    }
    /// Node `i`'s neighbourhood as the tree was when first asked: the
    /// [`SPREAD_NEIGHBOURS`] nodes nearest it (itself among them), each one's deviation
    /// from their mean over the square root of their number, `dof` values per node. A
    /// sum of them weighted by standard normals is a normal draw with the neighbours'
    /// covariance: long along the way the nodes go, short across it.
    fn spread(&mut self, i: usize) -> &[f64] {
        if self.spread.len() < self.len() {
            self.spread.resize(self.len(), None);
        }
        if self.spread[i].is_none() {
            let (dim, n, qs) = (self.dof, self.len(), &self.qs);
            let point = |k: usize| &qs[k * dim..(k + 1) * dim];
            let near = self.index.k_nearest(dim, n, point, point(i), SPREAD_NEIGHBOURS);
            let w = 1.0 / near.len() as f64;
            let mut mean = vec![0.0; dim];
            for &k in &near {
                mean.iter_mut().zip(point(k)).for_each(|(m, v)| *m += w * v);
            }
            let rows = near.iter().flat_map(|&k| point(k).iter().zip(&mean).map(|(v, m)| (v - m) * w.sqrt()));
            self.spread[i] = Some(rows.collect());
        }
        self.spread[i].as_deref().unwrap_or_default()
    }
    fn add(&mut self, q: &[f64], parent: usize) -> usize {
        self.qs.extend_from_slice(q);
        self.parent.push(parent as u32);
        self.sure.push(false);
        self.dead.push(false);
        self.len() - 1
    }
    /// The nodes from its root to node `i`.
    fn chain(&self, mut i: usize) -> Vec<usize> {
        let mut out = vec![i];
        while self.parent[i] != u32::MAX {
            i = self.parent[i] as usize;
            out.push(i);
        }
        out.reverse();
        out
    }
    /// Takes node `i` and its descendants out (a child is always younger than its parent).
    fn kill(&mut self, i: usize) {
        self.dead[i] = true;
        for k in i + 1..self.len() {
            let p = self.parent[k];
            if p != u32::MAX && self.dead[p as usize] {
                self.dead[k] = true;
            }
        }
    }
    /// Finishes the certifying check of the step into node `k`; false (its subtree taken
    /// out) when it fails.
    fn certify<S: Space>(&mut self, p: &RobotPlanner<S>, k: usize, mode: &Mode, checks: &mut u64) -> bool {
        if self.sure[k] {
            return true;
        }
        let parent = self.parent[k] as usize;
        if !p.rest_clear(self.q(parent), self.q(k), mode, checks) {
            self.kill(k);
            return false;
        }
        self.sure[k] = true;
        true
    }
}

enum Grew {
    Reached(usize),
    Advanced(usize),
    Trapped,
}

/// One RRT-Connect search through free space in one mode: from a start to whichever of
/// its goals the trees reach first.
pub(super) struct FreeConnect {
    /// The tree from the start, then the goals' forest, while `swapped` is false.
    a: Tree,
    b: Tree,
    swapped: bool,
    rng: ChaCha8Rng,
    mode: Mode,
    /// Per root of the goals' forest: the index of its goal among those given.
    goals: Vec<usize>,
    /// Extension attempts so far.
    pub(super) attempted: u64,
    /// A tree more than this many times the other's size hands it the next extension
    /// (see [`BALANCE`]); `usize::MAX`: the trees take turns.
    balance: usize,
    /// Whether the goals' tree aims along its spread (see [`SPREAD_SCALE`]).
    along_spread: bool,
}

impl FreeConnect {
    /// The search from `start` to `goals` in `mode`, or `None` when the start or every
    /// goal touches something (no path touching nothing can start or end there).
    pub(super) fn new<S: Space>(
        p: &RobotPlanner<S>,
        start: &[f64],
        goals: &[&[f64]],
        mode: Mode,
        checks: &mut u64,
    ) -> Option<FreeConnect> {
        if goals.is_empty() || !p.free(start, &mode, checks) {
            return None;
        }
        let usable: Vec<usize> = (0..goals.len()).filter(|&i| p.free(goals[i], &mode, checks)).collect();
        if usable.is_empty() {
            return None;
        }
        let roots: Vec<&[f64]> = usable.iter().map(|&i| goals[i]).collect();
        // Keyed by the goals (each leg of a grasp's path has its own).
        let bits: Vec<u64> = roots.iter().flat_map(|r| r.iter()).map(|v| v.to_bits()).collect();
        let rng = ChaCha8Rng::seed_from_u64(mix(&[p.seed, STREAM, mix(&bits)]));
        let (a, b) = (Tree::new(&[start]), Tree::new(&roots));
        Some(FreeConnect {
            a,
            b,
            swapped: false,
            rng,
            mode,
            goals: usable,
            attempted: 0,
            balance: BALANCE,
            along_spread: true,
        })
    }

    /// The search with the trees taking turns whatever their sizes.
    #[cfg(test)]
    pub(super) fn taking_turns(self) -> FreeConnect {
        FreeConnect { balance: usize::MAX, ..self }
    }

    /// The search with the goals' tree aiming as the start's does.
    #[cfg(test)]
    pub(super) fn aiming_alike(self) -> FreeConnect {
        FreeConnect { along_spread: false, ..self }
    }

    /// The sizes of the two trees (start's, goals').
    #[cfg(test)]
    pub(super) fn sizes(&self) -> (usize, usize) {
        if self.swapped {
            (self.b.len(), self.a.len())
        } else {
            (self.a.len(), self.b.len())
        }
    }

    /// Steps of the trees that passed the whole certifying check.
    #[cfg(test)]
    pub(super) fn certified_steps(&self) -> usize {
        let t = |t: &Tree| (0..t.len()).filter(|&k| t.sure[k] && t.parent[k] != u32::MAX).count();
        t(&self.a) + t(&self.b)
    }

    /// Nodes taken out of the trees by the certifying check.
    #[cfg(test)]
    pub(super) fn dead_nodes(&self) -> usize {
        self.a.dead.iter().chain(&self.b.dead).filter(|d| **d).count()
    }

    /// Up to `attempts` more extensions, each followed by a connect of the other tree;
    /// once the trees meet, the path from the start to a goal and that goal's index.
    /// Stops early at the time budget (the clock is read every 64 attempts: a reading
    /// costs about a check).
    pub(super) fn grow<S: Space>(
        &mut self,
        p: &RobotPlanner<S>,
        attempts: u64,
        t0: Instant,
        checks: &mut u64,
    ) -> Option<(Vec<Vec<f64>>, usize)> {
        let lim = p.space.limits().to_vec();
        for k in 0..attempts {
            if k % 64 == 0 && p.settings.time_budget.is_some_and(|tb| t0.elapsed().as_secs_f64() > tb) {
                return None;
            }
            if self.attempted == ESCAPE_AFTER {
                self.escape(p, checks);
            }
            self.attempted += 1;
            if self.a.len() > self.b.len().saturating_mul(self.balance) {
                std::mem::swap(&mut self.a, &mut self.b);
                self.swapped = !self.swapped;
            }
            // As the goal trees' (see `goals::local_target`): half the aims near a node of
            // the growing tree, so that a tree in a pocket spreads through it.
            // (A local aim's node seeds the search for the nearest: it is usually near.)
            let (aim, seed): (Vec<f64>, _) = if self.rng.random::<f64>() < TREE_LOCAL {
                let n = self.a.len();
                let i = ((self.rng.random::<f64>() * n as f64) as usize).min(n - 1);
                let q = self.a.q(i).to_vec();
                let mut off = vec![0.0; q.len()];
                // `a` is the goals' tree when swapped.
                if self.swapped && self.along_spread && n >= SPREAD_MIN_NODES {
                    for row in self.a.spread(i).chunks(q.len()) {
                        let g = SPREAD_SCALE * normal(&mut self.rng);
                        off.iter_mut().zip(row).for_each(|(o, v)| *o += g * v);
                    }
                    off.iter_mut().for_each(|o| *o += SPREAD_JITTER * normal(&mut self.rng));
                } else {
                    off.iter_mut().for_each(|o| *o = TREE_SIGMA * normal(&mut self.rng));
                }
                let aim = q.iter().zip(&off).zip(&lim).map(|((v, o), (lo, hi))| (v + o).clamp(*lo, *hi)).collect();
                (aim, Some(i))
            } else {
                (lim.iter().map(|(lo, hi)| lo + self.rng.random::<f64>() * (hi - lo)).collect(), None)
            };
            if let Grew::Reached(i) | Grew::Advanced(i) =
                p.free_step(&mut self.a, Start::Nearest(seed), &aim, &self.mode, checks)
            {
                let target = self.a.q(i).to_vec();
                // Connect: the other tree steps towards the new node until it reaches it or
                // is stopped. Each step's node is nearer the target than any other (a step
                // nearer than the nearest), so the next step starts there without a search.
                let mut from = Start::Nearest(None);
                loop {
                    match p.free_step(&mut self.b, from, &target, &self.mode, checks) {
                        Grew::Advanced(j) => from = Start::At(j),
                        Grew::Trapped => break,
                        Grew::Reached(j) => match self.met(p, i, j, checks) {
                            Some(found) => return Some(found),
                            // The trees go on growing without the step that failed.
                            None => break,
                        },
                    }
                }
            }
            std::mem::swap(&mut self.a, &mut self.b);
            self.swapped = !self.swapped;
        }
        None
    }

    /// The path from the start to a goal through node `i` of `a` and node `j` of `b` (the
    /// same configuration), shortened, and its goal's index; `None` when a step of the
    /// trees that the shortened path keeps fails the rest of the certifying check. Steps
    /// the shortcut drops are never certified (see [`RobotPlanner::shortcut_certifying`]).
    fn met<S: Space>(
        &mut self,
        p: &RobotPlanner<S>,
        i: usize,
        j: usize,
        checks: &mut u64,
    ) -> Option<(Vec<Vec<f64>>, usize)> {
        let (chain_a, chain_b) = (self.a.chain(i), self.b.chain(j));
        let (na, nb) = (chain_a.len(), chain_b.len());
        let mut path: Vec<Vec<f64>> = chain_a.iter().map(|&k| self.a.q(k).to_vec()).collect();
        path.extend(chain_b.iter().rev().skip(1).map(|&k| self.b.q(k).to_vec()));
        let goal_root = if self.swapped {
            path.reverse();
            chain_a[0]
        } else {
            chain_b[0]
        };
        let goal = self.goals[goal_root];
        let (a, b, swapped, steps) = (&mut self.a, &mut self.b, self.swapped, na + nb - 2);
        // Step `s` of the path as built (before any reversal) ends at a node of `a`
        // (`a`'s step into it) while on `a`'s chain, then starts at one of `b`'s (`b`'s
        // step into the node it leaves).
        let own = |s: usize, checks: &mut u64| {
            let s = if swapped { steps - 1 - s } else { s };
            match s + 1 < na {
                true => a.certify(p, chain_a[s + 1], &self.mode, checks),
                false => b.certify(p, chain_b[nb - 1 - (s + 1 - na)], &self.mode, checks),
            }
        };
        let short = p.shortcut_certifying(&path, &self.mode, &ObjectSet::new(), checks, own)?;
        Some((short, goal))
    }

    /// Grows the goals' tree along the escape line of each root (see
    /// `Space::escape_line`), when every step of it is clear as a tree's step must be: a
    /// goal behind a window is left the way the hand went in, which random extensions find
    /// only by chance (the Panda mesh's `narrow_gap` median 16.5 -> 12.3 ms). A line
    /// blocked on the way is left out whole: a stub leads nowhere, crowds its root, and
    /// changes the search where it cannot help (the UR5's wrist swings into the window's
    /// sides as its hand moves straight: most of its lines are blocked at the first step).
    fn escape<S: Space>(&mut self, p: &RobotPlanner<S>, checks: &mut u64) {
        let t = if self.swapped { &mut self.a } else { &mut self.b };
        let roots = t.parent.iter().take_while(|&&parent| parent == u32::MAX).count();
        for root in 0..roots {
            let line = p.space.escape_line(t.q(root));
            let mut from = t.q(root).to_vec();
            let clear = line.iter().all(|q| {
                let ok = p.coarse_clear_leaving(&from, q, &self.mode, checks);
                from.clone_from(q);
                ok
            });
            if !clear {
                continue;
            }
            let mut parent = root;
            for q in &line {
                parent = t.add(q, parent);
            }
        }
    }
}

/// Where a tree's step starts.
#[derive(Clone, Copy)]
enum Start {
    /// At this node.
    At(usize),
    /// At the live node nearest the aim; the search seeded with a node likely near it.
    Nearest(Option<usize>),
}

impl<S: Space> RobotPlanner<S> {
    /// One step of `t` from `from` towards `aim`, kept when the coarse samples of the
    /// motion touch nothing (see [`Tree`]).
    fn free_step(&self, t: &mut Tree, from: Start, aim: &[f64], mode: &Mode, checks: &mut u64) -> Grew {
        let near = match from {
            Start::At(i) => i,
            Start::Nearest(seed) => t.nearest(aim, seed),
        };
        let from = t.q(near).to_vec();
        let d = dist2(&from, aim).sqrt();
        let reached = d <= TREE_STEP;
        let to: Vec<f64> = match reached {
            true => aim.to_vec(),
            false => from.iter().zip(aim).map(|(x, y)| x + (y - x) * TREE_STEP / d).collect(),
        };
        // Every node of a tree touches nothing (its roots were checked, and each step's end).
        if !self.coarse_clear_leaving(&from, &to, mode, checks) {
            return Grew::Trapped;
        }
        let i = t.add(&to, near);
        if reached {
            Grew::Reached(i)
        } else {
            Grew::Advanced(i)
        }
    }

    fn free(&self, q: &[f64], mode: &Mode, checks: &mut u64) -> bool {
        self.space.touches_nothing(q, mode, checks)
    }
}

#[cfg(test)]
#[path = "spread_tests.rs"]
mod spread_tests;
