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
use crate::world::{aabb_gap, shape_distance, ObjectSet, StaticOwner, StaticShape};

/// Who holds what, with which fingers, and which object each may touch; how many objects
/// are in place. The pairs (and their order) are the same while this is.
type PairSet = (Vec<(Option<(ObjectId, usize)>, Option<ObjectId>)>, usize);

/// What each pair measured last, by its place in the order pairs are listed.
#[derive(Default)]
pub(super) struct Memory {
    set: Option<PairSet>,
    /// Slack (metres) and the pair's odometer at the measure.
    measured: Vec<Option<(f64, f64)>>,
    /// Per pair this instant: (lower bound on its free time, index).
    order: Vec<(f64, usize)>,
}

/// One pair this instant: both sides, the distance it must keep, how fast its sides can
/// close in, and its odometer.
struct Pair<'a> {
    a: Side<'a>,
    b: Side<'a>,
    must: f64,
    speed: f64,
    odometer: f64,
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
        let pairs = self.pairs(at, present, rates, odometers, s, memory.measured.len());
        let set: PairSet =
            (at.iter().map(|ra| (ra.held.map(|h| (h.object, h.posture)), ra.exempt)).collect(), present.len());
        if memory.set.as_ref() != Some(&set) || memory.measured.len() != pairs.len() {
            memory.set = Some(set);
            memory.measured.clear();
            memory.measured.resize(pairs.len(), None);
        }
        // Each pair's bound: the better of its boxes' gap now and its last slack less the
        // odometer since. No pair's free time is below its bound.
        memory.order.clear();
        let mut least = (f64::INFINITY, usize::MAX);
        for (k, p) in pairs.iter().enumerate() {
            if p.speed <= 0.0 {
                continue;
            }
            let mut slack = aabb_gap(p.a.aabb, p.b.aabb) - p.must;
            if let Some((then, odometer)) = memory.measured[k] {
                slack = slack.max(then - (p.odometer - odometer));
            }
            let bound = slack / p.speed;
            if bound < least.0 {
                least = (bound, k);
            }
            memory.order.push((bound, k));
        }
        // The pair of least bound measured first, then every pair whose bound is below the
        // least free time found.
        let mut free = f64::INFINITY;
        let mut measure = |k: usize, free: &mut f64| {
            let p = &pairs[k];
            let gap = aabb_gap(p.a.aabb, p.b.aabb);
            // A pair parry cannot measure keeps its gap.
            let d = shape_distance(p.a.pose, p.a.shape, p.b.pose, p.b.shape).map_or(gap, |d| d.max(gap));
            memory.measured[k] = Some((d - p.must, p.odometer));
            *free = free.min(((d - p.must) / p.speed).max(0.0));
        };
        if least.1 != usize::MAX {
            measure(least.1, &mut free);
        }
        for &(bound, k) in &memory.order {
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
    /// objects are in place.
    fn pairs<'s>(
        &'s self,
        at: &[RobotAt],
        present: &ObjectSet,
        rates: &[Vec<f64>],
        odometers: &[Vec<f64>],
        s: &'s Scratch,
        hint: usize,
    ) -> Vec<Pair<'s>> {
        let c = self.clearance;
        let mut out = Vec::with_capacity(hint);
        let sum = |v: &[Vec<f64>], r: usize| v.get(r).map_or(0.0, |v| v.iter().sum::<f64>());
        // Over the joints that move one of two bodies of robot `r` and not the other.
        let apart = |v: &[Vec<f64>], r: usize, a: &[bool], b: &[bool]| {
            let v = v.get(r).map_or(&[][..], Vec::as_slice);
            a.iter().zip(b).zip(v).filter(|((x, y), _)| x != y).map(|(_, v)| v).sum::<f64>()
        };
        for (ri, ra) in at.iter().enumerate() {
            let g = &self.robots[ri];
            let (speed, odometer) = (sum(rates, ri), sum(odometers, ri));
            let (posed, held) = (&s.posed[ri], &s.held[ri]);
            let checked = |e: &&StaticShape, carried: bool| match e.owner {
                StaticOwner::Fixed(_) => true,
                StaticOwner::Object(o) => {
                    present.contains(o) && ra.held.is_none_or(|h| h.object != o) && (carried || Some(o) != ra.exempt)
                }
            };
            for e in self.statics.iter().filter(|e| checked(e, false)) {
                for ps in posed.iter().filter(|ps| g.bodies[ps.body].moving) {
                    out.push(Pair { a: Side::of(ps), b: Side::fixed(e), must: c, speed, odometer });
                }
            }
            for e in self.statics.iter().filter(|e| checked(e, true)) {
                for part in held {
                    out.push(Pair { a: Side::held(part), b: Side::fixed(e), must: 0.0, speed, odometer });
                }
            }
            for &(a, b) in &g.self_pairs {
                let (ja, jb) = (&g.body_joints[a], &g.body_joints[b]);
                let (speed, odometer) = (apart(rates, ri, ja, jb), apart(odometers, ri, ja, jb));
                for x in posed.iter().filter(|x| x.body == a) {
                    for y in posed.iter().filter(|y| y.body == b) {
                        out.push(Pair { a: Side::of(x), b: Side::of(y), must: 0.0, speed, odometer });
                    }
                }
            }
            for part in held {
                for ps in posed.iter().filter(|ps| !g.bodies[ps.body].holds) {
                    let (jf, jb) = (&g.flange_joints, &g.body_joints[ps.body]);
                    let (speed, odometer) = (apart(rates, ri, jf, jb), apart(odometers, ri, jf, jb));
                    out.push(Pair { a: Side::held(part), b: Side::of(ps), must: 0.0, speed, odometer });
                }
            }
            for rj in ri + 1..at.len() {
                let gj = &self.robots[rj];
                let speed = speed + sum(rates, rj);
                let odometer = odometer + sum(odometers, rj);
                let mine = posed.iter().map(|x| (Side::of(x), g.bodies[x.body].moving));
                for (xa, xm) in mine.chain(held.iter().map(|p| (Side::held(p), true))) {
                    let theirs = s.posed[rj].iter().map(|y| (Side::of(y), gj.bodies[y.body].moving));
                    for (ya, ym) in theirs.chain(s.held[rj].iter().map(|p| (Side::held(p), true))) {
                        if xm || ym {
                            out.push(Pair { a: xa, b: ya, must: c, speed, odometer });
                        }
                    }
                }
            }
        }
        out
    }
}
