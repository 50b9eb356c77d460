//! The precedence graph G itself: nodes with per-robot flags, robot-labelled edges,
//! and the paper's `AnalyzeNode`, `expandNode` and `selectNode` (Algorithms 5, 7, 8).

use std::collections::BTreeMap;

use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::visit::EdgeRef;
use petgraph::Direction;
use serde::{Deserialize, Serialize};

use crate::plan::{Answer, FoundPath, Goal, Oracle};
use crate::resolve::{ObjectId, RobotId, Scenario, Target};
use crate::world::ObjectSet;

/// What a node stands for: a removable object, or the pseudo-node of a
/// `target ROBOT at [...]`, which only its robot can "grasp".
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Item {
    Config,
    Object(ObjectId),
}

impl Item {
    pub fn object(self) -> Option<ObjectId> {
        match self {
            Item::Config => None,
            Item::Object(o) => Some(o),
        }
    }

    /// The object's name, or `target` for the configuration pseudo-node.
    pub fn name(self, scn: &Scenario) -> String {
        match self {
            Item::Config => "target".to_string(),
            Item::Object(o) => scn.object(o).body.name.clone(),
        }
    }
}

/// The paper's flag `f_ij` of one robot at one node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Flag {
    /// Not asked yet (∅).
    Empty,
    /// The robot cannot grasp the object at all (N).
    Null,
    /// A path with nothing to remove first (F).
    Free,
    /// A path exists once the objects in `SO_ij` are removed (B).
    Blocked,
    /// A path exists, but `SO_ij` holds an object of this very branch, which cannot be
    /// removed before this one (D): following it would loop.
    Discarded,
}

impl Flag {
    /// The one-character symbol of Figure 5.
    pub fn symbol(self) -> &'static str {
        match self {
            Flag::Empty => "∅",
            Flag::Null => "N",
            Flag::Free => "F",
            Flag::Blocked => "B",
            Flag::Discarded => "D",
        }
    }
}

/// One node of G. The same object may appear on several branches (G is a tree), each
/// node with its own flags since Discarded depends on the branch.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub item: Item,
    /// The parent node and the robot whose `SO` put this node there.
    pub parent: Option<(NodeIndex, RobotId)>,
    /// One flag per robot that may act on the item, in robot order.
    pub flags: Vec<(RobotId, Flag)>,
    /// The selection cost of Algorithm 8 (see [`Graph::cost`]).
    pub cost: usize,
    /// Objects of this node and all its ancestors.
    branch: ObjectSet,
}

impl Node {
    pub fn flag(&self, robot: RobotId) -> Option<Flag> {
        self.flags.iter().find(|(r, _)| *r == robot).map(|(_, f)| *f)
    }

    pub fn is_analysed(&self) -> bool {
        self.flags.iter().all(|(_, f)| *f != Flag::Empty)
    }
}

/// An edge of G, from a node to one object of `SO_ij`, labelled with the robot `R_i`.
/// Edges of one robot out of one node are AND edges; those of different robots, OR.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    pub robot: RobotId,
}

/// One `findPath` asked of the oracle, in the order asked.
#[derive(Clone, Debug, PartialEq)]
pub struct Query {
    pub robot: RobotId,
    pub item: Item,
    pub answer: Answer,
}

/// The AND/OR precedence graph G and every answer obtained while building it.
#[derive(Clone, Debug)]
pub struct Graph {
    pub g: DiGraph<Node, Edge>,
    pub root: NodeIndex,
    /// Every query, in the order asked; answers are memoised by (robot, item).
    pub queries: Vec<Query>,
    asked: BTreeMap<(RobotId, Item), usize>,
}

impl Graph {
    /// G with only the root (Algorithm 4, step 2).
    pub fn new(scn: &Scenario) -> Graph {
        let (item, robots): (Item, Vec<RobotId>) = match &scn.target {
            Target::Object { object, .. } => (Item::Object(*object), scn.robot_ids().collect()),
            Target::Config { robot, .. } => (Item::Config, vec![*robot]),
        };
        let mut g = DiGraph::new();
        let branch = item.object().map(ObjectSet::single).unwrap_or_default();
        let flags = robots.into_iter().map(|r| (r, Flag::Empty)).collect();
        let root = g.add_node(Node { item, parent: None, flags, cost: 0, branch });
        Graph { g, root, queries: Vec::new(), asked: BTreeMap::new() }
    }

    /// The memoised answer of robot `robot` for `item`, if asked.
    pub fn answer(&self, robot: RobotId, item: Item) -> Option<&Answer> {
        self.asked.get(&(robot, item)).map(|i| &self.queries[*i].answer)
    }

    /// The found path of robot `robot` for `item`, if it was asked and found one.
    pub fn found(&self, robot: RobotId, item: Item) -> Option<&FoundPath> {
        self.answer(robot, item).and_then(|a| a.result.as_ref().ok())
    }

    pub fn node(&self, n: NodeIndex) -> &Node {
        &self.g[n]
    }

    /// Node indices in creation order.
    pub fn nodes(&self) -> impl Iterator<Item = NodeIndex> + '_ {
        self.g.node_indices()
    }

    /// Children of `n` through robot `robot`'s edges, in creation order.
    pub fn children(&self, n: NodeIndex, robot: RobotId) -> Vec<NodeIndex> {
        let mut c: Vec<NodeIndex> = self
            .g
            .edges_directed(n, Direction::Outgoing)
            .filter(|e| e.weight().robot == robot)
            .map(|e| e.target())
            .collect();
        c.sort();
        c
    }

    /// `AnalyzeNode` (Algorithm 5): asks every robot of the node that was not asked yet
    /// (all at once, through [`Oracle::find_paths`]) and sets the flags.
    pub fn analyse(&mut self, scn: &Scenario, n: NodeIndex, oracle: &dyn Oracle) {
        let item = self.g[n].item;
        let missing: Vec<RobotId> =
            self.g[n].flags.iter().map(|(r, _)| *r).filter(|r| self.answer(*r, item).is_none()).collect();
        if !missing.is_empty() {
            let goal = match (item, &scn.target) {
                (Item::Object(o), _) => Goal::Grasp(o),
                (Item::Config, Target::Config { q, .. }) => Goal::Reach(q.values.clone().into()),
                // The pseudo-node exists only for a configuration target.
                (Item::Config, Target::Object { object, .. }) => Goal::Grasp(*object),
            };
            let asks: Vec<(RobotId, Goal)> = missing.iter().map(|r| (*r, goal.clone())).collect();
            let answers = oracle.find_paths(&asks);
            assert_eq!(answers.len(), asks.len(), "the oracle answers every query");
            for (robot, answer) in missing.into_iter().zip(answers) {
                self.asked.insert((robot, item), self.queries.len());
                self.queries.push(Query { robot, item, answer });
            }
        }
        let branch = self.g[n].branch.clone();
        let flags: Vec<(RobotId, Flag)> = self.g[n]
            .flags
            .iter()
            .map(|(r, _)| {
                let flag = match self.answer(*r, item).map(|a| &a.result) {
                    None | Some(Err(_)) => Flag::Null,
                    Some(Ok(p)) if p.removals.is_empty() => Flag::Free,
                    Some(Ok(p)) if p.removals.intersects(&branch) => Flag::Discarded,
                    Some(Ok(_)) => Flag::Blocked,
                };
                (*r, flag)
            })
            .collect();
        self.g[n].flags = flags;
    }

    /// `expandNode` (Algorithm 7): unless some robot is Free, adds the objects of each
    /// Blocked robot's `SO` as children, robot by robot, in object order.
    pub fn expand(&mut self, scn: &Scenario, n: NodeIndex) {
        if self.g[n].flags.iter().any(|(_, f)| *f == Flag::Free) {
            return;
        }
        let item = self.g[n].item;
        let blocked: Vec<RobotId> =
            self.g[n].flags.iter().filter(|(_, f)| *f == Flag::Blocked).map(|(r, _)| *r).collect();
        for robot in blocked {
            let so: Vec<ObjectId> = match self.found(robot, item) {
                Some(p) => p.removals.iter().collect(),
                None => continue,
            };
            for o in so {
                let mut branch = self.g[n].branch.clone();
                branch.insert(o);
                let node = Node {
                    item: Item::Object(o),
                    parent: Some((n, robot)),
                    flags: scn.robot_ids().map(|r| (r, Flag::Empty)).collect(),
                    cost: 0,
                    branch,
                };
                let c = self.g.add_node(node);
                self.g.add_edge(n, c, Edge { robot });
                self.g[c].cost = self.cost(c);
            }
        }
    }

    /// The paper's node cost: how many objects must be removed, along this branch, to
    /// free the root — the union of the `SO` sets on the edges from the root down to
    /// `n` (so AND siblings count: they must go too).
    pub fn cost(&self, n: NodeIndex) -> usize {
        let mut removed = ObjectSet::new();
        let mut at = n;
        while let Some((parent, robot)) = self.g[at].parent {
            if let Some(p) = self.found(robot, self.g[parent].item) {
                removed.union_with(&p.removals);
            }
            at = parent;
        }
        removed.len()
    }

    /// `selectNode` (Algorithm 8): the unanalysed (hence terminal) node of lowest cost;
    /// among equals, the one created first.
    pub fn select(&self) -> Option<NodeIndex> {
        self.g.node_indices().filter(|n| !self.g[*n].is_analysed()).min_by_key(|n| (self.g[*n].cost, *n))
    }

    /// Whether node `n` is a proved dead end: every robot's flag rests on a proof. A
    /// Null answer is one unless its query ran out of budget. A found path proves a dead
    /// end only through a removal every path of its query needs ([`FoundPath::forced`]):
    /// one on the branch above (Discarded: a cycle), or one whose own node is a proved
    /// dead end (Blocked). A removal the roadmap alone asked for proves nothing: a bigger
    /// budget may find a way around it.
    ///
    /// [`FoundPath::forced`]: crate::plan::FoundPath::forced
    pub fn proved(&self, n: NodeIndex) -> bool {
        self.g[n].flags.iter().all(|(r, _)| self.proved_for(n, *r))
    }

    /// Whether robot `robot`'s part of node `n` is a proved dead end (see [`Graph::proved`]).
    pub fn proved_for(&self, n: NodeIndex, robot: RobotId) -> bool {
        let node = &self.g[n];
        match node.flag(robot) {
            Some(Flag::Null) => {
                self.answer(robot, node.item).is_some_and(|a| matches!(&a.result, Err(u) if u.is_proof()))
            }
            Some(Flag::Discarded) => self.found(robot, node.item).is_some_and(|p| p.forced.intersects(&node.branch)),
            Some(Flag::Blocked) => self.found(robot, node.item).is_some_and(|p| {
                self.children(n, robot)
                    .into_iter()
                    .any(|c| self.g[c].item.object().is_some_and(|o| p.forced.contains(o)) && self.proved(c))
            }),
            Some(Flag::Free | Flag::Empty) | None => false,
        }
    }

    /// The blocking cycle behind a Discarded flag: robot `robot` at node `n` needs
    /// `object`, which is on the branch above. Returns each object of the loop from
    /// `object` down to `n`, with the robot whose `SO` for it holds the next object
    /// (the last one's next is `object` again). `None` if `object` is not on the branch.
    pub fn cycle(&self, n: NodeIndex, robot: RobotId, object: ObjectId) -> Option<Vec<(ObjectId, RobotId)>> {
        let mut chain = Vec::new();
        let mut at = n;
        let mut via = robot;
        loop {
            let o = self.g[at].item.object()?;
            chain.push((o, via));
            if o == object {
                chain.reverse();
                return Some(chain);
            }
            let (parent, r) = self.g[at].parent?;
            at = parent;
            via = r;
        }
    }
}
