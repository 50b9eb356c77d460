//! The world's collision geometry as plain data, for drawing (`declutter show`): what is
//! drawn is exactly what is checked (a mesh as its convex hull in the default mode).

use parry3d_f64::shape::{Shape, TypedShape};

use super::scene::Owner;
use super::World;
use crate::resolve::{FixedId, ObjectId, Pose, RobotId};

/// A shape in a form a renderer draws directly. Round shapes are centred on their
/// frame with their axis along the frame's y (as parry and three.js both have them).
#[derive(Clone, Debug, PartialEq)]
pub enum Drawable {
    /// Full extents.
    Box {
        size: [f64; 3],
    },
    /// Axis y.
    Cylinder {
        radius: f64,
        length: f64,
    },
    Sphere {
        radius: f64,
    },
    /// Triangles (capsules, convex hulls, triangle meshes).
    Mesh {
        vertices: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
    },
}

/// One shape and its pose in the frame of what carries it (a link, an object, the world).
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnShape {
    pub shape: Drawable,
    pub pose: Pose,
}

/// A rigid body of a robot: a link's shapes, or the hand's (on the flange link). A
/// gripper's fingers move apart from the rest of their body as the fingers close: each
/// part that moves on its own is a body of its own, named as its body.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnBody {
    /// The link's name, or the hand's.
    pub name: String,
    /// Index into [`World::fk_links`]'s list: the link the body moves with.
    pub link: usize,
    /// The shapes with the fingers open.
    pub shapes: Vec<DrawnShape>,
}

fn drawable(s: &dyn Shape) -> Option<Drawable> {
    let mesh = |(v, t): (Vec<parry3d_f64::math::Vector>, Vec<[u32; 3]>)| Drawable::Mesh {
        vertices: v.iter().map(|p| [p.x, p.y, p.z]).collect(),
        triangles: t,
    };
    Some(match s.as_typed_shape() {
        TypedShape::Cuboid(c) => Drawable::Box { size: (c.half_extents * 2.0).to_array() },
        TypedShape::Cylinder(c) => Drawable::Cylinder { radius: c.radius, length: 2.0 * c.half_height },
        TypedShape::Ball(b) => Drawable::Sphere { radius: b.radius },
        TypedShape::Capsule(c) => mesh(c.to_trimesh(16, 8)),
        TypedShape::ConvexPolyhedron(c) => mesh(c.to_trimesh()),
        TypedShape::Custom(c) => mesh(super::hull::polyhedron(c)?.to_trimesh()),
        TypedShape::TriMesh(t) => Drawable::Mesh {
            vertices: t.vertices().iter().map(|p| p.to_array()).collect(),
            triangles: t.indices().to_vec(),
        },
        _ => return None,
    })
}

fn drawn(s: &dyn Shape, pose: &parry3d_f64::math::Pose) -> Option<DrawnShape> {
    Some(DrawnShape { shape: drawable(s)?, pose: Pose::from(*pose) })
}

impl World {
    /// The robot's collision bodies, each with the link it moves with, split where the
    /// fingers' postures move some shapes of a body and not others.
    pub fn drawn_robot(&self, r: RobotId) -> Vec<DrawnBody> {
        let m = &self.robots[r.index()];
        self.drawn_parts(r)
            .into_iter()
            .map(|(body, shapes)| {
                let b = &m.bodies[body];
                DrawnBody {
                    name: b.name.clone(),
                    link: b.link,
                    shapes: shapes
                        .iter()
                        .filter_map(|&si| drawn(&*m.shapes[si].placed.shape.0, &m.shapes[si].placed.pose))
                        .collect(),
                }
            })
            .collect()
    }

    /// Per body of [`World::drawn_robot`], in its order: the pose to apply after its link's
    /// (right-multiplied) with the fingers in `posture` (open: the identity).
    pub fn drawn_offsets(&self, r: RobotId, posture: usize) -> Vec<Pose> {
        self.drawn_parts(r).iter().map(|(_, shapes)| self.posture_offset(r, shapes[0], posture)).collect()
    }

    /// The drawn bodies as (collision body, its shapes): each body's shapes in runs that
    /// every finger posture moves alike.
    fn drawn_parts(&self, r: RobotId) -> Vec<(usize, Vec<usize>)> {
        let m = &self.robots[r.index()];
        let same = |a: usize, b: usize| {
            (0..m.postures.len()).all(|p| {
                let (x, y) = (self.posture_offset(r, a, p), self.posture_offset(r, b, p));
                (x.translation.vector - y.translation.vector).norm() < 1e-12 && x.rotation.angle_to(&y.rotation) < 1e-12
            })
        };
        let mut out: Vec<(usize, Vec<usize>)> = Vec::new();
        for (bi, b) in m.bodies.iter().enumerate() {
            let mut first: Option<usize> = None;
            for si in b.shapes.clone() {
                match (first, out.last_mut()) {
                    (Some(f), Some(part)) if same(f, si) => part.1.push(si),
                    _ => {
                        first = Some(si);
                        out.push((bi, vec![si]));
                    }
                }
            }
        }
        out
    }

    /// Where shape `si` stands in `posture` relative to where it stands open, in its link's frame.
    fn posture_offset(&self, r: RobotId, si: usize, posture: usize) -> Pose {
        let m = &self.robots[r.index()];
        let pose = |p: usize| m.postures.get(p).and_then(|p| p.poses.get(si)).map(|x| Pose::from(*x));
        match (pose(posture), pose(super::OPEN_POSTURE)) {
            (Some(now), Some(open)) => now * open.inverse(),
            _ => Pose::identity(),
        }
    }
    /// The object's shapes in its body frame.
    pub fn drawn_object(&self, o: ObjectId) -> Vec<DrawnShape> {
        self.object_parts[o.index()].iter().filter_map(|p| drawn(&*p.shape.0, &p.pose)).collect()
    }
    /// The fixed body's shapes in the world frame.
    pub fn drawn_fixed(&self, f: FixedId) -> Vec<DrawnShape> {
        // Every robot's scene holds the fixed bodies; the first one's will do.
        let Some(m) = self.robots.first() else { return Vec::new() };
        m.scene
            .entries
            .iter()
            .filter(|e| e.owner == Owner::Fixed(f))
            .filter_map(|e| drawn(&*e.shape.0, &e.pose))
            .collect()
    }
}
