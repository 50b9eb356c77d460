//! Tests of `shapes.rs`: mesh units, erosion, and the box tests against parry and
//! against an oracle of their own.

use super::*;
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::math::Rotation;
use proptest::prelude::*;

/// The largest separation along the six face normals, from `b`'s eight corners
/// projected on each axis: the test's own arithmetic, none of `faces_separate`'s.
fn face_gap_by_corners(a: PVec, b: PVec, pos12: &PPose) -> f64 {
    let corners: Vec<PVec> = (0..8)
        .map(|k| {
            let s = |bit: usize| if k & bit == 0 { 1.0 } else { -1.0 };
            pos12.transform_point(PVec::new(s(1) * b.x, s(2) * b.y, s(4) * b.z))
        })
        .collect();
    let a_corners: Vec<PVec> = (0..8)
        .map(|k| {
            let s = |bit: usize| if k & bit == 0 { 1.0 } else { -1.0 };
            PVec::new(s(1) * a.x, s(2) * a.y, s(4) * a.z)
        })
        .collect();
    let gap_along = |n: PVec| {
        let (lo1, hi1) = a_corners.iter().fold((f64::MAX, f64::MIN), |(l, h), c| (l.min(c.dot(n)), h.max(c.dot(n))));
        let (lo2, hi2) = corners.iter().fold((f64::MAX, f64::MIN), |(l, h), c| (l.min(c.dot(n)), h.max(c.dot(n))));
        (lo2 - hi1).max(lo1 - hi2)
    };
    let b_axes = [PVec::X, PVec::Y, PVec::Z].map(|e| pos12.rotation * e);
    [PVec::X, PVec::Y, PVec::Z].into_iter().chain(b_axes).map(gap_along).fold(f64::MIN, f64::max)
}

/// A vector with each coordinate in `lo..hi`.
fn vector(lo: f64, hi: f64) -> impl Strategy<Value = PVec> {
    (lo..hi, lo..hi, lo..hi).prop_map(|(x, y, z)| PVec::new(x, y, z))
}

/// A rotation about a random axis by up to a turn either way.
fn turn() -> impl Strategy<Value = Rotation> {
    (vector(-1.0, 1.0).prop_filter("an axis", |a| a.length() > 1e-3), -3.2f64..3.2)
        .prop_map(|(axis, angle)| Rotation::from_axis_angle(axis.normalize(), angle))
}

/// Two boxes' half extents and the second's pose in the first's frame, its centre within
/// `reach` along each axis.
fn two_boxes(reach: f64) -> impl Strategy<Value = (PVec, PVec, PPose)> {
    (vector(0.01, 1.0), vector(0.01, 1.0), vector(-reach, reach), turn())
        .prop_map(|(a, b, t, rot)| (a, b, PPose::from_parts(t, rot)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]
    /// A box's placed cuboid is its frame's pose times its centre, to the bit: the shift
    /// turned, the rotation the frame's. Its world box is parry's box of that cuboid but
    /// for rounding (one matrix turns both), and holds the cuboid's eight corners.
    #[test]
    fn a_box_is_placed_as_its_frame_times_its_centre(
        (lo, size, t, rot) in (vector(-1.0, 1.0), vector(0.0, 1.0), vector(-2.0, 2.0), turn())
    ) {
        let obb = Obb::of_aabb(&Aabb::new(lo, lo + size));
        let pose = PPose::from_parts(t, rot);
        let (fast, full) = (obb.placed(&pose), pose * obb.centre);
        prop_assert_eq!(fast.translation, full.translation);
        prop_assert_eq!(fast.rotation, full.rotation);
        let (ours, parry) = (obb.world_aabb(&pose), obb.cuboid.compute_aabb(&full));
        let apart = (ours.mins - parry.mins).abs().max_element().max((ours.maxs - parry.maxs).abs().max_element());
        prop_assert!(apart <= 1e-14, "{:?} against parry's {:?}", ours, parry);
        let h = obb.cuboid.half_extents;
        for k in 0..8 {
            let s = |bit: usize| if k & bit == 0 { 1.0 } else { -1.0 };
            let corner = full.transform_point(PVec::new(s(1) * h.x, s(2) * h.y, s(4) * h.z));
            prop_assert!(ours.loosened(1e-14).contains_local_point(corner), "{:?} outside {:?}", corner, ours);
        }
    }

    /// `faces_separate` says apart exactly when some face normal separates the boxes
    /// (away from the boundary, where rounding may go either way).
    #[test]
    fn faces_separate_as_the_corners_say((a, b, pos12) in two_boxes(2.0)) {
        let gap = face_gap_by_corners(a, b, &pos12);
        prop_assume!(gap.abs() > 1e-9);
        prop_assert_eq!(faces_separate(a, b, &pos12), gap > 0.0, "gap {}", gap);
    }

    /// `boxes_intersect` answers as parry's exact test of two cuboids, away from
    /// touching (the distance between them, by GJK, beyond 1e-9).
    #[test]
    fn boxes_intersect_as_parry_says((a, b, turned) in two_boxes(1.5), quarters in -2i32..=2, square in 0usize..4) {
        // A quarter of the cases turn about a box axis only, by a multiple of 90
        // degrees: parallel edges, where the crossed axes vanish.
        let pos12 = if square == 0 {
            PPose::from_parts(turned.translation, Rotation::from_rotation_z(f64::from(quarters) * std::f64::consts::FRAC_PI_2))
        } else {
            turned
        };
        let (ca, cb) = (Cuboid::new(a), Cuboid::new(b));
        let d = parry3d_f64::query::distance(&PPose::IDENTITY, &ca, &pos12, &cb).expect("convex").distance;
        let deep = parry3d_f64::query::contact(&PPose::IDENTITY, &ca, &pos12, &cb, 0.0).expect("convex");
        prop_assume!(d > 1e-9 || deep.is_some_and(|c| c.dist < -1e-9));
        let parry = parry3d_f64::query::intersection_test(&PPose::IDENTITY, &ca, &pos12, &cb).expect("convex").intersecting;
        prop_assert_eq!(boxes_intersect(a, b, &pos12), parry, "distance {}", d);
    }
}

#[test]
fn boxes_intersect_by_hand() {
    let unit = PVec::splat(0.5);
    let at = |x: f64, y: f64, z: f64| PPose::from_translation(PVec::new(x, y, z));
    assert!(!boxes_intersect(unit, unit, &at(1.01, 0.0, 0.0)));
    assert!(boxes_intersect(unit, unit, &at(0.99, 0.99, 0.99)));
    // b turned 45 degrees about z reaches sqrt(2) / 2 = 0.7071 along x: with a's 0.5,
    // the boxes meet while their centres are less than 1.2071 apart.
    let turned =
        |x: f64| PPose::from_parts(PVec::new(x, 0.0, 0.0), Rotation::from_rotation_z(std::f64::consts::FRAC_PI_4));
    assert!(boxes_intersect(unit, unit, &turned(1.20)));
    assert!(!boxes_intersect(unit, unit, &turned(1.21)));
}

/// Placements where the boxes are apart though no face normal separates them: only a
/// crossed edge axis can say so, and it does.
#[test]
fn boxes_apart_by_an_edge_axis_only_are_apart() {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let mut edge_only = 0;
    for _ in 0..20_000 {
        let mut v =
            |lo: f64, hi: f64| PVec::new(rng.random_range(lo..hi), rng.random_range(lo..hi), rng.random_range(lo..hi));
        let (a, b, t, axis) = (v(0.05, 0.5), v(0.05, 0.5), v(-1.0, 1.0), v(-1.0, 1.0));
        let pos12 = PPose::from_parts(t, Rotation::from_scaled_axis(axis * 3.0));
        let (ca, cb) = (Cuboid::new(a), Cuboid::new(b));
        let d = parry3d_f64::query::distance(&PPose::IDENTITY, &ca, &pos12, &cb).expect("convex").distance;
        if d > 1e-6 && !faces_separate(a, b, &pos12) {
            edge_only += 1;
            assert!(!boxes_intersect(a, b, &pos12), "{a:?} {b:?} {pos12:?}: apart by {d}");
        }
    }
    assert!(edge_only > 50, "only {edge_only} placements apart by an edge axis alone");
}

#[test]
fn faces_separate_by_hand() {
    let unit = PVec::splat(0.5);
    let at = |x: f64, y: f64, z: f64| PPose::from_translation(PVec::new(x, y, z));
    // Unit cubes side by side: apart beyond 1 along an axis, touching within.
    assert!(faces_separate(unit, unit, &at(1.01, 0.0, 0.0)));
    assert!(!faces_separate(unit, unit, &at(0.99, 0.0, 0.0)));
    assert!(!faces_separate(unit, unit, &at(0.0, 0.0, -0.99)));
    // Turned 45 degrees about z, b reaches sqrt(2) / 2 along x: apart beyond 1.2071.
    let turned =
        |x: f64| PPose::from_parts(PVec::new(x, 0.0, 0.0), Rotation::from_rotation_z(std::f64::consts::FRAC_PI_4));
    assert!(faces_separate(unit, unit, &turned(1.21)));
    assert!(!faces_separate(unit, unit, &turned(1.20)));
    // Only b's face normal separates: a plate (2 x 2 x 0.02) turned 45 degrees about
    // x, its normal n = (0, -1, 1) / sqrt(2), its centre at d n. Along n the cube
    // reaches 0.5 sqrt(2) = 0.7071 and the plate 0.01: apart beyond d = 0.7171. Along
    // the cube's y the plate reaches cos 45 + 0.01 sin 45 = 0.7142 from its centre at
    // d / sqrt(2): that axis separates only beyond d = 1.717.
    let plate = PVec::new(1.0, 1.0, 0.01);
    let n = PVec::new(0.0, -1.0, 1.0).normalize();
    let tilted = |d: f64| PPose::from_parts(n * d, Rotation::from_rotation_x(std::f64::consts::FRAC_PI_4));
    assert!(faces_separate(unit, plate, &tilted(0.72)));
    assert!(!faces_separate(unit, plate, &tilted(0.71)));
    assert!(faces_separate(plate, unit, &tilted(0.72).inverse()));
    assert!(!faces_separate(plate, unit, &tilted(0.71).inverse()));
}

#[test]
fn collada_unit_is_read_and_reset() {
    let doc = br#"<COLLADA><asset><unit name="mm" meter='0.001'/></asset></COLLADA>"#;
    let (u, fixed) = collada_unit(doc).expect("ok").expect("a unit");
    assert_eq!(u, 0.001);
    assert_eq!(String::from_utf8(fixed).unwrap(), r#"<COLLADA><asset><unit name="mm" meter='1'/></asset></COLLADA>"#);
    assert_eq!(collada_unit(br#"<asset><unit meter="1"/></asset>"#), Ok(None));
    assert_eq!(collada_unit(b"<asset/>"), Ok(None));
    assert!(collada_unit(br#"<unit meter="-2"/>"#).is_err());
    assert!(collada_unit(br#"<unit meter="NaN"/>"#).is_err());
}

#[test]
fn primitives_are_eroded_meshes_not() {
    for s in [
        SharedShape::cuboid(0.1, 0.2, 0.3),
        SharedShape::ball(0.1),
        SharedShape::cylinder(0.1, 0.05),
        SharedShape::capsule_z(0.1, 0.02),
    ] {
        let p = Placed::new(s, PPose::IDENTITY);
        let e = p.eroded.expect("eroded");
        let (a, b) = (p.shape.compute_local_aabb(), e.compute_local_aabb());
        assert!(((a.maxs - b.maxs).min_element() - 1e-3).abs() < 1e-12, "{a:?} {b:?}");
    }
    let hull = SharedShape::convex_hull(&[
        PVec::new(0.0, 0.0, 0.0),
        PVec::new(1.0, 0.0, 0.0),
        PVec::new(0.0, 1.0, 0.0),
        PVec::new(0.0, 0.0, 1.0),
    ])
    .unwrap();
    assert!(Placed::new(hull, PPose::IDENTITY).eroded.is_none());
}
