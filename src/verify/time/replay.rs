//! The sampling loop: instants chosen so that nothing moves more than the bound
//! between two of them, and the whole cell checked at each.

use super::advance::{Memory, Motion};
use super::events::Marks;
use super::grid::{Grid, WINDOWS};
use super::scene::{Cell, Finding, RobotAt, Scratch};
use super::track::{peak_speeds, peak_speeds_between, segment_at, state_at};
use super::{ReplayOptions, TimeViolation, Timeline, Track};
use crate::resolve::{ObjectId, RobotId};
use crate::verify::Violation;
use crate::world::{AxisReach, Farthest, Held, ObjectSet, ReachScratch, World};

/// Windows of at most this many steps by the bound that holds everywhere keep it.
const FEW_STEPS: f64 = 3.0;
/// At most this many parts of a stretch take their own rates for the proofs (see `run`):
/// eight did as well as sixteen on the `narrow_gap` medians and the paper's examples
/// (box_lid 85.3 against 87.0 M instructions), four slightly worse, thirty-two and
/// sixty-four worse again (each new part's rates requeue every pair).
const PARTS: u64 = 8;

/// Samples the timeline from 0 to the makespan; returns the number of instants checked.
/// Each pair of things too close is reported once, at the first instant found.
/// A robot at one instant as far as its own checks go: configuration, object held,
/// object it may touch.
type Stance = (Vec<f64>, Option<ObjectId>, Option<ObjectId>);

pub(super) fn run(
    world: &World,
    tl: &Timeline,
    tracks: &[&Track],
    marks: &Marks,
    opts: &ReplayOptions,
    out: &mut Vec<Violation>,
    instants: &mut Vec<f64>,
) -> u64 {
    let cell = Cell::new(world, opts.clearance);
    let held: Vec<f64> = tracks.iter().map(|tr| held_radius(world, tr, marks)).collect();
    let reach: Vec<Vec<f64>> =
        tracks.iter().zip(&held).map(|(tr, &h)| world.joint_reach(tr.robot).with_held(h)).collect();
    let axes: Vec<AxisReach> = tracks.iter().zip(&held).map(|(tr, &h)| world.axis_reach(tr.robot, h)).collect();
    let times = breakpoints(tl, tracks, marks);
    let n_objects = world.scenario().objects.len();
    let mut scratch = Scratch::default();
    let mut state = vec![(Vec::new(), Vec::new()); tracks.len()];
    let mut found: Vec<Finding> = Vec::new();
    let mut reported: Vec<(f64, Finding)> = Vec::new();
    let mut peak = Vec::new();
    let mut samples = 0u64;
    // What each robot was last checked with: (q, held object, exempt object), and how
    // many objects were in place then (they only ever disappear).
    let mut last: Vec<Option<Stance>> = vec![None; tracks.len()];
    let mut last_present = usize::MAX;
    let mut still = vec![false; tracks.len()];
    let mut memory = Memory::default();
    memory.every_pair = opts.every_pair;
    memory.reach = reach.clone();
    // Returns how long from `t` nothing can come too close (see `Cell::free_time`), given
    // each joint's rate and odometer; without them, only checks. `clear`: an earlier
    // instant of the stretch has already proved nothing too close at `t`, so the contact
    // checks are skipped. `closing`: one robot (by track) holding what it holds with its
    // fingers in another posture, on their way between open and closed.
    let mut sample = |t: f64,
                      motion: Option<Motion>,
                      clear: bool,
                      samples: &mut u64,
                      closing: Option<(usize, &Held)>|
     -> f64 {
        *samples += 1;
        if opts.record_instants {
            instants.push(t);
        }
        for (tr, (q, qd)) in tracks.iter().zip(state.iter_mut()) {
            state_at(tr, t, q, qd);
        }
        let mut present = ObjectSet::new();
        for o in 0..n_objects {
            let o = ObjectId(o as u32);
            if !marks.carries.iter().any(|c| c.object == o && t >= c.grasp) {
                present.insert(o);
            }
        }
        let at: Vec<RobotAt> = tracks
            .iter()
            .zip(&state)
            .enumerate()
            .map(|(ti, (tr, (q, _)))| RobotAt {
                q,
                held: closing.filter(|(k, _)| *k == ti).map(|(_, h)| h).or_else(|| {
                    marks.carries.iter().find(|c| c.robot == tr.robot && t >= c.grasp && t < c.release).map(|c| &c.held)
                }),
                exempt: marks
                    .carries
                    .iter()
                    .find(|c| c.robot == tr.robot && t >= c.exempt_from && t < c.grasp)
                    .map(|c| c.object),
            })
            .collect();
        let in_place = present.len();
        for (ri, ra) in at.iter().enumerate() {
            let now = (ra.q.to_vec(), ra.held.map(|h| h.object), ra.exempt);
            still[ri] = closing.is_none() && in_place <= last_present && last[ri].as_ref() == Some(&now);
            last[ri] = Some(now);
        }
        last_present = in_place;
        found.clear();
        cell.pose(&at, &mut scratch);
        // The bounds that give the free time also prove the instant itself clear when every
        // pair's lower bound is above what it must keep: the check would find nothing (not
        // taken in the reference mode that checks every step).
        let (free, proved) = match motion {
            Some(motion) => cell.free_time(&at, &present, &still, t, motion, &mut scratch, &mut memory),
            None => (0.0, false),
        };
        let settled = clear || (proved && !opts.every_step);
        if !settled {
            cell.pose_all(&mut scratch);
            cell.check(&at, &present, &still, &scratch, &mut found);
        }
        for f in found.drain(..) {
            if !reported.iter().any(|(_, r)| r.0 == f.0 && r.1 == f.1) {
                reported.push((t, f));
            }
        }
        free
    };
    let mut rates: Vec<Vec<f64>> = vec![Vec::new(); tracks.len()];
    let (mut part_rates, mut part_peak): (Vec<Vec<f64>>, _) = (vec![Vec::new(); tracks.len()], Vec::new());
    // Per robot, per joint: the integral of its rate up to the stretch's start.
    let mut travelled: Vec<Vec<f64>> = reach.iter().map(|r| vec![0.0; r.len()]).collect();
    let mut odometers = travelled.clone();
    let mut window_peak = Vec::new();
    // Per track: the time the first farthest-point list is of, that list, and the other's.
    let mut window_ends: Vec<(Option<f64>, Farthest, Farthest)> = vec![(None, Vec::new(), Vec::new()); tracks.len()];
    let (mut end_q, mut end_qd, mut end_scratch) = (Vec::new(), Vec::new(), ReachScratch::default());
    let (mut travel, mut window_reach) = (Vec::new(), Vec::new());
    let (mut stretch_ends, mut stretch_end_qd): (Vec<Vec<f64>>, _) = (vec![Vec::new(); tracks.len()], Vec::new());
    for w in times.windows(2) {
        let (ta, tb) = (w[0], w[1]);
        // How fast each joint of each robot moves any point it moves on this stretch, and
        // the fastest any point of any robot (or what it may carry) moves.
        let mid = 0.5 * (ta + tb);
        let segments: Vec<usize> = tracks.iter().map(|tr| segment_at(tr, mid)).collect();
        for (((tr, &k), r), rate) in tracks.iter().zip(&segments).zip(&reach).zip(rates.iter_mut()) {
            peak_speeds(tr, k, &mut peak);
            *rate = r.iter().zip(&peak).map(|(r, v)| r * v.abs()).collect();
        }
        let speed = rates.iter().map(|r| r.iter().sum::<f64>()).fold(0.0, f64::max);
        // Steps of the bound (no point moves more between two instants), each window of the
        // stretch by its own peak speeds and the arm's reach at its ends (along one Panda
        // path, 0.4-0.6 times the reach that holds everywhere: 0.6 times the instants where
        // it runs close to something); or longer where the instant just checked
        // proves that nothing can come too close before the next. The proofs take the
        // reach that holds everywhere and, in each part of the stretch, the peak speeds
        // from the part's start to the stretch's end (see below), so they hold across its
        // windows to its end.
        let uniform = ((speed * (tb - ta) / opts.bound).ceil().max(1.0)).min(u32::MAX as f64) as u64;
        let mut grid = Grid::new(ta, tb, uniform.min(WINDOWS), opts.bound, |a, b| {
            let mut fastest = 0.0f64;
            for (ti, ((tr, &k), r)) in tracks.iter().zip(&segments).zip(&reach).enumerate() {
                peak_speeds_between(tr, k, a, b, &mut window_peak);
                let everywhere: f64 = r.iter().zip(&window_peak).map(|(r, v)| r * v).sum();
                // A window of a few steps gains at most a step or two from the arm's
                // stance (and most such windows are passed with one instant or none).
                if everywhere * (b - a) <= FEW_STEPS * opts.bound {
                    fastest = fastest.max(everywhere);
                    continue;
                }
                // Each joint's reach over the window, from the arm's stance at its ends.
                let ends = &mut window_ends[ti];
                if ends.0 != Some(a) {
                    state_at(tr, a, &mut end_q, &mut end_qd);
                    axes[ti].farthest(&end_q, &mut end_scratch, &mut ends.1);
                }
                state_at(tr, b, &mut end_q, &mut end_qd);
                axes[ti].farthest(&end_q, &mut end_scratch, &mut ends.2);
                travel.clear();
                travel.extend(r.iter().zip(&window_peak).map(|(r, v)| r * v * (b - a)));
                axes[ti].over(&ends.1, &ends.2, &travel, r, &mut window_reach);
                fastest = fastest.max(window_reach.iter().zip(&window_peak).map(|(r, v)| r * v).sum::<f64>());
                // The next window starts where this one ends.
                ends.0 = Some(b);
                std::mem::swap(&mut ends.1, &mut ends.2);
            }
            fastest
        });
        // The proofs' rates, part by part of the stretch: in part `p`, each joint's peak
        // speed from the part's start to the stretch's end. Never more than the stretch's
        // (the first part's), never less than the joint's speed at any instant to come in
        // the stretch, so a proof at any instant holds to the stretch's end; and a move
        // slowing down to its end proves more the nearer it gets (where the Panda's grasps
        // and goals touch within the tolerance). The odometers add the part's rates up.
        let parts = Parts::new(ta, tb, uniform.min(PARTS));
        // Where each robot stands at the stretch's end: its bodies' reach is taken between
        // there and where they stand at each part's first instant.
        for (tr, q) in tracks.iter().zip(stretch_ends.iter_mut()) {
            state_at(tr, tb, q, &mut stretch_end_qd);
        }
        let mut part = 0;
        remainder_rates(tracks, &segments, &reach, parts.start(0), tb, &mut part_peak, &mut part_rates);
        let mut base = travelled.clone();
        // Nothing can be too close up to this instant, as the last one proved.
        let mut clear_until = f64::NEG_INFINITY;
        let mut at = grid.first();
        while let Some(i) = at {
            let t = grid.time(i);
            while part + 1 < parts.count && t >= parts.start(part + 1) {
                add_rates(&mut base, &part_rates, parts.start(part + 1) - parts.start(part));
                part += 1;
                remainder_rates(tracks, &segments, &reach, parts.start(part), tb, &mut part_peak, &mut part_rates);
            }
            for ((o, b), rate) in odometers.iter_mut().zip(&base).zip(&part_rates) {
                for ((o, b), v) in o.iter_mut().zip(b).zip(rate) {
                    *o = b + v * (t - parts.start(part));
                }
            }
            let proof = Some(Motion { rates: &part_rates, odometers: &odometers, until: tb, ends: &stretch_ends });
            let free = sample(t, proof, !opts.every_step && t <= clear_until, &mut samples, None);
            clear_until = t + free;
            at = if opts.every_step { grid.next(i) } else { grid.skip_to(i, t + free) };
        }
        // The parts not reached (the stretch's last proof skipped them) add their rates too.
        loop {
            let end = if part + 1 < parts.count { parts.start(part + 1) } else { tb };
            add_rates(&mut base, &part_rates, end - parts.start(part));
            if part + 1 >= parts.count {
                break;
            }
            part += 1;
            remainder_rates(tracks, &segments, &reach, parts.start(part), tb, &mut part_peak, &mut part_rates);
        }
        travelled = base;
    }
    sample(tl.makespan, None, false, &mut samples, None);
    // The fingers close on each object at its grasp and open at its release: each posture
    // on the way, with everything else as it is at that instant.
    for c in &marks.carries {
        let Some(ti) = tracks.iter().position(|tr| tr.robot == c.robot) else { continue };
        for t in [c.grasp, c.release].into_iter().filter(|t| t.is_finite() && *t <= tl.makespan) {
            for &posture in world.closing(c.robot, c.held.posture) {
                let held = Held { posture, ..c.held.clone() };
                sample(t, None, false, &mut samples, Some((ti, &held)));
            }
        }
    }
    for (t, (a, b, distance)) in reported {
        out.push(Violation::timed(Some(t), TimeViolation::Contact { a, b, distance, clearance: opts.clearance }));
    }
    samples
}

/// A stretch `[ta, tb)` cut into `count` equal parts (as the grid cuts it into windows).
struct Parts {
    ta: f64,
    tb: f64,
    count: u64,
}

impl Parts {
    fn new(ta: f64, tb: f64, count: u64) -> Parts {
        Parts { ta, tb, count: count.max(1) }
    }
    fn start(&self, p: u64) -> f64 {
        self.ta + (self.tb - self.ta) / self.count as f64 * p as f64
    }
}

/// Per track, per joint: its reach times its peak speed between `from` and `tb` on the
/// stretch's segment.
fn remainder_rates(
    tracks: &[&Track],
    segments: &[usize],
    reach: &[Vec<f64>],
    from: f64,
    tb: f64,
    peak: &mut Vec<f64>,
    out: &mut [Vec<f64>],
) {
    for (((tr, &k), r), rate) in tracks.iter().zip(segments).zip(reach).zip(out.iter_mut()) {
        peak_speeds_between(tr, k, from, tb, peak);
        rate.clear();
        rate.extend(r.iter().zip(peak.iter()).map(|(r, v)| r * v.abs()));
    }
}

/// `odometers += rates · dt`, joint by joint.
fn add_rates(odometers: &mut [Vec<f64>], rates: &[Vec<f64>], dt: f64) {
    for (o, rate) in odometers.iter_mut().zip(rates) {
        for (o, v) in o.iter_mut().zip(rate) {
            *o += v * dt;
        }
    }
}

/// How far from its flange origin a point of the largest object the track's robot ever
/// carries can be (0 if it carries none).
fn held_radius(world: &World, tr: &Track, marks: &Marks) -> f64 {
    let r: RobotId = tr.robot;
    marks.carries.iter().filter(|c| c.robot == r).map(|c| world.held_radius(&c.held)).fold(0.0, f64::max)
}

/// Every instant where something changes: trajectory points and events, within 0..makespan.
fn breakpoints(tl: &Timeline, tracks: &[&Track], marks: &Marks) -> Vec<f64> {
    let mut ts: Vec<f64> = vec![0.0, tl.makespan];
    ts.extend(tracks.iter().flat_map(|tr| tr.points.iter().map(|p| p.t)));
    ts.extend(marks.carries.iter().flat_map(|c| [c.exempt_from, c.grasp, c.release]));
    ts.retain(|t| t.is_finite() && *t >= 0.0 && *t <= tl.makespan);
    ts.sort_by(f64::total_cmp);
    ts.dedup();
    ts
}
