//! Which generated problems have a free path, established once by RRT-Connect
//! (`tests/common/rrt.rs`, the exact check, no removable object touched) and stored here
//! as data: `tests/families.rs`'s `establish_known_paths` printed this table, and
//! `known_paths_are_found_again_with_their_seeds` re-checks part of it.

use super::Arm;

/// RRT-Connect's iterations per seed when the table was established.
pub const ITERATIONS: usize = 100_000;

/// One arm and family: problems `0..examined` were examined; `paths` lists (index,
/// seed) of those RRT-Connect found a path for, with the first seed that did. An index
/// not listed had no clear goal, or no path within three seeds.
pub struct Known {
    pub arm: Arm,
    pub family: &'static str,
    pub examined: u64,
    pub paths: &'static [(u64, u64)],
}

pub const KNOWN: &[Known] = &[];
