//! How far the replay may skip ahead: conservative advancement over every pair the
//! checks look at, each pair remembering what it measured last.
//!
//! A pair's *slack* is its distance less what it must keep. Between two instants it
//! shrinks by at most how far the pair can move apart-wise (its *odometer*: the joints'
//! reaches times their peak speeds, integrated over time). So a slack measured earlier,
//! less the odometer since, is still a lower bound now, and only the pairs whose bound
//! could set the answer are measured again. The answer is the same as measuring every
//! pair afresh at every instant: the replay's instants do not change, only their cost.

use super::scene::{Cell, RobotAt, Scratch, Side};
use crate::resolve::ObjectId;
use crate::world::{aabb_gap, shape_distance, ObjectSet, StaticOwner};

/// Who holds what, with which fingers, and which object each may touch; how many objects
/// are in place. The pairs (and their order) are the same while this is.
type PairSet = (Vec<(Option<(ObjectId, usize)>, Option<ObjectId>)>, usize);

/// One side of a pair: a robot's shape or carried part (robot, index), or a static shape.
#[derive(Clone, Copy)]
enum Thing {
    Posed(usize, usize),
    Held(usize, usize),
    Static(usize),
}

/// Whose joints move a pair's sides apart.
enum Movers {
    /// Every joint of the robot (against the scene).
    Robot(usize),
    /// The robot's joints marked (two of its own bodies, or its flange and a body).
    Apart(usize, Vec<bool>),
    /// Every joint of both robots.
    Robots(usize, usize),
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
    /// Per movers this instant: how fast they can close a pair in, and their odometer.
    speed: Vec<f64>,
    odometer: Vec<f64>,
    /// Per pair this instant: a lower bound on its free time.
    bound: Vec<f64>,
}

impl Cell<'_> {
    /// How long from the instant last checked (posed in `s`) nothing can come closer than
    /// the checks allow. `rates[r][j]`: how fast joint `j` of robot `r` can move any point
    /// it moves (its reach times its peak speed on the stretch), so that a robot's points
    /// move at most the sum of its rates, and two of its own bodies apart at most the sum
    /// over the joints that move one and not the other; `odometers[r][j]`: the integral of
    /// that rate from the start. Every pair the checks look at is at least its boxes' gap
    /// apart; that gap, less the clearance the pair must keep, shrinks no faster than the
    /// pair moves apart. 0 when a pair is already too close; infinite when nothing moves.
    pub fn free_time(
        &self,
        at: &[RobotAt],
        present: &ObjectSet,
        rates: &[Vec<f64>],
        odometers: &[Vec<f64>],
        s: &Scratch,
        memory: &mut Memory,
    ) -> f64 {
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
                Movers::Robots(a, b) => total(v, *a) + total(v, *b),
            };
            memory.speed.push(of(rates));
            memory.odometer.push(of(odometers));
        }
        let side = |t: Thing| match t {
            Thing::Posed(r, i) => Side::of(&s.posed[r][i]),
            Thing::Held(r, i) => Side::held(&s.held[r][i]),
            Thing::Static(e) => Side::fixed(&self.statics[e]),
        };
        let aabb = |t: Thing| match t {
            Thing::Posed(r, i) => &s.posed[r][i].aabb,
            Thing::Held(r, i) => &s.held[r][i].aabb,
            Thing::Static(e) => &self.statics[e].aabb,
        };
        // Each pair's bound: its last slack less the odometer since, or its boxes' gap
        // when it has none (both are no more than its free time). The gap, once taken,
        // is remembered like a measured slack: most pairs are far apart, and walking
        // their boxes again at every instant was most of this loop's cost. A remembered
        // gap grows stale (a looser bound), so `measure` takes the gap afresh before it
        // measures, and remembers it when it proves the pair need not be measured.
        memory.bound.clear();
        let mut least = (f64::INFINITY, usize::MAX);
        for (k, p) in memory.pairs.iter().enumerate() {
            let speed = memory.speed[p.movers];
            let bound = if speed <= 0.0 {
                f64::INFINITY
            } else if let Some((then, odometer)) = memory.measured[k] {
                (then - (memory.odometer[p.movers] - odometer)) / speed
            } else {
                let slack = aabb_gap(aabb(p.a), aabb(p.b)) - p.must;
                memory.measured[k] = Some((slack, memory.odometer[p.movers]));
                slack / speed
            };
            if bound < least.0 {
                least = (bound, k);
            }
            memory.bound.push(bound);
        }
        // The pair of least bound measured first, then every pair whose bound is below the
        // least free time found, unless its boxes' gap now says it cannot be.
        let mut free = f64::INFINITY;
        let (pairs, speeds, odometer) = (&memory.pairs, &memory.speed, &memory.odometer);
        let measured = &mut memory.measured;
        let mut measure = |k: usize, free: &mut f64| {
            let p = &pairs[k];
            let (a, b) = (side(p.a), side(p.b));
            let gap = aabb_gap(a.aabb, b.aabb);
            if (gap - p.must) / speeds[p.movers] >= *free {
                // The gap is no more than the pair's slack now; keep the tighter bound.
                let now = odometer[p.movers];
                let stale = measured[k].map_or(f64::NEG_INFINITY, |(then, at)| then - (now - at));
                measured[k] = Some(((gap - p.must).max(stale), now));
                return;
            }
            // A pair parry cannot measure keeps its gap.
            let d = shape_distance(a.pose, a.shape, b.pose, b.shape).map_or(gap, |d| d.max(gap));
            measured[k] = Some((d - p.must, odometer[p.movers]));
            *free = free.min(((d - p.must) / speeds[p.movers]).max(0.0));
        };
        if least.1 != usize::MAX {
            measure(least.1, &mut free);
        }
        for (k, &bound) in memory.bound.iter().enumerate() {
            if free == 0.0 {
                break;
            }
            if bound < free && k != least.1 {
                measure(k, &mut free);
            }
        }
        free
    }

    /// Every pair the checks look at, in an order fixed by who holds what and which
    /// objects are in place; nothing measured yet.
    fn list_pairs(&self, at: &[RobotAt], present: &ObjectSet, s: &Scratch, memory: &mut Memory) {
        let c = self.clearance;
        let (pairs, movers) = (&mut memory.pairs, &mut memory.movers);
        pairs.clear();
        movers.clear();
        let mut group = |m: Movers| {
            movers.push(m);
            movers.len() - 1
        };
        for (ri, ra) in at.iter().enumerate() {
            let g = &self.robots[ri];
            let (posed, held) = (&s.posed[ri], &s.held[ri]);
            let checked = |owner: StaticOwner, carried: bool| match owner {
                StaticOwner::Fixed(_) => true,
                StaticOwner::Object(o) => {
                    present.contains(o) && ra.held.is_none_or(|h| h.object != o) && (carried || Some(o) != ra.exempt)
                }
            };
            let whole = group(Movers::Robot(ri));
            for (e, _) in self.statics.iter().enumerate().filter(|(_, st)| checked(st.owner, false)) {
                for (i, _) in posed.iter().enumerate().filter(|(_, ps)| g.bodies[ps.body].moving) {
                    pairs.push(Pair { a: Thing::Posed(ri, i), b: Thing::Static(e), must: c, movers: whole });
                }
            }
            for (e, _) in self.statics.iter().enumerate().filter(|(_, st)| checked(st.owner, true)) {
                for i in 0..held.len() {
                    pairs.push(Pair { a: Thing::Held(ri, i), b: Thing::Static(e), must: 0.0, movers: whole });
                }
            }
            let apart = |x: &[bool], y: &[bool]| x.iter().zip(y).map(|(x, y)| x != y).collect::<Vec<bool>>();
            for &(a, b) in &g.self_pairs {
                let m = group(Movers::Apart(ri, apart(&g.body_joints[a], &g.body_joints[b])));
                for (i, _) in posed.iter().enumerate().filter(|(_, x)| x.body == a) {
                    for (k, _) in posed.iter().enumerate().filter(|(_, y)| y.body == b) {
                        pairs.push(Pair { a: Thing::Posed(ri, i), b: Thing::Posed(ri, k), must: 0.0, movers: m });
                    }
                }
            }
            for i in 0..held.len() {
                for (k, ps) in posed.iter().enumerate().filter(|(_, ps)| !g.bodies[ps.body].holds) {
                    let m = group(Movers::Apart(ri, apart(&g.flange_joints, &g.body_joints[ps.body])));
                    pairs.push(Pair { a: Thing::Held(ri, i), b: Thing::Posed(ri, k), must: 0.0, movers: m });
                }
            }
            for rj in ri + 1..at.len() {
                let gj = &self.robots[rj];
                let both = group(Movers::Robots(ri, rj));
                let mine = (0..posed.len()).map(|i| (Thing::Posed(ri, i), g.bodies[posed[i].body].moving));
                for (x, xm) in mine.chain((0..held.len()).map(|i| (Thing::Held(ri, i), true))) {
                    let theirs =
                        (0..s.posed[rj].len()).map(|k| (Thing::Posed(rj, k), gj.bodies[s.posed[rj][k].body].moving));
                    for (y, ym) in theirs.chain((0..s.held[rj].len()).map(|k| (Thing::Held(rj, k), true))) {
                        if xm || ym {
                            pairs.push(Pair { a: x, b: y, must: c, movers: both });
                        }
                    }
                }
            }
        }
        memory.measured.clear();
        memory.measured.resize(memory.pairs.len(), None);
    }
}
