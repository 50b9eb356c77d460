//! Grippers: a finger joint (a movable joint hanging from the links rigid with the flange
//! in the arm's URDF, or any movable joint of a hand's URDF) stands open (its upper limit,
//! or the robot's `open`) with the hand empty, and closes while holding as the robot's
//! `closed` or the grasp's `width` says. Checked against positions computed by hand from
//! the URDFs, by pinned diagnostics for postures that cannot be, and on the Panda with its
//! own fingers from `../shared/robots` (skipped, saying why, when that directory is absent).

use std::path::{Path, PathBuf};
use std::process::Command;

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::RobotId;
use declutter::schedule::{EventKind, Schedule};
use declutter::world::{self, Drawable, Held, World, WorldOptions};

fn world_of(path: &Path) -> World {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(path, &FsLoader, &mut sources).unwrap_or_else(|e| panic!("{e:?}"));
    world::build(&scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"))
}

#[test]
fn a_hands_fingers_stand_at_their_upper_limits() {
    let w = world_of(Path::new("tests/fixtures/grippers/slide_hand.dcl"));
    let hand = w.drawn_robot(RobotId(0)).into_iter().find(|b| b.name == "slide").expect("the hand's body");
    // Each finger box (2 × 1 × 4 cm) sits at its joint's origin (z 2 cm), slid 3 cm out
    // along ±y, then its collision origin (±0.5 cm in y, 4 cm in z): (0, ±3.5 cm, 6 cm).
    let mut fingers: Vec<[f64; 3]> = hand
        .shapes
        .iter()
        .filter(|s| matches!(s.shape, Drawable::Box { size } if size == [0.02, 0.01, 0.04]))
        .map(|s| s.pose.translation.vector.into())
        .collect();
    fingers.sort_by(|a, b| a[1].total_cmp(&b[1]));
    assert_eq!(fingers.len(), 2);
    for (found, want) in fingers.iter().zip([[0.0, -0.035, 0.06], [0.0, 0.035, 0.06]]) {
        assert!(found.iter().zip(want).all(|(f, w)| (f - w).abs() < 1e-12), "{found:?}, want {want:?}");
    }
}

/// Where the finger boxes (2 × 1 × 4 cm) of the test's sliding hand stand, in the flange
/// frame, sorted along y.
fn slide_fingers(w: &World, q: &[f64], held: Option<&Held>) -> Vec<[f64; 3]> {
    let arm = RobotId(0);
    let mut shapes = Vec::new();
    let flange = w.pose_shapes(arm, q, held, &mut shapes);
    let mut found: Vec<[f64; 3]> = shapes
        .iter()
        .filter(|s| s.shape.as_cuboid().is_some_and(|c| (c.half_extents.y - 0.005).abs() < 1e-12))
        .map(|s| {
            let t = s.pose.translation;
            (flange.inverse() * nalgebra::Point3::new(t.x, t.y, t.z)).coords.into()
        })
        .collect();
    found.sort_by(|a, b| a[1].total_cmp(&b[1]));
    found
}

fn assert_near(found: &[[f64; 3]], want: &[[f64; 3]]) {
    assert_eq!(found.len(), want.len(), "{found:?}");
    for (f, w) in found.iter().zip(want) {
        assert!(f.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-9), "{found:?}, want {want:?}");
    }
}

#[test]
fn a_grasp_closes_the_fingers_as_its_width_or_the_robots_closed_says() {
    let w = world_of(Path::new("tests/fixtures/grippers/slide_closed.dcl"));
    let arm = RobotId(0);
    let block = w.scenario().object_by_name("block").expect("block");
    assert_eq!(w.finger_names(arm), ["left_joint"]);
    let q = w.home(arm).0.clone();
    // A finger's box stands at (0, ±(v + 0.5 cm), 6 cm) with the left joint at v (the right
    // one mimics it): 3 cm open, 1 cm as `closed [1cm]` says for `top`, and 1.5 cm for
    // `pinch`, whose `width 3cm` is shared by the two sliding fingers.
    let at = |v: f64| [[0.0, -(v + 0.005), 0.06], [0.0, v + 0.005, 0.06]];
    assert_near(&slide_fingers(&w, &q, None), &at(0.03));
    for (grasp, v) in [(0, 0.01), (1, 0.015)] {
        let held = w.held(arm, block, grasp, &q);
        assert_eq!(w.finger_values(arm, held.posture), [v], "grasp {grasp}");
        assert_near(&slide_fingers(&w, &q, Some(&held)), &at(v));
    }
    assert_eq!(w.finger_values(arm, 0), [0.03]);
}

#[test]
fn finger_postures_that_cannot_be_are_located_errors() {
    let mut all = String::new();
    for f in ["finger_count", "finger_limit", "finger_unit", "no_fingers", "width_limit", "width_turns"] {
        let out = Command::new(env!("CARGO_BIN_EXE_declutter"))
            .args(["check", &format!("tests/fixtures/grippers/bad/{f}.dcl")])
            .env("NO_COLOR", "1")
            .output()
            .expect("declutter runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{f}: {stderr}");
        all.push_str(&format!("===== {f}\n{stderr}"));
    }
    insta::assert_snapshot!(all);
}

fn panda_scenario(name: &str) -> Option<PathBuf> {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots/panda");
    if !robots.is_dir() {
        println!("skipped: {} is absent", robots.display());
        return None;
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("grippers");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let link = dir.join("robots");
    // Tests run in parallel: another may have made the link since the look.
    if std::fs::symlink_metadata(&link).is_err() {
        match std::os::unix::fs::symlink(robots.canonicalize().expect("robots"), &link) {
            Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => panic!("symlink: {e}"),
            _ => {}
        }
    }
    let path = dir.join(format!("{name}.dcl"));
    std::fs::copy(format!("tests/fixtures/grippers/{name}.dcl"), &path).expect("scenario copied");
    Some(path)
}

#[test]
fn the_pandas_own_fingers_stand_open_and_a_can_between_them_is_taken() {
    let Some(path) = panda_scenario("panda_fingers") else { return };
    let w = world_of(&path);
    let arm = RobotId(0);
    // The URDF's finger joints slide 0 to 4 cm each, along ±y of `panda_hand`: open,
    // their links' origins are 8 cm apart, in any configuration.
    let links = w.fk_links(arm, &w.home(arm).0);
    let at = |name: &str| links.iter().find(|(n, _)| n == name).unwrap_or_else(|| panic!("no {name}")).1;
    let gap = (at("panda_leftfinger").translation.vector - at("panda_rightfinger").translation.vector).norm();
    assert!((gap - 0.08).abs() < 1e-9, "the fingers are {gap} m apart");
    // The can (6.6 cm across) stands between them at the grasp; the schedule verifies.
    let planned = declutter::driver::plan_verified(&w, &|_| {}).unwrap_or_else(|v| panic!("{v:#?}"));
    assert_eq!(planned.schedule.status, declutter::schedule::Status::Solved, "{:?}", planned.schedule.reason);
    assert!(declutter::verify::verify(&w, &planned.schedule).is_ok());
}

/// Compiles and verifies; returns the schedule.
fn verified(w: &World) -> Schedule {
    let planned = declutter::driver::plan_verified(w, &|_| {}).unwrap_or_else(|v| panic!("{v:#?}"));
    assert_eq!(planned.schedule.status, declutter::schedule::Status::Solved, "{:?}", planned.schedule.reason);
    assert!(declutter::verify::verify(w, &planned.schedule).is_ok());
    planned.schedule
}

/// Each grasp event's and release event's finger values, in order.
fn finger_events(s: &Schedule) -> Vec<(EventKind, Vec<f64>)> {
    s.events.iter().map(|e| (e.kind, e.fingers.clone())).collect()
}

#[test]
fn the_panda_carries_the_can_with_its_fingers_closed_as_closed_or_width_says() {
    for (name, closed) in [("panda_closed", 0.0), ("panda_width", 0.033)] {
        let Some(path) = panda_scenario(name) else { return };
        let w = world_of(&path);
        let arm = RobotId(0);
        let can = w.scenario().object_by_name("can").expect("can");
        let s = verified(&w);
        // The schedule tells the controller: one finger joint (the other mimics it), open
        // on the way in, closed at the grasp, open again at the release.
        assert_eq!(s.trajectories[0].finger_joints, ["panda_finger_joint1"]);
        assert_eq!(finger_events(&s), [(EventKind::Grasp, vec![closed]), (EventKind::Release, vec![0.04])], "{name}");
        // A schedule that leaves the fingers open on the can is not the scenario's.
        let mut open_grip = s.clone();
        open_grip.events[0].fingers = vec![0.04];
        let found = declutter::verify::verify(&w, &open_grip).expect_err("open fingers are refused");
        let said: Vec<String> = found.iter().map(|v| v.to_string()).collect();
        assert!(
            said.iter().any(|m| m.contains("sets the fingers to [0.0400], but the scenario says")),
            "{name}: {said:#?}"
        );
        // While carrying, each finger's shapes stand 4 cm − v further in along the hand's ±y
        // than open: the fingers' own offset, whatever the arm's configuration.
        let a = &s.actions[0];
        let q = a.retreat[0].clone();
        let grasp = a.grasp.as_deref().and_then(|g| w.scenario().object(can).grasp_index(g));
        let held = w.held(arm, can, grasp.expect("the grasp is the can's"), &q);
        let (mut open, mut shut) = (Vec::new(), Vec::new());
        w.pose_shapes(arm, &q, None, &mut open);
        let flange = w.pose_shapes(arm, &q, Some(&held), &mut shut);
        let bodies = w.bodies(arm);
        for (o, c) in open.iter().zip(&shut) {
            let moved = (c.pose.translation - o.pose.translation).length();
            let finger = bodies[o.body].name.ends_with("finger");
            let want = if finger { 0.04 - closed } else { 0.0 };
            assert!((moved - want).abs() < 1e-9, "{name}: `{}` moved {moved} m", bodies[o.body].name);
            if finger {
                // Inwards: towards the flange's z axis, along its y.
                let y = |p: &declutter::world::PosedShape| {
                    let t = p.pose.translation;
                    (flange.inverse() * nalgebra::Point3::new(t.x, t.y, t.z)).y
                };
                assert!(y(c).abs() < y(o).abs(), "{name}: `{}` moved out", bodies[o.body].name);
            }
        }
    }
}

#[test]
fn fingers_opened_less_fit_between_the_bottles_and_nothing_moves() {
    // examples/gripper.dcl opens its fingers 8.5 cm: both bottles beside the can must go
    // (tests/examples.rs). Opened to 7.2 cm they pass 4 mm from each bottle.
    let text = std::fs::read_to_string("examples/gripper.dcl").expect("the example");
    let narrower = text.replace("    closed [1cm]", "    open [3.6cm]\n    closed [1cm]");
    assert_ne!(text, narrower);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gripper_open");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    for sub in ["hands", "robots"] {
        if std::fs::symlink_metadata(dir.join(sub)).is_err() {
            let to = Path::new("examples").join(sub).canonicalize().expect("examples");
            std::os::unix::fs::symlink(to, dir.join(sub)).expect("symlink");
        }
    }
    let path = dir.join("gripper.dcl");
    std::fs::write(&path, narrower).expect("scenario written");
    let w = world_of(&path);
    let s = verified(&w);
    assert!(s.removed.is_empty(), "{:?}", s.removed);
    let events = finger_events(&s);
    let want = [(EventKind::Grasp, 0.033), (EventKind::Release, 0.036)];
    assert_eq!(events.len(), 2, "{events:?}");
    for ((kind, v), (k, x)) in events.iter().zip(want) {
        assert!(*kind == k && v.len() == 1 && (v[0] - x).abs() < 1e-12, "{events:?}");
    }
}

#[test]
fn check_names_the_finger_joints_and_their_postures() {
    let out = Command::new(env!("CARGO_BIN_EXE_declutter"))
        .args(["check", "examples/gripper.dcl"])
        .env("NO_COLOR", "1")
        .output()
        .expect("declutter runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(
        stderr
            .lines()
            .any(|l| l == "  arm: hand `pg` on `flange`; fingers `finger_joint` open [42.5mm], closed [10.0mm]"),
        "{stderr}"
    );
}

#[test]
fn fingers_closing_through_a_pin_are_refused_by_the_planner_and_the_verifier() {
    // The pin stands between the open fingers and the block; closing to 1 cm, a finger
    // sweeps through it. The planner gives the grasp up, naming the pin ...
    let fixture = Path::new("tests/fixtures/grippers/closing_pin.dcl");
    let out = Command::new(env!("CARGO_BIN_EXE_declutter"))
        .args(["compile", fixture.to_str().expect("utf-8"), "--out", "/dev/null"])
        .env("NO_COLOR", "1")
        .output()
        .expect("declutter runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("declutter::plan::ungraspable") && stderr.contains("fixed body `pin`"), "{stderr}");
    // ... and a schedule planned without the pin, replayed with it, fails at the grasp:
    // open on the way in and closed after it the fingers miss the pin; between, they hit it.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("closing_pin");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let here = std::fs::canonicalize("tests/fixtures/grippers").expect("fixtures");
    let text = std::fs::read_to_string(fixture)
        .expect("fixture")
        .replace("\"slide_hand.urdf\"", &format!("\"{}/slide_hand.urdf\"", here.display()))
        .replace(
            "\"../../../examples/robots/tx90.urdf\"",
            &format!("\"{}/../../../examples/robots/tx90.urdf\"", here.display()),
        );
    let (with_pin, without) = (dir.join("with_pin.dcl"), dir.join("without.dcl"));
    std::fs::write(&with_pin, &text).expect("written");
    let no_pin: String = text.lines().filter(|l| !l.starts_with("fixed pin")).map(|l| format!("{l}\n")).collect();
    assert_ne!(no_pin, text);
    std::fs::write(&without, no_pin).expect("written");
    let s = verified(&world_of(&without));
    let found = declutter::verify::verify(&world_of(&with_pin), &s).expect_err("the fingers hit the pin");
    let grasp = s.events.iter().find(|e| e.kind == EventKind::Grasp).expect("a grasp").t;
    let said: Vec<String> = found.iter().map(ToString::to_string).collect();
    assert_eq!(said, [format!("t = {grasp:.3} s: robot `arm` body `slide` touches fixed body `pin`")], "{said:#?}");
}

#[test]
fn an_object_the_closing_fingers_would_sweep_through_goes_first() {
    // As closing_pin.dcl, the pin an object: the fingers pass it open, and would hit it
    // closing, so it is removed before the block is taken.
    let w = world_of(Path::new("tests/fixtures/grippers/closing_object.dcl"));
    let s = verified(&w);
    assert_eq!(s.removed, ["pin"]);
    assert_eq!(s.actions.iter().map(|a| a.object.clone().unwrap_or_default()).collect::<Vec<_>>(), ["pin", "block"]);
}
