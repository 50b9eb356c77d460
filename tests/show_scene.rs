//! What `declutter show` puts in its page, checked without a browser: the schedule's own
//! timeline (both arms at once), and the scene blob's geometry and keyframes against
//! the world's own kinematics. Planning is geometric: run with `--release`.

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::schedule::Schedule;
use declutter::show::{self, KEYFRAME_STEP};
use declutter::world::{self, World, WorldOptions};
use serde_json::Value;

fn box_lid() -> (World, Schedule) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(Path::new("examples/box_lid.dcl"), &FsLoader, &mut sources).unwrap();
    let world = world::build(&scn, &WorldOptions::default(), &FsLoader).unwrap();
    let planned = declutter::driver::plan_verified(&world, &|_| {}).unwrap();
    (world, planned.schedule)
}

fn largest_step(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// The scene blob, read back out of the page.
fn blob(html: &str) -> Value {
    let open = "<script type=\"application/json\" id=\"scene\">";
    let start = html.find(open).expect("the scene element") + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).expect("the scene is JSON")
}

fn pose_of(v: &Value, frame: usize, track: usize) -> Vec<f64> {
    v["poses"][frame].as_array().unwrap()[track * 7..track * 7 + 7].iter().map(|x| x.as_f64().unwrap()).collect()
}

#[test]
fn the_page_plays_the_schedules_own_time_both_arms_at_once() {
    let (w, s) = box_lid();
    let scn = w.scenario();
    let tl = show::timeline(&w, Some(&s));
    assert_eq!(s.removed, ["lid"]);
    let (r1, r2) = (scn.robot_by_name("r1").unwrap(), scn.robot_by_name("r2").unwrap());
    let (lid, can) = (tl.actions[0].clone(), tl.actions[1].clone());
    assert_eq!(tl.duration, s.makespan);
    assert_eq!(
        (lid.start, lid.end, can.start, can.end),
        (s.actions[0].start, s.actions[0].end, s.actions[1].start, s.actions[1].end)
    );
    // The schedule is concurrent: r1 goes for the can while r2 still carries the lid away.
    assert!(can.start < lid.end, "{} .. {}", can.start, lid.end);
    let mid = 0.5 * (can.start + lid.end.min(can.end));
    assert!(largest_step(&tl.tracks[r1.index()].sample(mid), w.home(r1)) > 0.1);
    assert!(largest_step(&tl.tracks[r2.index()].sample(mid), w.home(r2)) > 0.1);
    // Waypoints are reached in order, from the action's start to the grasp.
    let a = &s.actions[0].approach;
    assert_eq!(lid.approach_t[0], lid.start);
    assert!(lid.approach_t.windows(2).all(|p| p[0] < p[1]), "{:?}", lid.approach_t);
    // The lid is grasped at the end of the approach and let go at r2's `drop`, as the
    // schedule's events say.
    let events: Vec<_> = tl.events.iter().filter(|e| scn.object(e.object).body.name == "lid").collect();
    assert_eq!(events.len(), 2);
    assert_eq!(events[0].t, *lid.approach_t.last().unwrap());
    assert!(largest_step(&tl.tracks[r2.index()].sample(events[0].t), a.last().unwrap()) < 1e-12);
    let q_release = tl.tracks[r2.index()].sample(events[1].t);
    assert!(largest_step(&q_release, w.drop_config(r2)) < 1e-12, "released at {q_release:?}");
    // Between two points the page follows the schedule's Hermite curve: mid-segment, the
    // robot is neither at the segment's start nor its end.
    let pts = &s.trajectories[r2.index()].points;
    let k = pts.iter().position(|p| p.qd.iter().any(|v| v.abs() > 0.1)).expect("a moving point");
    let q_mid = tl.tracks[r2.index()].sample(0.5 * (pts[k - 1].t + pts[k].t));
    assert!(largest_step(&q_mid, &pts[k - 1].q) > 1e-3 && largest_step(&q_mid, &pts[k].q) > 1e-3);
}

#[test]
fn the_page_draws_the_world_and_carries_the_target_with_the_flange() {
    let (w, s) = box_lid();
    let scn = w.scenario();
    let v = blob(&show::show(&w, Some(&s), &[]));
    assert_eq!(v["status"], "verified");
    assert_eq!(v["step"], KEYFRAME_STEP);
    let bodies = v["bodies"].as_array().unwrap();
    let body = |name: &str| bodies.iter().find(|b| b["name"] == name).unwrap_or_else(|| panic!("no body {name}"));

    // The crate: five boxes, the floor 30 x 30 x 1 cm at (55 cm, 0, 0.5 cm).
    let crate_shapes = body("crate")["shapes"].as_array().unwrap();
    assert_eq!(crate_shapes.len(), 5);
    assert_eq!(crate_shapes[0]["type"], "box");
    assert_eq!(crate_shapes[0]["size"], serde_json::json!([0.3, 0.3, 0.01]));
    assert_eq!(crate_shapes[0]["pose"], serde_json::json!([0.55, 0.0, 0.005, 0.0, 0.0, 0.0, 1.0]));
    // The can: a cylinder of 3.3 cm by 11.5 cm, its axis along y in the shape frame.
    let can = body("can");
    assert_eq!(can["role"], "target");
    assert_eq!(body("lid")["role"], "removed");
    let cyl = &can["shapes"][0];
    assert_eq!(
        (cyl["type"].as_str(), cyl["radius"].as_f64(), cyl["length"].as_f64()),
        (Some("cylinder"), Some(0.033), Some(0.115))
    );
    // Every robot body the world has, plus one TCP per robot.
    let robot_bodies = bodies.iter().filter(|b| b["robot"].is_number()).count();
    let expected: usize = scn.robot_ids().map(|r| w.drawn_robot(r).len() + 1).sum();
    assert_eq!(robot_bodies, expected);

    // The can stands still until grasped, then rides with r1's flange until released.
    let track = can["track"].as_u64().unwrap() as usize;
    let frames = v["frames"].as_u64().unwrap() as usize;
    assert_eq!(pose_of(&v, 0, track)[..3], [0.55, 0.0, 0.0675]);
    let r1 = scn.robot_by_name("r1").unwrap();
    let a = &s.actions[1];
    let held = w.held(r1, scn.object_by_name("can").unwrap(), 0, a.approach.last().unwrap());
    let expected = w.fk_flange(r1, a.retreat.last().unwrap()) * held.pose_flange_object;
    let got = pose_of(&v, frames - 1, track);
    let t = expected.translation.vector;
    for (g, e) in got[..3].iter().zip([t.x, t.y, t.z]) {
        assert!((g - e).abs() <= 1e-4, "can at {got:?}, expected {t:?}");
    }
    // Both are released where their robots drop them: the can carried away at the end.
    let release = |o: &str| {
        s.events.iter().find(|e| e.object == o && e.kind == declutter::schedule::EventKind::Release).unwrap().t
    };
    assert_eq!(can["released_at"].as_f64(), Some((release("can") * 1e4).round() / 1e4));
    assert!(body("lid")["released_at"].is_number());
}

#[test]
fn the_cell_alone_has_one_keyframe_and_no_actions() {
    let (w, _) = box_lid();
    let v = blob(&show::show(&w, None, &[]));
    assert_eq!(
        (v["status"].as_str(), v["frames"].as_u64(), v["duration"].as_f64()),
        (Some("cell"), Some(1), Some(0.0))
    );
    assert_eq!(v["actions"], serde_json::json!([]));
    assert!(v["bodies"].as_array().unwrap().iter().all(|b| b["role"] != "removed"));
}

#[test]
fn the_page_closes_the_fingers_while_carrying() {
    // examples/gripper.dcl: a parallel gripper, open 4.25 cm a side; closed 1 cm on
    // `left`, 3 cm on `right`, 3.3 cm on the can. Its palm and two fingers are drawn apart;
    // a finger stands off the palm by how far it closed (both ride on the flange).
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(Path::new("examples/gripper.dcl"), &FsLoader, &mut sources).unwrap();
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).unwrap();
    let s = declutter::driver::plan_verified(&w, &|_| {}).unwrap().schedule;
    let v = blob(&show::show(&w, Some(&s), &[]));
    let hand: Vec<usize> = v["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|b| b["name"] == "arm pg")
        .map(|b| b["track"].as_u64().unwrap() as usize)
        .collect();
    assert_eq!(hand.len(), 3, "the palm and two fingers");
    let step = v["step"].as_f64().unwrap();
    let closed_by = |t: f64| {
        let k = (t / step).round() as usize;
        let palm = pose_of(&v, k, hand[0]);
        hand[1..].iter().map(|&f| largest_step(&pose_of(&v, k, f)[..3], &palm[..3])).fold(0.0, f64::max)
    };
    let grasps: Vec<(f64, f64)> = s.events.chunks(2).map(|e| (e[0].t, e[1].t)).collect();
    for ((grasp, release), closed) in grasps.iter().zip([0.01, 0.03, 0.033]) {
        // Halfway through the carry the fingers stand 4.25 cm − closed in from open; their
        // offset from the palm's origin in world axes is at most that (and at least its
        // largest component), so compare its norm.
        let k = (0.5 * (grasp + release) / step).round() as usize;
        let palm = pose_of(&v, k, hand[0]);
        for &f in &hand[1..] {
            let p = pose_of(&v, k, f);
            let moved = ((p[0] - palm[0]).powi(2) + (p[1] - palm[1]).powi(2) + (p[2] - palm[2]).powi(2)).sqrt();
            assert!((moved - (0.0425 - closed)).abs() < 3e-4, "carrying, a finger is {moved} m off the palm");
        }
        // Just before the grasp and after the release the hand is open: no offset.
        assert!(closed_by(grasp - 2.0 * step) < 3e-4);
        if release + 2.0 * step < s.makespan {
            assert!(closed_by(release + 2.0 * step) < 3e-4);
        }
    }
}
