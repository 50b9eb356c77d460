//! The configuration space one robot plans in, as the roadmap sees it.
//!
//! The roadmap and its searches only need joint limits and labelled checks, so they
//! are written against [`Space`]; the planner implements it for a robot of a
//! [`World`](crate::world::World) and tests implement it on exact 2-D geometry.

use crate::resolve::ObjectId;
use crate::world::{Blocker, Check, GraspConfig, Held, ObjectSet};

/// What the scene looks like for one check: objects taken out of it, and what the hand carries.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mode {
    pub absent: ObjectSet,
    pub held: Option<Held>,
}

impl Mode {
    /// The same scene with the hand empty: the object carried back in its place.
    pub fn empty_of(&self) -> Mode {
        let mut absent = self.absent.clone();
        if let Some(h) = &self.held {
            absent.remove(h.object);
        }
        Mode { absent, held: None }
    }
}

/// One robot's configuration space, with the other robots at home.
pub trait Space: Sync {
    fn dof(&self) -> usize;
    fn limits(&self) -> &[(f64, f64)];
    /// Labelled check of one configuration; adds the configurations checked to `checks`.
    fn check(&self, q: &[f64], mode: &Mode, checks: &mut u64) -> Check;
    /// Whether `check` would say `Touches` with no label; a space may say so sooner.
    fn touches_nothing(&self, q: &[f64], mode: &Mode, checks: &mut u64) -> bool {
        matches!(self.check(q, mode, checks), Check::Touches(l) if l.is_empty())
    }
    /// Labelled check of the straight joint-space segment `a`-`b` (endpoints included),
    /// at steps no longer than `step`.
    fn check_segment(&self, a: &[f64], b: &[f64], step: f64, mode: &Mode, checks: &mut u64) -> Check;
    /// `Some(n)` where `check_segment(a, b, step)` is the labelled check of each of
    /// `world::segment_sample(a, b, i, n)`, `i` in `0..=n` (its label the union of
    /// theirs, blocked when one is), so that they may be checked in any order.
    fn segment_steps(&self, _a: &[f64], _b: &[f64], _step: f64) -> Option<usize> {
        None
    }
    /// The labelled checks of samples `indices` of `ends` cut into `n` steps (see
    /// `segment_steps`), in turn, up to the first blocked one: their labels' union or it.
    fn check_samples(
        &self,
        (a, b): (&[f64], &[f64]),
        n: usize,
        indices: &mut dyn Iterator<Item = usize>,
        mode: &Mode,
        checks: &mut u64,
    ) -> Check {
        let mut q = a.to_vec();
        let mut out = ObjectSet::new();
        for i in indices {
            crate::world::segment_sample(a, b, i, n, &mut q);
            match self.check(&q, mode, checks) {
                Check::Touches(l) => out.union_with(&l),
                blocked => return blocked,
            }
        }
        Check::Touches(out)
    }
    /// `check_samples` of the same samples in [`Mode::empty_of`]`(mode)` and in `mode`,
    /// each up to its own first block: (the empty hand's, the carrying one's). A space
    /// may check them together where that costs less (see `World::check_samples_twin`).
    fn check_samples_twin(
        &self,
        ends: (&[f64], &[f64]),
        n: usize,
        indices: &[usize],
        mode: &Mode,
        checks: &mut u64,
    ) -> (Check, Check) {
        let empty = self.check_samples(ends, n, &mut indices.iter().copied(), &mode.empty_of(), checks);
        (empty, self.check_samples(ends, n, &mut indices.iter().copied(), mode, checks))
    }
    /// `check_segment` with the ends flagged in `known` (`a`, `b`) left unchecked where a
    /// space can skip them: the caller has their checks in `mode`, neither blocked, and
    /// joins their labels to this one's for `check_segment`'s answer.
    fn check_segment_known(
        &self,
        ends: (&[f64], &[f64]),
        step: f64,
        _known: (bool, bool),
        mode: &Mode,
        checks: &mut u64,
    ) -> Check {
        self.check_segment(ends.0, ends.1, step, mode, checks)
    }
    /// What `mode.held` adds to `check_segment` on the same samples, the robot's own
    /// bodies unchecked: used when the empty-hand label of the segment is known.
    fn check_segment_held(&self, a: &[f64], b: &[f64], step: f64, mode: &Mode, checks: &mut u64) -> Check {
        self.check_segment(a, b, step, mode, checks)
    }
    /// The certifying check of a segment: the samples of `check_segment` at `resolution`
    /// and more between them (for a world robot, exactly those `verify` takes).
    fn check_motion(&self, a: &[f64], b: &[f64], resolution: f64, mode: &Mode, checks: &mut u64) -> Check {
        self.check_segment(a, b, resolution / 4.0, mode, checks)
    }
    /// What `check_motion` adds to a clear `check_segment` at `resolution` of the same
    /// segment and mode: the certifying samples the coarse check did not take (all of
    /// them where a space cannot tell which those are). The certifying label is the
    /// coarse label joined with this one.
    fn check_motion_rest(&self, a: &[f64], b: &[f64], resolution: f64, mode: &Mode, checks: &mut u64) -> Check {
        self.check_motion(a, b, resolution, mode, checks)
    }
    /// `check_motion_rest` of the same segment in [`Mode::empty_of`]`(mode)` and in
    /// `mode`: (the empty hand's, the carrying one's), as `check_samples_twin`.
    fn check_motion_rest_twin(
        &self,
        a: &[f64],
        b: &[f64],
        resolution: f64,
        mode: &Mode,
        checks: &mut u64,
    ) -> (Check, Check) {
        let empty = self.check_motion_rest(a, b, resolution, &mode.empty_of(), checks);
        (empty, self.check_motion_rest(a, b, resolution, mode, checks))
    }
    fn home(&self) -> &[f64];
    /// Where a carried object is released (often `home`).
    fn drop_config(&self) -> &[f64];
    /// Reachable grasps of `o` (the paper's `selectGrasps`), in grasp order.
    fn grasps(&self, o: ObjectId) -> Vec<GraspConfig>;
    /// The object `o` as carried after grasping it at `q_grasp`.
    fn held(&self, o: ObjectId, grasp: usize, q_grasp: &[f64]) -> Held;
    /// What the fingers touch closing on `held` at `q_grasp` and opening again at the
    /// drop, besides the object: the objects in place they touch (to be removed first, as
    /// the approach's), or `Err` with the fixed body or robot they hit.
    fn fingers_clear(&self, _held: &Held, _q_grasp: &[f64], _checks: &mut u64) -> Result<ObjectSet, Blocker> {
        Ok(ObjectSet::new())
    }
    /// Configurations leading the hand out of where `q` puts it, from `q` (left out) on,
    /// unchecked; none where the space has no such notion (see `World::escape_line`).
    fn escape_line(&self, _q: &[f64]) -> Vec<Vec<f64>> {
        Vec::new()
    }
    /// Whether the scene holds objects, which can label a path; without any a path
    /// touches nothing or is blocked, and the free-space trees search first (see `run`).
    fn has_objects(&self) -> bool {
        true
    }
    /// Why `grasps(o)` is empty, in words naming the cause, where the space can tell.
    fn why_no_grasp(&self, _o: ObjectId) -> Option<String> {
        None
    }
}
