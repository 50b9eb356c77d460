//! Errors of the world phase. Each carries the span of the scenario line that
//! named the offending file or joint vector; URDF-internal positions are given by
//! link and joint names.

use miette::Diagnostic;
use thiserror::Error;

use crate::diag::{Located, Span};

/// An error building the [`World`](super::World) from a scenario.
#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum WorldError {
    #[error("cannot read URDF `{path}`: {reason}")]
    #[diagnostic(code(declutter::world::urdf_read))]
    UrdfRead {
        path: String,
        reason: String,
        #[label("named here")]
        span: Span,
    },

    #[error("URDF `{path}` is not valid: {reason}")]
    #[diagnostic(code(declutter::world::urdf_parse))]
    UrdfParse {
        path: String,
        reason: String,
        #[label("named here")]
        span: Span,
    },

    #[error("URDF `{path}` has no links")]
    #[diagnostic(
        code(declutter::world::urdf_empty),
        help("a `.xacro` file must be expanded first: `xacro robot.urdf.xacro > robot.urdf`")
    )]
    UrdfEmpty {
        path: String,
        #[label("this file defines no <link>")]
        span: Span,
    },

    #[error("URDF `{path}` is an unexpanded xacro file")]
    #[diagnostic(
        code(declutter::world::urdf_xacro),
        help("expand it first: `xacro robot.urdf.xacro > robot.urdf`; its `<xacro:...>` elements would otherwise be dropped")
    )]
    UrdfXacro {
        path: String,
        #[label("this file contains <xacro:...> elements")]
        span: Span,
    },

    #[error("URDF `{path}`: joint `{joint}` {reason}")]
    #[diagnostic(
        code(declutter::world::urdf_limit),
        help("a revolute or prismatic joint needs `<limit lower=\"..\" upper=\"..\" effort=\"..\" velocity=\"..\"/>` with its real, finite travel (rad or m); a joint that turns without end is `type=\"continuous\"`")
    )]
    UrdfLimit {
        path: String,
        joint: String,
        reason: String,
        #[label("in this robot model")]
        span: Span,
    },

    #[error("robot `{robot}` has no actuated joint between its root link `{root}` and its flange `{flange}`")]
    #[diagnostic(
        code(declutter::world::no_joints),
        help("a robot needs at least one revolute, continuous or prismatic joint on the chain to its flange; check the URDF's joints, or name a deeper link with `flange`")
    )]
    NoJoints {
        robot: String,
        root: String,
        flange: String,
        #[label("this robot model cannot move")]
        span: Span,
    },

    #[error("URDF `{path}`: {reason}")]
    #[diagnostic(code(declutter::world::urdf_structure))]
    UrdfStructure {
        path: String,
        reason: String,
        #[label("in this robot model")]
        span: Span,
    },

    #[error("mesh `{uri}` of {owner} not found ({tried})")]
    #[diagnostic(code(declutter::world::mesh_missing))]
    MeshMissing {
        /// "link `x`" of a URDF, or "body `x`" of the scenario.
        owner: String,
        uri: String,
        /// "looked at A, B", or why nothing could be looked at.
        tried: String,
        #[label("loading this file")]
        span: Span,
        /// Where such a URI is looked for (see `mesh_missing_help`).
        #[help]
        help: String,
    },

    #[error("mesh `{uri}` of {owner} cannot be loaded: {reason}")]
    #[diagnostic(code(declutter::world::mesh_load))]
    MeshLoad {
        /// "link `x`" of a URDF, or "body `x`" of the scenario.
        owner: String,
        uri: String,
        reason: String,
        #[label("loading this file")]
        span: Span,
    },

    #[error("robot `{robot}` has no link `{link}` to attach its hand to")]
    #[diagnostic(code(declutter::world::unknown_flange), help("the URDF's links: {links}"))]
    UnknownFlange {
        robot: String,
        link: String,
        /// Every link of the URDF, in file order (links in XML comments are not links).
        links: String,
        #[label("not a link of the URDF")]
        span: Span,
    },

    #[error("robot `{robot}` has no link `{link}`")]
    #[diagnostic(code(declutter::world::unknown_link), help("links with collision geometry: {links}"))]
    UnknownLink {
        robot: String,
        link: String,
        links: String,
        #[label("in this `allow_contact`")]
        span: Span,
    },

    #[error("{a} and {b} overlap by {depth_mm:.1} mm")]
    #[diagnostic(
        code(declutter::world::bodies_overlap),
        help("bodies may touch (up to the 1 mm contact tolerance) but not sink into each other; check the positions and sizes (and their units)")
    )]
    BodiesOverlap {
        a: String,
        b: String,
        depth_mm: f64,
        #[label("this one")]
        span: Span,
        /// The other body, when it is declared in the same file.
        #[label("overlaps this one")]
        other: Option<Span>,
        /// The other body, when it is declared in another file (a related report).
        elsewhere: Option<Span>,
    },

    #[error("cannot read SRDF `{path}`: {reason}")]
    #[diagnostic(code(declutter::world::srdf_read))]
    SrdfRead {
        path: String,
        reason: String,
        #[label("named here")]
        span: Span,
    },

    #[error("SRDF `{path}` line {line}: {reason}")]
    #[diagnostic(
        code(declutter::world::srdf_parse),
        help("an SRDF is the XML MoveIt's setup assistant writes (`<robot>` with `<disable_collisions link1=\"..\" link2=\"..\"/>`)")
    )]
    SrdfParse {
        path: String,
        line: u32,
        reason: String,
        #[label("this SRDF")]
        span: Span,
    },

    #[error("SRDF `{path}` line {line} names link `{link}`, which robot `{robot}`'s URDF does not have")]
    #[diagnostic(
        code(declutter::world::srdf_link),
        help("the URDF's links: {links}; is this the SRDF of another robot?")
    )]
    SrdfLink {
        path: String,
        line: u32,
        robot: String,
        link: String,
        links: String,
        #[label("this SRDF")]
        span: Span,
    },

    #[error("`{what}` of robot `{robot}` has {got} values, but the robot has {expected} joints ({joints})")]
    #[diagnostic(code(declutter::world::joint_count))]
    JointCount {
        robot: String,
        what: String,
        expected: usize,
        got: usize,
        joints: String,
        #[label("expected {expected} values")]
        span: Span,
    },

    #[error(
        "`{what}` of robot `{robot}` has {got} values, but its gripper has {expected} finger joint{} ({joints})",
        if *expected == 1 { "" } else { "s" }
    )]
    #[diagnostic(
        code(declutter::world::finger_count),
        help("one value per finger joint: a mimic joint follows its leader and takes no value")
    )]
    FingerCount {
        robot: String,
        what: String,
        expected: usize,
        got: usize,
        joints: String,
        #[label("expected {expected} value{}", if *expected == 1 { "" } else { "s" })]
        span: Span,
    },

    #[error("robot `{robot}` has no finger joints for `{what}` to set")]
    #[diagnostic(
        code(declutter::world::no_fingers),
        help("finger joints are the movable joints of a hand's URDF, and those hanging from the links rigid with the flange in the arm's URDF; a rigid hand needs no posture")
    )]
    NoFingers {
        robot: String,
        what: String,
        #[label("nothing to set")]
        span: Span,
    },

    #[error("grasp `{grasp}` of `{object}`: robot `{robot}` cannot close to {width_mm} mm: {reason}")]
    #[diagnostic(
        code(declutter::world::grasp_width),
        help("`width` sets sliding fingers so that their joint values add up to it (the Panda's two fingers at half the width each); for fingers that turn, give the robot `closed [..]`")
    )]
    GraspWidth {
        robot: String,
        object: String,
        grasp: String,
        width_mm: f64,
        reason: String,
        #[label("this width")]
        span: Span,
    },

    #[error(
        "`{what}` of robot `{robot}`: joint `{joint}` = {} is outside its limits {}",
        joint_value(*value, *turns),
        joint_range(*lower, *upper, *turns)
    )]
    #[diagnostic(code(declutter::world::joint_limit))]
    JointLimit {
        robot: String,
        what: String,
        joint: String,
        value: f64,
        lower: f64,
        upper: f64,
        /// A revolute or continuous joint (radians, shown in degrees too), not a prismatic one (metres).
        turns: bool,
        #[label("`{joint}` must lie in {}", joint_range(*lower, *upper, *turns))]
        span: Span,
        index: usize,
    },

    #[error("`{what}` of robot `{robot}`: joint `{joint}` {moves}, but its value is written as {written}")]
    #[diagnostic(
        code(declutter::world::joint_unit),
        help("write an angle (`deg` or `rad`) for a joint that turns and a length (`m`, `cm`, `mm`) for one that slides; a bare number is radians or metres by the joint")
    )]
    JointUnit {
        robot: String,
        what: String,
        joint: String,
        moves: &'static str,
        written: &'static str,
        #[label("{written}")]
        span: Span,
    },

    #[error("`{what}` of robot `{robot}` is in collision: {reason}")]
    #[diagnostic(code(declutter::world::config_collides))]
    ConfigCollides {
        robot: String,
        what: String,
        reason: String,
        #[label("this configuration collides")]
        span: Span,
        #[help]
        help: String,
    },
}

impl Located for WorldError {
    fn primary_span(&self) -> Option<Span> {
        Some(match self {
            WorldError::UrdfRead { span, .. }
            | WorldError::UrdfParse { span, .. }
            | WorldError::UrdfEmpty { span, .. }
            | WorldError::UrdfXacro { span, .. }
            | WorldError::UrdfLimit { span, .. }
            | WorldError::NoJoints { span, .. }
            | WorldError::UrdfStructure { span, .. }
            | WorldError::MeshMissing { span, .. }
            | WorldError::MeshLoad { span, .. }
            | WorldError::UnknownFlange { span, .. }
            | WorldError::UnknownLink { span, .. }
            | WorldError::SrdfRead { span, .. }
            | WorldError::BodiesOverlap { span, .. }
            | WorldError::SrdfParse { span, .. }
            | WorldError::SrdfLink { span, .. }
            | WorldError::JointCount { span, .. }
            | WorldError::FingerCount { span, .. }
            | WorldError::NoFingers { span, .. }
            | WorldError::GraspWidth { span, .. }
            | WorldError::JointLimit { span, .. }
            | WorldError::JointUnit { span, .. }
            | WorldError::ConfigCollides { span, .. } => *span,
        })
    }

    fn elsewhere(&self) -> Vec<(Span, String)> {
        match self {
            WorldError::BodiesOverlap { elsewhere: Some(s), .. } => vec![(*s, "overlaps this one".to_string())],
            _ => Vec::new(),
        }
    }
}

/// Where a missing mesh was looked for, by the kind of its URI.
pub(crate) fn mesh_missing_help(uri: &str) -> String {
    if uri.starts_with("package://") {
        "`package://NAME/...` is searched in the URDF's folder and its ancestors, then in `--package-path` \
         directories and DECLUTTER_PACKAGE_PATH"
            .to_string()
    } else if uri.starts_with("file://") {
        "`file://` URIs name an absolute path on this machine".to_string()
    } else {
        "a relative path is resolved from the folder of the file that names it".to_string()
    }
}

/// `2.7925 rad (160.0°)` for a turning joint, `0.3000 m` for a sliding one: values are
/// written in degrees more often than in radians.
fn joint_value(v: f64, turns: bool) -> String {
    if turns {
        format!("{v:.4} rad ({:.1}°)", v.to_degrees())
    } else {
        format!("{v:.4} m")
    }
}

fn joint_range(lo: f64, hi: f64, turns: bool) -> String {
    if turns {
        format!("[{lo:.4}, {hi:.4}] rad ([{:.1}°, {:.1}°])", lo.to_degrees(), hi.to_degrees())
    } else {
        format!("[{lo:.4}, {hi:.4}] m")
    }
}
