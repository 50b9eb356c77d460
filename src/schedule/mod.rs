//! Schedule: a planned [`Solution`] -> the [`Schedule`] a user runs, and its writers.
//!
//! In: the scenario and the solution of [`plan::andor::solve`](crate::plan::andor::solve).
//! Out: a `Schedule` (serde, both ways, so `verify` can read it back), written as YAML
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
use crate::world::JointPath;

/// A whole schedule, exactly the keys of the format (see the book's "Schedule format").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Schedule {
    /// The scenario's name, or its file's stem.
    pub scenario: String,
    pub status: Status,
    pub seed: u64,
    pub objective: Objective,
    pub target: TargetSpec,
    /// Object names in removal order (the target object last).
    pub removed: Vec<String>,
    pub actions: Vec<ScheduledAction>,
    pub graph: Vec<GraphNode>,
    pub stats: Vec<QueryStat>,
    /// Why there is no schedule (only when `status` is `infeasible`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Solved,
    Infeasible,
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
    /// Joint waypoints from home to the grasp (or to the target configuration).
    #[serde(serialize_with = "rows")]
    pub approach: Vec<Vec<f64>>,
    /// Joint waypoints from the grasp to the drop and back home, carrying the object.
    #[serde(serialize_with = "rows")]
    pub retreat: Vec<Vec<f64>>,
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

/// Builds the schedule of a solution.
pub fn build(scn: &Scenario, sol: &Solution) -> Schedule {
    let graph = &sol.graph;
    let target = target_spec(scn);
    let (status, removed, actions, reason) = match &sol.outcome {
        Ok(plan) => {
            let actions = plan
                .actions
                .iter()
                .enumerate()
                .map(|(i, a)| {
                    let found = graph.found(a.robot, a.item).expect("every planned action has a found path");
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
                        approach: waypoints(&found.approach),
                        retreat: waypoints(&found.retreat),
                    }
                })
                .collect();
            let removed = plan.removed().into_iter().map(|o| scn.object(o).body.name.clone()).collect();
            (Status::Solved, removed, actions, None)
        }
        Err(why) => (Status::Infeasible, Vec::new(), Vec::new(), Some(why.reason())),
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
        scenario: scenario_name(scn),
        status,
        seed: scn.planner.seed,
        objective: scn.planner.objective,
        target,
        removed,
        actions,
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
