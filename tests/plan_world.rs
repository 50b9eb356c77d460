//! The planner on real worlds: the box-and-lid cell built by hand with two TX-90s and
//! the SAH/SDH2 hands from examples/ (a transcription of examples/box_lid.dcl, which
//! `box_lid_dcl_scene_can_needs_lid_lid_is_free` runs from the file itself), and the
//! planar arm from examples/robots/planar3.urdf.

#[path = "common/box_lid.rs"]
mod box_lid;
mod world_support;

#[path = "common/planar.rs"]
mod planar;

use box_lid::{box_lid, box_lid_dcl};
use declutter::diag::FsLoader;
use declutter::plan::{Goal, Oracle, Planner};
use declutter::resolve::{ObjectId, Objective, RobotId, Scenario};
use declutter::world::{build, Check, CheckCtx, ObjectSet, World, WorldOptions};
use world_support::*;

fn world(scn: &Scenario) -> World {
    build(scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"))
}

fn free_along(w: &World, r: RobotId, path: &[declutter::world::Config], ctx: &CheckCtx) -> bool {
    path.windows(2).all(|s| w.check_segment(r, &s[0], &s[1], 2f64.to_radians(), ctx) == Check::free())
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn box_lid_can_needs_the_lid_removed_and_the_lid_is_free() {
    let scn = box_lid();
    let w = world(&scn);
    let planner = Planner::new(&w, &scn.planner);
    let (can, lid) = (ObjectId(0), ObjectId(1));
    for r in scn.robot_ids() {
        let a = planner.find_path(r, &Goal::Grasp(lid));
        eprintln!("{:?}", a.stats);
        assert_eq!(a.stats.reused_vertices, 0, "the first query of a robot starts a fresh roadmap");
        let f = a.result.unwrap_or_else(|e| panic!("{}: lid {e:?}", scn.robot(r).name));
        assert_eq!(f.removals, ObjectSet::new(), "{}: lid", scn.robot(r).name);
        let n = f.approach.0.len();
        assert!(free_along(&w, r, &f.approach.0[..n - 1], &CheckCtx::new()));
        let held = w.held(r, lid, f.grasp.unwrap_or(0), &f.retreat.0[0]);
        assert!(free_along(&w, r, &f.retreat.0, &CheckCtx::with_held(ObjectSet::single(lid), held)));

        let a = planner.find_path(r, &Goal::Grasp(can));
        eprintln!("{:?}", a.stats);
        let f = a.result.unwrap_or_else(|e| panic!("{}: can {e:?}", scn.robot(r).name));
        assert_eq!(f.removals, ObjectSet::single(lid), "{}: can", scn.robot(r).name);
        let gone = ObjectSet::single(lid);
        assert!(free_along(&w, r, &f.approach.0[..f.approach.0.len() - 1], &CheckCtx::with_absent(gone.clone())));
        let mut absent = gone.clone();
        absent.insert(can);
        let held = w.held(r, can, f.grasp.unwrap_or(0), &f.retreat.0[0]);
        assert!(free_along(&w, r, &f.retreat.0, &CheckCtx::with_held(absent, held)));
        assert!(a.stats.reused_vertices > 0);
        // Both objectives on the same roadmap.
        let v = planner.find_path_with(r, &Goal::Grasp(can), Objective::FewestVertices);
        assert!(v.result.is_ok());
    }
}

#[test]
fn planar3_reach_through_world() {
    let objects = vec![object(cuboid("box", [0.1, 0.1, 0.1], at(0.5, 0.0, 0.0)), vec![])];
    let fixed = vec![cuboid("wall", [0.1, 0.6, 0.1], at(-0.6, 0.0, 0.0))];
    let scn = scenario(vec![robot("p", planar3(), vec![1.5, 0.0, 0.0], None)], vec![], fixed, objects);
    let w = world(&scn);
    let planner = Planner::new(&w, &scn.planner);
    let r = RobotId(0);
    // Pointing along +x the arm passes through the box; pointing along -x, the wall.
    let a = planner.find_path(r, &Goal::Reach(vec![0.0, 0.0, 0.0].into()));
    assert_eq!(a.result.expect("path").removals, ObjectSet::single(ObjectId(0)));
    assert_eq!(a.stats.robot, "p");
    let b = planner.find_path(r, &Goal::Reach(vec![3.0, 0.0, 0.0].into()));
    assert!(b.result.is_err());
    let c = planner.find_path(r, &Goal::Reach(vec![0.0, 0.0, 0.0].into()));
    assert_eq!(c.stats.samples, 0, "answered from the reused roadmap");
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn box_lid_answers_do_not_depend_on_thread_count() {
    let scn = box_lid();
    let w = world(&scn);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            use rayon::prelude::*;
            let planner = Planner::new(&w, &scn.planner);
            // Robots and objects in parallel, as the AND/OR graph may ask.
            let jobs: Vec<(RobotId, ObjectId)> =
                scn.robot_ids().flat_map(|r| scn.object_ids().map(move |o| (r, o))).collect();
            jobs.par_iter().map(|&(r, o)| planner.find_path(r, &Goal::Grasp(o)).result).collect::<Vec<_>>()
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(4));
}

/// The brute-force comparison again (30 worlds), on the real World with examples/robots/planar3.urdf
/// (parry shapes, self-collision, contact tolerance): the grid is labelled by
/// `World::check` itself, so both sides see the same geometry.
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn planar3_world_fewest_removals_matches_grid() {
    use declutter::resolve::Shape;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
    use rayon::prelude::*;
    let n = 40;
    let cuboid_at = |name: String, r: &planar::Rect| {
        let pose = Isometry3::from_parts(
            Translation3::new(r.c[0], r.c[1], 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), r.a),
        );
        body(&name, Shape::Box { size: Vector3::new(2.0 * r.h[0], 2.0 * r.h[1], 0.1) }, pose)
    };
    let r = RobotId(0);
    let make = |seed: u64| {
        let (p, goal) = planar::random_world(5000 + seed, n);
        let objects =
            p.objects.iter().enumerate().map(|(i, r)| object(cuboid_at(format!("box{i}"), r), vec![])).collect();
        let fixed = p.fixed.iter().map(|r| cuboid_at("wall".into(), r)).collect();
        let scn = scenario(vec![robot("p", planar3(), p.home.clone(), None)], vec![], fixed, objects);
        (p, goal, scn)
    };
    // Worlds whose home and target are valid for the 3-D arm too (it also checks self-collision).
    let seeds: Vec<u64> = (0..200u64)
        .filter(|&seed| {
            let (_, goal, scn) = make(seed);
            build(&scn, &WorldOptions::default(), &FsLoader)
                .is_ok_and(|w| !w.check(r, &goal, &CheckCtx::new()).is_blocked())
        })
        .take(30)
        .collect();
    assert_eq!(seeds.len(), 30);
    let rows: Vec<(Option<usize>, Option<usize>, bool)> = seeds
        .into_par_iter()
        .map(|seed| {
            let (p, goal, scn) = make(seed);
            let w = world(&scn);
            let cell = |i: usize| -planar::LIMIT + (i as f64 + 0.5) * 2.0 * planar::LIMIT / n as f64;
            let mut labels = Vec::with_capacity(n * n * n);
            for i in 0..n {
                for j in 0..n {
                    for k in 0..n {
                        labels.push(match w.check(r, &[cell(i), cell(j), cell(k)], &CheckCtx::new()) {
                            Check::Blocked(_) => u32::MAX,
                            Check::Touches(s) => s.iter().fold(0, |m, o| m | 1 << o.0),
                        });
                    }
                }
            }
            let brute = planar::grid_min_removals(
                &labels,
                n,
                p.objects.len(),
                planar::cell_of(&p.home, n),
                planar::cell_of(&goal, n),
            );
            let planner = Planner::new(&w, &scn.planner);
            let a = planner.find_path(r, &Goal::Reach(goal.clone().into()));
            let ok = match &a.result {
                Ok(f) => free_along(&w, r, &f.approach.0, &CheckCtx::with_absent(f.removals.clone())),
                Err(_) => true,
            };
            (brute, a.result.ok().map(|f| f.removals.len()), ok)
        })
        .collect();
    let mut good = 0;
    for (i, (brute, mcr, ok)) in rows.iter().enumerate() {
        assert!(ok, "world {i}: returned path does not re-check clean");
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
    }
    let needing = rows.iter().filter(|r| r.1.is_some_and(|m| m > 0)).count();
    eprintln!("planar3 World: fewest_removals <= grid minimum in {good}/30 worlds ({needing} need removals)");
    assert!(good >= 28);
}

/// The acceptance check of examples/box_lid.dcl on its hand transcription: for both
/// robots the can needs the lid removed and the lid is free (r2 carries it to its own
/// drop configuration, so its query uses the return-home layer as well).
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn box_lid_dcl_scene_can_needs_lid_lid_is_free() {
    let scn = box_lid_dcl();
    let w = world(&scn);
    let planner = Planner::new(&w, &scn.planner);
    let (can, lid) = (ObjectId(0), ObjectId(1));
    for r in scn.robot_ids() {
        let name = &scn.robot(r).name;
        let a = planner.find_path(r, &Goal::Grasp(lid));
        eprintln!("{:?}", a.stats);
        assert_eq!(a.stats.reused_vertices, 0, "the first query of a robot starts a fresh roadmap");
        let f = a.result.unwrap_or_else(|e| panic!("{name}: lid {e:?}"));
        assert_eq!(f.removals, ObjectSet::new(), "{name}: lid");
        assert_eq!(f.retreat.0.last().map(|q| q.0.clone()), Some(w.home(r).0.clone()), "{name}: back home");
        let a = planner.find_path(r, &Goal::Grasp(can));
        eprintln!("{:?}", a.stats);
        let f = a.result.unwrap_or_else(|e| panic!("{name}: can {e:?}"));
        assert_eq!(f.removals, ObjectSet::single(lid), "{name}: can");
    }
}

fn box_lid_scenario_from_file() -> Scenario {
    let mut sources = declutter::diag::SourceMap::new();
    declutter::resolve::resolve(std::path::Path::new("examples/box_lid.dcl"), &FsLoader, &mut sources)
        .unwrap_or_else(|e| panic!("{e:#?}"))
}

/// The transcription is the file: same objects, same grasps (world poses and stand-offs),
/// so the planner tests and benches that use it measure the shipped example.
#[test]
fn box_lid_transcription_matches_the_file() {
    let (code, file) = (box_lid_dcl(), box_lid_scenario_from_file());
    assert_eq!(code.objects.len(), file.objects.len());
    for (a, b) in code.objects.iter().zip(&file.objects) {
        assert_eq!(a.body.name, b.body.name);
        assert_eq!(a.grasps.len(), b.grasps.len(), "{}", a.body.name);
        for (ga, gb) in a.grasps.iter().zip(&b.grasps) {
            let d = ga.pose_world_tcp.inverse() * gb.pose_world_tcp;
            assert!(d.translation.vector.norm() < 1e-9 && d.rotation.angle() < 1e-9, "{} vs {}", ga.name, gb.name);
            assert!((ga.approach - gb.approach).abs() < 1e-12);
        }
    }
}
