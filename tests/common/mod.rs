//! Hand-built scenarios and table oracles for the AND/OR graph tests.
#![allow(dead_code)]

pub mod planar;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::PathBuf;

use declutter::diag::{SourceMap, Span};
use declutter::plan::{Answer, Budget, FoundPath, Goal, Oracle, QueryStats, Unreachable};
use declutter::resolve::{
    Body, FileRef, Grasp, JointValues, Object, ObjectId, PlannerSettings, Pose, Robot, RobotId, Scenario, Target,
};
use declutter::world::{Config, JointPath, ObjectSet};

/// A scenario with robots `r1..rN` and objects `o0..oM`, declared one per line in a
/// fake source file (so diagnostics have spans to point at). `target`: `Some(k)` for
/// object `ok`, `None` for a configuration target of robot `config_robot`.
pub fn scenario(robots: usize, objects: usize, target: Option<u32>, config_robot: u32) -> (Scenario, SourceMap) {
    let mut text = String::new();
    let mut spans = Vec::new();
    let line = |text: &mut String, s: String| -> Span {
        let start = text.len();
        text.push_str(&s);
        let span = Span::new(declutter::diag::FileId(0), start, text.len());
        text.push('\n');
        span
    };
    let robot_spans: Vec<Span> =
        (1..=robots).map(|i| line(&mut text, format!("robot r{i} urdf \"arm.urdf\" home [0, 0]"))).collect();
    for j in 0..objects {
        spans.push(line(&mut text, format!("object o{j} {{ box 0.1 0.1 0.1 at [0.{j}, 0, 0] grasp top }}")));
    }
    let target_span = match target {
        Some(k) => line(&mut text, format!("target o{k}")),
        None => line(&mut text, format!("target r{} at [0.5, -0.5]", config_robot + 1)),
    };
    let q_span = Span::new(declutter::diag::FileId(0), target_span.start as usize + 10, target_span.end as usize);
    let robots = robot_spans
        .iter()
        .enumerate()
        .map(|(i, span)| Robot {
            name: format!("r{}", i + 1),
            span: *span,
            urdf: FileRef { path: PathBuf::from("arm.urdf"), written: "arm.urdf".into(), span: *span },
            pose_world_base: Pose::identity(),
            hand: None,
            flange: None,
            srdf: None,
            home: JointValues { values: vec![0.0, 0.0], span: *span, units: Vec::new() },
            drop: None,
            allow_contact: vec![],
            open: None,
            closed: None,
        })
        .collect();
    let objects = spans
        .iter()
        .enumerate()
        .map(|(j, span)| Object {
            body: Body { name: format!("o{j}"), span: *span, pose_world_body: Pose::identity(), parts: vec![] },
            grasps: vec![Grasp {
                name: "top".into(),
                span: *span,
                pose_object_tcp: Pose::identity(),
                pose_world_tcp: Pose::identity(),
                approach: 0.05,
                hands: None,
                width: None,
            }],
        })
        .collect();
    let target = match target {
        Some(k) => Target::Object { object: ObjectId(k), span: target_span },
        None => Target::Config {
            robot: RobotId(config_robot),
            q: JointValues { values: vec![0.5, -0.5], span: q_span, units: Vec::new() },
            span: target_span,
        },
    };
    let scn = Scenario {
        name: Some("hand-built".into()),
        root: PathBuf::from("hand-built.dcl"),
        hands: vec![],
        robots,
        fixed: vec![],
        objects,
        target,
        planner: PlannerSettings::default(),
    };
    let mut sources = SourceMap::new();
    sources.add("hand-built.dcl", "hand-built.dcl", text);
    (scn, sources)
}

/// `None` is the configuration target.
type Key = (u32, Option<u32>);

/// A table of answers; asking anything not in it panics, so tests pin exactly which
/// queries the expansion makes.
#[derive(Default)]
pub struct Table {
    rows: BTreeMap<Key, Result<Vec<u32>, Unreachable>>,
    /// Rows whose removals only the roadmap asked for (none forced).
    roadmap: Vec<Key>,
    pub asked: RefCell<Vec<(u32, Option<u32>)>>,
}

impl Table {
    pub fn new() -> Table {
        Table::default()
    }
    /// Robot `r` (1-based, like the paper's R1, R2) grasps object `o` once `so` are removed.
    pub fn path(mut self, r: u32, o: u32, so: &[u32]) -> Table {
        self.rows.insert((r - 1, Some(o)), Ok(so.to_vec()));
        self
    }
    /// Like [`Table::path`], but only the roadmap asked for the removals: a bigger one
    /// might find a way around them.
    pub fn roadmap_path(mut self, r: u32, o: u32, so: &[u32]) -> Table {
        self.roadmap.push((r - 1, Some(o)));
        self.path(r, o, so)
    }
    pub fn null(mut self, r: u32, o: u32, why: Unreachable) -> Table {
        self.rows.insert((r - 1, Some(o)), Err(why));
        self
    }
    /// Robot `r` reaches the configuration target once `so` are removed.
    pub fn reach(mut self, r: u32, so: &[u32]) -> Table {
        self.rows.insert((r - 1, None), Ok(so.to_vec()));
        self
    }
    pub fn null_reach(mut self, r: u32, why: Unreachable) -> Table {
        self.rows.insert((r - 1, None), Err(why));
        self
    }
    /// The queries asked, 1-based robots, in order.
    pub fn asked(&self) -> Vec<(u32, Option<u32>)> {
        self.asked.borrow().iter().map(|(r, o)| (r + 1, *o)).collect()
    }
}

impl Oracle for Table {
    fn find_path(&self, robot: RobotId, goal: &Goal) -> Answer {
        let o = match goal {
            Goal::Grasp(o) => Some(o.0),
            Goal::Reach(_) => None,
        };
        self.asked.borrow_mut().push((robot.0, o));
        let row = self.rows.get(&(robot.0, o)).unwrap_or_else(|| panic!("unexpected query: robot {robot:?} {goal:?}"));
        let n = self.asked.borrow().len() as u64;
        let stats = QueryStats {
            robot: format!("r{}", robot.0 + 1),
            object: o.map_or("target".into(), |o| format!("o{o}")),
            time_ms: 1.5 * n as f64,
            samples: 100 * n,
            connected: 60 * n,
            paths: 1,
            checks: 1000 * n,
            reused_vertices: 0,
        };
        let r = f64::from(robot.0);
        let x = f64::from(o.unwrap_or(9)) / 10.0;
        let result = row.clone().map(|so| FoundPath {
            grasp: o.map(|_| 0),
            approach: JointPath(vec![Config(vec![0.0, 0.0]), Config(vec![x, r + 0.25])]),
            retreat: if o.is_some() {
                JointPath(vec![Config(vec![x, r + 0.25]), Config(vec![-1.0, 0.5]), Config(vec![0.0, 0.0])])
            } else {
                JointPath(vec![])
            },
            removals: so.iter().copied().map(ObjectId).collect::<ObjectSet>(),
            // A table's removals are facts about the item unless marked as the roadmap's.
            forced: if self.roadmap.contains(&(robot.0, o)) {
                ObjectSet::new()
            } else {
                so.into_iter().map(ObjectId).collect::<ObjectSet>()
            },
        });
        Answer { result, stats }
    }
}

/// A query that stopped at the default sampling budget without a path (not a proof).
pub fn gave_up() -> Unreachable {
    Unreachable::BudgetExhausted(Budget { samples: 5000, max_samples: 5000, extensions: 0, timed_out: false })
}

/// Figure 2, with O5 free for both robots (Figure 3's solution).
pub fn figure_2_table() -> Table {
    Table::new()
        .path(1, 0, &[1])
        .path(2, 0, &[2])
        .path(1, 1, &[3, 4])
        .path(2, 1, &[5])
        .path(1, 2, &[6])
        .null(2, 2, Unreachable::NoGraspSolution)
        .path(1, 5, &[])
        .path(2, 5, &[])
}

/// Example 1 (Figure 6c): the lid blocks the can for both robots.
pub fn example_1_table() -> Table {
    Table::new().path(1, 0, &[1]).path(2, 0, &[1]).path(1, 1, &[]).path(2, 1, &[])
}

/// Example 3 (Figure 10b).
pub fn example_3_table() -> Table {
    Table::new()
        .path(1, 0, &[4, 5])
        .path(2, 0, &[5, 1])
        .null(1, 5, Unreachable::NoGraspSolution)
        .path(2, 5, &[2])
        .path(1, 4, &[])
        .path(2, 4, &[])
        .path(1, 1, &[3])
        .path(2, 1, &[])
        .null(1, 2, Unreachable::NoGraspSolution)
        .path(2, 2, &[])
}

pub fn cycle_table() -> Table {
    // The can needs O1 out of the way; O1 can only be taken by R1 once O2 is gone, and
    // O2 only once O1 is gone.
    Table::new()
        .path(1, 0, &[1])
        .path(2, 0, &[1])
        .path(1, 1, &[2])
        .null(2, 1, Unreachable::NoGraspSolution)
        .path(1, 2, &[1])
        .path(2, 2, &[1])
}
