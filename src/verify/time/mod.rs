//! The replay in time: every robot at its interpolated configuration at every
//! sampled instant, at once.
//!
//! In: the [`World`] and a [`Timeline`] (per-robot timed trajectories, grasp and
//! release events, the actions' intervals and waypoints), read from a timed schedule.
//! Out: the violations found, each naming the instant, the robots and bodies, and what
//! was hit.
//!
//! Between two points of a trajectory each joint follows the cubic Hermite curve
//! through both points' positions and velocities ([`hermite`]). The sampling is the
//! verifier's own, independent of the scenario's `resolution`: each stretch between
//! trajectory points is cut into windows, and in each the step is chosen so that no
//! point of any robot body, or of an object a robot carries, moves more than
//! [`SAMPLE_BOUND`] between consecutive samples (from the window's exact peak joint
//! speeds, and each joint's reach there: [`AxisReach`] at the window's ends, never more
//! than [`JointReach`], which holds everywhere). At each sample:
//! robot–robot, robot–carried object, carried–carried, robot–fixed, robot–object in
//! place, carried–scene, and self-collision over every link pair but the URDF's
//! adjacent ones and `allow_contact` (no sampled pruning). Objects are in place until
//! their grasp event, move with the hand until their release event, and are gone after.
//!
//! [`JointReach`]: crate::world::JointReach
//! [`AxisReach`]: crate::world::AxisReach

mod advance;
mod events;
pub mod from_schedule;
mod grid;
pub mod hermite;
pub mod read;
mod replay;
mod scene;
mod track;
mod violation;

pub use violation::{EventKind, Obstacle, Party, TimeViolation};

use crate::resolve::{ObjectId, RobotId};
use crate::world::World;

use super::Violation;

/// No point of any robot body or carried object moves more than this (metres) between
/// two consecutive samples of the replay.
pub const SAMPLE_BOUND: f64 = 2e-3;

/// Slack on velocity and acceleration limits, relative, for values written out and read back.
pub const RATE_TOLERANCE: f64 = 1e-6;

/// How close (joint space, max over joints) a trajectory point must be to an action's
/// waypoint, or to the grasp or drop configuration at an event, to count as there.
pub const WAYPOINT_TOLERANCE: f64 = 1e-6;

/// Slack on times compared across the schedule (seconds).
pub const TIME_TOLERANCE: f64 = 1e-9;

/// One point of a timed trajectory: time from the schedule's start, positions and velocities.
#[derive(Clone, Debug, PartialEq)]
pub struct TimedPoint {
    pub t: f64,
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
}

/// One robot's timed trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    pub robot: RobotId,
    pub points: Vec<TimedPoint>,
}

/// A grasp or release, as the schedule states it.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    pub t: f64,
    pub robot: RobotId,
    pub kind: EventKind,
    pub object: ObjectId,
    /// The finger joints' values from this instant (empty for a rigid hand).
    pub fingers: Vec<f64>,
}

/// What the replay needs of one action.
#[derive(Clone, Debug, PartialEq)]
pub struct TimedAction<'a> {
    pub id: u32,
    pub robot: RobotId,
    /// `None` for the reach of a configuration target.
    pub object: Option<ObjectId>,
    /// The grasp's index among the object's grasps (how the fingers close on it).
    pub grasp: usize,
    /// Ids of the actions whose objects must be carried clear before this one starts.
    pub after: &'a [u32],
    pub start: f64,
    pub end: f64,
    pub approach: &'a [Vec<f64>],
    pub retreat: &'a [Vec<f64>],
    /// False for an action already at fault elsewhere: its events still move its object,
    /// but its waypoints, events and start are not judged again.
    pub checked: bool,
}

/// A timed schedule as the replay reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct Timeline<'a> {
    pub makespan: f64,
    pub tracks: Vec<Track>,
    pub events: Vec<Event>,
    pub actions: Vec<TimedAction<'a>>,
}

/// The rates a timed schedule must respect: the scenario's, scaled by its `speed`.
#[derive(Clone, Debug, PartialEq)]
pub struct RateLimits {
    /// Per robot (scenario order), per actuated joint: |qd| at most this (URDF `velocity` × `speed`).
    pub velocity: Vec<Vec<f64>>,
    /// Per robot, per actuated joint: |qdd| at most this (the URDF's `drake:acceleration`
    /// where it has one, else the planner's `acceleration`; × `speed`).
    pub acceleration: Vec<Vec<f64>>,
}

/// How the replay samples and what it demands.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayOptions {
    /// See [`SAMPLE_BOUND`].
    pub bound: f64,
    /// Distance (metres) every moving thing must keep from what it may not touch; 0 asks
    /// only for no contact (overlaps within [`crate::world::CONTACT_TOLERANCE`] allowed).
    pub clearance: f64,
    pub limits: RateLimits,
    /// Check at every step of the bound, never skipping ahead where an instant proves
    /// that nothing can come too close before a later one, and run the contact check at
    /// every instant even where the bounds prove it clear: slower, and what the skipping
    /// is tested against (it finds the same, at the same instants).
    pub every_step: bool,
    /// Take every pair's bound at every instant when skipping ahead, rather than only the
    /// pairs whose bounds can matter, and measure every shape pair on its own, rather than
    /// a spherized body's balls together: slower, and what the faster way is tested
    /// against (it skips to the same instants).
    pub every_pair: bool,
    /// Keep every instant sampled in [`ReplaySummary::instants`] (for tests of the
    /// sampling itself).
    pub record_instants: bool,
}

/// What a replay looked at.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReplaySummary {
    /// Instants at which the whole cell was checked.
    pub samples: u64,
    /// Those instants in the order sampled (the fingers' postures at grasps and releases
    /// last), when [`ReplayOptions::record_instants`] asks for them.
    pub instants: Vec<f64>,
}

/// Replays the timeline; returns what it checked and every violation found.
pub fn replay(world: &World, tl: &Timeline, opts: &ReplayOptions) -> (ReplaySummary, Vec<Violation>) {
    let mut out = Vec::new();
    let tracks_ok = track::check_tracks(world, tl, &opts.limits, &mut out);
    let mut summary = ReplaySummary::default();
    if !tracks_ok {
        // Interpolating malformed trajectories would only repeat their faults as collisions.
        return (summary, out);
    }
    let by_robot = track::by_robot(world, tl);
    let marks = events::check_actions(world, tl, &by_robot, &mut out);
    summary.samples = replay::run(world, tl, &by_robot, &marks, opts, &mut out, &mut summary.instants);
    (summary, out)
}
