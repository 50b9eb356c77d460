//! PRMwO query times: the box-and-lid cells (two TX-90s; hand-built, and the
//! transcription of examples/box_lid.dcl) and a random planar-arm world,
//! first query on a fresh roadmap and the same query on the reused roadmap.
//! Run single-threaded for the one-core figure: `RAYON_NUM_THREADS=1 cargo bench --bench plan`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use declutter::diag::FsLoader;
use declutter::plan::{Goal, Oracle, Planner, PrmOptions, RobotPlanner};
use declutter::resolve::{ObjectId, PlannerSettings};
use declutter::world::{build, WorldOptions};

#[path = "../tests/common/box_lid.rs"]
mod box_lid;
#[path = "../tests/common/planar.rs"]
mod planar;
#[path = "../tests/world_support/mod.rs"]
mod world_support;

fn box_lid_queries(c: &mut Criterion) {
    for (scene, scn) in [("box_lid", box_lid::box_lid()), ("box_lid_dcl", box_lid::box_lid_dcl())] {
        scene_queries(c, scene, &scn);
    }
}

fn scene_queries(c: &mut Criterion, scene: &str, scn: &declutter::resolve::Scenario) {
    let w = build(scn, &WorldOptions::default(), &FsLoader).expect("world");
    for r in scn.robot_ids() {
        for (o, name) in [(ObjectId(0), "can"), (ObjectId(1), "lid")] {
            let goal = Goal::Grasp(o);
            let robot = &scn.robot(r).name;
            let p = Planner::new(&w, &scn.planner);
            let first = p.find_path(r, &goal);
            let again = p.find_path(r, &goal);
            eprintln!("{scene}/{robot}/{name}: first {:?}", first.stats);
            eprintln!("{scene}/{robot}/{name}: reused {:?}", again.stats);
            c.bench_function(&format!("{scene}/{robot}/{name}/first"), |b| {
                b.iter_batched(
                    || Planner::new(&w, &scn.planner),
                    |p| black_box(p.find_path(r, &goal)),
                    BatchSize::SmallInput,
                )
            });
            c.bench_function(&format!("{scene}/{robot}/{name}/reused"), |b| {
                b.iter(|| black_box(p.find_path(r, &goal)))
            });
        }
    }
}

fn planar_queries(c: &mut Criterion) {
    let (w, goal) = planar::random_world(1007, 64);
    let goal = Goal::Reach(goal.into());
    let settings = PlannerSettings::default();
    let p = RobotPlanner::new(w.clone(), &settings, &PrmOptions::default(), 0);
    eprintln!("planar: first {:?}", p.query(&goal).stats);
    eprintln!("planar: reused {:?}", p.query(&goal).stats);
    c.bench_function("planar/reach/first", |b| {
        b.iter_batched(
            || RobotPlanner::new(w.clone(), &settings, &PrmOptions::default(), 0),
            |p| black_box(p.query(&goal)),
            BatchSize::SmallInput,
        )
    });
    c.bench_function("planar/reach/reused", |b| b.iter(|| black_box(p.query(&goal))));
}

criterion_group!(benches, box_lid_queries, planar_queries);
criterion_main!(benches);
