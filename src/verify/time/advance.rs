//! How far the replay may skip ahead: conservative advancement over every pair the
//! checks look at, each pair remembering what it measured last.
//!
//! A pair's *slack* is its distance less what it must keep. Between two instants it
//! shrinks by at most how far the pair can move apart-wise (its *odometer*: the joints'
//! reaches times their peak speeds, integrated over time). So a slack measured earlier,
//! less the odometer since, is still a lower bound now, and only the pairs whose bound
//! could set the answer are measured again. The answer is the same as measuring every
//! pair afresh at every instant: the replay's instants do not change, only their cost.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};

use super::scene::{Cell, RobotAt, RobotGeo, Scratch, Side};
use crate::resolve::ObjectId;
use crate::world::{
    aabb_gap, distance_at_least, distance_at_least_from, in_closed_form, turned_boxes_gap, GjkStart, ObjectSet,
    StaticOwner, LOWER_BOUND_TOLERANCE,
};

/// Who holds what, with which fingers, and which object each may touch; how many objects
/// are in place. The pairs (and their order) are the same while this is.
type PairSet = (Vec<(Option<(ObjectId, usize)>, Option<ObjectId>)>, usize);

/// Shapes of one robot body, measured and queued together (see `Memory::units`).
struct Unit {
    body: usize,
    /// Indices among the robot's posed shapes.
    shapes: Vec<usize>,
}

/// One side of a pair: shapes of one robot body (robot, unit: see `Memory::units`) or a
/// carried part (robot, index), or a static shape.
#[derive(Clone, Copy)]
enum Thing {
    Unit(usize, usize),
    Held(usize, usize),
    Static(usize),
}

/// Whose joints move a pair's sides apart.
enum Movers {
    /// Every joint of the robot (against the scene).
    Robot(usize),
    /// The robot's joints marked (its flange, with what it carries, and a body).
    Apart(usize, Vec<bool>),
    /// The robot's joints, each rate scaled by a weight: one body against the scene, each
    /// joint weighted by the body's own reach over the reach its rate was taken with; two
    /// of its own bodies, each joint that moves one and not the other weighted so by that
    /// body's (0 for the others).
    Weighted(usize, Vec<f64>),
    /// Every joint of both robots.
    Robots(usize, usize),
}

impl Movers {
    fn robots(&self) -> [usize; 2] {
        match *self {
            Movers::Robot(r) | Movers::Apart(r, _) | Movers::Weighted(r, _) => [r, r],
            Movers::Robots(a, b) => [a, b],
        }
    }
}

/// Joint `j`'s rate weighed by how far it can move `body`'s own points over how far it
/// can move any (the reach its rate was taken with): the body's points then move no
/// faster than the weighed rates' sum. A joint whose rate was taken with no reach keeps
/// its rate as it is.
fn own_weight(g: &RobotGeo, reach: Option<&Vec<f64>>, body: usize, j: usize) -> f64 {
    match reach.and_then(|r| r.get(j)) {
        Some(&r) if r > 0.0 => g.body_reach[body][j] / r,
        _ => 1.0,
    }
}

/// One pair: its sides, the distance it must keep, and the index of its movers.
struct Pair {
    a: Thing,
    b: Thing,
    must: f64,
    movers: usize,
}

/// The pairs of the current [`PairSet`] and what each measured last.
#[derive(Default)]
pub(super) struct Memory {
    set: Option<PairSet>,
    pairs: Vec<Pair>,
    movers: Vec<Movers>,
    /// Per pair: slack (metres) and its movers' odometer at the measure.
    measured: Vec<Option<(f64, f64)>>,
    /// Per pair: the simplex its last GJK ended with (see `distance_at_least_from`).
    hints: Vec<GjkStart>,
    /// Per movers: whether any pair has them.
    populated: Vec<bool>,
    /// Per movers this instant: how fast they can close a pair in, and their odometer.
    speed: Vec<f64>,
    odometer: Vec<f64>,
    /// Per pair this instant: a lower bound on its free time.
    bound: Vec<f64>,
    /// Per robot: its posed shapes in units. A body of balls only (a spherized link) is
    /// one unit: its pairs are measured together, ball by ball, and queued once, not once
    /// per ball (measuring a ball is cheaper than queueing it). Any other shape is a unit
    /// of its own: measuring it is dear, and its own bound spares it more often.
    units: Vec<Vec<Unit>>,
    /// Per movers: their pairs' *expiries* (slack plus odometer at the measure: the
    /// odometer reading at which the bound reaches 0), least first. An entry is current
    /// while its stamp is its pair's; a measure stamps the pair anew and queues it again.
    queues: Vec<BinaryHeap<Reverse<Entry>>>,
    stamp: Vec<u32>,
    /// Entries taken off the queues this instant, to be put back.
    taken: Vec<(usize, Entry)>,
    /// The pairs changed since the last instant: the next one measures them all.
    fresh: bool,
    /// Take every pair's bound at every instant, not only the queues' fronts; every shape
    /// on its own, not a body of balls as one unit; and GJK without the turned boxes'
    /// gap first, from a cold start: what those shortcuts are tested against.
    pub every_pair: bool,
    /// Per robot, per joint: the reach its rates are taken with (`rates[r][j]` is this
    /// times the joint's speed), so that a pair of its bodies can weigh them by their own.
    pub reach: Vec<Vec<f64>>,
}

/// A queued pair: its expiry (ordered as `f64::total_cmp` orders), index and stamp.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    expiry: OrdF64,
    k: u32,
    stamp: u32,
}

#[derive(Clone, Copy, PartialEq)]
struct OrdF64(f64);

impl Eq for OrdF64 {}

impl PartialOrd for OrdF64 {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for OrdF64 {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// How far an expiry computed as `slack + odometer` may stray from the bound's own
/// arithmetic (`slack - (now - odometer)`): rounding of metres, far below this. Pairs
/// within it of a threshold are taken and decided by the bound itself.
const EXPIRY_SLOP: f64 = 1e-9;

impl Memory {
    /// Pair `k` measured: stamp it and queue its new expiry.
    fn requeue(&mut self, k: usize) {
        self.stamp[k] = self.stamp[k].wrapping_add(1);
        // A pair not measured yet (its movers stood still so far) is taken as soon as they
        // move, to take its boxes' gap as the full pass does. A NaN bound is never below
        // anything (the full pass never measures it): last.
        let expiry = match self.measured[k] {
            None => f64::NEG_INFINITY,
            Some((slack, at)) if (slack + at).is_nan() => f64::INFINITY,
            Some((slack, at)) => slack + at,
        };
        let entry = Entry { expiry: OrdF64(expiry), k: k as u32, stamp: self.stamp[k] };
        self.queues[self.pairs[k].movers].push(Reverse(entry));
    }

    /// Every pair queued afresh from what it measured (stale entries dropped).
    fn rebuild_queues(&mut self) {
        self.queues.clear();
        self.queues.resize_with(self.movers.len(), BinaryHeap::new);
        self.stamp.clear();
        self.stamp.resize(self.pairs.len(), 0);
        for k in 0..self.pairs.len() {
            self.requeue(k);
        }
    }

    /// What was taken and not measured goes back: as it was, or, a pair first bounded
    /// this instant, with its boxes' gap.
    fn put_back(&mut self) {
        let taken = std::mem::take(&mut self.taken);
        for &(g, e) in &taken {
            let k = e.k as usize;
            if self.stamp[k] != e.stamp {
                continue;
            }
            if e.expiry.0 == f64::NEG_INFINITY && self.measured[k].is_some() {
                self.requeue(k);
            } else {
                self.queues[g].push(Reverse(e));
            }
        }
        self.taken = taken;
    }

    /// Takes off `g`'s queue, into `taken`, every current entry whose expiry is below
    /// `limit` (odometer reading), dropping stale ones on the way.
    fn take_below(&mut self, g: usize, limit: f64) {
        while let Some(&Reverse(e)) = self.queues[g].peek() {
            if self.stamp[e.k as usize] != e.stamp {
                self.queues[g].pop();
                continue;
            }
            if e.expiry.0.partial_cmp(&limit) != Some(std::cmp::Ordering::Less) {
                return;
            }
            self.queues[g].pop();
            self.taken.push((g, e));
        }
    }
}

impl Cell<'_> {
    /// How long from the instant last checked (posed in `s`) nothing can come closer than
    /// the checks allow. `rates[r][j]`: how fast joint `j` of robot `r` can move any point
    /// it moves (its reach times its peak speed on the stretch), so that a robot's points
    /// move at most the sum of its rates, one body's at most the sum of each rate weighed by
    /// the body's own reach, and two of its own bodies apart at most the sum over the joints
    /// that move one and not the other; `odometers[r][j]`: the integral of
    /// that rate from the start. Every pair the checks look at is at least its boxes' gap
    /// apart; that gap, less the clearance the pair must keep, shrinks no faster than the
    /// pair moves apart. 0 when a pair is already too close; infinite when nothing moves.
    ///
    /// Also whether the bounds prove the instant itself clear: every pair whose movers
    /// move has a lower bound above what it must keep (a free time above 0 says so), and
    /// every pair whose movers stand still belongs to robots `still` (which the check
    /// skips: see [`Cell::check`]). A pair whose movers stand still is never bounded, so
    /// an instant with one of a robot not `still` is left to the check.
    #[allow(clippy::too_many_arguments)]
    pub fn free_time(
        &self,
        at: &[RobotAt],
        present: &ObjectSet,
        still: &[bool],
        rates: &[Vec<f64>],
        odometers: &[Vec<f64>],
        s: &Scratch,
        memory: &mut Memory,
    ) -> (f64, bool) {
        let set: PairSet =
            (at.iter().map(|ra| (ra.held.map(|h| (h.object, h.posture)), ra.exempt)).collect(), present.len());
        if memory.set.as_ref() != Some(&set) {
            memory.set = Some(set);
            self.list_pairs(at, present, s, memory);
        }
        let total = |v: &[Vec<f64>], r: usize| v.get(r).map_or(0.0, |v| v.iter().sum::<f64>());
        let marked = |v: &[Vec<f64>], r: usize, mask: &[bool]| {
            let v = v.get(r).map_or(&[][..], Vec::as_slice);
            mask.iter().zip(v).filter(|(m, _)| **m).map(|(_, v)| v).sum::<f64>()
        };
        memory.speed.clear();
        memory.odometer.clear();
        for m in &memory.movers {
            let of = |v: &[Vec<f64>]| match m {
                Movers::Robot(r) => total(v, *r),
                Movers::Apart(r, mask) => marked(v, *r, mask),
                Movers::Weighted(r, w) => v.get(*r).map_or(0.0, |v| v.iter().zip(w).map(|(v, w)| v * w).sum::<f64>()),
                Movers::Robots(a, b) => total(v, *a) + total(v, *b),
            };
            memory.speed.push(of(rates));
            memory.odometer.push(of(odometers));
        }
        let standing_bounded = memory.movers.iter().enumerate().all(|(g, m)| {
            memory.speed[g] > 0.0 || !memory.populated[g] || m.robots().iter().all(|&r| still.get(r) == Some(&true))
        });
        let free = if memory.fresh || memory.every_pair {
            let free = self.free_time_all(s, memory);
            if memory.fresh && !memory.every_pair {
                memory.rebuild_queues();
            }
            memory.fresh = false;
            free
        } else {
            self.free_time_queued(s, memory)
        };
        (free, standing_bounded && free > 0.0)
    }

    /// The shapes of one side of a pair.
    fn parts<'s>(
        &'s self,
        s: &'s Scratch,
        units: &'s [Vec<Unit>],
        t: Thing,
    ) -> impl Iterator<Item = Side<'s>> + Clone + 's {
        let (r, many): (usize, &[usize]) = match t {
            Thing::Unit(r, u) => (r, &units[r][u].shapes),
            _ => (0, &[]),
        };
        let one = match t {
            Thing::Unit(..) => None,
            Thing::Held(r, i) => Some(Side::held(&s.held[r][i])),
            Thing::Static(e) => Some(Side::fixed(&self.statics[e])),
        };
        many.iter().map(move |&i| Side::of(&s.posed[r][i])).chain(one)
    }

    /// The box around one side of a pair.
    fn aabb(&self, s: &Scratch, units: &[Vec<Unit>], t: Thing) -> Aabb {
        let mut parts = self.parts(s, units, t);
        let first = parts.next().map_or_else(Aabb::new_invalid, |p| *p.aabb);
        parts.fold(first, |b, p| b.merged(p.aabb))
    }

    /// Pair `k`'s bound on its free time: its last slack less the odometer since, or its
    /// boxes' gap when it has none (both are no more than its free time). The gap, once
    /// taken, is remembered like a measured slack: most pairs are far apart, and walking
    /// their boxes again at every instant was most of this loop's cost. A remembered gap
    /// grows stale (a looser bound), so [`Self::measure`] takes the gap afresh before it
    /// measures, and remembers it when it proves the pair need not be measured.
    fn bound(&self, s: &Scratch, memory: &mut Memory, k: usize) -> f64 {
        let p = &memory.pairs[k];
        let speed = memory.speed[p.movers];
        if speed <= 0.0 {
            f64::INFINITY
        } else if let Some((then, odometer)) = memory.measured[k] {
            (then - (memory.odometer[p.movers] - odometer)) / speed
        } else {
            let gap = aabb_gap(&self.aabb(s, &memory.units, p.a), &self.aabb(s, &memory.units, p.b));
            let slack = gap - p.must;
            memory.measured[k] = Some((slack, memory.odometer[p.movers]));
            slack / speed
        }
    }

    /// Measures pair `k` (unless its boxes' gap now proves it cannot lower `free`) and
    /// lowers `free` to its free time. A side of many shapes is measured shape by shape,
    /// each shape pair skipped the same way when its own boxes' gap (or, before GJK, its
    /// turned boxes' gap) proves it cannot lower `free`; the pair keeps the least slack
    /// (or gap) of its shape pairs.
    fn measure(&self, s: &Scratch, memory: &mut Memory, k: usize, free: &mut f64) {
        let p = &memory.pairs[k];
        let (a, b) = (self.parts(s, &memory.units, p.a), self.parts(s, &memory.units, p.b));
        let (speed, now, must) = (memory.speed[p.movers], memory.odometer[p.movers], p.must);
        let gap = aabb_gap(&self.aabb(s, &memory.units, p.a), &self.aabb(s, &memory.units, p.b));
        if (gap - must) / speed >= *free {
            // The gap is no more than the pair's slack now; keep the tighter bound.
            let stale = memory.measured[k].map_or(f64::NEG_INFINITY, |(then, at)| then - (now - at));
            memory.measured[k] = Some(((gap - must).max(stale), now));
            return;
        }
        let mut slack = f64::INFINITY;
        for x in a {
            for y in b.clone() {
                let gap = aabb_gap(x.aabb, y.aabb);
                if (gap - must) / speed >= *free {
                    slack = slack.min(gap - must);
                    continue;
                }
                // GJK is dear enough to try the turned boxes' gap first (not in the mode
                // the shortcuts are tested against).
                if !memory.every_pair && !in_closed_form(x.shape, y.shape) {
                    let turned = turned_boxes_gap(x.pose, x.shape, y.pose, y.shape).max(gap);
                    if (turned - must) / speed >= *free {
                        slack = slack.min(turned - must);
                        continue;
                    }
                }
                // A lower bound on the distance (GJK's dual bound, within 10 µm of it),
                // started from the pair's last simplex (not in the reference mode). A pair
                // parry cannot measure keeps its gap.
                let d = match memory.every_pair {
                    true => distance_at_least(x.pose, x.shape, y.pose, y.shape, LOWER_BOUND_TOLERANCE),
                    false => distance_at_least_from(
                        x.pose,
                        x.shape,
                        y.pose,
                        y.shape,
                        LOWER_BOUND_TOLERANCE,
                        &mut memory.hints[k],
                    ),
                };
                let d = d.map_or(gap, |d| d.max(gap));
                slack = slack.min(d - must);
                *free = free.min(((d - must) / speed).max(0.0));
            }
        }
        memory.measured[k] = Some((slack, now));
    }

    /// Every pair's bound, the least measured first, then every pair whose bound is below
    /// the least free time found, in the pairs' order.
    fn free_time_all(&self, s: &Scratch, memory: &mut Memory) -> f64 {
        memory.bound.clear();
        let mut least = (f64::INFINITY, usize::MAX);
        for k in 0..memory.pairs.len() {
            let bound = self.bound(s, memory, k);
            if bound < least.0 {
                least = (bound, k);
            }
            memory.bound.push(bound);
        }
        let mut free = f64::INFINITY;
        if least.1 != usize::MAX {
            self.measure(s, memory, least.1, &mut free);
        }
        for k in 0..memory.pairs.len() {
            if free == 0.0 {
                break;
            }
            if memory.bound[k] < free && k != least.1 {
                self.measure(s, memory, k, &mut free);
            }
        }
        free
    }

    /// [`Self::free_time_all`] by the queues: only the pairs whose bound can be the least
    /// or below the free time are taken off them (give or take [`EXPIRY_SLOP`]), and each
    /// is decided by its own bound, exactly as the full pass decides it: the same pairs
    /// are measured, in the same order, and the same free time comes out.
    fn free_time_queued(&self, s: &Scratch, memory: &mut Memory) -> f64 {
        memory.taken.clear();
        let moving: Vec<usize> = (0..memory.movers.len()).filter(|&g| memory.speed[g] > 0.0).collect();
        // Odometer reading below which a pair of movers `g` may have a bound under `b`.
        let limit =
            |m: &Memory, g: usize, b: f64| (b + b.abs() * 1e-9 + 1e-12) * m.speed[g] + m.odometer[g] + EXPIRY_SLOP;
        // The pairs not measured yet first: their bounds (boxes' gaps) are taken now.
        for &g in &moving {
            memory.take_below(g, f64::MIN);
        }
        let mut front = f64::INFINITY;
        for i in 0..memory.taken.len() {
            let k = memory.taken[i].1.k as usize;
            front = front.min(self.bound(s, memory, k));
        }
        for &g in &moving {
            if let Some(Reverse(e)) = memory.queues[g].peek() {
                front = front.min((e.expiry.0 - memory.odometer[g]) / memory.speed[g]);
            }
        }
        if front == f64::INFINITY || front.is_nan() {
            memory.put_back();
            return f64::INFINITY;
        }
        for &g in &moving {
            let lim = limit(memory, g, front);
            memory.take_below(g, lim);
        }
        let mut least = (f64::INFINITY, usize::MAX);
        for i in 0..memory.taken.len() {
            let k = memory.taken[i].1.k as usize;
            let b = self.bound(s, memory, k);
            if b < least.0 || (b == least.0 && b < f64::INFINITY && k < least.1) {
                least = (b, k);
            }
        }
        let mut free = f64::INFINITY;
        if least.1 != usize::MAX {
            self.measure(s, memory, least.1, &mut free);
            memory.requeue(least.1);
            for &g in &moving {
                let lim = limit(memory, g, free);
                memory.take_below(g, lim);
            }
        }
        let mut candidates: Vec<usize> =
            memory.taken.iter().map(|(_, e)| e.k as usize).filter(|&k| k != least.1).collect();
        candidates.sort_unstable();
        for k in candidates {
            if free == 0.0 {
                break;
            }
            if self.bound(s, memory, k) < free {
                self.measure(s, memory, k, &mut free);
                memory.requeue(k);
            }
        }
        memory.put_back();
        let queued: usize = memory.queues.iter().map(BinaryHeap::len).sum();
        if queued > 4 * memory.pairs.len() + 64 {
            memory.rebuild_queues();
        }
        free
    }

    /// Every pair the checks look at, in an order fixed by who holds what and which
    /// objects are in place; nothing measured yet.
    fn list_pairs(&self, at: &[RobotAt], present: &ObjectSet, s: &Scratch, memory: &mut Memory) {
        let c = self.clearance;
        let whole_bodies = !memory.every_pair;
        memory.units = s
            .posed
            .iter()
            .zip(&self.robots)
            .map(|(posed, g)| {
                let mut balls = vec![whole_bodies; g.bodies.len()];
                for ps in posed.iter().filter(|ps| ps.shape.0.as_ball().is_none()) {
                    balls[ps.body] = false;
                }
                let mut units: Vec<Unit> = Vec::new();
                let mut unit_of: Vec<Option<usize>> = vec![None; g.bodies.len()];
                for (i, ps) in posed.iter().enumerate() {
                    match unit_of[ps.body] {
                        Some(u) if balls[ps.body] => units[u].shapes.push(i),
                        _ => {
                            unit_of[ps.body] = Some(units.len());
                            units.push(Unit { body: ps.body, shapes: vec![i] });
                        }
                    }
                }
                units
            })
            .collect();
        let (pairs, movers, memory_reach) = (&mut memory.pairs, &mut memory.movers, &memory.reach);
        let units = &memory.units;
        pairs.clear();
        movers.clear();
        let mut group = |m: Movers| {
            movers.push(m);
            movers.len() - 1
        };
        for (ri, ra) in at.iter().enumerate() {
            let g = &self.robots[ri];
            let held = &s.held[ri];
            // Each unit, with its body.
            let bodies = |ri: usize| units[ri].iter().enumerate().map(|(u, unit)| (u, unit.body));
            let checked = |owner: StaticOwner, carried: bool| match owner {
                StaticOwner::Fixed(_) => true,
                StaticOwner::Object(o) => {
                    present.contains(o) && ra.held.is_none_or(|h| h.object != o) && (carried || Some(o) != ra.exempt)
                }
            };
            let whole = group(Movers::Robot(ri));
            let weigh = |body: usize| -> Vec<f64> {
                (0..g.body_joints[body].len()).map(|j| own_weight(g, memory_reach.get(ri), body, j)).collect()
            };
            // Against the scene a body closes in no faster than its own points move: the
            // joints below it, each by the body's own reach. A link near the base moves
            // slowly, whatever the wrist does.
            let mut own: Vec<Option<usize>> = vec![None; g.bodies.len()];
            for (e, _) in self.statics.iter().enumerate().filter(|(_, st)| checked(st.owner, false)) {
                for (u, b) in bodies(ri).filter(|&(_, b)| g.bodies[b].moving) {
                    let m = *own[b].get_or_insert_with(|| group(Movers::Weighted(ri, weigh(b))));
                    pairs.push(Pair { a: Thing::Unit(ri, u), b: Thing::Static(e), must: c, movers: m });
                }
            }
            for (e, _) in self.statics.iter().enumerate().filter(|(_, st)| checked(st.owner, true)) {
                for i in 0..held.len() {
                    pairs.push(Pair { a: Thing::Held(ri, i), b: Thing::Static(e), must: 0.0, movers: whole });
                }
            }
            let apart = |x: &[bool], y: &[bool]| x.iter().zip(y).map(|(x, y)| x != y).collect::<Vec<bool>>();
            for &(a, b) in &g.self_pairs {
                let weights = (0..g.body_joints[a].len())
                    .map(|j| {
                        let moved = match (g.body_joints[a][j], g.body_joints[b][j]) {
                            (true, false) => a,
                            (false, true) => b,
                            _ => return 0.0,
                        };
                        own_weight(g, memory_reach.get(ri), moved, j)
                    })
                    .collect();
                let m = group(Movers::Weighted(ri, weights));
                for (x, _) in bodies(ri).filter(|&(_, x)| x == a) {
                    for (y, _) in bodies(ri).filter(|&(_, y)| y == b) {
                        pairs.push(Pair { a: Thing::Unit(ri, x), b: Thing::Unit(ri, y), must: 0.0, movers: m });
                    }
                }
            }
            for i in 0..held.len() {
                for (u, b) in bodies(ri).filter(|&(_, b)| !g.bodies[b].holds) {
                    let m = group(Movers::Apart(ri, apart(&g.flange_joints, &g.body_joints[b])));
                    pairs.push(Pair { a: Thing::Held(ri, i), b: Thing::Unit(ri, u), must: 0.0, movers: m });
                }
            }
            for rj in ri + 1..at.len() {
                let gj = &self.robots[rj];
                let both = group(Movers::Robots(ri, rj));
                let mine = bodies(ri).map(|(u, b)| (Thing::Unit(ri, u), g.bodies[b].moving));
                for (x, xm) in mine.chain((0..held.len()).map(|i| (Thing::Held(ri, i), true))) {
                    let theirs = bodies(rj).map(|(u, b)| (Thing::Unit(rj, u), gj.bodies[b].moving));
                    for (y, ym) in theirs.chain((0..s.held[rj].len()).map(|k| (Thing::Held(rj, k), true))) {
                        if xm || ym {
                            pairs.push(Pair { a: x, b: y, must: c, movers: both });
                        }
                    }
                }
            }
        }
        memory.populated.clear();
        memory.populated.resize(memory.movers.len(), false);
        for p in &memory.pairs {
            memory.populated[p.movers] = true;
        }
        memory.measured.clear();
        memory.measured.resize(memory.pairs.len(), None);
        memory.hints.clear();
        memory.hints.resize(memory.pairs.len(), GjkStart::default());
        memory.fresh = true;
    }
}
