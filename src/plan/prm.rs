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

use super::knn::dist2;
use super::roadmap::{mix, Roadmap};
use super::search::{fewest_removals, fewest_vertices, mask, Found, Graph, Lab};
use super::space::{Mode, Space};
use super::{Answer, FoundPath, Goal, QueryStats, Unreachable};
use crate::resolve::{ObjectId, Objective, PlannerSettings};
use crate::world::{Check, Config, GraspConfig, Held, JointPath, ObjectSet};

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

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Node {
    Map(u32),
    Goal(u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum ModeKey {
    Empty,
    /// Carrying the object after the `.1`-th configuration `selectGrasps` returned.
    Carry(ObjectId, u32),
}

/// Anything that gets a label.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Item {
    Vertex(ModeKey, Node),
    /// Nodes in increasing order.
    Edge(ModeKey, Node, Node),
    /// Pre-grasp -> grasp with the object absent, then back carrying it.
    Approach(ObjectId, u32),
}

struct GoalNode {
    q: Vec<f64>,
    /// Cumulative neighbours at round r (index r).
    nbrs: Vec<Vec<u32>>,
}

type Carried = (Held, Vec<f64>, Vec<f64>);

struct State {
    map: Roadmap,
    goals: Vec<GoalNode>,
    goal_ids: HashMap<Vec<u64>, u32>,
    /// Empty-hand labels of roadmap edges, by edge index (`None`: not checked yet).
    map_edges: Vec<Option<Option<ObjectSet>>>,
    labels: HashMap<Item, Option<ObjectSet>>,
    /// Per (object, grasp): the held object, q_grasp and q_pregrasp.
    helds: HashMap<(ObjectId, u32), Carried>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Rule {
    Plain,
    /// Labels containing the object block (it cannot be removed to reach itself).
    Forbid(ObjectId),
    /// The object is gone from the scene.
    Strip(ObjectId),
}

impl Rule {
    fn known(self, l: Option<&ObjectSet>) -> Lab {
        self.apply(l, false)
    }
    fn bound(self, l: Option<&ObjectSet>) -> Lab {
        self.apply(l, true)
    }
    fn apply(self, l: Option<&ObjectSet>, unknown: bool) -> Lab {
        let Some(s) = l else { return Lab::Blocked };
        let s = match self {
            Rule::Plain => mask(s),
            Rule::Forbid(o) if s.contains(o) => return Lab::Blocked,
            Rule::Forbid(_) => mask(s),
            Rule::Strip(o) => mask(s) & !(1 << o.index().min(127)),
        };
        if unknown {
            Lab::Unknown(s)
        } else {
            Lab::Known(s)
        }
    }
}

/// A layered search graph for one goal at one round, with the key of every element.
struct Built {
    g: Graph,
    vkey: Vec<Item>,
    vrule: Vec<Rule>,
    /// `None` for elements whose label was final at build time.
    ekey: Vec<Option<Item>>,
    erule: Vec<Rule>,
    /// Layer of each vertex and its node.
    vnode: Vec<(u8, Node)>,
    /// Labels of the transition edges (which have no key).
    fixed: HashMap<u32, ObjectSet>,
    start: u32,
    goal: u32,
}

/// A usable grasp: its goal node and the approach/retreat label.
#[derive(Clone)]
struct GraspGoal {
    cfg: GraspConfig,
    /// Empty-hand label of the pre-grasp.
    pre_set: ObjectSet,
    /// Position in the `selectGrasps` answer (the carry mode's key).
    key: u32,
    pre: u32,
    approach: ObjectSet,
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

/// A configuration-level job for the workers.
struct Job {
    item: Item,
    a: Vec<f64>,
    b: Option<Vec<f64>>,
    mode: Mode,
    /// For `Approach`: the grasp configuration, checked pre -> grasp (absent) then back (held).
    grasp: Option<Vec<f64>>,
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
                helds: HashMap::new(),
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
        stats.reused_vertices = self.lock(|s| s.map.vlab.len() as u64, &mut checks);
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
        let dof = self.space.dof();
        // Goals: (object, grasps) or a single configuration.
        let (object, goals): (Option<ObjectId>, Vec<GraspGoal>) = match goal {
            Goal::Reach(q) => {
                let lim = self.space.limits();
                if q.len() != dof || q.iter().zip(lim).any(|(v, (lo, hi))| v < lo || v > hi) {
                    return Err(Unreachable::GoalBlocked);
                }
                let (id, lab) = self.goal_node(q, checks);
                if lab.is_none() {
                    return Err(Unreachable::GoalBlocked);
                }

                let cfg = GraspConfig { grasp: 0, q_grasp: Config(q.to_vec()), q_pregrasp: Config(q.to_vec()) };
                (
                    None,
                    vec![GraspGoal {
                        cfg,
                        key: 0,
                        pre: id,
                        pre_set: lab.unwrap_or_default(),
                        approach: ObjectSet::new(),
                    }],
                )
            }
            Goal::Grasp(o) => {
                let grasps = self.space.grasps(*o);
                if grasps.is_empty() {
                    return Err(Unreachable::NoGraspSolution);
                }
                let goals = self.grasp_goals(*o, grasps, checks);
                if goals.is_empty() {
                    return Err(Unreachable::NoGraspSolution);
                }
                (Some(*o), goals)
            }
        };
        stats.paths = goals.len() as u64;
        let drop = match object {
            Some(_) => self.drop_node(checks),
            None => None,
        };
        if object.is_some() && drop.is_none() {
            return Err(Unreachable::NoPath);
        }
        let max_r = Roadmap::max_rounds(self.opts.first_batch, self.settings.max_samples);
        let mut best: Option<(Cand, usize)> = None;
        for r in 0..=max_r {
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
            let cand = self.search_round(r, object, &live, drop, (objective, bound), checks).map(|mut c| {
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
                break;
            }
        }
        let Some((cand, _)) = best else { return Err(Unreachable::NoPath) };
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
                    s.goals.push(GoalNode { q: q.to_vec(), nbrs: Vec::new() });
                    (s.goals.len() - 1) as u32
                });
                s.labels.insert(Item::Vertex(ModeKey::Empty, Node::Goal(id)), lab.clone());
                id
            },
            checks,
        );
        (id, lab)
    }

    /// The node carried objects are taken to: home itself, or a goal node.
    fn drop_node(&self, checks: &mut u64) -> Option<Node> {
        let (home, drop) = (self.space.home(), self.space.drop_config());
        let home_ok = self.lock(|s| s.map.home_ok, checks);
        if !home_ok {
            return None;
        }
        if home == drop {
            return Some(Node::Map(0));
        }
        let (id, lab) = self.goal_node(drop, checks);
        lab.map(|_| Node::Goal(id))
    }

    /// selectGrasps results made into goals; grasps whose pre-grasp or straight
    /// approach hits something fixed (or the pre-grasp touches the object) are dropped.
    fn grasp_goals(&self, o: ObjectId, grasps: Vec<GraspConfig>, checks: &mut u64) -> Vec<GraspGoal> {
        let mut out = Vec::new();
        // Keyed by position: selectGrasps may return several solutions of one grasp.
        for (g, cfg) in grasps.into_iter().enumerate() {
            let (pre, lab) = self.goal_node(&cfg.q_pregrasp, checks);
            let Some(lab) = lab else { continue };
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
                        mode: Mode { absent: ObjectSet::single(o), held: Some(held) },
                        grasp: Some(cfg.q_grasp.to_vec()),
                    };
                    let l = self.eval(&job, checks);
                    self.lock(|s| s.labels.insert(item, l.clone()), checks);
                    l
                }
            };
            if let Some(approach) = approach {
                out.push(GraspGoal { cfg, key: g, pre, pre_set: lab, approach });
            }
        }
        out
    }

    fn eval(&self, job: &Job, checks: &mut u64) -> Option<ObjectSet> {
        let step = self.settings.resolution;
        let c = match (&job.b, &job.grasp) {
            (_, Some(grasp)) => {
                let absent = Mode { absent: job.mode.absent.clone(), held: None };
                self.space
                    .check_segment(&job.a, grasp, step, &absent, checks)
                    .and(self.space.check_segment(grasp, &job.a, step, &job.mode, checks))
            }
            (Some(b), None) => self.space.check_segment(&job.a, b, step, &job.mode, checks),
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
        (objective, bound): (Objective, u32),
        checks: &mut u64,
    ) -> Option<Cand> {
        let mut built: Vec<Built> = self.lock(
            |s| {
                if !s.map.home_ok {
                    return Vec::new();
                }
                goals.iter().map(|g| build(s, r, self.settings.neighbours, object, g, drop)).collect()
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
        loop {
            let found: Vec<Option<Found>> = built.par_iter().map(search).collect();
            // Unknown items on the chosen paths.
            let mut wanted: Vec<Item> = Vec::new();
            let mut seen = HashSet::new();
            for (b, f) in built.iter().zip(&found) {
                let Some(f) = f else { continue };
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
                    |s| built.iter().zip(&found).map(|(b, f)| f.as_ref().map(|f| exact_set(s, b, f))).collect(),
                    checks,
                );
                let mut best: Option<Cand> = None;
                for (i, (f, set)) in found.into_iter().zip(sets).enumerate() {
                    let (Some(f), Some(set)) = (f, set) else { continue };
                    let nodes = f.verts.iter().map(|&v| built[i].vnode[v as usize]).collect();
                    let c = Cand { found: f, goal: i, nodes, set };
                    let better = best.as_ref().is_none_or(|b| match objective {
                        Objective::FewestRemovals => key(&c) < key(b),
                        Objective::FewestVertices => vkey(&c) < vkey(b),
                    });
                    if better {
                        best = Some(c);
                    }
                }
                return best;
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
                    let l = self.eval(j, &mut c);
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
            for (b, f) in built.iter_mut().zip(&found) {
                let Some(f) = f else { continue };
                for &v in &f.verts {
                    let v = v as usize;
                    if let Some(l) = known.get(&b.vkey[v]) {
                        if !b.g.vlab[v].is_known() {
                            b.g.vlab[v] = b.vrule[v].known(l.as_ref());
                        }
                    }
                }
                for &e in &f.edges {
                    let e = e as usize;
                    if let Some(l) = b.ekey[e].and_then(|k| known.get(&k)) {
                        if !b.g.elab[e].is_known() {
                            b.g.elab[e] = b.erule[e].known(l.as_ref());
                        }
                    }
                }
            }
        }
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

/// The exact union of the labels on a fully known path.
fn exact_set(s: &State, b: &Built, f: &Found) -> ObjectSet {
    let mut out = ObjectSet::new();
    let mut add = |l: Option<Option<ObjectSet>>, rule: Rule| {
        if let Some(Some(mut l)) = l {
            if let Rule::Strip(o) = rule {
                l.remove(o);
            }
            out.union_with(&l);
        }
    };
    for &v in &f.verts {
        add(lookup(s, b.vkey[v as usize]), b.vrule[v as usize]);
    }
    for &e in &f.edges {
        match b.ekey[e as usize] {
            Some(k) => add(lookup(s, k), b.erule[e as usize]),
            None => add(b.fixed.get(&e).cloned().map(Some), Rule::Plain),
        }
    }
    out
}

#[derive(Clone, Copy, PartialEq, PartialOrd)]
struct Len(f64);

fn node_q(s: &State, n: Node) -> &[f64] {
    match n {
        Node::Map(v) => s.map.q(v),
        Node::Goal(g) => &s.goals[g as usize].q,
    }
}

/// The stored label of an item, if checked.
fn lookup(s: &State, it: Item) -> Option<Option<ObjectSet>> {
    match it {
        Item::Vertex(ModeKey::Empty, Node::Map(v)) => Some(Some(s.map.vlab[v as usize].clone())),
        Item::Edge(ModeKey::Empty, Node::Map(a), Node::Map(b)) => {
            let e = map_edge(s, a, b)?;
            s.map_edges[e].clone()
        }
        _ => s.labels.get(&it).cloned(),
    }
}

fn store(s: &mut State, it: Item, l: Option<ObjectSet>) {
    if let Item::Edge(ModeKey::Empty, Node::Map(a), Node::Map(b)) = it {
        if let Some(e) = map_edge(s, a, b) {
            s.map_edges[e] = Some(l);
            return;
        }
    }
    s.labels.insert(it, l);
}

fn map_edge(s: &State, a: u32, b: u32) -> Option<usize> {
    // Roadmap edges are sorted within each round and rounds are appended in order.
    let pair = (a.min(b), a.max(b));
    // The round of an edge is the round of its later vertex.
    let r = s.map.rounds.partition_point(|e| e.verts <= pair.1 as usize);
    let (from, to) = (s.map.rounds[r - 1].edges, s.map.rounds.get(r)?.edges);
    s.map.edges[from..to].binary_search(&pair).ok().map(|i| from + i)
}

fn mode_of(s: &State, m: ModeKey) -> Mode {
    match m {
        ModeKey::Empty => Mode::default(),
        ModeKey::Carry(o, g) => Mode { absent: ObjectSet::single(o), held: Some(s.helds[&(o, g)].0.clone()) },
    }
}

fn job(s: &State, it: Item) -> Job {
    match it {
        Item::Vertex(m, n) => Job { item: it, a: node_q(s, n).to_vec(), b: None, mode: mode_of(s, m), grasp: None },
        Item::Edge(m, a, b) => {
            Job { item: it, a: node_q(s, a).to_vec(), b: Some(node_q(s, b).to_vec()), mode: mode_of(s, m), grasp: None }
        }
        Item::Approach(o, g) => {
            let (held, q_grasp, q_pre) = s.helds[&(o, g)].clone();
            Job {
                item: it,
                a: q_pre,
                b: None,
                mode: Mode { absent: ObjectSet::single(o), held: Some(held) },
                grasp: Some(q_grasp),
            }
        }
    }
}

/// Cumulative neighbours of a goal node at round `r`.
fn goal_nbrs(s: &mut State, id: u32, r: usize, k: usize) -> Vec<u32> {
    let g = &mut s.goals[id as usize];
    while g.nbrs.len() <= r {
        let rr = g.nbrs.len();
        let mut n: Vec<u32> = if rr == 0 { Vec::new() } else { g.nbrs[rr - 1].clone() };
        n.extend(s.map.trees[rr].nearest(&g.q, k, |_| false).into_iter().map(|(_, i)| i));
        n.sort_unstable();
        n.dedup();
        g.nbrs.push(n);
    }
    g.nbrs[r].clone()
}

fn build(s: &mut State, r: usize, k: usize, object: Option<ObjectId>, goal: &GraspGoal, drop: Option<Node>) -> Built {
    use ModeKey::{Carry, Empty};
    let pre = goal.pre;
    let mut layers: Vec<(ModeKey, Rule, Vec<u32>)> = Vec::new();
    match object {
        None => layers.push((Empty, Rule::Plain, vec![pre])),
        Some(o) => {
            let carry = Carry(o, goal.key);
            layers.push((Empty, Rule::Forbid(o), vec![pre]));
            match drop {
                Some(Node::Goal(d)) => {
                    let extras = if d == pre { vec![pre] } else { vec![pre, d] };
                    layers.push((carry, Rule::Plain, extras));
                    layers.push((Empty, Rule::Strip(o), vec![d]));
                }
                _ => layers.push((carry, Rule::Plain, vec![pre])),
            }
        }
    }
    let mut nbrs: HashMap<u32, Vec<u32>> = HashMap::new();
    for (_, _, extras) in &layers {
        for &x in extras {
            if let std::collections::hash_map::Entry::Vacant(e) = nbrs.entry(x) {
                e.insert(goal_nbrs(s, x, r, k));
            }
        }
    }
    let s = &*s;
    let n = s.map.rounds[r].verts as u32;
    let m = s.map.rounds[r].edges;
    let mut b = Built {
        g: Graph::default(),
        vkey: Vec::new(),
        vrule: Vec::new(),
        ekey: Vec::new(),
        erule: Vec::new(),
        vnode: Vec::new(),
        fixed: HashMap::new(),
        start: 0,
        goal: 0,
    };
    let mut offsets = Vec::new();
    for (li, (mode, rule, extras)) in layers.iter().enumerate() {
        let (mode, rule) = (*mode, *rule);
        let off = b.g.vlab.len() as u32;
        offsets.push(off);
        let strip = |l: &ObjectSet| {
            let mut l = l.clone();
            if let Carry(o, _) = mode {
                l.remove(o);
            }
            l
        };
        let nodes = (0..n).map(Node::Map).chain(extras.iter().map(|&x| Node::Goal(x)));
        for node in nodes {
            let item = Item::Vertex(mode, node);
            let lab = match (mode, node) {
                (Empty, Node::Map(v)) => rule.known(Some(&s.map.vlab[v as usize])),
                _ => match lookup(s, item) {
                    Some(l) => rule.known(l.as_ref()),
                    None => {
                        // Carrying: the arm's own contacts stay, the object's are unknown.
                        let empty = lookup(s, Item::Vertex(Empty, node)).flatten();
                        match empty {
                            Some(l) => rule.bound(Some(&strip(&l))),
                            None => Lab::Unknown(0),
                        }
                    }
                },
            };
            b.g.add_vertex(lab);
            b.vkey.push(item);
            b.vrule.push(rule);
            b.vnode.push((li as u8, node));
        }
        let add_edge =
            |b: &mut Built, la: u32, lb: u32, na: Node, nb: Node, len: f64, known: Option<Option<ObjectSet>>| {
                let item = Item::Edge(mode, na.min(nb), na.max(nb));
                let lab = match known {
                    Some(l) => rule.known(l.as_ref()),
                    None => match (&b.g.vlab[la as usize], &b.g.vlab[lb as usize]) {
                        (Lab::Blocked, _) | (_, Lab::Blocked) => Lab::Blocked,
                        (Lab::Known(x) | Lab::Unknown(x), Lab::Known(y) | Lab::Unknown(y)) => Lab::Unknown(x | y),
                    },
                };
                b.g.add_edge(la, lb, len, lab);
                b.ekey.push(Some(item));
                b.erule.push(rule);
            };
        for e in 0..m {
            let (va, vb) = s.map.edges[e];
            let known = match mode {
                Empty => s.map_edges[e].clone(),
                Carry(..) => s.labels.get(&Item::Edge(mode, Node::Map(va), Node::Map(vb))).cloned(),
            };
            add_edge(&mut b, off + va, off + vb, Node::Map(va), Node::Map(vb), s.map.elen[e], known);
        }
        for (xi, &x) in extras.iter().enumerate() {
            let lx = off + n + xi as u32;
            let qx = &s.goals[x as usize].q;
            for &v in &nbrs[&x] {
                let len = dist2(qx, s.map.q(v)).sqrt();
                let known = lookup(s, Item::Edge(mode, Node::Map(v), Node::Goal(x)));
                add_edge(&mut b, off + v, lx, Node::Map(v), Node::Goal(x), len, known);
            }
        }
    }
    let local = |layer: usize, node: Node| -> u32 {
        let off = offsets[layer];
        match node {
            Node::Map(v) => off + v,
            Node::Goal(x) => off + n + layers[layer].2.iter().position(|&y| y == x).expect("extra") as u32,
        }
    };
    b.start = local(0, Node::Map(0));
    let transition = |b: &mut Built, a: u32, c: u32, len: f64, l: &ObjectSet| {
        let e = b.g.add_edge(a, c, len, Lab::Known(mask(l)));
        b.fixed.insert(e, l.clone());
        b.ekey.push(None);
        b.erule.push(Rule::Plain);
    };
    match object {
        None => b.goal = local(0, Node::Goal(pre)),
        Some(_) => {
            let len = 2.0 * dist2(&goal.cfg.q_pregrasp, &goal.cfg.q_grasp).sqrt();
            transition(&mut b, local(0, Node::Goal(pre)), local(1, Node::Goal(pre)), len, &goal.approach);
            if layers.len() == 3 {
                let Some(Node::Goal(d)) = drop else { unreachable!("three layers only with a drop goal") };
                transition(&mut b, local(1, Node::Goal(d)), local(2, Node::Goal(d)), 0.0, &ObjectSet::new());
                b.goal = local(2, Node::Map(0));
            } else {
                b.goal = local(1, drop.unwrap_or(Node::Map(0)));
            }
        }
    }
    b
}
