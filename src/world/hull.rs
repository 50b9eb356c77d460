//! A mesh's convex hull whose support function climbs the hull's edges instead of
//! visiting every vertex.
//!
//! parry3d answers a convex polyhedron's support query (the vertex farthest along a
//! direction) by scanning all its vertices; the TX-90's collision hulls have 300–1 200,
//! and GJK asks several times per pair: on mesh robots those scans were 40 % of a
//! planning run. On a convex polyhedron a vertex none of whose neighbours is farther along
//! the direction is the farthest (the edges at a vertex span the cone the whole hull lies
//! in), so a climb from a good start reaches it in a few steps: the start is looked up in
//! a cube map of directions, and the climb ends on the vertex parry's scan would return,
//! ties included, so every query answers exactly as parry's polyhedron. The geometry is the
//! mesh's convex hull, with the vertices parry's quickhull finds (a mesh that is already
//! convex keeps its own triangles); every other query is parry's polyhedron's, built
//! from the same triangles when one is first asked (most hulls never are).

use std::sync::OnceLock;

use parry3d_f64::bounding_volume::{self, Aabb, BoundingSphere};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::math::{Pose as PPose, Real, Vector as PVec};
use parry3d_f64::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d_f64::shape::{
    ConvexPolyhedron, FeatureId, PolygonalFeatureMap, Shape, ShapeType, SharedShape, SubShapeId, SupportMap, TypedShape,
};

/// Cells along each edge of a face of the cube map that gives a climb its start.
const SIDE: usize = 8;
/// Cells of the cube map: six faces of `SIDE` by `SIDE`.
const CELLS: usize = 6 * SIDE * SIDE;

#[derive(Clone)]
pub(crate) struct Hull {
    /// The vertices, in the triangles' indexing.
    points: Vec<PVec>,
    triangles: Vec<[u32; 3]>,
    /// parry's polyhedron of the same vertices and triangles, for the queries other than
    /// support (point projection, ray casts, drawing), built when one first asks: most
    /// hulls are never asked, and building it (faces, edges, their adjacency) was nearly
    /// half of loading a mesh arm.
    poly: OnceLock<ConvexPolyhedron>,
    /// Vertex `v`'s neighbours along the hull's edges: `nbrs[first[v]..first[v + 1]]`.
    first: Vec<u32>,
    nbrs: Vec<u32>,
    /// Per cube-map cell, the vertex farthest along the cell's central direction: a climb
    /// that starts there is a step or two from the top (from a dozen fixed directions it
    /// was three, each reading eight neighbours).
    start: Box<[u32; CELLS]>,
    /// Its own box, parry's point-cloud box of `points` (asked for by the verifier's
    /// box-gap bound at every measure: a scan of every vertex each time).
    local_box: Aabb,
}

/// The convex hull of a mesh as a shape, `None` when it is degenerate (flat or empty).
/// STL files repeat a vertex for every triangle that has it (about six times); the hull
/// of the distinct points is the same set of vertices and faces (checked on every mesh of
/// `../shared/robots`) and takes parry a third of the time.
pub(crate) fn mesh_hull(points: &[PVec], triangles: &[[u32; 3]]) -> Option<SharedShape> {
    let (vertices, remap) = dedup(points);
    match convex_triangles(&vertices, &remap, triangles) {
        Some((tris, edges)) => from_triangles(vertices, &tris, &edges),
        None => hull_shape(&vertices),
    }
}

/// The distinct points in first-seen order, and for each point its index among them.
fn dedup(points: &[PVec]) -> (Vec<PVec>, Vec<u32>) {
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

/// The convex hull of `points` as a shape, `None` when it is degenerate (flat or empty).
pub(crate) fn hull_shape(points: &[PVec]) -> Option<SharedShape> {
    let (vertices, triangles) = parry3d_f64::transformation::try_convex_hull(points).ok()?;
    let edges = closed_edges(vertices.len(), &triangles)?;
    from_triangles(vertices, &triangles, &edges)
}

/// Whether the triangles close a surface (see [`closed_edges`]).
#[cfg(test)]
fn closed(n: usize, triangles: &[[u32; 3]]) -> bool {
    closed_edges(n, triangles).is_some()
}

/// Directed edges grouped by first vertex: `(first, edges)`, see [`closed_edges`].
type ClosedEdges = (Vec<u32>, Vec<(u32, u32, u32)>);

/// When the triangles close a surface (no corner repeated, every directed edge once, and
/// its reverse once in another triangle): their directed edges grouped by first vertex,
/// those of `a` being `edges[first[a]..first[a + 1]]` sorted by second vertex, each as
/// (second vertex, its triangle, the triangle of its reverse). `None` otherwise.
fn closed_edges(n: usize, triangles: &[[u32; 3]]) -> Option<ClosedEdges> {
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

/// [`convex_triangles`]'s hull as a shape.
#[cfg(test)]
fn convex_mesh_shape(points: &[PVec], triangles: &[[u32; 3]]) -> Option<SharedShape> {
    let (vertices, tris, edges) = convex_mesh(points, triangles)?;
    from_triangles(vertices, &tris, &edges)
}

/// [`convex_mesh`]'s vertices and triangles.
#[cfg(test)]
fn as_convex_mesh(points: &[PVec], triangles: &[[u32; 3]]) -> Option<(Vec<PVec>, Vec<[u32; 3]>)> {
    convex_mesh(points, triangles).map(|(vertices, tris, _)| (vertices, tris))
}

/// A mesh that is its own hull: its distinct vertices, its triangles over them and their
/// edges (see [`convex_triangles`]).
#[cfg(test)]
fn convex_mesh(points: &[PVec], triangles: &[[u32; 3]]) -> Option<(Vec<PVec>, Vec<[u32; 3]>, ClosedEdges)> {
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
fn convex_triangles(vertices: &[PVec], remap: &[u32], triangles: &[[u32; 3]]) -> Option<(Vec<[u32; 3]>, ClosedEdges)> {
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
fn outgoing(n: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, Vec<(u32, u32)>) {
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

/// A hull from its vertices and outward triangles (closed and convex: the callers have
/// checked, `closed` being the triangles' edges, see [`closed_edges`]) and the edges the
/// support queries climb.
fn from_triangles(vertices: Vec<PVec>, triangles: &[[u32; 3]], closed: &ClosedEdges) -> Option<SharedShape> {
    // The indices are in range: `closed_edges` checked them.
    let n = vertices.len();
    if n < 4 || triangles.len() < 4 {
        return None;
    }
    // A vertex's neighbours: the ends of its directed edges (every edge's reverse is
    // there too, so these are all of them, each once), sorted as `closed_edges` left them.
    let (first, edges) = closed;
    let first = first.clone();
    let nbrs: Vec<u32> = edges.iter().map(|e| e.0).collect();
    let mut hull = Hull {
        local_box: bounding_volume::details::local_point_cloud_aabb_ref(&vertices),
        points: vertices,
        triangles: triangles.to_vec(),
        poly: OnceLock::new(),
        first,
        nbrs,
        start: Box::new([0; CELLS]),
    };
    // Cell by cell in an order where each is next to the last, each climbed from the
    // last's vertex: a few steps per cell, where a scan of every vertex would cost
    // `CELLS` times the vertices.
    let mut v = 0;
    for face in 0..6 {
        for i in 0..SIDE {
            for k in 0..SIDE {
                let j = if i % 2 == 0 { k } else { SIDE - 1 - k };
                let c = face * SIDE * SIDE + i * SIDE + j;
                v = hull.climb(v, cell_centre(c));
                hull.start[c] = v as u32;
            }
        }
    }
    Some(SharedShape::new(hull))
}

/// The cube-map cell of a direction: the face of its largest component (ties to the
/// earlier axis), then where the other two fall on that face. A zero or NaN direction
/// lands in some cell (the cast saturates); any start is correct, only slower.
#[inline]
fn cell(dir: PVec) -> usize {
    let a = dir.abs();
    let (axis, major, u, v) = if a.x >= a.y && a.x >= a.z {
        (0, dir.x, dir.y, dir.z)
    } else if a.y >= a.z {
        (1, dir.y, dir.z, dir.x)
    } else {
        (2, dir.z, dir.x, dir.y)
    };
    let face = 2 * axis + usize::from(major < 0.0);
    let scale = 0.5 * SIDE as f64 / major.abs();
    let at = |c: f64| (((c + major.abs()) * scale) as usize).min(SIDE - 1);
    face * SIDE * SIDE + at(u) * SIDE + at(v)
}

/// The direction through the middle of cube-map cell `c` (inverse of [`cell`]).
fn cell_centre(c: usize) -> PVec {
    let (face, i, j) = (c / (SIDE * SIDE), c / SIDE % SIDE, c % SIDE);
    let at = |k: usize| (k as f64 + 0.5) / SIDE as f64 * 2.0 - 1.0;
    let major = if face % 2 == 0 { 1.0 } else { -1.0 };
    let (u, v) = (at(i), at(j));
    match face / 2 {
        0 => PVec::new(major, u, v),
        1 => PVec::new(v, major, u),
        _ => PVec::new(u, v, major),
    }
}

/// Whether a shape is a hull (ours, or parry's own polyhedron), without building ours.
pub(crate) fn is_hull(s: &dyn Shape) -> bool {
    s.as_convex_polyhedron().is_some() || s.as_shape::<Hull>().is_some()
}

/// The polyhedron of a hull shape (ours, or parry's own).
pub(crate) fn polyhedron(s: &dyn Shape) -> Option<&ConvexPolyhedron> {
    s.as_convex_polyhedron().or_else(|| s.as_shape::<Hull>().map(Hull::poly))
}

/// The first farthest point along `dir`, by scanning every point (parry's own rule).
#[cfg(test)]
fn scan(points: &[PVec], dir: PVec) -> usize {
    let mut best = 0;
    let mut best_dot = points[0].dot(dir);
    for (i, p) in points.iter().enumerate().skip(1) {
        let d = p.dot(dir);
        if d > best_dot {
            (best, best_dot) = (i, d);
        }
    }
    best
}

impl Hull {
    /// The vertices.
    #[cfg(test)]
    pub fn points(&self) -> &[PVec] {
        &self.points
    }

    /// parry's polyhedron of the hull (built on first use). Its vertices are the hull's, in
    /// the same order; should parry refuse the triangles, its own hull of the vertices.
    pub fn poly(&self) -> &ConvexPolyhedron {
        self.poly.get_or_init(|| {
            // parry refuses only triangles with a repeated corner or an edge not shared by
            // exactly two of them, which every hull built here was checked against.
            ConvexPolyhedron::from_convex_mesh(self.points.clone(), &self.triangles)
                .or_else(|| ConvexPolyhedron::from_convex_hull(&self.points))
                .expect("a closed hull's triangles (checked when it was built)")
        })
    }

    /// The index of a vertex farthest along `dir`.
    #[inline]
    pub fn support_index(&self, dir: PVec) -> usize {
        self.climb(self.start[cell(dir)] as usize, dir)
    }

    /// From vertex `v`, along the edges to a vertex farthest along `dir`.
    #[inline]
    fn climb(&self, mut v: usize, dir: PVec) -> usize {
        let pts = &self.points;
        let mut best = pts[v].dot(dir);
        loop {
            let level = best;
            let mut next = v;
            let mut tie = false;
            for &u in &self.nbrs[self.first[v] as usize..self.first[v + 1] as usize] {
                let d = pts[u as usize].dot(dir);
                tie |= d == level;
                // Selects, not a branch: which neighbour is farther is a coin toss.
                let farther = d > best;
                next = if farther { u as usize } else { next };
                best = if farther { d } else { best };
            }
            if next == v {
                // Only a neighbour as far as `v` can lead off a plateau.
                if !tie {
                    return v;
                }
                match self.off_plateau(v, level, dir) {
                    Plateau::Beyond(u) => (next, best) = (u, pts[u].dot(dir)),
                    Plateau::Top(u) => return u,
                }
            }
            v = next;
        }
    }

    /// Leaves the plateau of vertices exactly as far along `dir` as `v` (`level`) around
    /// it: a vertex farther than it next to the plateau, if there is one, else the
    /// plateau's least index. A vertex inside a flat face (a mesh can have them) has only
    /// neighbours on that face: seen from the face's far side they all tie, and the rim of
    /// the face is where the climb goes on. On top, the least index is the vertex parry's
    /// scan returns (the first farthest), so that GJK and EPA take the same path with
    /// either: which of two equally far vertices they are given moves an EPA depth by
    /// micrometres.
    #[cold]
    fn off_plateau(&self, v: usize, level: f64, dir: PVec) -> Plateau {
        let pts = &self.points;
        let nbrs = |x: usize| self.nbrs[self.first[x] as usize..self.first[x + 1] as usize].iter().map(|&u| u as usize);
        let mut seen = vec![v];
        let mut i = 0;
        while let Some(&x) = seen.get(i) {
            i += 1;
            for u in nbrs(x) {
                let d = pts[u].dot(dir);
                if d > level {
                    return Plateau::Beyond(u);
                }
                if d == level && !seen.contains(&u) {
                    seen.push(u);
                }
            }
        }
        Plateau::Top(seen.into_iter().min().unwrap_or(v))
    }
}

/// Where a climb goes from a plateau: see [`Hull::off_plateau`].
#[derive(Debug, PartialEq)]
enum Plateau {
    Beyond(usize),
    Top(usize),
}

impl SupportMap for Hull {
    #[inline]
    fn local_support_point(&self, dir: PVec) -> PVec {
        self.points[self.support_index(dir)]
    }
}

impl PointQuery for Hull {
    #[inline]
    fn project_local_point(&self, pt: PVec, solid: bool) -> PointProjection {
        self.poly().project_local_point(pt, solid)
    }
    #[inline]
    fn project_local_point_and_get_feature(&self, pt: PVec) -> (PointProjection, FeatureId) {
        self.poly().project_local_point_and_get_feature(pt)
    }
}

impl RayCast for Hull {
    fn cast_local_ray_and_get_normal(&self, ray: &Ray, max_toi: Real, solid: bool) -> Option<RayIntersection> {
        self.poly().cast_local_ray_and_get_normal(ray, max_toi, solid)
    }
}

impl Shape for Hull {
    fn compute_local_aabb(&self) -> Aabb {
        self.local_box
    }
    fn compute_local_bounding_sphere(&self) -> BoundingSphere {
        bounding_volume::details::point_cloud_bounding_sphere(&self.points)
    }
    fn compute_aabb(&self, position: &PPose) -> Aabb {
        bounding_volume::details::point_cloud_aabb_ref(position, &self.points)
    }
    fn clone_dyn(&self) -> Box<dyn Shape> {
        Box::new(self.clone())
    }
    fn scale_dyn(&self, scale: PVec, num_subdivisions: u32) -> Option<Box<dyn Shape>> {
        self.poly().scale_dyn(scale, num_subdivisions)
    }
    fn mass_properties(&self, density: Real) -> MassProperties {
        self.poly().mass_properties(density)
    }
    fn shape_type(&self) -> ShapeType {
        ShapeType::Custom
    }
    fn as_typed_shape(&self) -> TypedShape<'_> {
        TypedShape::Custom(self)
    }
    fn ccd_thickness(&self) -> Real {
        self.poly().ccd_thickness()
    }
    fn ccd_angular_thickness(&self) -> Real {
        self.poly().ccd_angular_thickness()
    }
    fn is_convex(&self) -> bool {
        true
    }
    fn as_support_map(&self) -> Option<&dyn SupportMap> {
        Some(self as &dyn SupportMap)
    }
    fn as_polygonal_feature_map(&self) -> Option<(&dyn PolygonalFeatureMap, Real)> {
        self.poly().as_polygonal_feature_map()
    }
    fn feature_normal_at_point(&self, subshape: SubShapeId, feature: FeatureId, point: PVec) -> Option<PVec> {
        self.poly().feature_normal_at_point(subshape, feature, point)
    }
}

#[cfg(test)]
#[path = "hull_tests.rs"]
mod tests;
