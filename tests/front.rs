//! The front end's fixtures: every `tests/fixtures/*/err/*.dcl` must fail with pinned
//! diagnostics, every `ok` fixture and every example must pass; plus the CLI's exit codes
//! and the pinned `resolve` output of the box-lid example.

use std::path::{Path, PathBuf};
use std::process::Command;

use declutter::diag::{render_all, FsLoader, RenderOptions, SourceMap};
use declutter::resolve::{self, Shape, Target};

/// The path relative to the crate root, so snapshots do not depend on the checkout.
fn relative(path: &Path) -> PathBuf {
    path.strip_prefix(env!("CARGO_MANIFEST_DIR")).map(Path::to_path_buf).unwrap_or_else(|_| path.to_path_buf())
}

fn check(path: &Path) -> (bool, String) {
    let mut sources = SourceMap::new();
    match resolve::check(path, &FsLoader, &mut sources) {
        Ok(_) => (true, String::new()),
        Err(errs) => {
            assert!(!errs.is_empty(), "an error result must carry at least one error");
            (false, render_all(&sources, &errs, RenderOptions::plain()))
        }
    }
}

fn snapshot(path: &Path, output: &str) -> String {
    let source = std::fs::read_to_string(path).unwrap_or_default();
    format!("----- SOURCE\n{source}----- OUTPUT\n{output}")
}

#[test]
fn err_fixtures_fail_with_pinned_diagnostics() {
    insta::glob!("fixtures/*/err/*.dcl", |path| {
        let rel = relative(path);
        let (ok, out) = check(&rel);
        assert!(!ok, "{} should fail", rel.display());
        insta::assert_snapshot!(snapshot(path, &out));
    });
}

#[test]
fn ok_fixtures_pass() {
    insta::glob!("fixtures/*/ok/*.dcl", |path| {
        let rel = relative(path);
        let (ok, out) = check(&rel);
        assert!(ok, "{} should pass, got:\n{out}", rel.display());
        let mut sources = SourceMap::new();
        let output = match resolve::resolve(&rel, &FsLoader, &mut sources) {
            Ok(s) => resolve::to_yaml(&s),
            Err(_) => "(a library: no target)\n".to_string(),
        };
        insta::assert_snapshot!(snapshot(path, &output));
    });
}

#[test]
fn there_are_enough_error_fixtures() {
    let n = ["tests/fixtures/syntax/err", "tests/fixtures/resolve/err"]
        .iter()
        .flat_map(|d| std::fs::read_dir(d).into_iter().flatten().flatten())
        .filter(|e| e.path().extension().is_some_and(|x| x == "dcl"))
        .count();
    assert!(n >= 25, "only {n} error fixtures");
}

#[test]
fn every_example_checks() {
    let mut n = 0;
    for e in std::fs::read_dir("examples").unwrap().flatten() {
        let path = e.path();
        if path.extension().is_some_and(|x| x == "dcl") {
            let (ok, out) = check(&path);
            assert!(ok, "{} should check, got:\n{out}", path.display());
            n += 1;
        }
    }
    assert!(n >= 2);
}

#[test]
fn box_lid_resolves_to_world_frame() {
    let mut sources = SourceMap::new();
    let s = resolve::resolve(Path::new("examples/box_lid.dcl"), &FsLoader, &mut sources).unwrap();
    assert_eq!(s.name.as_deref(), Some("box-lid"));
    assert_eq!(s.robots.len(), 2);
    let lid = s.object(s.object_by_name("lid").unwrap());
    let handle = &lid.body.parts[1];
    assert!(matches!(handle.shape, Shape::Box { .. }));
    let t = handle.pose_world_part.translation.vector;
    assert!((t - nalgebra::Vector3::new(0.55, 0.0, 0.22)).norm() < 1e-12, "handle at {t:?}");
    let can_id = s.object_by_name("can").unwrap();
    assert!(matches!(s.target, Target::Object { object, .. } if object == can_id));
    let can = s.object(can_id);
    let names: Vec<&str> = can.grasps.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["top#0", "top#1", "top#2", "top#3"]);
    for (k, g) in can.grasps.iter().enumerate() {
        let p = g.pose_world_tcp.translation.vector;
        assert!((p - nalgebra::Vector3::new(0.55, 0.0, 0.1075)).norm() < 1e-12);
        // Copy k is turned k quarter turns about the can's z; its TCP +z points down into the can.
        let z = g.pose_world_tcp.rotation * nalgebra::Vector3::z();
        assert!((z + nalgebra::Vector3::z()).norm() < 1e-9);
        let x = g.pose_world_tcp.rotation * nalgebra::Vector3::x();
        let angle = x.y.atan2(x.x);
        let want = std::f64::consts::FRAC_PI_2 * k as f64;
        assert!((angle - want).sin().abs() < 1e-9 && (angle - want).cos() > 0.0, "top#{k}: {angle}");
        assert!((g.approach - 0.08).abs() < 1e-12);
        assert_eq!(g.hands, None);
    }
    let left1 = lid.grasps.iter().find(|g| g.name == "left#1").unwrap();
    assert!((left1.pose_world_tcp.translation.vector - nalgebra::Vector3::new(0.59, 0.0, 0.23)).norm() < 1e-12);
    assert_eq!(left1.hands.as_ref().map(Vec::len), Some(2));
}

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_declutter")).args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn cli_check_exit_codes() {
    let (code, stdout, stderr) = run(&["check", "examples/box_lid.dcl"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.is_empty());
    assert!(stderr.starts_with("ok: box-lid"), "{stderr}");

    let (code, _, stderr) = run(&["--no-color", "check", "tests/fixtures/resolve/err/angle_as_length.dcl"]);
    assert_eq!(code, 1);
    assert!(stderr.contains("declutter::resolve::unit_mismatch"), "{stderr}");

    let (code, _, stderr) = run(&["check", "tests/fixtures/does_not_exist.dcl"]);
    assert_eq!(code, 1);
    assert!(stderr.contains("cannot read"), "{stderr}");
}

#[test]
fn cli_resolve_prints_yaml() {
    let (code, stdout, stderr) = run(&["resolve", "examples/box_lid.dcl"]);
    assert_eq!(code, 0, "{stderr}");
    // It is valid YAML with the handle in the world frame.
    let doc: serde_json::Value = serde_saphyr::from_str(&stdout).unwrap();
    let handle = &doc["objects"][1]["parts"][1];
    assert_eq!(handle["box"]["size"], serde_json::json!([0.12, 0.02, 0.02]));
    assert_eq!(handle["pose"]["xyz"], serde_json::json!([0.55, 0, 0.22]));
    let grasps: Vec<&str> =
        doc["objects"][0]["grasps"].as_array().unwrap().iter().map(|g| g["name"].as_str().unwrap()).collect();
    assert_eq!(grasps, ["top#0", "top#1", "top#2", "top#3"]);
    insta::assert_snapshot!("box_lid_resolved", stdout);

    let (code, stdout, _) = run(&["resolve", "examples/cell.dcl"]);
    assert_eq!(code, 1, "a library has no target");
    assert!(stdout.is_empty());
}

#[test]
fn help_has_examples() {
    for cmd in ["check", "resolve"] {
        let (code, stdout, _) = run(&[cmd, "--help"]);
        assert_eq!(code, 0);
        assert!(stdout.contains(&format!("declutter {cmd} examples/box_lid.dcl")), "{stdout}");
    }
}

#[test]
fn cli_every_err_fixture_exits_1_with_its_code() {
    let mut seen = 0;
    for dir in ["tests/fixtures/syntax/err", "tests/fixtures/resolve/err"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
        for f in files.iter().filter(|f| f.extension().is_some_and(|e| e == "dcl")) {
            let mut sources = SourceMap::new();
            let errs = resolve::check(f, &FsLoader, &mut sources).expect_err("an err fixture fails");
            let code_of_first = errs[0].code_str();
            let (code, stdout, stderr) = run(&["--no-color", "check", f.to_str().unwrap()]);
            assert_eq!(code, 1, "{}: exit {code}\n{stderr}", f.display());
            assert!(stdout.is_empty(), "{}: nothing on stdout", f.display());
            assert!(stderr.contains(&code_of_first), "{}: {code_of_first} not in\n{stderr}", f.display());
            seen += 1;
        }
    }
    assert!(seen >= 25, "only {seen} error fixtures");
}

/// The `ok` fixtures pass the real `check`, which also loads URDFs and meshes and checks
/// the robots' configurations (everything.dcl once named a link the URDF lacks).
#[test]
fn cli_every_ok_fixture_checks() {
    for dir in ["tests/fixtures/syntax/ok", "tests/fixtures/resolve/ok"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
        for f in files.iter().filter(|f| f.extension().is_some_and(|e| e == "dcl")) {
            let (code, _, stderr) = run(&["--no-color", "check", f.to_str().unwrap()]);
            assert_eq!(code, 0, "{}: exit {code}\n{stderr}", f.display());
        }
    }
}

#[test]
fn quaternion_and_roll_pitch_yaw_resolve_identically() {
    let yaml = |p: &str| {
        let mut sources = SourceMap::new();
        let s = resolve::resolve(Path::new(p), &FsLoader, &mut sources).unwrap();
        resolve::to_yaml(&s)
    };
    let quat = yaml("tests/fixtures/resolve/ok/quat_pose.dcl");
    let rpy = yaml("tests/fixtures/resolve/ok/rpy_pose.dcl");
    assert!(quat.contains("rpy: [1.570796, 0, 0]"), "{quat}");
    assert_eq!(quat, rpy);
}

#[test]
fn bare_length_beyond_ten_metres_warns() {
    let path = Path::new("tests/fixtures/resolve/ok/bare_length.dcl");
    let mut sources = SourceMap::new();
    let summary = resolve::check(path, &FsLoader, &mut sources).unwrap();
    let codes: Vec<String> = summary.warnings.iter().map(|w| w.code_str()).collect();
    assert_eq!(codes, ["declutter::resolve::large_bare_length"]);
    insta::assert_snapshot!(render_all(&sources, &summary.warnings, RenderOptions::plain()));
    // `compile` and `resolve` print it too, and still succeed.
    let (code, _, stderr) = run(&["--no-color", "resolve", "tests/fixtures/resolve/ok/bare_length.dcl"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("did you mean `40mm` or `40cm`?"), "{stderr}");
}
