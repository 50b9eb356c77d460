//! URDF text -> [`Model`]: the link tree, joints and collision geometry, checked.
//!
//! Only what collision checking needs is kept: joint origins, axes, limits and
//! mimic relations, and `<collision>` elements. Visuals, inertials, transmissions
//! and Gazebo tags are ignored. Unknown joint types (`floating`, `planar`) are
//! errors rather than silently fixed.

use std::collections::HashMap;

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

/// What can be wrong with a URDF text.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum UrdfProblem {
    Parse(String),
    Empty,
    Structure(String),
}

/// How a joint moves its child.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Motion {
    Fixed,
    Rotate(Unit<Vector3<f64>>),
    Slide(Unit<Vector3<f64>>),
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum GeomKind {
    Box(Vector3<f64>),
    Cylinder { radius: f64, length: f64 },
    Capsule { radius: f64, length: f64 },
    Sphere(f64),
    Mesh { uri: String, scale: Vector3<f64> },
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Geom {
    pub pose_link_geom: Isometry3<f64>,
    pub kind: GeomKind,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ModelLink {
    pub name: String,
    /// Joint whose child this link is (`None` for the root).
    pub parent_joint: Option<usize>,
    pub child_joints: Vec<usize>,
    pub collisions: Vec<Geom>,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ModelJoint {
    pub name: String,
    pub motion: Motion,
    pub continuous: bool,
    pub pose_parent_joint: Isometry3<f64>,
    pub parent: usize,
    pub child: usize,
    pub lower: f64,
    pub upper: f64,
    /// (leader joint name, multiplier, offset)
    pub mimic: Option<(String, f64, f64)>,
}

/// A checked URDF tree: one root, every joint's links exist, no cycles.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Model {
    pub links: Vec<ModelLink>,
    pub joints: Vec<ModelJoint>,
    pub root: usize,
}

impl Model {
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
}

pub(crate) fn pose_of(p: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = p.xyz.0;
    let [r, pi, ya] = p.rpy.0;
    Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(r, pi, ya))
}

/// Parses and checks a URDF text.
pub(crate) fn parse(text: &str) -> Result<Model, UrdfProblem> {
    let robot = urdf_rs::read_from_string(text).map_err(|e| UrdfProblem::Parse(first_line(&e.to_string())))?;
    if robot.links.is_empty() {
        return Err(UrdfProblem::Empty);
    }
    let mut index = HashMap::new();
    let mut links = Vec::with_capacity(robot.links.len());
    for l in &robot.links {
        if index.insert(l.name.clone(), links.len()).is_some() {
            return Err(UrdfProblem::Structure(format!("link `{}` is defined twice", l.name)));
        }
        let mut collisions = Vec::new();
        for c in &l.collision {
            let kind = match &c.geometry {
                urdf_rs::Geometry::Box { size } => GeomKind::Box(Vector3::from(size.0)),
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    GeomKind::Cylinder { radius: *radius, length: *length }
                }
                urdf_rs::Geometry::Capsule { radius, length } => GeomKind::Capsule { radius: *radius, length: *length },
                urdf_rs::Geometry::Sphere { radius } => GeomKind::Sphere(*radius),
                urdf_rs::Geometry::Mesh { filename, scale } => GeomKind::Mesh {
                    uri: filename.clone(),
                    scale: scale.map_or(Vector3::new(1.0, 1.0, 1.0), |s| Vector3::from(s.0)),
                },
            };
            let ok = match &kind {
                GeomKind::Box(s) => s.iter().all(|v| v.is_finite() && *v > 0.0),
                GeomKind::Cylinder { radius, length } | GeomKind::Capsule { radius, length } => {
                    radius.is_finite() && *radius > 0.0 && length.is_finite() && *length >= 0.0
                }
                GeomKind::Sphere(r) => r.is_finite() && *r > 0.0,
                GeomKind::Mesh { scale, .. } => scale.iter().all(|v| v.is_finite() && *v != 0.0),
            };
            if !ok {
                return Err(UrdfProblem::Structure(format!(
                    "link `{}` has a collision shape with a zero, negative or non-finite size",
                    l.name
                )));
            }
            collisions.push(Geom { pose_link_geom: pose_of(&c.origin), kind });
        }
        links.push(ModelLink { name: l.name.clone(), parent_joint: None, child_joints: Vec::new(), collisions });
    }
    let mut joints = Vec::with_capacity(robot.joints.len());
    let mut names = HashMap::new();
    for j in &robot.joints {
        if names.insert(j.name.clone(), ()).is_some() {
            return Err(UrdfProblem::Structure(format!("joint `{}` is defined twice", j.name)));
        }
        let find = |n: &str| {
            index.get(n).copied().ok_or_else(|| {
                UrdfProblem::Structure(format!("joint `{}` names link `{n}`, which is not defined", j.name))
            })
        };
        let (parent, child) = (find(&j.parent.link)?, find(&j.child.link)?);
        let axis = || {
            let a = Vector3::from(j.axis.xyz.0);
            Unit::try_new(a, 1e-12)
                .filter(|_| a.iter().all(|v| v.is_finite()))
                .ok_or_else(|| UrdfProblem::Structure(format!("joint `{}` has a zero axis", j.name)))
        };
        let (motion, continuous) = match j.joint_type {
            urdf_rs::JointType::Fixed => (Motion::Fixed, false),
            urdf_rs::JointType::Revolute => (Motion::Rotate(axis()?), false),
            urdf_rs::JointType::Continuous => (Motion::Rotate(axis()?), true),
            urdf_rs::JointType::Prismatic => (Motion::Slide(axis()?), false),
            ref other => {
                return Err(UrdfProblem::Structure(format!(
                    "joint `{}` has type `{}`, which is not supported (use revolute, continuous, prismatic or fixed)",
                    j.name,
                    format!("{other:?}").to_lowercase()
                )))
            }
        };
        let (mut lower, mut upper) = (j.limit.lower, j.limit.upper);
        match motion {
            Motion::Rotate(_) if continuous || !(lower.is_finite() && upper.is_finite()) => {
                (lower, upper) = (-2.0 * std::f64::consts::PI, 2.0 * std::f64::consts::PI)
            }
            Motion::Slide(_) if !(lower.is_finite() && upper.is_finite()) => {
                return Err(UrdfProblem::Structure(format!("prismatic joint `{}` has no finite limits", j.name)))
            }
            _ => {}
        }
        if lower > upper {
            return Err(UrdfProblem::Structure(format!(
                "joint `{}` has lower limit {lower} above its upper limit {upper}",
                j.name
            )));
        }
        if links[child].parent_joint.is_some() {
            return Err(UrdfProblem::Structure(format!("link `{}` is the child of two joints", j.child.link)));
        }
        links[child].parent_joint = Some(joints.len());
        links[parent].child_joints.push(joints.len());
        let mimic = j.mimic.as_ref().map(|m| (m.joint.clone(), m.multiplier.unwrap_or(1.0), m.offset.unwrap_or(0.0)));
        joints.push(ModelJoint {
            name: j.name.clone(),
            motion,
            continuous,
            pose_parent_joint: pose_of(&j.origin),
            parent,
            child,
            lower,
            upper,
            mimic,
        });
    }
    let roots: Vec<usize> = (0..links.len()).filter(|&i| links[i].parent_joint.is_none()).collect();
    let root = match roots.as_slice() {
        [r] => *r,
        [] => return Err(UrdfProblem::Structure("the joints form a cycle: no root link".into())),
        many => {
            return Err(UrdfProblem::Structure(format!(
                "the model has {} root links ({}); a robot must be one tree",
                many.len(),
                many.iter().map(|&i| format!("`{}`", links[i].name)).collect::<Vec<_>>().join(", ")
            )))
        }
    };
    for j in &joints {
        if let Some((leader, _, _)) = &j.mimic {
            if !names.contains_key(leader) {
                return Err(UrdfProblem::Structure(format!(
                    "joint `{}` mimics joint `{leader}`, which is not defined",
                    j.name
                )));
            }
        }
    }
    let model = Model { links, joints, root };
    // Every link reachable from the root exactly once (a cycle would leave some unreached).
    let mut seen = 0;
    let mut stack = vec![root];
    while let Some(l) = stack.pop() {
        seen += 1;
        stack.extend(model.links[l].child_joints.iter().map(|&j| model.joints[j].child));
    }
    if seen != model.links.len() {
        return Err(UrdfProblem::Structure("the joints form a cycle".into()));
    }
    Ok(model)
}

fn first_line(s: &str) -> String {
    s.lines().next().unwrap_or("").trim().to_string()
}
