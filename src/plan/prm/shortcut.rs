//! Shortening a found path: waypoints are dropped where the straight move that
//! replaces them passes the certifying check touching only objects the path already
//! removes. The removal set cannot grow, so the answer stays as minimal as it was; the
//! motion gets shorter and loses the zigzags of goal trees and roadmap detours.

use crate::plan::{Map, Set};

use super::super::space::{Mode, Space};
use super::RobotPlanner;
use crate::world::{Check, ObjectSet};

impl<S: Space> RobotPlanner<S> {
    /// `run` with waypoints dropped, its ends kept: a straight move from `run[i]` to
    /// `run[k]` replaces the waypoints between when its certifying check touches only
    /// `allowed` (see [`drop_waypoints`]; the run's own steps are taken to have passed).
    ///
    /// Each move tried is decided on its coarse samples alone, and only the moves of the
    /// result get the rest of the check: most trial moves that pass are replaced by longer
    /// ones later, and the rest of their check (three samples in four) was most of a
    /// shortcut's cost. A move of the result that fails the rest is not taken again and the
    /// waypoints are dropped anew (every answer remembered). So the result is the one the
    /// full check of every move tried gives whenever every move that passed its coarse
    /// samples passes the rest; otherwise its waypoints may differ, each of its moves
    /// still having passed the whole check.
    pub(super) fn shortcut(
        &self,
        run: &[Vec<f64>],
        mode: &Mode,
        allowed: &ObjectSet,
        checks: &mut u64,
    ) -> Vec<Vec<f64>> {
        // The run's own steps passed: the result is always there.
        self.shortcut_certifying(run, mode, allowed, checks, |_, _| true).unwrap_or_else(|| run.to_vec())
    }

    /// [`Self::shortcut`] of a run whose own steps have passed only the coarse samples:
    /// `own(s, checks)` finishes the check of step `s` (from `run[s]` to `run[s + 1]`),
    /// asked only of the steps the result keeps, when the result is settled but for them.
    /// `None` once one fails. A free-space tree's path certified step by step before its
    /// shortcut spent a check on every step, most of which the shortcut then drops (the
    /// UR5's `narrow_gap` 54: 7 % of its compile).
    pub(super) fn shortcut_certifying(
        &self,
        run: &[Vec<f64>],
        mode: &Mode,
        allowed: &ObjectSet,
        checks: &mut u64,
        mut own: impl FnMut(usize, &mut u64) -> bool,
    ) -> Option<Vec<Vec<f64>>> {
        // Per move tried: its coarse answer, false once it failed the rest; the moves
        // that passed the rest.
        let mut coarse: Map<(usize, usize), bool> = Map::default();
        let mut sure: Set<(usize, usize)> = Set::default();
        'drop: loop {
            let kept = drop_waypoints(run.len(), |i, k| {
                *coarse
                    .entry((i, k))
                    .or_insert_with(|| self.coarse_within((&run[i], &run[k]), (false, false), mode, allowed, checks))
            });
            for w in kept.windows(2) {
                let (i, k) = (w[0], w[1]);
                if sure.contains(&(i, k)) {
                    continue;
                }
                if k == i + 1 {
                    if !own(i, checks) {
                        return None;
                    }
                } else if !self.rest_within((&run[i], &run[k]), mode, allowed, checks) {
                    coarse.insert((i, k), false);
                    continue 'drop;
                }
                sure.insert((i, k));
            }
            return Some(kept.iter().map(|&i| run[i].clone()).collect());
        }
    }

    /// The coarse samples of the certifying check of a step leaving `a`, itself known to
    /// touch nothing in `mode` (a free-space tree's node), touch nothing; `a` is not
    /// checked again. The rest is [`Self::rest_clear`]'s. The far end is checked first:
    /// most steps of a tree in a narrow passage are stopped, most often with their end
    /// inside something, which one check then says (the UR5's `narrow_gap` 66: 4 % fewer
    /// checks). Whether the step is clear does not depend on the order.
    pub(super) fn coarse_clear_leaving(&self, a: &[f64], b: &[f64], mode: &Mode, checks: &mut u64) -> bool {
        self.space.touches_nothing(b, mode, checks)
            && self.coarse_within((a, b), (true, true), mode, &ObjectSet::new(), checks)
    }

    /// The samples of the certifying check of a -> b that the coarse one does not take
    /// touch nothing in `mode`.
    pub(super) fn rest_clear(&self, a: &[f64], b: &[f64], mode: &Mode, checks: &mut u64) -> bool {
        self.rest_within((a, b), mode, &ObjectSet::new(), checks)
    }

    fn coarse_within(
        &self,
        (a, b): (&[f64], &[f64]),
        known: (bool, bool),
        mode: &Mode,
        allowed: &ObjectSet,
        checks: &mut u64,
    ) -> bool {
        let res = self.settings.resolution;
        within(self.space.check_segment_known((a, b), res, known, mode, checks), allowed)
    }

    fn rest_within(&self, (a, b): (&[f64], &[f64]), mode: &Mode, allowed: &ObjectSet, checks: &mut u64) -> bool {
        within(self.space.check_motion_rest(a, b, self.settings.resolution, mode, checks), allowed)
    }
}

/// The indices of the waypoints of a run of `n` kept when those between `i` and `k` are
/// dropped wherever `clear(i, k)` (never asked for neighbours): divide and conquer, the
/// whole run first, then each half; then one pass dropping single waypoints.
fn drop_waypoints(n: usize, mut clear: impl FnMut(usize, usize) -> bool) -> Vec<usize> {
    let mut keep = vec![false; n];
    if let (Some(f), Some(l)) = (keep.first_mut(), n.checked_sub(1)) {
        *f = true;
        keep[l] = true;
    }
    let mut todo = vec![(0, n.saturating_sub(1))];
    while let Some((i, k)) = todo.pop() {
        if k <= i + 1 || clear(i, k) {
            continue;
        }
        let m = (i + k) / 2;
        keep[m] = true;
        todo.push((m, k));
        todo.push((i, m));
    }
    let mut out: Vec<usize> = (0..n).filter(|&i| keep[i]).collect();
    // Halving keeps midpoints a better split would not need: drop each waypoint whose
    // neighbours see each other.
    let mut i = 1;
    while i + 1 < out.len() {
        if clear(out[i - 1], out[i + 1]) {
            out.remove(i);
        } else {
            i += 1;
        }
    }
    out
}

fn within(c: Check, allowed: &ObjectSet) -> bool {
    matches!(c, Check::Touches(l) if l.is_subset(allowed))
}
