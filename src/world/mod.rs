//! World: a resolved [`Scenario`] turned into something the planner can query fast.
//!
//! In: a `Scenario` and a [`Loader`]. Out: a [`World`] holding each robot's kinematic
//! chain (from its URDF), the hand attached at the flange, fixed and removable bodies
//! as parry3d shapes, and the labelled collision check PRMwO needs: "at this
//! configuration, is the robot blocked by something fixed, and which removable
//! objects does it touch?". Geometry code never sees spans; errors name ids and the
//! CLI maps them back to declarations.

mod labels;

pub use labels::{Blocker, Check, ObjectSet};

use std::ops::{Deref, DerefMut};

use serde::Serialize;

use crate::resolve::{ObjectId, Pose};

/// A robot configuration: one value per actuated joint, in chain order (radians or metres).
#[derive(Clone, Debug, PartialEq, Serialize, Default)]
#[serde(transparent)]
pub struct Config(pub Vec<f64>);

impl Deref for Config {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.0
    }
}
impl DerefMut for Config {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.0
    }
}
impl From<Vec<f64>> for Config {
    fn from(v: Vec<f64>) -> Config {
        Config(v)
    }
}

/// A sequence of configurations, each segment to be moved along in a straight joint-space line.
#[derive(Clone, Debug, PartialEq, Serialize, Default)]
#[serde(transparent)]
pub struct JointPath(pub Vec<Config>);

/// An object carried by the hand: it moves rigidly with the flange.
#[derive(Clone, Debug, PartialEq)]
pub struct Held {
    pub object: ObjectId,
    /// The object's pose in the flange frame, fixed at the moment of grasping.
    pub pose_flange_object: Pose,
}

/// A reachable grasp of an object by one robot (the paper's `selectGrasps`).
#[derive(Clone, Debug, PartialEq)]
pub struct GraspConfig {
    /// Index into the object's `grasps`.
    pub grasp: usize,
    /// Arm configuration with the TCP at the grasp pose.
    pub q_grasp: Config,
    /// Arm configuration at the approach stand-off, from which the hand moves straight in.
    pub q_pregrasp: Config,
}
