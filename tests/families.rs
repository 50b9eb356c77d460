//! The benchmark families of `tests/common/families.rs` (a real TX-90 among generated
//! obstacles): pinned solved counts on a small subset, every schedule verified, and
//! no removal in the narrow-gap family. Skipped when `../shared/robots` is absent.

#[path = "common/families.rs"]
mod families;
#[path = "common/rrt.rs"]
mod rrt;

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::{RobotId, Target};
use declutter::schedule::Status;
use declutter::world::{self, World, WorldOptions};
use families::{probe, problem, shared_robots, Arm, FAMILIES};

/// A problem's world and its target configuration.
fn load(path: &Path) -> (World, Vec<f64>) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(path, &FsLoader, &mut sources).expect("resolves");
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("builds");
    let Target::Config { q, .. } = &scn.target else { panic!("{}: a configuration target", path.display()) };
    let goal = q.values.clone();
    (w, goal)
}

/// (solved, removals) of one problem, planned and verified as `compile` does.
fn solve(path: &Path) -> (bool, usize) {
    solve_in(&load(path).0, path)
}

/// [`solve`] on a problem already loaded from `path`.
fn solve_in(w: &World, path: &Path) -> (bool, usize) {
    match declutter::driver::plan_verified(w, &|_| {}) {
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

/// Per family over problems `0..n`: which a plain RRT-Connect (over the exact check,
/// touching no removable object) finds a path for, and which `declutter` solves.
fn against_rrt(arm: Arm, n: u64, iterations: usize, dir: &Path) -> Option<Vec<String>> {
    let robots = shared_robots()?;
    let probe = probe(arm, &robots, dir).expect("the arm builds on the table");
    let mut out = Vec::new();
    for family in FAMILIES {
        let (mut by_rrt, mut by_us) = (Vec::new(), Vec::new());
        for i in 0..n {
            let Some(p) = problem(arm, &probe, &robots, dir, family, i) else { continue };
            let (w, goal) = load(&p.path);
            let r = RobotId(0);
            if let Some(path) = rrt::rrt_connect(&w, r, w.home(r), &goal, iterations, i) {
                assert!(path.windows(2).all(|s| rrt::motion_free(&w, r, &s[0], &s[1])), "{family} {i}: a free path");
                by_rrt.push(i);
            }
            if solve_in(&w, &p.path).0 {
                by_us.push(i);
            }
        }
        let missed: Vec<u64> = by_rrt.iter().filter(|i| !by_us.contains(i)).copied().collect();
        out.push(format!("{family}: RRT-Connect {by_rrt:?}, declutter {by_us:?}, missed {missed:?}"));
    }
    Some(out)
}

/// With the same budget (5000 RRT-Connect iterations, `declutter`'s default 5000
/// samples), `declutter` solves every problem of the first ten per family that the
/// standard planner solves.
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn a_standard_planner_with_the_same_budget_solves_no_more() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("families-rrt");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let Some(got) = against_rrt(Arm::Tx90, 10, 5000, &dir) else { return };
    assert!(got.iter().all(|l| l.ends_with("missed []")), "{got:#?}");
    insta::assert_snapshot!(got.join("\n"));
}

/// On the Panda, RRT-Connect with ten times the budget (50 000 iterations, under a
/// second each here) finds paths through the narrow gap that `declutter` misses with its
/// default: a shortfall pinned so that closing it shows (issue 12).
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn panda_through_the_narrow_gap_a_standard_planner_finds_what_declutter_misses() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("families-panda-rrt");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let Some(got) = against_rrt(Arm::Panda, 5, 50_000, &dir) else { return };
    insta::assert_snapshot!(got.join("\n"));
}

/// Whether the problems `declutter` leaves unsolved have a path at all: RRT-Connect with
/// 100 000 iterations, five seeds each (`cargo test --release --test families --
/// --ignored --nocapture unsolved`; minutes).
#[test]
#[ignore = "a long run: RRT-Connect at 100 000 iterations"]
fn whether_the_unsolved_have_a_path() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("families-rrt-long");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let Some(robots) = shared_robots() else { return };
    let probe = probe(Arm::Tx90, &robots, &dir).expect("the arm builds on the table");
    for family in FAMILIES {
        for i in 0..10 {
            let Some(p) = problem(Arm::Tx90, &probe, &robots, &dir, family, i) else { continue };
            let (w, goal) = load(&p.path);
            if solve_in(&w, &p.path).0 {
                continue;
            }
            let r = RobotId(0);
            let found: Vec<u64> =
                (0..5).filter(|&seed| rrt::rrt_connect(&w, r, w.home(r), &goal, 100_000, seed).is_some()).collect();
            println!("{family} {i}: unsolved by declutter; RRT-Connect found a path with seeds {found:?} of 0..5");
        }
    }
}
