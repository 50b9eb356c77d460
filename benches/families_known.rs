//! The measure of the benchmark families: over every problem known to have a
//! free path (the stored table of `tests/common/families/known.rs`), per arm and family,
//! the solved fraction, the removals, and the median and 95th percentile (nearest rank)
//! of the time from the written scenario to a verified schedule (resolve, world build,
//! plan, schedule, verify) — what `declutter compile` does, in-process. Skipped when
//! `../shared/robots` is absent.
//!
//! One core: `RAYON_NUM_THREADS=1 cargo bench --bench families_known` (about ten
//! minutes; two processes with `FAMILY_ARMS=Tx90,Panda` and `FAMILY_ARMS=Ur5,PandaMesh`
//! take five each). `FAMILY_NAMES=cage,narrow_gap` for some families only;
//! `FAMILY_REPEAT=3` times each problem three times and keeps its median.
//!
//! Times are the process's CPU time (on a shared machine the wall clock also counts
//! waiting for a core); the wall-clock median and 95th percentile are printed beside
//! them, and the median CPU time of each stage: loading (resolve, URDFs, world build),
//! planning (the planner's queries, the AND/OR graph and the schedule, every refinement's)
//! and verifying (the replay). A schedule that fails verification is counted unsolved and printed; *replanned*
//! counts the problems whose first schedule failed verification and were planned again at
//! a finer resolution (as `compile` does), the time of both included.

use std::cell::RefCell;
use std::path::Path;
use std::time::Instant;

use declutter::diag::{FsLoader, SourceMap};
use declutter::schedule::Status;
use declutter::world::{self, WorldOptions};

#[path = "support/cpu_time.rs"]
mod cpu_time;
#[path = "../tests/common/families.rs"]
mod families;

use families::known::{Known, KNOWN};
use families::{chosen, probe, problem, shared_robots, ARMS};

/// What one problem came to.
struct Outcome {
    solved: bool,
    removals: usize,
    /// Planned again at a finer resolution because the first schedule failed verification.
    replanned: bool,
    cpu_s: f64,
    wall_s: f64,
    /// CPU seconds of the stages (of the median run): loading (resolve and world build),
    /// planning (the planner, the AND/OR graph and the schedule, every refinement's) and
    /// verifying.
    stages: [f64; 3],
}

/// Load to verified schedule, as `compile` does; the schedule must be solved and verified.
/// (solved, removals, replanned), and the CPU time of each stage (see [`Outcome`]).
fn end_to_end(path: &Path, clock: &cpu_time::CpuTime) -> ((bool, usize, bool), [f64; 3]) {
    let start = clock.now_ns();
    let mut sources = SourceMap::new();
    let world = declutter::resolve::resolve(path, &FsLoader, &mut sources)
        .map_err(|e| format!("resolve: {e:?}"))
        .and_then(|scn| world::build(&scn, &WorldOptions::default(), &FsLoader).map_err(|e| format!("world: {e:?}")));
    let loaded = clock.now_ns();
    let w = match world {
        Ok(w) => w,
        Err(e) => {
            eprintln!("{}: {e}", path.display());
            return ((false, 0, true), [0.0; 3]);
        }
    };
    // The driver says when each phase starts: planning (once per resolution tried) or
    // verifying.
    let phases: RefCell<Vec<(bool, u64)>> = RefCell::new(Vec::new());
    let planned = declutter::driver::plan_verified(&w, &|phase: &str| {
        phases.borrow_mut().push((phase.starts_with("verifying"), clock.now_ns()))
    });
    let end = clock.now_ns();
    let mut stages = [(loaded - start) as f64 * 1e-9, 0.0, 0.0];
    let phases = phases.into_inner();
    for (k, &(verifying, from)) in phases.iter().enumerate() {
        let to = phases.get(k + 1).map_or(end, |p| p.1);
        stages[if verifying { 2 } else { 1 }] += (to - from) as f64 * 1e-9;
    }
    let outcome = match planned {
        Ok(p) => (p.schedule.status == Status::Solved, p.schedule.removed.len(), p.refinements > 0),
        Err(v) => {
            eprintln!("{}: the schedule failed verification: {v:?}", path.display());
            (false, 0, true)
        }
    };
    (outcome, stages)
}

/// One run: CPU and wall seconds, (solved, removals, replanned), the stages' CPU seconds.
type Run = (f64, f64, (bool, usize, bool), [f64; 3]);

/// `repeat` runs of one problem; its median times (the runs plan the same: one seed).
fn timed(path: &Path, repeat: usize) -> Outcome {
    let clock = cpu_time::CpuTime::process();
    let mut runs: Vec<Run> = (0..repeat)
        .map(|_| {
            let (c, t) = (clock.now_ns(), Instant::now());
            let (outcome, stages) = end_to_end(path, &clock);
            ((clock.now_ns() - c) as f64 * 1e-9, t.elapsed().as_secs_f64(), outcome, stages)
        })
        .collect();
    runs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (cpu_s, _, (solved, removals, replanned), stages) = runs[runs.len() / 2];
    let mut walls: Vec<f64> = runs.iter().map(|r| r.1).collect();
    walls.sort_by(f64::total_cmp);
    Outcome { solved, removals, replanned, cpu_s, wall_s: walls[walls.len() / 2], stages }
}

/// The `p`-quantile of sorted `xs` (nearest rank), in milliseconds.
fn ms(xs: &[f64], p: f64) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    1000.0 * xs[((p * xs.len() as f64).ceil() as usize).clamp(1, xs.len()) - 1]
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` runs this once with no
    // such flag, where a ten-minute measure has no place.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let Some(robots) = shared_robots() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("families-measure");
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("{}: {e}", dir.display());
        std::process::exit(1);
    }
    let repeat: usize = std::env::var("FAMILY_REPEAT").ok().and_then(|v| v.parse().ok()).unwrap_or(1).max(1);
    // Over every row: (solved, known path, removals, replanned).
    let mut all = (0, 0, 0, 0);
    println!(
        "| arm | family | solved / known path | removals | replanned | median | p95 | wall median | wall p95 | load | plan | verify |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for arm in ARMS.into_iter().filter(|a| chosen("FAMILY_ARMS", &format!("{a:?}"))) {
        let Some(probe) = probe(arm, &robots, &dir) else {
            eprintln!("{arm:?} does not build on the table");
            std::process::exit(1);
        };
        for &Known { family, paths, .. } in KNOWN.iter().filter(|k| k.arm == arm && chosen("FAMILY_NAMES", k.family)) {
            let mut outs = Vec::new();
            for &(i, _) in paths {
                let Some(p) = problem(arm, &probe, &robots, &dir, family, i) else {
                    eprintln!("{arm:?} {family} {i}: a known problem no longer draws its goal");
                    std::process::exit(1);
                };
                outs.push(timed(&p.path, repeat));
            }
            let solved = outs.iter().filter(|o| o.solved).count();
            let removals: usize = outs.iter().map(|o| o.removals).sum();
            let replanned = outs.iter().filter(|o| o.replanned).count();
            all = (all.0 + solved, all.1 + paths.len(), all.2 + removals, all.3 + replanned);
            let sorted = |f: fn(&Outcome) -> f64| {
                let mut v: Vec<f64> = outs.iter().map(f).collect();
                v.sort_by(f64::total_cmp);
                v
            };
            let (cpu, wall) = (sorted(|o| o.cpu_s), sorted(|o| o.wall_s));
            let (load, plan, verify) = (sorted(|o| o.stages[0]), sorted(|o| o.stages[1]), sorted(|o| o.stages[2]));
            println!(
                "| {arm:?} | `{family}` | {solved} / {} | {removals} | {replanned} | {:.1} ms | {:.0} ms | {:.1} ms | {:.0} ms | {:.2} ms | {:.2} ms | {:.2} ms |",
                paths.len(),
                ms(&cpu, 0.5),
                ms(&cpu, 0.95),
                ms(&wall, 0.5),
                ms(&wall, 0.95),
                ms(&load, 0.5),
                ms(&plan, 0.5),
                ms(&verify, 0.5),
            );
        }
    }
    println!(
        "\nIn all: {} of {} solved, {} removals, {} planned again at a finer resolution.",
        all.0, all.1, all.2, all.3
    );
}
