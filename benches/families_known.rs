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
//! them. A schedule that fails verification is counted unsolved and printed; *replanned*
//! counts the problems whose first schedule failed verification and were planned again at
//! a finer resolution (as `compile` does), the time of both included.

use std::path::Path;
use std::time::Instant;

use declutter::schedule::Status;

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
}

/// Load to verified schedule, as `compile` does; the schedule must be solved and verified.
/// (solved, removals, replanned).
fn end_to_end(path: &Path) -> (bool, usize, bool) {
    match families::compile(path) {
        Ok(p) => (p.schedule.status == Status::Solved, p.schedule.removed.len(), p.refinements > 0),
        Err(e) => {
            eprintln!("{}: {e}", path.display());
            (false, 0, true)
        }
    }
}

/// `repeat` runs of one problem; its median times (the runs plan the same: one seed).
fn timed(path: &Path, repeat: usize) -> Outcome {
    let clock = cpu_time::CpuTime::process();
    let mut runs: Vec<(f64, f64, (bool, usize, bool))> = (0..repeat)
        .map(|_| {
            let (c, t) = (clock.now_ns(), Instant::now());
            let outcome = end_to_end(path);
            ((clock.now_ns() - c) as f64 * 1e-9, t.elapsed().as_secs_f64(), outcome)
        })
        .collect();
    runs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (cpu_s, _, (solved, removals, replanned)) = runs[runs.len() / 2];
    let mut walls: Vec<f64> = runs.iter().map(|r| r.1).collect();
    walls.sort_by(f64::total_cmp);
    Outcome { solved, removals, replanned, cpu_s, wall_s: walls[walls.len() / 2] }
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
    println!("| arm | family | solved / known path | removals | replanned | median | p95 | wall median | wall p95 |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|");
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
            println!(
                "| {arm:?} | `{family}` | {solved} / {} | {removals} | {replanned} | {:.1} ms | {:.0} ms | {:.1} ms | {:.0} ms |",
                paths.len(),
                ms(&cpu, 0.5),
                ms(&cpu, 0.95),
                ms(&wall, 0.5),
                ms(&wall, 0.95)
            );
        }
    }
    println!(
        "\nIn all: {} of {} solved, {} removals, {} planned again at a finer resolution.",
        all.0, all.1, all.2, all.3
    );
}
