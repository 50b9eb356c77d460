//! A mesh's own surface as its hull: its distinct points, its edges, and whether it is
//! closed and convex (after flipping the few edges an exporter cut the wrong way), so
//! that most collision meshes need no quickhull.

use parry3d_f64::math::Vector as PVec;

/// The distinct points in first-seen order, and for each point its index among them.
pub(super) fn dedup(points: &[PVec]) -> (Vec<PVec>, Vec<u32>) {
    let mut index = std::collections::HashMap::with_capacity_and_hasher(points.len(), BuildBitsHasher::default());
    let mut distinct = Vec::new();
    let remap = points
        .iter()
        .map(|p| {
            *index.entry(p.to_array().map(f64::to_bits)).or_insert_with(|| {
                distinct.push(*p);
                (distinct.len() - 1) as u32
            })
        })
        .collect();
    (distinct, remap)
}

/// A multiply-rotate hash of a point's bits, mixed at the end: the default SipHash was a
/// tenth of loading a mesh robot.
#[derive(Default)]
struct BitsHasher(u64);

impl std::hash::Hasher for BitsHasher {
    fn write(&mut self, bytes: &[u8]) {
        // `[u64; 3]` hashes its words as one slice of bytes: take them eight at a time.
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn finish(&self) -> u64 {
        // splitmix64's finaliser: points read from single precision have 29 zero low bits,
        // and the table indexes by the low bits.
        let z = (self.0 ^ (self.0 >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        let z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

type BuildBitsHasher = std::hash::BuildHasherDefault<BitsHasher>;

/// Whether the triangles close a surface (see [`closed_edges`]).
#[cfg(test)]
pub(super) fn closed(n: usize, triangles: &[[u32; 3]]) -> bool {
    closed_edges(n, triangles).is_some()
}

/// Directed edges grouped by first vertex: `(first, edges)`, see [`closed_edges`].
pub(super) type ClosedEdges = (Vec<u32>, Vec<(u32, u32, u32)>);

/// When the triangles close a surface (no corner repeated, every directed edge once, and
/// its reverse once in another triangle): their directed edges grouped by first vertex,
/// those of `a` being `edges[first[a]..first[a + 1]]` sorted by second vertex, each as
/// (second vertex, its triangle, the triangle of its reverse). `None` otherwise.
pub(super) fn closed_edges(n: usize, triangles: &[[u32; 3]]) -> Option<ClosedEdges> {
    if triangles.iter().flatten().any(|&i| i as usize >= n)
        || triangles.iter().any(|t| t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
    {
        return None;
    }
    let (first, mut out) = outgoing(n, triangles);
    // Sorted, a vertex's edges are found by halving: a fan's centre (a cylinder's cap) has
    // dozens, and scanning them for each neighbour was most of loading the TX-90.
    for a in 0..n {
        out[first[a] as usize..first[a + 1] as usize].sort_unstable_by_key(|e| e.0);
    }
    let from = |a: u32| &out[first[a as usize] as usize..first[a as usize + 1] as usize];
    let mut edges = Vec::with_capacity(out.len());
    for a in 0..n as u32 {
        let own = from(a);
        for (i, &(b, t)) in own.iter().enumerate() {
            if i > 0 && own[i - 1].0 == b {
                return None;
            }
            let back = from(b);
            let j = back.binary_search_by_key(&a, |e| e.0).ok()?;
            // Equal keys sit side by side: the reverse must be alone.
            if (j > 0 && back[j - 1].0 == a) || back.get(j + 1).is_some_and(|e| e.0 == a) {
                return None;
            }
            edges.push((b, t, back[j].1));
        }
    }
    Some((first, edges))
}

/// [`convex_mesh`]'s vertices and triangles.
#[cfg(test)]
pub(super) fn as_convex_mesh(points: &[PVec], triangles: &[[u32; 3]]) -> Option<(Vec<PVec>, Vec<[u32; 3]>)> {
    convex_mesh(points, triangles).map(|(vertices, tris, _)| (vertices, tris))
}

/// A mesh that is its own hull: its distinct vertices, its triangles over them and their
/// edges (see [`convex_triangles`]).
#[cfg(test)]
pub(super) fn convex_mesh(points: &[PVec], triangles: &[[u32; 3]]) -> Option<(Vec<PVec>, Vec<[u32; 3]>, ClosedEdges)> {
    let (vertices, remap) = dedup(points);
    let (tris, edges) = convex_triangles(&vertices, &remap, triangles)?;
    Some((vertices, tris, edges))
}

/// The hull of a mesh that is its own hull (most collision meshes are): its triangles over
/// its distinct `vertices` (`remap` taking the mesh's indices to theirs) and their edges,
/// without parry's quickhull, which was most of loading a mesh robot. `None` unless the
/// mesh is closed, one piece of a sphere's topology, faces outwards, bends outwards at
/// every edge (once the few edges that bend in, if any, are flipped: see
/// [`Bends::flip_outward`]) and has no vertex off its triangles; then every vertex is on
/// the hull and the triangles cover it. Otherwise the caller builds the hull.
pub(super) fn convex_triangles(
    vertices: &[PVec],
    remap: &[u32],
    triangles: &[[u32; 3]],
) -> Option<(Vec<[u32; 3]>, ClosedEdges)> {
    let mut tris = Vec::with_capacity(triangles.len());
    for t in triangles {
        let t = t.map(|i| remap.get(i as usize).copied());
        let [Some(a), Some(b), Some(c)] = t else { return None };
        if a == b || b == c || c == a {
            return None;
        }
        tris.push([a, b, c]);
    }
    let (v, f) = (vertices.len(), tris.len());
    // A closed surface of a sphere's topology: V - E + F = 2 with E = 3F / 2.
    if v < 4 || f % 2 != 0 || v + f / 2 != 2 + f {
        return None;
    }
    let size = {
        let (lo, hi) = vertices.iter().fold((vertices[0], vertices[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        (hi - lo).length()
    };
    let bends = Bends { vertices, size };
    match bends.convex(&tris)? {
        Ok(edges) => Some((tris, edges)),
        // A few edges bending in (under an eighth): cut the wrong way across a quad?
        Err(inward) if inward * 8 <= f * 3 / 2 => {
            bends.flip_outward(&mut tris)?;
            let edges = bends.convex(&tris)?.ok()?;
            Some((tris, edges))
        }
        Err(_) => None,
    }
}

/// Which way a closed surface bends at its edges.
struct Bends<'v> {
    vertices: &'v [PVec],
    /// The vertices' extent: the flatness tolerance scales with it.
    size: f64,
}

/// Edge flips a surface may take to become convex, per edge.
const FLIPS_PER_EDGE: usize = 4;

impl Bends<'_> {
    /// Whether, across edge `a -> b` of triangle `t`, the corner `across` of the other
    /// triangle lies outside `t`'s plane: the surface bends inwards there.
    fn bends_in(&self, t: [u32; 3], across: u32) -> bool {
        let [x, y, z] = t.map(|i| self.vertices[i as usize]);
        let n = (y - x).cross(z - x);
        n.dot(self.vertices[across as usize] - x) > 1e-9 * n.length() * self.size
    }

    /// The surface's edges when it is closed, covers every vertex, bends outwards at every
    /// edge and encloses a positive volume; `Err` with the number of edges bending inwards
    /// when that is all that is wrong; `None` otherwise.
    fn convex(&self, tris: &[[u32; 3]]) -> Option<Result<ClosedEdges, usize>> {
        let v = self.vertices.len();
        // Every directed edge once, and its reverse once in another triangle: closed,
        // manifold, consistently wound.
        let (first, edges) = closed_edges(v, tris)?;
        let mut inward = 0;
        for a in 0..v as u32 {
            let own = &edges[first[a as usize] as usize..first[a as usize + 1] as usize];
            // A vertex on no triangle may lie anywhere, inside the hull or out.
            if own.is_empty() {
                return None;
            }
            for &(b, t, t2) in own {
                // The other triangle's third vertex must not lie outside this triangle's plane.
                let other = tris[t2 as usize].into_iter().find(|&i| i != a && i != b)?;
                if a < b && self.bends_in(tris[t as usize], other) {
                    inward += 1;
                }
            }
        }
        if inward > 0 {
            return Some(Err(inward));
        }
        // Outward: the triangles enclose a positive volume (six times it, from the origin).
        let volume: f64 = tris
            .iter()
            .map(|t| {
                let [x, y, z] = t.map(|i| self.vertices[i as usize]);
                x.dot(y.cross(z))
            })
            .sum();
        if volume.is_nan() || volume <= 0.0 {
            return None;
        }
        Some(Ok((first, edges)))
    }

    /// Flips each edge that bends inwards to the other diagonal of the quad its two
    /// triangles make, until none does (Lawson's flips; the edges around a flipped one are
    /// looked at again). Exporters often cut a quad whose corners are not quite in one
    /// plane along the diagonal that bends in: the Panda's collision meshes have 2 to 25
    /// such edges, up to a millimetre deep, every vertex on the hull. `None` when a flip
    /// would make an edge that is already there, or after [`FLIPS_PER_EDGE`] flips per
    /// edge; whatever the flips leave, [`Bends::convex`] decides.
    fn flip_outward(&self, tris: &mut [[u32; 3]]) -> Option<()> {
        // Per vertex, its directed edges out (second vertex, triangle): a handful each.
        let mut out: Vec<Vec<(u32, u32)>> = vec![Vec::with_capacity(8); self.vertices.len()];
        for (i, t) in tris.iter().enumerate() {
            for k in 0..3 {
                out[t[k] as usize].push((t[(k + 1) % 3], i as u32));
            }
        }
        let owner = |out: &[Vec<(u32, u32)>], a: u32, b: u32| out[a as usize].iter().find(|e| e.0 == b).map(|e| e.1);
        let set =
            |out: &mut [Vec<(u32, u32)>], a: u32, b: u32, t: u32| match out[a as usize].iter_mut().find(|e| e.0 == b) {
                Some(e) => e.1 = t,
                None => out[a as usize].push((b, t)),
            };
        let unset = |out: &mut [Vec<(u32, u32)>], a: u32, b: u32| out[a as usize].retain(|e| e.0 != b);
        let mut todo: Vec<(u32, u32)> = (0..out.len() as u32)
            .flat_map(|a| out[a as usize].iter().filter(move |e| a < e.0).map(move |e| (a, e.0)))
            .collect();
        todo.reverse();
        let third = |t: [u32; 3], a: u32, b: u32| t.into_iter().find(|&i| i != a && i != b);
        let mut budget = FLIPS_PER_EDGE * todo.len();
        while let Some((a, b)) = todo.pop() {
            let (Some(t), Some(t2)) = (owner(&out, a, b), owner(&out, b, a)) else { continue };
            let (c, d) = (third(tris[t as usize], a, b)?, third(tris[t2 as usize], a, b)?);
            if !self.bends_in(tris[t as usize], d) {
                continue;
            }
            budget = budget.checked_sub(1)?;
            if c == d || owner(&out, c, d).is_some() || owner(&out, d, c).is_some() {
                return None;
            }
            // `t` is (a, b, c) and `t2` (b, a, d), turned; the quad a-d-b-c is cut along
            // c-d instead, each new triangle wound as the old ones.
            tris[t as usize] = [a, d, c];
            tris[t2 as usize] = [d, b, c];
            unset(&mut out, a, b);
            unset(&mut out, b, a);
            for (x, y, tri) in [(a, d, t), (d, c, t), (c, a, t), (d, b, t2), (b, c, t2), (c, d, t2)] {
                set(&mut out, x, y, tri);
            }
            todo.extend([(a, d), (d, b), (b, c), (c, a)].map(|(x, y)| (x.min(y), x.max(y))));
        }
        Some(())
    }
}

/// The directed edges `a -> b` of the triangles grouped by `a`, each with its triangle:
/// those of `a` are `out[first[a]..first[a + 1]]` (a counting sort).
pub(super) fn outgoing(n: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, Vec<(u32, u32)>) {
    let edges = || {
        triangles
            .iter()
            .enumerate()
            .flat_map(|(i, t)| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(a, b)| (a, b, i as u32)))
    };
    let mut first = vec![0u32; n + 1];
    for (a, _, _) in edges() {
        first[a as usize + 1] += 1;
    }
    for v in 0..n {
        first[v + 1] += first[v];
    }
    let mut fill = first.clone();
    let mut out = vec![(0, 0); first[n] as usize];
    for (a, b, t) in edges() {
        out[fill[a as usize] as usize] = (b, t);
        fill[a as usize] += 1;
    }
    (first, out)
}
