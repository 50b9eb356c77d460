//! MoveIt's planning scene and motion-plan request, as their YAML spells them
//! (`moveit_msgs/PlanningScene`, `moveit_msgs/MotionPlanRequest`). Only the fields
//! declutter uses are typed; [`unsupported`] names every other field that carries data.

use serde::Deserialize;
use serde_json::Value;
use serde_saphyr::Spanned;

#[derive(Debug, Default, Deserialize)]
pub struct PlanningScene {
    #[serde(default)]
    pub name: Option<String>,
    #[serde(default)]
    pub robot_state: Option<RobotState>,
    #[serde(default)]
    pub world: Option<WorldMsg>,
    #[serde(default)]
    pub allowed_collision_matrix: Option<Acm>,
}

#[derive(Debug, Default, Deserialize)]
pub struct WorldMsg {
    #[serde(default)]
    pub collision_objects: Vec<CollisionObject>,
}

#[derive(Debug, Deserialize)]
pub struct CollisionObject {
    pub id: Spanned<String>,
    #[serde(default)]
    pub header: Header,
    /// The object's pose (MoveIt ≥ 1.1); its shapes' poses are relative to it.
    #[serde(default)]
    pub pose: Option<PoseMsg>,
    #[serde(default)]
    pub primitives: Vec<Primitive>,
    #[serde(default)]
    pub primitive_poses: Vec<PoseMsg>,
    #[serde(default)]
    pub meshes: Vec<MeshMsg>,
    #[serde(default)]
    pub mesh_poses: Vec<PoseMsg>,
    /// 0 add, 1 remove, 2 append, 3 move.
    #[serde(default)]
    pub operation: u8,
}

#[derive(Debug, Default, Deserialize)]
pub struct Header {
    #[serde(default)]
    pub frame_id: String,
}

#[derive(Debug, Clone, Copy, Default, Deserialize)]
pub struct PointMsg {
    #[serde(default)]
    pub x: f64,
    #[serde(default)]
    pub y: f64,
    #[serde(default)]
    pub z: f64,
}

#[derive(Debug, Clone, Copy, Deserialize)]
pub struct QuatMsg {
    #[serde(default)]
    pub x: f64,
    #[serde(default)]
    pub y: f64,
    #[serde(default)]
    pub z: f64,
    #[serde(default = "one")]
    pub w: f64,
}

fn one() -> f64 {
    1.0
}

impl Default for QuatMsg {
    fn default() -> Self {
        QuatMsg { x: 0.0, y: 0.0, z: 0.0, w: 1.0 }
    }
}

#[derive(Debug, Clone, Copy, Default, Deserialize)]
pub struct PoseMsg {
    #[serde(default)]
    pub position: PointMsg,
    #[serde(default)]
    pub orientation: QuatMsg,
}

/// `shape_msgs/SolidPrimitive`: BOX 1 [x, y, z], SPHERE 2 [r], CYLINDER 3 [height, radius], CONE 4.
#[derive(Debug, Deserialize)]
pub struct Primitive {
    #[serde(rename = "type")]
    pub kind: Spanned<u8>,
    #[serde(default)]
    pub dimensions: Vec<f64>,
}

#[derive(Debug, Deserialize)]
pub struct MeshMsg {
    #[serde(default)]
    pub triangles: Vec<Triangle>,
    #[serde(default)]
    pub vertices: Vec<PointMsg>,
}

#[derive(Debug, Deserialize)]
pub struct Triangle {
    pub vertex_indices: Spanned<Vec<u64>>,
}

#[derive(Debug, Default, Deserialize)]
pub struct Acm {
    #[serde(default)]
    pub entry_names: Vec<String>,
    #[serde(default)]
    pub entry_values: Vec<AcmRow>,
}

#[derive(Debug, Default, Deserialize)]
pub struct AcmRow {
    #[serde(default)]
    pub enabled: Vec<bool>,
}

#[derive(Debug, Default, Deserialize)]
pub struct RobotState {
    #[serde(default)]
    pub joint_state: JointState,
}

#[derive(Debug, Default, Deserialize)]
pub struct JointState {
    #[serde(default)]
    pub name: Vec<String>,
    #[serde(default)]
    pub position: Vec<f64>,
}

#[derive(Debug, Default, Deserialize)]
pub struct MotionPlanRequest {
    #[serde(default)]
    pub start_state: Option<RobotState>,
    #[serde(default)]
    pub goal_constraints: Vec<Constraints>,
    /// MoveIt's scaling of the joints' velocity and acceleration limits; 0 (or absent) is unset.
    #[serde(default)]
    pub max_velocity_scaling_factor: f64,
    #[serde(default)]
    pub max_acceleration_scaling_factor: f64,
}

#[derive(Debug, Default, Deserialize)]
pub struct Constraints {
    #[serde(default)]
    pub joint_constraints: Vec<JointConstraint>,
}

#[derive(Debug, Deserialize)]
pub struct JointConstraint {
    pub joint_name: Spanned<String>,
    pub position: f64,
}

/// The fields each message kind is read for; `*` descends into every list element.
/// Fields outside these that hold data (anything but null, 0, false, "", [] or {}) are
/// reported, by their path, as not imported.
const SCENE_FIELDS: &[(&str, &[&str])] = &[
    ("", &["name", "robot_state", "robot_model_name", "world", "allowed_collision_matrix", "is_diff"]),
    ("robot_state", &["joint_state", "is_diff"]),
    ("robot_state.joint_state", &["header", "name", "position", "velocity", "effort"]),
    ("world", &["collision_objects"]),
    (
        "world.collision_objects.*",
        &["id", "header", "pose", "type", "primitives", "primitive_poses", "meshes", "mesh_poses", "operation"],
    ),
    ("world.collision_objects.*.primitives.*", &["type", "dimensions"]),
    ("world.collision_objects.*.meshes.*", &["triangles", "vertices"]),
    ("allowed_collision_matrix", &["entry_names", "entry_values"]),
];

const REQUEST_FIELDS: &[(&str, &[&str])] = &[
    (
        "",
        &[
            "start_state",
            "goal_constraints",
            "group_name",
            "num_planning_attempts",
            "allowed_planning_time",
            "max_velocity_scaling_factor",
            "max_acceleration_scaling_factor",
        ],
    ),
    ("start_state", &["joint_state", "is_diff"]),
    ("start_state.joint_state", &["header", "name", "position", "velocity", "effort"]),
    ("goal_constraints.*", &["name", "joint_constraints"]),
    (
        "goal_constraints.*.joint_constraints.*",
        &["joint_name", "position", "tolerance_above", "tolerance_below", "weight"],
    ),
];

/// Which of a scene's (or, with `request`, a request's) fields carrying data are not imported.
pub fn unsupported(doc: &Value, request: bool) -> Vec<String> {
    let table = if request { REQUEST_FIELDS } else { SCENE_FIELDS };
    let mut out = Vec::new();
    walk(doc, "", "", table, &mut out);
    out
}

/// `pattern` is the path with list indices as `*`, `path` the same with the indices.
fn walk(v: &Value, pattern: &str, path: &str, table: &[(&str, &[&str])], out: &mut Vec<String>) {
    let join = |a: &str, b: &str| if a.is_empty() { b.to_string() } else { format!("{a}.{b}") };
    match v {
        Value::Object(map) => {
            let Some((_, known)) = table.iter().find(|(p, _)| *p == pattern) else { return };
            for (k, child) in map {
                if known.contains(&k.as_str()) {
                    walk(child, &join(pattern, k), &join(path, k), table, out);
                } else if !empty(child) && !empty_octomap(k, child) {
                    out.push(join(path, k));
                }
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                walk(child, &join(pattern, "*"), &format!("{path}[{i}]"), table, out);
            }
        }
        _ => {}
    }
}

/// MoveIt writes an empty octomap with an identity origin (`w: 1`): no data is no map.
fn empty_octomap(key: &str, v: &Value) -> bool {
    key == "octomap" && v.pointer("/octomap/data").is_none_or(empty)
}

/// A value MoveIt writes for a field left at its default.
fn empty(v: &Value) -> bool {
    match v {
        Value::Null => true,
        Value::Bool(b) => !b,
        Value::Number(n) => n.as_f64() == Some(0.0),
        Value::String(s) => s.is_empty(),
        Value::Array(a) => a.iter().all(empty),
        Value::Object(m) => m.values().all(empty),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unsupported_fields_are_named_by_path_and_empty_defaults_are_not() {
        let doc: Value = serde_json::json!({
            "name": "s",
            "link_padding": [],
            "fixed_frame_transforms": [{"child_frame_id": "cam"}],
            "world": {
                "collision_objects": [
                    {"id": "a", "planes": [], "subframe_names": ["tip"], "primitives": [{"type": 1, "dimensions": [1, 1, 1]}]}
                ],
                "octomap": {"octomap": {"data": [1, 2]}}
            }
        });
        assert_eq!(
            unsupported(&doc, false),
            ["fixed_frame_transforms", "world.collision_objects[0].subframe_names", "world.octomap"]
        );
    }
}
