//! The concurrent placement's promise, re-checked densely: while two robots are both in
//! an action, they and what they carry stay `timing::SEPARATION` apart. Every 1 ms of
//! the compiled schedules of the shipped two-arm examples, by exact distances (not the
//! placement's own jumps ahead).

mod time_support;

use declutter::resolve::RobotId;
use declutter::schedule::{EventKind, Schedule};
use declutter::timing::{hermite, SEPARATION};
use declutter::world::{Held, RobotAt, World};
use time_support::compiled;

/// What robot `r` holds at `t`, as the schedule's events say.
fn held_at(w: &World, s: &Schedule, r: RobotId, t: f64) -> Option<Held> {
    let name = &w.scenario().robot(r).name;
    let traj = &s.trajectories[r.index()];
    let mine: Vec<_> = s.events.iter().filter(|e| &e.robot == name).collect();
    mine.iter().filter(|e| e.kind == EventKind::Grasp && e.t <= t).find_map(|g| {
        let released =
            mine.iter().any(|e| e.kind == EventKind::Release && e.object == g.object && e.t > g.t && e.t <= t);
        if released {
            return None;
        }
        let o = w.scenario().object_ids().find(|&o| w.scenario().object(o).body.name == g.object)?;
        let grasp = s.actions.iter().find(|a| a.object.as_ref() == Some(&g.object)).and_then(|a| a.grasp.as_deref());
        let grasp = w.scenario().object(o).grasp_index(grasp?)?;
        Some(w.held(r, o, grasp, &hermite(&traj.points, g.t)))
    })
}

/// The least distance between two robots while both are in an action, and when.
fn closest(w: &World, s: &Schedule) -> Option<(f64, f64)> {
    let robots: Vec<RobotId> = w.scenario().robot_ids().collect();
    let busy = |r: RobotId, t: f64| {
        let name = &w.scenario().robot(r).name;
        s.actions.iter().any(|a| &a.robot == name && a.start <= t && (t <= a.end || a.object.is_none()))
    };
    let mut best: Option<(f64, f64)> = None;
    let steps = (s.makespan / 1e-3).ceil() as usize;
    for i in 0..=steps {
        let t = (i as f64 * 1e-3).min(s.makespan);
        for (k, &a) in robots.iter().enumerate() {
            for &b in &robots[k + 1..] {
                if !(busy(a, t) && busy(b, t)) {
                    continue;
                }
                let (qa, qb) =
                    (hermite(&s.trajectories[a.index()].points, t), hermite(&s.trajectories[b.index()].points, t));
                let (ha, hb) = (held_at(w, s, a, t), held_at(w, s, b, t));
                let d = w.robots_apart(
                    RobotAt { robot: a, q: &qa, held: ha.as_ref() },
                    RobotAt { robot: b, q: &qb, held: hb.as_ref() },
                    f64::INFINITY,
                );
                if best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, t));
                }
            }
        }
    }
    best
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn robots_working_at_once_keep_their_separation_at_every_millisecond() {
    for name in ["box_lid", "cans_3", "cans_5", "clutter", "three_arm", "split_lid"] {
        let (w, s) = compiled(&format!("examples/{name}.dcl"));
        let overlap = closest(&w, &s);
        // Each of these has actions of two robots running at once.
        let (d, t) = overlap.unwrap_or_else(|| panic!("{name}: no two robots ever work at once"));
        assert!(d >= SEPARATION - 1e-9, "{name}: {:.2} mm apart at t = {t:.3} s", d * 1e3);
        eprintln!("{name}: closest {:.1} mm at t = {t:.3} s", d * 1e3);
    }
}
