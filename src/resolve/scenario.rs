//! The typed, resolved scenario: every name an id, every quantity in SI units,
//! every pose in the world frame, every `use` inlined and every grasp expanded.

use std::path::PathBuf;

use nalgebra::{Isometry3, Vector3};
use serde::Serialize;

use crate::diag::Span;

/// A rigid transform, `pose_ab` maps frame-b coordinates into frame a.
pub type Pose = Isometry3<f64>;

macro_rules! id_type {
    ($(#[$m:meta])* $name:ident) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
        #[serde(transparent)]
        pub struct $name(pub u32);
        impl $name {
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    };
}

id_type!(/// Index into [`Scenario::robots`].
    RobotId);
id_type!(/// Index into [`Scenario::objects`] (removable objects only).
    ObjectId);
id_type!(/// Index into [`Scenario::fixed`].
    FixedId);
id_type!(/// Index into [`Scenario::hands`].
    HandId);

/// A path to a file the scenario names, with the span of the string that named it.
#[derive(Debug, Clone, PartialEq)]
pub struct FileRef {
    /// Resolved against the directory of the file that named it.
    pub path: PathBuf,
    /// The path exactly as written, for messages.
    pub written: String,
    pub span: Span,
}

/// A vector of joint values in radians (metres for prismatic joints), as written.
#[derive(Debug, Clone, PartialEq)]
pub struct JointValues {
    pub values: Vec<f64>,
    pub span: Span,
    /// The unit each value was written with, and its span, so the world (which knows
    /// which joints turn and which slide) can refuse `1cm` for a revolute joint. Empty
    /// when not recorded (values built in code): then every value is taken as written.
    pub units: Vec<(JointUnit, Span)>,
}

/// The kind of unit a joint value was written with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointUnit {
    /// A bare number: radians or metres, by the joint.
    Bare,
    /// `deg` or `rad`.
    Angle,
    /// `m`, `cm` or `mm`.
    Length,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Hand {
    pub name: String,
    pub span: Span,
    /// Rigid collision model of the hand in the flange frame.
    pub urdf: FileRef,
    /// Pose of the grasp frame (TCP) in the flange frame; its +z points into the object.
    pub pose_flange_tcp: Pose,
}

/// A pair of link names whose collisions are never checked (or always checked).
#[derive(Debug, Clone, PartialEq)]
pub struct LinkPair {
    pub a: String,
    pub b: String,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    pub name: String,
    pub span: Span,
    pub urdf: FileRef,
    pub pose_world_base: Pose,
    pub hand: Option<HandId>,
    /// URDF link the hand is attached to; `None` means the chain's last link.
    pub flange: Option<(String, Span)>,
    /// The robot package's SRDF, whose `disable_collisions` pairs are not checked.
    pub srdf: Option<FileRef>,
    pub home: JointValues,
    /// Where removed objects are released; `None` means `home`.
    pub drop: Option<JointValues>,
    /// Link pairs the user says may touch (self-collision overrides).
    pub allow_contact: Vec<LinkPair>,
    /// The finger joints' values with the hand empty; `None`: each at its upper limit.
    pub open: Option<JointValues>,
    /// The finger joints' values while holding; `None`: as open (unless a grasp's `width`).
    pub closed: Option<JointValues>,
}

/// A collision primitive centred on its own frame. Sizes are full extents as written,
/// converted to metres.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Box {
        size: Vector3<f64>,
    },
    /// Axis z, centred.
    Cylinder {
        radius: f64,
        length: f64,
    },
    /// Axis z, centred; `length` is the straight part between the two hemispheres.
    Capsule {
        radius: f64,
        length: f64,
    },
    Sphere {
        radius: f64,
    },
    Mesh {
        file: FileRef,
        scale: Vector3<f64>,
    },
}

/// One shape of a body, placed in the world frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    pub shape: Shape,
    pub pose_world_part: Pose,
    /// Pose relative to the body frame, as written.
    pub pose_body_part: Pose,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub name: String,
    pub span: Span,
    pub pose_world_body: Pose,
    pub parts: Vec<Part>,
}

/// One expanded grasp of an object (`top#2`).
#[derive(Debug, Clone, PartialEq)]
pub struct Grasp {
    /// Expanded name, `NAME` or `NAME#k`.
    pub name: String,
    pub span: Span,
    /// TCP pose in the object frame.
    pub pose_object_tcp: Pose,
    /// TCP pose in the world frame.
    pub pose_world_tcp: Pose,
    /// Stand-off along the TCP's -z from which the hand moves straight in (metres).
    pub approach: f64,
    /// Hands this grasp is for; `None` means every hand.
    pub hands: Option<Vec<HandId>>,
    /// The opening sliding fingers close to while holding (metres), with its span.
    pub width: Option<(f64, Span)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    pub body: Body,
    pub grasps: Vec<Grasp>,
}

impl Object {
    /// The index of the grasp named (expanded, as `top#2`) `name`.
    pub fn grasp_index(&self, name: &str) -> Option<usize> {
        self.grasps.iter().position(|g| g.name == name)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// Grasp this object, removing whatever blocks it.
    Object { object: ObjectId, span: Span },
    /// Bring a robot to a configuration, removing whatever blocks it.
    Config { robot: RobotId, q: JointValues, span: Span },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// The path whose union of labels is smallest (default).
    FewestRemovals,
    /// The paper's rule: the path with fewest vertices, then its labels.
    FewestVertices,
}

#[derive(Debug, Clone, PartialEq)]
pub struct PlannerSettings {
    pub seed: u64,
    pub max_samples: usize,
    /// Largest joint step (radians) the local planner takes unchecked.
    pub resolution: f64,
    pub objective: Objective,
    /// Wall-clock budget per query in seconds, if any.
    pub time_budget: Option<f64>,
    /// Neighbours each new sample tries to connect to.
    pub neighbours: usize,
    /// Stop a query at the first path found (the paper's cheapest stop rule).
    pub first_path: bool,
    /// Joint acceleration limit (rad/s², m/s² on a prismatic joint) for every joint;
    /// URDF has none. Scaled by `speed` like the velocity limits.
    pub acceleration: f64,
    /// Scaling of every velocity and acceleration limit, in (0, 1] (MoveIt's scaling factors).
    pub speed: f64,
}

/// Default `acceleration`: 3 rad/s², a cautious figure for a 6-axis industrial arm.
pub const DEFAULT_ACCELERATION: f64 = 3.0;

impl Default for PlannerSettings {
    fn default() -> Self {
        PlannerSettings {
            seed: 1,
            max_samples: 5000,
            resolution: 2f64.to_radians(),
            objective: Objective::FewestRemovals,
            time_budget: None,
            neighbours: 10,
            first_path: false,
            acceleration: DEFAULT_ACCELERATION,
            speed: 1.0,
        }
    }
}

/// A whole resolved scenario. Ids index the vectors.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    pub name: Option<String>,
    /// The file the user named on the command line.
    pub root: PathBuf,
    pub hands: Vec<Hand>,
    pub robots: Vec<Robot>,
    pub fixed: Vec<Body>,
    pub objects: Vec<Object>,
    pub target: Target,
    pub planner: PlannerSettings,
}

impl Scenario {
    pub fn robot(&self, id: RobotId) -> &Robot {
        &self.robots[id.index()]
    }
    pub fn object(&self, id: ObjectId) -> &Object {
        &self.objects[id.index()]
    }
    pub fn robot_ids(&self) -> impl Iterator<Item = RobotId> {
        (0..self.robots.len() as u32).map(RobotId)
    }
    pub fn object_ids(&self) -> impl Iterator<Item = ObjectId> {
        (0..self.objects.len() as u32).map(ObjectId)
    }
    pub fn object_by_name(&self, name: &str) -> Option<ObjectId> {
        self.objects.iter().position(|o| o.body.name == name).map(|i| ObjectId(i as u32))
    }
    pub fn robot_by_name(&self, name: &str) -> Option<RobotId> {
        self.robots.iter().position(|r| r.name == name).map(|i| RobotId(i as u32))
    }
}
