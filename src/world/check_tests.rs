//! Tests of `check.rs`: the moving hulls' boxes, and unturned shapes placed as the full
//! product.

use parry3d_f64::math::{Rotation, Vector as PVec};
use parry3d_f64::shape::SharedShape;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;

#[test]
fn a_moving_hulls_box_holds_its_exact_box_in_any_pose() {
    // A lopsided hull off its own origin (as mesh links are): the turned local box
    // must contain every vertex's world box, or the broad phase would drop a contact.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let pts: Vec<PVec> = (0..60)
        .map(|_| PVec::new(0.3 + 0.2 * rng.random::<f64>(), -0.1 + 0.05 * rng.random::<f64>(), rng.random::<f64>()))
        .collect();
    let hull = SharedShape::convex_hull(&pts).expect("a hull of random points");
    let p = Placed::new(hull, PPose::IDENTITY);
    let mut looser = 0.0f64;
    for _ in 0..1000 {
        let axis = PVec::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
        let rot = Rotation::from_scaled_axis(axis * 6.0);
        let pose = PPose::from_parts(PVec::new(rng.random(), rng.random(), rng.random()), rot);
        let (fast, exact) = (moving_aabb(&p, &pose), p.shape.compute_aabb(&pose));
        assert!(fast.contains(&exact), "{fast:?} does not hold {exact:?}");
        looser = looser.max((fast.volume() / exact.volume()).ln());
    }
    // Not vacuous: the two differ (a box around everything would also pass the above).
    assert!(looser > 0.01 && looser < 3.0, "log volume ratio {looser}");
}

/// A shape flagged unturned is placed by turning its offset only: in every posture of
/// every robot of the shipped examples (the grippers' fingers included) that must be the
/// full product, value for value, wherever the link stands.
#[test]
fn unturned_shapes_are_placed_as_the_full_product() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    // And a finger that turns through 26 postures (a hinge from 0 to 0.5 rad).
    let hinge = std::env::temp_dir().join(format!("declutter-hinge-{}.dcl", std::process::id()));
    let text = format!(
        "scenario \"hinge\"\nhand hinge {{\n    urdf \"{}\"\n    tcp at (0, 0, 5cm)\n}}\nrobot arm {{\n    urdf \"{}\"\n    hand hinge\n    home [0, -20deg, 110deg, 0, 60deg, 0]\n    open [0]\n    closed [0.5]\n}}\nobject block box(2cm, 4cm, 4cm) at (60cm, 0, 2cm) {{\n    grasp top at (0, 0, 1cm) rot (180deg, 0, 0) approach 5cm\n}}\ntarget block\n",
        root.join("tests/fixtures/grippers/hinge_hand.urdf").display(),
        root.join("examples/robots/tx90.urdf").display()
    );
    std::fs::write(&hinge, text).expect("a temporary file");
    let (mut flagged, mut turned) = (0, 0);
    let names = ["box_lid", "gripper", "split_lid", "mesh_part", "three_arm", "reach_pose"];
    for file in names.iter().map(|n| root.join(format!("examples/{n}.dcl"))).chain([hinge.clone()]) {
        let name = file.display();
        let mut sources = crate::diag::SourceMap::new();
        let scn = crate::resolve::resolve(&file, &crate::diag::FsLoader, &mut sources)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let w =
            super::super::build(&scn, &super::super::WorldOptions::default(), &crate::diag::FsLoader).expect("builds");
        for m in &w.robots {
            for (si, sh) in m.shapes.iter().enumerate() {
                flagged += usize::from(sh.unturned);
                for posture in 0..m.postures.len().max(1) {
                    let shape = m.shape_pose(si, posture);
                    turned += usize::from(shape.rotation != Rotation::IDENTITY);
                    let axis =
                        PVec::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
                    let link = PPose::from_parts(
                        PVec::new(rng.random(), rng.random(), rng.random()),
                        Rotation::from_scaled_axis(axis * 6.0),
                    );
                    let (placed, product) = (place(&link, shape, sh.unturned), link * *shape);
                    assert_eq!(placed.translation, product.translation, "{name}: {} shape {si}", m.name);
                    // The same rotation, up to the sign of a zero (x + 0 · y).
                    assert!(
                        placed.rotation.to_array().iter().zip(product.rotation.to_array()).all(|(a, b)| a == &b),
                        "{name}: {} shape {si}",
                        m.name
                    );
                }
            }
        }
    }
    let _ = std::fs::remove_file(&hinge);
    // Both kinds are there: the test is not vacuous either way.
    assert!(flagged > 10 && turned > 10, "{flagged} flagged, {turned} turned in some posture");
}
