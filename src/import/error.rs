//! What `import` can reject or warn of, each with a stable code and, where the input has
//! one, the place in the YAML file.

use miette::Diagnostic;
use thiserror::Error;

use crate::diag::{Located, Span};

#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum ImportError {
    #[error("`{path}` is not a valid MoveIt {what}: {message}")]
    #[diagnostic(
        code(declutter::import::yaml),
        help("a planning scene or motion-plan request as MoveIt writes it in YAML (`moveit_msgs/PlanningScene`, `moveit_msgs/MotionPlanRequest`)")
    )]
    Yaml {
        path: String,
        what: &'static str,
        message: String,
        #[label("here")]
        span: Option<Span>,
    },

    #[error("shape type {kind} of `{id}` is not a MoveIt solid primitive")]
    #[diagnostic(
        code(declutter::import::primitive),
        help("`shape_msgs/SolidPrimitive` types are 1 box, 2 sphere, 3 cylinder, 4 cone")
    )]
    UnknownPrimitive {
        id: String,
        kind: u8,
        #[label("not 1 to 4")]
        span: Option<Span>,
    },

    #[error("a {shape} of `{id}` needs {expected}, found {found} values")]
    #[diagnostic(code(declutter::import::dimensions))]
    Dimensions {
        id: String,
        shape: &'static str,
        expected: &'static str,
        found: usize,
        #[label("this primitive")]
        span: Option<Span>,
    },

    #[error("`{id}` has a size or coordinate that is not a positive finite number: {value}")]
    #[diagnostic(code(declutter::import::bad_value), help("sizes are positive and every number is finite"))]
    BadValue {
        id: String,
        value: String,
        #[label("in this object")]
        span: Option<Span>,
    },

    #[error("`{id}` has {shapes} shapes but {poses} poses for them")]
    #[diagnostic(code(declutter::import::pose_count), help("MoveIt pairs each primitive and mesh with one pose"))]
    PoseCount {
        id: String,
        shapes: usize,
        poses: usize,
        #[label("in this object")]
        span: Option<Span>,
    },

    #[error("a mesh triangle of `{id}` names vertex {index}, but the mesh has {count} vertices")]
    #[diagnostic(code(declutter::import::mesh_index))]
    MeshIndex {
        id: String,
        index: u64,
        count: usize,
        #[label("this triangle")]
        span: Option<Span>,
    },

    #[error("joint `{joint}` is not a joint of any robot of the cell")]
    #[diagnostic(code(declutter::import::unknown_joint))]
    UnknownJoint {
        joint: String,
        #[label("no robot has this joint")]
        span: Option<Span>,
        #[help]
        help: String,
    },

    #[error("joint `{joint}` belongs to several robots of the cell ({robots})")]
    #[diagnostic(
        code(declutter::import::ambiguous_joint),
        help("MoveIt names the joints of a multi-arm cell apart (a prefix per arm); use a cell whose robots' URDFs do the same, or one robot")
    )]
    AmbiguousJoint { joint: String, robots: String },

    #[error("the request's goal moves joints of several robots ({robots})")]
    #[diagnostic(
        code(declutter::import::several_robots),
        help("a `target ROBOT at [...]` is one robot's configuration; split the goal by robot")
    )]
    SeveralRobots { robots: String },

    #[error("the request's goal leaves joint `{joint}` of `{robot}` unset")]
    #[diagnostic(
        code(declutter::import::incomplete_goal),
        help("a configuration target gives every joint of the robot; add a joint constraint for it")
    )]
    IncompleteGoal { robot: String, joint: String },

    #[error("a motion-plan request needs `--cell`")]
    #[diagnostic(
        code(declutter::import::request_without_cell),
        help("the request's joints are matched by name to the robots of a cell file (`--cell cell.dcl`)")
    )]
    RequestWithoutCell,

    #[error("the request has no joint goal")]
    #[diagnostic(
        code(declutter::import::no_goal),
        help("declutter imports `goal_constraints[0].joint_constraints` as `target ROBOT at [...]`")
    )]
    NoGoal,

    #[error("cannot read `{path}`: {reason}")]
    #[diagnostic(code(declutter::import::unreadable))]
    Unreadable { path: String, reason: String },

    #[error("`--removable {pattern}` is not a regular expression: {message}")]
    #[diagnostic(code(declutter::import::regex), help("e.g. `--removable '^(can|box)_'`"))]
    BadRegex { pattern: String, message: String },

    #[error("the cell `{path}` declares no robot")]
    #[diagnostic(
        code(declutter::import::cell_without_robot),
        help("`--cell` names a file with the robots (and hands) the scene is for, like examples/cell.dcl")
    )]
    CellWithoutRobot { path: String },

    #[error("cannot write `{path}`: {reason}")]
    #[diagnostic(code(declutter::import::write))]
    Write { path: String, reason: String },

    #[error("the joint state lists {names} names but {positions} positions")]
    #[diagnostic(code(declutter::import::joint_state))]
    JointState { names: usize, positions: usize },
}

impl Located for ImportError {
    fn primary_span(&self) -> Option<Span> {
        use ImportError::*;
        match self {
            Yaml { span, .. }
            | UnknownPrimitive { span, .. }
            | Dimensions { span, .. }
            | BadValue { span, .. }
            | PoseCount { span, .. }
            | MeshIndex { span, .. }
            | UnknownJoint { span, .. } => *span,
            SeveralRobots { .. }
            | AmbiguousJoint { .. }
            | IncompleteGoal { .. }
            | RequestWithoutCell
            | NoGoal
            | JointState { .. }
            | Unreadable { .. }
            | BadRegex { .. }
            | CellWithoutRobot { .. }
            | Write { .. } => None,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum ImportWarning {
    #[error("`{field}` is not imported")]
    #[diagnostic(
        code(declutter::import::unsupported_field),
        severity(Warning),
        help("declutter imports collision objects (boxes, spheres, cylinders, meshes), the allowed collision matrix, the start state and a joint goal")
    )]
    UnsupportedField { field: String },

    #[error("`{id}` is renamed `{name}`: a declutter name is letters, digits and `_`, not starting with a digit, and unique")]
    #[diagnostic(code(declutter::import::renamed), severity(Warning))]
    Renamed {
        id: String,
        name: String,
        #[label("this id")]
        span: Option<Span>,
    },

    #[error("the request scales velocities by {velocity} and accelerations by {acceleration}; declutter's one `speed` scales both, so it is {speed}")]
    #[diagnostic(
        code(declutter::import::scaling),
        severity(Warning),
        help("`speed` takes the smaller factor, so neither scaled limit is exceeded; the other is scaled further than the request asks")
    )]
    Scaling { velocity: f64, acceleration: f64, speed: f64 },

    #[error("`{field}` is {value}, not in (0, 1]: not imported")]
    #[diagnostic(
        code(declutter::import::scaling_range),
        severity(Warning),
        help("MoveIt's scaling factors are fractions of the joints' limits")
    )]
    ScalingRange { field: String, value: f64 },

    #[error("poses in frame `{frame}` are taken as world-frame poses")]
    #[diagnostic(
        code(declutter::import::frame),
        severity(Warning),
        help("declutter has no transform tree; if `{frame}` is a robot's base link, that robot's `base` must be at the origin")
    )]
    Frame { frame: String },

    #[error("a cone of `{id}` is not imported: declutter has no cone shape")]
    #[diagnostic(
        code(declutter::import::cone),
        severity(Warning),
        help("approximate it by a cylinder in the scenario")
    )]
    Cone {
        id: String,
        #[label("this primitive")]
        span: Option<Span>,
    },

    #[error("`{id}` has operation {operation} (only 0, add, is imported); it is left out")]
    #[diagnostic(code(declutter::import::operation), severity(Warning))]
    Operation {
        id: String,
        operation: u8,
        #[label("this object")]
        span: Option<Span>,
    },

    #[error("an orientation of `{id}` is zero; taken as no rotation, as MoveIt does")]
    #[diagnostic(code(declutter::import::zero_quaternion), severity(Warning))]
    ZeroQuaternion {
        id: String,
        #[label("this object")]
        span: Option<Span>,
    },

    #[error("the allowed collision matrix allows `{a}` and `{b}` to touch, but {why}; not imported")]
    #[diagnostic(
        code(declutter::import::acm_pair),
        severity(Warning),
        help("declutter takes allowed pairs between two links of one robot as `allow_contact`")
    )]
    AcmPair { a: String, b: String, why: String },

    #[error("the cell's {count} object{} not carried over", if *count == 1 { " is" } else { "s are" })]
    #[diagnostic(
        code(declutter::import::cell_objects),
        severity(Warning),
        help("a cell file holds robots, hands and fixed bodies; declare objects in the scene")
    )]
    CellObjects { count: usize },

    #[error("{count} removable object{} no grasps", if *count == 1 { " has" } else { "s have" })]
    #[diagnostic(
        code(declutter::import::no_grasps),
        severity(Warning),
        help("a MoveIt scene has no grasps; add `grasp` lines to each object the robots may remove")
    )]
    NoGrasps { count: usize },
}

impl Located for ImportWarning {
    fn primary_span(&self) -> Option<Span> {
        use ImportWarning::*;
        match self {
            Renamed { span, .. } | Cone { span, .. } | Operation { span, .. } | ZeroQuaternion { span, .. } => *span,
            UnsupportedField { .. }
            | Frame { .. }
            | AcmPair { .. }
            | NoGrasps { .. }
            | CellObjects { .. }
            | Scaling { .. }
            | ScalingRange { .. } => None,
        }
    }
}
