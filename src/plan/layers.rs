//! The layered search graphs of a query and the label store they read: which
//! roadmap elements have been checked in which mode (empty hand, or carrying an
//! object after a given grasp), and how a graph for one round and one goal is built.

use crate::plan::{Map, Set};

use super::chains::{contract, Chain};
use super::knn::{dist2, GrowingIndex};
use super::roadmap::Roadmap;
use super::search::{mask, Found, Lab, LabelGraph, Mask};
use super::space::Mode;
use crate::resolve::ObjectId;
use crate::world::{GraspConfig, Held, ObjectSet};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(super) enum Node {
    Map(u32),
    Goal(u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum ModeKey {
    Empty,
    /// Carrying the object after the `.1`-th configuration `selectGrasps` returned.
    Carry(ObjectId, u32),
}

/// Anything that gets a label (the key of the label store; the AND/OR graph's
/// `andor::Item` is a different thing, an object or the target configuration).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum LabelKey {
    Vertex(ModeKey, Node),
    /// Nodes in increasing order.
    Edge(ModeKey, Node, Node),
    /// Pre-grasp -> grasp with the object absent, then back carrying it.
    Approach(ObjectId, u32),
}

pub(super) struct GoalNode {
    pub(super) q: Vec<f64>,
    /// Cumulative neighbours at round r (index r).
    pub(super) nbrs: Vec<Vec<u32>>,
    /// The tree grown from this goal (see `RobotPlanner::grow_tree`): (node, parent,
    /// round added), in growth order; its nodes are goal nodes of their own.
    pub(super) tree: Vec<(u32, u32, usize)>,
    /// Rounds the tree has been grown for.
    pub(super) tree_rounds: usize,
    /// The tree's links to the roadmap: (tree node, roadmap vertex, round found).
    pub(super) links: Vec<(u32, u32, usize)>,
    /// A nearest-node index of the tree (its root first).
    pub(super) index: GrowingIndex,
}

impl GoalNode {
    pub(super) fn new(q: &[f64]) -> GoalNode {
        GoalNode {
            q: q.to_vec(),
            nbrs: Vec::new(),
            tree: Vec::new(),
            tree_rounds: 0,
            links: Vec::new(),
            index: GrowingIndex::default(),
        }
    }
}

pub(super) type Carried = (Held, Vec<f64>, Vec<f64>);

pub(super) struct State {
    pub(super) map: Roadmap,
    pub(super) goals: Vec<GoalNode>,
    pub(super) goal_ids: Map<Vec<u64>, u32>,
    /// Empty-hand labels of roadmap edges, by edge index (`None`: not checked yet).
    pub(super) map_edges: Vec<Option<Option<ObjectSet>>>,
    pub(super) labels: Map<LabelKey, Option<ObjectSet>>,
    /// Segment items whose stored label comes from the certifying (fine) check.
    pub(super) certified: Set<LabelKey>,
    /// Per (object, grasp): the held object, q_grasp and q_pregrasp.
    pub(super) helds: Map<(ObjectId, u32), Carried>,
    /// `selectGrasps` answers, computed once per object (IK is not cheap).
    pub(super) grasps: Map<ObjectId, Vec<GraspConfig>>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Rule {
    Plain,
    /// Labels containing the object block (it cannot be removed to reach itself).
    Forbid(ObjectId),
    /// The object is gone from the scene.
    Strip(ObjectId),
}

impl Rule {
    pub(super) fn known(self, l: Option<&ObjectSet>) -> Lab {
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
            Rule::Strip(o) => mask(s).without(o),
        };
        if unknown {
            Lab::Unknown(s)
        } else {
            Lab::Known(s)
        }
    }
}

/// The first tree nodes (in growth order) also join the roadmap through their nearest
/// vertices, like the goal itself; the rest only through their connect links.
const TREE_LINKED: usize = 32;

/// A layered search graph for one goal at one round, with the key of every element.
pub(super) struct Built {
    pub(super) g: LabelGraph,
    pub(super) vkey: Vec<LabelKey>,
    pub(super) vrule: Vec<Rule>,
    /// `None` for elements whose label was final at build time.
    pub(super) ekey: Vec<Option<LabelKey>>,
    pub(super) erule: Vec<Rule>,
    /// Layer of each vertex and its node.
    pub(super) vnode: Vec<(u8, Node)>,
    /// Labels of the transition edges (which have no key).
    pub(super) fixed: Map<u32, ObjectSet>,
    /// Edges standing for a run of goal-tree nodes (no key either; see `chains`).
    pub(super) chains: Map<u32, Chain>,
    pub(super) start: u32,
    pub(super) goal: u32,
}

/// A usable grasp: its goal node and the approach/retreat label.
#[derive(Clone)]
pub(super) struct GraspGoal {
    pub(super) cfg: GraspConfig,
    /// Empty-hand label of the pre-grasp.
    pub(super) pre_set: ObjectSet,
    /// Position in the `selectGrasps` answer (the carry mode's key).
    pub(super) key: u32,
    pub(super) pre: u32,
    pub(super) approach: ObjectSet,
}

/// A configuration-level job for the workers.
pub(super) struct Job {
    pub(super) item: LabelKey,
    pub(super) a: Vec<f64>,
    pub(super) b: Option<Vec<f64>>,
    pub(super) mode: Mode,
    /// For `Approach`: the grasp configuration, checked pre -> grasp (absent) then back (held).
    pub(super) grasp: Option<Vec<f64>>,
    /// For an edge carrying an object: the same edge's empty-hand label, when known.
    pub(super) empty: Option<Option<ObjectSet>>,
}

/// The exact union of the labels on a fully known path.
pub(super) fn exact_set(s: &State, b: &Built, f: &Found) -> ObjectSet {
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
        match (b.ekey[e as usize], b.chains.get(&e)) {
            (Some(k), _) => add(lookup(s, k), b.erule[e as usize]),
            (None, Some(c)) => add(c.label(s), b.erule[e as usize]),
            (None, None) => add(b.fixed.get(&e).cloned().map(Some), Rule::Plain),
        }
    }
    out
}

impl Built {
    /// The (layer, node) of every vertex of a found path, runs of tree nodes the graph
    /// holds as one edge walked node by node.
    pub(super) fn path_nodes(&self, f: &Found) -> Vec<(u8, Node)> {
        let mut out = Vec::with_capacity(f.verts.len());
        for (i, &v) in f.verts.iter().enumerate() {
            let (layer, node) = self.vnode[v as usize];
            out.push((layer, node));
            if let Some(c) = f.edges.get(i).and_then(|e| self.chains.get(e)) {
                out.extend(c.walk_from(node).map(|n| (layer, n)));
            }
        }
        out
    }

    /// The keys a found path's edges are made of (a tree run's parts for its edge).
    pub(super) fn edge_keys<'a>(&'a self, f: &'a Found) -> impl Iterator<Item = LabelKey> + 'a {
        f.edges.iter().flat_map(move |e| {
            let run = self.chains.get(e).map(|c| c.keys.as_slice()).unwrap_or_default();
            self.ekey[*e as usize].into_iter().chain(run.iter().copied())
        })
    }

    /// Labels tree runs again after some of their parts' labels changed (certified);
    /// returns whether any did.
    pub(super) fn relabel_chains(&mut self, s: &State, changed: &Map<LabelKey, Option<ObjectSet>>) -> bool {
        let mut any = false;
        for (&e, c) in &self.chains {
            if c.keys.iter().any(|k| changed.contains_key(k)) {
                // Parts are never unchecked (see `build`); an unknown label here has no key
                // to check it by, so the run is left out rather than searched as unknown.
                let rule = self.erule[e as usize];
                self.g.set_elab(e as usize, c.label(s).map_or(Lab::Blocked, |l| rule.known(l.as_ref())));
                any = true;
            }
        }
        any
    }
}

pub(super) fn node_q(s: &State, n: Node) -> &[f64] {
    match n {
        Node::Map(v) => s.map.q(v),
        Node::Goal(g) => &s.goals[g as usize].q,
    }
}

/// The stored label of an item, if checked.
pub(super) fn lookup(s: &State, it: LabelKey) -> Option<Option<ObjectSet>> {
    match it {
        LabelKey::Vertex(ModeKey::Empty, Node::Map(v)) => Some(Some(s.map.vlab[v as usize].clone())),
        LabelKey::Edge(ModeKey::Empty, Node::Map(a), Node::Map(b)) => {
            let e = map_edge(s, a, b)?;
            s.map_edges[e].clone()
        }
        _ => s.labels.get(&it).cloned(),
    }
}

pub(super) fn store(s: &mut State, it: LabelKey, l: Option<ObjectSet>) {
    if let LabelKey::Edge(ModeKey::Empty, Node::Map(a), Node::Map(b)) = it {
        if let Some(e) = map_edge(s, a, b) {
            s.map_edges[e] = Some(l);
            return;
        }
    }
    s.labels.insert(it, l);
}

pub(super) fn map_edge(s: &State, a: u32, b: u32) -> Option<usize> {
    // Roadmap edges are sorted within each round and rounds are appended in order.
    let pair = (a.min(b), a.max(b));
    // The round of an edge is the round of its later vertex.
    let r = s.map.rounds.partition_point(|e| e.verts <= pair.1 as usize);
    let (from, to) = (s.map.rounds[r - 1].edges, s.map.rounds.get(r)?.edges);
    s.map.edges[from..to].binary_search(&pair).ok().map(|i| from + i)
}

pub(super) fn mode_of(s: &State, m: ModeKey) -> Mode {
    match m {
        ModeKey::Empty => Mode::default(),
        ModeKey::Carry(o, g) => Mode { absent: ObjectSet::single(o), held: Some(s.helds[&(o, g)].0.clone()) },
    }
}

pub(super) fn job(s: &State, it: LabelKey) -> Job {
    match it {
        LabelKey::Vertex(m, n) => {
            Job { item: it, a: node_q(s, n).to_vec(), b: None, mode: mode_of(s, m), grasp: None, empty: None }
        }
        LabelKey::Edge(m, a, b) => Job {
            item: it,
            a: node_q(s, a).to_vec(),
            b: Some(node_q(s, b).to_vec()),
            mode: mode_of(s, m),
            grasp: None,
            empty: match m {
                ModeKey::Carry(..) => lookup(s, LabelKey::Edge(ModeKey::Empty, a, b)),
                ModeKey::Empty => None,
            },
        },
        LabelKey::Approach(o, g) => {
            let (held, q_grasp, q_pre) = s.helds[&(o, g)].clone();
            Job {
                item: it,
                a: q_pre,
                b: None,
                mode: Mode { absent: ObjectSet::single(o), held: Some(held) },
                grasp: Some(q_grasp),
                empty: None,
            }
        }
    }
}

/// Cumulative neighbours of a goal node at round `r`.
pub(super) fn goal_nbrs(s: &mut State, id: u32, r: usize, k: usize) -> Vec<u32> {
    let g = &mut s.goals[id as usize];
    while g.nbrs.len() <= r {
        let rr = g.nbrs.len();
        let mut n: Vec<u32> = if rr == 0 { Vec::new() } else { g.nbrs[rr - 1].clone() };
        let k = super::roadmap::neighbours(k, s.map.dof, s.map.rounds[rr].verts);
        n.extend(s.map.trees[rr].nearest(&g.q, k, |_| false).into_iter().map(|(_, i)| i));
        n.sort_unstable();
        n.dedup();
        g.nbrs.push(n);
    }
    g.nbrs[r].clone()
}

/// The layered graph of one goal at round `r`; edges blocked, or touching `bound`
/// objects or more, are left out. With `trees`, the goal's tree joins the layers the
/// goal is in, `contracted` (see `chains`) in the empty-hand layers.
pub(super) fn build(
    s: &mut State,
    r: usize,
    k: usize,
    object: Option<ObjectId>,
    goal: &GraspGoal,
    drop: Option<Node>,
    (bound, trees, contracted): (u32, bool, bool),
) -> Built {
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
    // The goal's tree (up to round r) joins every layer the goal is in.
    let tree: Vec<(u32, u32)> = match trees {
        true => s.goals[pre as usize].tree.iter().filter(|t| t.2 <= r).map(|t| (t.0, t.1)).collect(),
        false => Vec::new(),
    };
    for (_, _, extras) in layers.iter_mut() {
        if extras.contains(&pre) {
            extras.extend(tree.iter().map(|t| t.0));
        }
    }
    // Tree nodes reach the roadmap only through the links their connect steps found.
    let mut nbrs: Map<u32, Vec<u32>> = Map::default();
    if trees {
        for &(x, v, rr) in &s.goals[pre as usize].links {
            if rr <= r {
                nbrs.entry(x).or_default().push(v);
            }
        }
    }
    let in_tree: Set<u32> = tree.iter().skip(TREE_LINKED).map(|t| t.0).collect();
    // Each node once, though it may be in several layers.
    let mut done = Set::default();
    for x in layers.iter().flat_map(|l| l.2.iter().copied()) {
        if !done.insert(x) {
            continue;
        }
        if in_tree.contains(&x) {
            nbrs.entry(x).or_default();
        } else {
            // The goal and the first tree nodes: their nearest vertices beside any links.
            let near = goal_nbrs(s, x, r, k);
            let e = nbrs.entry(x).or_default();
            if !near.iter().all(|v| e.contains(v)) {
                e.extend(near);
                e.sort_unstable();
                e.dedup();
            }
        }
    }
    // Layers in the empty hand see the tree contracted (see `chains`): all its labels
    // are known there. Carrying, its edges are checked lazily one by one.
    let cut = contracted && !tree.is_empty();
    let mut runs: Vec<Chain> = Vec::new();
    if cut {
        let lens = |a: u32, b: u32| dist2(&s.goals[a as usize].q, &s.goals[b as usize].q).sqrt();
        let (kept, chains) = contract(pre, &tree, |x| nbrs.get(&x).is_some_and(|v| !v.is_empty()), lens);
        let kept: Set<u32> = kept.into_iter().collect();
        let whole: Set<u32> = tree.iter().map(|t| t.0).collect();
        for (mode, _, extras) in layers.iter_mut() {
            if *mode == Empty && extras.contains(&pre) {
                extras.retain(|x| !whole.contains(x) || kept.contains(x));
            }
        }
        runs = chains;
    }
    let s = &*s;
    let n = s.map.rounds[r].verts as u32;
    let m = s.map.rounds[r].edges;
    let mut b = Built {
        g: LabelGraph::default(),
        vkey: Vec::new(),
        vrule: Vec::new(),
        ekey: Vec::new(),
        erule: Vec::new(),
        vnode: Vec::new(),
        fixed: Map::default(),
        chains: Map::default(),
        start: 0,
        goal: 0,
    };
    // Each roadmap vertex's degree at round r: room for its edges in every layer.
    let mut degree = vec![0usize; n as usize];
    for &(va, vb) in &s.map.edges[..m] {
        degree[va as usize] += 1;
        degree[vb as usize] += 1;
    }
    let mut offsets = Vec::new();
    for (li, (mode, rule, extras)) in layers.iter().enumerate() {
        let (mode, rule) = (*mode, *rule);
        let off = b.g.vlab().len() as u32;
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
            let item = LabelKey::Vertex(mode, node);
            let lab = match (mode, node) {
                (Empty, Node::Map(v)) => rule.known(Some(&s.map.vlab[v as usize])),
                _ => match lookup(s, item) {
                    Some(l) => rule.known(l.as_ref()),
                    None => {
                        // Carrying: the arm's own contacts stay, the object's are unknown.
                        let empty = lookup(s, LabelKey::Vertex(Empty, node)).flatten();
                        match empty {
                            Some(l) => rule.bound(Some(&strip(&l))),
                            None => Lab::Unknown(Mask::default()),
                        }
                    }
                },
            };
            match node {
                Node::Map(v) => b.g.add_vertex_of_degree(lab, degree[v as usize]),
                Node::Goal(_) => b.g.add_vertex(lab),
            };
            b.vkey.push(item);
            b.vrule.push(rule);
            b.vnode.push((li as u8, node));
        }
        let add_edge =
            |b: &mut Built, la: u32, lb: u32, na: Node, nb: Node, len: f64, known: Option<Option<ObjectSet>>| {
                let item = LabelKey::Edge(mode, na.min(nb), na.max(nb));
                let lab = match known {
                    Some(l) => rule.known(l.as_ref()),
                    None => match (&b.g.vlab()[la as usize], &b.g.vlab()[lb as usize]) {
                        (Lab::Blocked, _) | (_, Lab::Blocked) => Lab::Blocked,
                        (Lab::Known(x) | Lab::Unknown(x), Lab::Known(y) | Lab::Unknown(y)) => Lab::Unknown(x.union(y)),
                    },
                };
                // Edges no answer better than `bound` can use are left out of the graph.
                if lab.bound().is_none_or(|m| m.count() >= bound) {
                    return;
                }
                b.g.add_edge(la, lb, len, lab);
                b.ekey.push(Some(item));
                b.erule.push(rule);
            };
        for e in 0..m {
            let (va, vb) = s.map.edges[e];
            let known = match mode {
                Empty => s.map_edges[e].clone(),
                Carry(..) => s.labels.get(&LabelKey::Edge(mode, Node::Map(va), Node::Map(vb))).cloned(),
            };
            add_edge(&mut b, off + va, off + vb, Node::Map(va), Node::Map(vb), s.map.elen[e], known);
        }
        for (xi, &x) in extras.iter().enumerate() {
            let lx = off + n + xi as u32;
            let qx = &s.goals[x as usize].q;
            for &v in &nbrs[&x] {
                let len = dist2(qx, s.map.q(v)).sqrt();
                let known = lookup(s, LabelKey::Edge(mode, Node::Map(v), Node::Goal(x)));
                add_edge(&mut b, off + v, lx, Node::Map(v), Node::Goal(x), len, known);
            }
        }
        let pos: Map<u32, u32> = extras.iter().enumerate().map(|(i, &x)| (x, off + n + i as u32)).collect();
        // The same test as the one that left the runs' interiors out of `extras` above.
        if extras.contains(&pre) && mode == Empty && cut {
            for c in &runs {
                let (nc, np) = (Node::Goal(c.from), Node::Goal(c.to));
                if c.interior.is_empty() {
                    let known = lookup(s, LabelKey::Edge(mode, nc.min(np), nc.max(np)));
                    add_edge(&mut b, pos[&c.to], pos[&c.from], np, nc, c.len, known);
                    continue;
                }
                // Parts never checked cannot happen in the empty hand; leave such a run out.
                let lab = c.label(s).map_or(Lab::Blocked, |l| rule.known(l.as_ref()));
                if lab.bound().is_none_or(|m| m.count() >= bound) {
                    continue;
                }
                let e = b.g.add_edge(pos[&c.to], pos[&c.from], c.len, lab);
                b.ekey.push(None);
                b.erule.push(rule);
                b.chains.insert(e, c.clone());
            }
        } else if extras.contains(&pre) {
            for &(c, p) in &tree {
                let (nc, np) = (Node::Goal(c), Node::Goal(p));
                let len = dist2(&s.goals[c as usize].q, &s.goals[p as usize].q).sqrt();
                let known = lookup(s, LabelKey::Edge(mode, nc.min(np), nc.max(np)));
                add_edge(&mut b, pos[&p], pos[&c], np, nc, len, known);
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
        Some(o) => {
            // The approach and retreat, labelled like an edge: coarsely first, certified
            // when a winning path uses it.
            let len = 2.0 * dist2(&goal.cfg.q_pregrasp, &goal.cfg.q_grasp).sqrt();
            let item = LabelKey::Approach(o, goal.key);
            if let Some(Some(l)) = lookup(s, item) {
                b.g.add_edge(local(0, Node::Goal(pre)), local(1, Node::Goal(pre)), len, Lab::Known(mask(&l)));
                b.ekey.push(Some(item));
                b.erule.push(Rule::Plain);
            }
            if layers.len() == 3 {
                let Some(Node::Goal(d)) = drop else { unreachable!("three layers only with a drop goal") };
                transition(&mut b, local(1, Node::Goal(d)), local(2, Node::Goal(d)), 0.0, &ObjectSet::new());
                b.goal = local(2, Node::Map(0));
            } else {
                b.goal = local(1, drop.unwrap_or(Node::Map(0)));
            }
        }
    }
    b.g.h = estimate(s, &b, object.map(|_| (goal, drop)));
    b
}

/// The searches' A* estimate for each vertex of a built graph: the straight distance to
/// its layer's end plus the shortest the later layers can be (each layer's end to the
/// next one's, and the approach's out and back). A transition edge costs exactly the
/// difference of its ends' estimates and every other edge is at least the straight
/// distance it spans, so no edge breaks the estimate.
fn estimate(s: &State, b: &Built, grasp: Option<(&GraspGoal, Option<Node>)>) -> Vec<f64> {
    let q_of = |n: Node| node_q(s, n);
    // Per layer: where it ends and the rest of the way from there.
    let ends: Vec<(&[f64], f64)> = match grasp {
        None => vec![(q_of(b.vnode[b.goal as usize].1), 0.0)],
        Some((g, drop)) => {
            let (pre, home) = (&s.goals[g.pre as usize].q[..], q_of(Node::Map(0)));
            let approach = 2.0 * dist2(&g.cfg.q_pregrasp, &g.cfg.q_grasp).sqrt();
            match drop {
                Some(Node::Goal(d)) => {
                    let dq = &s.goals[d as usize].q[..];
                    let back = dist2(dq, home).sqrt();
                    vec![(pre, approach + dist2(pre, dq).sqrt() + back), (dq, back), (home, 0.0)]
                }
                _ => vec![(pre, approach + dist2(pre, home).sqrt()), (home, 0.0)],
            }
        }
    };
    b.vnode
        .iter()
        .map(|&(layer, node)| {
            let (end, rest) = ends[layer as usize];
            dist2(q_of(node), end).sqrt() + rest
        })
        .collect()
}
