//! A static k-d tree over joint-space points for k-nearest-neighbour queries.
//!
//! The roadmap grows in rounds whose sizes double, so the tree is rebuilt once per
//! round (O(n log n)); a query is O(log n) on average instead of a linear scan. The
//! dimension is a run-time value, which kiddo's const-generic trees would need a
//! dispatch for. Distances are plain Euclidean in joint space.

/// A k-d tree over `n` points of dimension `dim`, stored flat.
pub(crate) struct KdTree {
    dim: usize,
    pts: Vec<f64>,
    /// Point indices, arranged as an implicit balanced tree (median at the middle).
    order: Vec<u32>,
}

/// The point nearest `q` among the `n` points of a growing set (`point(i)`, `dim`
/// values each), as an index into it; ties go to the lower index. `index` holds a k-d
/// tree over the first points, rebuilt when those it does not hold, scanned one by one,
/// pass `tail` or a sixteenth of those it does.
pub(crate) fn nearest_growing<'a>(
    index: &mut Option<(KdTree, usize)>,
    dim: usize,
    n: usize,
    tail: usize,
    point: impl Fn(usize) -> &'a [f64],
    q: &[f64],
) -> usize {
    let held = index.as_ref().map_or(0, |x| x.1);
    if n - held > tail.max(held / 16) {
        let flat: Vec<f64> = (0..n).flat_map(|i| point(i).iter().copied()).collect();
        *index = Some((KdTree::build(dim, &flat, n), n));
    }
    let (mut best, held) = match index {
        Some((kd, held)) => {
            let near = kd.nearest(q, 1, |_| false).first().map(|&(d, i)| (d, i as usize));
            (near.unwrap_or((f64::INFINITY, 0)), *held)
        }
        None => ((f64::INFINITY, 0), 0),
    };
    for i in held..n {
        let d = dist2(point(i), q);
        if d < best.0 {
            best = (d, i);
        }
    }
    best.1
}

/// Squared Euclidean distance.
pub(crate) fn dist2(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

impl KdTree {
    /// Builds over the first `n` points of `pts` (flat, `dim` values each).
    pub(crate) fn build(dim: usize, pts: &[f64], n: usize) -> KdTree {
        let mut order: Vec<u32> = (0..n as u32).collect();
        let pts = pts[..n * dim].to_vec();
        split(&pts, dim, &mut order, 0);
        KdTree { dim, pts, order }
    }

    /// The `k` nearest points to `q` as (squared distance, index), nearest first; ties by index.
    /// Points for which `skip` returns true are ignored.
    pub(crate) fn nearest(&self, q: &[f64], k: usize, skip: impl Fn(u32) -> bool) -> Vec<(f64, u32)> {
        let mut best: Vec<(f64, u32)> = Vec::with_capacity(k + 1);
        if k > 0 {
            self.search(&self.order, 0, q, k, &skip, &mut best);
        }
        best
    }

    fn point(&self, i: u32) -> &[f64] {
        let s = i as usize * self.dim;
        &self.pts[s..s + self.dim]
    }

    fn search<F: Fn(u32) -> bool>(
        &self,
        idx: &[u32],
        depth: usize,
        q: &[f64],
        k: usize,
        skip: &F,
        best: &mut Vec<(f64, u32)>,
    ) {
        if idx.is_empty() {
            return;
        }
        let mid = idx.len() / 2;
        let i = idx[mid];
        let p = self.point(i);
        if !skip(i) {
            let d = dist2(p, q);
            if best.len() < k || d <= best[best.len() - 1].0 {
                insert(best, k, (d, i));
            }
        }
        let axis = depth % self.dim;
        let diff = q[axis] - p[axis];
        let (near, far) = if diff < 0.0 { (&idx[..mid], &idx[mid + 1..]) } else { (&idx[mid + 1..], &idx[..mid]) };
        self.search(near, depth + 1, q, k, skip, best);
        if best.len() < k || diff * diff <= best[best.len() - 1].0 {
            self.search(far, depth + 1, q, k, skip, best);
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

fn split(pts: &[f64], dim: usize, idx: &mut [u32], depth: usize) {
    if idx.len() <= 1 {
        return;
    }
    let axis = depth % dim;
    let mid = idx.len() / 2;
    idx.select_nth_unstable_by(mid, |&a, &b| {
        pts[a as usize * dim + axis].total_cmp(&pts[b as usize * dim + axis]).then(a.cmp(&b))
    });
    let (lo, hi) = idx.split_at_mut(mid);
    split(pts, dim, lo, depth + 1);
    split(pts, dim, &mut hi[1..], depth + 1);
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

    /// Seven dimensions (an arm's), points on a coarse grid so many distances tie, k from
    /// one to past the leaf size: the same (distance, index) lists as a linear scan.
    #[test]
    fn matches_linear_scan_with_ties_in_seven_dimensions() {
        let dim = 7;
        let mut s = 777u64;
        let mut rnd = |m: u64| {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) % m
        };
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
}
