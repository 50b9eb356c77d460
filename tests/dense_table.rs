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
    assert_eq!(planned.schedule.removed.last().map(String::as_str), Some("target"));
    // The target's side grasps are blocked by its nearest neighbours: something goes first.
    assert!(planned.schedule.removed.len() >= 2, "{:?}", planned.schedule.removed);
}
