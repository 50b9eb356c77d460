//! The reach at a configuration against forward kinematics: no point of a shape (or of
//! a carried object) moves faster than it says, over a whole motion too, and it is
//! tighter than the reach that holds everywhere. On the shipped TX-90s, the UR5, both
//! Pandas, and an arm on a rail (a sliding joint, a joint mimicking another: leaving
//! out the slide or the mimic's multiplier fails the first test).

use nalgebra::{Point3, Vector3};
use parry3d_f64::math::Vector as PVec;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{AxisReach, Farthest, ReachScratch};
use crate::resolve::RobotId;
use crate::world::test_arms::{example, shared_arms, world_of};
use crate::world::{PosedShape, World};

/// An arm on a rail: a sliding joint, then three turning ones (the last mimicking the
/// second, turned by -4 times its angle), boxes and a ball off their axes.
const RAIL: &str = r#"<?xml version="1.0"?>
<robot name="rail">
  <link name="base"><collision><geometry><box size="2 0.2 0.1"/></geometry></collision></link>
  <link name="cart"><collision><origin xyz="0 0 0.1"/><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="upper"><collision><origin xyz="0.25 0.05 0"/><geometry><box size="0.5 0.08 0.08"/></geometry></collision></link>
  <link name="fore"><collision><origin xyz="0.2 0 0.03" rpy="0.3 0 0.2"/><geometry><box size="0.4 0.06 0.06"/></geometry></collision></link>
  <link name="tip"><collision><origin xyz="0.1 0.25 0"/><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="cart"/><axis xyz="1 0 0"/>
    <limit lower="-0.8" upper="0.8" effort="1" velocity="1"/></joint>
  <joint name="pan" type="revolute"><parent link="cart"/><child link="upper"/><origin xyz="0 0 0.2"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="lift" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.5 0 0" rpy="0 -0.4 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="twist" type="revolute"><parent link="fore"/><child link="tip"/><origin xyz="0.4 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/><mimic joint="lift" multiplier="-4"/></joint>
</robot>
"#;

/// The arm on a rail alone, from files of its own (tests run on parallel threads).
fn rail() -> (String, World) {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("declutter-rail-{}-{k}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    std::fs::write(dir.join("rail.urdf"), RAIL).expect("a temporary file");
    let file = dir.join("rail.dcl");
    let text = "scenario \"rail\"\nrobot arm {\n    urdf \"rail.urdf\"\n    home [0m, 0, 0]\n}\ntarget arm at [0.1m, 0.2, -0.3]\n";
    std::fs::write(&file, text).expect("a temporary file");
    let w = world_of(&file);
    let _ = std::fs::remove_dir_all(&dir);
    ("rail".to_string(), w)
}

/// The shipped examples' arms (a TX-90 with hands, a gripper's fingers), the arm on a
/// rail, and the shared ones.
fn arms() -> Vec<(String, World)> {
    ["box_lid", "gripper"]
        .map(|n| (n.to_string(), example(n)))
        .into_iter()
        .chain([rail()])
        .chain(shared_arms())
        .collect()
}

fn random_q(w: &World, r: RobotId, rng: &mut ChaCha8Rng) -> Vec<f64> {
    w.robots[r.index()].chain.limits.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect()
}

/// Per joint value, the bound at `q` alone (no motion).
fn at(reach: &AxisReach, q: &[f64], everywhere: &[f64], scratch: &mut ReachScratch) -> Vec<f64> {
    let mut far: Farthest = Vec::new();
    reach.farthest(q, scratch, &mut far);
    let mut out = Vec::new();
    reach.over(&far, &far, &vec![0.0; everywhere.len()], everywhere, &mut out);
    out
}

/// Points on every shape (their support points in 26 directions, in the world) and the
/// flange's pose, at `q`.
fn points(w: &World, r: RobotId, q: &[f64]) -> (Vec<Vector3<f64>>, nalgebra::Isometry3<f64>) {
    let mut posed: Vec<PosedShape> = Vec::new();
    let flange = w.pose_shapes(r, q, None, &mut posed);
    let mut out = Vec::new();
    for ps in &posed {
        let Some(support) = ps.shape.0.as_support_map() else { continue };
        for d in (0..27).filter(|&i| i != 13) {
            let dir = PVec::new((d % 3) as f64 - 1.0, ((d / 3) % 3) as f64 - 1.0, (d / 9) as f64 - 1.0);
            let p = ps.pose * support.local_support_point(dir);
            out.push(Vector3::new(p.x, p.y, p.z));
        }
    }
    (out, flange)
}

#[test]
fn no_point_moves_faster_than_the_reach_at_its_configuration() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut cases, mut tighter) = (0, 0);
    for (name, w) in arms() {
        for ri in 0..w.robots.len() {
            let r = RobotId(ri as u32);
            let held_radius = 0.3;
            let everywhere = w.joint_reach(r).with_held(held_radius);
            let reach = w.axis_reach(r, held_radius);
            let mut scratch = ReachScratch::default();
            // A carried point, fixed in the flange's frame, as far out as allowed.
            let held: Vector3<f64> = Vector3::new(0.2, -0.1, 0.2).normalize() * held_radius;
            for _ in 0..200 {
                let q = random_q(&w, r, &mut rng);
                let bound = at(&reach, &q, &everywhere, &mut scratch);
                tighter += usize::from(bound.iter().zip(&everywhere).any(|(b, e)| *b < 0.8 * e));
                // Half the cases turn one joint alone: there the bound is the farthest
                // point's distance from that axis, and a point on a ball's far side nearly
                // meets it.
                let one = rng.random_range(0..2 * q.len());
                let v: Vec<f64> = (0..q.len())
                    .map(|j| if one < q.len() { f64::from(u8::from(j == one)) } else { rng.random_range(-1.0..1.0) })
                    .collect();
                let h = 1e-7;
                let moved: Vec<f64> = q.iter().zip(&v).map(|(q, v)| q + h * v).collect();
                let speed: f64 = bound.iter().zip(&v).map(|(b, v)| b * v.abs()).sum();
                let ((p0, f0), (p1, f1)) = (points(&w, r, &q), points(&w, r, &moved));
                let mut fastest = p0.iter().zip(&p1).map(|(a, b)| (b - a).norm() / h).fold(0.0, f64::max);
                fastest = fastest.max(((f1 * Point3::from(held)) - (f0 * Point3::from(held))).norm() / h);
                assert!(
                    fastest <= speed * (1.0 + 1e-5) + 1e-9,
                    "{name}: a point at {fastest} m/s, bound {speed} at {q:?}"
                );
                cases += 1;
            }
        }
    }
    // Tighter than the bound that holds everywhere (by a fifth on some joint) in most cases.
    assert!(tighter * 2 > cases, "{tighter} of {cases}");
}

#[test]
fn the_reach_over_a_motion_holds_at_every_instant_of_it() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut gained = 0.0f64;
    for (name, w) in arms() {
        for ri in 0..w.robots.len() {
            let r = RobotId(ri as u32);
            let everywhere = w.joint_reach(r).with_held(0.1);
            let reach = w.axis_reach(r, 0.1);
            let mut scratch = ReachScratch::default();
            let limits = w.robots[ri].chain.limits.clone();
            for _ in 0..100 {
                let a = random_q(&w, r, &mut rng);
                let b: Vec<f64> = a
                    .iter()
                    .zip(&limits)
                    .map(|(x, (lo, hi))| (x + rng.random_range(-0.5..0.5)).clamp(*lo, *hi))
                    .collect();
                let (mut fa, mut fb) = (Vec::new(), Vec::new());
                reach.farthest(&a, &mut scratch, &mut fa);
                reach.farthest(&b, &mut scratch, &mut fb);
                let travel: Vec<f64> =
                    everywhere.iter().zip(a.iter().zip(&b)).map(|(e, (x, y))| e * (y - x).abs()).collect();
                let mut over = Vec::new();
                reach.over(&fa, &fb, &travel, &everywhere, &mut over);
                for k in 0..=64 {
                    let s = k as f64 / 64.0;
                    let q: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x + s * (y - x)).collect();
                    for (j, (now, bound)) in at(&reach, &q, &everywhere, &mut scratch).iter().zip(&over).enumerate() {
                        assert!(now <= &(bound + 1e-12), "{name}: joint {j} reaches {now} at {s}, bound {bound}");
                    }
                }
                gained += over.iter().zip(&everywhere).map(|(o, e)| e - o).sum::<f64>();
            }
        }
    }
    assert!(gained > 0.0);
}

/// Per body: support points of its shapes at `q` (as [`points`]), by body.
fn body_points(w: &World, r: RobotId, q: &[f64]) -> Vec<Vec<Vector3<f64>>> {
    let mut posed: Vec<PosedShape> = Vec::new();
    w.pose_shapes(r, q, None, &mut posed);
    let mut out = vec![Vec::new(); w.robots[r.index()].bodies.len()];
    for ps in &posed {
        let Some(support) = ps.shape.0.as_support_map() else { continue };
        for d in (0..27).filter(|&i| i != 13) {
            let dir = PVec::new((d % 3) as f64 - 1.0, ((d / 3) % 3) as f64 - 1.0, (d / 9) as f64 - 1.0);
            let p = ps.pose * support.local_support_point(dir);
            out[ps.body].push(Vector3::new(p.x, p.y, p.z));
        }
    }
    out
}

/// A body's own reach over a motion, from where it stands at the motion's ends: no point
/// of the body moves faster than it says at any instant of a straight motion whose joints
/// turn no more than the bound was given (leaving out the drift of the joints between an
/// axis and the body fails it), and it is tighter than the static reach.
#[test]
fn no_point_of_a_body_moves_faster_than_its_reach_from_where_it_stood() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut bodies, mut tighter) = (0usize, 0usize);
    for (name, w) in arms() {
        for ri in 0..w.robots.len() {
            let r = RobotId(ri as u32);
            let own = w.body_reach(r);
            let reach = w.axis_reach(r, 0.0);
            let mut scratch = ReachScratch::default();
            let limits = w.robots[ri].chain.limits.clone();
            for _ in 0..60 {
                let a = random_q(&w, r, &mut rng);
                let b: Vec<f64> = a
                    .iter()
                    .zip(&limits)
                    .map(|(x, (lo, hi))| (x + rng.random_range(-0.4..0.4)).clamp(*lo, *hi))
                    .collect();
                let turn: Vec<f64> = a.iter().zip(&b).map(|(x, y)| (y - x).abs()).collect();
                let (mut far_a, mut far_b, mut bound) = (Vec::new(), Vec::new(), Vec::new());
                reach.bodies_farthest(&a, &mut scratch, &mut far_a);
                reach.bodies_farthest(&b, &mut scratch, &mut far_b);
                reach.bodies_over((&far_a, &far_b), &turn, &own, &mut bound);
                for (bound, own) in bound.iter().zip(&own).filter(|(_, o)| o.iter().any(|o| *o > 0.0)) {
                    tighter += usize::from(bound.iter().zip(own).any(|(b, o)| *b < 0.8 * o));
                    bodies += 1;
                }
                // Along the motion, each body's points move no faster, joint by joint.
                let h = 1e-7;
                for k in 0..=16 {
                    let s = k as f64 / 16.0;
                    let q: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x + s * (y - x)).collect();
                    let j = rng.random_range(0..q.len());
                    let mut moved = q.clone();
                    moved[j] += h;
                    let (p0, p1) = (body_points(&w, r, &q), body_points(&w, r, &moved));
                    for (body, (p0, p1)) in p0.iter().zip(&p1).enumerate() {
                        let fastest = p0.iter().zip(p1).map(|(x, y)| (y - x).norm() / h).fold(0.0, f64::max);
                        let allowed = bound[body][j];
                        assert!(
                            fastest <= allowed * (1.0 + 1e-5) + 1e-9,
                            "{name}: body {body} at {fastest} m/s per unit of joint {j}, bound {allowed} (at {s})"
                        );
                    }
                }
            }
        }
    }
    // Tighter than the static reach (by a fifth on some joint) for most moving bodies.
    assert!(tighter * 2 > bodies, "{tighter} of {bodies} moving bodies");
}
