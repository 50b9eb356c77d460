//! The fixed (and removable) boxes of each family, in the hand's frame: x from the base
//! out to the hand, y to its left, z up from the table (`at[2]` is a height, not an
//! offset from the hand).

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::Arm;

/// A box in the hand's frame.
pub struct Obstacle {
    pub size: [f64; 3],
    pub at: [f64; 3],
    pub removable: bool,
}

fn fixed(size: [f64; 3], at: [f64; 3]) -> Obstacle {
    Obstacle { size, at, removable: false }
}

/// `lo + (hi - lo) * u`, `u` uniform in [0, 1).
fn between(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

/// The obstacles of `family` around a hand at height `z`. The first four families draw
/// as they always have (their problems must not change; `narrow_gap`'s boxes were moved
/// apart on 2026-11-27 with as many draws, its table of known paths established again);
/// the later ones scale with the arm's hand.
pub fn obstacles(family: &str, arm: Arm, rng: &mut ChaCha8Rng, z: f64) -> Vec<Obstacle> {
    let mut out = Vec::new();
    let (width, length) = arm.hand();
    match family {
        "table_top" => {
            // A few fixed blocks around, not under, the hand.
            for _ in 0..3 {
                let (a, d) = (rng.random::<f64>() * std::f64::consts::TAU, 0.18 + 0.1 * rng.random::<f64>());
                out.push(fixed([0.06, 0.06, 0.12], [d * a.cos(), d * a.sin(), 0.06]));
            }
        }
        "cage" => {
            let h = 0.11 + 0.03 * rng.random::<f64>();
            let top = z + 0.12;
            for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                out.push(fixed([0.02, 0.02, top], [sx * h, sy * h, top / 2.0]));
            }
            out.push(fixed([2.0 * h + 0.04, 2.0 * h + 0.04, 0.02], [0.0, 0.0, top + 0.01]));
        }
        "shelf" => {
            let gap = 0.13 + 0.05 * rng.random::<f64>();
            let (below, above) = (z - gap / 2.0, z + gap / 2.0);
            out.push(fixed([0.4, 0.6, 0.02], [0.05, 0.0, below.max(0.03) - 0.01]));
            out.push(fixed([0.4, 0.6, 0.02], [0.05, 0.0, above + 0.01]));
            out.push(fixed([0.02, 0.6, above + 0.02], [0.26, 0.0, (above + 0.02) / 2.0]));
        }
        "narrow_gap" => {
            // A wall 10 cm in front of the hand (towards the base) with a window around
            // the line from the base to the hand, 16-20 cm wide.
            let w = 0.08 + 0.02 * rng.random::<f64>();
            let x = -0.1;
            let height = z + 0.4;
            out.push(fixed([0.02, 0.5, height], [x, w + 0.25, height / 2.0]));
            out.push(fixed([0.02, 0.5, height], [x, -w - 0.25, height / 2.0]));
            out.push(fixed([0.02, 2.0 * w, (z - w).max(0.0)], [x, 0.0, (z - w).max(0.0) / 2.0]));
            out.push(fixed([0.02, 2.0 * w, height - z - w], [x, 0.0, (height + z + w) / 2.0]));
            // Removable boxes beside the window on the near side, never in it: two a side,
            // each in its own 7.5 cm slot, so that they stand clear of each other (5 cm
            // boxes at least 5.5 cm apart; drawn anywhere in one 8 cm band, most pairs
            // overlapped, a scene `declutter check` rejects).
            for k in 0..4 {
                let side = if k % 2 == 0 { 1.0 } else { -1.0 };
                let slot = (k / 2) as f64;
                let off = w + 0.06 + 0.075 * slot + 0.02 * rng.random::<f64>();
                out.push(Obstacle { size: [0.05, 0.05, 0.1], at: [x - 0.08, side * off, 0.05], removable: true });
            }
        }
        "bookshelf" => {
            // 3-4 boards a shelf's height apart between two sides and a back, open to the
            // base; the hand in one shelf, `reach_in` behind its front edge.
            let boards = 3 + (rng.random::<f64>() < 0.5) as usize;
            let gap = between(rng, width + 0.1, width + 0.18);
            let (depth, wide) = (between(rng, 0.32, 0.4), between(rng, 0.5, 0.7));
            let reach_in = between(rng, 0.1, 0.18);
            // The hand's height above the board below it, and which shelf that is: any
            // whose bottom board stays above the table.
            let above = between(rng, 0.35, 0.6) * gap;
            let highest = (((z - above - 0.02) / gap).floor() as usize).min(boards - 2);
            let shelf = (rng.random::<f64>() * (highest + 1) as f64) as usize;
            let bottom = z - above - shelf as f64 * gap;
            let top = bottom + (boards - 1) as f64 * gap;
            let x = depth / 2.0 - reach_in;
            for k in 0..boards {
                out.push(fixed([depth, wide, 0.02], [x, 0.0, bottom + k as f64 * gap]));
            }
            for side in [1.0, -1.0] {
                out.push(fixed([depth, 0.02, top + 0.01], [x, side * (wide + 0.02) / 2.0, (top + 0.01) / 2.0]));
            }
            out.push(fixed([0.02, wide + 0.04, top + 0.01], [depth - reach_in + 0.01, 0.0, (top + 0.01) / 2.0]));
        }
        "deep_box" => {
            // An open box on the table, its walls rising above the wrist of a hand that
            // points down into it near the floor; the hand off its centre by a little.
            let half = [
                between(rng, 0.5 * width + 0.06, 0.5 * width + 0.12),
                between(rng, 0.5 * width + 0.06, 0.5 * width + 0.12),
            ];
            let height = z + length + between(rng, 0.04, 0.1);
            let centre = [between(rng, -0.03, 0.03), between(rng, -0.03, 0.03)];
            for side in [1.0, -1.0] {
                let at_x = [centre[0] + side * (half[0] + 0.01), centre[1], height / 2.0];
                out.push(fixed([0.02, 2.0 * half[1] + 0.04, height], at_x));
                let at_y = [centre[0], centre[1] + side * (half[1] + 0.01), height / 2.0];
                out.push(fixed([2.0 * half[0], 0.02, height], at_y));
            }
        }
        "under_table" => {
            // A second table over the hand, on four legs; its near edge between the hand
            // and the base, so the hand reaches in under it between the near legs.
            let clear = between(rng, length + 0.02, length + 0.1);
            let top = z + clear;
            let (depth, wide) = (between(rng, 0.45, 0.65), between(rng, 0.6, 0.8));
            let near = -between(rng, 0.12, 0.22);
            let x = near + depth / 2.0;
            out.push(fixed([depth, wide, 0.03], [x, 0.0, top + 0.015]));
            for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                let at = [x + sx * (depth / 2.0 - 0.03), sy * (wide / 2.0 - 0.03), top / 2.0];
                out.push(fixed([0.04, 0.04, top], at));
            }
        }
        _ => {}
    }
    out
}
