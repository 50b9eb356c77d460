//! A goal tree as the searches see it: contracted onto the nodes a path can enter or
//! leave it by (the root, and the nodes joined to the roadmap), each run of nodes
//! between two of those becoming one edge.
//!
//! A tree grown through a narrow place holds tens of thousands of nodes, nearly all on
//! runs (connect marches, dead branches) no path between the roadmap and the root can
//! leave midway: a lazy search that walked them all at every iteration spent most of a
//! failing query there. Only the branch points of the subtree spanning the kept nodes
//! stay besides them; dead branches go. Every simple path between kept nodes is kept,
//! with its length and the union of its labels, so the fewest-removals answer is the
//! same; the searches then expand a contracted edge back into its nodes.

use crate::plan::Map;

use super::layers::{lookup, LabelKey, ModeKey, Node, State};
use crate::world::ObjectSet;

/// A run of tree nodes seen by the searches as one edge.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Chain {
    /// The end farther from the root.
    pub(super) from: u32,
    /// The kept ancestor the run leads to.
    pub(super) to: u32,
    /// The nodes strictly between them, from `from` towards `to`.
    pub(super) interior: Vec<u32>,
    /// The labels it is made of: its interior vertices' and its tree edges'.
    pub(super) keys: Vec<LabelKey>,
    pub(super) len: f64,
}

impl Chain {
    /// The union of its labels in the empty hand; `None` inside when a part is blocked,
    /// outer `None` when a part has not been checked.
    pub(super) fn label(&self, s: &State) -> Option<Option<ObjectSet>> {
        let mut out = ObjectSet::new();
        for &k in &self.keys {
            match lookup(s, k)? {
                Some(l) => out.union_with(&l),
                None => return Some(None),
            }
        }
        Some(Some(out))
    }

    /// Its interior nodes in the order a path entering at `at` walks them.
    pub(super) fn walk_from(&self, at: Node) -> impl Iterator<Item = Node> + '_ {
        let forward = at == Node::Goal(self.from);
        let n = self.interior.len();
        (0..n).map(move |i| Node::Goal(self.interior[if forward { i } else { n - 1 - i }]))
    }
}

/// Contracts the tree of `root` (`tree`: (node, parent) in growth order, so parents
/// come first) onto the nodes `kept` says a path may enter or leave it by. Returns the
/// tree nodes the searches keep (growth order, root excluded) and one chain per kept
/// node, to its nearest kept ancestor; `len` is the length of a tree edge.
pub(super) fn contract(
    root: u32,
    tree: &[(u32, u32)],
    kept: impl Fn(u32) -> bool,
    len: impl Fn(u32, u32) -> f64,
) -> (Vec<u32>, Vec<Chain>) {
    let pos: Map<u32, usize> = tree.iter().enumerate().map(|(i, t)| (t.0, i)).collect();
    let parent = |i: usize| pos.get(&tree[i].1).copied();
    // Which nodes lie on the way from a kept node to the root, and how many of their
    // children do: children come after their parents, so a reverse pass sees them first.
    let mut needed: Vec<bool> = tree.iter().map(|t| kept(t.0)).collect();
    let mut kids = vec![0u32; tree.len()];
    for i in (0..tree.len()).rev() {
        if needed[i] {
            if let Some(p) = parent(i) {
                needed[p] = true;
                kids[p] += 1;
            }
        }
    }
    let keep: Vec<bool> = (0..tree.len()).map(|i| needed[i] && (kept(tree[i].0) || kids[i] >= 2)).collect();
    let edge = |a: u32, b: u32| {
        let (a, b) = (Node::Goal(a), Node::Goal(b));
        LabelKey::Edge(ModeKey::Empty, a.min(b), a.max(b))
    };
    let mut nodes = Vec::new();
    let mut chains = Vec::new();
    for i in (0..tree.len()).filter(|&i| keep[i]) {
        let from = tree[i].0;
        let (mut cur, mut up) = (from, tree[i].1);
        let mut chain = Chain { from, to: root, interior: Vec::new(), keys: Vec::new(), len: 0.0 };
        loop {
            chain.keys.push(edge(cur, up));
            chain.len += len(cur, up);
            match pos.get(&up) {
                Some(&j) if !keep[j] => {
                    chain.interior.push(up);
                    chain.keys.push(LabelKey::Vertex(ModeKey::Empty, Node::Goal(up)));
                    cur = up;
                    up = tree[j].1;
                }
                _ => break,
            }
        }
        chain.to = up;
        nodes.push(from);
        chains.push(chain);
    }
    (nodes, chains)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain as (from, to, interior, length).
    type Run = (u32, u32, Vec<u32>, f64);

    fn run(tree: &[(u32, u32)], kept: &[u32]) -> (Vec<u32>, Vec<Run>) {
        let (nodes, chains) = contract(0, tree, |x| kept.contains(&x), |a, b| f64::from(a + b));
        (nodes, chains.into_iter().map(|c| (c.from, c.to, c.interior, c.len)).collect())
    }

    #[test]
    fn runs_become_edges_and_dead_branches_go() {
        // 0 - 1 - 2 - 3 (kept), 2 - 4 - 5 (kept), 1 - 6 - 7 (dead).
        let tree = [(1, 0), (2, 1), (3, 2), (4, 2), (5, 4), (6, 1), (7, 6)];
        let (nodes, chains) = run(&tree, &[3, 5]);
        // 2 branches towards two kept nodes: it stays; 1, 4, 6, 7 do not.
        assert_eq!(nodes, vec![2, 3, 5]);
        assert_eq!(chains, vec![(2, 0, vec![1], 3.0 + 1.0), (3, 2, vec![], 5.0), (5, 2, vec![4], 9.0 + 6.0)]);
    }

    #[test]
    fn a_kept_node_on_the_way_ends_a_chain() {
        let tree = [(1, 0), (2, 1), (3, 2)];
        let (nodes, chains) = run(&tree, &[1, 3]);
        assert_eq!(nodes, vec![1, 3]);
        assert_eq!(chains, vec![(1, 0, vec![], 1.0), (3, 1, vec![2], 5.0 + 3.0)]);
    }

    #[test]
    fn nothing_kept_keeps_nothing() {
        let (nodes, chains) = run(&[(1, 0), (2, 1)], &[]);
        assert!(nodes.is_empty() && chains.is_empty());
    }

    #[test]
    fn a_chain_walks_either_way() {
        let c = Chain { from: 5, to: 0, interior: vec![4, 2], keys: Vec::new(), len: 0.0 };
        assert_eq!(c.walk_from(Node::Goal(5)).collect::<Vec<_>>(), vec![Node::Goal(4), Node::Goal(2)]);
        assert_eq!(c.walk_from(Node::Goal(0)).collect::<Vec<_>>(), vec![Node::Goal(2), Node::Goal(4)]);
    }
}
