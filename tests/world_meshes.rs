//! Mesh files and where they are found: `package://` search (folder ancestors, extra
//! directories, the environment variable, relative invocation), and COLLADA units.

mod world_support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use declutter::diag::MemLoader;
use declutter::resolve::{Object, ObjectId, RobotId, Shape};
use declutter::world::{build, Check, CheckCtx, MeshMode, WorldError, WorldOptions};
use world_support::*;

/// An ASCII STL tetrahedron, 0.1 m on a side.
const STL: &str =
    "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\nvertex 0 0.1 0\nendloop\nendfacet\n\
facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 0.1 0\nvertex 0 0 0.1\nendloop\nendfacet\n\
facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 0 0.1\nvertex 0.1 0 0\nendloop\nendfacet\nendsolid t\n";

/// A one-joint arm whose link carries the mesh at `uri`.
fn arm_urdf(uri: &str) -> String {
    format!(
        r#"<robot name="r"><link name="base"/><link name="l1"><collision><geometry><mesh filename="{uri}"/></geometry></collision></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#
    )
}

/// A fresh directory under the system's temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let p = std::env::temp_dir().join(format!("declutter-world-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).expect("temp dir");
        TempDir(p)
    }
    fn write(&self, rel: &str, text: &str) -> PathBuf {
        let p = self.0.join(rel);
        std::fs::create_dir_all(p.parent().expect("parent")).expect("mkdir");
        std::fs::write(&p, text).expect("write");
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A scenario for the one-joint arm at `urdf` (as written in the file).
fn cell(urdf: &str) -> String {
    format!("robot arm {{\n    urdf \"{urdf}\"\n    home [0]\n}}\ntarget arm at [0]\n")
}

/// `declutter check FILE` run in `dir`, with `env` set and the package variable cleared otherwise.
fn check_in(dir: &Path, args: &[&str], env: Option<&Path>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_declutter"));
    cmd.current_dir(dir).arg("check").args(args).env_remove("DECLUTTER_PACKAGE_PATH").env("NO_COLOR", "1");
    if let Some(p) = env {
        cmd.env("DECLUTTER_PACKAGE_PATH", p);
    }
    cmd.output().expect("run declutter")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn package_uri_found_above_the_cwd_when_the_scenario_path_is_relative() {
    // ws/src/mypkg/{cell.dcl, urdf/arm.urdf, meshes/l1.stl}, run from ws/src/mypkg.
    let t = TempDir::new("relative");
    let pkg = t.0.join("ws/src/mypkg");
    t.write("ws/src/mypkg/urdf/arm.urdf", &arm_urdf("package://mypkg/meshes/l1.stl"));
    t.write("ws/src/mypkg/meshes/l1.stl", STL);
    t.write("ws/src/mypkg/cell.dcl", &cell("urdf/arm.urdf"));
    let out = check_in(&pkg, &["cell.dcl"], None);
    assert!(out.status.success(), "{}", stderr(&out));
    // And from a subfolder, with `..` in the scenario path.
    t.write("ws/src/mypkg/scenarios/cell.dcl", &cell("../urdf/arm.urdf"));
    let out = check_in(&pkg.join("scenarios"), &["cell.dcl"], None);
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn package_uri_found_through_package_path_and_the_variable() {
    // The URDF is not inside its package: only the extra directory finds the mesh.
    let t = TempDir::new("extra");
    t.write("cell/arm.urdf", &arm_urdf("package://mypkg/meshes/l1.stl"));
    t.write("cell/cell.dcl", &cell("arm.urdf"));
    t.write("share/mypkg/meshes/l1.stl", STL);
    let share = t.0.join("share");
    let dir = t.0.join("cell");

    let out = check_in(&dir, &["cell.dcl"], None);
    assert!(!out.status.success(), "found without a package path");
    let err = stderr(&out);
    assert!(err.contains("declutter::world::mesh_missing") && err.contains("looked at"), "{err}");
    // The walk went up from the absolute folder to the filesystem root (the message
    // is wrapped, so only the last candidate is matched whole).
    assert!(err.contains(" /mypkg/meshes/l1.stl)"), "{err}");

    let share_s = share.display().to_string();
    let out = check_in(&dir, &["--package-path", &share_s, "cell.dcl"], None);
    assert!(out.status.success(), "--package-path: {}", stderr(&out));
    let out = check_in(&dir, &["cell.dcl"], Some(&share));
    assert!(out.status.success(), "DECLUTTER_PACKAGE_PATH: {}", stderr(&out));
    // The variable holds a list: a useless first entry does not hide the second.
    let list = std::env::join_paths([t.0.join("nowhere"), share.clone()]).expect("join");
    let out = check_in(&dir, &["cell.dcl"], Some(Path::new(&list)));
    assert!(out.status.success(), "DECLUTTER_PACKAGE_PATH list: {}", stderr(&out));
}

#[test]
fn package_path_of_the_world_api() {
    let loader = MemLoader::new()
        .with("/cell/arm.urdf", arm_urdf("package://mypkg/meshes/l1.stl"))
        .with("/opt/share/mypkg/meshes/l1.stl", STL);
    let scn = scenario(vec![robot("arm", "/cell/arm.urdf", vec![0.0], None)], vec![], vec![], vec![]);
    let errs = build(&scn, &WorldOptions::default(), &loader).expect_err("not found without a package path");
    assert!(matches!(&errs[0], WorldError::MeshMissing { tried, .. } if tried.contains("/cell/mypkg/meshes/l1.stl")));
    let opts = WorldOptions { package_path: vec!["/opt/share".into()], ..WorldOptions::default() };
    let w = build(&scn, &opts, &loader).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(w.dof(RobotId(0)), 1);
}

#[test]
fn missing_mesh_never_reports_an_empty_list() {
    // A relative URDF folder used to be walked as is; an empty one looked nowhere.
    let loader = MemLoader::new().with("arm.urdf", arm_urdf("package://mypkg/meshes/l1.stl"));
    let scn = scenario(vec![robot("arm", "arm.urdf", vec![0.0], None)], vec![], vec![], vec![]);
    let errs = build(&scn, &WorldOptions::default(), &loader).expect_err("missing");
    let msg = errs[0].to_string();
    assert!(msg.contains("(looked at /") && !msg.contains("looked at )"), "{msg}");
}

/// A tetrahedron 100 units on a side in millimetres (`<unit meter="0.001">`), its node
/// moved 100 units along x: in metres, x spans [0.1, 0.2] only if the unit scales the
/// node's translation as well as the vertices.
fn dae_mm() -> String {
    dae_tetrahedron("0.001", "100", "100")
}

#[test]
fn mesh_loader_leaves_collada_node_translations_unscaled() {
    // Why `shapes::collada_unit` exists: mesh-loader 0.1 applies `<unit>` to the
    // vertices but not to the node's translation. If this starts failing, mesh-loader
    // was fixed; the workaround stays correct (it hands mesh-loader a unit of 1).
    let scene = mesh_loader::Loader::default()
        .merge_meshes(true)
        .load_from_slice(dae_mm().as_bytes(), "tet.dae")
        .expect("loads");
    let xs: Vec<f32> = scene.meshes[0].vertices.iter().map(|v| v[0]).collect();
    let (lo, hi) = xs.iter().fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!((lo - 100.0).abs() < 1e-3 && (hi - 100.1).abs() < 1e-3, "x in [{lo}, {hi}]");
}

#[test]
fn collada_unit_applies_to_node_translations() {
    // Probes inside the tetrahedron as it should be placed (x in [0.1, 0.2] m), and
    // where mesh-loader alone would put it (x near 100 m).
    let probe = |name: &str, x: f64| Object {
        body: body(name, Shape::Sphere { radius: 0.005 }, at(x, 0.02, 0.02)),
        grasps: vec![],
    };
    let loader = MemLoader::new().with("/m/arm.urdf", arm_urdf("tet.dae")).with("/m/tet.dae", dae_mm());
    let scn = scenario(
        vec![robot("arm", "/m/arm.urdf", vec![0.0], None)],
        vec![],
        vec![],
        vec![probe("right", 0.12), probe("wrong", 100.02)],
    );
    let opts = WorldOptions { self_collision_samples: 0, ..WorldOptions::default() };
    let w = build(&scn, &opts, &loader).unwrap_or_else(|e| panic!("{e:?}"));
    let Check::Touches(s) = w.check(RobotId(0), &[0.0], &CheckCtx::new()) else { panic!("blocked") };
    assert!(s.contains(ObjectId(0)) && !s.contains(ObjectId(1)), "{s:?}");
}

/// An ASCII STL of `facets`, each three vertices.
fn stl(facets: &[[[f64; 3]; 3]]) -> String {
    let mut s = String::from("solid t\n");
    for f in facets {
        s.push_str("facet normal 0 0 1\nouter loop\n");
        for v in f {
            s.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        s.push_str("endloop\nendfacet\n");
    }
    s + "endsolid t\n"
}

fn mesh_errors(mesh: &str, mode: MeshMode) -> Vec<String> {
    let loader = MemLoader::new().with("/m/arm.urdf", arm_urdf("m.stl")).with("/m/m.stl", mesh);
    let scn = scenario(vec![robot("arm", "/m/arm.urdf", vec![0.0], None)], vec![], vec![], vec![]);
    let opts = WorldOptions { mesh_mode: mode, self_collision_samples: 0, ..WorldOptions::default() };
    match build(&scn, &opts, &loader) {
        Ok(_) => Vec::new(),
        Err(e) => e.iter().map(ToString::to_string).collect(),
    }
}

#[test]
fn a_mesh_on_one_line_is_refused_and_a_flat_sheet_loads_in_both_modes() {
    // Two triangles along the x axis: four vertices, no area.
    let line = stl(&[
        [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.1, 0.0, 0.0]],
    ]);
    let no_area = "mesh `m.stl` of link `l1` cannot be loaded: its triangles have no area (every vertex on one line)";
    assert_eq!(mesh_errors(&line, MeshMode::ConvexHull), [no_area]);
    assert_eq!(mesh_errors(&line, MeshMode::TriMesh), [no_area]);
    // A 10 cm square sheet in the plane z = 0: a thin wall, in both modes.
    let sheet = stl(&[
        [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.1, 0.1, 0.0]],
        [[0.0, 0.0, 0.0], [0.1, 0.1, 0.0], [0.0, 0.1, 0.0]],
    ]);
    assert_eq!(mesh_errors(&sheet, MeshMode::TriMesh), Vec::<String>::new());
    assert_eq!(mesh_errors(&sheet, MeshMode::ConvexHull), Vec::<String>::new());
    assert_eq!(mesh_errors(STL, MeshMode::ConvexHull), Vec::<String>::new());
}

#[test]
fn a_mesh_scale_stretches_the_shape_per_axis() {
    // The tetrahedron spans [0, 0.1] on each axis; scaled by (2, 1, 1) it reaches x = 0.2.
    // A small sphere at x = 0.15 (y = z = 0.01) is inside only if the scale applied.
    let probe = Object { body: body("probe", Shape::Sphere { radius: 0.002 }, at(0.15, 0.01, 0.01)), grasps: vec![] };
    let touches = |scale: &str| {
        let uri = format!("tet.stl\" scale=\"{scale}");
        let loader = MemLoader::new().with("/m/arm.urdf", arm_urdf(&uri)).with("/m/tet.stl", STL);
        let scn = scenario(vec![robot("arm", "/m/arm.urdf", vec![0.0], None)], vec![], vec![], vec![probe.clone()]);
        let opts = WorldOptions { self_collision_samples: 0, ..WorldOptions::default() };
        let w = build(&scn, &opts, &loader).unwrap_or_else(|e| panic!("{e:?}"));
        let Check::Touches(s) = w.check(RobotId(0), &[0.0], &CheckCtx::new()) else { panic!("blocked") };
        s.contains(ObjectId(0))
    };
    assert!(!touches("1 1 1"));
    assert!(touches("2 1 1"));
    assert!(!touches("1 2 2"), "y and z stretched, x not: the probe is still outside");
}
