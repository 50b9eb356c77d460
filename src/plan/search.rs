//! Searches on a labelled graph: the minimum-constraint-removal search
//! (`fewest_removals`) and the paper's fewest-vertices rule.
//!
//! Labels may be unknown (not yet checked): the search then uses a lower bound, a
//! subset of the true label, and the caller checks the chosen path and searches again
//! (lazy evaluation). Because true labels only grow, the first path whose labels are
//! all known is optimal on the graph.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

use crate::world::ObjectSet;

pub(crate) use super::mask::Mask;

pub(crate) fn mask(s: &ObjectSet) -> Mask {
    Mask::from_set(s)
}

/// The label of a vertex or an edge.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Lab {
    /// Not checked yet; the true label contains this set.
    Unknown(Mask),
    Known(Mask),
    /// Hits something fixed.
    Blocked,
}

impl Lab {
    pub(crate) fn bound(&self) -> Option<&Mask> {
        match self {
            Lab::Unknown(s) | Lab::Known(s) => Some(s),
            Lab::Blocked => None,
        }
    }
    pub(crate) fn is_known(&self) -> bool {
        !matches!(self, Lab::Unknown(_))
    }
}

/// An undirected graph with labelled vertices and edges (what the searches run on;
/// `andor::Graph` is the AND/OR precedence graph).
#[derive(Clone, Debug, Default)]
pub(crate) struct LabelGraph {
    /// Per vertex: (neighbour, edge).
    pub adj: Vec<Vec<(u32, u32)>>,
    vlab: Vec<Lab>,
    pub elen: Vec<f64>,
    elab: Vec<Lab>,
    /// Per vertex and per edge: whether its label is known or bounded to touch nothing.
    /// The lazy loop's searches for a path touching nothing read these bytes, not the
    /// labels: on a graph of 100 000 edges they stay in cache, the labels do not.
    vfree: Vec<bool>,
    efree: Vec<bool>,
    /// Per vertex, a lower bound on its path length to the goal that no edge breaks
    /// (`h(a) <= len(a, b) + h(b)`): the searches' A* estimate. Empty: zero.
    pub h: Vec<f64>,
}

/// Whether a label lets a path touching nothing through.
fn touches_nothing(l: &Lab) -> bool {
    l.bound().is_some_and(|s| s.is_subset(&Mask::default()))
}

impl LabelGraph {
    pub(crate) fn add_vertex(&mut self, lab: Lab) -> u32 {
        self.add_vertex_of_degree(lab, 0)
    }
    /// [`LabelGraph::add_vertex`] with room for `degree` edges: a layered graph's
    /// roadmap vertices know theirs, and growing each list edge by edge was most of the
    /// reallocations of a large problem's graph building.
    pub(crate) fn add_vertex_of_degree(&mut self, lab: Lab, degree: usize) -> u32 {
        self.adj.push(Vec::with_capacity(degree));
        self.vfree.push(touches_nothing(&lab));
        self.vlab.push(lab);
        (self.vlab.len() - 1) as u32
    }
    pub(crate) fn vlab(&self) -> &[Lab] {
        &self.vlab
    }
    pub(crate) fn elab(&self) -> &[Lab] {
        &self.elab
    }
    pub(crate) fn set_vlab(&mut self, v: usize, lab: Lab) {
        self.vfree[v] = touches_nothing(&lab);
        self.vlab[v] = lab;
    }
    pub(crate) fn set_elab(&mut self, e: usize, lab: Lab) {
        self.efree[e] = touches_nothing(&lab);
        self.elab[e] = lab;
    }
    fn h(&self, v: u32) -> f64 {
        self.h.get(v as usize).copied().unwrap_or(0.0)
    }
    pub(crate) fn add_edge(&mut self, a: u32, b: u32, len: f64, lab: Lab) -> u32 {
        let e = self.elen.len() as u32;
        self.elen.push(len);
        self.efree.push(touches_nothing(&lab));
        self.elab.push(lab);
        self.adj[a as usize].push((b, e));
        self.adj[b as usize].push((a, e));
        e
    }
}

/// A path found by a search, with the union of the (bounds of the) labels on it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Found {
    pub verts: Vec<u32>,
    pub edges: Vec<u32>,
    pub set: Mask,
    pub len: f64,
}

/// A path length as a key: a total order on f64 (lengths are finite), for the heaps
/// and for ranking candidates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Len(pub f64);
impl Eq for Len {}
impl PartialOrd for Len {
    fn partial_cmp(&self, o: &Len) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Len {
    fn cmp(&self, o: &Len) -> Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// Minimum-constraint removal: the path from `start` to `goal` whose union of labels is
/// smallest, then the shortest path whose labels lie inside that union.
///
/// Phase one is a Dijkstra over (vertex, label set) ordered by (|set|, length) that
/// drops a state when the same vertex was already reached with a subset: exact for the
/// smallest set, and the number of states per vertex stays an antichain of sets.
/// Phase two is a plain Dijkstra on length through elements whose labels lie inside
/// the set found, which breaks ties between paths with that set by length.
///
/// States with `bound` or more objects are dropped: the caller already holds an
/// answer that small, so only strictly smaller sets are worth finding.
pub(crate) fn fewest_removals(g: &LabelGraph, start: u32, goal: u32, bound: u32) -> Option<Found> {
    // A path touching nothing is what phase one would find first when one exists (no set
    // is smaller), and phase two would then search for it again: search for it alone.
    if bound > 0 {
        if let Some(f) = shortest_within(g, start, goal, Mask::default()) {
            return Some(f);
        }
    }
    let best = smallest_set(g, start, goal, bound)?;
    shortest_within(g, start, goal, best)
}

fn smallest_set(g: &LabelGraph, start: u32, goal: u32, bound: u32) -> Option<Mask> {
    let start_set = g.vlab()[start as usize].bound()?.clone();
    if start_set.count() >= bound {
        return None;
    }
    // Per vertex: the sets it was reached with (an antichain), and whether each is live.
    let mut fronts: Vec<Vec<Mask>> = vec![Vec::new(); g.vlab().len()];
    fronts[start as usize].push(start_set.clone());
    let mut heap = BinaryHeap::new();
    heap.push(Reverse((start_set.count(), Len(g.h(start)), Len(0.0), start, start_set)));
    while let Some(Reverse((_, _, Len(len), v, set))) = heap.pop() {
        if !fronts[v as usize].contains(&set) {
            continue;
        }
        if v == goal {
            return Some(set);
        }
        for &(w, e) in &g.adj[v as usize] {
            let (Some(el), Some(wl)) = (g.elab()[e as usize].bound(), g.vlab()[w as usize].bound()) else {
                continue;
            };
            let s2 = set.union(el).union(wl);
            let n2 = s2.count();
            if n2 >= bound {
                continue;
            }
            let front = &mut fronts[w as usize];
            if front.iter().any(|o| o.is_subset(&s2)) {
                continue;
            }
            front.retain(|o| !s2.is_subset(o));
            front.push(s2.clone());
            let len2 = len + g.elen[e as usize];
            heap.push(Reverse((n2, Len(len2 + g.h(w)), Len(len2), w, s2)));
        }
    }
    None
}

/// The path a search's `prev` links spell from `goal` back to `start`, with the union of
/// the labels on it (the searches only walk unblocked elements).
fn trace_back(g: &LabelGraph, prev: &[(u32, u32)], start: u32, goal: u32, len: f64) -> Found {
    let (mut verts, mut edges) = (vec![goal], Vec::new());
    let mut u = goal;
    while u != start {
        let (p, e) = prev[u as usize];
        edges.push(e);
        verts.push(p);
        u = p;
    }
    verts.reverse();
    edges.reverse();
    let vert_labels = verts.iter().map(|&x| &g.vlab()[x as usize]);
    let edge_labels = edges.iter().map(|&e| &g.elab()[e as usize]);
    let set = vert_labels.chain(edge_labels).fold(Mask::default(), |acc, l| match l.bound() {
        Some(b) => acc.union(b),
        None => acc,
    });
    Found { verts, edges, set, len }
}

/// The shortest path through elements whose labels lie inside `within`.
fn shortest_within(g: &LabelGraph, start: u32, goal: u32, within: Mask) -> Option<Found> {
    if within == Mask::default() {
        return shortest_by(g, start, goal, |v| g.vfree[v], |e| g.efree[e]);
    }
    let ok = |l: &Lab| l.bound().is_some_and(|s| s.is_subset(&within));
    shortest_by(g, start, goal, |v| ok(&g.vlab[v]), |e| ok(&g.elab[e]))
}

/// The shortest path through the vertices and edges `ok_v` and `ok_e` let through.
fn shortest_by(
    g: &LabelGraph,
    start: u32,
    goal: u32,
    ok_v: impl Fn(usize) -> bool,
    ok_e: impl Fn(usize) -> bool,
) -> Option<Found> {
    if !ok_v(start as usize) {
        return None;
    }
    let n = g.vlab.len();
    let mut dist = vec![f64::INFINITY; n];
    let mut prev: Vec<(u32, u32)> = vec![(u32::MAX, u32::MAX); n];
    let mut heap = BinaryHeap::new();
    dist[start as usize] = 0.0;
    // A* on the graph's estimate (Dijkstra without one): with a consistent estimate a
    // vertex's first pop has its shortest distance, as in Dijkstra.
    heap.push(Reverse((Len(g.h(start)), start, Len(0.0))));
    while let Some(Reverse((_, v, Len(d)))) = heap.pop() {
        if d > dist[v as usize] {
            continue;
        }
        if v == goal {
            return Some(trace_back(g, &prev, start, goal, d));
        }
        for &(w, e) in &g.adj[v as usize] {
            if !ok_e(e as usize) || !ok_v(w as usize) {
                continue;
            }
            let d2 = d + g.elen[e as usize];
            if d2 < dist[w as usize] {
                dist[w as usize] = d2;
                prev[w as usize] = (v, e);
                heap.push(Reverse((Len(d2 + g.h(w)), w, Len(d2))));
            }
        }
    }
    None
}

/// The paper's rule: the path with the fewest vertices (ties broken by length),
/// ignoring labels except blocks; its set is the union of the labels on it.
pub(crate) fn fewest_vertices(g: &LabelGraph, start: u32, goal: u32) -> Option<Found> {
    g.vlab()[start as usize].bound()?;
    let n = g.vlab().len();
    let mut best: Vec<(u32, f64)> = vec![(u32::MAX, f64::INFINITY); n];
    let mut prev: Vec<(u32, u32)> = vec![(u32::MAX, u32::MAX); n];
    let mut heap = BinaryHeap::new();
    best[start as usize] = (0, 0.0);
    heap.push(Reverse((0u32, Len(0.0), start)));
    while let Some(Reverse((h, Len(l), v))) = heap.pop() {
        if (h, l) != best[v as usize] {
            continue;
        }
        if v == goal {
            return Some(trace_back(g, &prev, start, goal, l));
        }
        for &(w, e) in &g.adj[v as usize] {
            if g.elab()[e as usize].bound().is_none() || g.vlab()[w as usize].bound().is_none() {
                continue;
            }
            let cand = (h + 1, l + g.elen[e as usize]);
            let cur = best[w as usize];
            if cand.0 < cur.0 || (cand.0 == cur.0 && cand.1 < cur.1) {
                best[w as usize] = cand;
                prev[w as usize] = (v, e);
                heap.push(Reverse((cand.0, Len(cand.1), w)));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resolve::ObjectId;

    fn set(ids: &[u32]) -> Mask {
        mask(&ids.iter().map(|&i| ObjectId(i)).collect())
    }

    fn none() -> Mask {
        Mask::default()
    }

    /// A seeded linear congruential generator: `rnd(m)` is uniform-ish in `0..m`.
    fn lcg(mut s: u64) -> impl FnMut(u64) -> u64 {
        move |m| {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) % m
        }
    }

    /// start 0, goal 3. Short route 0-1-3 touches {0,1}; long route 0-2-4-3 touches {2};
    /// a blocked shortcut 0-3.
    fn diamond() -> LabelGraph {
        let mut g = LabelGraph::default();
        for _ in 0..5 {
            g.add_vertex(Lab::Known(none()));
        }
        g.add_edge(0, 3, 0.5, Lab::Blocked);
        g.add_edge(0, 1, 1.0, Lab::Known(set(&[0])));
        g.add_edge(1, 3, 1.0, Lab::Known(set(&[1])));
        g.add_edge(0, 2, 1.0, Lab::Known(none()));
        g.add_edge(2, 4, 1.0, Lab::Known(set(&[2])));
        g.add_edge(4, 3, 1.0, Lab::Known(none()));
        g
    }

    #[test]
    fn mcr_prefers_fewer_removals_over_fewer_vertices() {
        let g = diamond();
        let mcr = fewest_removals(&g, 0, 3, u32::MAX).unwrap();
        assert_eq!(mcr.verts, vec![0, 2, 4, 3]);
        assert_eq!(mcr.set, set(&[2]));
        let fv = fewest_vertices(&g, 0, 3).unwrap();
        assert_eq!(fv.verts, vec![0, 1, 3]);
        assert_eq!(fv.set, set(&[0, 1]));
    }

    #[test]
    fn mcr_counts_repeated_labels_once() {
        // Route A touches {5} on three edges; route B touches {6} then {7}.
        let mut g = LabelGraph::default();
        for _ in 0..6 {
            g.add_vertex(Lab::Known(none()));
        }
        g.add_edge(0, 1, 1.0, Lab::Known(set(&[5])));
        g.add_edge(1, 2, 1.0, Lab::Known(set(&[5])));
        g.add_edge(2, 5, 1.0, Lab::Known(set(&[5])));
        g.add_edge(0, 3, 0.1, Lab::Known(set(&[6])));
        g.add_edge(3, 5, 0.1, Lab::Known(set(&[7])));
        let f = fewest_removals(&g, 0, 5, u32::MAX).unwrap();
        assert_eq!(f.set, set(&[5]));
        assert_eq!(f.verts, vec![0, 1, 2, 5]);
    }

    #[test]
    fn dominance_keeps_incomparable_sets() {
        // Vertex 1 is reached cheaply with {0} and expensively with {1}; only {1}
        // combines with the last edge's {1} into a one-object answer. Pruning by
        // length alone would lose it.
        let mut g = LabelGraph::default();
        for _ in 0..4 {
            g.add_vertex(Lab::Known(none()));
        }
        g.add_edge(0, 1, 1.0, Lab::Known(set(&[0])));
        g.add_edge(0, 2, 1.0, Lab::Known(set(&[1])));
        g.add_edge(2, 1, 5.0, Lab::Known(none()));
        g.add_edge(1, 3, 1.0, Lab::Known(set(&[1])));
        let f = fewest_removals(&g, 0, 3, u32::MAX).unwrap();
        assert_eq!(f.set, set(&[1]));
        assert_eq!(f.verts, vec![0, 2, 1, 3]);
        // With an answer of one object in hand, nothing better exists.
        assert!(fewest_removals(&g, 0, 3, 1).is_none());
        // A subset reached with no greater length dominates: {0} at length 1 beats {0,1} at 2.
        let mut h = g.clone();
        h.add_edge(0, 1, 2.0, Lab::Known(set(&[0, 1])));
        assert_eq!(fewest_removals(&h, 0, 3, u32::MAX).unwrap().set, set(&[1]));
    }

    #[test]
    fn vertex_labels_count_and_blocked_vertices_are_avoided() {
        let mut g = LabelGraph::default();
        g.add_vertex(Lab::Known(none()));
        g.add_vertex(Lab::Blocked);
        g.add_vertex(Lab::Known(set(&[3])));
        g.add_vertex(Lab::Known(none()));
        g.add_edge(0, 1, 1.0, Lab::Known(none()));
        g.add_edge(1, 3, 1.0, Lab::Known(none()));
        g.add_edge(0, 2, 1.0, Lab::Known(none()));
        g.add_edge(2, 3, 1.0, Lab::Known(none()));
        let f = fewest_removals(&g, 0, 3, u32::MAX).unwrap();
        assert_eq!(f.set, set(&[3]));
        assert_eq!(fewest_vertices(&g, 0, 3).unwrap().verts, vec![0, 2, 3]);
        g.set_vlab(2, Lab::Blocked);
        assert!(fewest_removals(&g, 0, 3, u32::MAX).is_none());
        assert!(fewest_vertices(&g, 0, 3).is_none());
    }

    #[test]
    fn brute_force_agreement_on_random_small_graphs() {
        // Exhaustive check: the smallest subset S such that a path exists using only
        // elements whose labels lie in S equals the MCR answer's size.
        let mut rnd = lcg(99);
        for _ in 0..200 {
            let n = 8;
            let mut g = LabelGraph::default();
            for _ in 0..n {
                let l = if rnd(4) == 0 { set(&[rnd(5) as u32]) } else { none() };
                g.add_vertex(Lab::Known(l));
            }
            g.set_vlab(0, Lab::Known(none()));
            for _ in 0..14 {
                let (a, b) = (rnd(n) as u32, rnd(n) as u32);
                if a == b {
                    continue;
                }
                let lab = match rnd(6) {
                    0 => Lab::Blocked,
                    1 | 2 => Lab::Known(set(&[rnd(5) as u32])),
                    _ => Lab::Known(none()),
                };
                g.add_edge(a, b, 1.0 + rnd(3) as f64, lab);
            }
            let mcr = fewest_removals(&g, 0, n as u32 - 1, u32::MAX).map(|f| f.set.count() as usize);
            let brute = (0u32..32).filter(|m| path_within(&g, *m, n as u32 - 1)).map(|m| m.count_ones() as usize).min();
            assert_eq!(mcr, brute);
        }
    }

    /// Random graphs on random points of the plane, each edge at least as long as the
    /// straight line it spans: with the distance to the goal as the estimate, both
    /// searches find answers of the same set size and length as with no estimate, and
    /// the path found is as long as it says.
    #[test]
    fn an_estimate_changes_no_answer() {
        let mut rnd = lcg(7);
        let mut searched = 0;
        for _ in 0..300 {
            let n = 30;
            let pts: Vec<(f64, f64)> = (0..n).map(|_| (rnd(1000) as f64 / 100.0, rnd(1000) as f64 / 100.0)).collect();
            let mut g = LabelGraph::default();
            for _ in 0..n {
                let l = if rnd(5) == 0 { set(&[rnd(6) as u32]) } else { none() };
                g.add_vertex(Lab::Known(l));
            }
            g.set_vlab(0, Lab::Known(none()));
            for _ in 0..90 {
                let (a, b) = (rnd(n) as usize, rnd(n) as usize);
                if a == b {
                    continue;
                }
                let straight = ((pts[a].0 - pts[b].0).powi(2) + (pts[a].1 - pts[b].1).powi(2)).sqrt();
                let lab = match rnd(8) {
                    0 => Lab::Blocked,
                    1 | 2 => Lab::Known(set(&[rnd(6) as u32])),
                    _ => Lab::Known(none()),
                };
                g.add_edge(a as u32, b as u32, straight * (1.0 + rnd(3) as f64 / 4.0), lab);
            }
            let goal = n as u32 - 1;
            let plain = fewest_removals(&g, 0, goal, u32::MAX);
            let mut h = g.clone();
            let gp = pts[goal as usize];
            h.h = pts.iter().map(|p| ((p.0 - gp.0).powi(2) + (p.1 - gp.1).powi(2)).sqrt()).collect();
            let guided = fewest_removals(&h, 0, goal, u32::MAX);
            match (&plain, &guided) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    searched += 1;
                    assert_eq!(a.set.count(), b.set.count());
                    assert!((a.len - b.len).abs() < 1e-9, "{} vs {}", a.len, b.len);
                    let walked: f64 = b.edges.iter().map(|&e| g.elen[e as usize]).sum();
                    assert!((walked - b.len).abs() < 1e-9);
                    assert_eq!((b.verts[0], *b.verts.last().unwrap()), (0, goal));
                }
                _ => panic!("one search found a path, the other not"),
            }
        }
        assert!(searched > 100, "too few graphs had a path: {searched}");
    }

    /// The search for a path touching nothing reads the graph's per-element bytes; they
    /// follow every label written, as a lazy search rewrites them: the same answers as
    /// reading the labels themselves.
    #[test]
    fn the_touching_nothing_bytes_follow_every_label_written() {
        let mut rnd = lcg(41);
        let lab = |r: u64, o: u32| match r {
            0 => Lab::Blocked,
            1 => Lab::Known(set(&[o])),
            2 => Lab::Unknown(set(&[o])),
            3 => Lab::Unknown(none()),
            _ => Lab::Known(none()),
        };
        let mut found = 0;
        for _ in 0..200 {
            let n = 16;
            let mut g = LabelGraph::default();
            for _ in 0..n {
                g.add_vertex(lab(rnd(7), rnd(3) as u32));
            }
            for _ in 0..40 {
                let (a, b) = (rnd(n) as u32, rnd(n) as u32);
                if a != b {
                    g.add_edge(a, b, 1.0 + rnd(3) as f64, lab(rnd(7), rnd(3) as u32));
                }
            }
            for _ in 0..10 {
                let by_labels =
                    shortest_by(&g, 0, n as u32 - 1, |v| touches_nothing(&g.vlab[v]), |e| touches_nothing(&g.elab[e]));
                let by_bytes = shortest_within(&g, 0, n as u32 - 1, Mask::default());
                assert_eq!(by_labels, by_bytes);
                found += by_bytes.is_some() as usize;
                let v = rnd(n) as usize;
                g.set_vlab(v, lab(rnd(7), rnd(3) as u32));
                let e = rnd(g.elen.len() as u64) as usize;
                g.set_elab(e, lab(rnd(7), rnd(3) as u32));
            }
        }
        assert!(found > 200, "only {found} searches found a path");
    }

    fn path_within(g: &LabelGraph, mask: u32, goal: u32) -> bool {
        let within: Mask = (0..32).filter(|i| mask & (1 << i) != 0).map(ObjectId).collect();
        let ok = |l: &Lab| l.bound().is_some_and(|s| s.is_subset(&within));
        let mut seen = vec![false; g.vlab().len()];
        let mut stack = vec![0u32];
        if !ok(&g.vlab()[0]) {
            return false;
        }
        seen[0] = true;
        while let Some(v) = stack.pop() {
            if v == goal {
                return true;
            }
            for &(w, e) in &g.adj[v as usize] {
                if !seen[w as usize] && ok(&g.elab()[e as usize]) && ok(&g.vlab()[w as usize]) {
                    seen[w as usize] = true;
                    stack.push(w);
                }
            }
        }
        false
    }
}
