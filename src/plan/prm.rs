//! PRMwO queries for one robot (the paper's Algorithms 1 and 3) on a shared, lazily
//! labelled roadmap.
//!
//! A grasp query searches one layered graph per reachable grasp: layer A is the
//! roadmap with the empty hand (edges touching the target object are unusable: it
//! cannot be removed to grasp it), a transition edge does pre-grasp -> grasp ->
//! pre-grasp (the straight approach with the object ignored, then the retreat carrying
//! it), layer B is the roadmap carrying the object to the drop configuration, and,
//! when drop differs from home, layer C returns home with the empty hand. One search
//! over the layers minimises the union of every label on the whole motion.
//!
//! Lock discipline: the per-robot state is locked only for short sequential steps;
//! rayon is never called while it is held, so queries for the same robot may run
//! inside rayon tasks without deadlock, and every result is a pure function of the
//! seed, the roadmap prefix and the goal, whatever the thread count or query order.

use std::collections::{HashMap, HashSet};
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use super::layers::{
    build, exact_set, job, lookup, node_q, store, Built, GoalNode, GraspGoal, Item, Job, ModeKey, Node, State,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::knn::dist2;
use super::roadmap::{mix, Roadmap};
use super::search::{fewest_removals, fewest_vertices, Found};
use super::space::{Mode, Space};
use super::{Answer, Budget, FoundPath, Goal, QueryStats, Unreachable};
use crate::resolve::{ObjectId, Objective, PlannerSettings};
use crate::world::{Blocker, Check, Config, GraspConfig, JointPath, ObjectSet};

/// Tree growth per round: the first round's attempts, doubling, capped.
const TREE_FIRST: usize = 8;
const TREE_MAX: usize = 128;
/// Longest step of a tree extension (radians, Euclidean in joint space).
const TREE_STEP: f64 = 0.3;
/// The seed stream of the goal trees.
const TREE_STREAM: u64 = 0x7472_6565;

/// Tuning beyond [`PlannerSettings`].
#[derive(Clone, Debug, PartialEq)]
pub struct PrmOptions {
    /// Samples in round 1; the cumulative count doubles every round.
    pub first_batch: usize,
    /// Stop once this many rounds pass without a smaller removal set (`None`: grow
    /// until a free path appears or `max_samples` is reached, the paper's rule).
    pub patience: Option<usize>,
}

impl Default for PrmOptions {
    fn default() -> Self {
        PrmOptions { first_batch: 32, patience: None }
    }
}

/// One candidate answer during a query.
#[derive(Clone)]
struct Cand {
    found: Found,
    /// (layer, node) of each vertex of the path.
    nodes: Vec<(u8, Node)>,
    /// The exact union of the labels on the path.
    set: ObjectSet,
    /// Index into the query's goals (grasps).
    goal: usize,
}

/// The PRMwO planner of one robot over a [`Space`].
pub struct RobotPlanner<S: Space> {
    space: S,
    settings: PlannerSettings,
    opts: PrmOptions,
    /// Scenario seed mixed with the robot's identity.
    seed: u64,
    state: Mutex<Option<State>>,
}

impl<S: Space> RobotPlanner<S> {
    /// `robot_key` distinguishes robots (their index) in the seed.
    pub fn new(space: S, settings: &PlannerSettings, opts: &PrmOptions, robot_key: u64) -> Self {
        RobotPlanner {
            space,
            settings: settings.clone(),
            opts: opts.clone(),
            seed: mix(&[settings.seed, robot_key]),
            state: Mutex::new(None),
        }
    }

    pub fn space(&self) -> &S {
        &self.space
    }

    /// Roadmap vertices so far.
    pub fn roadmap_len(&self) -> usize {
        self.lock(|s| s.map.vlab.len(), &mut 0)
    }

    fn lock<T>(&self, f: impl FnOnce(&mut State) -> T, checks: &mut u64) -> T {
        let mut guard = self.state.lock().unwrap_or_else(|p| p.into_inner());
        let st = guard.get_or_insert_with(|| {
            let map = Roadmap::new(&self.space, checks);
            State {
                map,
                goals: Vec::new(),
                goal_ids: HashMap::new(),
                map_edges: Vec::new(),
                labels: HashMap::new(),
                certified: HashSet::new(),
                helds: HashMap::new(),
                grasps: HashMap::new(),
            }
        });
        f(st)
    }

    /// Answers one query with the settings' objective.
    pub fn query(&self, goal: &Goal) -> Answer {
        self.query_with(goal, self.settings.objective)
    }

    /// Answers one query with the given objective (both objectives share the roadmap).
    pub fn query_with(&self, goal: &Goal, objective: Objective) -> Answer {
        let t0 = Instant::now();
        let mut stats = QueryStats::default();
        let mut checks = 0u64;
        // Before `lock` builds a fresh roadmap (home alone): a first query reuses nothing.
        stats.reused_vertices = {
            let guard = self.state.lock().unwrap_or_else(|p| p.into_inner());
            guard.as_ref().map_or(0, |s| s.map.vlab.len() as u64)
        };
        let result = self.run(goal, objective, t0, &mut stats, &mut checks);
        stats.checks = checks;
        stats.time_ms = t0.elapsed().as_secs_f64() * 1e3;
        Answer { result, stats }
    }

    fn run(
        &self,
        goal: &Goal,
        objective: Objective,
        t0: Instant,
        stats: &mut QueryStats,
        checks: &mut u64,
    ) -> Result<FoundPath, Unreachable> {
        // Goals: (object, grasps) or a single configuration.
        let (object, goals): (Option<ObjectId>, Vec<GraspGoal>) = match goal {
            Goal::Reach(q) => {
                if let Some(b) = self.outside_limits(q) {
                    return Err(Unreachable::GoalBlocked(b));
                }
                let (id, lab) = self.goal_node(q, checks);
                let Some(lab) = lab else { return Err(Unreachable::GoalBlocked(self.blocker(q))) };
                let cfg = GraspConfig { grasp: 0, q_grasp: Config(q.to_vec()), q_pregrasp: Config(q.to_vec()) };
                (None, vec![GraspGoal { cfg, key: 0, pre: id, pre_set: lab, approach: ObjectSet::new() }])
            }
            Goal::Grasp(o) => {
                let grasps = match self.lock(|s| s.grasps.get(o).cloned(), checks) {
                    Some(g) => g,
                    None => {
                        let g = self.space.grasps(*o);
                        self.lock(|s| s.grasps.insert(*o, g.clone()), checks);
                        g
                    }
                };
                if grasps.is_empty() {
                    return Err(Unreachable::NoGraspSolution);
                }
                let (goals, blockers) = self.grasp_goals(*o, grasps, checks);
                if goals.is_empty() {
                    return Err(Unreachable::ApproachBlocked { blockers });
                }
                (Some(*o), goals)
            }
        };
        stats.paths = goals.len() as u64;
        let drop = match object {
            Some(_) => Some(self.drop_node(checks).map_err(Unreachable::DropBlocked)?),
            None => None,
        };
        let max_r = Roadmap::max_rounds(self.opts.first_batch, self.settings.max_samples);
        let mut best: Option<(Cand, usize)> = None;
        let mut timed_out = false;
        let mut last = 0;
        for r in 0..=max_r {
            last = r;
            self.ensure_round(r, stats, checks);
            // fewest_removals keeps the best answer, so later rounds only look for smaller sets.
            let bound = match (&best, objective) {
                (Some((b, _)), Objective::FewestRemovals) => b.set.len() as u32,
                _ => u32::MAX,
            };
            // A grasp whose straight approach (or pre-grasp) alone touches `bound` objects
            // cannot beat the best answer on any roadmap: leave it out, and stop when none is left.
            let live: Vec<GraspGoal> =
                goals.iter().filter(|g| (g.approach.union(&g.pre_set).len() as u32) < bound).cloned().collect();
            if live.is_empty() {
                break;
            }
            // The paper's rule samples on only while a free path may still appear.
            if objective == Objective::FewestVertices
                && best.is_some()
                && goals.iter().all(|g| !g.approach.is_empty() || !g.pre_set.is_empty())
            {
                break;
            }
            // Until a first path is found, trees grown from the goals search their
            // neighbourhood, where narrow entrances (a cage, a shelf) usually are.
            let trees = best.is_none() && r > 0;
            if trees {
                for g in &live {
                    self.grow_tree(g.pre, r, checks);
                }
            }
            let cand = self.search_round(r, object, &live, drop, (objective, bound, trees), checks).map(|mut c| {
                c.goal = goals.iter().position(|g| g.key == live[c.goal].key).expect("live goal");
                c
            });
            let better = match (&cand, &best) {
                (None, _) => false,
                (Some(_), None) => true,
                (Some(c), Some((b, _))) => match objective {
                    // The paper's rule: the fewest-vertices path on the final roadmap.
                    Objective::FewestVertices => true,
                    Objective::FewestRemovals => key(c) < key(b),
                },
            };
            if better {
                let improved = best.as_ref().is_none_or(|(b, _)| cand.as_ref().unwrap().set.len() < b.set.len());
                let since = if improved { r } else { best.as_ref().unwrap().1 };
                best = Some((cand.unwrap(), since));
            }
            if let Some((b, since)) = &best {
                if b.set.is_empty() || self.settings.first_path {
                    break;
                }
                if self.opts.patience.is_some_and(|p| r >= since + p) {
                    break;
                }
            }
            if self.settings.time_budget.is_some_and(|tb| t0.elapsed().as_secs_f64() > tb) {
                timed_out = r < max_r;
                break;
            }
        }
        let Some((cand, _)) = best else {
            let samples = self.lock(|s| s.map.rounds.get(last).map_or(0, |e| e.samples), checks);
            let max_samples = self.settings.max_samples as u64;
            return Err(Unreachable::BudgetExhausted(Budget { samples, max_samples, timed_out }));
        };
        Ok(self.assemble(&cand, object, &goals, checks))
    }

    /// Grows the roadmap to round `r`, computing missing rounds without the lock.
    fn ensure_round(&self, r: usize, stats: &mut QueryStats, checks: &mut u64) {
        loop {
            let next = self.lock(|s| (s.map.rounds_done() < r).then(|| s.map.snapshot()), checks);
            let Some(snapshot) = next else { return };
            let round = snapshot.next_round(
                &self.space,
                self.seed,
                self.opts.first_batch,
                self.settings.max_samples,
                self.settings.neighbours,
            );
            let (samples, added, c) = (round.samples - snapshot.samples, round.vlab.len(), round.checks);
            let appended = self.lock(
                |s| {
                    let ok = s.map.append(round);
                    s.map_edges.resize(s.map.edges.len(), None);
                    ok
                },
                checks,
            );
            if appended {
                stats.samples += samples;
                stats.connected += added as u64;
                *checks += c;
            }
        }
    }

    /// The goal node for a configuration, created (and checked) on first use.
    fn goal_node(&self, q: &[f64], checks: &mut u64) -> (u32, Option<ObjectSet>) {
        let key: Vec<u64> = q.iter().map(|v| v.to_bits()).collect();
        let existing = self.lock(
            |s| {
                s.goal_ids
                    .get(&key)
                    .map(|&id| (id, s.labels.get(&Item::Vertex(ModeKey::Empty, Node::Goal(id))).cloned()))
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
                s.labels.insert(Item::Vertex(ModeKey::Empty, Node::Goal(id)), lab.clone());
                id
            },
            checks,
        );
        (id, lab)
    }

    /// Grows the tree of goal node `root` through round `r`: an RRT from the goal whose
    /// nodes join the search graphs beside it (each also linked to its nearest roadmap
    /// vertices), so a goal inside a narrow place reaches out of it before the roadmap
    /// is dense there. Round `rr` adds up to `TREE_FIRST << (rr - 1)` nodes (capped)
    /// from an RNG seeded by (seed, goal, rr): the tree is a pure function of those,
    /// whichever query grows it. Checked under the robot's lock, without rayon.
    fn grow_tree(&self, root: u32, r: usize, checks: &mut u64) {
        let mut c = 0;
        self.lock(
            |s| {
                let q_root = s.goals[root as usize].q.clone();
                let key = mix(&q_root.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
                let lim = self.space.limits().to_vec();
                while s.goals[root as usize].tree_rounds < r {
                    let rr = s.goals[root as usize].tree_rounds + 1;
                    let mut rng = ChaCha8Rng::seed_from_u64(mix(&[self.seed, TREE_STREAM, key, rr as u64]));
                    let attempts = (TREE_FIRST << (rr - 1).min(16)).min(TREE_MAX);
                    for _ in 0..attempts {
                        let target: Vec<f64> =
                            lim.iter().map(|(lo, hi)| lo + rng.random::<f64>() * (hi - lo)).collect();
                        let nodes = std::iter::once(root).chain(s.goals[root as usize].tree.iter().map(|t| t.0));
                        let near = nodes
                            .map(|x| (dist2(&s.goals[x as usize].q, &target), x))
                            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                        let Some((d2, near)) = near else { break };
                        let q_near = s.goals[near as usize].q.clone();
                        let t = (TREE_STEP / d2.sqrt().max(f64::MIN_POSITIVE)).min(1.0);
                        let q: Vec<f64> = q_near.iter().zip(&target).map(|(a, b)| a + t * (b - a)).collect();
                        let Check::Touches(l) = self.space.check(&q, &Mode::default(), &mut c) else { continue };
                        let res = self.settings.resolution;
                        let seg = self.space.check_segment(&q_near, &q, res, &Mode::default(), &mut c);
                        let Check::Touches(le) = seg else { continue };
                        s.goals.push(GoalNode::new(&q));
                        let id = (s.goals.len() - 1) as u32;
                        s.labels.insert(Item::Vertex(ModeKey::Empty, Node::Goal(id)), Some(l));
                        s.labels.insert(Item::Edge(ModeKey::Empty, Node::Goal(near), Node::Goal(id)), Some(le));
                        s.goals[root as usize].tree.push((id, near, rr));
                    }
                    s.goals[root as usize].tree_rounds = rr;
                }
            },
            checks,
        );
        *checks += c;
    }

    /// The node carried objects are taken to: home itself, or a goal node; or what
    /// blocks it.
    fn drop_node(&self, checks: &mut u64) -> Result<Node, Blocker> {
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
    fn blocker(&self, q: &[f64]) -> Blocker {
        match self.space.check(q, &Mode::default(), &mut 0) {
            Check::Blocked(b) => b,
            // A space whose checks changed their mind: say so rather than invent a body.
            Check::Touches(_) => Blocker::JointLimit { joint: "(unknown)".into(), value: f64::NAN },
        }
    }

    /// The first joint of `q` outside its limits (or a wrong joint count), as a block.
    fn outside_limits(&self, q: &[f64]) -> Option<Blocker> {
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
    fn grasp_goals(&self, o: ObjectId, grasps: Vec<GraspConfig>, checks: &mut u64) -> (Vec<GraspGoal>, Vec<Blocker>) {
        let mut out = Vec::new();
        let mut blocked = Vec::new();
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
            let held = self.space.held(o, &cfg.q_grasp);
            let item = Item::Approach(o, g);
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
                    let l = self.eval(&job, false, checks);
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

    /// Labels one item. Segments, the straight approach included, are checked every
    /// `resolution` while searching and with the certifying check (`fine`) once on a
    /// chosen path.
    fn eval(&self, job: &Job, fine: bool, checks: &mut u64) -> Option<ObjectSet> {
        let res = self.settings.resolution;
        let seg = |a: &[f64], b: &[f64], mode: &Mode, checks: &mut u64| {
            if fine {
                self.space.check_segment_fine(a, b, res, mode, checks)
            } else {
                self.space.check_segment(a, b, res, mode, checks)
            }
        };
        let c = match (&job.b, &job.grasp) {
            // The approach in (object absent, hand empty) and the retreat carrying the
            // object pass the same samples, and a check carrying an object finds all the
            // empty hand finds (the robot's own bodies are checked the same way) plus what
            // the object touches: the retreat alone gives the union.
            (_, Some(grasp)) => seg(grasp, &job.a, &job.mode, checks),
            // Carrying, with the empty hand's label of this edge known: the robot's own
            // bodies meet the same things (less the object, now in the hand), so only the
            // object needs checking; an edge blocked for the empty hand stays blocked.
            (Some(b), None) if !fine && job.empty.is_some() => match &job.empty {
                Some(Some(empty)) => match self.space.check_segment_held(&job.a, b, res, &job.mode, checks) {
                    Check::Touches(mut l) => {
                        let mut robot = empty.clone();
                        for o in job.mode.absent.iter() {
                            robot.remove(o);
                        }
                        l.union_with(&robot);
                        Check::Touches(l)
                    }
                    blocked => blocked,
                },
                _ => return None,
            },
            (Some(b), None) => seg(&job.a, b, &job.mode, checks),
            (None, None) => self.space.check(&job.a, &job.mode, checks),
        };
        match c {
            Check::Touches(l) => Some(l),
            Check::Blocked(_) => None,
        }
    }

    /// Searches every goal's graph at round `r`, evaluating labels lazily, and returns
    /// the best candidate.
    fn search_round(
        &self,
        r: usize,
        object: Option<ObjectId>,
        goals: &[GraspGoal],
        drop: Option<Node>,
        (objective, bound, trees): (Objective, u32, bool),
        checks: &mut u64,
    ) -> Option<Cand> {
        let mut built: Vec<Built> = self.lock(
            |s| {
                if !s.map.home_ok {
                    return Vec::new();
                }
                goals.iter().map(|g| build(s, r, self.settings.neighbours, object, g, drop, (bound, trees))).collect()
            },
            checks,
        );
        if built.is_empty() {
            return None;
        }
        let search = |b: &Built| match objective {
            Objective::FewestRemovals => fewest_removals(&b.g, b.start, b.goal, bound),
            Objective::FewestVertices => fewest_vertices(&b.g, b.start, b.goal),
        };
        // Each goal's answer on its current labels; re-searched only when they change.
        let mut found: Vec<Option<Found>> = built.par_iter().map(search).collect();
        let mut dirty = vec![false; built.len()];
        loop {
            let stale: Vec<usize> = (0..built.len()).filter(|&i| dirty[i]).collect();
            let fresh: Vec<Option<Found>> = stale.par_iter().map(|&i| search(&built[i])).collect();
            for (i, f) in stale.into_iter().zip(fresh) {
                found[i] = f;
                dirty[i] = false;
            }
            // Which goals' paths to evaluate. Unknown labels are lower bounds and only grow,
            // so under `fewest_removals` each goal's (set size, length) can only get worse:
            // the goal with the smallest key is the only one worth checking, and once its
            // path is fully known no other goal can beat it. The paper's rule has no such
            // bound (a blocked edge can make a longer path touch less), so it checks all.
            let chosen: Vec<usize> = match objective {
                Objective::FewestRemovals => found
                    .iter()
                    .enumerate()
                    .filter_map(|(i, f)| f.as_ref().map(|f| ((f.set.count(), Len(f.len), i), i)))
                    .min_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal))
                    .map(|(_, i)| vec![i])
                    .unwrap_or_default(),
                Objective::FewestVertices => (0..built.len()).collect(),
            };
            // Unknown items on the chosen paths.
            let mut wanted: Vec<Item> = Vec::new();
            let mut seen = HashSet::new();
            for &i in &chosen {
                let (b, Some(f)) = (&built[i], &found[i]) else { continue };
                for &v in &f.verts {
                    if !b.g.vlab[v as usize].is_known() && seen.insert(b.vkey[v as usize]) {
                        wanted.push(b.vkey[v as usize]);
                    }
                }
                for &e in &f.edges {
                    if !b.g.elab[e as usize].is_known() {
                        let k = b.ekey[e as usize].expect("unknown edges have keys");
                        if seen.insert(k) {
                            wanted.push(k);
                        }
                    }
                }
            }
            if wanted.is_empty() {
                let sets: Vec<Option<ObjectSet>> = self.lock(
                    |s| chosen.iter().map(|&i| found[i].as_ref().map(|f| exact_set(s, &built[i], f))).collect(),
                    checks,
                );
                let mut best: Option<Cand> = None;
                for (&i, set) in chosen.iter().zip(sets) {
                    let (Some(f), Some(set)) = (&found[i], set) else { continue };
                    let nodes = f.verts.iter().map(|&v| built[i].vnode[v as usize]).collect();
                    let c = Cand { found: f.clone(), goal: i, nodes, set };
                    let better = best.as_ref().is_none_or(|b| match objective {
                        Objective::FewestRemovals => key(&c) < key(b),
                        Objective::FewestVertices => vkey(&c) < vkey(b),
                    });
                    if better {
                        best = Some(c);
                    }
                }
                // Certify the winner's segments with the fine check. Its labels contain the
                // coarse ones, so the coarse labels were lower bounds: if none changed the
                // answer stands, else the changed labels go into every graph and we search on.
                let Some(c) = &best else { return None };
                let changed = self.certify(&built[c.goal], &c.found, checks);
                if changed.is_empty() {
                    return best;
                }
                for (b, d) in built.iter_mut().zip(dirty.iter_mut()) {
                    for e in 0..b.ekey.len() {
                        if let Some(l) = b.ekey[e].and_then(|k| changed.get(&k)) {
                            b.g.elab[e] = b.erule[e].known(l.as_ref());
                            *d = true;
                        }
                    }
                }
                continue;
            }
            // Look up or prepare jobs under the lock, evaluate without it.
            let (mut known, jobs): (HashMap<Item, Option<ObjectSet>>, Vec<Job>) = self.lock(
                |s| {
                    let mut known = HashMap::new();
                    let mut jobs = Vec::new();
                    for it in wanted {
                        match lookup(s, it) {
                            Some(l) => {
                                known.insert(it, l);
                            }
                            None => jobs.push(job(s, it)),
                        }
                    }
                    (known, jobs)
                },
                checks,
            );
            let results: Vec<(Option<ObjectSet>, u64)> = jobs
                .par_iter()
                .map(|j| {
                    let mut c = 0;
                    let l = self.eval(j, false, &mut c);
                    (l, c)
                })
                .collect();
            self.lock(
                |s| {
                    for (j, (l, _)) in jobs.iter().zip(&results) {
                        store(s, j.item, l.clone());
                    }
                },
                checks,
            );
            for (j, (l, c)) in jobs.iter().zip(results) {
                *checks += c;
                known.insert(j.item, l);
            }
            for ((b, f), d) in built.iter_mut().zip(&found).zip(dirty.iter_mut()) {
                let Some(f) = f else { continue };
                for &v in &f.verts {
                    let v = v as usize;
                    if let Some(l) = known.get(&b.vkey[v]) {
                        if !b.g.vlab[v].is_known() {
                            b.g.vlab[v] = b.vrule[v].known(l.as_ref());
                            *d = true;
                        }
                    }
                }
                for &e in &f.edges {
                    let e = e as usize;
                    if let Some(l) = b.ekey[e].and_then(|k| known.get(&k)) {
                        if !b.g.elab[e].is_known() {
                            b.g.elab[e] = b.erule[e].known(l.as_ref());
                            *d = true;
                        }
                    }
                }
            }
        }
    }

    /// Re-checks the segments of a path that only have a coarse label with the fine
    /// check; returns the items whose label changed (now stored).
    fn certify(&self, b: &Built, f: &Found, checks: &mut u64) -> HashMap<Item, Option<ObjectSet>> {
        let jobs: Vec<Job> = self.lock(
            |s| {
                let mut seen = HashSet::new();
                f.edges
                    .iter()
                    .filter_map(|&e| b.ekey[e as usize])
                    .filter(|k| {
                        matches!(k, Item::Edge(..) | Item::Approach(..)) && !s.certified.contains(k) && seen.insert(*k)
                    })
                    .map(|k| job(s, k))
                    .collect()
            },
            checks,
        );
        let results: Vec<(Option<ObjectSet>, u64)> = jobs
            .par_iter()
            .map(|j| {
                let mut c = 0;
                (self.eval(j, true, &mut c), c)
            })
            .collect();
        *checks += results.iter().map(|r| r.1).sum::<u64>();
        self.lock(
            |s| {
                let mut changed = HashMap::new();
                for (j, (l, _)) in jobs.iter().zip(results) {
                    s.certified.insert(j.item);
                    if lookup(s, j.item).as_ref() != Some(&l) {
                        store(s, j.item, l.clone());
                        changed.insert(j.item, l);
                    }
                }
                changed
            },
            checks,
        )
    }

    /// Turns a candidate's layered path into joint paths.
    fn assemble(&self, cand: &Cand, object: Option<ObjectId>, goals: &[GraspGoal], checks: &mut u64) -> FoundPath {
        let g = &goals[cand.goal];
        let configs: Vec<(u8, Vec<f64>)> =
            self.lock(|s| cand.nodes.iter().map(|&(layer, node)| (layer, node_q(s, node).to_vec())).collect(), checks);
        let mut approach: Vec<Config> = configs.iter().filter(|c| c.0 == 0).map(|c| Config(c.1.clone())).collect();
        let mut retreat = Vec::new();
        if object.is_some() {
            approach.push(g.cfg.q_grasp.clone());
            retreat.push(g.cfg.q_grasp.clone());
            for (_, q) in configs.iter().filter(|c| c.0 > 0) {
                if retreat.last().is_none_or(|l: &Config| l.0 != *q) {
                    retreat.push(Config(q.clone()));
                }
            }
        }
        FoundPath {
            grasp: object.map(|_| g.cfg.grasp),
            approach: JointPath(approach),
            retreat: JointPath(retreat),
            removals: cand.set.clone(),
        }
    }
}

fn key(c: &Cand) -> (usize, Len, usize) {
    (c.set.len(), Len(c.found.len), c.goal)
}

fn vkey(c: &Cand) -> (usize, usize, Len, usize) {
    (c.set.len(), c.found.verts.len(), Len(c.found.len), c.goal)
}

#[derive(Clone, Copy, PartialEq, PartialOrd)]
struct Len(f64);
