//! Lazy labelling: one round's search over every goal's layered graph, checking only
//! the elements a best path uses, then certifying the winner with the fine check.

use crate::plan::{Map, Set};

use rayon::prelude::*;

use super::super::layers::{build, exact_set, job, lookup, store, Built, GraspGoal, Job, LabelKey, Node, Rule, State};
use super::super::mask::Mask;
use super::super::search::{fewest_removals, fewest_vertices, Found, Lab, Len};
use super::super::space::{Mode, Space};
use super::walk::{twin_units, twins, Walk, Walker};
use super::{key, vkey, Cand, RobotPlanner};
use crate::resolve::{ObjectId, Objective};
use crate::world::{Check, ObjectSet, OPEN_POSTURE};

/// The stored coarse label a certification of `j`'s item may build on (see
/// [`Pass::Rest`]): none for a carrying edge whose empty-hand label is known and whose
/// fingers close on the object, which may have had its coarse label from the empty
/// hand's (labels are only ever added), with the fingers open rather than closed. Where
/// they hold it open, as in the empty hand, that label is the carrying check's own: the
/// arm's own contacts are the same, less the object.
pub(super) fn coarse_for_rest(s: &State, j: &Job) -> Option<ObjectSet> {
    let open = j.mode.held.as_ref().is_none_or(|h| h.posture == OPEN_POSTURE);
    lookup(s, j.item).flatten().filter(|_| j.empty.is_none() || open)
}

/// How [`RobotPlanner::eval`] checks an item's segments.
#[derive(Clone, Copy)]
pub(super) enum Pass<'a> {
    /// Every `resolution`: the search's check.
    Coarse,
    /// The certifying check.
    Fine,
    /// The certifying check's samples that the coarse check did not take, joined with
    /// the coarse label given: for an item whose coarse label came from the same
    /// segments in the same mode (samples do not depend on the way a segment is walked).
    Rest(&'a ObjectSet),
}

impl<S: Space> RobotPlanner<S> {
    /// Labels one item. Segments, the straight approach included, are checked every
    /// `resolution` while searching and with the certifying check once on a chosen path.
    pub(super) fn eval(&self, job: &Job, pass: Pass, checks: &mut u64) -> Option<ObjectSet> {
        let res = self.settings.resolution;
        let seg = |a: &[f64], b: &[f64], mode: &Mode, checks: &mut u64| match pass {
            Pass::Coarse => self.space.check_segment(a, b, res, mode, checks),
            Pass::Fine => self.space.check_motion(a, b, res, mode, checks),
            Pass::Rest(_) => self.space.check_motion_rest(a, b, res, mode, checks),
        };
        let c = match (&job.b, &job.grasp) {
            // The approach in (object absent, hand empty) and the retreat carrying the
            // object pass the same samples, and a check carrying an object finds all the
            // empty hand finds (the robot's own bodies are checked the same way) plus what
            // the object touches: the retreat alone gives the union.
            // A gripper that closes on the object goes in open: then the way in is checked
            // with the fingers open too, and the fingers' closing, and the labels joined.
            (_, Some(grasp)) => match (seg(grasp, &job.a, &job.mode, checks), &job.mode.held) {
                (Check::Touches(mut l), Some(held)) if held.posture != OPEN_POSTURE => {
                    let open = Mode { absent: job.mode.absent.clone(), held: None };
                    match seg(&job.a, grasp, &open, checks) {
                        Check::Touches(o) => l.union_with(&o),
                        Check::Blocked(_) => return None,
                    }
                    match self.space.fingers_clear(held, grasp, checks) {
                        Ok(o) => l.union_with(&o),
                        Err(_) => return None,
                    }
                    Check::Touches(l)
                }
                (c, _) => c,
            },
            // Carrying, with the empty hand's label of this edge known: the robot's own
            // bodies meet the same things (less the object, now in the hand), so only the
            // object needs checking; an edge blocked for the empty hand stays blocked.
            (Some(b), None) if matches!(pass, Pass::Coarse) && job.empty.is_some() => match &job.empty {
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
        match (c, pass) {
            (Check::Touches(l), Pass::Rest(coarse)) => Some(l.union(coarse)),
            (Check::Touches(l), _) => Some(l),
            (Check::Blocked(_), _) => None,
        }
    }

    /// Searches every goal's graph at round `r`, evaluating labels lazily, and returns
    /// the best candidate.
    pub(super) fn search_round(
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
                // Fewest vertices counts a tree's nodes: its graphs keep them all.
                let shape = (bound, trees, objective == Objective::FewestRemovals);
                goals.iter().map(|g| build(s, r, self.settings.neighbours, object, g, drop, shape)).collect()
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
        // Edges partly walked by an earlier search of this round (see `eval_until_spoilt`).
        let mut walks: Map<LabelKey, Walk> = Map::default();
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
            // Unknown items on the chosen paths, from the paths' two ends inwards (see
            // `Stakes`), each with what its path took it to cost.
            let mut wanted: Vec<LabelKey> = Vec::new();
            let mut stakes = Stakes::default();
            let mut seen = Set::default();
            for &i in &chosen {
                let (b, Some(f)) = (&built[i], &found[i]) else { continue };
                // Under `fewest_removals` a label beyond the path's set changes its key too.
                let set = (objective == Objective::FewestRemovals).then_some(&f.set);
                let mut items = Vec::with_capacity(f.verts.len() + f.edges.len());
                for (k, &v) in f.verts.iter().enumerate() {
                    if !b.g.vlab()[v as usize].is_known() {
                        items.push((b.vkey[v as usize], b.vrule[v as usize]));
                    }
                    if let Some(&e) = f.edges.get(k).filter(|&&e| !b.g.elab()[e as usize].is_known()) {
                        items.push((b.ekey[e as usize].expect("unknown edges have keys"), b.erule[e as usize]));
                    }
                }
                for (k, rule) in ends_inwards(items) {
                    stakes.add(k, rule, set);
                    if seen.insert(k) {
                        wanted.push(k);
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
                    let nodes = built[i].path_nodes(f);
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
                self.lock(
                    |s| {
                        for (b, d) in built.iter_mut().zip(dirty.iter_mut()) {
                            *d |= b.relabel_chains(s, &changed);
                        }
                    },
                    checks,
                );
                for (b, d) in built.iter_mut().zip(dirty.iter_mut()) {
                    for e in 0..b.ekey.len() {
                        if let Some(l) = b.ekey[e].and_then(|k| changed.get(&k)) {
                            b.g.set_elab(e, b.erule[e].known(l.as_ref()));
                            *d = true;
                        }
                    }
                }
                continue;
            }
            // Look up or prepare jobs under the lock, evaluate without it.
            let (mut known, jobs): (Map<LabelKey, Option<ObjectSet>>, Vec<Job>) = self.lock(
                |s| {
                    let mut known = Map::default();
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
            // Checked up to the first that spoils its path (see `Stakes`); none when an
            // item another query labelled already does: the search runs again first.
            let spoilt = known.iter().any(|(k, l)| stakes.spoilt_by(k, l));
            let results = match spoilt {
                true => Vec::new(),
                false => {
                    let (results, spent) = self.eval_until_spoilt(&jobs, &stakes, &mut walks);
                    *checks += spent;
                    results
                }
            };
            self.lock(
                |s| {
                    for (i, l) in &results {
                        store(s, jobs[*i].item, l.clone());
                    }
                },
                checks,
            );
            for (i, l) in results {
                known.insert(jobs[i].item, l);
            }
            for ((b, f), d) in built.iter_mut().zip(&found).zip(dirty.iter_mut()) {
                let Some(f) = f else { continue };
                for &v in &f.verts {
                    let v = v as usize;
                    if let Some(l) = known.get(&b.vkey[v]) {
                        if !b.g.vlab()[v].is_known() {
                            b.g.set_vlab(v, b.vrule[v].known(l.as_ref()));
                            *d = true;
                        }
                    }
                }
                for &e in &f.edges {
                    let e = e as usize;
                    if let Some(l) = b.ekey[e].and_then(|k| known.get(&k)) {
                        if !b.g.elab()[e].is_known() {
                            b.g.set_elab(e, b.erule[e].known(l.as_ref()));
                            *d = true;
                        }
                    }
                }
            }
        }
    }

    /// Labels `jobs` up to the first that spoils its path (see [`Stakes`]): the labels
    /// found, by job index, and the checks spent. The jobs other than plain edges first,
    /// in their order, in chunks of 1, 2, 4, ...; then the plain edges together, level by
    /// level (see [`Walk`]), each edge's level checked in turn and left at its first
    /// blocked sample. An edge left partly walked keeps its walk in `walks` for the
    /// round's next search. The same checks whatever the thread count.
    fn eval_until_spoilt(
        &self,
        jobs: &[Job],
        stakes: &Stakes,
        walks: &mut Map<LabelKey, Walk>,
    ) -> (Vec<(usize, Option<ObjectSet>)>, u64) {
        let res = self.settings.resolution;
        let (mut out, mut spent) = (Vec::with_capacity(jobs.len()), 0);
        let mut single: Vec<(usize, Walk)> = Vec::new();
        let mut others: Vec<usize> = Vec::new();
        for (i, j) in jobs.iter().enumerate() {
            let walk = match (&j.b, &j.grasp, &j.empty) {
                (Some(b), None, None) => {
                    walks.remove(&j.item).or_else(|| Some(Walk::new(&j.a, b, self.space.segment_steps(&j.a, b, res)?)))
                }
                _ => None,
            };
            match walk {
                Some(w) => single.push((i, w)),
                None => others.push(i),
            }
        }
        let mut walking = twins(jobs, single);
        let mut chunk = 1;
        let mut at = 0;
        let mut spoilt = false;
        while at < others.len() && !spoilt {
            let part = &others[at..(at + chunk).min(others.len())];
            let done: Vec<(Option<ObjectSet>, u64)> = part
                .par_iter()
                .map(|&i| {
                    let mut c = 0;
                    (self.eval(&jobs[i], Pass::Coarse, &mut c), c)
                })
                .collect();
            for (&i, (l, c)) in part.iter().zip(done) {
                spoilt |= stakes.spoilt_by(&jobs[i].item, &l);
                spent += c;
                out.push((i, l));
            }
            at += part.len();
            chunk *= 2;
        }
        while !walking.is_empty() && !spoilt {
            let done: Vec<((bool, bool), u64)> = walking
                .par_iter_mut()
                .map(|wk| {
                    let mut c = 0;
                    let mode = &jobs[wk.i].mode;
                    let blocked = match &mut wk.twin {
                        None => (wk.walk.step(&self.space, mode, &mut c), false),
                        Some((_, empty)) => wk.walk.step_twin(empty, &self.space, mode, &mut c),
                    };
                    (blocked, c)
                })
                .collect();
            let mut left = Vec::with_capacity(walking.len());
            let mut settle = |i: usize, w: Walk, blocked: bool| {
                let l = match (blocked, w.done()) {
                    (true, _) => None,
                    (false, true) => Some(w.label),
                    (false, false) => return Some((i, w)),
                };
                spoilt |= stakes.spoilt_by(&jobs[i].item, &l);
                out.push((i, l));
                None
            };
            for (wk, ((blocked, twin_blocked), c)) in walking.into_iter().zip(done) {
                spent += c;
                let own = settle(wk.i, wk.walk, blocked);
                let twin = wk.twin.and_then(|(i, w)| settle(i, w, twin_blocked));
                match (own, twin) {
                    (Some((i, walk)), twin) => left.push(Walker { i, walk, twin }),
                    (None, Some((i, walk))) => left.push(Walker { i, walk, twin: None }),
                    (None, None) => {}
                }
            }
            walking = left;
        }
        for wk in walking {
            walks.insert(jobs[wk.i].item, wk.walk);
            walks.extend(wk.twin.map(|(i, w)| (jobs[i].item, w)));
        }
        (out, spent)
    }

    /// Re-checks the segments of a path that only have a coarse label with the fine
    /// check; returns the items whose label changed (now stored). Where the coarse label
    /// came from the same segments in the same mode (every coarse label but a carrying
    /// edge's taken from its empty-hand label, see `eval`), only the samples it did not
    /// take are checked.
    pub(super) fn certify(&self, b: &Built, f: &Found, checks: &mut u64) -> Map<LabelKey, Option<ObjectSet>> {
        let jobs: Vec<(Job, Option<ObjectSet>)> = self.lock(
            |s| {
                let mut seen = Set::default();
                b.edge_keys(f)
                    .filter(|k| {
                        matches!(k, LabelKey::Edge(..) | LabelKey::Approach(..))
                            && !s.certified.contains(k)
                            && seen.insert(*k)
                    })
                    .map(|k| {
                        let j = job(s, k);
                        let coarse = coarse_for_rest(s, &j);
                        (j, coarse)
                    })
                    .collect()
            },
            checks,
        );
        // A carrying edge and the same edge with the hand empty, both built on coarse
        // labels, are certified on one walk of their samples (as they were labelled).
        let items: Vec<&Job> = jobs.iter().map(|(j, _)| j).collect();
        let units = twin_units(&items, |c, e| jobs[c].1.is_some() && jobs[e].1.is_some());
        let done: Vec<(Option<ObjectSet>, Option<Option<ObjectSet>>, u64)> = units
            .par_iter()
            .map(|&(k, twin)| {
                let mut c = 0;
                let (j, coarse) = &jobs[k];
                match (twin.and_then(|e| jobs[e].1.as_ref()), coarse, &j.b) {
                    (Some(empty_coarse), Some(coarse), Some(b)) => {
                        let res = self.settings.resolution;
                        let (empty, carry) = self.space.check_motion_rest_twin(&j.a, b, res, &j.mode, &mut c);
                        let join = |c: Check, coarse: &ObjectSet| match c {
                            Check::Touches(l) => Some(l.union(coarse)),
                            Check::Blocked(_) => None,
                        };
                        (join(carry, coarse), Some(join(empty, empty_coarse)), c)
                    }
                    _ => {
                        let pass = coarse.as_ref().map_or(Pass::Fine, Pass::Rest);
                        (self.eval(j, pass, &mut c), None, c)
                    }
                }
            })
            .collect();
        let mut results: Vec<Option<ObjectSet>> = vec![None; jobs.len()];
        for (&(k, twin), (l, twin_l, c)) in units.iter().zip(done) {
            *checks += c;
            results[k] = l;
            if let (Some(e), Some(l)) = (twin, twin_l) {
                results[e] = l;
            }
        }
        self.lock(
            |s| {
                let mut changed = Map::default();
                for ((j, _), l) in jobs.iter().zip(results) {
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
}

/// What each unknown item of the chosen paths was taken to cost: its label's rule in
/// each path, and under `fewest_removals` that path's set. Unknown labels are lower
/// bounds, so a path stays the search's answer while every item checked comes out
/// within its set; an item blocked, or touching more, spoils it, and the items after it
/// need not be checked before the search runs again (on a narrow passage's roadmap most
/// paths fail at one edge, and checking the free edges on the way there was most of a
/// round's search). The items other than plain edges are checked from the path's two
/// ends inwards, the start's first (on the shipped examples fewer checks than in the
/// path's order or from the goal's end); the plain edges all together (see [`Walk`]).
#[derive(Default)]
struct Stakes(Vec<(LabelKey, Rule, Option<Mask>)>);

impl Stakes {
    fn add(&mut self, k: LabelKey, rule: Rule, set: Option<&Mask>) {
        self.0.push((k, rule, set.cloned()));
    }
    /// A path's items are tens at most: a scan costs less than hashing.
    fn spoilt_by(&self, k: &LabelKey, l: &Option<ObjectSet>) -> bool {
        self.0.iter().filter(|(key, _, _)| key == k).any(|(_, rule, set)| match rule.known(l.as_ref()) {
            Lab::Blocked => true,
            Lab::Known(m) | Lab::Unknown(m) => set.as_ref().is_some_and(|s| !m.is_subset(s)),
        })
    }
}

/// `items` reordered first, last, second, second to last, ...
fn ends_inwards<T>(items: Vec<T>) -> impl Iterator<Item = T> {
    let mut items: std::collections::VecDeque<T> = items.into();
    let mut front = true;
    std::iter::from_fn(move || {
        front = !front;
        match front {
            false => items.pop_front(),
            true => items.pop_back(),
        }
    })
}

#[cfg(test)]
#[path = "lazy_tests.rs"]
mod tests;
