//! End to end: each shipped example compiled (world built once, then planning, the
//! AND/OR graph, the schedule and its verification), each also from the file (parse,
//! resolve, URDFs, world, then the same: what the user waits for), and a scaling
//! series of N cans around a target, each timed by wall clock and by process CPU time;
//! and the timing and verifying stages apart (`stage/`, wall clock).
//!
//! `RAYON_NUM_THREADS=1 cargo bench --bench compile` (one core)

use std::path::Path;

use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use declutter::diag::{FsLoader, SourceMap};
use declutter::world::{self, World, WorldOptions};

#[path = "../tests/common/table.rs"]
mod table;

#[path = "support/cpu_time.rs"]
mod cpu_time;
use cpu_time::CpuTime;

fn world_of(path: &Path) -> World {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(path, &FsLoader, &mut sources).expect("scenario resolves");
    world::build(&scn, &WorldOptions::default(), &FsLoader).expect("world builds")
}

/// What `compile` does between loading and writing: plan, schedule, verify.
fn plan_and_schedule(w: &World) -> usize {
    match declutter::driver::plan_verified(w, &|_| {}) {
        Ok(p) => p.schedule.actions.len(),
        Err(v) => panic!("bench scene failed verification: {v:?}"),
    }
}

/// Every shipped scenario with a target (`cell.dcl` is a library).
fn example_names() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("examples/ exists")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter_map(|f| f.strip_suffix(".dcl").map(str::to_string))
        .filter(|n| n != "cell")
        .collect();
    names.sort();
    names
}

/// From the file to the verified schedule: what `declutter compile` does but writing.
fn from_file(path: &Path) -> usize {
    plan_and_schedule(&world_of(path))
}

fn examples<M: Measurement + 'static>(c: &mut Criterion<M>, tag: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut g = c.benchmark_group(format!("{tag}compile"));
    g.sample_size(20);
    for name in example_names() {
        let w = world_of(&dir.join(format!("{name}.dcl")));
        g.bench_function(&name, |b| b.iter(|| plan_and_schedule(&w)));
    }
    g.finish();
    let mut g = c.benchmark_group(format!("{tag}from_file"));
    g.sample_size(20);
    for name in example_names() {
        let path = dir.join(format!("{name}.dcl"));
        g.bench_function(name, |b| b.iter(|| from_file(&path)));
    }
    g.finish();
}

fn scaling<M: Measurement + 'static>(c: &mut Criterion<M>, tag: &str) {
    let mut g = c.benchmark_group(format!("{tag}table"));
    g.sample_size(10);
    for n in [5, 10, 20, 50, 100, 200] {
        let w = world_of(&table::can_table(n, Path::new(env!("CARGO_TARGET_TMPDIR"))));
        g.bench_with_input(BenchmarkId::from_parameter(n), &w, |b, w| b.iter(|| plan_and_schedule(w)));
    }
    g.finish();
}

/// The stages after planning, apart: timing a planned solution (the concurrent
/// placement with its distance checks) and the verifier's replay of the schedule.
fn stages(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut g = c.benchmark_group("stage");
    g.sample_size(20);
    for name in ["box_lid", "cans_3", "cans_5", "split_lid"] {
        let w = world_of(&dir.join(format!("{name}.dcl")));
        let planned = declutter::driver::plan_verified(&w, &|_| {}).expect("verifies");
        let (sol, sched) = (&planned.solution, &planned.schedule);
        g.bench_function(format!("timing/{name}"), |b| {
            b.iter(|| declutter::schedule::build(&w, sol, declutter::schedule::Execution::Concurrent).makespan)
        });
        g.bench_function(format!("verify/{name}"), |b| b.iter(|| declutter::verify::verify(&w, sched).is_ok()));
    }
    g.finish();
}

fn wall(c: &mut Criterion) {
    examples(c, "");
    scaling(c, "");
    stages(c);
}

fn cpu(c: &mut Criterion<CpuTime>) {
    examples(c, "cpu_");
    scaling(c, "cpu_");
}

criterion_group!(wall_clock, wall);
criterion_group! {
    name = cpu_clock;
    config = Criterion::default().with_measurement(CpuTime::process());
    targets = cpu
}
criterion_main!(wall_clock, cpu_clock);
