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

mod inner;
mod surface;

pub(crate) use inner::Ball;

#[cfg(test)]
use surface::{as_convex_mesh, closed, convex_mesh};
use surface::{closed_edges, convex_triangles, dedup, ClosedEdges};

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
    /// Balls inside the hull, the largest first (see [`inner`]), found when first asked
    /// for: a hull never near a box (most of a hand's) never needs them, and finding them
    /// for a thousand faces costs about what loading the mesh does.
    inner: OnceLock<Box<[Ball]>>,
}

/// The convex hull of a mesh as a shape, `None` when it is degenerate (flat or empty).
/// STL files repeat a vertex for every triangle that has it (about six times); the hull
/// of the distinct points is the same set of vertices and faces (checked on every mesh of
/// `../shared/robots`) and takes parry a third of the time.
pub(crate) fn mesh_hull(points: &[PVec], triangles: &[[u32; 3]]) -> Option<SharedShape> {
    let (vertices, remap) = dedup(points);
    match convex_triangles(&vertices, &remap, triangles) {
        Some((tris, edges)) => from_triangles(vertices, &tris, edges),
        None => hull_shape(&vertices),
    }
}

/// The convex hull of `points` as a shape, `None` when it is degenerate (flat or empty).
pub(crate) fn hull_shape(points: &[PVec]) -> Option<SharedShape> {
    let (vertices, triangles) = parry3d_f64::transformation::try_convex_hull(points).ok()?;
    let edges = closed_edges(vertices.len(), &triangles)?;
    from_triangles(vertices, &triangles, edges)
}

/// [`convex_triangles`]'s hull as a shape.
#[cfg(test)]
fn convex_mesh_shape(points: &[PVec], triangles: &[[u32; 3]]) -> Option<SharedShape> {
    let (vertices, tris, edges) = convex_mesh(points, triangles)?;
    from_triangles(vertices, &tris, edges)
}

/// A hull from its vertices and outward triangles (closed and convex: the callers have
/// checked, `closed` being the triangles' edges, see [`closed_edges`]) and the edges the
/// support queries climb.
fn from_triangles(vertices: Vec<PVec>, triangles: &[[u32; 3]], closed: ClosedEdges) -> Option<SharedShape> {
    // The indices are in range: `closed_edges` checked them.
    let n = vertices.len();
    if n < 4 || triangles.len() < 4 {
        return None;
    }
    // A vertex's neighbours: the ends of its directed edges (every edge's reverse is
    // there too, so these are all of them, each once), sorted as `closed_edges` left them.
    let (first, edges) = closed;
    let nbrs: Vec<u32> = edges.iter().map(|e| e.0).collect();
    let local_box = bounding_volume::details::local_point_cloud_aabb_ref(&vertices);
    let mut hull = Hull {
        inner: OnceLock::new(),
        local_box,
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

/// A box's corners and outward triangles, as parry's hull gives them (for tests).
#[cfg(test)]
pub(crate) fn box_mesh(half: PVec) -> (Vec<PVec>, Vec<[u32; 3]>) {
    let corners: Vec<PVec> = (0..8)
        .map(|k| {
            PVec::new(
                if k & 1 == 0 { -half.x } else { half.x },
                if k & 2 == 0 { -half.y } else { half.y },
                if k & 4 == 0 { -half.z } else { half.z },
            )
        })
        .collect();
    parry3d_f64::transformation::try_convex_hull(&corners).expect("a box")
}

/// The balls inside a hull of ours (none for any other shape).
pub(crate) fn inner_of(s: &dyn Shape) -> &[Ball] {
    s.as_shape::<Hull>().map_or(&[], Hull::inner)
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

    /// Balls inside the hull, the largest first: a contact of one proves the hull's.
    pub fn inner(&self) -> &[Ball] {
        self.inner.get_or_init(|| inner::inner_balls(&self.points, &self.triangles, &self.local_box).into())
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
