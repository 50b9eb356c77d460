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

/// Established on 2026-11-25 on the shared 2-core machine: `KNOWN_N=10 KNOWN_SEEDS=2`
/// (13 minutes; the UR5's last three families again after its wrist's size was
/// corrected, 3 s), then `KNOWN_FROM=10 KNOWN_N=20 KNOWN_SEEDS=2` (13 minutes).
#[rustfmt::skip]
pub const KNOWN: &[Known] = &[
    Known { arm: Arm::Tx90, family: "table_top", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Tx90, family: "cage", examined: 20, paths: &[(0, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Tx90, family: "shelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Tx90, family: "narrow_gap", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Tx90, family: "bookshelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Tx90, family: "deep_box", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Tx90, family: "under_table", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Panda, family: "table_top", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Panda, family: "cage", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Panda, family: "shelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Panda, family: "narrow_gap", examined: 20, paths: &[(0, 0), (1, 0), (3, 1), (4, 0), (5, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (17, 0), (18, 0)] },
    Known { arm: Arm::Panda, family: "bookshelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Panda, family: "deep_box", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Panda, family: "under_table", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Ur5, family: "table_top", examined: 20, paths: &[(0, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Ur5, family: "cage", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (5, 0), (6, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Ur5, family: "shelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Ur5, family: "narrow_gap", examined: 20, paths: &[(1, 0), (2, 0), (5, 0), (6, 0), (7, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (16, 0)] },
    Known { arm: Arm::Ur5, family: "bookshelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::Ur5, family: "deep_box", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (17, 0), (18, 0)] },
    Known { arm: Arm::Ur5, family: "under_table", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::PandaMesh, family: "table_top", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::PandaMesh, family: "cage", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::PandaMesh, family: "shelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::PandaMesh, family: "narrow_gap", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (19, 0)] },
    Known { arm: Arm::PandaMesh, family: "bookshelf", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::PandaMesh, family: "deep_box", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
    Known { arm: Arm::PandaMesh, family: "under_table", examined: 20, paths: &[(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (6, 0), (7, 0), (8, 0), (9, 0), (10, 0), (11, 0), (12, 0), (13, 0), (14, 0), (15, 0), (16, 0), (17, 0), (18, 0), (19, 0)] },
];
