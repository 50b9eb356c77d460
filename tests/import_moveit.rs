//! `declutter import moveit` on scene files written in MoveIt's YAML format: the written
//! scenario resolves to the scene's poses (to 1e-6), with pinned warnings; bad input is
//! a located error, exit 1, and nothing written.

use std::path::{Path, PathBuf};
use std::process::Command;

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::{self, Shape, Target};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("import_moveit").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(args: &[&str], dir: &Path) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_declutter")).arg("--no-color").args(args).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).replace(&dir.display().to_string(), "OUT");
    (out.status.code().unwrap_or(-1), stderr)
}

const SCENE: &str = "tests/fixtures/moveit/scene.yaml";
const REQUEST: &str = "tests/fixtures/moveit/request.yaml";
const CELL: &str = "tests/fixtures/mini.dcl";

fn pose(xyz: [f64; 3], xyzw: [f64; 4]) -> Isometry3<f64> {
    let q = nalgebra::Quaternion::new(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
    Isometry3::from_parts(Translation3::new(xyz[0], xyz[1], xyz[2]), UnitQuaternion::from_quaternion(q))
}

fn assert_pose(found: &Isometry3<f64>, want: &Isometry3<f64>, what: &str) {
    let dt = (found.translation.vector - want.translation.vector).norm();
    let da = found.rotation.angle_to(&want.rotation);
    assert!(dt < 1e-6 && da < 1e-6, "{what}: {found:?} vs {want:?} ({dt} m, {da} rad)");
}

#[test]
fn scene_and_request_become_a_scenario_with_the_scenes_poses() {
    let dir = scratch("full");
    let out = dir.join("kitchen.dcl");
    let (code, stderr) = run(
        &[
            "import",
            "moveit",
            SCENE,
            "--request",
            REQUEST,
            "--cell",
            CELL,
            "--removable",
            "^can",
            "-o",
            out.to_str().unwrap(),
        ],
        &dir,
    );
    assert_eq!(code, 0, "{stderr}");
    insta::assert_snapshot!(stderr);

    let mut sources = SourceMap::new();
    let scn = resolve::resolve(&out, &FsLoader, &mut sources).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(scn.name.as_deref(), Some("kitchen"));
    let fixed = |n: &str| scn.fixed.iter().find(|b| b.name == n).unwrap_or_else(|| panic!("no fixed `{n}`"));

    // A rotated box: 45° about z, as the scene's quaternion says.
    let b = fixed("rotated_box");
    assert_pose(
        &b.parts[0].pose_world_part,
        &pose([0.7, 0.2, 0.1], [0.0, 0.0, 0.3826834323650898, 0.9238795325112867]),
        "box",
    );
    assert_eq!(b.parts[0].shape, Shape::Box { size: Vector3::new(0.1, 0.2, 0.2) });

    // MoveIt's cylinder is [height, radius].
    let can = &scn.objects[scn.object_by_name("can_1").unwrap().index()];
    assert_eq!(can.body.parts[0].shape, Shape::Cylinder { radius: 0.033, length: 0.115 });
    assert_pose(&can.body.parts[0].pose_world_part, &pose([0.55, -0.1, 0.0575], [0.0, 0.0, 0.0, 1.0]), "can");

    // An object pose composed with each primitive's: the sphere sits at
    // (0.5, -0.35, 0.05) + Rz(90°)·(0.1, 0, 0.08) = (0.5, -0.25, 0.13), turned Rz(90°)·Rx(90°).
    let caddy = fixed("caddy");
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert_pose(&caddy.parts[0].pose_world_part, &pose([0.5, -0.35, 0.05], [0.0, 0.0, h, h]), "caddy box");
    let rz_rx = UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2)
        * UnitQuaternion::from_euler_angles(std::f64::consts::FRAC_PI_2, 0.0, 0.0);
    let want = Isometry3::from_parts(Translation3::new(0.5, -0.25, 0.13), rz_rx);
    assert_pose(&caddy.parts[1].pose_world_part, &want, "caddy sphere");
    assert_eq!(caddy.parts[1].shape, Shape::Sphere { radius: 0.03 });

    // The mesh is written beside the scenario, in the object's frame turned 180° about z.
    let wedge = fixed("wedge");
    assert!(matches!(&wedge.parts[0].shape, Shape::Mesh { file, .. } if file.path.ends_with("kitchen_wedge.stl")));
    assert_pose(&wedge.parts[0].pose_world_part, &pose([0.45, 0.35, 0.0], [0.0, 0.0, 1.0, 0.0]), "wedge");
    let stl = std::fs::read(dir.join("kitchen_wedge.stl")).unwrap();
    assert_eq!(stl.len(), 84 + 4 * 50, "a binary STL of four triangles");

    // The request's start state is the robot's home, its joint goal the target; the
    // allowed collision matrix's pair of two arm links is an `allow_contact`.
    let arm = &scn.robots[0];
    assert_eq!(arm.home.values, [0.0, -0.35, 1.92, 0.0, 1.0, 0.0]);
    assert!(arm.allow_contact.iter().any(|p| p.a == "link_3" && p.b == "link_5"));
    match &scn.target {
        Target::Config { q, .. } => assert_eq!(q.values, [-0.5, 0.3, 1.2, 0.0, 1.4, 0.3]),
        t => panic!("target {t:?}"),
    }
    // MoveIt's scaling factors (velocity 0.5, acceleration 0.25): `speed` is the smaller,
    // with a warning (pinned above) that one factor scales both.
    assert_eq!(scn.planner.speed, 0.25);
    // The written scenario passes the full check too (URDFs and meshes load).
    let (code, stderr) = run(&["check", out.to_str().unwrap()], &dir);
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn scene_alone_is_a_library_of_bodies() {
    let dir = scratch("alone");
    let out = dir.join("scene.dcl");
    let (code, stderr) = run(&["import", "moveit", SCENE, "-o", out.to_str().unwrap()], &dir);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("allows `link_3` and `link_5` to touch, but no `--cell`"), "{stderr}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(!text.contains("robot ") && !text.contains("target "), "{text}");
    assert_eq!(text.matches("\nfixed ").count(), 4, "{text}");
}

#[test]
fn bad_input_is_located_and_nothing_is_written() {
    let cases: [(&str, &[&str]); 6] = [
        ("bad_yaml", &["tests/fixtures/moveit/bad_yaml.yaml"]),
        ("bad_primitive", &["tests/fixtures/moveit/bad_primitive.yaml"]),
        ("bad_mesh", &["tests/fixtures/moveit/bad_mesh.yaml"]),
        ("bad_goal", &[SCENE, "--cell", CELL, "--request", "tests/fixtures/moveit/bad_goal.yaml"]),
        ("request_without_cell", &[SCENE, "--request", REQUEST]),
        ("bad_regex", &[SCENE, "--removable", "can("]),
    ];
    let mut all = String::new();
    for (name, args) in cases {
        let dir = scratch(name);
        let out = dir.join("out.dcl");
        let mut full = vec!["import", "moveit"];
        full.extend_from_slice(args);
        full.extend(["-o", out.to_str().unwrap()]);
        let (code, stderr) = run(&full, &dir);
        assert_eq!(code, 1, "{name}: {stderr}");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "{name}: something was written");
        all.push_str(&format!("===== {name}\n{stderr}"));
    }
    insta::assert_snapshot!(all);
}
