//! Schedule: a planned [`Solution`], timed -> the [`Schedule`] a user runs, and its writers.
//!
//! In: the world and the solution of [`plan::andor::solve`](crate::plan::andor::solve);
//! the actions are placed in time by [`crate::timing`]. Out: a `Schedule`
//! (format version [`SCHEDULE_VERSION`]; serde, both ways, so `verify` can read it back), written as YAML
//! ([`to_yaml`]) or JSON ([`to_json`]), and G as Graphviz DOT ([`to_dot`]). Everything
//! written is in a fixed order: actions in execution order, `after` sorted, graph
//! nodes in creation order, robots in declaration order, statistics in query order.
//! Joint values are written as computed (f64 radians, shortest round-trip form); they
//! are not rounded, so a schedule read back is bit-identical.

mod dot;

pub use dot::to_dot;

use indexmap::IndexMap;
use serde::{Deserialize, Serialize};

use crate::plan::andor::{Flag, Item, Solution};
use crate::resolve::{Objective, Scenario, Target};
use crate::timing::{self, Motion};
use crate::world::{JointPath, World};

pub use crate::timing::{Execution, TrajPoint};

/// The format version this build writes and reads.
pub const SCHEDULE_VERSION: u32 = 2;

/// A whole schedule, exactly the keys of the format (see the book's "Schedule format").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Schedule {
    /// Always [`SCHEDULE_VERSION`] when written by this build.
    pub schedule_version: u32,
    /// The scenario's name, or its file's stem.
    pub scenario: String,
    pub status: Status,
    pub seed: u64,
    pub objective: Objective,
    pub execution: Execution,
    pub target: TargetSpec,
    /// The blocking objects in removal order (not the target, which is `target`).
    pub removed: Vec<String>,
    /// Seconds from the first motion until every robot is idle (0 when infeasible).
    pub makespan: f64,
    pub actions: Vec<ScheduledAction>,
    /// One per robot, in declaration order, each covering 0..makespan.
    pub trajectories: Vec<RobotTrajectory>,
    /// Gripper events in time order (ties: action order).
    pub events: Vec<Event>,
    pub graph: Vec<GraphNode>,
    pub stats: Vec<QueryStat>,
    /// Why there is no schedule (only when `status` is `infeasible` or `gave_up`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Solved,
    /// Proved: no assignment exists (every dead end has a cause that no budget changes).
    Infeasible,
    /// None found within the planning budget; a bigger budget may find one.
    GaveUp,
}

/// The target as written: an object's name, or a robot and its joint values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum TargetSpec {
    Object(String),
    Config { robot: String, q: Vec<f64> },
}

/// One robot motion: approach, grasp, carry away, drop, go home.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScheduledAction {
    /// 1-based, in execution order.
    pub id: u32,
    pub robot: String,
    /// The object grasped (`None` for the reach of a configuration target).
    pub object: Option<String>,
    /// The grasp used, as expanded (`top#2`); `None` for a configuration target.
    pub grasp: Option<String>,
    /// Ids of the actions that must finish before this one starts, ascending.
    pub after: Vec<u32>,
    /// Seconds from the schedule's start when the robot leaves home.
    pub start: f64,
    /// Seconds when it is back home (or, for a configuration target, at the target).
    pub end: f64,
    /// Joint waypoints from home to the grasp (or to the target configuration).
    #[serde(serialize_with = "rows")]
    pub approach: Vec<Vec<f64>>,
    /// Joint waypoints from the grasp to the drop and back home, carrying the object.
    #[serde(serialize_with = "rows")]
    pub retreat: Vec<Vec<f64>>,
}

/// A robot's timed motion: a ROS `trajectory_msgs/JointTrajectory` with the robot's name.
/// Between consecutive points the motion is the cubic Hermite curve through (q, qd).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotTrajectory {
    pub robot: String,
    pub joint_names: Vec<String>,
    pub points: Vec<TrajPoint>,
    /// The gripper's finger joints, which the events set (none for a rigid hand).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub finger_joints: Vec<String>,
}

/// The gripper closes on (`grasp`) or lets go of (`release`) an object at time `t`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Event {
    pub t: f64,
    pub robot: String,
    pub kind: EventKind,
    pub object: String,
    /// The robot's `finger_joints` from this instant: closed on the object at a grasp,
    /// open again at a release (none for a rigid hand).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fingers: Vec<f64>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    Grasp,
    Release,
}

/// One node of G: its object, and per robot its flag and, where a path was found, the
/// objects that path needs removed first.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GraphNode {
    /// The object's name, or `target` for a configuration target.
    pub object: String,
    pub flags: IndexMap<String, Flag>,
    pub blocked_by: IndexMap<String, Vec<String>>,
}

/// Figures of one `findPath` query, in query order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QueryStat {
    pub robot: String,
    pub object: String,
    pub time_ms: f64,
    pub samples: u64,
    pub connected: u64,
    pub paths: u64,
    pub checks: u64,
}

/// One waypoint per line (`- [q1, q2, …]`) in YAML; plain arrays in JSON.
fn rows<S: serde::Serializer>(waypoints: &[Vec<f64>], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = s.serialize_seq(Some(waypoints.len()))?;
    for w in waypoints {
        seq.serialize_element(&serde_saphyr::FlowSeq(w))?;
    }
    seq.end()
}

fn waypoints(p: &JointPath) -> Vec<Vec<f64>> {
    p.0.iter().map(|q| q.0.clone()).collect()
}

/// The scenario's name, or the stem of its file.
pub fn scenario_name(scn: &Scenario) -> String {
    scn.name.clone().unwrap_or_else(|| {
        scn.root.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scenario".to_string())
    })
}

/// The scenario's target as a schedule writes it.
pub fn target_spec(scn: &Scenario) -> TargetSpec {
    match &scn.target {
        Target::Object { object, .. } => TargetSpec::Object(scn.object(*object).body.name.clone()),
        Target::Config { robot, q, .. } => {
            TargetSpec::Config { robot: scn.robot(*robot).name.clone(), q: q.values.clone() }
        }
    }
}

impl std::fmt::Display for TargetSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TargetSpec::Object(name) => write!(f, "object `{name}`"),
            TargetSpec::Config { robot, q } => {
                let q: Vec<String> = q.iter().map(|v| format!("{v:.6}")).collect();
                write!(f, "robot `{robot}` at [{}]", q.join(", "))
            }
        }
    }
}

/// Builds the schedule of a solution, its actions placed in time by `execution`.
pub fn build(world: &World, sol: &Solution, execution: Execution) -> Schedule {
    let mut s = build_with(world.scenario(), sol, execution, |motions| timing::timeline(world, motions, execution));
    // The gripper: its joints, and where each event sets them.
    let scn = world.scenario();
    for tr in &mut s.trajectories {
        if let Some(r) = scn.robot_by_name(&tr.robot) {
            tr.finger_joints = world.finger_names(r).iter().map(|n| n.to_string()).collect();
        }
    }
    for e in &mut s.events {
        let (Some(r), Some(o)) = (scn.robot_by_name(&e.robot), scn.object_by_name(&e.object)) else { continue };
        let posture = match e.kind {
            EventKind::Release => crate::world::OPEN_POSTURE,
            EventKind::Grasp => {
                let grasp =
                    s.actions.iter().find(|a| a.object.as_ref() == Some(&e.object)).and_then(|a| a.grasp.as_deref());
                let g = grasp.and_then(|g| scn.object(o).grasp_index(g)).unwrap_or(usize::MAX);
                world.posture_of(r, o, g)
            }
        };
        e.fingers = world.finger_values(r, posture).to_vec();
    }
    s
}

/// Builds the schedule of a solution, its actions placed in time by `time` (tests
/// without a world pass [`timing::sequential`] over hand-made robots).
pub fn build_with(
    scn: &Scenario,
    sol: &Solution,
    execution: Execution,
    time: impl FnOnce(&[Motion]) -> timing::Timeline,
) -> Schedule {
    let graph = &sol.graph;
    let target = target_spec(scn);
    let mut makespan = 0.0;
    let mut trajectories = Vec::new();
    let mut events = Vec::new();
    let (status, removed, actions, reason) = match &sol.outcome {
        Ok(plan) => {
            let found: Vec<_> = plan
                .actions
                .iter()
                .map(|a| graph.found(a.robot, a.item).expect("every planned action has a found path"))
                .collect();
            let motions: Vec<Motion> = plan
                .actions
                .iter()
                .zip(&found)
                .map(|(a, f)| Motion {
                    robot: a.robot,
                    object: a.item.object(),
                    grasp: f.grasp,
                    approach: &f.approach.0,
                    retreat: &f.retreat.0,
                    after: &a.after,
                })
                .collect();
            let timeline = time(&motions);
            makespan = timeline.makespan;
            trajectories = scn
                .robot_ids()
                .zip(timeline.trajectories)
                .map(|(r, t)| RobotTrajectory {
                    robot: scn.robot(r).name.clone(),
                    joint_names: t.joint_names,
                    points: t.points,
                    finger_joints: Vec::new(),
                })
                .collect();
            for (m, ta) in motions.iter().zip(&timeline.actions) {
                let (Some(o), robot) = (m.object, scn.robot(m.robot).name.clone()) else { continue };
                let object = scn.object(o).body.name.clone();
                if let Some(t) = ta.grasp {
                    events.push(Event {
                        t,
                        robot: robot.clone(),
                        kind: EventKind::Grasp,
                        object: object.clone(),
                        fingers: Vec::new(),
                    });
                }
                if let Some(t) = ta.release {
                    events.push(Event { t, robot, kind: EventKind::Release, object, fingers: Vec::new() });
                }
            }
            events.sort_by(|a, b| a.t.total_cmp(&b.t));
            let actions = plan
                .actions
                .iter()
                .enumerate()
                .map(|(i, a)| {
                    let found = found[i];
                    let timed = &timeline.actions[i];
                    let grasp = match (a.item, found.grasp) {
                        (Item::Object(o), Some(g)) => scn.object(o).grasps.get(g).map(|g| g.name.clone()),
                        _ => None,
                    };
                    ScheduledAction {
                        id: i as u32 + 1,
                        robot: scn.robot(a.robot).name.clone(),
                        object: a.item.object().map(|o| scn.object(o).body.name.clone()),
                        grasp,
                        after: a.after.iter().map(|j| *j as u32 + 1).collect(),
                        start: timed.start,
                        end: timed.end,
                        approach: waypoints(&found.approach),
                        retreat: waypoints(&found.retreat),
                    }
                })
                .collect();
            let target_object = match scn.target {
                Target::Object { object, .. } => Some(object),
                Target::Config { .. } => None,
            };
            let removed = plan
                .removed()
                .into_iter()
                .filter(|o| Some(*o) != target_object)
                .map(|o| scn.object(o).body.name.clone())
                .collect();
            (Status::Solved, removed, actions, None)
        }
        Err(why) => {
            let status = if why.is_proof() { Status::Infeasible } else { Status::GaveUp };
            (status, Vec::new(), Vec::new(), Some(why.reason()))
        }
    };
    // The graph is a tree, so an object can stand under several branches; a repeat that
    // was never analysed (all flags Empty) says nothing its first entry does not, and the
    // list has no edges to place it by, so it is left out.
    let mut listed = std::collections::HashSet::new();
    let nodes = graph
        .nodes()
        .filter(|&n| {
            let node = graph.node(n);
            let first = listed.insert(node.item.name(scn));
            first || node.flags.iter().any(|(_, f)| *f != Flag::Empty)
        })
        .map(|n| {
            let node = graph.node(n);
            let mut flags = IndexMap::new();
            let mut blocked_by = IndexMap::new();
            for (r, f) in &node.flags {
                let robot = scn.robot(*r).name.clone();
                flags.insert(robot.clone(), *f);
                if let (Some(p), true) = (graph.found(*r, node.item), *f != Flag::Empty) {
                    blocked_by.insert(robot, p.removals.iter().map(|o| scn.object(o).body.name.clone()).collect());
                }
            }
            GraphNode { object: node.item.name(scn), flags, blocked_by }
        })
        .collect();
    let stats = graph
        .queries
        .iter()
        .map(|q| QueryStat {
            robot: scn.robot(q.robot).name.clone(),
            object: q.item.name(scn),
            time_ms: q.answer.stats.time_ms,
            samples: q.answer.stats.samples,
            connected: q.answer.stats.connected,
            paths: q.answer.stats.paths,
            checks: q.answer.stats.checks,
        })
        .collect();
    Schedule {
        schedule_version: SCHEDULE_VERSION,
        scenario: scenario_name(scn),
        status,
        seed: scn.planner.seed,
        objective: scn.planner.objective,
        execution,
        target,
        removed,
        makespan,
        actions,
        trajectories,
        events,
        graph: nodes,
        stats,
        reason,
    }
}

/// Errors of the writers (serialisation cannot fail on these types in practice).
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum WriteError {
    #[error("cannot write the schedule as YAML: {message}")]
    #[diagnostic(code(declutter::schedule::yaml))]
    Yaml { message: String },
    #[error("cannot write the schedule as JSON: {message}")]
    #[diagnostic(code(declutter::schedule::json))]
    Json { message: String },
}

/// The schedule as YAML (the default output).
pub fn to_yaml(s: &Schedule) -> Result<String, WriteError> {
    serde_saphyr::to_string(s).map_err(|e| WriteError::Yaml { message: e.to_string() })
}

/// The schedule as pretty-printed JSON, with a final newline.
pub fn to_json(s: &Schedule) -> Result<String, WriteError> {
    serde_json::to_string_pretty(s)
        .map(|mut t| {
            t.push('\n');
            t
        })
        .map_err(|e| WriteError::Json { message: e.to_string() })
}

impl crate::diag::Located for WriteError {
    fn primary_span(&self) -> Option<crate::diag::Span> {
        None
    }
}
