//! How far the replay may skip ahead: conservative advancement over every pair the
//! checks look at, each pair remembering what it measured last.
//!
//! A pair's *slack* is its distance less what it must keep. Between two instants it
//! shrinks by at most how far the pair can move apart-wise (its *odometer*: the joints'
//! reaches times their peak speeds, integrated over time). So a slack measured earlier,
//! less the odometer since, is still a lower bound now, and only the pairs whose bound
//! could set the answer are measured again. The answer is the same as measuring every
//! pair afresh at every instant: the replay's instants do not change, only their cost.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};

mod expiry;
mod pairs;

use expiry::Expiries;

use super::scene::{depth_slack, Cell, RobotAt, Scratch, Side};
use crate::resolve::ObjectId;
use crate::world::{
    aabb_gap, distance_at_least_from, in_closed_form, turned_boxes_gap, BodiesFarthest, GjkStart, ObjectSet,
    ReachScratch, LOWER_BOUND_TOLERANCE,
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
    /// body's (0 for the others). `moved[j]`: the body joint `j` is weighted by, if any.
    /// The body's reach is taken where it stands at each part of a stretch (see
    /// [`Memory::start_stretch`]), so the weights change with the parts.
    Weighted { robot: usize, moved: Vec<Option<usize>>, weights: Vec<f64> },
    /// Every joint of both robots.
    Robots(usize, usize),
}

impl Movers {
    fn robots(&self) -> [usize; 2] {
        match *self {
            Movers::Robot(r) | Movers::Apart(r, _) | Movers::Weighted { robot: r, .. } => [r, r],
            Movers::Robots(a, b) => [a, b],
        }
    }
}

/// A pair taken off the queue: its index, its expiry and stamp then.
#[derive(Clone, Copy)]
struct Taken {
    k: u32,
    expires: f64,
    stamp: u32,
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
    /// The rates of the stretch's part (see [`Cell::free_time`]): the speeds below hold
    /// while these do.
    rates: Vec<Vec<f64>>,
    /// Per movers on this stretch: how fast they can close a pair in.
    speed: Vec<f64>,
    /// The robots of movers that have pairs and stand still on this stretch.
    standing: Vec<usize>,
    /// When the stretch's part (or the pairs) began, and each movers' odometer then: on
    /// one part an odometer grows at its movers' speed, so an expiry is also a time.
    t0: f64,
    odo0: Vec<f64>,
    /// The end of the stretch the part's rates and weights hold to.
    until: f64,
    /// The joint odometers when the part began; this instant's less those (a movers'
    /// odometer is its odometer then plus its weighted sum of these: its weights change
    /// from part to part, each holding from its part's first instant on).
    joint_odo0: Vec<Vec<f64>>,
    joint_odo: Vec<Vec<f64>>,
    /// Per robot, per body, per joint: the body's reach from where it stood at the part's
    /// first instant to the stretch's end; how far its bodies are from its axes there and
    /// at the stretch's end (with the end's time); room to find them.
    local: Vec<Vec<Vec<f64>>>,
    far_here: BodiesFarthest,
    far_end: Vec<(f64, BodiesFarthest, f64)>,
    turn: Vec<f64>,
    reach_scratch: ReachScratch,
    /// Per movers their odometer, taken when first asked for at this instant (`odo_at`
    /// holds the instant's number).
    odometer: Vec<f64>,
    odo_at: Vec<u64>,
    instant: u64,
    /// Per pair this instant: a lower bound on its free time.
    bound: Vec<f64>,
    /// Per robot: its posed shapes in units. A body of balls only (a spherized link) is
    /// one unit: its pairs are measured together, ball by ball, and queued once, not once
    /// per ball (measuring a ball is cheaper than queueing it). Any other shape is a unit
    /// of its own: measuring it is dear, and its own bound spares it more often.
    units: Vec<Vec<Unit>>,
    /// Per robot and unit: its shapes' box at the instant numbered, taken when first asked
    /// for there (a unit of balls is in many pairs, each asking for its box).
    unit_box: Vec<Vec<(u64, Aabb)>>,
    /// Every pair whose movers move, by the instant its bound runs out on this stretch (its
    /// *expiry*, slack plus odometer at the measure, reached at the movers' speed): one
    /// queue for all movers, since on one stretch every odometer grows at a constant rate.
    /// A measure queues the pair anew; a new stretch queues every pair afresh.
    queue: Expiries,
    /// Per pair: how many times it was queued, so that a pair taken off and queued anew
    /// at the same instant is put back with its new expiry, not the one it was taken with.
    stamp: Vec<u32>,
    /// Pairs taken off the queue this instant, to be put back.
    taken: Vec<Taken>,
    /// The pairs changed since the last instant: the next one measures them all.
    fresh: bool,
    /// Take every pair's bound at every instant, not only the queue's front, and every
    /// shape on its own, not a body of balls as one unit: what those two are tested
    /// against. A pair is measured alike in both (the turned boxes' gap before GJK, GJK
    /// from the pair's last simplex: lower bounds held to their own tests), so that both
    /// skip to the same instants: GJK stops within its tolerance wherever its start
    /// leaves it, and two such bounds may straddle an instant.
    pub every_pair: bool,
    /// Per robot, per joint: the reach its rates are taken with (`rates[r][j]` is this
    /// times the joint's speed), so that a pair of its bodies can weigh them by their own.
    pub reach: Vec<Vec<f64>>,
}

/// What a part of a stretch gives the proofs (see [`Cell::free_time`]): per robot, per
/// joint, how fast it moves any point from now to the stretch's end and how far it has
/// moved one since the start; the stretch's end, and where each robot stands then.
#[derive(Clone, Copy)]
pub(super) struct Motion<'a> {
    pub rates: &'a [Vec<f64>],
    pub odometers: &'a [Vec<f64>],
    pub until: f64,
    pub ends: &'a [Vec<f64>],
}

/// How far an expiry computed as `slack + odometer` may stray from the bound's own
/// arithmetic (`slack - (now - odometer)`): rounding of metres, far below this. Pairs
/// within it of a threshold are taken and decided by the bound itself.
const EXPIRY_SLOP: f64 = 1e-9;

/// What movers `m` add up of per-robot, per-joint values `v` (rates or odometers).
fn movers_sum(m: &Movers, v: &[Vec<f64>]) -> f64 {
    let total = |r: usize| v.get(r).map_or(0.0, |v| v.iter().sum::<f64>());
    match m {
        Movers::Robot(r) => total(*r),
        Movers::Apart(r, mask) => {
            let v = v.get(*r).map_or(&[][..], Vec::as_slice);
            mask.iter().zip(v).filter(|(m, _)| **m).map(|(_, v)| v).sum::<f64>()
        }
        Movers::Weighted { robot, weights, .. } => {
            v.get(*robot).map_or(0.0, |v| v.iter().zip(weights).map(|(v, w)| v * w).sum::<f64>())
        }
        Movers::Robots(a, b) => total(*a) + total(*b),
    }
}

impl Memory {
    /// Movers `g`'s odometer at this instant.
    fn odometer(&mut self, g: usize) -> f64 {
        if self.odo_at[g] != self.instant {
            self.odo_at[g] = self.instant;
            self.odometer[g] = self.odo0[g] + movers_sum(&self.movers[g], &self.joint_odo);
        }
        self.odometer[g]
    }

    /// A new part of a stretch (or new pairs), from this instant to `until`: each movers'
    /// odometer now, by the weights it had (new pairs start from 0), then its weights by
    /// its bodies' reach where they stand (`local`), its speed, and the odometers the
    /// queue's times count from.
    fn start_stretch(&mut self, t: f64, until: f64, rates: &[Vec<f64>], listed: bool) {
        self.odo0.resize(self.movers.len(), 0.0);
        for g in 0..self.movers.len() {
            self.odo0[g] = if listed { 0.0 } else { self.odometer(g) };
        }
        // The joint odometers count from here.
        for (then, now) in self.joint_odo0.iter_mut().zip(self.joint_odo.iter_mut()) {
            for (then, now) in then.iter_mut().zip(now.iter_mut()) {
                *then += *now;
                *now = 0.0;
            }
        }
        for m in &mut self.movers {
            if let Movers::Weighted { robot, moved, weights } = m {
                let (local, reach) = (&self.local[*robot], self.reach.get(*robot));
                for (j, (w, b)) in weights.iter_mut().zip(moved.iter()).enumerate() {
                    *w = match (b, reach.and_then(|r| r.get(j))) {
                        (None, _) => 0.0,
                        (Some(b), Some(&r)) if r > 0.0 => local[*b][j] / r,
                        // A joint whose rate was taken with no reach keeps its rate.
                        (Some(_), _) => 1.0,
                    };
                }
            }
        }
        self.odo_at.fill(0);
        self.rates.clear();
        self.rates.extend(rates.iter().cloned());
        self.speed.clear();
        self.speed.extend(self.movers.iter().map(|m| movers_sum(m, rates)));
        self.t0 = t;
        self.until = until;
        self.standing.clear();
        for (g, m) in self.movers.iter().enumerate() {
            if self.populated[g] && self.speed[g] <= 0.0 {
                self.standing.extend(m.robots());
            }
        }
        self.standing.sort_unstable();
        self.standing.dedup();
    }

    /// Pair `k` measured: stamp it and queue it by when its bound runs out.
    fn requeue(&mut self, k: usize) {
        self.stamp[k] = self.stamp[k].wrapping_add(1);
        let e = self.expiry(k);
        self.queue.set(k, e);
    }

    /// When pair `k`'s bound runs out on this stretch; NaN (not queued) when its movers
    /// stand still: its bound is infinite while they do.
    fn expiry(&self, k: usize) -> f64 {
        let g = self.pairs[k].movers;
        if self.speed[g] <= 0.0 || self.speed[g].is_nan() {
            return f64::NAN;
        }
        // A pair not measured yet (its movers stood still so far) is taken as soon as they
        // move, to take its boxes' gap as the full pass does. A NaN bound is never below
        // anything (the full pass never measures it): last. Otherwise the instant the
        // odometer reaches the expiry, made earlier by twice the slop so that rounding
        // never leaves a pair in the queue that the full pass would take.
        match self.measured[k] {
            None => f64::NEG_INFINITY,
            Some((slack, at)) if (slack + at).is_nan() => f64::INFINITY,
            Some((slack, at)) => self.t0 + (slack + at - 2.0 * EXPIRY_SLOP - self.odo0[g]) / self.speed[g],
        }
    }

    /// Every pair queued afresh from what it measured.
    fn rebuild_queue(&mut self) {
        self.stamp.clear();
        self.stamp.resize(self.pairs.len(), 0);
        let mut queue = std::mem::take(&mut self.queue);
        queue.fill(self.pairs.len(), |k| self.expiry(k));
        self.queue = queue;
    }

    /// What was taken and not queued anew goes back: as it was, or, a pair first bounded
    /// this instant, with its boxes' gap.
    fn put_back(&mut self) {
        let taken = std::mem::take(&mut self.taken);
        for e in &taken {
            let k = e.k as usize;
            if self.stamp[k] != e.stamp {
                continue;
            }
            if e.expires == f64::NEG_INFINITY && self.measured[k].is_some() {
                self.requeue(k);
            } else {
                self.queue.set(k, e.expires);
            }
        }
        self.taken = taken;
        self.taken.clear();
    }

    /// The least expiry queued, `+∞` when none.
    fn front(&self) -> f64 {
        self.queue.least()
    }

    /// Takes off the queue, into `taken`, every pair that runs out before `limit` (a
    /// time).
    fn take_below(&mut self, limit: f64) {
        let (taken, stamp) = (&mut self.taken, &self.stamp);
        self.queue.take_below(limit, |k, expires| taken.push(Taken { k: k as u32, expires, stamp: stamp[k] }));
    }
}

impl Cell<'_> {
    /// How long from the instant last checked (posed in `s`) nothing can come closer than
    /// the checks allow. `rates[r][j]`: how fast joint `j` of robot `r` can move any point
    /// it moves (its reach times its peak speed from now to the stretch's end), so that a
    /// robot's points move at most the sum of its rates; one body's at most the sum of each
    /// rate weighed by the body's own reach over the rate's, the body's reach taken from
    /// where it stands at the part's first instant and at the stretch's end (`ends`, at
    /// `until`); two of its own bodies apart at most the sum so over the joints that move
    /// one and not the other. `odometers[r][j]`: the integral of the rate from the start
    /// (a body's odometer adds each part's weighed rates). Every pair the checks look at
    /// is at least its boxes' gap apart; that gap, less the clearance the pair must keep,
    /// shrinks no faster than the pair moves apart. 0 when a pair is already too close;
    /// infinite when nothing moves.
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
        t: f64,
        Motion { rates, odometers, until, ends }: Motion,
        s: &mut Scratch,
        memory: &mut Memory,
    ) -> (f64, bool) {
        let set: PairSet =
            (at.iter().map(|ra| (ra.held.map(|h| (h.object, h.posture)), ra.exempt)).collect(), present.len());
        let listed = memory.set.as_ref() != Some(&set);
        if listed {
            memory.set = Some(set);
            self.list_pairs(at, present, &*s, memory);
        }
        memory.instant += 1;
        if memory.joint_odo0.len() != odometers.len()
            || memory.joint_odo0.iter().zip(odometers).any(|(a, b)| a.len() != b.len())
        {
            memory.joint_odo0 = odometers.iter().map(|o| vec![0.0; o.len()]).collect();
        }
        memory.joint_odo.resize_with(odometers.len(), Vec::new);
        for ((d, o), o0) in memory.joint_odo.iter_mut().zip(odometers).zip(&memory.joint_odo0) {
            d.clear();
            d.extend(o.iter().zip(o0).map(|(o, o0)| o - o0));
        }
        if listed || memory.rates.as_slice() != rates || memory.until != until {
            self.local_reach(at, (t, until), rates, ends, memory);
            memory.start_stretch(t, until, rates, listed);
            if !memory.fresh && !memory.every_pair {
                memory.rebuild_queue();
            }
        }
        let standing_bounded = memory.standing.iter().all(|&r| still.get(r) == Some(&true));
        let free = if memory.fresh || memory.every_pair {
            let free = self.free_time_all(s, memory);
            if memory.fresh && !memory.every_pair {
                memory.rebuild_queue();
            }
            memory.fresh = false;
            free
        } else {
            self.free_time_queued(s, memory, t)
        };
        (free, standing_bounded && free > 0.0)
    }

    /// Per robot, per body, per joint: the body's reach from where it stands to where it
    /// stands at the stretch's end (`ends`, at `until`), each joint turning at most its
    /// peak speed (its rate over the reach the rate was taken with) all the while (see
    /// `AxisReach::bodies_over`). A robot standing still keeps what it had (its speed is
    /// nought whatever its weights); without that reach, the body's static reach.
    fn local_reach(
        &self,
        at: &[RobotAt],
        (t, until): (f64, f64),
        rates: &[Vec<f64>],
        ends: &[Vec<f64>],
        memory: &mut Memory,
    ) {
        memory.local.resize_with(at.len(), Vec::new);
        memory.far_end.resize_with(at.len(), || (f64::NAN, Vec::new(), 0.0));
        for (ri, ra) in at.iter().enumerate() {
            let own = &self.robots[ri].body_reach;
            let (Some(reach), Some(rates), Some(end)) = (memory.reach.get(ri), rates.get(ri), ends.get(ri)) else {
                memory.local[ri].clone_from(own);
                continue;
            };
            if memory.local[ri].len() == own.len() && rates.iter().all(|v| *v == 0.0) {
                continue;
            }
            let axes = &self.axes[ri];
            let left = until - t;
            // A reach taken earlier in the stretch still holds to its end (it bounds more
            // time, at rates no lower): it is taken again only once the time left has
            // halved, not at every part (most of what a part would gain, at a third of the
            // cost on the examples, where many parts have one instant each).
            let (end_time, far_end, taken_with) = &mut memory.far_end[ri];
            if *end_time == until && left > 0.5 * *taken_with {
                continue;
            }
            if *end_time != until {
                *end_time = until;
                axes.bodies_farthest(end, &mut memory.reach_scratch, far_end);
            }
            *taken_with = left;
            axes.bodies_farthest(ra.q, &mut memory.reach_scratch, &mut memory.far_here);
            memory.turn.clear();
            memory.turn.extend(rates.iter().zip(reach).map(|(v, r)| if *r > 0.0 { v / r * left } else { 0.0 }));
            axes.bodies_over((&memory.far_here, &memory.far_end[ri].1), &memory.turn, own, &mut memory.local[ri]);
        }
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
    fn aabb(&self, s: &mut Scratch, memory: &mut Memory, t: Thing) -> Aabb {
        // A single shape's box is its own (looked up, not walked to: a pair asks for its
        // sides' boxes at every bound and measure). (`list_pairs` sizes the boxes with the
        // units.)
        let (r, u) = match t {
            Thing::Static(e) => return self.statics[e].aabb,
            Thing::Held(r, i) => return s.held[r][i].aabb,
            Thing::Unit(r, u) => (r, u),
        };
        let (at, aabb) = memory.unit_box[r][u];
        if at == memory.instant {
            return aabb;
        }
        // Its shapes posed now: a unit's box taken at this instant says they are, for the
        // measures that follow (see `Cell::pose`).
        self.pose_shapes(s, r, &memory.units[r][u].shapes);
        let mut parts = self.parts(s, &memory.units, t);
        let first = parts.next().map_or_else(Aabb::new_invalid, |p| *p.aabb);
        let aabb = parts.fold(first, |b, p| b.merged(p.aabb));
        memory.unit_box[r][u] = (memory.instant, aabb);
        aabb
    }

    /// Pair `k`'s bound on its free time: its last slack less the odometer since, or its
    /// boxes' gap when it has none (both are no more than its free time). The gap, once
    /// taken, is remembered like a measured slack: most pairs are far apart, and walking
    /// their boxes again at every instant was most of this loop's cost. A remembered gap
    /// grows stale (a looser bound), so [`Self::measure`] takes the gap afresh before it
    /// measures, and remembers it when it proves the pair need not be measured.
    fn bound(&self, s: &mut Scratch, memory: &mut Memory, k: usize) -> f64 {
        let g = memory.pairs[k].movers;
        let speed = memory.speed[g];
        if speed <= 0.0 {
            return f64::INFINITY;
        }
        let now = memory.odometer(g);
        let p = &memory.pairs[k];
        if let Some((then, odometer)) = memory.measured[k] {
            (then - (now - odometer)) / speed
        } else {
            let (a, b, must) = (p.a, p.b, p.must);
            let gap = aabb_gap(&self.aabb(s, memory, a), &self.aabb(s, memory, b));
            let slack = gap - must;
            memory.measured[k] = Some((slack, now));
            slack / speed
        }
    }

    /// Measures pair `k` (unless its boxes' gap now proves it cannot lower `free`) and
    /// lowers `free` to its free time. A side of many shapes is measured shape by shape,
    /// each shape pair skipped the same way when its own boxes' gap (or, before GJK, its
    /// turned boxes' gap) proves it cannot lower `free`; the pair keeps the least slack
    /// (or gap) of its shape pairs.
    fn measure(&self, s: &mut Scratch, memory: &mut Memory, k: usize, free: &mut f64) {
        let now = memory.odometer(memory.pairs[k].movers);
        let (side_a, side_b) = (memory.pairs[k].a, memory.pairs[k].b);
        let gap = aabb_gap(&self.aabb(s, memory, side_a), &self.aabb(s, memory, side_b));
        // (Both sides' shapes are posed now: their boxes were taken.)
        let s = &*s;
        let p = &memory.pairs[k];
        let (a, b) = (self.parts(s, &memory.units, p.a), self.parts(s, &memory.units, p.b));
        let (speed, must) = (memory.speed[p.movers], p.must);
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
                // GJK is dear enough to try the turned boxes' gap first.
                if !in_closed_form(x.shape, y.shape) {
                    let turned = turned_boxes_gap(x.pose, x.shape, y.pose, y.shape).max(gap);
                    if (turned - must) / speed >= *free {
                        slack = slack.min(turned - must);
                        continue;
                    }
                }
                // A lower bound on the distance (GJK's dual bound, within 10 µm of it),
                // started from the pair's last simplex. A pair parry cannot measure keeps
                // its gap.
                let d = distance_at_least_from(
                    x.pose,
                    x.shape,
                    y.pose,
                    y.shape,
                    LOWER_BOUND_TOLERANCE,
                    &mut memory.hints[k],
                );
                let d = d.map_or(gap, |d| d.max(gap));
                // Touching within the tolerance, where only contact counts: how much deeper.
                let d = match d <= 0.0 && must == 0.0 {
                    true => depth_slack(x, y).unwrap_or(d),
                    false => d,
                };
                slack = slack.min(d - must);
                *free = free.min(((d - must) / speed).max(0.0));
            }
        }
        memory.measured[k] = Some((slack, now));
    }

    /// Every pair's bound, the least measured first, then every pair whose bound is below
    /// the least free time found, in the pairs' order.
    fn free_time_all(&self, s: &mut Scratch, memory: &mut Memory) -> f64 {
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

    /// [`Self::free_time_all`] by the queue: only the pairs whose bound can be the least
    /// or below the free time are taken off it (give or take [`EXPIRY_SLOP`]), and each is
    /// decided by its own bound, exactly as the full pass decides it: the same pairs are
    /// measured, in the same order, and the same free time comes out.
    fn free_time_queued(&self, s: &mut Scratch, memory: &mut Memory, t: f64) -> f64 {
        memory.taken.clear();
        // The time by which a pair whose bound is below `b` runs out.
        let limit = |b: f64| t + (b + b.abs() * 1e-9 + 1e-12);
        // The pairs not measured yet first: their bounds (boxes' gaps) are taken now.
        memory.take_below(f64::MIN);
        let mut front = f64::INFINITY;
        for i in 0..memory.taken.len() {
            let k = memory.taken[i].k as usize;
            front = front.min(self.bound(s, memory, k));
        }
        front = front.min(memory.front() - t);
        if front == f64::INFINITY || front.is_nan() {
            memory.put_back();
            return f64::INFINITY;
        }
        memory.take_below(limit(front));
        let mut least = (f64::INFINITY, usize::MAX);
        for i in 0..memory.taken.len() {
            let k = memory.taken[i].k as usize;
            let b = self.bound(s, memory, k);
            if b < least.0 || (b == least.0 && b < f64::INFINITY && k < least.1) {
                least = (b, k);
            }
        }
        let mut free = f64::INFINITY;
        if least.1 != usize::MAX {
            self.measure(s, memory, least.1, &mut free);
            memory.requeue(least.1);
            memory.take_below(limit(free));
        }
        let mut candidates: Vec<usize> = memory.taken.iter().map(|e| e.k as usize).filter(|&k| k != least.1).collect();
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
        free
    }
}
