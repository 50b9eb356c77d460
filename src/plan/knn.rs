//! A static k-d tree over joint-space points for k-nearest-neighbour queries.
//!
//! The roadmap grows in rounds whose sizes double, so the tree is rebuilt once per
//! round (O(n log n)); a query is O(log n) on average instead of a linear scan. The
//! search trees that grow a node at a time index theirs with [`GrowingIndex`]. The
//! dimension is a run-time value, which kiddo's const-generic trees would need a
//! dispatch for. Distances are plain Euclidean in joint space.

/// A k-d tree over `n` points of dimension `dim`, stored flat.
pub(crate) struct KdTree {
    dim: usize,
    /// The points in the tree's order (`order[pos]`'s at `pos`).
    pts: Vec<f64>,
    /// Added to every index it reports: the first point's index in a larger set.
    offset: u32,
    /// Point indices, arranged as an implicit balanced tree (median at the middle).
    order: Vec<u32>,
    /// Per position that is a subtree's median, the axis that subtree is split on.
    axes: Vec<u8>,
    /// Per position that is the median of a subtree or a leaf (`lo + (hi - lo) / 2` of
    /// its range, distinct for every non-empty range), the box of its points: `dim`
    /// lower bounds then `dim` upper ones.
    boxes: Vec<f64>,
}

/// Subtrees of at most this many points are scanned, not split further.
const LEAF: usize = 16;

/// Runs of this many points become a k-d tree of their own; fewer are scanned one by one.
const RUN: usize = 32;

/// A nearest-point index over a set that only grows (a search tree's nodes, by age):
/// static k-d trees over consecutive runs of the points, sizes `RUN` times distinct
/// powers of two, oldest and largest first, and the newest points (fewer than `RUN`)
/// scanned one by one. Two trees of one size merge into one of twice it (Bentley and
/// Saxe's logarithmic method), so a point is rebuilt into a larger tree O(log n) times
/// and a query searches O(log n) trees: no rebuild of the whole set, and no long tail
/// of points scanned one by one as the set grows.
#[derive(Default)]
pub(crate) struct GrowingIndex {
    trees: Vec<KdTree>,
    /// The points the trees hold: the first `held`.
    held: usize,
}

impl GrowingIndex {
    /// The point nearest `q` among the first `n` points of the set (`point(i)`, `dim`
    /// values each, `n` never less than at the last call) that `skip` does not leave out,
    /// as an index into it; ties go to the lower index. The first point when every one
    /// is left out. `seed`: a point likely near `q` (below `n`); the search starts from
    /// its distance, so that far subtrees are pruned from the first, with the same answer.
    pub(crate) fn nearest<'a>(
        &mut self,
        dim: usize,
        n: usize,
        point: impl Fn(usize) -> &'a [f64],
        q: &[f64],
        skip: impl Fn(u32) -> bool,
        seed: Option<usize>,
    ) -> usize {
        self.catch_up(dim, n, &point);
        let mut best = match seed.filter(|&i| i < n && !skip(i as u32)) {
            Some(i) => (dist2(point(i), q), i as u32),
            None => (f64::INFINITY, u32::MAX),
        };
        for t in &self.trees {
            t.nearest_one(q, &skip, &mut best);
        }
        let mut best = if best.1 == u32::MAX { (f64::INFINITY, 0) } else { (best.0, best.1 as usize) };
        for i in self.held..n {
            if skip(i as u32) {
                continue;
            }
            // (A tie with the seed, which may be newer, goes to the older point.)
            let d = dist2(point(i), q);
            if d < best.0 || (d == best.0 && i < best.1) {
                best = (d, i);
            }
        }
        best.1
    }

    /// The `k` points nearest `q` among the first `n` (as [`Self::nearest`]'s), nearest
    /// first, ties to the lower index; all of them when there are fewer.
    pub(crate) fn k_nearest<'a>(
        &mut self,
        dim: usize,
        n: usize,
        point: impl Fn(usize) -> &'a [f64],
        q: &[f64],
        k: usize,
    ) -> Vec<usize> {
        self.catch_up(dim, n, &point);
        let mut all: Vec<(f64, u32)> = self.trees.iter().flat_map(|t| t.nearest(q, k, |_| false)).collect();
        all.extend((self.held..n).map(|i| (dist2(point(i), q), i as u32)));
        all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        all.into_iter().take(k).map(|(_, i)| i as usize).collect()
    }

    /// Builds the k-d trees of the full runs of `RUN` points among the first `n`.
    fn catch_up<'a>(&mut self, dim: usize, n: usize, point: &impl Fn(usize) -> &'a [f64]) {
        while n - self.held >= RUN {
            let (mut start, end) = (self.held, self.held + RUN);
            while self.trees.last().is_some_and(|t| t.len() == end - start) {
                start = self.trees.pop().map_or(start, |t| t.offset as usize);
            }
            let flat: Vec<f64> = (start..end).flat_map(|i| point(i).iter().copied()).collect();
            self.trees.push(KdTree::build_run(dim, flat, start as u32));
            self.held = end;
        }
    }
}

/// Squared Euclidean distance.
pub(crate) fn dist2(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

impl KdTree {
    /// Builds over the first `n` points of `pts` (flat, `dim` values each).
    pub(crate) fn build(dim: usize, pts: &[f64], n: usize) -> KdTree {
        KdTree::build_run(dim, pts[..n * dim].to_vec(), 0)
    }

    /// Builds over all of `pts` (flat), reporting point `i` as `offset + i`.
    fn build_run(dim: usize, pts: Vec<f64>, offset: u32) -> KdTree {
        let mut order: Vec<u32> = (0..(pts.len() / dim.max(1)) as u32).collect();
        let mut axes = vec![0u8; order.len()];
        split(&pts, dim, &mut order, &mut axes);
        // Stored in the tree's order, so that a subtree's points lie together.
        let pts: Vec<f64> =
            order.iter().flat_map(|&i| pts[i as usize * dim..(i as usize + 1) * dim].iter().copied()).collect();
        let mut boxes = vec![0.0; pts.len() * 2];
        if !order.is_empty() {
            bound(&pts, dim, (0, order.len()), &mut boxes);
        }
        KdTree { dim, pts, offset, order, axes, boxes }
    }

    /// How many points it holds.
    fn len(&self) -> usize {
        self.order.len()
    }

    /// The `k` nearest points to `q` as (squared distance, index), nearest first; ties by index.
    /// Points for which `skip` returns true are ignored.
    pub(crate) fn nearest(&self, q: &[f64], k: usize, skip: impl Fn(u32) -> bool) -> Vec<(f64, u32)> {
        let mut best: Vec<(f64, u32)> = Vec::with_capacity(k + 1);
        self.nearest_into(q, k, &skip, &mut best);
        best
    }

    /// Merges its `k` nearest points into `best` (sorted as `nearest` returns them, at
    /// most `k` long): the `k` nearest of both.
    fn nearest_into<F: Fn(u32) -> bool>(&self, q: &[f64], k: usize, skip: &F, best: &mut Vec<(f64, u32)>) {
        if k > 0 {
            // An arm's joints fit the stack buffer (a growing tree searches a few trees
            // per query); only a space of more dimensions allocates.
            let mut buf = [0.0; 16];
            let mut heap = Vec::new();
            let off = match self.dim <= buf.len() {
                true => &mut buf[..self.dim],
                false => {
                    heap.resize(self.dim, 0.0);
                    &mut heap[..]
                }
            };
            self.search((0, self.order.len()), q, k, skip, best, (off, 0.0));
        }
    }

    /// Lowers `best` (squared distance, index; `u32::MAX` for none yet) to the point
    /// nearest `q` that `skip` leaves in, ties to the lower index: what `nearest_into` with
    /// `k = 1` finds, by a search whose points are arrays of an arm's dimension (the
    /// growing trees' queries were most of a hard query's instructions, in the generic
    /// loops and the list of the best).
    fn nearest_one<F: Fn(u32) -> bool>(&self, q: &[f64], skip: &F, best: &mut (f64, u32)) {
        match self.dim {
            6 => self.one_fixed::<6, F>(q, skip, best),
            7 => self.one_fixed::<7, F>(q, skip, best),
            _ => {
                let mut list: Vec<(f64, u32)> = Vec::with_capacity(2);
                if best.1 != u32::MAX {
                    list.push(*best);
                }
                self.nearest_into(q, 1, skip, &mut list);
                if let Some(&b) = list.first() {
                    *best = b;
                }
            }
        }
    }

    fn one_fixed<const D: usize, F: Fn(u32) -> bool>(&self, q: &[f64], skip: &F, best: &mut (f64, u32)) {
        let Ok(q) = <&[f64; D]>::try_from(q) else { return };
        let mut off = [0.0; D];
        self.search_one::<D, F>((0, self.order.len()), q, skip, best, (&mut off, 0.0));
    }

    /// [`Self::search`] for the one nearest point, in `D` dimensions.
    fn search_one<const D: usize, F: Fn(u32) -> bool>(
        &self,
        (lo, hi): (usize, usize),
        q: &[f64; D],
        skip: &F,
        best: &mut (f64, u32),
        (off, rd): (&mut [f64; D], f64),
    ) {
        // The subtree's box is a tighter bound than the cell's splitting planes: a query
        // from outside a growing tree's reach (half its aims are uniform in the joint
        // limits) is near none of it, and the planes cut only a few of its axes.
        if hi > lo && best.1 != u32::MAX && self.box_dist2::<D>(lo + (hi - lo) / 2, q) * (1.0 - 1e-9) > best.0 {
            return;
        }
        if hi - lo <= LEAF {
            // A leaf's points as arrays: one bounds check for the leaf, not one per value.
            let (points, _) = self.pts[lo * D..hi * D].as_chunks::<D>();
            for (p, &i) in points.iter().zip(&self.order[lo..hi]) {
                self.consider(p, self.offset + i, q, skip, best);
            }
            return;
        }
        let mid = lo + (hi - lo) / 2;
        self.visit_one(mid, q, skip, best);
        let axis = self.axes[mid] as usize;
        let diff = q[axis] - self.pts[mid * D + axis];
        let (near, far) = if diff < 0.0 { ((lo, mid), (mid + 1, hi)) } else { ((mid + 1, hi), (lo, mid)) };
        self.search_one::<D, F>(near, q, skip, best, (&mut *off, rd));
        let old = off[axis];
        let far_rd = rd - old * old + diff * diff;
        // As in `search`: shrunk so that rounding never prunes a tie.
        if best.1 == u32::MAX || far_rd * (1.0 - 1e-9) <= best.0 {
            off[axis] = diff;
            self.search_one::<D, F>(far, q, skip, best, (&mut *off, far_rd));
            off[axis] = old;
        }
    }

    /// The squared distance from `q` to the box of the subtree or leaf whose middle
    /// position is `pos`: at most any of its points' distance.
    #[inline(always)]
    fn box_dist2<const D: usize>(&self, pos: usize, q: &[f64; D]) -> f64 {
        let (lo, hi) = self.boxes[pos * 2 * D..(pos + 1) * 2 * D].split_at(D);
        let (Ok(lo), Ok(hi)) = (<&[f64; D]>::try_from(lo), <&[f64; D]>::try_from(hi)) else { return 0.0 };
        let mut d = 0.0;
        for i in 0..D {
            let out = (lo[i] - q[i]).max(q[i] - hi[i]).max(0.0);
            d += out * out;
        }
        d
    }

    #[inline(always)]
    fn visit_one<const D: usize, F: Fn(u32) -> bool>(&self, pos: usize, q: &[f64; D], skip: &F, best: &mut (f64, u32)) {
        let Ok(p) = <&[f64; D]>::try_from(&self.pts[pos * D..(pos + 1) * D]) else { return };
        self.consider(p, self.offset + self.order[pos], q, skip, best);
    }

    /// Point `id` at `p`, against the best so far.
    #[inline(always)]
    fn consider<const D: usize, F: Fn(u32) -> bool>(
        &self,
        p: &[f64; D],
        id: u32,
        q: &[f64; D],
        skip: &F,
        best: &mut (f64, u32),
    ) {
        if skip(id) {
            return;
        }
        // The same sum, in the same order, as `dist2`: the same bits.
        let mut d = 0.0;
        for i in 0..D {
            d += (p[i] - q[i]) * (p[i] - q[i]);
        }
        if best.1 == u32::MAX || d < best.0 || (d == best.0 && id < best.1) {
            *best = (d, id);
        }
    }

    /// The point at position `pos` of the tree's order, and its index.
    fn at(&self, pos: usize) -> (&[f64], u32) {
        (&self.pts[pos * self.dim..(pos + 1) * self.dim], self.offset + self.order[pos])
    }

    /// Searches positions `lo..hi` (a subtree: its median at the middle, split on the axis
    /// `axes` holds there), `off` holding per axis how far `q` lies outside the subtree's cell
    /// and `rd` their squares' sum, a lower bound on the distance to any of its points
    /// (Arya and Mount's incremental distance: in seven dimensions the splitting plane's
    /// own distance alone prunes little).
    #[allow(clippy::too_many_arguments)]
    fn search<F: Fn(u32) -> bool>(
        &self,
        (lo, hi): (usize, usize),
        q: &[f64],
        k: usize,
        skip: &F,
        best: &mut Vec<(f64, u32)>,
        (off, rd): (&mut [f64], f64),
    ) {
        if hi - lo <= LEAF {
            for pos in lo..hi {
                self.visit(pos, q, k, skip, best);
            }
            return;
        }
        let mid = lo + (hi - lo) / 2;
        self.visit(mid, q, k, skip, best);
        let axis = self.axes[mid] as usize;
        let diff = q[axis] - self.pts[mid * self.dim + axis];
        let (near, far) = if diff < 0.0 { ((lo, mid), (mid + 1, hi)) } else { ((mid + 1, hi), (lo, mid)) };
        self.search(near, q, k, skip, best, (&mut *off, rd));
        let old = off[axis];
        let far_rd = rd - old * old + diff * diff;
        // Shrunk a little so that rounding in the running sum never prunes a point that
        // ties with the worst kept (ties are decided by index).
        if best.len() < k || far_rd * (1.0 - 1e-9) <= best[best.len() - 1].0 {
            off[axis] = diff;
            self.search(far, q, k, skip, best, (&mut *off, far_rd));
            off[axis] = old;
        }
    }

    fn visit<F: Fn(u32) -> bool>(&self, pos: usize, q: &[f64], k: usize, skip: &F, best: &mut Vec<(f64, u32)>) {
        let (p, id) = self.at(pos);
        if !skip(id) {
            let d = dist2(p, q);
            if best.len() < k || d <= best[best.len() - 1].0 {
                insert(best, k, (d, id));
            }
        }
    }
}

/// Keeps `best` sorted by (distance, index) and at most `k` long.
fn insert(best: &mut Vec<(f64, u32)>, k: usize, item: (f64, u32)) {
    if best.len() == k && cmp(&item, &best[k - 1]).is_ge() {
        return;
    }
    let pos = best.partition_point(|b| cmp(b, &item).is_lt());
    best.insert(pos, item);
    best.truncate(k);
}

fn cmp(a: &(f64, u32), b: &(f64, u32)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

/// Fills `boxes` (see [`KdTree::boxes`]) for the subtree or leaf over positions `lo..hi`
/// of `pts` (in the tree's order) and every one inside it; its box.
fn bound(pts: &[f64], dim: usize, (lo, hi): (usize, usize), boxes: &mut [f64]) -> Vec<f64> {
    let mid = lo + (hi - lo) / 2;
    let mut b: Vec<f64> = [vec![f64::INFINITY; dim], vec![f64::NEG_INFINITY; dim]].concat();
    let take = |b: &mut Vec<f64>, other: &[f64]| {
        for a in 0..dim {
            b[a] = b[a].min(other[a]);
            b[dim + a] = b[dim + a].max(other[dim + a]);
        }
    };
    if hi - lo <= LEAF {
        for pos in lo..hi {
            let p = &pts[pos * dim..(pos + 1) * dim];
            take(&mut b, &[p, p].concat());
        }
    } else {
        let p = &pts[mid * dim..(mid + 1) * dim];
        take(&mut b, &[p, p].concat());
        for child in [(lo, mid), (mid + 1, hi)] {
            if child.1 > child.0 {
                let c = bound(pts, dim, child, boxes);
                take(&mut b, &c);
            }
        }
    }
    boxes[mid * 2 * dim..(mid + 1) * 2 * dim].copy_from_slice(&b);
    b
}

/// Arranges `idx` as a subtree: its median at the middle along the axis its points spread
/// widest on (ties to the lower axis; `axes` keeps it at the median's position), the
/// halves likewise. A search tree's nodes bunch along some joints and spread along others
/// (and joint ranges differ): cycling through the axes split the bunched ones as often as
/// the spread, and a search visited more cells.
fn split(pts: &[f64], dim: usize, idx: &mut [u32], axes: &mut [u8]) {
    if idx.len() <= LEAF {
        return;
    }
    let (mut lo, mut hi) = (vec![f64::INFINITY; dim], vec![f64::NEG_INFINITY; dim]);
    for &i in idx.iter() {
        for a in 0..dim {
            let v = pts[i as usize * dim + a];
            (lo[a], hi[a]) = (lo[a].min(v), hi[a].max(v));
        }
    }
    let axis = (1..dim).fold(0, |best, a| if hi[a] - lo[a] > hi[best] - lo[best] { a } else { best });
    let mid = idx.len() / 2;
    idx.select_nth_unstable_by(mid, |&a, &b| {
        pts[a as usize * dim + axis].total_cmp(&pts[b as usize * dim + axis]).then(a.cmp(&b))
    });
    axes[mid] = axis as u8;
    let (lo, hi) = idx.split_at_mut(mid);
    let (axes_lo, axes_hi) = axes.split_at_mut(mid);
    split(pts, dim, lo, axes_lo);
    split(pts, dim, &mut hi[1..], &mut axes_hi[1..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_linear_scan() {
        let dim = 3;
        let mut s = 12345u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let pts: Vec<f64> = (0..500 * dim).map(|_| rnd()).collect();
        let tree = KdTree::build(dim, &pts, 500);
        for _ in 0..50 {
            let q: Vec<f64> = (0..dim).map(|_| rnd()).collect();
            let got = tree.nearest(&q, 7, |i| i == 3);
            let mut all: Vec<(f64, u32)> =
                (0..500u32).filter(|&i| i != 3).map(|i| (dist2(&pts[i as usize * dim..][..dim], &q), i)).collect();
            all.sort_by(cmp);
            all.truncate(7);
            assert_eq!(got, all);
        }
    }

    /// Seeded draws of 0..m (a linear congruential generator's high bits).
    fn grid_draws(seed: u64) -> impl FnMut(u64) -> u64 {
        let mut s = seed;
        move |m| {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) % m
        }
    }

    /// Seven dimensions (an arm's), points on a coarse grid so many distances tie, k from
    /// one to past the leaf size: the same (distance, index) lists as a linear scan.
    #[test]
    fn matches_linear_scan_with_ties_in_seven_dimensions() {
        let dim = 7;
        let mut rnd = grid_draws(777);
        for n in [1usize, 5, 9, 17, 300] {
            let pts: Vec<f64> = (0..n * dim).map(|_| rnd(4) as f64).collect();
            let tree = KdTree::build(dim, &pts, n);
            for k in [1, 3, 8, 9, 30] {
                let q: Vec<f64> = (0..dim).map(|_| rnd(4) as f64).collect();
                let got = tree.nearest(&q, k, |i| i % 11 == 5);
                let mut all: Vec<(f64, u32)> = (0..n as u32)
                    .filter(|i| i % 11 != 5)
                    .map(|i| (dist2(&pts[i as usize * dim..][..dim], &q), i))
                    .collect();
                all.sort_by(cmp);
                all.truncate(k);
                assert_eq!(got, all, "n {n} k {k}");
            }
        }
    }

    /// A set grown a point at a time past several merges (1 000 points, runs of 32),
    /// on a coarse grid so that distances tie: after every insertion, the nearest point
    /// of a linear scan, ties to the lower index. (A merge that dropped a run, a wrong
    /// offset or a tie kept by the wrong tree would each fail it.) Every third query leaves
    /// out the points whose index is 5 mod 7 (a search tree's dead nodes), in the trees and
    /// the scanned tail alike; every fourth comes from outside the points' box. Three in
    /// four are seeded (a newer point than a tie, a point left out, an older one).
    #[test]
    fn growing_index_matches_linear_scan_as_points_arrive() {
        // An arm's six and seven joints take the fixed-size search; three the generic one.
        for dim in [3, 6, 7] {
            let mut rnd = grid_draws(4242 + dim as u64);
            let pts: Vec<Vec<f64>> = (0..1000).map(|_| (0..dim).map(|_| rnd(3) as f64).collect()).collect();
            let mut index = GrowingIndex::default();
            let mut largest = 0;
            for n in 1..=pts.len() {
                for k in 0..4 {
                    // The fourth query from a wider box, mostly outside the points' (where
                    // the subtrees' boxes prune).
                    let q: Vec<f64> = match k {
                        3 => (0..dim).map(|_| rnd(9) as f64 - 3.0).collect(),
                        _ => (0..dim).map(|_| rnd(3) as f64).collect(),
                    };
                    let skip = |i: u32| k == 2 && i % 7 == 5;
                    // Seeds: the newest point (a tie with it goes to an older one), one
                    // left out (index 5), one in the trees; none.
                    let seed = match k {
                        1 => Some(n - 1),
                        2 => Some(5.min(n - 1)),
                        3 => Some(n / 2),
                        _ => None,
                    };
                    let got = index.nearest(dim, n, |i| &pts[i], &q, skip, seed);
                    let want = (0..n)
                        .filter(|&i| !skip(i as u32))
                        .min_by(|&a, &b| dist2(&pts[a], &q).total_cmp(&dist2(&pts[b], &q)).then(a.cmp(&b)));
                    assert_eq!(Some(got), want, "dim {dim} n {n}");
                }
                largest = largest.max(index.trees.first().map_or(0, KdTree::len));
            }
            assert_eq!(index.held, 992, "every whole run is in a tree");
            assert_eq!(largest, 512, "runs merged into one tree of 16");
            let sizes: Vec<usize> = index.trees.iter().map(KdTree::len).collect();
            assert_eq!(sizes, [512, 256, 128, 64, 32], "992 = 31 runs, one tree per bit");
        }
    }

    /// The `k` nearest of a set grown a point at a time (on a coarse grid, so that
    /// distances tie), k from 1 to past the set: a linear scan's, nearest first, ties to
    /// the lower index, in the trees and the scanned tail alike.
    #[test]
    fn growing_index_k_nearest_matches_linear_scan() {
        for dim in [3, 6] {
            let mut rnd = grid_draws(99 + dim as u64);
            let pts: Vec<Vec<f64>> = (0..300).map(|_| (0..dim).map(|_| rnd(3) as f64).collect()).collect();
            let mut index = GrowingIndex::default();
            for n in 1..=pts.len() {
                let q: Vec<f64> = (0..dim).map(|_| rnd(3) as f64).collect();
                let k = [1, 5, 16, 40][n % 4];
                let got = index.k_nearest(dim, n, |i| &pts[i], &q, k);
                let mut want: Vec<usize> = (0..n).collect();
                want.sort_by(|&a, &b| dist2(&pts[a], &q).total_cmp(&dist2(&pts[b], &q)).then(a.cmp(&b)));
                want.truncate(k);
                assert_eq!(got, want, "dim {dim} n {n} k {k}");
            }
            assert!(index.held >= 288, "the trees were searched");
        }
    }
}
