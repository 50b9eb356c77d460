//! An independent dense re-check of a timeline, for tests: uniform time steps from one
//! global speed bound (not the verifier's per-stretch steps), every pair of robot
//! shapes and every robot shape against what is in place, by parry's contact depth.
#![allow(dead_code)]

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::{ObjectId, RobotId};
use declutter::schedule::Schedule;
use declutter::verify::time::hermite::Cubic;
use declutter::verify::time::{EventKind, Timeline, Track};
use declutter::world::{self, PosedShape, StaticOwner, World, WorldOptions, CONTACT_TOLERANCE};
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::query;

/// Positions of `tr` at `t`, by the same Hermite rule the schedule format states.
fn q_at(tr: &Track, t: f64) -> Vec<f64> {
    let p = &tr.points;
    let k = p.iter().rposition(|x| x.t <= t).unwrap_or(0).min(p.len().saturating_sub(2));
    if p.len() < 2 || t <= p[0].t {
        return p[0].q.clone();
    }
    if t >= p[p.len() - 1].t {
        return p[p.len() - 1].q.clone();
    }
    let (a, b) = (&p[k], &p[k + 1]);
    let h = b.t - a.t;
    (0..a.q.len()).map(|j| Cubic::new(h, a.q[j], a.qd[j], b.q[j], b.qd[j]).position((t - a.t) / h)).collect()
}

/// Sample instants: between consecutive trajectory points of any robot, a uniform step
/// from that stretch's largest joint speeds (read off a 64-step grid of the cubic and
/// raised 5 %: the velocity is a parabola, whose peak between grid points is barely above
/// the grid's, 0.03 % for a rest-to-rest move) times each joint's reach, so that no point
/// moves more than `bound` between samples.
fn instants(w: &World, tl: &Timeline, bound: f64) -> Vec<f64> {
    let mut knots: Vec<f64> = tl.tracks.iter().flat_map(|tr| tr.points.iter().map(|p| p.t)).collect();
    knots.push(0.0);
    knots.push(tl.makespan);
    knots.retain(|t| (0.0..=tl.makespan).contains(t));
    knots.sort_by(f64::total_cmp);
    knots.dedup();
    let reach: Vec<Vec<f64>> = tl.tracks.iter().map(|tr| w.joint_reach(tr.robot).with_held(0.5)).collect();
    let mut out = Vec::new();
    for k in knots.windows(2) {
        let (a, b) = (k[0], k[1]);
        let mut speed: f64 = 0.0;
        for (tr, reach) in tl.tracks.iter().zip(&reach) {
            // The segment of this track covering the stretch.
            let Some(i) = tr.points.windows(2).position(|p| p[0].t <= a && b <= p[1].t) else { continue };
            let (p, q) = (&tr.points[i], &tr.points[i + 1]);
            let h = q.t - p.t;
            let v: f64 = (0..p.q.len())
                .map(|j| {
                    let c = Cubic::new(h, p.q[j], p.qd[j], q.q[j], q.qd[j]);
                    let peak = (0..=64).map(|m| c.velocity(m as f64 / 64.0).abs()).fold(0.0, f64::max);
                    1.05 * peak * reach[j]
                })
                .sum();
            speed = speed.max(v);
        }
        let n = ((speed * (b - a) / bound).ceil() as usize).max(1);
        out.extend((0..n).map(|i| a + (b - a) * i as f64 / n as f64));
    }
    out.push(tl.makespan);
    out
}

/// Overlapping deeper than the contact tolerance, by the world's rule: a primitive shrunk
/// by the tolerance meets the other shape; two meshes by parry's contact depth.
fn deep(a: &PosedShape, b: &PosedShape) -> bool {
    if !a.aabb.intersects(&b.aabb) {
        return false;
    }
    match (&a.eroded, &b.eroded) {
        (Some(e), _) => query::intersection_test(&a.pose, &*e.0, &b.pose, &*b.shape.0).map_or(true, |i| i.intersecting),
        (None, Some(e)) => {
            query::intersection_test(&b.pose, &*e.0, &a.pose, &*a.shape.0).map_or(true, |i| i.intersecting)
        }
        (None, None) => {
            matches!(query::contact(&a.pose, &*a.shape.0, &b.pose, &*b.shape.0, 0.0), Ok(Some(c)) if c.dist < -CONTACT_TOLERANCE)
        }
    }
}

/// Contacts between robots, and between robots and fixed bodies or objects not yet
/// grasped (the grasping robot's hand excepted from the grasp on), sampled so that no
/// point moves more than `bound` between samples. Returns (t, description) of each.
pub fn dense_contacts(w: &World, tl: &Timeline, bound: f64) -> Vec<(f64, String)> {
    let statics = w.static_shapes();
    let mut out = Vec::new();
    let mut posed: Vec<Vec<PosedShape>> = vec![Vec::new(); tl.tracks.len()];
    let grasped =
        |o: ObjectId, t: f64| tl.events.iter().any(|e| e.kind == EventKind::Grasp && e.object == o && e.t <= t);
    // The robot that grasps an object may touch it from its approach's last waypoint on.
    let grasper = |o: ObjectId| tl.actions.iter().find(|a| a.object == Some(o)).map(|a| a.robot);
    // Each grasp: who holds what from when to when, and the object's pose in the hand.
    let carries: Vec<_> = tl
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Grasp)
        .filter_map(|g| {
            let tr = tl.tracks.iter().find(|t| t.robot == g.robot)?;
            let release = tl
                .events
                .iter()
                .find(|e| e.kind == EventKind::Release && e.object == g.object && e.t >= g.t)
                .map_or(f64::INFINITY, |e| e.t);
            let grasp = tl.actions.iter().find(|a| a.object == Some(g.object) && a.robot == g.robot)?.grasp;
            Some((g.robot, g.t, release, w.held(g.robot, g.object, grasp, &q_at(tr, g.t))))
        })
        .collect();
    for t in instants(w, tl, bound) {
        for (k, tr) in tl.tracks.iter().enumerate() {
            let holding = carries.iter().find(|(r, from, to, _)| *r == tr.robot && t >= *from && t < *to);
            let flange = w.pose_shapes(tr.robot, &q_at(tr, t), holding.map(|c| &c.3), &mut posed[k]);
            // A carried object rides along as one more shape of its robot, a body of its own.
            for (r, from, to, held) in &carries {
                if *r == tr.robot && t >= *from && t < *to {
                    for p in w.pose_held(held, &flange) {
                        posed[k].push(PosedShape {
                            body: usize::MAX,
                            shape: p.shape,
                            eroded: p.eroded,
                            pose: p.pose,
                            aabb: p.aabb,
                        });
                    }
                }
            }
        }
        for (k, tr) in tl.tracks.iter().enumerate() {
            let bodies = w.bodies(tr.robot);
            let name = |b: usize| bodies.get(b).map_or("(carried)", |x| x.name.as_str()).to_string();
            for a in posed[k].iter().filter(|a| a.body == usize::MAX || bodies[a.body].moving) {
                if a.body == usize::MAX {
                    // Carried objects are checked against the other robots only: they rest on
                    // the scene when grasped.
                    continue;
                }
                for s in &statics {
                    if let StaticOwner::Object(o) = s.owner {
                        if grasped(o, t) || grasper(o) == Some(tr.robot) {
                            continue;
                        }
                    }
                    let fixed = PosedShape {
                        body: usize::MAX,
                        shape: s.shape.clone(),
                        eroded: None,
                        pose: s.pose,
                        aabb: s.aabb,
                    };
                    let hit = deep(a, &fixed);
                    if hit {
                        out.push((t, format!("robot {} body {} hits {:?}", tr.robot.0, name(a.body), s.owner)));
                    }
                }
            }
            for (l, other) in tl.tracks.iter().enumerate().skip(k + 1) {
                let ob = w.bodies(other.robot);
                let other_name = |b: usize| ob.get(b).map_or("(carried)", |x| x.name.as_str()).to_string();
                let moving = |b: usize, list: &[declutter::world::BodyInfo]| list.get(b).is_none_or(|x| x.moving);
                for a in &posed[k] {
                    for b in &posed[l] {
                        if (moving(a.body, &bodies) || moving(b.body, &ob)) && deep(a, b) {
                            out.push((
                                t,
                                format!(
                                    "robot {} body {} hits robot {} body {}",
                                    tr.robot.0,
                                    name(a.body),
                                    other.robot.0,
                                    other_name(b.body)
                                ),
                            ));
                        }
                    }
                }
            }
        }
    }
    out
}

/// The robot ids of a timeline's tracks, for messages.
pub fn robots(tl: &Timeline) -> Vec<RobotId> {
    tl.tracks.iter().map(|t| t.robot).collect()
}

/// The schedule `compile` writes for a scenario file, with its world.
pub fn compiled(file: &str) -> (World, Schedule) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(Path::new(file), &FsLoader, &mut sources).expect("example resolves");
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("example world builds");
    let planned = declutter::driver::plan_verified(&w, &|_| {}).unwrap_or_else(|v| panic!("{v:#?}"));
    (w, planned.schedule)
}

/// Moves robot `robot`'s motion from `from` seconds on earlier by `by` seconds (it must be
/// idle in `from - by .. from`), with its actions and events; it then holds its last
/// configuration to the makespan.
pub fn shift_earlier(s: &mut Schedule, robot: &str, from: f64, by: f64) {
    let tr = s.trajectories.iter_mut().find(|t| t.robot == robot).expect("the robot's trajectory");
    tr.points.retain(|p| p.t < from - by || p.t >= from);
    for p in tr.points.iter_mut().filter(|p| p.t >= from) {
        p.t -= by;
    }
    let mut last = tr.points.last().cloned().expect("points");
    if last.t < s.makespan {
        last.t = s.makespan;
        tr.points.push(last);
    }
    for a in s.actions.iter_mut().filter(|a| a.robot == robot && a.start >= from) {
        a.start -= by;
        a.end -= by;
    }
    for e in s.events.iter_mut().filter(|e| e.robot == robot && e.t >= from) {
        e.t -= by;
    }
}
