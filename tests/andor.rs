//! The AND/OR graph on hand-built findPath answers: the paper's Figure 2 and the
//! graphs of its three examples (Figures 6c, 8b, 10b), Null and Discarded flags,
//! infeasible cycles and objects, and more than two robots.

mod common;

use common::{cycle_table, example_3_table, scenario, Table};
use declutter::diag::{render_one, RenderOptions};
use declutter::plan::andor::{solve, Cause, Flag, Reason, Solution};
use declutter::plan::Unreachable;
use declutter::resolve::Scenario;
use declutter::world::Blocker;

/// Each node as `object r1:F r2:B`, in creation order, with `<-parent/robot`.
fn nodes(scn: &Scenario, sol: &Solution) -> Vec<String> {
    let g = &sol.graph;
    g.nodes()
        .map(|n| {
            let node = g.node(n);
            let flags: Vec<String> =
                node.flags.iter().map(|(r, f)| format!("{}:{}", scn.robot(*r).name, f.symbol())).collect();
            let parent = match node.parent {
                Some((p, r)) => format!(" <-{}/{}", g.node(p).item.name(scn), scn.robot(r).name),
                None => String::new(),
            };
            format!("{} {}{parent}", node.item.name(scn), flags.join(" "))
        })
        .collect()
}

/// Each action as `id robot object after [ids]`, 1-based ids.
fn actions(scn: &Scenario, sol: &Solution) -> Vec<String> {
    let plan = sol.outcome.as_ref().expect("a plan");
    plan.actions
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let after: Vec<String> = a.after.iter().map(|j| (j + 1).to_string()).collect();
            format!("{} {} {} after [{}]", i + 1, scn.robot(a.robot).name, a.item.name(scn), after.join(","))
        })
        .collect()
}

fn o(k: u32) -> Option<u32> {
    Some(k)
}

#[test]
fn figure_2_and_3() {
    let (scn, _) = scenario(2, 7, Some(0), 0);
    let t = Table::new()
        .path(1, 0, &[1])
        .path(2, 0, &[2])
        .path(1, 1, &[3, 4])
        .path(2, 1, &[5])
        .path(1, 2, &[6])
        .null(2, 2, Unreachable::NoGraspSolution)
        .path(1, 5, &[])
        .path(2, 5, &[]);
    let sol = solve(&scn, &t);
    assert_eq!(
        nodes(&scn, &sol),
        [
            "o0 r1:B r2:B",
            "o1 r1:B r2:B <-o0/r1",
            "o2 r1:B r2:N <-o0/r2",
            "o3 r1:∅ r2:∅ <-o1/r1",
            "o4 r1:∅ r2:∅ <-o1/r1",
            "o5 r1:F r2:F <-o1/r2",
            "o6 r1:∅ r2:∅ <-o2/r1",
        ]
    );
    // Costs: objects to remove on the branch, AND siblings included.
    let costs: Vec<usize> = sol.graph.nodes().map(|n| sol.graph.node(n).cost).collect();
    assert_eq!(costs, [0, 1, 1, 3, 3, 2, 2]);
    // Lazy: o3, o4, o6 are never asked; o5 (cost 2, created before o6) is.
    assert_eq!(t.asked(), [(1, o(0)), (2, o(0)), (1, o(1)), (2, o(1)), (1, o(2)), (2, o(2)), (1, o(5)), (2, o(5))]);
    // Figure 3: O5 with R1, O1 with R2, finally O0 with R1.
    assert_eq!(actions(&scn, &sol), ["1 r1 o5 after []", "2 r2 o1 after [1]", "3 r1 o0 after [2]"]);
}

#[test]
fn example_1_box_lid() {
    let (scn, _) = scenario(2, 2, Some(0), 0);
    let t = Table::new().path(1, 0, &[1]).path(2, 0, &[1]).path(1, 1, &[]).path(2, 1, &[]);
    let sol = solve(&scn, &t);
    // Figure 6c: the lid is a child for both robots; the first lid node frees the can.
    assert_eq!(nodes(&scn, &sol), ["o0 r1:B r2:B", "o1 r1:F r2:F <-o0/r1", "o1 r1:∅ r2:∅ <-o0/r2"]);
    assert_eq!(t.asked().len(), 4);
    // As in the paper: R2 removes the lid, R1 grasps the can.
    assert_eq!(actions(&scn, &sol), ["1 r2 o1 after []", "2 r1 o0 after [1]"]);
}

#[test]
fn example_2_cans() {
    let (scn, _) = scenario(2, 4, Some(0), 0);
    let t = Table::new().path(1, 0, &[2]).path(2, 0, &[3]).path(1, 2, &[]).path(2, 2, &[]);
    let sol = solve(&scn, &t);
    // Figure 8b: O3 is never analysed, O2 is free for both.
    assert_eq!(nodes(&scn, &sol), ["o0 r1:B r2:B", "o2 r1:F r2:F <-o0/r1", "o3 r1:∅ r2:∅ <-o0/r2"]);
    assert_eq!(actions(&scn, &sol), ["1 r2 o2 after []", "2 r1 o0 after [1]"]);
}

#[test]
fn example_3_six_cans() {
    let (scn, _) = scenario(2, 6, Some(0), 0);
    let t = example_3_table();
    let sol = solve(&scn, &t);
    // Figure 10b: O5 on both branches (Null for R1), O1 Free for R2 so not expanded.
    assert_eq!(
        nodes(&scn, &sol),
        [
            "o0 r1:B r2:B",
            "o4 r1:F r2:F <-o0/r1",
            "o5 r1:N r2:B <-o0/r1",
            "o1 r1:B r2:F <-o0/r2",
            "o5 r1:N r2:B <-o0/r2",
            "o2 r1:N r2:F <-o5/r2",
            "o2 r1:∅ r2:∅ <-o5/r2",
        ]
    );
    // The second O5 reuses the memoised answers: ten queries, none repeated.
    assert_eq!(
        t.asked(),
        [(1, o(0)), (2, o(0)), (1, o(4)), (2, o(4)), (1, o(5)), (2, o(5)), (1, o(1)), (2, o(1)), (1, o(2)), (2, o(2))]
    );
    // Figure 11: R2 removes O2, R1 removes O4, R2 removes O5, R1 grasps O0.
    assert_eq!(
        actions(&scn, &sol),
        ["1 r2 o2 after []", "2 r1 o4 after []", "3 r2 o5 after [1]", "4 r1 o0 after [2,3]"]
    );
}

#[test]
fn discarded_branch_is_bypassed_by_the_other_robot() {
    // O2 by R1 needs O1 out first, but O1 is O2's parent: Discarded. R2 can take O2
    // once O3 is gone.
    let (scn, _) = scenario(2, 4, Some(0), 0);
    let t = Table::new()
        .path(1, 0, &[1])
        .null(2, 0, crate::common::gave_up())
        .path(1, 1, &[2])
        .path(2, 1, &[2])
        .path(1, 2, &[1])
        .path(2, 2, &[3])
        .path(1, 3, &[])
        .null(2, 3, crate::common::gave_up());
    let sol = solve(&scn, &t);
    assert_eq!(
        nodes(&scn, &sol),
        [
            "o0 r1:B r2:N",
            "o1 r1:B r2:B <-o0/r1",
            "o2 r1:D r2:B <-o1/r1",
            "o2 r1:D r2:B <-o1/r2",
            "o3 r1:F r2:N <-o2/r2",
            "o3 r1:∅ r2:∅ <-o2/r2",
        ]
    );
    // Four actions either way; R2 takes O1 so each robot does two.
    assert_eq!(
        actions(&scn, &sol),
        ["1 r1 o3 after []", "2 r2 o2 after [1]", "3 r2 o1 after [2]", "4 r1 o0 after [3]"]
    );
}

#[test]
fn shared_blocker_is_removed_once() {
    let (scn, _) = scenario(2, 4, Some(0), 0);
    let t = Table::new()
        .path(1, 0, &[1, 2])
        .null(2, 0, Unreachable::NoGraspSolution)
        .path(1, 1, &[3])
        .null(2, 1, Unreachable::NoGraspSolution)
        .path(1, 2, &[3])
        .null(2, 2, Unreachable::NoGraspSolution)
        .path(1, 3, &[])
        .path(2, 3, &[]);
    let sol = solve(&scn, &t);
    assert_eq!(
        actions(&scn, &sol),
        ["1 r2 o3 after []", "2 r1 o1 after [1]", "3 r1 o2 after [1]", "4 r1 o0 after [2,3]"]
    );
    assert_eq!(sol.outcome.as_ref().unwrap().removed().len(), 4);
}

#[test]
fn three_robots() {
    let (scn, _) = scenario(3, 4, Some(0), 0);
    let t = Table::new()
        .path(1, 0, &[1, 2])
        .path(2, 0, &[2, 3])
        .null(3, 0, Unreachable::NoGraspSolution)
        .path(1, 1, &[])
        .path(2, 1, &[])
        .path(3, 1, &[])
        .path(1, 2, &[3])
        .null(2, 2, crate::common::gave_up())
        .path(3, 2, &[]);
    let sol = solve(&scn, &t);
    assert_eq!(
        nodes(&scn, &sol),
        [
            "o0 r1:B r2:B r3:N",
            "o1 r1:F r2:F r3:F <-o0/r1",
            "o2 r1:B r2:N r3:F <-o0/r1",
            "o2 r1:∅ r2:∅ r3:∅ <-o0/r2",
            "o3 r1:∅ r2:∅ r3:∅ <-o0/r2",
        ]
    );
    assert_eq!(t.asked().len(), 9);
    // One action per robot: R2 takes O1, R3 takes O2 (free for it), R1 the target.
    assert_eq!(actions(&scn, &sol), ["1 r2 o1 after []", "2 r3 o2 after []", "3 r1 o0 after [1,2]"]);
}

#[test]
fn configuration_target() {
    let (scn, _) = scenario(2, 2, None, 1);
    let t = Table::new().reach(2, &[1]).path(1, 1, &[]).path(2, 1, &[]);
    let sol = solve(&scn, &t);
    // The pseudo-node has R2's flag only; R1 is never asked to reach it.
    assert_eq!(nodes(&scn, &sol), ["target r2:B", "o1 r1:F r2:F <-target/r2"]);
    assert_eq!(t.asked(), [(2, None), (1, o(1)), (2, o(1))]);
    assert_eq!(actions(&scn, &sol), ["1 r1 o1 after []", "2 r2 target after [1]"]);
}

#[test]
fn cycle_is_infeasible() {
    let (scn, sources) = scenario(2, 3, Some(0), 0);
    let t = cycle_table();
    let sol = solve(&scn, &t);
    assert_eq!(
        nodes(&scn, &sol),
        [
            "o0 r1:B r2:B",
            "o1 r1:B r2:N <-o0/r1",
            "o1 r1:B r2:N <-o0/r2",
            "o2 r1:D r2:D <-o1/r1",
            "o2 r1:D r2:D <-o1/r1",
        ]
    );
    let err = sol.outcome.as_ref().unwrap_err();
    assert_eq!(err.causes.len(), 1);
    let Cause::Cycle { objects, .. } = &err.causes[0] else { panic!("not a cycle: {:?}", err.causes[0]) };
    assert_eq!(objects.iter().map(|o| o.0).collect::<Vec<_>>(), [1, 2]);
    assert_eq!(
        err.reason(),
        "`o0` cannot be reached: grasping `o1` with `r1` needs `o2` removed first, and grasping `o2` with `r1` \
         needs `o1` removed first: they block each other"
    );
    insta::assert_snapshot!(render_one(&sources, err, RenderOptions::plain()));
}

#[test]
fn a_removal_only_the_roadmap_asked_for_proves_nothing() {
    // One robot; the target `o0` needs `o1` removed, and nothing can grasp `o1`. When the
    // grasps of `o0` themselves touch `o1` that is a proof; when only the roadmap's path
    // does, a bigger roadmap may find a way around `o1`.
    let (scn, sources) = scenario(1, 2, Some(0), 0);
    let forced = Table::new().path(1, 0, &[1]).null(1, 1, Unreachable::NoGraspSolution);
    let sol = solve(&scn, &forced);
    assert!(sol.outcome.as_ref().unwrap_err().is_proof());
    let roadmap = Table::new().roadmap_path(1, 0, &[1]).null(1, 1, Unreachable::NoGraspSolution);
    let sol = solve(&scn, &roadmap);
    let err = sol.outcome.as_ref().unwrap_err();
    assert!(!err.is_proof());
    insta::assert_snapshot!(render_one(&sources, err, RenderOptions::plain()));
}

#[test]
fn object_no_robot_can_grasp() {
    let (scn, sources) = scenario(2, 2, Some(0), 0);
    let self_hit = Blocker::SelfCollision { link_a: "l1".into(), link_b: "l3".into() };
    let t = Table::new()
        .path(1, 0, &[1])
        .null(2, 0, crate::common::gave_up())
        .null(1, 1, Unreachable::NoGraspSolution)
        .null(2, 1, Unreachable::ApproachBlocked { blockers: vec![self_hit.clone()] });
    let sol = solve(&scn, &t);
    assert_eq!(nodes(&scn, &sol), ["o0 r1:B r2:N", "o1 r1:N r2:N <-o0/r1"]);
    let err = sol.outcome.as_ref().unwrap_err();
    // `r2` gave up on `o0` within its budget: with a bigger one it might grasp it, so
    // `o1` being ungraspable proves nothing about the target.
    assert!(!err.is_proof());
    let Cause::Unproved { what, reasons, .. } = &err.causes[0] else { panic!("{:?}", err.causes[0]) };
    assert_eq!(
        (what.as_str(), reasons.as_slice()),
        ("to grasp `o0`", &["`r2` gave up within its budget".to_string()][..])
    );
    let r2_text = "its grasps are reachable, but every approach or retreat carrying it is blocked: links `l1` and \
                   `l3` collide";
    assert_eq!(
        err.causes[1..],
        [Cause::Ungraspable {
            object: declutter::resolve::ObjectId(1),
            name: "o1".into(),
            reasons: vec![
                (
                    "r1".into(),
                    Reason {
                        why: Unreachable::NoGraspSolution,
                        text: "no grasp has an inverse-kinematics solution clear of fixed bodies".into()
                    }
                ),
                (
                    "r2".into(),
                    Reason { why: Unreachable::ApproachBlocked { blockers: vec![self_hit] }, text: r2_text.into() }
                ),
            ],
            span: scn.objects[1].body.span,
        }]
    );
    assert_eq!(
        err.reason(),
        format!(
            "no way to `o0` was found within the planning budget: nothing proves there is no way to grasp `o0`: \
             `r2` gave up within its budget; no robot can grasp `o1` (`r1`: no grasp has an inverse-kinematics \
             solution clear of fixed bodies; `r2`: {r2_text})"
        )
    );
    insta::assert_snapshot!(render_one(&sources, err, RenderOptions::plain()));
}

#[test]
fn object_not_found_within_the_budget_is_not_a_proof() {
    // As above, but `r2` gave up on `o1` at its sampling budget: a bigger one might find a path.
    let (scn, sources) = scenario(2, 2, Some(0), 0);
    let t = Table::new()
        .path(1, 0, &[1])
        .null(2, 0, crate::common::gave_up())
        .null(1, 1, Unreachable::NoGraspSolution)
        .null(2, 1, crate::common::gave_up());
    let sol = solve(&scn, &t);
    let err = sol.outcome.as_ref().unwrap_err();
    assert!(!err.is_proof());
    assert!(matches!(err.causes.as_slice(), [Cause::NotFound { what, .. }] if what == "to grasp `o1`"));
    assert_eq!(
        err.reason(),
        "no way to `o0` was found within the planning budget: no path to grasp `o1` was found within the planning \
         budget (`r1`: no grasp has an inverse-kinematics solution clear of fixed bodies; `r2`: no path to a grasp \
         within 5000 samples)"
    );
    insta::assert_snapshot!(render_one(&sources, err, RenderOptions::plain()));
}

#[test]
fn target_no_robot_can_grasp() {
    let (scn, _) = scenario(2, 1, Some(0), 0);
    let t = Table::new().null(1, 0, Unreachable::NoGraspSolution).null(2, 0, Unreachable::NoGraspSolution);
    let sol = solve(&scn, &t);
    assert_eq!(nodes(&scn, &sol), ["o0 r1:N r2:N"]);
    let err = sol.outcome.as_ref().unwrap_err();
    assert!(matches!(err.causes.as_slice(), [Cause::Ungraspable { name, .. }] if name == "o0"));
}

#[test]
fn flags_do_not_depend_on_flag_order_of_answers() {
    // Same answers, a fresh oracle: identical graph and plan (determinism).
    let (scn, _) = scenario(2, 6, Some(0), 0);
    let a = solve(&scn, &example_3_table());
    let b = solve(&scn, &example_3_table());
    assert_eq!(nodes(&scn, &a), nodes(&scn, &b));
    assert_eq!(a.outcome, b.outcome);
    assert_eq!(a.graph.node(a.graph.root).flags[0].1, Flag::Blocked);
}

#[test]
fn a_cheaper_but_cyclic_choice_is_rejected() {
    // Taking O1 and O2 both with R1 would be three actions, but each needs the other
    // gone first. O2 with R2 needs O3 gone: four actions, in an order that works; R2
    // also takes O3, so each robot does two.
    let (scn, _) = scenario(2, 4, Some(0), 0);
    let t = Table::new()
        .path(1, 0, &[1, 2])
        .null(2, 0, Unreachable::NoGraspSolution)
        .path(1, 1, &[2])
        .null(2, 1, Unreachable::NoGraspSolution)
        .path(1, 2, &[1])
        .path(2, 2, &[3])
        .path(1, 3, &[])
        .path(2, 3, &[]);
    let sol = solve(&scn, &t);
    assert_eq!(
        nodes(&scn, &sol),
        [
            "o0 r1:B r2:N",
            "o1 r1:B r2:N <-o0/r1",
            "o2 r1:B r2:B <-o0/r1",
            "o2 r1:D r2:B <-o1/r1",
            "o1 r1:D r2:N <-o2/r1",
            "o3 r1:F r2:F <-o2/r2",
            "o3 r1:∅ r2:∅ <-o2/r2",
        ]
    );
    assert_eq!(
        actions(&scn, &sol),
        ["1 r2 o3 after []", "2 r2 o2 after [1]", "3 r1 o1 after [2]", "4 r1 o0 after [2,3]"]
    );
}

#[test]
fn configuration_target_out_of_reach() {
    let (scn, sources) = scenario(2, 1, None, 0);
    let limit = Blocker::JointLimit { joint: "j2".into(), value: -0.5 };
    let t = Table::new().null_reach(1, Unreachable::GoalBlocked(limit));
    let sol = solve(&scn, &t);
    let err = sol.outcome.as_ref().unwrap_err();
    assert_eq!(
        err.reason(),
        "`r1 at [0.5, -0.5]` cannot be reached: `r1` cannot reach the target configuration: it is outside the \
         limits of joint `j2` (-0.5000 rad)"
    );
    insta::assert_snapshot!(render_one(&sources, err, RenderOptions::plain()));
}

#[test]
fn configuration_target_not_found_speaks_of_the_configuration() {
    let (scn, sources) = scenario(2, 1, None, 0);
    let t = Table::new().null_reach(1, crate::common::gave_up());
    let sol = solve(&scn, &t);
    let err = sol.outcome.as_ref().unwrap_err();
    let text = err.reason();
    assert_eq!(
        text,
        "no way to `r1 at [0.5, -0.5]` was found within the planning budget: no path for `r1` to the target \
         configuration was found within the planning budget (`r1`: no path to it within 5000 samples)"
    );
    assert!(!text.contains("grasp"), "{text}");
    insta::assert_snapshot!(render_one(&sources, err, RenderOptions::plain()));
}

/// A configuration target's query that also grew the free-space trees says what both
/// searches spent.
#[test]
fn configuration_target_given_up_counts_the_free_trees_extensions() {
    let (scn, _) = scenario(2, 1, None, 0);
    let budget = declutter::plan::Budget { samples: 5000, max_samples: 5000, extensions: 78_976, timed_out: false };
    let t = Table::new().null_reach(1, Unreachable::BudgetExhausted(budget));
    let sol = solve(&scn, &t);
    let err = sol.outcome.as_ref().unwrap_err();
    assert!(!err.is_proof());
    assert_eq!(
        err.reason(),
        "no way to `r1 at [0.5, -0.5]` was found within the planning budget: no path for `r1` to the target \
         configuration was found within the planning budget (`r1`: no path to it within 5000 samples, then 78976 \
         free-space RRT-Connect extensions)"
    );
}

mod random {
    //! On random complete tables: a plan, when there is one, is a valid precedence
    //! order; and there is none exactly when no acyclic derivation exists at all.
    use std::collections::BTreeSet;

    use proptest::prelude::*;

    use super::common::{scenario, Table};
    use declutter::plan::andor::{solve, Item};

    /// Per (robot, object): `None` = Null, `Some(mask)` = blocked by the objects in mask.
    fn table() -> impl Strategy<Value = (usize, usize, Vec<Option<u8>>)> {
        (2usize..=3, 2usize..=6).prop_flat_map(|(robots, objects)| {
            let cell = prop_oneof![1 => Just(None), 3 => (0u8..64).prop_map(Some)];
            (Just(robots), Just(objects), proptest::collection::vec(cell, robots * objects))
        })
    }

    /// Least fixed point over the whole table: is the target removable at all?
    fn solvable(robots: usize, objects: usize, cells: &[Option<u8>]) -> bool {
        let mut done = BTreeSet::new();
        loop {
            let before = done.len();
            for o in 0..objects {
                for r in 0..robots {
                    if let Some(mask) = cells[r * objects + o] {
                        let so: Vec<usize> = (0..objects).filter(|k| mask & (1 << k) != 0 && *k != o).collect();
                        if so.iter().all(|k| done.contains(k)) {
                            done.insert(o);
                        }
                    }
                }
            }
            if done.contains(&0) {
                return true;
            }
            if done.len() == before {
                return false;
            }
        }
    }

    /// Actions per robot, busiest first.
    fn loads(choice: &[Option<u32>]) -> Vec<usize> {
        let mut l: Vec<usize> = (0..3).map(|r| choice.iter().filter(|x| **x == Some(r)).count()).collect();
        l.sort_by(|a, b| b.cmp(a));
        l
    }

    /// The smallest (actions, loads) over every choice of at most one robot
    /// per object that is closed under SO, acyclic and includes the target.
    fn brute_force(graph: &declutter::plan::andor::Graph, objects: usize) -> (usize, Vec<usize>) {
        use declutter::resolve::{ObjectId, RobotId};
        let mut best = (usize::MAX, vec![]);
        for code in 0..4usize.pow(objects as u32) {
            let mut choice = vec![None; objects];
            let mut c = code;
            for slot in choice.iter_mut() {
                let v = (c % 4) as u32;
                c /= 4;
                if v > 0 {
                    *slot = Some(v - 1);
                }
            }
            if choice[0].is_none() {
                continue;
            }
            let so = |o: usize| -> Option<Vec<usize>> {
                let r = choice[o]?;
                let p = graph.found(RobotId(r), Item::Object(ObjectId(o as u32)))?;
                Some(p.removals.iter().map(|x| x.index()).collect())
            };
            let closed = (0..objects)
                .all(|o| choice[o].is_none() || so(o).is_some_and(|s| s.iter().all(|k| choice[*k].is_some())));
            if !closed {
                continue;
            }
            // Acyclic: repeatedly mark the objects whose SO is all marked.
            let mut done = vec![false; objects];
            let mut progress = true;
            while progress {
                progress = false;
                for o in 0..objects {
                    if choice[o].is_some() && !done[o] && so(o).unwrap().iter().all(|k| done[*k]) {
                        done[o] = true;
                        progress = true;
                    }
                }
            }
            if (0..objects).any(|o| choice[o].is_some() && !done[o]) {
                continue;
            }
            let n = choice.iter().filter(|x| x.is_some()).count();
            best = best.min((n, loads(&choice)));
        }
        best
    }

    proptest! {
        #[test]
        fn plans_are_valid_and_complete((robots, objects, cells) in table()) {
            let (scn, _) = scenario(robots, objects, Some(0), 0);
            let mut t = Table::new();
            for r in 0..robots {
                for o in 0..objects {
                    t = match cells[r * objects + o] {
                        None => t.null(r as u32 + 1, o as u32, crate::common::gave_up()),
                        Some(mask) => {
                            let so: Vec<u32> = (0..objects as u32).filter(|k| mask & (1 << k) != 0 && *k as usize != o).collect();
                            t.path(r as u32 + 1, o as u32, &so)
                        }
                    };
                }
            }
            let sol = solve(&scn, &t);
            prop_assert_eq!(sol.outcome.is_ok(), solvable(robots, objects, &cells));
            // No query is asked twice.
            let asked = t.asked();
            let unique: BTreeSet<_> = asked.iter().collect();
            prop_assert_eq!(unique.len(), asked.len());
            if let Ok(plan) = &sol.outcome {
                let last = plan.actions.last().unwrap();
                prop_assert_eq!(last.item, Item::Object(declutter::resolve::ObjectId(0)));
                let items: BTreeSet<Item> = plan.actions.iter().map(|a| a.item).collect();
                prop_assert_eq!(items.len(), plan.actions.len());
                for (i, a) in plan.actions.iter().enumerate() {
                    let so = &sol.graph.found(a.robot, a.item).unwrap().removals;
                    let mut want: Vec<usize> = so
                        .iter()
                        .map(|o| plan.actions.iter().position(|b| b.item == Item::Object(o)).unwrap())
                        .collect();
                    want.sort();
                    prop_assert_eq!(&a.after, &want);
                    prop_assert!(a.after.iter().all(|j| *j < i));
                }
                // Rules 1 and 2 against brute force over the answers G holds.
                let best = brute_force(&sol.graph, objects);
                let mut mine = vec![None; objects];
                for a in &plan.actions {
                    mine[a.item.object().unwrap().index()] = Some(a.robot.0);
                }
                prop_assert_eq!((plan.actions.len(), loads(&mine)), best);
            }
        }
    }
}

#[test]
fn no_robot_at_all() {
    let (scn, _) = scenario(0, 1, Some(0), 0);
    let sol = solve(&scn, &Table::new());
    let err = sol.outcome.as_ref().unwrap_err();
    assert_eq!(err.reason(), "`o0` cannot be reached: no robot can grasp `o0` (the scenario declares no robot)");
}

#[test]
fn wide_and_is_spread_over_three_robots() {
    // The target needs twelve objects gone, each free for every robot.
    let (scn, _) = scenario(3, 13, Some(0), 0);
    let all: Vec<u32> = (1..13).collect();
    let mut t = Table::new().path(1, 0, &all).null(2, 0, crate::common::gave_up()).null(3, 0, crate::common::gave_up());
    for o in 1..13 {
        t = t.path(1, o, &[]).path(2, o, &[]).path(3, o, &[]);
    }
    let start = std::time::Instant::now();
    let sol = solve(&scn, &t);
    assert!(start.elapsed().as_secs() < 20);
    let plan = sol.outcome.as_ref().unwrap();
    assert_eq!(plan.actions.len(), 13);
    let per_robot: Vec<usize> = (0..3).map(|r| plan.actions.iter().filter(|a| a.robot.0 == r).count()).collect();
    assert_eq!(per_robot, [5, 4, 4]);
}
