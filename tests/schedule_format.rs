//! The schedule format (YAML, JSON) and the DOT drawing of G, on hand-built answers.

mod common;

use common::{cycle_table, example_1_table, example_3_table, figure_2_table, scenario, Table};
use declutter::plan::andor::{solve, Flag};
use declutter::schedule::{build, to_dot, to_json, to_yaml, Schedule, Status, TargetSpec};

const KEYS: [&str; 10] =
    ["scenario", "status", "seed", "objective", "target", "removed", "actions", "graph", "stats", "reason"];

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
    assert_eq!(s.removed, ["o2", "o4", "o5", "o0"]);
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
    let mut want: Vec<&str> = KEYS[..9].to_vec();
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
