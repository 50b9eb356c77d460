//! Shortening a found path: waypoints are dropped where the straight move that
//! replaces them passes the certifying check touching only objects the path already
//! removes. The removal set cannot grow, so the answer stays as minimal as it was; the
//! motion gets shorter and loses the zigzags of goal trees and roadmap detours.

use super::super::space::{Mode, Space};
use super::RobotPlanner;
use crate::world::{Check, ObjectSet};

impl<S: Space> RobotPlanner<S> {
    /// `run` with waypoints dropped, its ends kept: a straight move from `run[i]` to
    /// `run[k]` replaces the waypoints between when it is clear (divide and conquer:
    /// the whole run first, then each half; then one pass dropping single waypoints).
    pub(super) fn shortcut(
        &self,
        run: &[Vec<f64>],
        mode: &Mode,
        allowed: &ObjectSet,
        checks: &mut u64,
    ) -> Vec<Vec<f64>> {
        let mut keep = vec![false; run.len()];
        if let (Some(f), Some(l)) = (keep.first_mut(), run.len().checked_sub(1)) {
            *f = true;
            keep[l] = true;
        }
        let mut todo = vec![(0, run.len().saturating_sub(1))];
        while let Some((i, k)) = todo.pop() {
            if k <= i + 1 || self.clear(&run[i], &run[k], mode, allowed, checks) {
                continue;
            }
            let m = (i + k) / 2;
            keep[m] = true;
            todo.push((m, k));
            todo.push((i, m));
        }
        let mut out: Vec<Vec<f64>> = run.iter().zip(keep).filter(|(_, k)| *k).map(|(q, _)| q.clone()).collect();
        // Halving keeps midpoints a better split would not need: drop each waypoint
        // whose neighbours see each other.
        let mut i = 1;
        while i + 1 < out.len() {
            if self.clear(&out[i - 1], &out[i + 1], mode, allowed, checks) {
                out.remove(i);
            } else {
                i += 1;
            }
        }
        out
    }

    /// Whether the certifying check of a -> b touches only `allowed`: its coarse samples
    /// first (most moves that fail are blocked, and a few samples spread along the
    /// segment find it), then the rest.
    fn clear(&self, a: &[f64], b: &[f64], mode: &Mode, allowed: &ObjectSet, checks: &mut u64) -> bool {
        self.coarse_within((a, b), false, mode, allowed, checks) && self.rest_within((a, b), mode, allowed, checks)
    }

    /// The coarse samples of the certifying check of a step leaving `a`, itself known to
    /// touch nothing in `mode` (a free-space tree's node), touch nothing; `a` is not
    /// checked again. The rest is [`Self::rest_clear`]'s.
    pub(super) fn coarse_clear_leaving(&self, a: &[f64], b: &[f64], mode: &Mode, checks: &mut u64) -> bool {
        self.coarse_within((a, b), true, mode, &ObjectSet::new(), checks)
    }

    /// The samples of the certifying check of a -> b that the coarse one does not take
    /// touch nothing in `mode`.
    pub(super) fn rest_clear(&self, a: &[f64], b: &[f64], mode: &Mode, checks: &mut u64) -> bool {
        self.rest_within((a, b), mode, &ObjectSet::new(), checks)
    }

    fn coarse_within(
        &self,
        (a, b): (&[f64], &[f64]),
        a_known: bool,
        mode: &Mode,
        allowed: &ObjectSet,
        checks: &mut u64,
    ) -> bool {
        let res = self.settings.resolution;
        within(self.space.check_segment_known((a, b), res, (a_known, false), mode, checks), allowed)
    }

    fn rest_within(&self, (a, b): (&[f64], &[f64]), mode: &Mode, allowed: &ObjectSet, checks: &mut u64) -> bool {
        within(self.space.check_motion_rest(a, b, self.settings.resolution, mode, checks), allowed)
    }
}

fn within(c: Check, allowed: &ObjectSet) -> bool {
    matches!(c, Check::Touches(l) if l.is_subset(allowed))
}
