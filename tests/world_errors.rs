//! Errors building a world carry the span of the scenario line at fault.

mod world_support;

use declutter::diag::{render_all, FileId, Located, MemLoader, RenderOptions, SourceMap, Span};
use declutter::resolve::{JointValues, RobotId, Scenario, Target};
use declutter::world::{build, WorldError, WorldOptions};
use miette::Diagnostic;
use world_support::*;

/// A scenario text the spans point into (the parser is not involved).
const SRC: &str = r#"robot arm {
  urdf "arm.urdf"
  home [0, 0, 0]
  drop [0, 0, 0, 0]
}
hand h { urdf "hand.urdf" }
fixed post: box 0.1 0.1 0.1 at (0.2, 0, 0)
"#;

fn span_of(needle: &str) -> Span {
    let start = SRC.find(needle).unwrap_or_else(|| panic!("{needle} not in SRC"));
    Span::new(FileId(0), start, start + needle.len())
}

fn arm_scenario(urdf: &str, home: Vec<f64>) -> Scenario {
    arm_scenario_dof(urdf, home, 3)
}

fn arm_scenario_dof(urdf: &str, home: Vec<f64>, dof: usize) -> Scenario {
    let mut r = robot("arm", urdf, home, None);
    r.urdf.span = span_of("\"arm.urdf\"");
    r.home = JointValues { values: r.home.values.clone(), span: span_of("[0, 0, 0]") };
    let mut scn = scenario(vec![r], vec![], vec![], vec![]);
    // A valid `target arm at [...]`.
    scn.target =
        Target::Config { robot: RobotId(0), q: JointValues { values: vec![0.0; dof], span: sp(0, 1) }, span: sp(0, 1) };
    scn
}

fn errors(scn: &Scenario, loader: &MemLoader) -> Vec<WorldError> {
    match build(scn, &WorldOptions { self_collision_samples: 0, ..WorldOptions::default() }, loader) {
        Ok(_) => panic!("expected errors"),
        Err(e) => e,
    }
}

fn code(e: &WorldError) -> String {
    e.code().map(|c| c.to_string()).unwrap_or_default()
}

fn rendered(errs: &[WorldError]) -> String {
    let mut map = SourceMap::new();
    map.add("cell.dcl", "cell.dcl", SRC);
    render_all(&map, errs, RenderOptions::plain())
}

fn one_link(extra: &str) -> String {
    format!(
        r#"<robot name="r"><link name="base"/><link name="l1">{extra}</link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#
    )
}

#[test]
fn broken_urdf_xml() {
    let loader = MemLoader::new().with("/m/arm.urdf", r#"<robot name="r"><link name="a"></robot>"#);
    let errs = errors(&arm_scenario("/m/arm.urdf", vec![]), &loader);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::urdf_parse");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
}

#[test]
fn xacro_has_no_links() {
    let xacro = r#"<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm">
  <xacro:include filename="$(find arm)/urdf/arm.xacro"/>
  <xacro:arm prefix=""/>
</robot>"#;
    let loader = MemLoader::new().with("/m/arm.urdf.xacro", xacro);
    let errs = errors(&arm_scenario("/m/arm.urdf.xacro", vec![]), &loader);
    assert_eq!(code(&errs[0]), "declutter::world::urdf_empty", "{errs:?}");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
    insta::assert_snapshot!(rendered(&errs));
}

#[test]
fn missing_urdf_file() {
    let errs = errors(&arm_scenario("/m/nowhere.urdf", vec![]), &MemLoader::new());
    assert_eq!(code(&errs[0]), "declutter::world::urdf_read");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
}

#[test]
fn missing_mesh() {
    let urdf =
        one_link(r#"<collision><geometry><mesh filename="package://arm/meshes/l1.stl"/></geometry></collision>"#);
    // The visual mesh is missing too, and does not matter.
    let urdf = urdf.replace(
        "<collision>",
        r#"<visual><geometry><mesh filename="meshes/visual.dae"/></geometry></visual><collision>"#,
    );
    let loader = MemLoader::new().with("/m/arm/urdf/arm.urdf", urdf);
    let errs = errors(&arm_scenario_dof("/m/arm/urdf/arm.urdf", vec![0.0], 1), &loader);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::mesh_missing");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
    let msg = errs[0].to_string();
    assert!(msg.contains("/m/arm/meshes/l1.stl"), "{msg}");
    insta::assert_snapshot!(rendered(&errs));
}

#[test]
fn mesh_found_through_package_uri_and_loaded() {
    // An ASCII STL tetrahedron under the package folder (an ancestor of the URDF's).
    let stl =
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 0\nvertex 0 0.1 0\nendloop\nendfacet\n\
facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 0.1 0\nvertex 0 0 0.1\nendloop\nendfacet\n\
facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 0 0.1\nvertex 0.1 0 0\nendloop\nendfacet\nendsolid t\n";
    let urdf = one_link(
        r#"<collision><geometry><mesh filename="package://arm/meshes/l1.stl" scale="2 2 2"/></geometry></collision>"#,
    );
    let loader = MemLoader::new().with("/m/arm/urdf/arm.urdf", urdf).with("/m/arm/meshes/l1.stl", stl);
    let scn = arm_scenario_dof("/m/arm/urdf/arm.urdf", vec![0.0], 1);
    let w = build(&scn, &WorldOptions::default(), &loader).unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(w.dof(declutter::resolve::RobotId(0)), 1);
}

#[test]
fn unknown_mimic_leader() {
    let urdf = one_link("").replace("<axis", r#"<mimic joint="nope"/><axis"#);
    let loader = MemLoader::new().with("/m/arm.urdf", urdf);
    let errs = errors(&arm_scenario("/m/arm.urdf", vec![]), &loader);
    assert_eq!(code(&errs[0]), "declutter::world::urdf_structure", "{errs:?}");
    assert!(errs[0].to_string().contains("nope"));
}

#[test]
fn home_of_wrong_length() {
    let scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0]);
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::joint_count");
    assert_eq!(errs[0].primary_span(), Some(span_of("[0, 0, 0]")));
    assert!(errs[0].to_string().contains("joint1, joint2, joint3"));
}

#[test]
fn home_outside_limits() {
    let scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 3.0, 0.0]);
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::joint_limit");
    assert_eq!(errs[0].primary_span(), Some(span_of("[0, 0, 0]")));
    assert!(matches!(&errs[0], WorldError::JointLimit { joint, index: 1, .. } if joint == "joint2"));
}

#[test]
fn drop_of_wrong_length_points_at_drop() {
    let mut scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0, 0.0]);
    scn.robots[0].drop = Some(JointValues { values: vec![0.0; 4], span: span_of("[0, 0, 0, 0]") });
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(code(&errs[0]), "declutter::world::joint_count");
    assert_eq!(errs[0].primary_span(), Some(span_of("[0, 0, 0, 0]")));
}

#[test]
fn home_colliding_with_a_fixed_body() {
    let mut scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0, 0.0]);
    scn.fixed.push(cuboid("post", [0.1, 0.1, 0.1], at(0.2, 0.0, 0.0)));
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::config_collides");
    assert_eq!(errs[0].primary_span(), Some(span_of("[0, 0, 0]")));
    let msg = errs[0].to_string();
    assert!(msg.contains("link1") && msg.contains("post"), "{msg}");
    insta::assert_snapshot!(rendered(&errs));
}

#[test]
fn unknown_flange_link() {
    let mut scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0, 0.0]);
    scn.robots[0].flange = Some(("wrist".into(), span_of("home")));
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(code(&errs[0]), "declutter::world::unknown_flange");
    assert_eq!(errs[0].primary_span(), Some(span_of("home")));
}

#[test]
fn allow_contact_with_an_unknown_link() {
    let mut scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0, 0.0]);
    scn.robots[0].allow_contact =
        vec![declutter::resolve::LinkPair { a: "link1".into(), b: "elbow".into(), span: span_of("drop") }];
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::unknown_link");
    assert_eq!(errs[0].primary_span(), Some(span_of("drop")));
    assert!(errs[0].to_string().contains("`elbow`"));
}

#[test]
fn several_errors_come_back_at_once_in_order() {
    let mut scn = arm_scenario("/m/arm.urdf", vec![]);
    scn.hands.push(hand("h", "/m/hand.urdf", 0.1));
    scn.hands[0].urdf.span = span_of("\"hand.urdf\"");
    let errs = errors(&scn, &MemLoader::new());
    let spans: Vec<_> = errs.iter().map(|e| e.primary_span()).collect();
    assert_eq!(spans, vec![Some(span_of("\"arm.urdf\"")), Some(span_of("\"hand.urdf\""))]);
}

#[test]
fn target_configuration_is_checked_too() {
    let mut scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0, 0.0]);
    scn.target =
        Target::Config { robot: RobotId(0), q: JointValues { values: vec![0.0; 2], span: sp(3, 5) }, span: sp(0, 9) };
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(code(&errs[0]), "declutter::world::joint_count");
    assert_eq!(errs[0].primary_span(), Some(sp(3, 5)));
}

/// A tetrahedron as COLLADA and as OBJ, loaded through relative mesh paths.
const DAE: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tet" name="tet">
      <mesh>
        <source id="tet-pos">
          <float_array id="tet-pos-array" count="12">0 0 0 0.1 0 0 0 0.1 0 0 0 0.1</float_array>
          <technique_common>
            <accessor source="#tet-pos-array" count="4" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="tet-vtx"><input semantic="POSITION" source="#tet-pos"/></vertices>
        <triangles count="4">
          <input semantic="VERTEX" source="#tet-vtx" offset="0"/>
          <p>0 2 1 0 1 3 0 3 2 1 2 3</p>
        </triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="s"><node id="n"><instance_geometry url="#tet"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##;

const OBJ: &str = "mtllib gone.mtl\nv 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

#[test]
fn dae_and_obj_meshes_load() {
    for (file, text) in [("tet.dae", DAE), ("tet.obj", OBJ)] {
        let urdf =
            one_link(&format!(r#"<collision><geometry><mesh filename="meshes/{file}"/></geometry></collision>"#));
        let loader = MemLoader::new().with("/m/arm.urdf", urdf).with(format!("/m/meshes/{file}"), text);
        let scn = arm_scenario_dof("/m/arm.urdf", vec![0.0], 1);
        let k = declutter::world::load_kinematics(&scn.robots[0].urdf, None, &WorldOptions::default(), &loader)
            .unwrap_or_else(|e| panic!("{file}: {e:?}"));
        assert_eq!(k.shape_count(), 1, "{file}");
    }
    // A file that is no mesh at all.
    let urdf = one_link(r#"<collision><geometry><mesh filename="meshes/bad.stl"/></geometry></collision>"#);
    let loader = MemLoader::new().with("/m/arm.urdf", urdf).with("/m/meshes/bad.stl", "solid x\nendsolid x\n");
    let errs = errors(&arm_scenario_dof("/m/arm.urdf", vec![0.0], 1), &loader);
    assert_eq!(code(&errs[0]), "declutter::world::mesh_load", "{errs:?}");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
}
