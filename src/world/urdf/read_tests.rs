//! The URDF reader against urdf-rs, which the world used to read URDFs with: the same
//! links, joints, poses and limits from every URDF of `../shared/robots` and
//! `examples/robots`, and from variations of a small arm over what the format lets an
//! author leave out or write another way.

use std::path::{Path, PathBuf};

use nalgebra::UnitQuaternion;

use super::read::{
    self, JointKind, Orientation, RawCollision, RawJoint, RawLimit, RawLink, RawPose, RawRobot, RawShape,
};
use super::{parse, UrdfProblem};

/// What urdf-rs reads, in the reader's terms. urdf-rs fills an absent `<limit>` with
/// zeros: the world took all zeros for "no limit", and so does this oracle.
fn oracle(text: &str) -> Result<RawRobot, String> {
    let r = urdf_rs::read_from_string(text).map_err(|e| e.to_string())?;
    let pose = |p: &urdf_rs::Pose| RawPose { xyz: p.xyz.0, orientation: Orientation::Rpy(p.rpy.0) };
    let links = r
        .links
        .iter()
        .map(|l| RawLink {
            name: l.name.clone(),
            collisions: l
                .collision
                .iter()
                .map(|c| RawCollision {
                    origin: pose(&c.origin),
                    shape: match &c.geometry {
                        urdf_rs::Geometry::Box { size } => RawShape::Box(size.0),
                        urdf_rs::Geometry::Cylinder { radius, length } => {
                            RawShape::Cylinder { radius: *radius, length: *length }
                        }
                        urdf_rs::Geometry::Capsule { radius, length } => {
                            RawShape::Capsule { radius: *radius, length: *length }
                        }
                        urdf_rs::Geometry::Sphere { radius } => RawShape::Sphere(*radius),
                        urdf_rs::Geometry::Mesh { filename, scale } => {
                            RawShape::Mesh { filename: filename.clone(), scale: scale.map(|s| s.0) }
                        }
                    },
                })
                .collect(),
        })
        .collect();
    let joints = r
        .joints
        .iter()
        .map(|j| {
            let l = &j.limit;
            let none = l.lower == 0.0 && l.upper == 0.0 && l.effort == 0.0 && l.velocity == 0.0;
            RawJoint {
                name: j.name.clone(),
                kind: match j.joint_type {
                    urdf_rs::JointType::Revolute => JointKind::Revolute,
                    urdf_rs::JointType::Continuous => JointKind::Continuous,
                    urdf_rs::JointType::Prismatic => JointKind::Prismatic,
                    urdf_rs::JointType::Fixed => JointKind::Fixed,
                    urdf_rs::JointType::Floating => JointKind::Unsupported("floating"),
                    urdf_rs::JointType::Planar => JointKind::Unsupported("planar"),
                    urdf_rs::JointType::Spherical => JointKind::Unsupported("spherical"),
                },
                origin: pose(&j.origin),
                parent: j.parent.link.clone(),
                child: j.child.link.clone(),
                axis: j.axis.xyz.0,
                limit: (!none).then_some(RawLimit {
                    lower: l.lower,
                    upper: l.upper,
                    effort: l.effort,
                    velocity: l.velocity,
                }),
                mimic: j.mimic.as_ref().map(|m| (m.joint.clone(), m.multiplier, m.offset)),
            }
        })
        .collect();
    Ok(RawRobot { links, joints })
}

fn ours(text: &str) -> Result<RawRobot, UrdfProblem> {
    let doc = roxmltree::Document::parse(text).map_err(|e| UrdfProblem::Parse(e.to_string()))?;
    read::robot(&doc)
}

/// urdf-rs turns a quaternion into roll, pitch and yaw; the reader keeps it. Poses are
/// compared as rotations, everything else exactly (a NaN limit equal to a NaN).
fn same(a: &RawRobot, b: &RawRobot) -> bool {
    let rot = |p: &RawPose| match p.orientation {
        Orientation::Rpy([r, p, y]) => UnitQuaternion::from_euler_angles(r, p, y),
        Orientation::Quat([x, y, z, w]) => UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z)),
    };
    let pose = |p: &RawPose, q: &RawPose| p.xyz == q.xyz && rot(p).angle_to(&rot(q)) < 1e-9;
    let plain = |p: &RawPose| RawPose { orientation: Orientation::Rpy([0.0; 3]), ..*p };
    let strip = |r: &RawRobot| {
        let mut r = r.clone();
        r.links.iter_mut().flat_map(|l| &mut l.collisions).for_each(|c| c.origin = plain(&c.origin));
        r.joints.iter_mut().for_each(|j| j.origin = plain(&j.origin));
        r
    };
    // Through Debug, which prints every float exactly, so that NaN equals NaN.
    format!("{:?}", strip(a)) == format!("{:?}", strip(b))
        && a.links
            .iter()
            .flat_map(|l| &l.collisions)
            .zip(b.links.iter().flat_map(|l| &l.collisions))
            .all(|(x, y)| pose(&x.origin, &y.origin))
        && a.joints.iter().zip(&b.joints).all(|(x, y)| pose(&x.origin, &y.origin))
}

fn urdfs_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            urdfs_under(&p, out);
        } else if p.extension().is_some_and(|x| x == "urdf") {
            out.push(p);
        }
    }
}

#[test]
fn every_shipped_and_shared_urdf_reads_as_urdf_rs_reads_it() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    urdfs_under(&root.join("examples"), &mut files);
    let shipped = files.len();
    let shared = root.join("../shared/robots");
    if shared.is_dir() {
        urdfs_under(&shared, &mut files);
    } else {
        eprintln!("skipping ../shared/robots: {} is absent", shared.display());
    }
    assert!(shipped >= 2, "examples hold {shipped} URDFs");
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let (a, b) = (ours(&text).unwrap(), oracle(&text).unwrap());
        assert!(same(&a, &b), "{}:\n{a:?}\n{b:?}", f.display());
        assert!(!a.joints.is_empty() && a.links.iter().any(|l| !l.collisions.is_empty()), "{}", f.display());
        parse(&text).unwrap_or_else(|e| panic!("{}: {e:?}", f.display()));
    }
}

const ARM: &str = r#"<?xml version="1.0"?>
<!-- a two-link arm -->
<robot name="arm" VERSION>
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <visual><geometry><box size="1 1 1"/></geometry></visual>
    <collision name="c0">ORIGIN<geometry>SHAPE</geometry></collision>
    <collision><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
  <joint name="j1" type="TYPE">
    JOINT_ORIGIN<parent link="base"/><child link="upper"/>AXIS
    LIMIT
    MIMIC
    <dynamics damping="0.1"/>
  </joint>
  <link name="upper"/>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="tip"/>
    <limit lower="-1" upper="1" effort="1" velocity="2"/></joint>
  <link name="tip"><collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision></link>
</robot>"#;

/// Each slot's spellings: what an author may write there.
const SLOTS: [(&str, &[&str]); 8] = [
    ("VERSION", &["", r#"version="1.0""#, r#"version="1.1""#, r#"version="1.2""#, r#"version="x""#]),
    (
        "ORIGIN",
        &[
            "",
            "<origin/>",
            r#"<origin xyz="0.1 -0.2 3e-1"/>"#,
            r#"<origin xyz="  0.1   0.2	0.3 " rpy="0.3 -0.2 1.5"/>"#,
            r#"<origin rpy="0 0 3.14159"/>"#,
            r#"<origin xyz="1 2 3" quat_xyzw="0 0 0.3826834 0.9238795"/>"#,
            r#"<origin quat_xyzw="0.1 0.2 0.3 0.9"/>"#,
            r#"<origin rpy="0 0 1" quat_xyzw="0 0 0 1"/>"#,
            r#"<origin xyz="1 2"/>"#,
            r#"<origin xyz="1 2 x"/>"#,
        ],
    ),
    (
        "SHAPE",
        &[
            r#"<box size="0.1 0.2 0.3"/>"#,
            r#"<cylinder radius="0.1" length="0.5"/>"#,
            r#"<cylinder radius="0.1" length="0"/>"#,
            r#"<capsule radius="0.1" length="0.5"/>"#,
            r#"<sphere radius=" 0.25 "/>"#,
            r#"<sphere radius="-1"/>"#,
            r#"<sphere/>"#,
            r#"<mesh filename="package://arm/meshes/base.stl"/>"#,
            r#"<mesh filename="meshes/base.stl" scale="0.001 0.001 0.001"/>"#,
            r#"<cone radius="1"/>"#,
        ],
    ),
    ("TYPE", &["revolute", "continuous", "prismatic", "fixed", "floating", "planar", "hinge"]),
    ("JOINT_ORIGIN", &["", r#"<origin xyz="0 0 0.5" rpy="1.5707963 0 0"/>"#]),
    ("AXIS", &["", r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="0 1 -1"/>"#]),
    (
        "LIMIT",
        &[
            "",
            r#"<limit lower="-2" upper="2" effort="10" velocity="1.5"/>"#,
            r#"<limit lower="-2" upper="2" velocity="1.5"/>"#,
            r#"<limit upper="2" effort="1" velocity="1.5"/>"#,
            r#"<limit lower="-2" upper="2" effort="1"/>"#,
            r#"<limit lower="2" upper="-2" effort="1" velocity="1"/>"#,
            r#"<limit lower="-2" upper="2" effort="1" velocity="-1"/>"#,
            r#"<limit lower="-2" upper="2" effort="1" velocity="1" acceleration="3"/>"#,
            r#"<limit lower="nan" upper="2" effort="1" velocity="1"/>"#,
        ],
    ),
    ("MIMIC", &["", r#"<mimic joint="j2"/>"#, r#"<mimic joint="j2" multiplier="-1" offset="0.1"/>"#, r#"<mimic/>"#]),
];

/// Spellings where the reader is deliberately not urdf-rs: a number list with a word
/// in it (urdf-rs drops the word and may then count three numbers).
const LOOSER_ORACLE: [&str; 1] = [r#"<origin xyz="1 2 x"/>"#];

#[test]
fn variations_of_an_arm_read_as_urdf_rs_reads_them() {
    // Every spelling of every slot once, the other slots at a rotating choice: 7 x 10
    // combinations cover each spelling beside several of the others.
    let mut checked = (0, 0);
    let mut seen = std::collections::HashSet::new();
    for round in 0..70 {
        let mut text = ARM.to_string();
        let mut picked = Vec::new();
        for (k, (slot, spellings)) in SLOTS.iter().enumerate() {
            let s = spellings[(round * (k + 1) + round / spellings.len()) % spellings.len()];
            picked.push(s);
            seen.insert((k, s));
            text = text.replace(slot, s);
        }
        let (a, b) = (ours(&text), oracle(&text));
        match (&a, &b) {
            (Ok(a), Ok(b)) => {
                assert!(same(a, b), "{picked:?}\n{a:?}\n{b:?}");
                checked.0 += 1;
            }
            (Err(_), Err(_)) => checked.1 += 1,
            (Err(e), Ok(_)) if picked.iter().any(|p| LOOSER_ORACLE.contains(p)) => {
                assert!(matches!(e, UrdfProblem::Parse(m) if m.contains("is not 3 numbers")), "{e:?}")
            }
            _ => panic!("{picked:?}: ours {a:?}, urdf-rs {b:?}"),
        }
    }
    // Every spelling and both outcomes must be exercised, or the comparison proves little.
    assert_eq!(seen.len(), SLOTS.iter().map(|(_, s)| s.len()).sum::<usize>());
    assert!(checked.0 >= 15 && checked.1 >= 15, "{checked:?}");
}

#[test]
fn reading_problems_name_the_line_and_what_is_wrong() {
    let err = |text: &str| match ours(text) {
        Err(UrdfProblem::Parse(m)) => m,
        other => panic!("{other:?}"),
    };
    let arm = |slot: &str, s: &str| {
        let mut t = ARM.to_string();
        for (name, spellings) in SLOTS {
            t = t.replace(name, if name == slot { s } else { spellings[0] });
        }
        t
    };
    assert_eq!(err(&arm("ORIGIN", r#"<origin xyz="1 2"/>"#)), r#"line 8: <origin xyz="1 2"> is not 3 numbers"#);
    assert_eq!(err(&arm("SHAPE", "<sphere/>")), "line 8: <sphere> has no `radius`");
    assert_eq!(
        err(&arm("SHAPE", r#"<cone radius="1"/>"#)),
        "line 8: <cone> is not a URDF shape (box, cylinder, capsule, sphere or mesh)"
    );
    assert_eq!(err(&arm("LIMIT", r#"<limit lower="-2" upper="2" effort="1"/>"#)), "line 13: <limit> has no `velocity`");
    assert_eq!(
        err(&arm("VERSION", r#"version="1.2""#).replace(r#"velocity="2""#, r#"velocity="-2""#)),
        "line 19: joint `j2` has a negative effort or velocity limit (URDF 1.2)"
    );
    assert_eq!(
        err(&arm("ORIGIN", r#"<origin rpy="0 0 1" quat_xyzw="0 0 0 1"/>"#)
            .replace("<robot name=\"arm\" >", "<robot name=\"arm\" version=\"1.1\">")),
        "line 8: <origin> gives both rpy and quat_xyzw"
    );
    assert_eq!(err("<robt/>"), "line 1: the root element is <robt>, not <robot>");
    // Before 1.1 a quaternion is ignored, as urdfdom does.
    let q = arm("ORIGIN", r#"<origin quat_xyzw="0 0 1 0"/>"#);
    assert_eq!(ours(&q).unwrap().links[0].collisions[0].origin, RawPose::default());
}

#[test]
fn a_quaternion_is_taken_whole_and_normalised() {
    // A half turn about z written as a quaternion of length 2, and one a hair from
    // pitch 90°, where urdfdom's roll-pitch-yaw conversion would snap to 90°.
    let arm = |q: &str| {
        ARM.replace("VERSION", r#"version="1.1""#)
            .replace("ORIGIN", &format!(r#"<origin quat_xyzw="{q}"/>"#))
            .replace("SHAPE", r#"<sphere radius="0.1"/>"#)
            .replace("TYPE", "fixed")
            .replace("JOINT_ORIGIN", "")
            .replace("AXIS", "")
            .replace("LIMIT", "")
            .replace("MIMIC", "")
    };
    let m = parse(&arm("0 0 2 0")).unwrap();
    let r = m.links[0].collisions[0].pose_link_geom.rotation;
    assert!((r * nalgebra::Vector3::x() - -nalgebra::Vector3::x()).norm() < 1e-15, "{r:?}");
    let pitch = 89.9f64.to_radians() / 2.0;
    let m = parse(&arm(&format!("0 {} 0 {}", pitch.sin(), pitch.cos()))).unwrap();
    let angle = m.links[0].collisions[0].pose_link_geom.rotation.angle();
    assert!((angle - 89.9f64.to_radians()).abs() < 1e-12, "{}", angle.to_degrees());
    assert!(
        matches!(parse(&arm("0 0 0 0")), Err(UrdfProblem::Structure(m)) if m.contains("quat_xyzw [0.0, 0.0, 0.0, 0.0]"))
    );
}

/// Spelled another way, a URDF reads the same: a comment or white space after any tag,
/// attributes on lines of their own, an empty element written open and closed.
fn respelled(text: &str, picks: &[u8]) -> String {
    let mut pick = picks.iter().cycle().copied();
    let empty = regex::Regex::new(r"<([A-Za-z_:]+)([^<>]*?)\s*/>").unwrap();
    let text = empty.replace_all(text, |c: &regex::Captures| match pick.next().unwrap_or(0) % 2 {
        0 => format!("<{}{}></{}>", &c[1], &c[2], &c[1]),
        _ => c[0].to_string(),
    });
    let mut out = String::with_capacity(text.len() * 2);
    let mut in_tag = false;
    let mut quoted = false;
    for ch in text.chars() {
        match ch {
            '"' if in_tag => quoted = !quoted,
            ' ' if in_tag && !quoted => {
                out.push_str(["\n    ", " ", "\t", "  "][usize::from(pick.next().unwrap_or(0) % 4)]);
                continue;
            }
            '<' => in_tag = true,
            _ => {}
        }
        out.push(ch);
        if ch == '>' {
            in_tag = false;
            out.push_str(["", "<!-- a comment -->", "\n", ""][usize::from(pick.next().unwrap_or(0) % 4)]);
        }
    }
    out
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
    #[test]
    fn a_urdf_spelled_another_way_reads_the_same(picks in proptest::collection::vec(0u8..=255, 1..64)) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/robots/tx90.urdf");
        let text = std::fs::read_to_string(path).unwrap();
        let again = respelled(&text, &picks);
        proptest::prop_assert_ne!(&again, &text);
        let (a, b) = (ours(&text).unwrap(), ours(&again).unwrap());
        proptest::prop_assert!(same(&a, &b), "{}", again);
    }
}
