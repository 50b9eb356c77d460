//! Show: (World, Schedule, violations) -> one self-contained HTML page that replays the
//! schedule in 3-D (`declutter show`).
//!
//! In: a built world, optionally a schedule and what `verify` said about it. Out: an
//! HTML string holding three.js (vendored, inlined), a small viewer script, and one
//! JSON blob: every body's collision geometry as the world loaded it, and the world
//! pose of every moving body at fixed keyframes, which the page interpolates. The time
//! is the schedule's own (its trajectories and events), read in [`timeline`] alone. Sits beside `verify` at the
//! end of the pipeline; only the driver calls it.

mod page;
mod scene;
mod timeline;

pub use page::{html, THREE_VERSION};
pub use scene::{SceneData, KEYFRAME_STEP, MAX_KEYFRAMES};
pub use timeline::{timeline, Timeline};

use crate::schedule::Schedule;
use crate::verify::Violation;
use crate::world::World;

/// The page for a world, and a schedule with its violations (none when it verified).
pub fn show(world: &World, schedule: Option<&Schedule>, violations: &[Violation]) -> String {
    let timeline = timeline(world, schedule);
    html(&scene::build(world, schedule, &timeline, violations))
}
