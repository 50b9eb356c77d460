//! A robot package loads as its authors meant it: its own collision filters (Drake's
//! filter groups in the URDF, MoveIt's SRDF), its tool frame, and a located error when
//! an SRDF does not fit the URDF. The `../shared/robots` cases are skipped, with the
//! reason printed, when that directory is absent.

mod world_support;

use std::path::Path;
use std::process::Command;

use declutter::diag::{FsLoader, SourceMap};
use declutter::world::{self, load_kinematics, WorldOptions};
use world_support::*;

fn run(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_declutter")).arg("--no-color").args(args).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// A one-robot scenario of `urdf` (and `srdf`) at the middle of every joint's range.
fn mid_range_scenario(name: &str, urdf: &Path, srdf: Option<&Path>) -> std::path::PathBuf {
    let k = load_kinematics(&file(urdf, sp(0, 1)), None, &WorldOptions::default(), &FsLoader)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let home: Vec<String> = k.limits().iter().map(|(lo, hi)| format!("{}rad", (lo + hi) / 2.0)).collect();
    let home = home.join(", ");
    let srdf = srdf.map_or(String::new(), |s| format!("    srdf \"{}\"\n", s.display()));
    let text =
        format!("robot arm {{\n    urdf \"{}\"\n{srdf}    home [{home}]\n}}\ntarget arm at [{home}]\n", urdf.display());
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("robot_packages");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.dcl"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn every_shared_robot_checks_at_mid_range_with_its_own_filters() {
    let Some(root) = shared_robots() else { return };
    let erd = "panda/example-robot-data/robots/panda_description";
    // (name, URDF, SRDF, the link the hand is bolted to without `flange`)
    let cases = [
        ("tx90", "tx90/tx90.urdf", None, "link_6"),
        ("panda", &format!("{erd}/urdf/panda.urdf")[..], Some(&format!("{erd}/srdf/panda.srdf")[..]), "panda_hand_tcp"),
        // This file has no TCP link: the deepest link is a finger, so a user names the flange.
        ("panda_spheres", "panda/vamp/panda_spherized.urdf", Some("panda/vamp/panda.srdf"), "panda_leftfinger"),
        ("ur5", "ur5/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf", None, "tool0"),
        ("ur5_spheres", "ur5/vamp/ur5_spherized.urdf", Some("ur5/vamp/ur5.srdf"), "tool0"),
        (
            "iiwa_primitive",
            "iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf",
            None,
            "iiwa_link_ee_kuka",
        ),
        (
            "iiwa_polytope",
            "iiwa/drake_models/iiwa_description/urdf/iiwa14_polytope_collision.urdf",
            None,
            "iiwa_link_ee_kuka",
        ),
        (
            "iiwa_spheres",
            "iiwa/drake_models/iiwa_description/urdf/iiwa14_spheres_dense_collision.urdf",
            None,
            "iiwa_link_ee_kuka",
        ),
    ];
    for (name, urdf, srdf, tool) in cases {
        let scn = mid_range_scenario(name, &root.join(urdf), srdf.map(|s| root.join(s)).as_deref());
        let (code, stderr) = run(&["check", scn.to_str().unwrap()]);
        assert_eq!(code, 0, "{name}:\n{stderr}");
        assert!(stderr.contains(&format!("  arm: no hand; tool frame `{tool}`")), "{name}:\n{stderr}");
    }
}

#[test]
fn drakes_filter_group_takes_the_wrist_pair_out_of_the_self_checks() {
    let Some(root) = shared_robots() else { return };
    let urdf = root.join("iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf");
    let scn_path = mid_range_scenario("iiwa_pairs", &urdf, None);
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(&scn_path, &FsLoader, &mut sources).unwrap();
    let opts = WorldOptions { self_collision_samples: 0, ..WorldOptions::default() };
    let w = world::build(&scn, &opts, &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    let pairs = w.self_collision_pairs(declutter::resolve::RobotId(0));
    let has = |a: &str, b: &str| pairs.iter().any(|&(x, y)| (x == a && y == b) || (x == b && y == a));
    // The file's `iiwa_wrist` group (links 5, 6, 7) ignores itself; the others are checked.
    assert!(!has("iiwa_link_5", "iiwa_link_7"), "{pairs:?}");
    assert!(has("iiwa_link_3", "iiwa_link_7"), "{pairs:?}");
}

#[test]
fn drakes_acceleration_limits_time_the_iiwa_and_the_planners_default_the_rest() {
    let Some(root) = shared_robots() else { return };
    let urdf = root.join("iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf");
    let scn_path = mid_range_scenario("iiwa_accelerations", &urdf, None);
    let text = std::fs::read_to_string(&scn_path).unwrap() + "planner {\n    speed 0.5\n}\n";
    std::fs::write(&scn_path, text).unwrap();
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(&scn_path, &FsLoader, &mut sources).unwrap();
    let opts = WorldOptions { self_collision_samples: 0, ..WorldOptions::default() };
    let w = world::build(&scn, &opts, &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    let arm = declutter::resolve::RobotId(0);
    // The file's `<limit drake:acceleration=...>`, joints 1 to 7.
    let file = [8.57, 8.57, 8.74, 11.36, 12.23, 15.72, 15.72];
    assert_eq!(w.acceleration_limits(arm), file);
    // Timing keeps them, scaled by `speed` like the velocities.
    let t = declutter::timing::RobotTiming::of(&w, arm);
    assert_eq!(t.limits.acceleration, file.map(|a| a * 0.5));
    assert_eq!(t.limits.velocity[0], 1.4835298641951802 * 0.5);
    // A URDF without them (the TX-90) gets the planner's `acceleration`, 3 rad/s² by default.
    let scn_path = mid_range_scenario("tx90_accelerations", &root.join("tx90/tx90.urdf"), None);
    let scn = declutter::resolve::resolve(&scn_path, &FsLoader, &mut sources).unwrap();
    let w = world::build(&scn, &opts, &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(w.acceleration_limits(arm), [3.0; 6]);
}

#[test]
fn what_check_can_know_before_planning_is_a_located_error() {
    let mut all = String::new();
    for f in ["srdf_unknown_link", "srdf_malformed", "target_collides", "objects_overlap"] {
        let (code, stderr) = run(&["check", &format!("tests/fixtures/packages/{f}.dcl")]);
        assert_eq!(code, 1, "{f}: {stderr}");
        all.push_str(&format!("===== {f}\n{stderr}"));
    }
    insta::assert_snapshot!(all);
    let (code, stderr) = run(&["check", "tests/fixtures/packages/srdf_ok.dcl"]);
    assert_eq!(code, 0, "{stderr}");
}

/// The Panda and the iiwa (7 joints, a spherical shoulder, axes 5 and 6 meeting) solve
/// a pose in closed form at sampled values of joint 7: every answer in limits and on the
/// pose, joint 7 at home's value or one of 12 spread over its range (the numeric
/// solver's would fall anywhere), distinct postures first; and no pose the numeric
/// solver reaches is left without an answer.
#[test]
fn seven_joint_arms_solve_a_pose_in_closed_form_wherever_the_numeric_solver_does() {
    use rand::{RngExt, SeedableRng};
    let Some(root) = shared_robots() else { return };
    let erd = "panda/example-robot-data/robots/panda_description";
    let cases = [
        ("panda_ik", format!("{erd}/urdf/panda.urdf")),
        ("iiwa_ik", "iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf".to_string()),
    ];
    for (name, urdf) in cases {
        let scn_path = mid_range_scenario(name, &root.join(&urdf), None);
        let mut sources = SourceMap::new();
        let scn = declutter::resolve::resolve(&scn_path, &FsLoader, &mut sources).unwrap();
        let base = WorldOptions { self_collision_samples: 0, ..WorldOptions::default() };
        let w = world::build(&scn, &base, &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
        let numeric = WorldOptions { closed_form_ik: false, ..base };
        let wn = world::build(&scn, &numeric, &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
        let arm = declutter::resolve::RobotId(0);
        let lim = w.limits(arm).to_vec();
        let (lo7, hi7) = lim[6];
        let home7 = w.home(arm)[6].clamp(lo7, hi7);
        let sampled = |v: f64| {
            (v - home7).abs() < 1e-12
                || (0..12).any(|i| (v - (lo7 + (hi7 - lo7) * (i as f64 + 0.5) / 12.0)).abs() < 1e-12)
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let (mut reached, mut both) = (0, 0);
        for i in 0..40 {
            let q: Vec<f64> = lim.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
            let pose = w.fk_tcp(arm, &q);
            let closed = w.ik(arm, &pose, 1, 6);
            for s in &closed {
                assert!(s.iter().zip(&lim).all(|(v, (lo, hi))| v >= lo && v <= hi), "{name} #{i}: {s:?} out of limits");
                let got = w.fk_tcp(arm, s);
                let gap = (got.translation.vector - pose.translation.vector)
                    .norm()
                    .max(got.rotation.angle_to(&pose.rotation));
                assert!(gap < 1e-9, "{name} #{i}: {s:?} misses the pose by {gap}");
                assert!(sampled(s[6]), "{name} #{i}: joint 7 at {} is not a sampled value", s[6]);
            }
            let far = |a: &[f64], b: &[f64]| a.iter().zip(b).any(|(x, y)| (x - y).abs() > 0.5);
            let postures =
                closed.iter().take_while(|s| closed.iter().take_while(|t| t != s).all(|t| far(t, s))).count();
            assert!(postures >= closed.len().min(2), "{name} #{i}: the first answers are one posture: {closed:?}");
            // Asked for every solution: all of those six, and more.
            let all = w.ik(arm, &pose, 1, usize::MAX);
            assert!(closed.iter().all(|s| all.contains(s)) && all.len() >= closed.len(), "{name} #{i}");
            reached += !closed.is_empty() as usize;
            if !wn.ik(arm, &pose, 1, 6).is_empty() {
                both += 1;
                assert!(
                    !closed.is_empty(),
                    "{name} #{i}: the numeric solver reaches {q:?}'s pose, the closed form does not"
                );
            }
        }
        // The sampled configurations' own poses: most are reached at some sampled joint 7.
        assert!(reached >= 30 && both >= 30, "{name}: closed form {reached}, numeric {both} of 40");
        eprintln!("{name}: closed form reached {reached} of 40 poses, the numeric solver {both}");
    }
}
