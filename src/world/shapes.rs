//! Geometry -> parry3d shapes: primitives, and mesh files found on the package path.
//!
//! Cylinders and capsules are along z in URDF and in scenarios, along y in parry;
//! the returned local pose turns one into the other. Meshes become convex hulls
//! ([`MeshMode::ConvexHull`], the default) or triangle meshes.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Pose as PPose, Vector as PVec};
use parry3d_f64::shape::{Cuboid, Shape, SharedShape};

use crate::diag::Loader;

/// Penetration depth (metres) below which two shapes are not in collision. The same
/// everywhere: robot vs scene, self-collision, carried object.
pub const CONTACT_TOLERANCE: f64 = 1e-3;

/// How mesh files become collision shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeshMode {
    /// The convex hull of the vertices: fast, and conservative (never misses a contact).
    #[default]
    ConvexHull,
    /// The triangles as given: exact surface, slower.
    TriMesh,
}

/// A shape placed in some frame (a link's, a body's).
#[derive(Clone)]
pub(crate) struct Placed {
    pub shape: SharedShape,
    pub pose: PPose,
    /// The shape eroded by the contact tolerance, for primitives: two shapes overlap
    /// deeper than the tolerance exactly when the eroded one meets the other.
    pub eroded: Option<SharedShape>,
    /// Bounding boxes of the shape and of its eroded form, for the pre-test.
    pub obb: Obb,
    pub eroded_obb: Option<Obb>,
    /// How its world box is computed, found once: asking the shape its type at every
    /// check (a dynamic downcast per question) was a few per cent of a sphere robot's.
    pub boxed: Boxed,
    /// The eroded shape's radius when it is a ball (a spherized link's).
    pub eroded_ball: Option<f64>,
}

#[derive(Clone, Copy)]
pub(crate) enum Boxed {
    /// A mesh hull: its local box, turned (see `check::moving_aabb`).
    Hull,
    /// A ball of this radius: the centre give or take it, as parry's own.
    Ball(f64),
    /// Anything else: [`aabb_of`].
    Other,
}

impl Placed {
    /// A hull's balls inside it (see `hull::inner`; none for any other shape): one that
    /// meets a box deeper than the contact tolerance proves the shape does.
    #[inline]
    pub fn inner(&self) -> &[super::hull::Ball] {
        match self.boxed {
            Boxed::Hull => super::hull::inner_of(&*self.shape.0),
            _ => &[],
        }
    }

    pub fn new(shape: SharedShape, pose: PPose) -> Placed {
        let eroded = erode(&shape, CONTACT_TOLERANCE);
        let obb = Obb::of(&*shape.0);
        let eroded_obb = eroded.as_ref().map(|e| Obb::of(&*e.0));
        let boxed = match (super::hull::is_hull(&*shape.0).then_some(()), shape.as_ball()) {
            (Some(_), _) => Boxed::Hull,
            (None, Some(b)) => Boxed::Ball(b.radius),
            (None, None) => Boxed::Other,
        };
        let eroded_ball = eroded.as_ref().and_then(|e| e.as_ball()).map(|b| b.radius);
        Placed { shape, pose, eroded, obb, eroded_obb, boxed, eroded_ball }
    }
}

/// The world-aligned box of a placed shape. parry bounds a cylinder with six support
/// queries; the closed form (an axis `a`: `h |a_i| + r sqrt(1 - a_i^2)` per axis) costs
/// a tenth, and cylinders (cans, hands, links) are in almost every check.
#[inline]
pub(crate) fn aabb_of(s: &dyn Shape, pose: &PPose) -> Aabb {
    if let Some(c) = s.as_cylinder() {
        // parry's cylinders run along their local y.
        let a = pose.rotation * PVec::Y;
        let e = |x: f64| c.half_height * x.abs() + c.radius * (1.0 - x * x).max(0.0).sqrt();
        let half = PVec::new(e(a.x), e(a.y), e(a.z));
        return Aabb::new(pose.translation - half, pose.translation + half);
    }
    s.compute_aabb(pose)
}

/// A shape's local bounding box as a cuboid about its centre. Two shapes whose boxes
/// are apart (a separating-axis test, a tenth of a GJK query) cannot touch: this rules
/// out most pairs whose world-aligned boxes overlap before GJK runs.
#[derive(Clone, Debug)]
pub(crate) struct Obb {
    pub cuboid: Cuboid,
    pub centre: PPose,
    /// The shape is this cuboid: the pre-test would be the test itself.
    pub exact: bool,
}

impl Obb {
    pub fn of(s: &dyn Shape) -> Obb {
        Obb { exact: s.as_cuboid().is_some(), ..Obb::of_aabb(&s.compute_local_aabb()) }
    }

    /// The box `aabb`, as a cuboid about its centre.
    pub fn of_aabb(aabb: &Aabb) -> Obb {
        Obb { cuboid: Cuboid::new(aabb.half_extents()), centre: PPose::from_translation(aabb.center()), exact: false }
    }

    /// The cuboid's pose when its frame stands at `pose`: `pose * centre` without the
    /// quaternion product, the centre being a shift only (both constructors make it so).
    #[inline]
    pub fn placed(&self, pose: &PPose) -> PPose {
        let mut at = *pose;
        at.translation = pose.translation + pose.rotation * self.centre.translation;
        at
    }

    /// Its world box when its frame stands at `pose`: one rotation matrix turns both the
    /// centre's shift and the extents (parry's box of the placed cuboid turns the shift by
    /// the quaternion, then builds the matrix for the extents; every check builds a box
    /// per body this way).
    #[inline]
    pub fn world_aabb(&self, pose: &PPose) -> Aabb {
        let m = parry3d_f64::math::Matrix::from_quat(pose.rotation);
        let centre = pose.translation + m * self.centre.translation;
        let extents = m.abs() * self.cuboid.half_extents;
        Aabb::new(centre - extents, centre + extents)
    }

    /// False only when the boxes, placed at `p1` and `p2`, are apart.
    #[inline]
    pub fn may_touch(&self, p1: &PPose, other: &Obb, p2: &PPose) -> bool {
        if self.exact && other.exact {
            return true;
        }
        // The face normals of both boxes only: the edge-edge axes cost more than they
        // rule out, and leaving them out keeps the test conservative.
        let pos12 = self.placed(p1).inv_mul(&other.placed(p2));
        !faces_separate(self.cuboid.half_extents, other.cuboid.half_extents, &pos12)
    }

    /// How far apart the boxes are along the best of their face normals: never more than
    /// the distance between anything inside them (negative when no face separates them).
    #[inline]
    pub fn gap(&self, p1: &PPose, other: &Obb, p2: &PPose) -> f64 {
        let pos12 = self.placed(p1).inv_mul(&other.placed(p2));
        boxes_face_gap(self.cuboid.half_extents, other.cuboid.half_extents, &pos12)
    }
}

/// Within this much (metres) of a ball's radius, a ball against a box is left to parry.
pub(crate) const BALL_MARGIN: f64 = 1e-9;

/// A moving ball (centre `c`, eroded radius `r`) against a fixed box (half extents `he`
/// at `p2`), decided by the distance from the centre to the box: what parry's
/// intersection test decides, but without its dispatch and the boxes' pre-test (most of
/// a spherized arm's narrow phase). `None` where the distance is within [`BALL_MARGIN`]
/// of the radius: there rounding could part the two, and parry's own test decides.
#[inline]
pub(crate) fn ball_meets_box(c: PVec, r: f64, p2: &PPose, he: PVec) -> Option<bool> {
    let local = p2.rotation.inverse() * (c - p2.translation);
    let d2 = (local.abs() - he).max(PVec::ZERO).length_squared();
    if d2 > (r + BALL_MARGIN) * (r + BALL_MARGIN) {
        Some(false)
    } else if r > BALL_MARGIN && d2 < (r - BALL_MARGIN) * (r - BALL_MARGIN) {
        Some(true)
    } else {
        None
    }
}

/// Whether a face normal of either box separates them: box `a` (half extents) at the
/// origin, box `b` at `pos12`. The classic six face axes of the separating-axis test
/// (Gottschalk's), written out: parry's own (`cuboid_cuboid_find_local_separating_normal_oneway`,
/// twice) measures each axis through support points and was a quarter of a check.
#[inline]
pub(crate) fn faces_separate(a: PVec, b: PVec, pos12: &PPose) -> bool {
    TwoBoxes::new(a, b, pos12, 0.0).faces_apart()
}

/// Slack added to the turned axes' absolute cosines in [`boxes_intersect`]: where an
/// edge of one box is parallel to an edge of the other their cross product vanishes, and
/// rounding alone must not make it a separating axis. It widens every reach by about
/// `1e-10` of the boxes' sizes: a hair towards "intersecting".
const PARALLEL_SLACK: f64 = 1e-10;

/// Whether boxes `a` and `b` (half extents) intersect, `a` at the origin and `b` at
/// `pos12`: the separating-axis test over all fifteen axes (three face normals of each,
/// nine edge-edge crosses; Gottschalk's, as Ericson writes it). Exact for boxes, as
/// parry's `intersection_test` of two cuboids, which measures each axis through support
/// points at several times the cost; robots of boxes against scenes of boxes ask it most.
#[inline]
pub(crate) fn boxes_intersect(a: PVec, b: PVec, pos12: &PPose) -> bool {
    let boxes = TwoBoxes::new(a, b, pos12, PARALLEL_SLACK);
    !boxes.faces_apart() && !boxes.edges_apart()
}

/// A lower bound on the distance between boxes `a` and `b` (half extents), `a` at the
/// origin and `b` at `pos12`: their largest gap along the six face normals (a gap along
/// any unit axis is no more than the distance); 0 or less when no face normal separates
/// them.
#[inline]
pub(crate) fn boxes_face_gap(a: PVec, b: PVec, pos12: &PPose) -> f64 {
    TwoBoxes::new(a, b, pos12, 0.0).face_gaps().fold(f64::NEG_INFINITY, f64::max)
}

/// Two boxes in the first one's frame, as the separating-axis tests read them.
struct TwoBoxes {
    a: [f64; 3],
    b: [f64; 3],
    /// b's centre.
    t: [f64; 3],
    /// `r[i][j]`: a's axis i against b's axis j.
    r: [[f64; 3]; 3],
    /// `|r[i][j]|` plus a slack.
    abs: [[f64; 3]; 3],
}

impl TwoBoxes {
    #[inline]
    fn new(a: PVec, b: PVec, pos12: &PPose, slack: f64) -> TwoBoxes {
        // b's axes are m's columns in a's frame.
        let m = parry3d_f64::math::Matrix::from_quat(pos12.rotation);
        let r = [
            [m.x_axis.x, m.y_axis.x, m.z_axis.x],
            [m.x_axis.y, m.y_axis.y, m.z_axis.y],
            [m.x_axis.z, m.y_axis.z, m.z_axis.z],
        ];
        let abs = r.map(|row| row.map(|x| x.abs() + slack));
        TwoBoxes { a: a.to_array(), b: b.to_array(), t: pos12.translation.to_array(), r, abs }
    }

    /// The gaps between the boxes along the six face normals, a's then b's (positive
    /// where that normal separates them), one at a time as asked.
    #[inline]
    fn face_gaps(&self) -> impl Iterator<Item = f64> + '_ {
        let TwoBoxes { a, b, t, r, abs } = self;
        // Along a's axis i, b reaches sum_j b_j |r_ij| from its centre.
        let along_a = (0..3).map(move |i| t[i].abs() - (a[i] + b[0] * abs[i][0] + b[1] * abs[i][1] + b[2] * abs[i][2]));
        // Along b's axis j, a reaches sum_i a_i |r_ij|.
        let along_b = (0..3).map(move |j| {
            let along = t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j];
            along.abs() - (b[j] + a[0] * abs[0][j] + a[1] * abs[1][j] + a[2] * abs[2][j])
        });
        along_a.chain(along_b)
    }

    /// A face normal of either box separates them.
    #[inline]
    fn faces_apart(&self) -> bool {
        self.face_gaps().any(|gap| gap > 0.0)
    }

    /// A cross of an edge of each separates them.
    #[inline]
    fn edges_apart(&self) -> bool {
        let TwoBoxes { a, b, t, r, abs } = self;
        (0..3).any(|i| {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            (0..3).any(|j| {
                let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
                let reach_a = a[i1] * abs[i2][j] + a[i2] * abs[i1][j];
                let reach_b = b[j1] * abs[i][j2] + b[j2] * abs[i][j1];
                (t[i2] * r[i1][j] - t[i1] * r[i2][j]).abs() > reach_a + reach_b
            })
        })
    }
}

/// A primitive shrunk by `t` on every side (never below half its size); `None` for meshes.
fn erode(s: &SharedShape, t: f64) -> Option<SharedShape> {
    let shrink = |x: f64| (x - t).max(x / 2.0);
    if let Some(c) = s.as_cuboid() {
        let h = c.half_extents;
        return Some(SharedShape::cuboid(shrink(h.x), shrink(h.y), shrink(h.z)));
    }
    if let Some(b) = s.as_ball() {
        return Some(SharedShape::ball(shrink(b.radius)));
    }
    if let Some(c) = s.as_cylinder() {
        return Some(SharedShape::cylinder(shrink(c.half_height), shrink(c.radius)));
    }
    if let Some(c) = s.as_capsule() {
        return Some(SharedShape::capsule(c.segment.a, c.segment.b, shrink(c.radius)));
    }
    None
}

/// A primitive or mesh, before placement.
pub(crate) enum Geometry<'a> {
    Box(Vector3<f64>),
    Cylinder { radius: f64, length: f64 },
    Capsule { radius: f64, length: f64 },
    Sphere(f64),
    Mesh { path: &'a Path, scale: Vector3<f64> },
}

pub(crate) fn to_ppose(iso: &Isometry3<f64>) -> PPose {
    PPose::from(*iso)
}

/// A shape's world pose, `link * shape`. Many shapes stand unturned on their link (a
/// spherized arm's balls, meshes drawn in their link's frame): their rotation is then the
/// link's own, and the quaternion product (by one, the same values) is left out.
#[inline]
pub(crate) fn place(link: &PPose, shape: &PPose, unturned: bool) -> PPose {
    if unturned {
        let mut pose = *link;
        pose.translation = link.translation + link.rotation * shape.translation;
        pose
    } else {
        *link * *shape
    }
}

/// Loads mesh files once per build.
pub(crate) struct MeshCache<'l> {
    pub loader: &'l dyn Loader,
    pub mode: MeshMode,
    cache: HashMap<(PathBuf, [u64; 3]), SharedShape>,
}

impl<'l> MeshCache<'l> {
    pub fn new(loader: &'l dyn Loader, mode: MeshMode) -> MeshCache<'l> {
        MeshCache { loader, mode, cache: HashMap::new() }
    }

    /// A shape and its pose in the frame `pose_frame_geom` is given in.
    pub fn make(&mut self, g: &Geometry<'_>, pose_frame_geom: &Isometry3<f64>) -> Result<Placed, String> {
        // parry's round shapes are along y; ours along z.
        let y_to_z = Isometry3::from_parts(
            nalgebra::Translation3::identity(),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2),
        );
        let (shape, local) = match g {
            Geometry::Box(s) => (SharedShape::cuboid(s.x / 2.0, s.y / 2.0, s.z / 2.0), Isometry3::identity()),
            Geometry::Cylinder { radius, length } => (SharedShape::cylinder(length / 2.0, *radius), y_to_z),
            Geometry::Capsule { radius, length } => {
                (SharedShape::capsule_z(length / 2.0, *radius), Isometry3::identity())
            }
            Geometry::Sphere(r) => (SharedShape::ball(*r), Isometry3::identity()),
            Geometry::Mesh { path, scale } => (self.mesh(path, scale)?, Isometry3::identity()),
        };
        Ok(Placed::new(shape, to_ppose(&(pose_frame_geom * local))))
    }

    fn mesh(&mut self, path: &Path, scale: &Vector3<f64>) -> Result<SharedShape, String> {
        let key = (path.to_path_buf(), [scale.x.to_bits(), scale.y.to_bits(), scale.z.to_bits()]);
        if let Some(s) = self.cache.get(&key) {
            return Ok(s.clone());
        }
        let mut bytes = self.loader.read_bytes(path).map_err(|e| e.to_string())?;
        let is_dae = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("dae"));
        let mut unit = 1.0;
        if is_dae {
            if let Some((u, fixed)) = collada_unit(&bytes)? {
                (unit, bytes) = (u, fixed);
            }
        }
        let loader = self.loader;
        // Material files of OBJ meshes are optional for collision: a missing one reads as empty.
        let reader = |p: &Path| Ok(loader.read_bytes(p).unwrap_or_default());
        let scene = mesh_loader::Loader::default()
            .merge_meshes(true)
            .load_from_slice_with_reader(&bytes, path, reader)
            .map_err(|e| e.to_string())?;
        let mut vertices: Vec<PVec> = Vec::new();
        let mut indices: Vec<[u32; 3]> = Vec::new();
        for m in &scene.meshes {
            let base = vertices.len() as u32;
            vertices.extend(
                m.vertices
                    .iter()
                    .map(|v| PVec::new(v[0] as f64, v[1] as f64, v[2] as f64) * unit)
                    .map(|v| PVec::new(v.x * scale.x, v.y * scale.y, v.z * scale.z)),
            );
            // A face naming a missing vertex would make parry index out of bounds.
            let count = m.vertices.len() as u64;
            if m.faces.iter().flatten().any(|&i| u64::from(i) >= count) {
                return Err("a face refers to a vertex the mesh does not have".into());
            }
            indices.extend(m.faces.iter().map(|f| f.map(|i| i.wrapping_add(base))));
        }
        if vertices.len() > u32::MAX as usize {
            return Err("the mesh has too many vertices".into());
        }
        if vertices.len() < 4 || vertices.iter().any(|v| !v.is_finite()) {
            return Err("the mesh has fewer than 4 vertices or non-finite coordinates".into());
        }
        // Triangles of no area (every vertex on one line or point) bound nothing, in
        // either mode; a flat sheet is a thin wall in both.
        let area: f64 = indices
            .iter()
            .filter_map(|f| {
                let [a, b, c] = f.map(|i| vertices.get(i as usize).copied());
                Some((b? - a?).cross(c? - a?).length() / 2.0)
            })
            .sum();
        if !indices.is_empty() && area <= 1e-12 {
            return Err("its triangles have no area (every vertex on one line)".into());
        }
        let mode = self.mode;
        let make = move || match mode {
            MeshMode::ConvexHull => super::hull::mesh_hull(&vertices, &indices)
                .ok_or_else(|| "its convex hull is degenerate (flat or empty)".to_string()),
            MeshMode::TriMesh => {
                if indices.is_empty() {
                    return Err("the mesh has no triangles".into());
                }
                SharedShape::trimesh(vertices, indices).map_err(|e| format!("{e:?}"))
            }
        };
        // parry's hull still has internal assertions that some near-degenerate point
        // clouds trip; a user's mesh must give an error, not a crash.
        let shape = std::panic::catch_unwind(make)
            .map_err(|_| "parry could not build a shape from it (degenerate geometry)".to_string())??;
        self.cache.insert(key, shape.clone());
        Ok(shape)
    }
}

/// A COLLADA file's `<unit meter="..">` when it is not 1, and the file with it set to 1.
///
/// mesh-loader scales the vertices by the unit but not the nodes' translations (checked
/// by a test), so a millimetre file with offset nodes would land 1000× too far. Loading
/// it in its own units and scaling the result is exact: a uniform scale commutes with
/// the nodes' rigid transforms. The first `<unit>` is the document's: `<asset>` must be
/// the first child of `<COLLADA>`.
fn collada_unit(bytes: &[u8]) -> Result<Option<(f64, Vec<u8>)>, String> {
    let Ok(text) = std::str::from_utf8(bytes) else { return Ok(None) };
    let Some(start) = text.find("<unit") else { return Ok(None) };
    let tag_end = text[start..].find('>').map_or(text.len(), |e| start + e);
    let tag = &text[start..tag_end];
    let Some(attr) = tag.find("meter=") else { return Ok(None) };
    let value_start = start + attr + "meter=".len() + 1;
    let Some(quote) = text[value_start - 1..].chars().next().filter(|c| *c == '"' || *c == '\'') else {
        return Ok(None);
    };
    let Some(len) = text[value_start..tag_end].find(quote) else { return Ok(None) };
    let raw = &text[value_start..value_start + len];
    let unit: f64 = raw.trim().parse().map_err(|_| format!("its COLLADA unit meter=\"{raw}\" is not a number"))?;
    if !(unit > 0.0 && unit <= MAX_UNIT) {
        return Err(format!("its COLLADA unit meter=\"{raw}\" is not a positive length up to {MAX_UNIT} m"));
    }
    if unit == 1.0 {
        return Ok(None);
    }
    let fixed = format!("{}1{}", &text[..value_start], &text[value_start + len..]);
    Ok(Some((unit, fixed.into_bytes())))
}

/// Largest COLLADA unit accepted (metres): anything bigger is a broken file.
const MAX_UNIT: f64 = 1e3;

/// Resolves a URDF mesh URI: `package://NAME/rest`, `file:///abs`, or a path relative to
/// the URDF's folder. Returns the candidates tried when none exists (possibly none).
pub(crate) fn resolve_uri(
    uri: &str,
    urdf_dir: &Path,
    package_path: &[PathBuf],
    loader: &dyn Loader,
) -> Result<PathBuf, Vec<PathBuf>> {
    if let Some(rest) = uri.strip_prefix("package://") {
        let (pkg, sub) = rest.split_once('/').unwrap_or((rest, ""));
        let mut tried = Vec::new();
        // Walk the ancestors of the absolute folder: a relative one (scenario given by a
        // relative path) would stop the walk at the current directory.
        let start = if urdf_dir.as_os_str().is_empty() { Path::new(".") } else { urdf_dir };
        let urdf_dir = std::path::absolute(start).unwrap_or_else(|_| urdf_dir.to_path_buf());
        for dir in urdf_dir.ancestors().chain(package_path.iter().map(PathBuf::as_path)) {
            if dir.as_os_str().is_empty() {
                continue;
            }
            let mut cands = vec![dir.join(pkg).join(sub)];
            if dir.file_name().is_some_and(|n| n == pkg) {
                cands.insert(0, dir.join(sub));
            }
            for c in cands {
                if loader.exists(&c) {
                    return Ok(c);
                }
                if !tried.contains(&c) {
                    tried.push(c);
                }
            }
        }
        return Err(tried);
    }
    let p = match uri.strip_prefix("file://") {
        Some(abs) => PathBuf::from(abs),
        None => urdf_dir.join(uri),
    };
    if loader.exists(&p) {
        Ok(p)
    } else {
        Err(vec![p])
    }
}

/// The candidates of [`resolve_uri`] for an error message.
pub(crate) fn describe_tried(tried: &[PathBuf]) -> String {
    if tried.is_empty() {
        return "no folder to look in: the URDF's folder is unknown and no package path is given".into();
    }
    let list: Vec<String> = tried.iter().map(|p| p.display().to_string()).collect();
    format!("looked at {}", list.join(", "))
}

#[cfg(test)]
#[path = "shapes_tests.rs"]
mod tests;
