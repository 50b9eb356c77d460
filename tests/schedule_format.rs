//! The schedule format (YAML, JSON) and the DOT drawing of G, on hand-built answers.

mod common;

use common::{cycle_table, example_1_table, example_3_table, figure_2_table, scenario, Table};
use declutter::plan::andor::Solution;
use declutter::plan::andor::{solve, Flag};
use declutter::resolve::Scenario;
use declutter::schedule::{self, to_dot, to_json, to_yaml, EventKind, Execution, Schedule, Status, TargetSpec};
use declutter::timing::{self, Limits, RobotTiming};

const KEYS: [&str; 15] = [
    "schedule_version",
    "scenario",
    "status",
    "seed",
    "objective",
    "execution",
    "target",
    "removed",
    "makespan",
    "actions",
    "trajectories",
    "events",
    "graph",
    "stats",
    "reason",
];

/// Two-joint robots at 1 rad/s and 1 rad/s², home and drop at [0, 0], timed sequentially.
fn build(scn: &Scenario, sol: &Solution) -> Schedule {
    let robots: Vec<RobotTiming> = scn
        .robots
        .iter()
        .map(|_| RobotTiming {
            joint_names: vec!["j1".into(), "j2".into()],
            limits: Limits { velocity: vec![1.0; 2], acceleration: vec![1.0; 2] },
            home: vec![0.0, 0.0],
            drop: vec![0.0, 0.0],
        })
        .collect();
    schedule::build_with(scn, sol, Execution::Sequential, |m| timing::sequential(&robots, m))
}

fn top_level_keys(json: &str) -> Vec<String> {
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    v.as_object().unwrap().keys().cloned().collect()
}

#[test]
fn example_3_yaml() {
    let (scn, _) = scenario(2, 6, Some(0), 0);
    let sol = solve(&scn, &example_3_table());
    let s = build(&scn, &sol);
    assert_eq!(s.status, Status::Solved);
    assert_eq!(s.removed, ["o2", "o4", "o5"], "the target `o0` is `target`, not removed");
    assert_eq!(s.actions.iter().map(|a| a.after.clone()).collect::<Vec<_>>(), [vec![], vec![], vec![1], vec![2, 3]]);
    assert_eq!(s.graph[2].flags["r1"], Flag::Null);
    assert_eq!(s.graph[0].blocked_by["r2"], ["o1", "o5"]);
    assert_eq!(s.stats.len(), 10);
    let yaml = to_yaml(&s).unwrap();
    insta::assert_snapshot!(yaml);
    let back: Schedule = serde_saphyr::from_str(&yaml).unwrap();
    assert_eq!(back, s);
}

#[test]
fn example_1_json() {
    let (scn, _) = scenario(2, 2, Some(0), 0);
    let sol = solve(&scn, &example_1_table());
    let s = build(&scn, &sol);
    let json = to_json(&s).unwrap();
    let mut keys = top_level_keys(&json);
    keys.sort();
    let mut want: Vec<&str> = KEYS[..14].to_vec();
    want.sort();
    assert_eq!(keys, want);
    insta::assert_snapshot!(json);
    let back: Schedule = serde_json::from_str(&json).unwrap();
    assert_eq!(back, s);
}

#[test]
fn infeasible_yaml_carries_reason() {
    let (scn, _) = scenario(2, 3, Some(0), 0);
    let sol = solve(&scn, &cycle_table());
    let s = build(&scn, &sol);
    assert_eq!(s.status, Status::Infeasible);
    assert!(s.actions.is_empty() && s.removed.is_empty());
    assert_eq!(
        s.reason.as_deref(),
        Some(
            "`o0` cannot be reached: grasping `o1` with `r1` needs `o2` removed first, and grasping `o2` with \
             `r1` needs `o1` removed first: they block each other"
        )
    );
    let json = to_json(&s).unwrap();
    assert_eq!(top_level_keys(&json).len(), KEYS.len());
    let yaml = to_yaml(&s).unwrap();
    insta::assert_snapshot!(yaml);
    let back: Schedule = serde_saphyr::from_str(&yaml).unwrap();
    assert_eq!(back, s);
}

#[test]
fn configuration_target_yaml() {
    let (scn, _) = scenario(2, 2, None, 1);
    let t = Table::new().reach(2, &[1]).path(1, 1, &[]).path(2, 1, &[]);
    let s = build(&scn, &solve(&scn, &t));
    assert_eq!(s.target, TargetSpec::Config { robot: "r2".into(), q: vec![0.5, -0.5] });
    assert_eq!(s.actions[1].object, None);
    assert_eq!(s.actions[1].grasp, None);
    assert!(s.actions[1].retreat.is_empty());
    let yaml = to_yaml(&s).unwrap();
    insta::assert_snapshot!(yaml);
    let back: Schedule = serde_saphyr::from_str(&yaml).unwrap();
    assert_eq!(back, s);
}

#[test]
fn sequential_times_chain_and_trajectories_cover_the_makespan() {
    let (scn, _) = scenario(2, 6, Some(0), 0);
    let s = build(&scn, &solve(&scn, &example_3_table()));
    assert_eq!(s.schedule_version, 2);
    assert_eq!(s.execution, Execution::Sequential);
    assert_eq!(s.actions[0].start, 0.0);
    for w in s.actions.windows(2) {
        assert_eq!(w[1].start, w[0].end, "sequential: each action starts when the previous ended");
    }
    assert_eq!(s.makespan, s.actions.last().unwrap().end);
    for t in &s.trajectories {
        assert_eq!(t.points.first().unwrap().t, 0.0);
        assert_eq!(t.points.last().unwrap().t, s.makespan);
        assert!(t.points.windows(2).all(|w| w[0].t < w[1].t), "strictly increasing times");
    }
    // Four object actions: a grasp and a release each, in time order.
    assert_eq!(s.events.len(), 8);
    assert!(s.events.windows(2).all(|w| w[0].t <= w[1].t));
    assert_eq!(s.events[0].kind, EventKind::Grasp);
    assert_eq!(s.events[0].t, s.actions[0].start + (s.actions[0].end - s.actions[0].start) - retreat_time(&s, 0));
}

/// Hand-computed duration of the retreat of action `i` ([g → (-1, 0.5) → (0, 0)], 1 rad/s,
/// 1 rad/s²): a segment of largest joint travel d ≥ 1 rad takes d + 1 s, a shorter one 2√d s.
fn retreat_time(s: &Schedule, i: usize) -> f64 {
    let seg = |a: &[f64], b: &[f64]| {
        let d = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        if d >= 1.0 {
            d + 1.0
        } else {
            2.0 * d.sqrt()
        }
    };
    s.actions[i].retreat.windows(2).map(|w| seg(&w[0], &w[1])).sum()
}

#[test]
fn configuration_target_reach_is_timed_by_hand() {
    // r2 (index 1) reaches [0.9, 1.25] from [0, 0]: joint 2 travels 1.25 rad ≥ 1 rad, so
    // a trapezoid of 1.25 + 1 = 2.25 s; joint 1 follows at 0.9/1.25 of its speed.
    let (scn, _) = scenario(2, 2, None, 1);
    let t = Table::new().reach(2, &[1]).path(1, 1, &[]).path(2, 1, &[]);
    let s = build(&scn, &solve(&scn, &t));
    let reach = &s.actions[1];
    assert!((reach.end - reach.start - 2.25).abs() < 1e-12, "{} .. {}", reach.start, reach.end);
    let traj = &s.trajectories[1];
    let peak = traj.points.iter().filter(|p| p.t > reach.start).map(|p| p.qd[1]).fold(0.0, f64::max);
    assert!((peak - 1.0).abs() < 1e-12, "joint 2 cruises at its 1 rad/s limit");
}

#[test]
fn unknown_keys_are_rejected() {
    let (scn, _) = scenario(2, 2, Some(0), 0);
    let s = build(&scn, &solve(&scn, &example_1_table()));
    let mut v: serde_json::Value = serde_json::from_str(&to_json(&s).unwrap()).unwrap();
    v["actions"][0]["speed"] = serde_json::json!(1.0);
    assert!(serde_json::from_value::<Schedule>(v.clone()).is_err());
    v["actions"][0].as_object_mut().unwrap().remove("speed");
    v["extra"] = serde_json::json!(true);
    assert!(serde_json::from_value::<Schedule>(v).is_err());
}

#[test]
fn figure_2_dot() {
    let (scn, _) = scenario(2, 7, Some(0), 0);
    let sol = solve(&scn, &figure_2_table());
    let dot = to_dot(&scn, &sol);
    // O1's two R1 children are an AND group through one junction point.
    assert!(dot.contains("n1 -> and1_0"));
    assert!(dot.contains("and1_0 -> n3") && dot.contains("and1_0 -> n4"));
    insta::assert_snapshot!(dot);
}

#[test]
fn example_3_dot() {
    let (scn, _) = scenario(2, 6, Some(0), 0);
    let dot = to_dot(&scn, &solve(&scn, &example_3_table()));
    insta::assert_snapshot!(dot);
}

#[test]
fn cycle_dot() {
    let (scn, _) = scenario(2, 3, Some(0), 0);
    let dot = to_dot(&scn, &solve(&scn, &cycle_table()));
    insta::assert_snapshot!(dot);
}
