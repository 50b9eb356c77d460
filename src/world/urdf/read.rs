//! URDF XML -> the elements the model is built from, read once with roxmltree.
//!
//! It reads what urdfdom (ROS's reference parser) and urdf-rs both read, the way they
//! read it: the `version` attribute (1.1 adds `<origin quat_xyzw>`, 1.2 open limits
//! and positive sizes), defaults for what is left out, the first of a repeated element
//! where one is expected. Only what the world uses is read (collision geometry,
//! joints, limits, mimics); visuals, inertials, transmissions and the rest are skipped
//! unread. urdf-rs read the same text twice (an XML tree re-serialised, then serde):
//! a seventh of an easy Panda problem. Its reading is this one's test oracle.

use roxmltree::{Document, Node};

use super::UrdfProblem;

/// `<origin>`'s rotation as the file gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Orientation {
    Rpy([f64; 3]),
    /// (x, y, z, w) as written, not yet normalised.
    Quat([f64; 4]),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RawPose {
    pub xyz: [f64; 3],
    pub orientation: Orientation,
}

impl Default for RawPose {
    fn default() -> Self {
        RawPose { xyz: [0.0; 3], orientation: Orientation::Rpy([0.0; 3]) }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RawShape {
    Box([f64; 3]),
    Cylinder { radius: f64, length: f64 },
    Capsule { radius: f64, length: f64 },
    Sphere(f64),
    Mesh { filename: String, scale: Option<[f64; 3]> },
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawCollision {
    pub origin: RawPose,
    pub shape: RawShape,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawLink {
    pub name: String,
    pub collisions: Vec<RawCollision>,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum JointKind {
    Revolute,
    Continuous,
    Prismatic,
    Fixed,
    /// `floating`, `planar` or `spherical`: URDF types the world does not move.
    Unsupported(&'static str),
}

/// `<limit>` with urdf-rs's defaults for what it leaves out (version < 1.2: zeros;
/// 1.2: open, infinite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RawLimit {
    pub lower: f64,
    pub upper: f64,
    pub effort: f64,
    pub velocity: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RawJoint {
    pub name: String,
    pub kind: JointKind,
    pub origin: RawPose,
    pub parent: String,
    pub child: String,
    pub axis: [f64; 3],
    pub limit: Option<RawLimit>,
    /// (leader joint, multiplier, offset)
    pub mimic: Option<(String, Option<f64>, Option<f64>)>,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct RawRobot {
    pub links: Vec<RawLink>,
    pub joints: Vec<RawJoint>,
}

/// URDF versions are compared as (major, minor); a missing or malformed `version`
/// is 1.0, as urdfdom reads it.
type Version = (u32, u32);
const V1_1: Version = (1, 1);
const V1_2: Version = (1, 2);

/// Reads the robot's links and joints from a parsed URDF.
pub(crate) fn robot(doc: &Document) -> Result<RawRobot, UrdfProblem> {
    let root = doc.root_element();
    if root.tag_name().name() != "robot" {
        return Err(problem(doc, root, format!("the root element is <{}>, not <robot>", root.tag_name().name())));
    }
    let version = root
        .attribute("version")
        .and_then(|v| {
            let (major, minor) = v.trim().split_once('.')?;
            Some((major.parse().ok()?, minor.parse().ok()?))
        })
        .unwrap_or((1, 0));
    let r = Reader { doc, version };
    let mut out = RawRobot::default();
    for n in root.children().filter(Node::is_element) {
        match n.tag_name().name() {
            "link" => out.links.push(r.link(n)?),
            "joint" => out.joints.push(r.joint(n)?),
            _ => {}
        }
    }
    Ok(out)
}

struct Reader<'a, 'input> {
    doc: &'a Document<'input>,
    version: Version,
}

impl<'input> Reader<'_, 'input> {
    fn link(&self, n: Node<'_, 'input>) -> Result<RawLink, UrdfProblem> {
        let name = self.required(n, "name")?.to_string();
        let mut collisions = Vec::new();
        for c in children(n, "collision") {
            let origin = self.origin(c)?;
            let geometry = first(c, "geometry").ok_or_else(|| self.at(c, "a <collision> has no <geometry>".into()))?;
            collisions.push(RawCollision { origin, shape: self.shape(geometry)? });
        }
        Ok(RawLink { name, collisions })
    }

    fn shape(&self, geometry: Node<'_, 'input>) -> Result<RawShape, UrdfProblem> {
        let Some(s) = geometry.children().find(Node::is_element) else {
            return Err(self.at(geometry, "<geometry> holds no shape".into()));
        };
        let shape = match s.tag_name().name() {
            "box" => RawShape::Box(self.vec3(s, "size")?.ok_or_else(|| self.missing(s, "size"))?),
            "cylinder" => RawShape::Cylinder { radius: self.number(s, "radius")?, length: self.number(s, "length")? },
            "capsule" => RawShape::Capsule { radius: self.number(s, "radius")?, length: self.number(s, "length")? },
            "sphere" => RawShape::Sphere(self.number(s, "radius")?),
            "mesh" => {
                RawShape::Mesh { filename: self.required(s, "filename")?.to_string(), scale: self.vec3(s, "scale")? }
            }
            other => {
                return Err(
                    self.at(s, format!("<{other}> is not a URDF shape (box, cylinder, capsule, sphere or mesh)"))
                )
            }
        };
        let sizes: &[f64] = match &shape {
            RawShape::Box(size) => size,
            RawShape::Cylinder { radius, length } | RawShape::Capsule { radius, length } => &[*radius, *length],
            RawShape::Sphere(radius) => &[*radius],
            RawShape::Mesh { .. } => &[],
        };
        // URDF 1.2 makes positive sizes part of the format; earlier files are held to
        // the world's own (slightly looser) size check.
        if self.version >= V1_2 && !sizes.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(self.at(s, format!("<{}> needs positive finite sizes (URDF 1.2)", s.tag_name().name())));
        }
        Ok(shape)
    }

    fn joint(&self, n: Node<'_, 'input>) -> Result<RawJoint, UrdfProblem> {
        let name = self.required(n, "name")?.to_string();
        let kind = match self.required(n, "type")? {
            "revolute" => JointKind::Revolute,
            "continuous" => JointKind::Continuous,
            "prismatic" => JointKind::Prismatic,
            "fixed" => JointKind::Fixed,
            "floating" => JointKind::Unsupported("floating"),
            "planar" => JointKind::Unsupported("planar"),
            "spherical" => JointKind::Unsupported("spherical"),
            other => {
                return Err(self.at(n, format!("joint `{name}` has type `{other}`, which is not a URDF joint type")))
            }
        };
        let link_of = |tag: &str| -> Result<String, UrdfProblem> {
            let e = first(n, tag).ok_or_else(|| self.at(n, format!("joint `{name}` has no <{tag}>")))?;
            Ok(self.required(e, "link")?.to_string())
        };
        let (parent, child) = (link_of("parent")?, link_of("child")?);
        // urdfdom keeps the default axis when <axis> has no xyz.
        let axis = match first(n, "axis") {
            Some(a) => self.vec3(a, "xyz")?.unwrap_or([1.0, 0.0, 0.0]),
            None => [1.0, 0.0, 0.0],
        };
        let limit = first(n, "limit").map(|l| self.limit(l, &name)).transpose()?;
        let mimic = match first(n, "mimic") {
            Some(m) => Some((
                self.required(m, "joint")?.to_string(),
                self.optional(m, "multiplier")?,
                self.optional(m, "offset")?,
            )),
            None => None,
        };
        Ok(RawJoint { origin: self.origin(n)?, name, kind, parent, child, axis, limit, mimic })
    }

    /// Before 1.2 a left-out bound or effort is 0 and `velocity` is required; from 1.2
    /// a left-out one is open (infinite) and the values are checked as the format says.
    fn limit(&self, l: Node<'_, 'input>, joint: &str) -> Result<RawLimit, UrdfProblem> {
        if self.version < V1_2 {
            return Ok(RawLimit {
                lower: self.optional(l, "lower")?.unwrap_or(0.0),
                upper: self.optional(l, "upper")?.unwrap_or(0.0),
                effort: self.optional(l, "effort")?.unwrap_or(0.0),
                velocity: self.number(l, "velocity")?,
            });
        }
        let open = |attr: &str, default: f64| -> Result<f64, UrdfProblem> {
            match self.optional(l, attr)? {
                Some(v) if v.is_nan() => Err(self.at(l, format!("joint `{joint}`'s {attr} is not a number"))),
                Some(v) => Ok(v),
                None => Ok(default),
            }
        };
        let limit = RawLimit {
            lower: open("lower", f64::NEG_INFINITY)?,
            upper: open("upper", f64::INFINITY)?,
            effort: open("effort", f64::INFINITY)?,
            velocity: open("velocity", f64::INFINITY)?,
        };
        if limit.upper < limit.lower {
            return Err(self.at(l, format!("joint `{joint}`'s upper limit is below its lower limit (URDF 1.2)")));
        }
        if limit.effort < 0.0 || limit.velocity < 0.0 {
            return Err(self.at(l, format!("joint `{joint}` has a negative effort or velocity limit (URDF 1.2)")));
        }
        Ok(limit)
    }

    fn origin(&self, n: Node<'_, 'input>) -> Result<RawPose, UrdfProblem> {
        let Some(o) = first(n, "origin") else {
            return Ok(RawPose::default());
        };
        let xyz = self.vec3(o, "xyz")?.unwrap_or([0.0; 3]);
        let rpy = self.vec3(o, "rpy")?;
        // Before 1.1 urdfdom ignores `quat_xyzw`.
        let quat = match o.attribute("quat_xyzw") {
            Some(q) if self.version >= V1_1 => Some(self.numbers::<4>(o, "quat_xyzw", q)?),
            _ => None,
        };
        let orientation = match (rpy, quat) {
            (Some(_), Some(_)) => return Err(self.at(o, "<origin> gives both rpy and quat_xyzw".into())),
            (_, Some(q)) => Orientation::Quat(q),
            (rpy, None) => Orientation::Rpy(rpy.unwrap_or([0.0; 3])),
        };
        Ok(RawPose { xyz, orientation })
    }

    fn required<'n>(&self, n: Node<'n, 'input>, attr: &str) -> Result<&'n str, UrdfProblem> {
        n.attribute(attr).ok_or_else(|| self.missing(n, attr))
    }

    fn missing(&self, n: Node, attr: &str) -> UrdfProblem {
        self.at(n, format!("<{}> has no `{attr}`", n.tag_name().name()))
    }

    fn number(&self, n: Node<'_, 'input>, attr: &str) -> Result<f64, UrdfProblem> {
        self.optional(n, attr)?.ok_or_else(|| self.missing(n, attr))
    }

    fn optional(&self, n: Node<'_, 'input>, attr: &str) -> Result<Option<f64>, UrdfProblem> {
        n.attribute(attr).map(|v| Ok(self.numbers::<1>(n, attr, v)?[0])).transpose()
    }

    fn vec3(&self, n: Node<'_, 'input>, attr: &str) -> Result<Option<[f64; 3]>, UrdfProblem> {
        n.attribute(attr).map(|v| self.numbers::<3>(n, attr, v)).transpose()
    }

    /// Exactly `N` numbers separated by white space.
    fn numbers<const N: usize>(&self, n: Node, attr: &str, text: &str) -> Result<[f64; N], UrdfProblem> {
        let mut out = [0.0; N];
        let mut words = text.split_whitespace();
        for slot in &mut out {
            match words.next().map(str::parse::<f64>) {
                Some(Ok(v)) => *slot = v,
                _ => return Err(self.bad_numbers::<N>(n, attr, text)),
            }
        }
        match words.next() {
            None => Ok(out),
            Some(_) => Err(self.bad_numbers::<N>(n, attr, text)),
        }
    }

    fn bad_numbers<const N: usize>(&self, n: Node, attr: &str, text: &str) -> UrdfProblem {
        let what = if N == 1 { "a number".to_string() } else { format!("{N} numbers") };
        self.at(n, format!("<{} {attr}=\"{text}\"> is not {what}", n.tag_name().name()))
    }

    /// A reading problem, placed at its element's line.
    fn at(&self, n: Node, message: String) -> UrdfProblem {
        problem(self.doc, n, message)
    }
}

fn problem(doc: &Document, n: Node, message: String) -> UrdfProblem {
    UrdfProblem::Parse(format!("line {}: {message}", doc.text_pos_at(n.range().start).row))
}

fn children<'a, 'input: 'a>(n: Node<'a, 'input>, tag: &'a str) -> impl Iterator<Item = Node<'a, 'input>> + 'a {
    n.children().filter(move |c| c.is_element() && c.tag_name().name() == tag)
}

fn first<'a, 'input: 'a>(n: Node<'a, 'input>, tag: &'a str) -> Option<Node<'a, 'input>> {
    children(n, tag).next()
}
