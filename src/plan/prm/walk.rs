//! An edge's samples walked level by level, alone or beside the same edge's walk with
//! the hand empty (see `lazy`'s search).

use crate::plan::Map;

use super::super::layers::{Job, LabelKey, ModeKey, Node};
use super::super::space::{Mode, Space};
use crate::world::{Check, ObjectSet};

/// An edge's samples being checked level by level: those inside coarse to fine (level
/// `k` halving the gaps the levels before it left, as `check_segment` goes), then its
/// two ends. A segment blocked anywhere is found after about as many checks as its own
/// check would take, whichever edge of a path it is, and every sample is checked once.
pub(super) struct Walk {
    pub(super) a: Vec<f64>,
    pub(super) b: Vec<f64>,
    /// The segment's steps: samples `0..=n` (see `world::segment_sample`).
    pub(super) n: usize,
    /// The next level's stride; 0 for the ends, `usize::MAX` once they are checked.
    pub(super) stride: usize,
    /// The labels of the samples checked.
    pub(super) label: ObjectSet,
}

/// A walk, and the same edge's walk with the hand empty where this one carries an
/// object: stepped together, on one placing of the robot per sample (see
/// `Space::check_samples_twin`).
pub(super) struct Walker {
    pub(super) i: usize,
    pub(super) walk: Walk,
    pub(super) twin: Option<(usize, Walk)>,
}

/// The walks of `jobs`, each carrying edge's paired with the same edge's empty-hand walk
/// where one is at the same level. The labels are each walk's own: only checks are saved.
pub(super) fn twins(jobs: &[Job], single: Vec<(usize, Walk)>) -> Vec<Walker> {
    let items: Vec<&Job> = single.iter().map(|(i, _)| &jobs[*i]).collect();
    let units = twin_units(&items, |c, e| single[c].1.stride == single[e].1.stride && single[c].1.n == single[e].1.n);
    let mut slots: Vec<Option<(usize, Walk)>> = single.into_iter().map(Some).collect();
    let mut out = Vec::with_capacity(units.len());
    for (k, twin) in units {
        let Some((i, walk)) = slots[k].take() else { continue };
        let twin = twin.and_then(|e| slots[e].take());
        out.push(Walker { i, walk, twin });
    }
    out
}

/// `items` as units to check: each position in `items` with the position of the same
/// edge's empty-hand item paired with it, the paired ones not on their own. Only carrying
/// edges are paired, each empty-hand item at most once, in the carrying mode's empty hand
/// (the object back in place) and where `fits(carrying position, empty-hand position)`.
pub(super) fn twin_units(items: &[&Job], fits: impl Fn(usize, usize) -> bool) -> Vec<(usize, Option<usize>)> {
    let mut empties: Map<(Node, Node), usize> = Map::default();
    for (k, j) in items.iter().enumerate() {
        if let LabelKey::Edge(ModeKey::Empty, a, b) = j.item {
            empties.insert((a, b), k);
        }
    }
    let mut partner: Vec<Option<usize>> = vec![None; items.len()];
    let mut paired = vec![false; items.len()];
    for (k, j) in items.iter().enumerate() {
        let LabelKey::Edge(ModeKey::Carry(..), a, b) = j.item else { continue };
        let Some(e) = empties.remove(&(a, b)) else { continue };
        if fits(k, e) && items[e].mode == j.mode.empty_of() {
            partner[k] = Some(e);
            paired[e] = true;
        } else {
            empties.insert((a, b), e);
        }
    }
    (0..items.len()).filter(|&k| !paired[k]).map(|k| (k, partner[k])).collect()
}

impl Walk {
    pub(super) fn new(a: &[f64], b: &[f64], n: usize) -> Walk {
        let top = n.checked_next_power_of_two().unwrap_or(usize::MAX / 2 + 1);
        Walk { a: a.to_vec(), b: b.to_vec(), n, stride: top / 2, label: ObjectSet::new() }
    }
    pub(super) fn done(&self) -> bool {
        self.stride == usize::MAX
    }
    /// Checks the next level's samples in turn (see `Space::check_samples`); true at
    /// the first blocked one.
    pub(super) fn step<S: Space>(&mut self, space: &S, mode: &Mode, checks: &mut u64) -> bool {
        let c = space.check_samples((&self.a, &self.b), self.n, &mut self.level(), mode, checks);
        self.advance(c)
    }
    /// [`Walk::step`] of this walk, carrying an object in `mode`, and of `empty`, the
    /// same edge's walk at the same level with the hand empty: (blocked, empty blocked).
    pub(super) fn step_twin<S: Space>(
        &mut self,
        empty: &mut Walk,
        space: &S,
        mode: &Mode,
        checks: &mut u64,
    ) -> (bool, bool) {
        let level: Vec<usize> = self.level().collect();
        let (e, c) = space.check_samples_twin((&self.a, &self.b), self.n, &level, mode, checks);
        (self.advance(c), empty.advance(e))
    }
    /// The samples of the next level.
    fn level(&self) -> impl Iterator<Item = usize> {
        let (n, s) = (self.n, self.stride);
        let (from, to, by) = if s == 0 { (0, n, n.max(1)) } else { (s, n - 1, 2 * s) };
        (from..=to).step_by(by)
    }
    /// Joins a level's check; true when it is blocked.
    fn advance(&mut self, c: Check) -> bool {
        match c {
            Check::Touches(l) => self.label.union_with(&l),
            Check::Blocked(_) => return true,
        }
        self.stride = if self.stride == 0 { usize::MAX } else { self.stride / 2 };
        false
    }
}
