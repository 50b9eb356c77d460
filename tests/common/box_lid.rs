//! The box-and-lid cell built by hand (no parser): two TX-90s facing each other across
//! a table; on it a fixed open box holding a can, closed by a lid. Shared by the
//! planner tests and benches/plan.rs.

use declutter::resolve::{HandId, Pose, Scenario, Shape};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

use crate::world_support::*;

fn rot_y(deg: f64) -> Pose {
    Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_euler_angles(0.0, deg.to_radians(), 0.0))
}
fn rot_z(deg: f64) -> Pose {
    Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_euler_angles(0.0, 0.0, deg.to_radians()))
}

/// A table between two TX-90s; on it a fixed open box holding a can, closed by a lid.
/// Objects: 0 the can, 1 the lid. Robots: 0 `left` (SAH), 1 `right` (SDH2).
pub fn box_lid() -> Scenario {
    let (cx, top) = (0.75, 0.2);
    let mut fixed = vec![cuboid("table", [0.6, 1.0, 0.1], at(cx, 0.0, top - 0.05))];
    let (inner, wall, h) = (0.24, 0.01, 0.12);
    let off = inner / 2.0 + wall / 2.0;
    for (n, x, y, sx, sy) in [
        ("wall_n", 0.0, off, inner + 2.0 * wall, wall),
        ("wall_s", 0.0, -off, inner + 2.0 * wall, wall),
        ("wall_e", off, 0.0, wall, inner),
        ("wall_w", -off, 0.0, wall, inner),
    ] {
        fixed.push(cuboid(n, [sx, sy, h], at(cx + x, y, top + h / 2.0)));
    }
    let p_can = at(cx, 0.0, top + 0.05);
    let can = body("can", Shape::Cylinder { radius: 0.033, length: 0.1 }, p_can);
    let p_lid = at(cx, 0.0, top + h + 0.005);
    let lid = cuboid("lid", [inner + 2.0 * wall + 0.02, inner + 2.0 * wall + 0.02, 0.01], p_lid);
    let down = |z: f64, turn: f64| at(0.0, 0.0, z) * rot_z(turn) * rot_y(180.0);
    let can_grasps = vec![grasp("top", &p_can, down(0.03, 0.0), 0.1), grasp("top#2", &p_can, down(0.03, 90.0), 0.1)];
    let lid_grasps = vec![grasp("top", &p_lid, down(0.0, 0.0), 0.1), grasp("top#2", &p_lid, down(0.0, 90.0), 0.1)];
    let home = vec![0.0, 0.0, 90f64.to_radians(), 0.0, 0.0, 0.0];
    let a = robot("left", tx90(), home.clone(), Some(HandId(0)));
    let mut b = robot("right", tx90(), home, Some(HandId(1)));
    b.pose_world_base = at(2.0 * cx, 0.0, 0.0) * rot_z(180.0);
    scenario(
        vec![a, b],
        vec![hand("sah", sah(), 0.16), hand("sdh2", sdh2(), 0.18)],
        fixed,
        vec![object(can, can_grasps), object(lid, lid_grasps)],
    )
}

fn rot_x(deg: f64) -> Pose {
    Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_euler_angles(deg.to_radians(), 0.0, 0.0))
}

/// examples/box_lid.dcl (with examples/cell.dcl) transcribed by hand, for use until the
/// resolver is merged: two TX-90s side by side at y = ±50 cm, a crate of five fixed
/// boxes at x = 55 cm, a can inside, and a lid with a handle on top; r2 drops objects
/// at its own `drop` configuration. Objects: 0 can, 1 lid. Robots: 0 r1 (SAH), 1 r2 (SDH2).
pub fn box_lid_dcl() -> Scenario {
    let d = |v: f64| v.to_radians();
    let mut sdh2 = hand("sdh2", sdh2(), 0.18);
    sdh2.pose_flange_tcp = at(0.0, 0.0, 0.18) * rot_z(90.0);
    let home = vec![0.0, d(-20.0), d(110.0), 0.0, d(60.0), 0.0];
    let mut r1 = robot("r1", tx90(), home.clone(), Some(HandId(0)));
    r1.pose_world_base = at(0.0, -0.5, 0.0);
    let mut r2 = robot("r2", tx90(), home, Some(HandId(1)));
    r2.pose_world_base = at(0.0, 0.5, 0.0);
    r2.drop = Some(declutter::resolve::JointValues {
        values: vec![d(90.0), 0.0, d(90.0), 0.0, d(45.0), 0.0],
        span: sp(41, 42),
        units: Vec::new(),
    });
    let table = cuboid("table", [1.4, 1.6, 0.04], at(0.6, 0.0, -0.02));
    let p_crate = at(0.55, 0.0, 0.0);
    let part = |size: [f64; 3], p: Pose| declutter::resolve::Part {
        shape: Shape::Box { size: size.into() },
        pose_world_part: p_crate * p,
        pose_body_part: p,
        span: sp(72, 73),
    };
    let mut crate_ = cuboid("crate", [0.3, 0.3, 0.01], p_crate);
    crate_.parts = vec![
        part([0.3, 0.3, 0.01], at(0.0, 0.0, 0.005)),
        part([0.3, 0.01, 0.2], at(0.0, 0.145, 0.1)),
        part([0.3, 0.01, 0.2], at(0.0, -0.145, 0.1)),
        part([0.01, 0.3, 0.2], at(0.145, 0.0, 0.1)),
        part([0.01, 0.3, 0.2], at(-0.145, 0.0, 0.1)),
    ];
    let p_can = at(0.55, 0.0, 0.0675);
    let can = body("can", Shape::Cylinder { radius: 0.033, length: 0.115 }, p_can);
    let repeat = |name: &str, p_obj: &Pose, tcp: Pose, approach: f64, n: usize| -> Vec<declutter::resolve::Grasp> {
        (0..n)
            .map(|k| {
                let label = if k == 0 { name.to_string() } else { format!("{name}#{}", k + 1) };
                grasp(&label, p_obj, rot_z(360.0 * k as f64 / n as f64) * tcp, approach)
            })
            .collect()
    };
    let can_grasps = repeat("top", &p_can, at(0.0, 0.0, 0.04) * rot_x(180.0), 0.08, 4);
    let p_lid = at(0.55, 0.0, 0.205);
    let mut lid = cuboid("lid", [0.32, 0.32, 0.01], p_lid);
    let handle = at(0.0, 0.0, 0.015);
    lid.parts.push(declutter::resolve::Part {
        shape: Shape::Box { size: [0.12, 0.02, 0.02].into() },
        pose_world_part: p_lid * handle,
        pose_body_part: handle,
        span: sp(74, 75),
    });
    let mut lid_grasps = repeat("middle", &p_lid, at(0.0, 0.0, 0.025) * rot_x(180.0), 0.06, 2);
    lid_grasps.extend(repeat("left", &p_lid, at(-0.04, 0.0, 0.025) * rot_x(180.0), 0.06, 2));
    lid_grasps.extend(repeat("right", &p_lid, at(0.04, 0.0, 0.025) * rot_x(180.0), 0.06, 2));
    scenario(
        vec![r1, r2],
        vec![hand("sah", sah(), 0.16), sdh2],
        vec![table, crate_],
        vec![object(can, can_grasps), object(lid, lid_grasps)],
    )
}
