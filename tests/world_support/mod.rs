//! Hand-built scenarios for the world tests (no parser involved).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use declutter::diag::{FileId, Span};
use declutter::resolve::*;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

pub fn sp(a: usize, b: usize) -> Span {
    Span::new(FileId(0), a, b)
}

pub fn manifest() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn file(path: impl AsRef<Path>, span: Span) -> FileRef {
    let path = path.as_ref().to_path_buf();
    FileRef { written: path.display().to_string(), path, span }
}

pub fn at(x: f64, y: f64, z: f64) -> Pose {
    Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::identity())
}

pub fn robot(name: &str, urdf: impl AsRef<Path>, home: Vec<f64>, hand: Option<HandId>) -> Robot {
    Robot {
        name: name.into(),
        span: sp(0, 1),
        urdf: file(urdf, sp(10, 20)),
        pose_world_base: Pose::identity(),
        hand,
        flange: None,
        srdf: None,
        home: JointValues { values: home, span: sp(30, 40), units: Vec::new() },
        drop: None,
        allow_contact: Vec::new(),
        open: None,
        closed: None,
    }
}

pub fn hand(name: &str, urdf: impl AsRef<Path>, tcp_z: f64) -> Hand {
    Hand { name: name.into(), span: sp(50, 51), urdf: file(urdf, sp(52, 60)), pose_flange_tcp: at(0.0, 0.0, tcp_z) }
}

pub fn body(name: &str, shape: Shape, pose: Pose) -> Body {
    Body {
        name: name.into(),
        span: sp(70, 71),
        pose_world_body: pose,
        parts: vec![Part { shape, pose_world_part: pose, pose_body_part: Pose::identity(), span: sp(72, 73) }],
    }
}

pub fn cuboid(name: &str, size: [f64; 3], pose: Pose) -> Body {
    body(name, Shape::Box { size: Vector3::from(size) }, pose)
}

pub fn object(b: Body, grasps: Vec<Grasp>) -> Object {
    Object { body: b, grasps }
}

pub fn grasp(name: &str, pose_world_object: &Pose, pose_object_tcp: Pose, approach: f64) -> Grasp {
    Grasp {
        name: name.into(),
        span: sp(80, 81),
        pose_object_tcp,
        pose_world_tcp: pose_world_object * pose_object_tcp,
        approach,
        hands: None,
        width: None,
    }
}

pub fn scenario(robots: Vec<Robot>, hands: Vec<Hand>, fixed: Vec<Body>, objects: Vec<Object>) -> Scenario {
    let target = if objects.is_empty() {
        Target::Config { robot: RobotId(0), q: robots[0].home.clone(), span: sp(90, 91) }
    } else {
        Target::Object { object: ObjectId(0), span: sp(90, 91) }
    };
    Scenario {
        name: Some("test".into()),
        root: manifest().join("test.dcl"),
        hands,
        robots,
        fixed,
        objects,
        target,
        planner: PlannerSettings::default(),
    }
}

pub fn tx90() -> PathBuf {
    manifest().join("examples/robots/tx90.urdf")
}
pub fn planar3() -> PathBuf {
    manifest().join("examples/robots/planar3.urdf")
}
pub fn sah() -> PathBuf {
    manifest().join("examples/hands/sah.urdf")
}
pub fn sdh2() -> PathBuf {
    manifest().join("examples/hands/sdh2.urdf")
}

/// `../shared/robots`, or `None` (with the reason printed) when it is absent.
pub fn shared_robots() -> Option<PathBuf> {
    let p = manifest().join("../shared/robots");
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipped: {} is absent (the shared robot files are not in this checkout)", p.display());
        None
    }
}

/// A COLLADA tetrahedron with legs `side` long along x, y and z, in units of `meter`
/// metres, its node translated by `dx` units along x.
pub fn dae_tetrahedron(meter: &str, side: &str, dx: &str) -> String {
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="u" meter="{meter}"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tet" name="tet">
      <mesh>
        <source id="tet-pos">
          <float_array id="tet-pos-array" count="12">0 0 0 {side} 0 0 0 {side} 0 0 0 {side}</float_array>
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
    <visual_scene id="s"><node id="n"><translate>{dx} 0 0</translate><instance_geometry url="#tet"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##
    )
}
