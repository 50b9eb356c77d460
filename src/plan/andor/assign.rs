//! The assignment of remove-actions to robots: an AND/OR solution over the answers
//! G holds, in place of the paper's greedy `checkGraph` (Algorithm 6).
//!
//! A choice gives each needed item one robot with a found path; it is a solution when
//! every object in a chosen path's `SO` is itself chosen (AND), and no object needs
//! itself removed first, through any chain of chosen paths (no cycle). Objects needed
//! by several branches are removed once. Among solutions the rule is, in order:
//!
//! 1. fewest actions (distinct items removed, the target included);
//! 2. the robots' loads, busiest first: fewest actions for the busiest robot, then
//!    for the second busiest, and so on (spreads the work);
//! 3. lowest robot ids, compared item by item: the target first, then objects by id.
//!
//! The search is exhaustive, pruned on rule 1 and on the busiest robot; past [`SEARCH_BUDGET`] partial
//! choices it keeps the best found so far, or the first solution found bottom-up.

use std::collections::{BTreeMap, BTreeSet};

use crate::resolve::{ObjectId, RobotId};
use crate::world::ObjectSet;

use super::graph::{Graph, Item};

/// Partial choices the exhaustive search may visit before settling.
pub const SEARCH_BUDGET: usize = 200_000;

/// One remove-action (or, last, the target's grasp or reach).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Action {
    pub robot: RobotId,
    pub item: Item,
    /// Indices into the plan's actions that must finish first (the actions removing
    /// this path's `SO`), sorted.
    pub after: Vec<usize>,
}

/// Actions in execution order; the target's is last.
///
/// Chosen by the rule of this module: fewest actions, then the most even loads (busiest
/// robot first), then the lowest robot ids (target first, then objects by id). Among ready
/// actions the order takes the longest chain still waiting first, then the lowest item.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    pub actions: Vec<Action>,
}

impl Plan {
    /// The removed objects in action order (the target last, if it is an object).
    pub fn removed(&self) -> Vec<ObjectId> {
        self.actions.iter().filter_map(|a| a.item.object()).collect()
    }

    /// The robot chosen for `item`, if it is part of the plan.
    pub fn robot_for(&self, item: Item) -> Option<RobotId> {
        self.actions.iter().find(|a| a.item == item).map(|a| a.robot)
    }
}

/// For each item with at least one found path: (robot, SO) in robot order.
type Options = BTreeMap<Item, Vec<(RobotId, ObjectSet)>>;

/// The best assignment over the answers in `graph`, or `None` if the root has none yet.
pub fn assign(graph: &Graph) -> Option<Plan> {
    let root = graph.node(graph.root).item;
    let root_robots: Vec<RobotId> = graph.node(graph.root).flags.iter().map(|(r, _)| *r).collect();
    let mut options: Options = BTreeMap::new();
    for q in &graph.queries {
        if q.item == root && !root_robots.contains(&q.robot) {
            continue;
        }
        if let Ok(p) = &q.answer.result {
            options.entry(q.item).or_default().push((q.robot, p.removals.clone()));
        }
    }
    for v in options.values_mut() {
        v.sort_by_key(|(r, _)| *r);
    }
    let solvable = solvable(&options);
    if !solvable.contains_key(&root) {
        return None;
    }
    // Keep only the options whose every blocker can be removed at all.
    for v in options.values_mut() {
        v.retain(|(_, so)| so.iter().all(|o| solvable.contains_key(&Item::Object(o))));
    }
    let robots = options.values().flatten().map(|(r, _)| *r).collect();
    let mut search = Search { options: &options, root, robots, best: None, visited: 0 };
    let mut chosen = BTreeMap::new();
    let mut open = BTreeSet::from([root]);
    search.dfs(&mut chosen, &mut open);
    let choice = match search.best {
        Some((_, c)) => c,
        None => bottom_up(&options, &solvable, root),
    };
    Some(order(&options, &choice, root))
}

/// Least fixed point: the rank at which each item becomes removable (0: a Free path),
/// with the lowest robot that achieves it. Well-founded, so cycle-free by construction.
fn solvable(options: &Options) -> BTreeMap<Item, (usize, RobotId)> {
    let mut done: BTreeMap<Item, (usize, RobotId)> = BTreeMap::new();
    let mut rank = 0;
    loop {
        let mut new = Vec::new();
        for (item, opts) in options {
            if done.contains_key(item) {
                continue;
            }
            let ok = opts.iter().find(|(_, so)| so.iter().all(|o| done.contains_key(&Item::Object(o))));
            if let Some((r, _)) = ok {
                new.push((*item, *r));
            }
        }
        if new.is_empty() {
            return done;
        }
        for (item, r) in new {
            done.insert(item, (rank, r));
        }
        rank += 1;
    }
}

/// The fallback: each needed item with the robot that made it removable first.
fn bottom_up(options: &Options, solvable: &BTreeMap<Item, (usize, RobotId)>, root: Item) -> BTreeMap<Item, RobotId> {
    let mut choice = BTreeMap::new();
    let mut stack = vec![root];
    while let Some(item) = stack.pop() {
        if choice.contains_key(&item) {
            continue;
        }
        let robot = solvable[&item].1;
        choice.insert(item, robot);
        if let Some((_, so)) = options[&item].iter().find(|(r, _)| *r == robot) {
            stack.extend(so.iter().map(Item::Object));
        }
    }
    choice
}

/// The comparison key of the assignment rule (smaller is better): actions, loads
/// sorted busiest first (one per robot with any option), robot ids.
type Key = (usize, Vec<usize>, Vec<u32>);

fn busiest(choice: &BTreeMap<Item, RobotId>) -> usize {
    let mut per_robot: BTreeMap<RobotId, usize> = BTreeMap::new();
    for r in choice.values() {
        *per_robot.entry(*r).or_default() += 1;
    }
    per_robot.values().copied().max().unwrap_or(0)
}

fn key(choice: &BTreeMap<Item, RobotId>, root: Item, robots: &BTreeSet<RobotId>) -> Key {
    let mut loads: Vec<usize> = robots.iter().map(|r| choice.values().filter(|c| *c == r).count()).collect();
    loads.sort_by(|a, b| b.cmp(a));
    let ids =
        std::iter::once(choice[&root].0).chain(choice.iter().filter(|(i, _)| **i != root).map(|(_, r)| r.0)).collect();
    (choice.len(), loads, ids)
}

struct Search<'a> {
    options: &'a Options,
    root: Item,
    /// Every robot with an option, so loads compare at equal length.
    robots: BTreeSet<RobotId>,
    best: Option<(Key, BTreeMap<Item, RobotId>)>,
    visited: usize,
}

impl Search<'_> {
    fn dfs(&mut self, chosen: &mut BTreeMap<Item, RobotId>, open: &mut BTreeSet<Item>) {
        self.visited += 1;
        if self.visited > SEARCH_BUDGET {
            return;
        }
        // Every open item costs one more action at least, and the busiest robot only
        // gets busier.
        if let Some((best, _)) = &self.best {
            let actions = chosen.len() + open.len();
            if actions > best.0 || (actions == best.0 && busiest(chosen) > best.1[0]) {
                return;
            }
        }
        let Some(item) = open.pop_first() else {
            if acyclic(self.options, chosen) {
                let k = key(chosen, self.root, &self.robots);
                if self.best.as_ref().is_none_or(|(b, _)| k < *b) {
                    self.best = Some((k, chosen.clone()));
                }
            }
            return;
        };
        let opts = self.options.get(&item).map(Vec::as_slice).unwrap_or(&[]);
        for (robot, so) in opts {
            chosen.insert(item, *robot);
            let added: Vec<Item> =
                so.iter().map(Item::Object).filter(|i| !chosen.contains_key(i) && !open.contains(i)).collect();
            open.extend(added.iter().copied());
            self.dfs(chosen, open);
            for i in &added {
                open.remove(i);
            }
            chosen.remove(&item);
        }
        open.insert(item);
    }
}

fn so_of(options: &Options, item: Item, robot: RobotId) -> &ObjectSet {
    &options[&item].iter().find(|(r, _)| *r == robot).expect("chosen robots have an option").1
}

/// Whether the precedence "remove SO before the item" of a choice has no cycle.
fn acyclic(options: &Options, choice: &BTreeMap<Item, RobotId>) -> bool {
    let mut indegree: BTreeMap<Item, usize> = choice.keys().map(|i| (*i, 0)).collect();
    for (item, robot) in choice {
        indegree.insert(*item, so_of(options, *item, *robot).len());
    }
    let mut ready: Vec<Item> = indegree.iter().filter(|(_, d)| **d == 0).map(|(i, _)| *i).collect();
    let mut seen = 0;
    while let Some(done) = ready.pop() {
        seen += 1;
        for (item, robot) in choice {
            if let Item::Object(o) = done {
                if so_of(options, *item, *robot).contains(o) {
                    let d = indegree.get_mut(item).expect("every chosen item has a degree");
                    *d -= 1;
                    if *d == 0 {
                        ready.push(*item);
                    }
                }
            }
        }
    }
    seen == choice.len()
}

/// Orders an acyclic choice: whenever several actions are ready, the one with the
/// longest chain of actions still waiting on it goes first (critical path), then the
/// lowest item. The target, which everything leads to, comes last.
fn order(options: &Options, choice: &BTreeMap<Item, RobotId>, root: Item) -> Plan {
    let needs = |item: Item| -> Vec<Item> { so_of(options, item, choice[&item]).iter().map(Item::Object).collect() };
    // Height: the longest chain of dependents from the item up to the target.
    let mut height: BTreeMap<Item, usize> = BTreeMap::from([(root, 0)]);
    let mut stack = vec![root];
    while let Some(item) = stack.pop() {
        let h = height[&item];
        for n in needs(item) {
            if height.get(&n).is_none_or(|old| *old < h + 1) {
                height.insert(n, h + 1);
                stack.push(n);
            }
        }
    }
    let mut index: BTreeMap<Item, usize> = BTreeMap::new();
    let mut actions: Vec<Action> = Vec::new();
    while index.len() < choice.len() {
        let next = choice
            .keys()
            .filter(|i| !index.contains_key(i) && needs(**i).iter().all(|n| index.contains_key(n)))
            .min_by_key(|i| (std::cmp::Reverse(height.get(i).copied().unwrap_or(0)), **i))
            .copied()
            .expect("an acyclic choice always has a ready action");
        let mut after: Vec<usize> = needs(next).iter().map(|n| index[n]).collect();
        after.sort();
        index.insert(next, actions.len());
        actions.push(Action { robot: choice[&next], item: next, after });
    }
    Plan { actions }
}
