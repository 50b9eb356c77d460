//! URDF text -> [`Model`]: the link tree, joints and collision geometry, checked.
//!
//! Only what collision checking needs is kept: joint origins, axes, limits and
//! mimic relations, and `<collision>` elements. Visuals, inertials, transmissions
//! and Gazebo tags are ignored. Unknown joint types (`floating`, `planar`) are
//! errors rather than silently fixed.

use std::collections::HashMap;

use nalgebra::{Isometry3, Quaternion, Translation3, Unit, UnitQuaternion, Vector3};

mod read;
#[cfg(test)]
mod read_tests;

use read::{JointKind, Orientation, RawLimit, RawPose, RawShape};

/// What can be wrong with a URDF text.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum UrdfProblem {
    Parse(String),
    Empty,
    /// Unexpanded xacro: `<xacro:...>` elements would be dropped silently.
    Xacro,
    Structure(String),
    /// A revolute or prismatic joint's `<limit>` is missing, not finite, or absurd.
    Limit {
        joint: String,
        reason: String,
    },
}

/// Largest length (metres) or scale factor accepted anywhere in a URDF: anything
/// bigger is a typo or a placeholder, and would overflow poses downstream.
pub(crate) const MAX_LENGTH: f64 = 1e6;
/// Largest joint limit accepted (radians or metres): beyond it the sampling of
/// configurations is meaningless; a joint that turns freely is `continuous`.
pub(crate) const MAX_TRAVEL: f64 = 1e3;

/// Velocity limit (rad/s or m/s) of a movable joint whose URDF gives none (URDF 1.2
/// leaves an absent `velocity` open), or a non-positive or non-finite one: a cautious
/// figure rather than an error, since collision checking never needs it and many
/// hand-written URDFs leave it at 0. Continuous joints have no `<limit>` at all.
pub const DEFAULT_VELOCITY: f64 = 1.0;

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
    /// `<limit velocity>` (rad/s or m/s); [`DEFAULT_VELOCITY`] when absent, zero or not finite.
    pub velocity: f64,
    /// `<limit drake:acceleration>` (rad/s² or m/s²), Drake's extension; URDF itself has none.
    pub acceleration: Option<f64>,
    /// (leader joint name, multiplier, offset)
    pub mimic: Option<(String, f64, f64)>,
}

/// A checked URDF tree: one root, every joint's links exist, no cycles.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Model {
    pub links: Vec<ModelLink>,
    pub joints: Vec<ModelJoint>,
    pub root: usize,
    /// Link pairs the file's own `<drake:collision_filter_group>`s exclude from collision.
    pub filter_pairs: Vec<(String, String)>,
}

impl Model {
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
}

/// The pose of an `<origin>`, or why it is unusable (`what` names the element).
fn pose_of(p: &RawPose, what: &str) -> Result<Isometry3<f64>, UrdfProblem> {
    let [x, y, z] = p.xyz;
    let (angles, directed): (&[f64], _) = match &p.orientation {
        Orientation::Rpy(rpy) => (rpy, true),
        // A quaternion is normalised, as urdfdom does; one of length zero has no direction.
        Orientation::Quat(q) => (q, q.iter().any(|v| *v != 0.0)),
    };
    // NaN or inf would make every shape's AABB NaN, and a NaN box never intersects
    // anything: collision would be off for the link without a word.
    if !(p.xyz.iter().all(|v| v.is_finite() && v.abs() <= MAX_LENGTH)
        && angles.iter().all(|v| v.is_finite())
        && directed)
    {
        return Err(UrdfProblem::Structure(format!(
            "{what} has an <origin> that is not finite or beyond {MAX_LENGTH} m (xyz {:?}, {})",
            p.xyz,
            match &p.orientation {
                Orientation::Rpy(rpy) => format!("rpy {rpy:?}"),
                Orientation::Quat(q) => format!("quat_xyzw {q:?}"),
            }
        )));
    }
    let rotation = match p.orientation {
        Orientation::Rpy([r, pi, ya]) => UnitQuaternion::from_euler_angles(r, pi, ya),
        Orientation::Quat([qx, qy, qz, qw]) => UnitQuaternion::from_quaternion(Quaternion::new(qw, qx, qy, qz)),
    };
    Ok(Isometry3::from_parts(Translation3::new(x, y, z), rotation))
}

/// Limits of a revolute or prismatic joint: required, finite, ordered and not absurd.
fn checked_limits(joint: &str, limit: Option<&RawLimit>) -> Result<(f64, f64), UrdfProblem> {
    let bad = |reason: String| Err(UrdfProblem::Limit { joint: joint.to_string(), reason });
    let Some(l) = limit else {
        return bad("has no <limit> (the URDF specification requires one for revolute and prismatic joints)".into());
    };
    let (lower, upper) = (l.lower, l.upper);
    if !(lower.is_finite() && upper.is_finite()) {
        return bad(format!("has limits [{lower:?}, {upper:?}], which are not finite"));
    }
    if lower.abs() > MAX_TRAVEL || upper.abs() > MAX_TRAVEL {
        return bad(format!("has limits [{lower:?}, {upper:?}], beyond ±{MAX_TRAVEL} (rad or m)"));
    }
    if lower > upper {
        return bad(format!("has lower limit {lower:?} above its upper limit {upper:?}"));
    }
    Ok((lower, upper))
}

/// Parses and checks a URDF text.
pub(crate) fn parse(text: &str) -> Result<Model, UrdfProblem> {
    // Expanded files keep the `xmlns:xacro` declaration, so only elements tell.
    if text.contains("<xacro:") {
        return Err(UrdfProblem::Xacro);
    }
    let doc = roxmltree::Document::parse(text).map_err(|e| UrdfProblem::Parse(e.to_string()))?;
    let robot = read::robot(&doc)?;
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
        for c in &l.collisions {
            let kind = match &c.shape {
                RawShape::Box(size) => GeomKind::Box(Vector3::from(*size)),
                RawShape::Cylinder { radius, length } => GeomKind::Cylinder { radius: *radius, length: *length },
                RawShape::Capsule { radius, length } => GeomKind::Capsule { radius: *radius, length: *length },
                RawShape::Sphere(radius) => GeomKind::Sphere(*radius),
                RawShape::Mesh { filename, scale } => GeomKind::Mesh {
                    uri: filename.clone(),
                    scale: scale.map_or(Vector3::new(1.0, 1.0, 1.0), Vector3::from),
                },
            };
            let ok = match &kind {
                GeomKind::Box(s) => s.iter().all(|&v| v > 0.0 && v <= MAX_LENGTH),
                GeomKind::Cylinder { radius, length } | GeomKind::Capsule { radius, length } => {
                    *radius > 0.0 && *radius <= MAX_LENGTH && *length >= 0.0 && *length <= MAX_LENGTH
                }
                GeomKind::Sphere(r) => *r > 0.0 && *r <= MAX_LENGTH,
                GeomKind::Mesh { scale, .. } => scale.iter().all(|v| v.abs() <= MAX_LENGTH && *v != 0.0),
            };
            // (The comparisons are false for NaN, and the bounds exclude infinities.)
            if !ok {
                return Err(UrdfProblem::Structure(format!(
                    "link `{}` has a collision shape with a zero, negative, non-finite or absurd (over {MAX_LENGTH}) size or scale",
                    l.name
                )));
            }
            let pose_link_geom = pose_of(&c.origin, &format!("a collision of link `{}`", l.name))?;
            collisions.push(Geom { pose_link_geom, kind });
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
        let (parent, child) = (find(&j.parent)?, find(&j.child)?);
        let axis = || {
            let a = Vector3::from(j.axis);
            Unit::try_new(a, 1e-12).filter(|_| a.iter().all(|v| v.abs() <= MAX_LENGTH)).ok_or_else(|| {
                UrdfProblem::Structure(format!(
                    "joint `{}` has a zero, non-finite or absurd axis {:?}",
                    j.name, a.data.0[0]
                ))
            })
        };
        let (motion, continuous) = match j.kind {
            JointKind::Fixed => (Motion::Fixed, false),
            JointKind::Revolute => (Motion::Rotate(axis()?), false),
            JointKind::Continuous => (Motion::Rotate(axis()?), true),
            JointKind::Prismatic => (Motion::Slide(axis()?), false),
            JointKind::Unsupported(other) => {
                return Err(UrdfProblem::Structure(format!(
                "joint `{}` has type `{other}`, which is not supported (use revolute, continuous, prismatic or fixed)",
                j.name
            )))
            }
        };
        let (lower, upper) = match motion {
            Motion::Rotate(_) if continuous => (-2.0 * std::f64::consts::PI, 2.0 * std::f64::consts::PI),
            Motion::Rotate(_) | Motion::Slide(_) => checked_limits(&j.name, j.limit.as_ref())?,
            // A fixed joint's limits are never read.
            Motion::Fixed => (0.0, 0.0),
        };
        if links[child].parent_joint.is_some() {
            return Err(UrdfProblem::Structure(format!("link `{}` is the child of two joints", j.child)));
        }
        links[child].parent_joint = Some(joints.len());
        links[parent].child_joints.push(joints.len());
        let mimic =
            j.mimic.as_ref().map(|(leader, mult, offset)| (leader.clone(), mult.unwrap_or(1.0), offset.unwrap_or(0.0)));
        if let Some((_, mult, offset)) = &mimic {
            if !(mult.abs() <= MAX_TRAVEL && offset.abs() <= MAX_TRAVEL) {
                return Err(UrdfProblem::Structure(format!(
                    "joint `{}` has a mimic multiplier {mult:?} or offset {offset:?} that is not finite or beyond ±{MAX_TRAVEL}",
                    j.name
                )));
            }
        }
        joints.push(ModelJoint {
            name: j.name.clone(),
            motion,
            continuous,
            pose_parent_joint: pose_of(&j.origin, &format!("joint `{}`", j.name))?,
            parent,
            child,
            lower,
            upper,
            velocity: match j.limit {
                Some(RawLimit { velocity, .. }) if velocity.is_finite() && velocity > 0.0 => velocity,
                _ => DEFAULT_VELOCITY,
            },
            acceleration: None,
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
    let filter_pairs = drake_filter_pairs(&doc, &names_of(&links))?;
    for (name, a) in drake_accelerations(&doc)? {
        if let Some(j) = joints.iter_mut().find(|j| j.name == name) {
            j.acceleration = Some(a);
        }
    }
    let model = Model { links, joints, root, filter_pairs };
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

fn names_of(links: &[ModelLink]) -> Vec<&str> {
    links.iter().map(|l| l.name.as_str()).collect()
}

/// Drake's collision filter groups: each `<drake:collision_filter_group>` lists member
/// links and the groups (itself included, when listed) whose members it never collides
/// with.
fn drake_filter_pairs(doc: &roxmltree::Document, links: &[&str]) -> Result<Vec<(String, String)>, UrdfProblem> {
    let named = |n: &roxmltree::Node, tag: &str| n.is_element() && n.tag_name().name() == tag;
    let mut groups: Vec<(String, Vec<String>, Vec<String>)> = Vec::new();
    for g in doc.descendants().filter(|n| named(n, "collision_filter_group")) {
        let name = g.attribute("name").unwrap_or_default().to_string();
        let mut members = Vec::new();
        let mut ignored = Vec::new();
        for c in g.children() {
            if named(&c, "member") {
                let link = c.attribute("link").unwrap_or_default();
                if !links.contains(&link) {
                    return Err(UrdfProblem::Structure(format!(
                        "collision filter group `{name}` names link `{link}`, which is not defined"
                    )));
                }
                members.push(link.to_string());
            } else if named(&c, "ignored_collision_filter_group") {
                ignored.push(c.attribute("name").unwrap_or_default().to_string());
            }
        }
        groups.push((name, members, ignored));
    }
    let mut pairs = Vec::new();
    for (name, members, ignored) in &groups {
        for other in ignored {
            let Some((_, others, _)) = groups.iter().find(|(n, _, _)| n == other) else {
                return Err(UrdfProblem::Structure(format!(
                    "collision filter group `{name}` ignores group `{other}`, which is not defined"
                )));
            };
            for a in members {
                for b in others {
                    if a != b {
                        pairs.push((a.clone(), b.clone()));
                    }
                }
            }
        }
    }
    Ok(pairs)
}

/// Drake's per-joint acceleration limits, `<limit drake:acceleration="8.57" .../>`, by
/// joint name. A value that is not a positive finite number is an error: a limit the
/// file states must be one the timing can keep.
fn drake_accelerations(doc: &roxmltree::Document) -> Result<Vec<(String, f64)>, UrdfProblem> {
    let mut out = Vec::new();
    for joint in doc.descendants().filter(|n| n.is_element() && n.tag_name().name() == "joint") {
        let name = joint.attribute("name").unwrap_or_default();
        for limit in joint.children().filter(|n| n.is_element() && n.tag_name().name() == "limit") {
            let Some(v) = limit.attributes().find(|a| a.name() == "acceleration" && a.namespace().is_some()) else {
                continue;
            };
            match v.value().trim().parse::<f64>() {
                Ok(a) if a.is_finite() && a > 0.0 => out.push((name.to_string(), a)),
                _ => {
                    return Err(UrdfProblem::Structure(format!(
                        "joint `{name}` has `drake:acceleration=\"{}\"`, not a positive number",
                        v.value()
                    )))
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod filter_tests {
    use super::*;

    const ARM: &str = r#"<robot name="r" xmlns:drake="http://drake.mit.edu">
  <link name="a"/><link name="b"/><link name="c"/>
  <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
  <joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>
  <drake:collision_filter_group name="wrist">
    <drake:member link="b"/>
    <drake:member link="c"/>
    <drake:ignored_collision_filter_group name="wrist"/>
  </drake:collision_filter_group>
</robot>"#;

    #[test]
    fn drake_filter_groups_become_pairs() {
        let m = parse(ARM).unwrap();
        assert_eq!(m.filter_pairs, [("b".to_string(), "c".to_string()), ("c".to_string(), "b".to_string())]);
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/robots/iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf");
        if let Ok(text) = std::fs::read_to_string(&p) {
            eprintln!("{:?}", parse(&text).unwrap().filter_pairs);
        }
    }

    #[test]
    fn a_filter_group_naming_an_unknown_link_is_refused() {
        let text = ARM.replace(r#"<drake:member link="c"/>"#, r#"<drake:member link="x"/>"#);
        assert!(matches!(parse(&text), Err(UrdfProblem::Structure(r)) if r.contains("names link `x`")));
    }

    const SLIDER: &str = r#"<robot name="r" xmlns:drake="http://drake.mit.edu">
  <link name="a"/><link name="b"/>
  <joint name="j1" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.5" velocity="0.2" effort="1" drake:acceleration="ACC"/></joint>
</robot>"#;

    #[test]
    fn drakes_acceleration_is_read_and_a_bad_one_refused() {
        let m = parse(&SLIDER.replace("ACC", "2.5")).unwrap();
        assert_eq!((m.joints[0].velocity, m.joints[0].acceleration), (0.2, Some(2.5)));
        for bad in ["-1", "0", "inf", "fast"] {
            let r = parse(&SLIDER.replace("ACC", bad));
            assert!(
                matches!(&r, Err(UrdfProblem::Structure(e)) if e.contains("`drake:acceleration=\"")),
                "{bad}: {r:?}"
            );
        }
        assert_eq!(parse(&SLIDER.replace(r#" drake:acceleration="ACC""#, "")).unwrap().joints[0].acceleration, None);
    }
}
