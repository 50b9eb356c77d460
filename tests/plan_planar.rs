//! PRMwO on an exact planar arm: labels, grasp queries, the brute-force comparison
//! of `fewest_removals` with a grid search, and determinism across thread counts.

mod common;

use common::planar::{cell_of, grid_min_removals, label_grid, random_world, Planar, Rect};
use declutter::plan::{Goal, Mode, PrmOptions, RobotPlanner, Space, Unreachable};
use declutter::resolve::{ObjectId, Objective, PlannerSettings};
use declutter::world::{Check, JointPath, ObjectSet};

fn set(ids: &[u32]) -> ObjectSet {
    ids.iter().map(|&i| ObjectId(i)).collect()
}

/// Re-checks a path with `removed` taken out of the scene: it must touch nothing.
fn path_is_free(w: &Planar, path: &JointPath, removed: &ObjectSet, held: Option<declutter::world::Held>) -> bool {
    let mode = Mode { absent: removed.clone(), held };
    let mut c = 0;
    path.0
        .windows(2)
        .all(|s| w.check_segment(&s[0], &s[1], PlannerSettings::default().resolution, &mode, &mut c) == Check::free())
        && path.0.iter().all(|q| w.check(q, &mode, &mut c) == Check::free())
}

#[test]
fn labels_are_exact() {
    // A box on the x axis at 0.5 m: the straight arm touches it, the folded arm does not.
    let w = Planar::new(vec![Rect::aabb(0.5, 0.0, 0.05, 0.05)], vec![Rect::aabb(0.0, 0.8, 0.3, 0.05)], vec![0.0; 3]);
    let mut c = 0;
    assert_eq!(w.check(&[0.0, 0.0, 0.0], &Mode::default(), &mut c), Check::Touches(set(&[0])));
    assert_eq!(w.check(&[-1.5, 0.0, 0.0], &Mode::default(), &mut c), Check::free());
    assert!(w.check(&[1.57, 0.0, 0.0], &Mode::default(), &mut c).is_blocked());
    let absent = Mode { absent: set(&[0]), held: None };
    assert_eq!(w.check(&[0.0, 0.0, 0.0], &absent, &mut c), Check::free());
    // A segment sweeping through the box picks up its label.
    assert_eq!(
        w.check_segment(&[-1.0, 0.0, 0.0], &[-0.0, 0.0, 0.0], 0.05, &Mode::default(), &mut c),
        Check::Touches(set(&[0]))
    );
    assert!(c > 20);
}

/// The box-and-lid scene in 2-D: a target box with a lid on top, both grasped from
/// above, a third box with no grasp, and a fixed wall far above.
fn lid_world() -> Planar {
    let objects = vec![
        Rect::aabb(0.45, 0.0, 0.04, 0.04),  // 0: target
        Rect::aabb(0.45, 0.1, 0.08, 0.025), // 1: lid on top of it
        Rect::aabb(-0.5, -0.4, 0.05, 0.05), // 2: elsewhere, no grasp
    ];
    let fixed = vec![Rect::aabb(0.0, 0.85, 0.8, 0.03)];
    let mut w = Planar::new(objects, fixed, vec![2.0, 0.5, 0.5]);
    let down = -std::f64::consts::FRAC_PI_2;
    assert!(w.add_grasp(0, down, 0.1, true));
    assert!(w.add_grasp(1, down, 0.1, true));
    w
}

#[test]
fn grasp_queries_label_the_whole_motion() {
    let w = lid_world();
    let p = RobotPlanner::new(w.clone(), &PlannerSettings::default(), &PrmOptions::default(), 0);
    let lid = p.query(&Goal::Grasp(ObjectId(1)));
    let found = lid.result.clone().expect("lid reachable");
    assert_eq!(found.removals, ObjectSet::new(), "{:?}", lid.stats);
    assert_eq!(found.grasp, Some(0));
    // Up to the pre-grasp the path touches nothing; the last step is the approach, where the lid is ignored.
    let n = found.approach.0.len();
    assert!(path_is_free(&w, &JointPath(found.approach.0[..n - 1].to_vec()), &ObjectSet::new(), None));
    let held = w.held(ObjectId(1), &found.retreat.0[0]);
    let carry = Mode { absent: ObjectSet::single(ObjectId(1)), held: Some(held) };
    let mut c = 0;
    assert!(found.retreat.0.windows(2).all(|s| w.check_segment(&s[0], &s[1], 0.01, &carry, &mut c) == Check::free()));
    let target = p.query(&Goal::Grasp(ObjectId(0)));
    let found = target.result.clone().expect("target reachable");
    // The hand must pass the lid to reach the target.
    assert_eq!(found.removals, set(&[1]));
    // Approach ends at the grasp, retreat starts there and ends home.
    assert_eq!(found.approach.0.last(), found.retreat.0.first());
    assert_eq!(found.approach.0.first().map(|q| q.0.clone()), Some(w.home.clone()));
    assert_eq!(found.retreat.0.last().map(|q| q.0.clone()), Some(w.home.clone()));
    assert!(target.stats.reused_vertices > 0, "second query reuses the roadmap");
    assert_eq!(target.stats.paths, 1);
    // No grasps at all.
    assert_eq!(p.query(&Goal::Grasp(ObjectId(2))).result, Err(Unreachable::NoGraspSolution));
    // A target configuration inside the wall.
    assert_eq!(p.query(&Goal::Reach(vec![1.57, 0.0, 0.0].into())).result, Err(Unreachable::GoalBlocked));
}

#[test]
fn reach_path_rechecks_clean_and_reuse_is_cheaper() {
    let (w, goal) = random_world(7, 64);
    let p = RobotPlanner::new(w.clone(), &PlannerSettings::default(), &PrmOptions::default(), 0);
    let a = p.query(&Goal::Reach(goal.clone().into()));
    let f = a.result.expect("a path");
    assert!(path_is_free(&w, &f.approach, &f.removals, None));
    let b = p.query(&Goal::Reach(goal.into()));
    assert_eq!(b.result.expect("same path"), f);
    assert_eq!(b.stats.samples, 0);
    assert!(b.stats.checks <= a.stats.checks);
}

/// The brute-force comparison of the issue: 100 random planar worlds.
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn fewest_removals_matches_grid_brute_force() {
    use rayon::prelude::*;
    let n = 64;
    type Row = (Option<usize>, Option<usize>, Option<usize>, bool);
    let rows: Vec<Row> = (0..100u64)
        .into_par_iter()
        .map(|seed| {
            let (w, goal) = random_world(1000 + seed, n);
            let labels = label_grid(&w, n);
            let brute = grid_min_removals(&labels, n, w.objects.len(), cell_of(&w.home, n), cell_of(&goal, n));
            let p = RobotPlanner::new(w.clone(), &PlannerSettings::default(), &PrmOptions::default(), 0);
            let mcr = p.query_with(&Goal::Reach(goal.clone().into()), Objective::FewestRemovals);
            let fv = p.query_with(&Goal::Reach(goal.clone().into()), Objective::FewestVertices);
            let mut ok = true;
            for r in [&mcr, &fv] {
                if let Ok(f) = &r.result {
                    ok &= path_is_free(&w, &f.approach, &f.removals, None);
                }
            }
            let size = |r: &declutter::plan::Answer| r.result.as_ref().ok().map(|f| f.removals.len());
            (brute, size(&mcr), size(&fv), ok)
        })
        .collect();
    let mut good = 0;
    let (mut worse, mut extra, mut both) = (0, 0, 0);
    for (i, (brute, mcr, fv, ok)) in rows.iter().enumerate() {
        assert!(ok, "world {i}: a returned path does not re-check clean");
        let fine = match (brute, mcr) {
            (Some(b), Some(m)) => m <= b,
            (None, _) => true,
            (Some(_), None) => false,
        };
        if fine {
            good += 1;
        } else {
            eprintln!("world {i}: grid {brute:?}, fewest_removals {mcr:?}");
        }
        if let (Some(m), Some(v)) = (mcr, fv) {
            both += 1;
            if v > m {
                worse += 1;
                extra += v - m;
            }
        }
    }
    eprintln!("fewest_removals <= grid minimum in {good}/100 worlds");
    eprintln!(
        "fewest_vertices removes more than fewest_removals in {worse}/{both} worlds, {extra} extra objects in total ({:.2} per such world)",
        if worse > 0 { extra as f64 / worse as f64 } else { 0.0 }
    );
    assert!(good >= 95, "only {good}/100");
}

#[test]
fn identical_answers_with_1_2_and_4_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut out = Vec::new();
            for seed in [3u64, 11] {
                let (w, goal) = random_world(seed, 32);
                let p = RobotPlanner::new(w, &PlannerSettings::default(), &PrmOptions::default(), 0);
                out.push(p.query(&Goal::Reach(goal.clone().into())).result);
                out.push(p.query_with(&Goal::Reach(goal.into()), Objective::FewestVertices).result);
            }
            let w = lid_world();
            let p = RobotPlanner::new(w, &PlannerSettings::default(), &PrmOptions::default(), 0);
            // Queries for the same robot issued in parallel must not race.
            let both: Vec<_> = rayon::iter::ParallelIterator::collect(rayon::iter::ParallelIterator::map(
                rayon::iter::IntoParallelIterator::into_par_iter(vec![1u32, 0]),
                |o| p.query(&Goal::Grasp(ObjectId(o))).result,
            ));
            out.extend(both);
            out
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(4));
}
