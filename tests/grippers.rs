//! Grippers stand open: a finger joint (a movable joint hanging from the links rigid with
//! the flange in the arm's URDF, or any movable joint of a hand's URDF) is held at its
//! upper limit, so that an object fits between the fingertips. Checked against positions
//! computed by hand from the URDFs, and on the Panda with its own fingers from
//! `../shared/robots` (skipped, saying why, when that directory is absent).

use std::path::{Path, PathBuf};

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::RobotId;
use declutter::world::{self, Drawable, World, WorldOptions};

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

fn panda_scenario() -> Option<PathBuf> {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots/panda");
    if !robots.is_dir() {
        println!("skipped: {} is absent", robots.display());
        return None;
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("grippers");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let link = dir.join("robots");
    if std::fs::symlink_metadata(&link).is_err() {
        std::os::unix::fs::symlink(robots.canonicalize().expect("robots"), &link).expect("symlink");
    }
    let path = dir.join("panda_fingers.dcl");
    std::fs::copy("tests/fixtures/grippers/panda_fingers.dcl", &path).expect("scenario copied");
    Some(path)
}

#[test]
fn the_pandas_own_fingers_stand_open_and_a_can_between_them_is_taken() {
    let Some(path) = panda_scenario() else { return };
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
