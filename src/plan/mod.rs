//! Plan: World -> PRMwO roadmaps, `findPath` answers, and the AND/OR precedence graph.
//!
//! The roadmap side answers "how can robot R grasp object O, and what must be removed
//! first?" ([`Answer`]); the graph side combines those answers across robots and
//! objects into an assignment of remove-actions. The two meet only through
//! [`Oracle`], so the graph logic can be tested on hand-built answers.
//!
//! Roadmap side: [`Planner`] holds one [`RobotPlanner`] per robot of a `World` and
//! implements [`Oracle`]; `Planner::find_path_with` picks the objective per query so
//! `fewest_removals` and the paper's `fewest_vertices` can be compared on one roadmap.
//! [`RobotPlanner`] works over any [`Space`] (a robot of a `World` via [`RobotSpace`],
//! or exact test geometry).

mod chains;
mod knn;
mod layers;
mod mask;
mod planner;
mod prm;
mod roadmap;
mod search;
mod space;

pub use planner::{Planner, RobotSpace};
pub use prm::{PrmOptions, RobotPlanner};
pub use space::{Mode, Space};

use serde::Serialize;

pub mod andor;

/// The planner's hash maps and sets. Their keys (label keys, node numbers) are hashed
/// millions of times a query, and std's SipHash spent 7-10 % of a large problem's time
/// there; foldhash's fixed-seed hasher is a few times cheaper and has no per-process seed.
/// Nothing reads these in their iteration order, so outputs do not depend on the hasher.
pub(crate) type Map<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;
pub(crate) type Set<K> = std::collections::HashSet<K, foldhash::fast::FixedState>;

use crate::resolve::{ObjectId, RobotId};
use crate::world::{Blocker, Config, JointPath, ObjectSet};

/// What a query asks a robot to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Goal {
    /// Grasp this object and carry it to the drop configuration.
    Grasp(ObjectId),
    /// Reach this configuration (a `target ROBOT at [...]`).
    Reach(Config),
}

/// Why a robot cannot do a goal (the paper's Null flag): a proof that it cannot, with
/// the cause where one is known, or [`Unreachable::BudgetExhausted`], which proves nothing.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Unreachable {
    /// No grasp of the object has an inverse-kinematics solution for this robot
    /// (or every solution collides with a fixed body).
    NoGraspSolution,
    /// As [`Unreachable::NoGraspSolution`], with the world's reason for this robot: out of
    /// reach, every inverse-kinematics solution hits a named body, or no grasp fits its hand.
    NoGrasp { why: String },
    /// Grasp configurations exist, but every pre-grasp, straight approach or retreat
    /// carrying the object hits something fixed: what the first hit of each grasp was
    /// (one entry per distinct block, in grasp order).
    ApproachBlocked { blockers: Vec<Blocker> },
    /// The goal configuration itself is outside a joint's limits or hits something fixed.
    GoalBlocked(Blocker),
    /// Where carried objects are released (the drop configuration, or home) hits
    /// something fixed.
    DropBlocked(Blocker),
    /// Not a proof: the roadmap grew to its budget without a path to any goal.
    BudgetExhausted(Budget),
}

impl Unreachable {
    /// Whether this is a proof that the goal cannot be done (whatever the budget).
    pub fn is_proof(&self) -> bool {
        !matches!(self, Unreachable::BudgetExhausted(_))
    }
}

/// How far a query that found nothing went (deterministic figures only; the time
/// spent is in the answer's [`QueryStats`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Budget {
    /// Samples the robot's roadmap had drawn when the query gave up.
    pub samples: u64,
    /// The `max_samples` setting.
    pub max_samples: u64,
    /// Extension attempts of the free-space RRT-Connect trees grown beside the roadmap
    /// (0 when none grew: the query stopped in its first two rounds, or home or every
    /// goal touches something).
    pub extensions: u64,
    /// Stopped by the `time_budget` setting before `max_samples` was reached.
    pub timed_out: bool,
}

/// A found path and the removable objects it touches (the paper's P_ij and SO_ij).
#[derive(Clone, Debug, PartialEq)]
pub struct FoundPath {
    /// Index into the object's `grasps` (`None` for a `Reach` goal).
    pub grasp: Option<usize>,
    /// Home -> pre-grasp -> grasp (or home -> goal configuration).
    pub approach: JointPath,
    /// Grasp -> pre-grasp -> drop -> home, carrying the object (empty for `Reach`).
    pub retreat: JointPath,
    /// Objects that must be removed first for the whole motion to be collision-free.
    pub removals: ObjectSet,
    /// The removals every path of the query needs, whatever the roadmap: those of the
    /// goal itself (for an object, of every usable grasp's pre-grasp and straight move
    /// in and out). The rest of `removals` come from the roadmap, and a bigger budget
    /// may find a way around them.
    pub forced: ObjectSet,
}

/// Per-query figures, as in the paper's Table 1.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct QueryStats {
    pub robot: String,
    pub object: String,
    pub time_ms: f64,
    /// Samples generated by this query (0 when a reused roadmap already answered it).
    pub samples: u64,
    /// Samples that joined the roadmap.
    pub connected: u64,
    /// Grasp paths computed (one per reachable grasp tried).
    pub paths: u64,
    /// Collision checks performed (configurations, including segment steps).
    pub checks: u64,
    /// Roadmap vertices already present when the query started (reuse).
    pub reused_vertices: u64,
}

/// The answer of one `findPath(R_i, O_j)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Answer {
    pub result: Result<FoundPath, Unreachable>,
    pub stats: QueryStats,
}

/// Answers `findPath` queries. The planner implements it on real roadmaps; tests of
/// the graph logic implement it with tables.
pub trait Oracle {
    fn find_path(&self, robot: RobotId, goal: &Goal) -> Answer;

    /// Answers several queries, in order. The AND/OR graph asks all robots about one
    /// node at once through this, so a planner may answer them in parallel; the
    /// answers must not depend on how they are scheduled.
    fn find_paths(&self, queries: &[(RobotId, Goal)]) -> Vec<Answer> {
        queries.iter().map(|(robot, goal)| self.find_path(*robot, goal)).collect()
    }
}
