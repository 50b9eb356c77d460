//! Geometry -> parry3d shapes: primitives, and mesh files found on the package path.
//!
//! Cylinders and capsules are along z in URDF and in scenarios, along y in parry;
//! the returned local pose turns one into the other. Meshes become convex hulls
//! ([`MeshMode::ConvexHull`], the default) or triangle meshes.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use parry3d_f64::math::{Pose as PPose, Vector as PVec};
use parry3d_f64::shape::SharedShape;

use crate::diag::Loader;

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
}

impl Placed {
    pub fn new(shape: SharedShape, pose: PPose) -> Placed {
        let eroded = erode(&shape, super::check::CONTACT_TOLERANCE);
        Placed { shape, pose, eroded }
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
        let bytes = self.loader.read_bytes(path).map_err(|e| e.to_string())?;
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
                    .map(|v| PVec::new(v[0] as f64 * scale.x, v[1] as f64 * scale.y, v[2] as f64 * scale.z)),
            );
            indices.extend(m.faces.iter().map(|f| [f[0] + base, f[1] + base, f[2] + base]));
        }
        if vertices.len() < 4 || vertices.iter().any(|v| !v.is_finite()) {
            return Err("the mesh has fewer than 4 vertices or non-finite coordinates".into());
        }
        let shape = match self.mode {
            MeshMode::ConvexHull => SharedShape::convex_hull(&vertices)
                .ok_or_else(|| "its convex hull is degenerate (flat or empty)".to_string())?,
            MeshMode::TriMesh => {
                if indices.is_empty() {
                    return Err("the mesh has no triangles".into());
                }
                SharedShape::trimesh(vertices, indices).map_err(|e| format!("{e:?}"))?
            }
        };
        self.cache.insert(key, shape.clone());
        Ok(shape)
    }
}

/// Resolves a URDF mesh URI: `package://NAME/rest`, `file:///abs`, or a path relative to
/// the URDF's folder. Returns the candidates tried when none exists.
pub(crate) fn resolve_uri(
    uri: &str,
    urdf_dir: &Path,
    package_path: &[PathBuf],
    loader: &dyn Loader,
) -> Result<PathBuf, Vec<PathBuf>> {
    if let Some(rest) = uri.strip_prefix("package://") {
        let (pkg, sub) = rest.split_once('/').unwrap_or((rest, ""));
        let mut tried = Vec::new();
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_are_eroded_meshes_not() {
        for s in [
            SharedShape::cuboid(0.1, 0.2, 0.3),
            SharedShape::ball(0.1),
            SharedShape::cylinder(0.1, 0.05),
            SharedShape::capsule_z(0.1, 0.02),
        ] {
            let p = Placed::new(s, PPose::IDENTITY);
            let e = p.eroded.expect("eroded");
            let (a, b) = (p.shape.compute_local_aabb(), e.compute_local_aabb());
            assert!(((a.maxs - b.maxs).min_element() - 1e-3).abs() < 1e-12, "{a:?} {b:?}");
        }
        let hull = SharedShape::convex_hull(&[
            PVec::new(0.0, 0.0, 0.0),
            PVec::new(1.0, 0.0, 0.0),
            PVec::new(0.0, 1.0, 0.0),
            PVec::new(0.0, 0.0, 1.0),
        ])
        .unwrap();
        assert!(Placed::new(hull, PPose::IDENTITY).eroded.is_none());
    }
}
