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
    r.home = JointValues { values: r.home.values.clone(), span: span_of("[0, 0, 0]"), units: Vec::new() };
    let mut scn = scenario(vec![r], vec![], vec![], vec![]);
    // A valid `target arm at [...]`.
    scn.target = Target::Config {
        robot: RobotId(0),
        q: JointValues { values: vec![0.0; dof], span: sp(0, 1), units: Vec::new() },
        span: sp(0, 1),
    };
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
fn a_urdf_element_that_cannot_be_read_names_its_line() {
    // Not XML (the reader's own position), and XML whose sphere has no radius.
    let broken = r#"<robot name="r"><link name="a"></robot>"#;
    let no_radius = one_link("<collision>\n<geometry><sphere/></geometry></collision>");
    for (text, line) in [(broken, "1:"), (no_radius.as_str(), "line 2: <sphere> has no `radius`")] {
        let loader = MemLoader::new().with("/m/arm.urdf", text);
        let errs = errors(&arm_scenario("/m/arm.urdf", vec![]), &loader);
        assert_eq!(code(&errs[0]), "declutter::world::urdf_parse", "{errs:?}");
        assert!(errs[0].to_string().contains(line), "{}", errs[0]);
        insta::assert_snapshot!(rendered(&errs));
    }
}

#[test]
fn xacro_is_refused() {
    let xacro = r#"<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="arm">
  <xacro:include filename="$(find arm)/urdf/arm.xacro"/>
  <xacro:arm prefix=""/>
</robot>"#;
    let loader = MemLoader::new().with("/m/arm.urdf.xacro", xacro);
    let errs = errors(&arm_scenario("/m/arm.urdf.xacro", vec![]), &loader);
    assert_eq!(code(&errs[0]), "declutter::world::urdf_xacro", "{errs:?}");
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
    insta::assert_snapshot!(rendered(&errs));
}

#[test]
fn drop_of_wrong_length_points_at_drop() {
    let mut scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0, 0.0]);
    scn.robots[0].drop = Some(JointValues { values: vec![0.0; 4], span: span_of("[0, 0, 0, 0]"), units: Vec::new() });
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
    insta::assert_snapshot!(rendered(&errs));
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
    scn.target = Target::Config {
        robot: RobotId(0),
        q: JointValues { values: vec![0.0; 2], span: sp(3, 5), units: Vec::new() },
        span: sp(0, 9),
    };
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("errors");
    assert_eq!(code(&errs[0]), "declutter::world::joint_count");
    assert_eq!(errs[0].primary_span(), Some(sp(3, 5)));
}

/// A tetrahedron as COLLADA and as OBJ, loaded through relative mesh paths.
fn dae() -> String {
    dae_tetrahedron("1", "0.1", "0")
}

const OBJ: &str = "mtllib gone.mtl\nv 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

#[test]
fn dae_and_obj_meshes_load() {
    for (file, text) in [("tet.dae", dae()), ("tet.obj", OBJ.to_string())] {
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

/// The errors of the one-joint arm built from `urdf` (one value in `home`).
fn urdf_errors(urdf: &str) -> Vec<WorldError> {
    let loader = MemLoader::new().with("/m/arm.urdf", urdf.to_string());
    // Sampling on: a URDF that slipped through would reach the self-collision sampler.
    let opts = WorldOptions { self_collision_samples: 50, ..WorldOptions::default() };
    match build(&arm_scenario_dof("/m/arm.urdf", vec![0.0], 1), &opts, &loader) {
        Ok(_) => panic!("expected errors for\n{urdf}"),
        Err(e) => e,
    }
}

#[test]
fn xacro_with_some_plain_links_is_refused_too() {
    // Top-level links would load, and the ones inside <xacro:if> would vanish.
    let urdf = one_link("").replace(
        "<link name=\"base\"/>",
        r#"<link name="base"/><xacro:if value="$(arg tool)"><link name="tool"/></xacro:if>"#,
    );
    let urdf = urdf.replace("<robot name=\"r\">", r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">"#);
    let errs = urdf_errors(&urdf);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::urdf_xacro");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
    assert!(errs[0].help().is_some_and(|h| h.to_string().contains("xacro robot.urdf.xacro > robot.urdf")));
}

#[test]
fn expanded_urdf_keeping_the_xacro_namespace_loads() {
    // xacro's output keeps `xmlns:xacro` on <robot> (every real URDF in ../shared does).
    let urdf =
        one_link("").replace("<robot name=\"r\">", r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">"#);
    let loader = MemLoader::new().with("/m/arm.urdf", urdf);
    build(&arm_scenario_dof("/m/arm.urdf", vec![0.0], 1), &WorldOptions::default(), &loader)
        .unwrap_or_else(|e| panic!("{e:?}"));
}

#[test]
fn absurd_prismatic_limits_are_refused_not_sampled() {
    let urdf = one_link("<collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>")
        .replace("type=\"revolute\"", "type=\"prismatic\"")
        .replace("lower=\"-1\" upper=\"1\"", "lower=\"-1e308\" upper=\"1e308\"");
    let errs = urdf_errors(&urdf);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::urdf_limit");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
    assert!(matches!(&errs[0], WorldError::UrdfLimit { joint, .. } if joint == "j1"), "{errs:?}");
    insta::assert_snapshot!(rendered(&errs));
}

#[test]
fn non_finite_or_missing_limits_are_refused() {
    for (limit, says) in [
        (r#"<limit lower="NaN" upper="1" effort="1" velocity="1"/>"#, "not finite"),
        (r#"<limit lower="-1" upper="inf" effort="1" velocity="1"/>"#, "not finite"),
        (r#"<limit lower="-2000" upper="1" effort="1" velocity="1"/>"#, "beyond ±1000"),
        (r#"<limit lower="1" upper="-1" effort="1" velocity="1"/>"#, "above its upper limit"),
        ("", "has no <limit>"),
    ] {
        for kind in ["revolute", "prismatic"] {
            let urdf = one_link("")
                .replace(r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#, limit)
                .replace("type=\"revolute\"", &format!("type=\"{kind}\""));
            let errs = urdf_errors(&urdf);
            assert_eq!(errs.len(), 1, "{kind} {limit}: {errs:?}");
            assert_eq!(code(&errs[0]), "declutter::world::urdf_limit", "{kind} {limit}");
            let msg = errs[0].to_string();
            assert!(msg.contains("joint `j1`") && msg.contains(says), "{kind} {limit}: {msg}");
        }
    }
    // A continuous joint needs no <limit>: it turns in (-2π, 2π).
    let urdf = one_link("")
        .replace("type=\"revolute\"", "type=\"continuous\"")
        .replace(r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#, "");
    let loader = MemLoader::new().with("/m/arm.urdf", urdf);
    let k = declutter::world::load_kinematics(&file("/m/arm.urdf", sp(0, 1)), None, &WorldOptions::default(), &loader)
        .unwrap_or_else(|e| panic!("{e:?}"));
    assert_eq!(k.limits(), &[(-std::f64::consts::TAU, std::f64::consts::TAU)]);
}

#[test]
fn revolute_without_limit_has_a_pinned_message() {
    let urdf = one_link("").replace(r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#, "");
    insta::assert_snapshot!(rendered(&urdf_errors(&urdf)));
}

#[test]
fn non_finite_numbers_anywhere_are_refused() {
    let shape =
        r#"<collision><origin xyz="0 0 0" rpy="0 0 0"/><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#;
    let base = one_link(shape).replace("<axis", r#"<origin xyz="0 0 0" rpy="0 0 0"/><axis"#);
    let cases = [
        // (text to replace, replacement, what the message names)
        (r#"<origin xyz="0 0 0" rpy="0 0 0"/><axis"#, r#"<origin xyz="NaN 0 0" rpy="0 0 0"/><axis"#, "joint `j1`"),
        (r#"<origin xyz="0 0 0" rpy="0 0 0"/><axis"#, r#"<origin xyz="0 0 0" rpy="0 inf 0"/><axis"#, "joint `j1`"),
        (
            r#"<origin xyz="0 0 0" rpy="0 0 0"/><geometry>"#,
            r#"<origin xyz="0 0 1e300" rpy="0 0 0"/><geometry>"#,
            "link `l1`",
        ),
        (
            r#"<origin xyz="0 0 0" rpy="0 0 0"/><geometry>"#,
            r#"<origin xyz="0 0 0" rpy="NaN 0 0"/><geometry>"#,
            "link `l1`",
        ),
        (r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="0 NaN 1"/>"#, "joint `j1`"),
        (r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="0 0 1e308"/>"#, "joint `j1`"),
        (r#"<box size="0.1 0.1 0.1"/>"#, r#"<box size="0.1 inf 0.1"/>"#, "link `l1`"),
        (r#"<box size="0.1 0.1 0.1"/>"#, r#"<sphere radius="NaN"/>"#, "link `l1`"),
        (r#"<box size="0.1 0.1 0.1"/>"#, r#"<cylinder radius="0.1" length="1e300"/>"#, "link `l1`"),
        (r#"<box size="0.1 0.1 0.1"/>"#, r#"<mesh filename="m.stl" scale="1 NaN 1"/>"#, "link `l1`"),
    ];
    for (from, to, names) in cases {
        assert!(base.contains(from), "{from}");
        let errs = urdf_errors(&base.replacen(from, to, 1));
        assert_eq!(errs.len(), 1, "{to}: {errs:?}");
        assert_eq!(code(&errs[0]), "declutter::world::urdf_structure", "{to}: {errs:?}");
        assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
        let msg = errs[0].to_string();
        assert!(msg.contains(names), "{to}: {msg}");
    }
    // A mimic joint with a NaN multiplier.
    let urdf = format!(
        "{}{}",
        base.trim_end_matches("</robot>"),
        r#"<link name="l2"/><joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
<mimic joint="j1" multiplier="NaN"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#
    );
    let errs = urdf_errors(&urdf);
    assert_eq!(code(&errs[0]), "declutter::world::urdf_structure", "{errs:?}");
    assert!(errs[0].to_string().contains("joint `j2`"), "{errs:?}");
}

#[test]
fn robot_without_actuated_joints_says_so() {
    let urdf = one_link("").replace("type=\"revolute\"", "type=\"fixed\"");
    let errs = urdf_errors(&urdf);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::no_joints");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
    insta::assert_snapshot!(rendered(&errs));
}

/// `1cm` for a revolute joint was once read as 0.01 rad; the world, which knows which
/// joints turn, refuses it and points at the value.
#[test]
fn a_length_for_a_turning_joint_is_refused() {
    let root = env!("CARGO_MANIFEST_DIR");
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("joint_unit");
    std::fs::create_dir_all(&dir).unwrap();
    let text = format!(
        r#"scenario "unit"
use "{root}/examples/cell.dcl"
object can cylinder(radius: 3.3cm, length: 11.5cm) at (60cm, 0, 5.75cm) {{
    grasp top at (0, 0, 4cm) rot (180deg, 0, 0) approach 8cm repeat 4 about z
}}
robot r3 {{
    urdf "{root}/examples/robots/tx90.urdf"
    base at (0, 1.5m, 0)
    home [0, 1cm, 110deg, 0, 60deg, 0]
}}
target can
"#
    );
    let file = dir.join("unit.dcl");
    std::fs::write(&file, &text).unwrap();
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(&file, &declutter::diag::FsLoader, &mut sources).expect("resolves");
    let errs = build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).expect_err("refused");
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::joint_unit");
    let span = errs[0].primary_span().expect("a span");
    assert_eq!(&text[span.start as usize..span.end as usize], "1cm");
    assert!(matches!(&errs[0], WorldError::JointUnit { joint, moves: "turns", .. } if joint == "joint_2"));
    // The same value as an angle, or bare, is accepted.
    for ok in ["10deg", "0.17"] {
        std::fs::write(&file, text.replace("1cm", ok)).unwrap();
        let mut sources = SourceMap::new();
        let scn = declutter::resolve::resolve(&file, &declutter::diag::FsLoader, &mut sources).expect("resolves");
        assert!(build(&scn, &WorldOptions::default(), &declutter::diag::FsLoader).is_ok(), "{ok}");
    }
}

#[test]
fn missing_mesh_by_relative_path_has_its_own_help() {
    let urdf = one_link(r#"<collision><geometry><mesh filename="meshes/l1.stl"/></geometry></collision>"#);
    let loader = MemLoader::new().with("/m/arm.urdf", urdf);
    let errs = errors(&arm_scenario_dof("/m/arm.urdf", vec![0.0], 1), &loader);
    assert_eq!(errs.len(), 1, "{errs:?}");
    let help = miette::Diagnostic::help(&errs[0]).map(|h| h.to_string());
    assert_eq!(help.as_deref(), Some("a relative path is resolved from the folder of the file that names it"));
}

#[test]
fn broken_mesh_of_a_fixed_body_names_the_body() {
    let mut scn = arm_scenario(planar3().to_str().unwrap(), vec![0.0, 0.0, 0.0]);
    let file =
        declutter::resolve::FileRef { path: "/m/post.stl".into(), written: "post.stl".into(), span: span_of("drop") };
    let shape = declutter::resolve::Shape::Mesh { file, scale: nalgebra::Vector3::new(1.0, 1.0, 1.0) };
    scn.fixed.push(body("post", shape, at(2.0, 2.0, 0.0)));
    let loader = MemLoader::new().with("/m/post.stl", "solid nothing\nthis is not STL\n");
    let errs = build(&scn, &WorldOptions::default(), &loader).expect_err("a broken mesh");
    let planar = errs.iter().filter(|e| code(e) != "declutter::world::mesh_load").count();
    assert_eq!(planar, errs.len() - 1, "{errs:?}");
    let e = errs.iter().find(|e| code(e) == "declutter::world::mesh_load").expect("a mesh_load error");
    assert!(e.to_string().starts_with("mesh `post.stl` of body `post` cannot be loaded: "), "{e}");
    assert_eq!(e.primary_span(), Some(span_of("drop")));
}

#[test]
fn urdf_without_links_is_refused() {
    let errs = urdf_errors(r#"<robot name="nothing"></robot>"#);
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert_eq!(code(&errs[0]), "declutter::world::urdf_empty");
    assert_eq!(errs[0].to_string(), "URDF `/m/arm.urdf` has no links");
    assert_eq!(errs[0].primary_span(), Some(span_of("\"arm.urdf\"")));
}
