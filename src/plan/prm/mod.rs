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

mod connect;
mod free;
mod goals;
mod lazy;
mod shortcut;
#[cfg(test)]
mod tests;
mod walk;

use crate::plan::{Map, Set};
use std::sync::Mutex;
use std::time::Instant;

use super::layers::{mode_of, node_q, GraspGoal, ModeKey, Node, State};
use super::roadmap::{mix, samples_at, Roadmap};
use super::search::{Found, Len};
use super::space::Mode;
use super::space::Space;
use super::{Answer, Budget, FoundPath, Goal, QueryStats, Unreachable};
use crate::resolve::{ObjectId, Objective, PlannerSettings};
use crate::world::{Config, GraspConfig, JointPath, ObjectSet};

/// Rounds in which a search without growing the goal trees comes first (see `run`).
const SEARCH_FIRST_ROUNDS: usize = 2;

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
                goal_ids: Map::default(),
                map_edges: Vec::new(),
                labels: Map::default(),
                certified: Set::default(),
                helds: Map::default(),
                grasps: Map::default(),
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
                    return Err(match self.space.why_no_grasp(*o) {
                        Some(why) => Unreachable::NoGrasp { why },
                        None => Unreachable::NoGraspSolution,
                    });
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
        // The search through free space (see `connect` and `free`), set up on first use;
        // `None` inside when home or every goal touches something.
        let mut free: Option<free::FreeSearch> = None;
        let mut free_ready = false;
        // The first round whose search the free-space trees precede. In a scene without
        // objects the first: there every path is free or blocked, and the first rounds'
        // searches (with their goal trees) mostly spent checks on queries the trees
        // answer anyway (the families' objectless rows' medians fell by a tenth, the
        // UR5's `cage` 11.4 -> 8.1 ms). With objects the roadmap still comes first in
        // the first rounds: a path it finds with removals bounds the rest, and a roadmap
        // that earlier queries grew answers at little cost.
        let free_first = if self.space.has_objects() { SEARCH_FIRST_ROUNDS + 1 } else { 1 };
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
            // The round's extension attempts for the free-space trees (see `connect`).
            let mut grow_free = |free: &mut Option<free::FreeSearch>, none_yet: bool, checks: &mut u64| {
                if !free_ready {
                    *free = free::FreeSearch::new(self, object, &goals, checks);
                    free_ready = true;
                }
                let f = free.as_mut()?;
                let (first, max) = (self.opts.first_batch, self.settings.max_samples);
                let drawn = samples_at(r, first, max) - if r > 1 { samples_at(r - 1, first, max) } else { 0 };
                let per = if none_yet { connect::PER_SAMPLE_NONE } else { connect::PER_SAMPLE_FEWER };
                f.grow(self, &goals, per * drawn, t0, checks)
            };
            // From the third round on, while no path touching nothing is known (and a
            // first path is not all that was asked for), the free-space trees grow beside
            // the roadmap, before the round's search: when they get through, the round's
            // graph (the largest yet) is not searched. Without objects, from the first
            // round (see `free_first`).
            let wanted = match &best {
                None => true,
                Some((b, _)) => {
                    !b.set.is_empty() && !self.settings.first_path && objective == Objective::FewestRemovals
                }
            };
            if wanted && r >= free_first {
                if let Some(found) = grow_free(&mut free, best.is_none(), checks) {
                    return Ok(found);
                }
            }
            // Until a first path is found, trees grown from the goals search their
            // neighbourhood, where narrow entrances (a cage, a shelf) usually are. In the
            // first rounds, whose graphs are small, the trees grow only when the round's
            // roadmap with the trees so far finds no path: easy queries skip them.
            let trees = best.is_none() && r > 0;
            let mut cand = None;
            if trees && r <= SEARCH_FIRST_ROUNDS {
                cand = self.search_round(r, object, &live, drop, (objective, bound, trees), checks);
            }
            // In the first rounds the free-space trees grow only after the round's
            // roadmap found no path at all (a query the small roadmap answers, with
            // removals or without, spends nothing on them), and before the goal trees:
            // such a query is most often a narrow passage, which they get through, and
            // the goal trees and the second search are then not needed.
            if cand.is_none() && best.is_none() && trees && r < free_first {
                if let Some(found) = grow_free(&mut free, true, checks) {
                    return Ok(found);
                }
            }
            if cand.is_none() {
                if trees {
                    for g in &live {
                        self.grow_tree(g.pre, r, goals.len(), checks);
                    }
                }
                cand = self.search_round(r, object, &live, drop, (objective, bound, trees), checks);
            }
            let cand = cand.map(|mut c| {
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
            let extensions = free.map_or(0, |f| f.attempted);
            return Err(Unreachable::BudgetExhausted(Budget { samples, max_samples, extensions, timed_out }));
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
    /// Turns a candidate's layered path into joint paths.
    fn assemble(&self, cand: &Cand, object: Option<ObjectId>, goals: &[GraspGoal], checks: &mut u64) -> FoundPath {
        let g = &goals[cand.goal];
        let (found, carry) = self.lock(
            |s| {
                let found: Vec<(u8, Vec<f64>)> =
                    cand.nodes.iter().map(|&(layer, node)| (layer, node_q(s, node).to_vec())).collect();
                (found, object.map(|o| mode_of(s, ModeKey::Carry(o, g.key))))
            },
            checks,
        );
        // Each layer's run of waypoints is shortened in that layer's mode.
        let mode = |layer: u8| match (layer, object) {
            (0, _) | (_, None) => Mode::default(),
            (1, Some(_)) => carry.clone().unwrap_or_default(),
            (_, Some(o)) => Mode { absent: ObjectSet::single(o), held: None },
        };
        let mut configs: Vec<(u8, Vec<f64>)> = Vec::with_capacity(found.len());
        for run in found.chunk_by(|a, b| a.0 == b.0) {
            let qs: Vec<Vec<f64>> = run.iter().map(|c| c.1.clone()).collect();
            let short = self.shortcut(&qs, &mode(run[0].0), &cand.set, checks);
            configs.extend(short.into_iter().map(|q| (run[0].0, q)));
        }
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
            forced: forced(goals),
        }
    }
}

/// What every usable goal's own configurations and straight moves touch: no path of the
/// query can avoid removing these.
fn forced(goals: &[GraspGoal]) -> ObjectSet {
    let mut sets = goals.iter().map(|g| {
        let mut l = g.pre_set.clone();
        l.union_with(&g.approach);
        l
    });
    let first = sets.next().unwrap_or_default();
    sets.fold(first, |acc, l| acc.iter().filter(|o| l.contains(*o)).collect())
}

fn key(c: &Cand) -> (usize, Len, usize) {
    (c.set.len(), Len(c.found.len), c.goal)
}

fn vkey(c: &Cand) -> (usize, usize, Len, usize) {
    (c.set.len(), c.found.verts.len(), Len(c.found.len), c.goal)
}
