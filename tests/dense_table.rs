//! Certification: in a dense table the planner's coarse checks step over the gaps
//! between cans; the certifying check on chosen paths must find what they miss, so the
//! schedule verifies at the scenario's own resolution without re-planning.

#[path = "common/table.rs"]
mod table;

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::world::{self, WorldOptions};

#[test]
fn a_twenty_can_table_verifies_without_refinement() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let path = table::can_table(20, dir);
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(&path, &FsLoader, &mut sources).expect("scene resolves");
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("world builds");
    let planned = match declutter::driver::plan_verified(&w, &|_| {}) {
        Ok(p) => p,
        Err(v) => panic!("verification failed: {v:?}"),
    };
    assert_eq!(planned.refinements, 0, "the schedule needed a finer resolution");
    // `removed` lists the blockers only; the target is grasped by the last action.
    assert!(!planned.schedule.removed.iter().any(|o| o == "target"), "{:?}", planned.schedule.removed);
    assert_eq!(planned.schedule.actions.last().and_then(|a| a.object.as_deref()), Some("target"));
    // The target's side grasps are blocked by its nearest neighbours: something goes first.
    assert!(!planned.schedule.removed.is_empty(), "{:?}", planned.schedule.removed);
}

/// The scaling series of the book's Performance page (`book/src/figures/scaling.csv`):
/// its queries, removals and collision checks are deterministic for the seed, so they
/// must be what the planner does today (the median times are the bench's own).
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn the_books_scaling_figures_are_current() {
    let csv = std::fs::read_to_string("book/src/figures/scaling.csv").expect("the figures exist");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("scaling");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let page = std::fs::read_to_string("book/src/performance.md").expect("the page exists");
    let mut rows = csv.lines();
    assert_eq!(rows.next(), Some("cans,median_ms,queries,removals,checks"));
    for row in rows {
        let cells: Vec<&str> = row.split(',').collect();
        let n: usize = cells[0].parse().expect("a count of cans");
        let mut sources = SourceMap::new();
        let scn = declutter::resolve::resolve(&table::can_table(n, &dir), &FsLoader, &mut sources).expect("resolves");
        let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("world builds");
        let s = declutter::driver::plan_verified(&w, &|_| {}).expect("verifies").schedule;
        let removals = s.removed.iter().filter(|o| o.as_str() != "target").count();
        let checks: u64 = s.stats.iter().map(|q| q.checks).sum();
        let got = format!("{},{},{}", s.stats.len(), removals, checks);
        assert_eq!(cells[2..].join(","), got, "{n} cans (queries,removals,checks): update scaling.csv and the page");
        // The page's table shows the same row, checks with a space between thousands.
        let (k, units) = (s.stats.len(), checks % 1000);
        let checks = if checks >= 1000 { format!("{} {units:03}", checks / 1000) } else { checks.to_string() };
        let line = format!("| {n} | ");
        let page_row = page.lines().find(|l| l.replace("  ", " ").starts_with(&line)).expect("a row per count");
        let tail = format!("| {k} | {removals} | {checks} |");
        assert!(page_row.ends_with(&tail), "performance.md: `{page_row}` should end with `{tail}`");
    }
}
