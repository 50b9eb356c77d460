//! The goals of a query: configuration goal nodes, the trees grown from them, the
//! drop node, the usable grasps, and what blocks them when none is usable.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::super::knn::dist2;
use super::super::layers::{GoalNode, GraspGoal, Job, LabelKey, ModeKey, Node, State};
use super::super::roadmap::{mix, normal, samples_at};
use super::super::space::{Mode, Space};
use super::RobotPlanner;
use crate::resolve::ObjectId;
use crate::world::{Blocker, Check, GraspConfig, ObjectSet};

/// Tree growth per round: this many extension attempts per roadmap sample the round
/// draws, so `max_samples` bounds the trees too, shared among the query's goals (at
/// least `TREE_MIN` each).
const TREE_PER_SAMPLE: u64 = 8;
const TREE_MIN: usize = 8;
const TREE_MAX: usize = 1 << 16;
/// The share of extensions aimed near a tree node drawn uniformly (see `local_target`);
/// the rest aim at a uniform sample of the joint space, as RRT's do.
pub(super) const TREE_LOCAL: f64 = 0.5;
/// The spread of those aims: a normal deviate of this many radians per joint.
pub(super) const TREE_SIGMA: f64 = 1.0;
/// Longest step of a tree extension (radians, Euclidean in joint space).
pub(super) const TREE_STEP: f64 = 0.3;
/// Most steps of one connect march (see `RobotPlanner::connect`).
const CONNECT_MAX: usize = 64;
/// The seed stream of the goal trees.
const TREE_STREAM: u64 = 0x7472_6565;

impl<S: Space> RobotPlanner<S> {
    /// The goal node for a configuration, created (and checked) on first use.
    pub(super) fn goal_node(&self, q: &[f64], checks: &mut u64) -> (u32, Option<ObjectSet>) {
        let key: Vec<u64> = q.iter().map(|v| v.to_bits()).collect();
        let existing = self.lock(
            |s| {
                s.goal_ids
                    .get(&key)
                    .map(|&id| (id, s.labels.get(&LabelKey::Vertex(ModeKey::Empty, Node::Goal(id))).cloned()))
            },
            checks,
        );
        if let Some((id, Some(l))) = existing {
            return (id, l);
        }
        let lab = match self.space.check(q, &Mode::default(), checks) {
            Check::Touches(l) => Some(l),
            Check::Blocked(_) => None,
        };
        let id = self.lock(
            |s| {
                let id = *s.goal_ids.entry(key).or_insert_with(|| {
                    s.goals.push(GoalNode::new(q));
                    (s.goals.len() - 1) as u32
                });
                s.labels.insert(LabelKey::Vertex(ModeKey::Empty, Node::Goal(id)), lab.clone());
                id
            },
            checks,
        );
        (id, lab)
    }

    /// Grows the tree of goal node `root` through round `r`: an RRT-Connect from the goal
    /// with the roadmap as its other tree (see [`Self::connect`]). Its nodes join the
    /// search graphs beside the goal, so a goal inside a narrow place reaches out of it
    /// before the roadmap is dense there. Half its extensions aim at uniform samples,
    /// half near a node of its own (see [`local_target`]). Round `rr` makes
    /// [`TREE_PER_SAMPLE`] extension attempts per sample the roadmap draws in that round,
    /// divided among the query's `share` goals (the object's usable grasps, or 1), from
    /// an RNG seeded by (seed, goal, rr): the tree is a pure function of those, whichever
    /// query grows it. Checked under the robot's lock, without rayon.
    pub(super) fn grow_tree(&self, root: u32, r: usize, share: usize, checks: &mut u64) {
        let mut c = 0;
        self.lock(
            |s| {
                let q_root = s.goals[root as usize].q.clone();
                let key = mix(&q_root.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
                let lim = self.space.limits().to_vec();
                while s.goals[root as usize].tree_rounds < r {
                    let rr = s.goals[root as usize].tree_rounds + 1;
                    let mut rng = ChaCha8Rng::seed_from_u64(mix(&[self.seed, TREE_STREAM, key, rr as u64]));
                    let (first, max) = (self.opts.first_batch, self.settings.max_samples);
                    let drawn = samples_at(rr, first, max) - if rr > 1 { samples_at(rr - 1, first, max) } else { 0 };
                    let attempts = ((TREE_PER_SAMPLE * drawn) as usize / share.max(1)).clamp(TREE_MIN, TREE_MAX);
                    let links = s.goals[root as usize].links.len();
                    for _ in 0..attempts {
                        // In the first rounds, a tree that reaches the roadmap has done its
                        // round's work: the search that follows may well find the path, and
                        // an easy query should not pay for the rest. A rule of the tree's
                        // own, so the tree stays a function of (seed, goal, round).
                        if rr <= super::SEARCH_FIRST_ROUNDS && s.goals[root as usize].links.len() > links {
                            break;
                        }
                        let target = match rng.random::<f64>() < TREE_LOCAL {
                            true => local_target(s, root, &lim, &mut rng),
                            false => lim.iter().map(|(lo, hi)| lo + rng.random::<f64>() * (hi - lo)).collect(),
                        };
                        if let Some(id) = self.extend(s, root, &target, rr, &mut c) {
                            self.connect(s, root, id, rr, &mut c);
                        }
                    }
                    s.goals[root as usize].tree_rounds = rr;
                }
            },
            checks,
        );
        *checks += c;
    }

    /// RRT-Connect's connect step, with the roadmap as the other tree: from tree node
    /// `from`, march towards its nearest roadmap vertex (see [`Self::march`]); a
    /// reached vertex becomes the tree's link to the roadmap. Tree nodes join the search
    /// graphs only through their tree edges and such links, so a tree of thousands of
    /// nodes stays cheap to search.
    fn connect(&self, s: &mut State, root: u32, from: u32, rr: usize, c: &mut u64) {
        let Some(&(_, v)) = s.map.trees[rr].nearest(&s.goals[from as usize].q, 1, |_| false).first() else { return };
        let q_v = s.map.q(v).to_vec();
        if let Some((cur, le)) = self.march(s, root, from, &q_v, rr, c) {
            s.labels.insert(LabelKey::Edge(ModeKey::Empty, Node::Map(v), Node::Goal(cur)), Some(le));
            s.goals[root as usize].links.push((cur, v, rr));
        }
    }

    /// RRT's extension of goal `root`'s tree: one step from the node nearest `target`
    /// towards it, added when the step and its motion hit nothing fixed.
    fn extend(&self, s: &mut State, root: u32, target: &[f64], rr: usize, c: &mut u64) -> Option<u32> {
        let near = nearest_in_tree(s, root, target);
        let q_near = s.goals[near as usize].q.clone();
        let q = step_towards(&q_near, target, dist2(&q_near, target).sqrt());
        let Check::Touches(l) = self.space.check(&q, &Mode::default(), c) else { return None };
        let Check::Touches(le) = self.tree_segment((&q_near, tree_label(s, near)), (&q, Some(&l)), c) else {
            return None;
        };
        Some(add_tree_node(s, root, near, &q, (l, le), rr))
    }

    /// From node `from` of goal `root`'s tree, march towards `to` in steps of
    /// [`TREE_STEP`], adding a node per clear step, up to [`CONNECT_MAX`] steps, until
    /// blocked or within a step of `to`: then the last node and its clear segment's
    /// label to `to`.
    fn march(
        &self,
        s: &mut State,
        root: u32,
        from: u32,
        to: &[f64],
        rr: usize,
        c: &mut u64,
    ) -> Option<(u32, ObjectSet)> {
        let mut cur = from;
        for _ in 0..CONNECT_MAX {
            let q_cur = s.goals[cur as usize].q.clone();
            let d = dist2(&q_cur, to).sqrt();
            if d <= TREE_STEP {
                return match self.tree_segment((&q_cur, tree_label(s, cur)), (to, None), c) {
                    Check::Touches(le) => Some((cur, le)),
                    Check::Blocked(_) => None,
                };
            }
            let q = step_towards(&q_cur, to, d);
            let Check::Touches(l) = self.space.check(&q, &Mode::default(), c) else { return None };
            let Check::Touches(le) = self.tree_segment((&q_cur, tree_label(s, cur)), (&q, Some(&l)), c) else {
                return None;
            };
            cur = add_tree_node(s, root, cur, &q, (l, le), rr);
        }
        None
    }

    /// A tree edge's check (the coarse one: a path through the tree is certified when it
    /// wins, like any other). An end whose empty-hand label is given (a tree node, a step's
    /// end just checked) is not checked again: its label is joined to the rest's, which
    /// is the whole check's label.
    fn tree_segment(
        &self,
        (a, la): (&[f64], Option<&ObjectSet>),
        (b, lb): (&[f64], Option<&ObjectSet>),
        c: &mut u64,
    ) -> Check {
        let res = self.settings.resolution;
        match self.space.check_segment_known((a, b), res, (la.is_some(), lb.is_some()), &Mode::default(), c) {
            Check::Touches(mut l) => {
                for known in [la, lb].into_iter().flatten() {
                    l.union_with(known);
                }
                Check::Touches(l)
            }
            blocked => blocked,
        }
    }

    /// The node carried objects are taken to: home itself, or a goal node; or what
    /// blocks it.
    pub(super) fn drop_node(&self, checks: &mut u64) -> Result<Node, Blocker> {
        let (home, drop) = (self.space.home(), self.space.drop_config());
        let home_ok = self.lock(|s| s.map.home_ok, checks);
        if !home_ok {
            return Err(self.blocker(home));
        }
        if home == drop {
            return Ok(Node::Map(0));
        }
        if let Some(b) = self.outside_limits(drop) {
            return Err(b);
        }
        match self.goal_node(drop, checks) {
            (id, Some(_)) => Ok(Node::Goal(id)),
            (_, None) => Err(self.blocker(drop)),
        }
    }

    /// What blocks a configuration known to be blocked (checked again: failures only).
    /// Checks made only to explain a failure are not counted in the query's figures.
    pub(super) fn blocker(&self, q: &[f64]) -> Blocker {
        match self.space.check(q, &Mode::default(), &mut 0) {
            Check::Blocked(b) => b,
            // A space whose checks changed their mind: say so rather than invent a body.
            Check::Touches(_) => Blocker::JointLimit { joint: "(unknown)".into(), value: f64::NAN },
        }
    }

    /// The first joint of `q` outside its limits (or a wrong joint count), as a block.
    pub(super) fn outside_limits(&self, q: &[f64]) -> Option<Blocker> {
        let lim = self.space.limits();
        let bad = q.len() != self.space.dof() || q.iter().zip(lim).any(|(v, (lo, hi))| v < lo || v > hi);
        if !bad {
            return None;
        }
        // A world robot names the joint; a test space may not check limits at all.
        if let Check::Blocked(b @ Blocker::JointLimit { .. }) = self.space.check(q, &Mode::default(), &mut 0) {
            return Some(b);
        }
        let i = q.iter().zip(lim).position(|(v, (lo, hi))| v < lo || v > hi).unwrap_or(q.len().min(lim.len()));
        Some(Blocker::JointLimit { joint: format!("#{}", i + 1), value: q.get(i).copied().unwrap_or(f64::NAN) })
    }

    /// selectGrasps results made into goals; grasps whose pre-grasp or straight
    /// approach hits something fixed (or the pre-grasp touches the object) are dropped.
    /// Also returns, when no grasp is left, what blocked each (distinct blocks, in order).
    pub(super) fn grasp_goals(
        &self,
        o: ObjectId,
        grasps: Vec<GraspConfig>,
        checks: &mut u64,
    ) -> (Vec<GraspGoal>, Vec<Blocker>) {
        let mut out = Vec::new();
        let mut blocked = Vec::new();
        let mut closing: Vec<Blocker> = Vec::new();
        // Keyed by position: selectGrasps may return several solutions of one grasp.
        for (g, cfg) in grasps.into_iter().enumerate() {
            let (pre, lab) = self.goal_node(&cfg.q_pregrasp, checks);
            let Some(lab) = lab else {
                blocked.push((cfg.clone(), None));
                continue;
            };
            if lab.contains(o) {
                continue;
            }
            let g = g as u32;
            let held = self.space.held(o, cfg.grasp, &cfg.q_grasp);
            // Fingers that would hit something fixed closing on the object (or opening at
            // the drop) rule the grasp out, saying what they hit; objects they would touch
            // are in the approach's label (see `eval`).
            if let Err(b) = self.space.fingers_clear(&held, &cfg.q_grasp, checks) {
                closing.push(b);
                continue;
            }
            let item = LabelKey::Approach(o, g);
            let cached = self.lock(
                |s| {
                    s.helds
                        .entry((o, g))
                        .or_insert_with(|| (held.clone(), cfg.q_grasp.to_vec(), cfg.q_pregrasp.to_vec()));
                    s.labels.get(&item).cloned()
                },
                checks,
            );
            let approach = match cached {
                Some(l) => l,
                None => {
                    let job = Job {
                        item,
                        a: cfg.q_pregrasp.to_vec(),
                        b: None,
                        mode: Mode { absent: ObjectSet::single(o), held: Some(held.clone()) },
                        grasp: Some(cfg.q_grasp.to_vec()),
                        empty: None,
                    };
                    let l = self.eval(&job, super::lazy::Pass::Coarse, checks);
                    self.lock(|s| s.labels.insert(item, l.clone()), checks);
                    l
                }
            };
            match approach {
                Some(approach) => out.push(GraspGoal { cfg, key: g, pre, pre_set: lab, approach }),
                None => blocked.push((cfg, Some(held))),
            }
        }
        if !out.is_empty() {
            return (out, Vec::new());
        }
        // Only on failure: check the blocked grasps again to say what blocks them.
        let mut blockers: Vec<Blocker> = Vec::new();
        for b in closing {
            if !blockers.contains(&b) {
                blockers.push(b);
            }
        }
        for (cfg, held) in blocked {
            let b = match held {
                None => self.blocker(&cfg.q_pregrasp),
                Some(held) => {
                    let mode = Mode { absent: ObjectSet::single(o), held: Some(held) };
                    let res = self.settings.resolution;
                    match self.space.check_segment(&cfg.q_grasp, &cfg.q_pregrasp, res, &mode, &mut 0) {
                        Check::Blocked(b) => b,
                        Check::Touches(_) => continue,
                    }
                }
            };
            if !blockers.contains(&b) {
                blockers.push(b);
            }
        }
        (out, blockers)
    }
}

/// The node of goal `root`'s tree (the root included) nearest `q`; ties go to the older
/// node (see [`GrowingIndex`](super::super::knn::GrowingIndex)).
fn nearest_in_tree(s: &mut State, root: u32, q: &[f64]) -> u32 {
    let node = |s: &State, i: usize| if i == 0 { root } else { s.goals[root as usize].tree[i - 1].0 };
    let n = 1 + s.goals[root as usize].tree.len();
    let dof = s.goals[root as usize].q.len();
    let mut index = std::mem::take(&mut s.goals[root as usize].index);
    let i = index.nearest(dof, n, |i| &s.goals[node(s, i) as usize].q, q, |_| false, None);
    s.goals[root as usize].index = index;
    node(s, i)
}

/// The empty-hand label of goal tree node `id` (a goal or a node added to its tree), when
/// known and not blocked.
fn tree_label(s: &State, id: u32) -> Option<&ObjectSet> {
    s.labels.get(&LabelKey::Vertex(ModeKey::Empty, Node::Goal(id))).and_then(|l| l.as_ref())
}

/// An extension's aim near a node of goal `root`'s tree drawn uniformly (the root
/// included), a normal step of [`TREE_SIGMA`] per joint away, within the limits.
/// Uniform samples pull a tree's outermost nodes, which in a pocket (a goal behind a
/// window, inside a cage) face the walls: nearly every such extension fails and the
/// tree stays a few dozen nodes. Aims drawn per node instead (as EST does) spread the
/// tree through the pocket until some node sees its way out.
fn local_target(s: &State, root: u32, lim: &[(f64, f64)], rng: &mut ChaCha8Rng) -> Vec<f64> {
    let tree = &s.goals[root as usize].tree;
    let i = (rng.random::<f64>() * (tree.len() + 1) as f64) as usize;
    let node = if i == 0 { root } else { tree[(i - 1).min(tree.len() - 1)].0 };
    let q = &s.goals[node as usize].q;
    q.iter().zip(lim).map(|(v, (lo, hi))| (v + TREE_SIGMA * normal(rng)).clamp(*lo, *hi)).collect()
}

/// The point [`TREE_STEP`] from `a` towards `b` (`b` itself when nearer), `d` being their distance.
fn step_towards(a: &[f64], b: &[f64], d: f64) -> Vec<f64> {
    let t = (TREE_STEP / d.max(f64::MIN_POSITIVE)).min(1.0);
    a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect()
}

/// Adds `q` to goal `root`'s tree under `parent`, with its empty-hand label and its
/// edge's.
fn add_tree_node(s: &mut State, root: u32, parent: u32, q: &[f64], (l, le): (ObjectSet, ObjectSet), rr: usize) -> u32 {
    s.goals.push(GoalNode::new(q));
    let id = (s.goals.len() - 1) as u32;
    s.labels.insert(LabelKey::Vertex(ModeKey::Empty, Node::Goal(id)), Some(l));
    s.labels.insert(LabelKey::Edge(ModeKey::Empty, Node::Goal(parent), Node::Goal(id)), Some(le));
    s.goals[root as usize].tree.push((id, parent, rr));
    id
}
