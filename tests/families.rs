//! The benchmark families of `tests/common/families.rs` (a real TX-90 among generated
//! obstacles): pinned solved counts on a small subset, every schedule verified, and
//! no removal in the narrow-gap family. Skipped when `../shared/robots` is absent.

#[path = "common/families.rs"]
mod families;

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::schedule::Status;
use declutter::world::{self, WorldOptions};
use families::{probe, problem, shared_robots, Arm, FAMILIES};

/// (solved, removals) of one problem, planned and verified as `compile` does.
fn solve(path: &Path) -> (bool, usize) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(path, &FsLoader, &mut sources).expect("resolves");
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("builds");
    match declutter::driver::plan_verified(&w, &|_| {}) {
        Ok(p) => (p.schedule.status == Status::Solved, p.schedule.removed.len()),
        Err(v) => panic!("{}: the schedule failed verification: {v:?}", path.display()),
    }
}

/// Solved counts per family over problems `0..n`, and the removals in `narrow_gap`.
fn run(arm: Arm, n: u64, dir: &Path) -> Option<Vec<(String, u64, usize)>> {
    let robots = shared_robots()?;
    let probe = probe(arm, &robots, dir).expect("the arm builds on the table");
    let mut out = Vec::new();
    for family in FAMILIES {
        let (mut solved, mut removals) = (0, 0);
        for i in 0..n {
            // A draw that never yields a clear goal among its obstacles counts as unsolved.
            let Some(p) = problem(arm, &probe, &robots, dir, family, i) else {
                eprintln!("{arm:?} {family} {i}: no clear goal in the draws allowed");
                continue;
            };
            let (ok, r) = solve(&p.path);
            solved += u64::from(ok);
            removals += r;
        }
        out.push((family.to_string(), solved, removals));
    }
    Some(out)
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn solved_counts_of_the_first_ten_per_family() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("families");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let Some(got) = run(Arm::Tx90, 10, &dir) else { return };
    let text: Vec<String> = got.iter().map(|(f, s, r)| format!("{f}: {s}/10 solved, {r} removed")).collect();
    insta::assert_snapshot!(text.join("\n"));
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn panda_solved_counts_of_the_first_five_per_family() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("families-panda");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let Some(got) = run(Arm::Panda, 5, &dir) else { return };
    let text: Vec<String> = got.iter().map(|(f, s, r)| format!("{f}: {s}/5 solved, {r} removed")).collect();
    insta::assert_snapshot!(text.join("\n"));
}

/// The solved fraction over 100 problems per family (`cargo test --release --test
/// families -- --ignored --nocapture`); the times are the bench's (`cargo bench --bench
/// families`).
#[test]
#[ignore = "a long run: 400 problems"]
fn solved_fraction_of_a_hundred_per_family() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("families-100");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let n = std::env::var("FAMILY_N").ok().and_then(|v| v.parse().ok()).unwrap_or(100);
    for arm in [Arm::Tx90, Arm::Panda] {
        let Some(got) = run(arm, n, &dir) else { return };
        for (f, s, r) in got {
            println!("{arm:?} {f}: {s}/{n} solved, {r} removed");
        }
    }
}
