//! The spanned syntax tree. Every node carries the [`Span`] of the text it came from;
//! nothing here is checked beyond the grammar (units, names and counts are `resolve`'s job).

use crate::diag::Span;

/// One parsed `.dcl` file.
#[derive(Debug, Clone, PartialEq)]
pub struct File {
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// A string literal, escapes already decoded.
#[derive(Debug, Clone, PartialEq)]
pub struct Str {
    pub value: String,
    pub span: Span,
}

/// A number with an optional unit suffix written right after it (`16cm`, `90deg`, `4`).
#[derive(Debug, Clone, PartialEq)]
pub struct Quantity {
    /// The number as written, without the unit (kept for exact integer parsing).
    pub number: String,
    /// The parsed value; may be infinite for literals like `1e999`.
    pub value: f64,
    pub unit: Option<Ident>,
    pub span: Span,
}

/// `(a, b, c)` — any number of quantities; `resolve` checks the count.
#[derive(Debug, Clone, PartialEq)]
pub struct Tuple {
    pub items: Vec<Quantity>,
    pub span: Span,
}

/// `[a, b, c]` — joint values.
#[derive(Debug, Clone, PartialEq)]
pub struct List {
    pub items: Vec<Quantity>,
    pub span: Span,
}

/// `at (x, y, z) [rot (roll, pitch, yaw) | rot quat(x, y, z, w)]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    pub at: Tuple,
    pub rot: Option<Rotation>,
    pub span: Span,
}

/// A pose's rotation as written.
#[derive(Debug, Clone, PartialEq)]
pub enum Rotation {
    /// `(roll, pitch, yaw)`: fixed-axis x, then y, then z.
    Rpy(Tuple),
    /// `quat(x, y, z, w)`: a quaternion in ROS order; `span` covers `quat(...)`.
    Quat { xyzw: Tuple, span: Span },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShapeKind {
    Box,
    Cylinder,
    Capsule,
    Sphere,
    Mesh,
}

impl ShapeKind {
    pub fn keyword(self) -> &'static str {
        match self {
            ShapeKind::Box => "box",
            ShapeKind::Cylinder => "cylinder",
            ShapeKind::Capsule => "capsule",
            ShapeKind::Sphere => "sphere",
            ShapeKind::Mesh => "mesh",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum ArgValue {
    Quantity(Quantity),
    Str(Str),
}

impl ArgValue {
    pub fn span(&self) -> Span {
        match self {
            ArgValue::Quantity(q) => q.span,
            ArgValue::Str(s) => s.span,
        }
    }
}

/// One shape argument, `radius: 3cm` or positional `3cm`.
#[derive(Debug, Clone, PartialEq)]
pub struct Arg {
    pub name: Option<Ident>,
    pub value: ArgValue,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Scale {
    Uniform(Quantity),
    PerAxis(Tuple),
}

/// `box(1, 2, 3)`, `mesh("a.stl") scale 0.001`.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    pub kind: ShapeKind,
    pub kind_span: Span,
    pub args: Vec<Arg>,
    /// The parentheses and what is between them.
    pub args_span: Span,
    pub scale: Option<(Scale, Span)>,
    pub span: Span,
}

/// A shape inside a body block, with its pose relative to the body.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    pub shape: Shape,
    pub pose: Option<Pose>,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
    Z,
}

#[derive(Debug, Clone, PartialEq)]
pub enum GraspOption {
    Approach {
        length: Quantity,
        span: Span,
    },
    /// `width 6cm`: the fingers' opening while holding.
    Width {
        length: Quantity,
        span: Span,
    },
    Repeat {
        count: Quantity,
        axis: Axis,
        span: Span,
    },
    For {
        hands: Vec<Ident>,
        span: Span,
    },
}

impl GraspOption {
    pub fn span(&self) -> Span {
        match self {
            GraspOption::Approach { span, .. }
            | GraspOption::Width { span, .. }
            | GraspOption::Repeat { span, .. }
            | GraspOption::For { span, .. } => *span,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Grasp {
    pub name: Ident,
    pub pose: Pose,
    pub options: Vec<GraspOption>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum BodyItem {
    Part(Part),
    Grasp(Grasp),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyKind {
    Fixed,
    Object,
}

/// `fixed NAME [shape] [pose] [{ parts and grasps }]`, likewise `object`.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub kind: BodyKind,
    pub kind_span: Span,
    pub name: Ident,
    pub shape: Option<Shape>,
    pub pose: Option<Pose>,
    pub items: Vec<BodyItem>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum HandItem {
    Urdf { path: Str, span: Span },
    Tcp { pose: Pose, span: Span },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Hand {
    pub name: Ident,
    pub items: Vec<HandItem>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum RobotItem {
    Urdf {
        path: Str,
        span: Span,
    },
    Base {
        pose: Pose,
        span: Span,
    },
    Hand {
        name: Ident,
        span: Span,
    },
    Flange {
        link: Str,
        span: Span,
    },
    /// `srdf "FILE"`: the robot package's semantic description (its collision filters).
    Srdf {
        path: Str,
        span: Span,
    },
    Home {
        q: List,
        span: Span,
    },
    Drop {
        q: List,
        span: Span,
    },
    /// `open [..]`: the finger joints on the way in and whenever the hand is empty.
    Open {
        q: List,
        span: Span,
    },
    /// `closed [..]`: the finger joints while holding (a grasp's `width` overrides it).
    Closed {
        q: List,
        span: Span,
    },
    AllowContact {
        a: Str,
        b: Str,
        span: Span,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    pub name: Ident,
    pub items: Vec<RobotItem>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Quantity(Quantity),
    Str(Str),
    Ident(Ident),
}

impl Value {
    pub fn span(&self) -> Span {
        match self {
            Value::Quantity(q) => q.span,
            Value::Str(s) => s.span,
            Value::Ident(i) => i.span,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct PlannerEntry {
    pub key: Ident,
    pub value: Value,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    pub name: Ident,
    pub q: Option<List>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    Scenario { name: Str, span: Span },
    Use { path: Str, span: Span },
    Hand(Hand),
    Robot(Robot),
    Body(Box<Body>),
    Planner { entries: Vec<PlannerEntry>, span: Span },
    Target(Target),
}
