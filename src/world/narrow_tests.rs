//! Tests of `narrow.rs`: deep overlaps proved without EPA, a hull's balls, a ball against
//! a box.

use parry3d_f64::math::{Rotation, Vector as PVec};
use parry3d_f64::query::gjk::CsoPoint;
use parry3d_f64::shape::SharedShape;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;

/// The contact definition itself: intersecting, and EPA's depth over the tolerance.
fn by_depth(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> bool {
    query::intersection_test(p1, s1, p2, s2).expect("convex").intersecting
        && query::contact(p1, s1, p2, s2, 0.0).expect("convex").is_some_and(|c| c.dist < -CONTACT_TOLERANCE)
}

#[test]
fn a_hull_pressed_into_a_box_face_by_hand() {
    // A 10 cm cube as a hull, pushed `d` into the top face of a 40 cm box: depth `d`.
    let corners: Vec<PVec> =
        (0..8).map(|k| PVec::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64) * 0.1).collect();
    let hull = SharedShape::convex_hull(&corners).expect("a cube");
    let table = Cuboid::new(PVec::splat(0.2));
    let at = |d: f64| PPose::from_translation(PVec::new(-0.05, -0.05, 0.2 - d));
    for (d, deep, hit) in [(0.003, true, true), (0.0015, false, true), (0.0005, false, false)] {
        assert_eq!(surely_deeper(&at(d), &*hull.0, &PPose::IDENTITY, &table), deep, "{d}");
        assert_eq!(surely_deeper(&PPose::IDENTITY, &table, &at(d), &*hull.0), deep, "{d}, the box first");
        assert_eq!(collide(&at(d), &*hull.0, &PPose::IDENTITY, &table), hit, "{d}");
    }
}

/// A hull's balls prove a contact with a box only where the exact test finds one: a
/// 10 cm cube of ours (its largest ball at its centre, touching every face) pushed from 0
/// to 3 mm into a box's face; the balls prove the contacts from just past the tolerance.
#[test]
fn a_hulls_balls_prove_only_contacts_the_exact_test_finds() {
    let corners: Vec<PVec> =
        (0..8).map(|k| PVec::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64) * 0.1).collect();
    let hull = super::super::hull::hull_shape(&corners).expect("a cube");
    let p = Placed::new(hull, PPose::IDENTITY);
    assert!((p.inner()[0].1 - 0.05).abs() < 1e-8, "{:?}", p.inner());
    let table = Cuboid::new(PVec::splat(0.2));
    let obb = Obb::of(&table);
    let at = |d: f64| PPose::from_translation(PVec::new(-0.05, -0.05, 0.2 - d));
    let mut first_proved = None;
    for k in 0..=60 {
        let d = k as f64 * 5e-5;
        let proved = Cell::new(0);
        let box_at = (&PPose::IDENTITY, &table as &dyn Shape, &obb);
        let with = collide_moving((&at(d), &p, true), box_at, &mut no_start(), &proved);
        let without = collide_moving((&at(d), &p, false), box_at, &mut no_start(), &Cell::new(0));
        assert_eq!(with, without, "{d}");
        if (d - CONTACT_TOLERANCE).abs() > 1e-6 {
            assert_eq!(without, d > CONTACT_TOLERANCE, "{d}");
        }
        if proved.get() > 0 {
            first_proved.get_or_insert(d);
        }
    }
    let d = first_proved.expect("deeper contacts proved by the balls");
    assert!((d - (CONTACT_TOLERANCE + 5e-5)).abs() < 1e-9, "first proved at {d}");
}

/// The penetration depth of two convex polytopes (their vertices and triangles, placed),
/// exactly: the least overlap of their projections over every face normal of their
/// Minkowski difference (each one's triangle normals and the cross products of an edge
/// of each); 0 when one of them separates them. Any direction's overlap is at least the
/// depth, and one of those is the depth's own.
fn polytope_depth(a: (&[PVec], &[[u32; 3]]), b: (&[PVec], &[[u32; 3]])) -> f64 {
    let normals = |(pts, tris): (&[PVec], &[[u32; 3]])| -> Vec<PVec> {
        tris.iter()
            .map(|t| (pts[t[1] as usize] - pts[t[0] as usize]).cross(pts[t[2] as usize] - pts[t[0] as usize]))
            .collect()
    };
    let edges = |(pts, tris): (&[PVec], &[[u32; 3]])| -> Vec<PVec> {
        tris.iter()
            .flat_map(|t| [(0, 1), (1, 2), (2, 0)].map(|(i, j)| pts[t[j] as usize] - pts[t[i] as usize]))
            .collect()
    };
    let (ea, eb) = (edges(a), edges(b));
    let crossed = ea.iter().flat_map(|x| eb.iter().map(move |y| x.cross(*y)));
    let span = |pts: &[PVec], n: PVec| {
        pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.dot(n)), hi.max(p.dot(n))))
    };
    let mut depth = f64::INFINITY;
    for n in normals(a).into_iter().chain(normals(b)).chain(crossed) {
        let Some(n) = n.try_normalize().filter(|_| n.length() > 1e-9) else { continue };
        let ((alo, ahi), (blo, bhi)) = (span(a.0, n), span(b.0, n));
        depth = depth.min((ahi - blo).min(bhi - alo));
    }
    depth.max(0.0)
}

#[test]
fn deep_overlaps_proved_by_the_shrunk_box_are_deep_and_collide_answers_as_the_exact_depth_does() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut proved, mut measured) = (0, 0);
    // GJK started from the last pair's separating direction, or from a random one (drawn
    // from a stream of their own): the verdict is the same (see `collide_from`).
    let (mut stale, mut dirs) = (PVec::ZERO, ChaCha8Rng::seed_from_u64(111));
    for _ in 0..20_000 {
        let pts: Vec<PVec> = (0..12).map(|_| PVec::new(rng.random(), rng.random(), rng.random()) * 0.1).collect();
        let hull = SharedShape::convex_hull(&pts).expect("a hull of random points");
        let half = PVec::new(rng.random(), rng.random(), rng.random()) * 0.1 + PVec::splat(0.001);
        let block = Cuboid::new(half);
        let axis = PVec::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
        let turn = Rotation::from_scaled_axis(axis * 6.0);
        // Half anywhere near the box; half pressed into one of its faces (normal `u`)
        // by 0 to 5 mm (the hull's farthest point against `u` that far inside the
        // face's plane, somewhere over the face), where shallow overlaps are.
        let axis = rng.random_range(0..3);
        let mut u = PVec::ZERO;
        u[axis] = if rng.random::<bool>() { 1.0 } else { -1.0 };
        let across = (PVec::new(rng.random(), rng.random(), rng.random()) * 2.0 - PVec::ONE) * half;
        let lowest = pts.iter().map(|p| turn * *p).min_by(|a, b| a.dot(u).total_cmp(&b.dot(u))).expect("points");
        let mut sideways = across - lowest;
        sideways[axis] = 0.0;
        let pressed = (half[axis] - 0.005 * rng.random::<f64>() - lowest.dot(u)) * u + sideways;
        let anywhere = (PVec::new(rng.random(), rng.random(), rng.random()) - PVec::splat(0.5)) * 0.3;
        let pose = PPose::from_parts(if rng.random::<bool>() { pressed } else { anywhere }, turn);
        let (h, id) = (&*hull.0, PPose::IDENTITY);
        // The truth from the exact depth (EPA's can fall short: see the log of
        // 2026-11-27); a depth within rounding of the tolerance decides nothing.
        let (corners, faces) = parry3d_f64::transformation::try_convex_hull(&pts).expect("a hull");
        let placed: Vec<PVec> = corners.iter().map(|p| pose * *p).collect();
        let (box_corners, box_faces) = super::super::hull::box_mesh(half);
        let depth = polytope_depth((&placed, &faces), (&box_corners, &box_faces));
        if (depth - CONTACT_TOLERANCE).abs() < 1e-6 {
            continue;
        }
        let truth = depth > CONTACT_TOLERANCE;
        assert_eq!(collide(&pose, h, &id, &block), truth, "{pose:?} {half:?}: depth {depth}");
        assert_eq!(collide_from(&pose, h, &id, &block, &mut stale), truth, "{pose:?} {half:?} from {stale:?}");
        let mut random = PVec::new(dirs.random::<f64>() - 0.5, dirs.random::<f64>() - 0.5, dirs.random::<f64>() - 0.5);
        assert_eq!(collide_from(&pose, h, &id, &block, &mut random), truth, "{pose:?} {half:?} from {random:?}");
        if surely_deeper(&pose, h, &id, &block) {
            proved += 1;
            assert!(depth > DEEP - 1e-9, "depth {depth} under {DEEP}: {pose:?} {half:?}");
        } else if query::intersection_test(&pose, h, &id, &block).expect("convex").intersecting {
            measured += 1;
        }
    }
    // Both ways are taken: proved deep, and left to EPA.
    assert!(proved > 1000 && measured > 1000, "{proved} proved, {measured} measured");
}

#[test]
fn overlaps_proved_deep_by_gjks_simplex_are_deep_by_epa_and_collide_answers_as_depth_does() {
    // Hull against hull and against a cylinder, anywhere near each other or pressed
    // together 0 to 5 mm along a random direction (where shallow overlaps are).
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let (mut proved, mut measured) = (0, 0);
    let cloud = |rng: &mut ChaCha8Rng| -> Vec<PVec> {
        (0..12).map(|_| PVec::new(rng.random(), rng.random(), rng.random()) * 0.1).collect()
    };
    let mut stale = PVec::ZERO;
    for k in 0..20_000 {
        let a = SharedShape::convex_hull(&cloud(&mut rng)).expect("a hull of random points");
        let b = match k % 2 {
            0 => SharedShape::convex_hull(&cloud(&mut rng)).expect("a hull of random points"),
            _ => SharedShape::cylinder(0.01 + 0.05 * rng.random::<f64>(), 0.01 + 0.05 * rng.random::<f64>()),
        };
        let axis = PVec::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
        let turn = Rotation::from_scaled_axis(axis * 6.0);
        let anywhere = (PVec::new(rng.random(), rng.random(), rng.random()) - PVec::splat(0.5)) * 0.12;
        let mut pose = PPose::from_parts(anywhere, turn);
        if rng.random::<bool>() {
            // Slide `b` along `u` until it just touches `a`, then press it in by up to 5 mm.
            let u = (PVec::new(rng.random(), rng.random(), rng.random()) - PVec::splat(0.5)).normalize();
            let id = PPose::IDENTITY;
            let apart = |t: f64| PPose::from_parts(anywhere + u * t, turn);
            let (mut lo, mut hi) = (-1.0, 1.0);
            if !query::intersection_test(&id, &*a.0, &apart(lo), &*b.0).expect("convex").intersecting
                || query::intersection_test(&id, &*a.0, &apart(hi), &*b.0).expect("convex").intersecting
            {
                continue;
            }
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                match query::intersection_test(&id, &*a.0, &apart(mid), &*b.0).expect("convex").intersecting {
                    true => lo = mid,
                    false => hi = mid,
                }
            }
            pose = apart(hi - 0.005 * rng.random::<f64>());
        }
        let id = PPose::IDENTITY;
        let (sa, sb) = (&*a.0, &*b.0);
        let truth = by_depth(&id, sa, &pose, sb);
        assert_eq!(collide(&id, sa, &pose, sb), truth, "{pose:?}");
        assert_eq!(collide_from(&id, sa, &pose, sb, &mut stale), truth, "{pose:?} from {stale:?}");
        match gjk_meet(&id, sa, &pose, sb, &mut no_start()).expect("two shapes GJK tests") {
            Meet::Deep => {
                proved += 1;
                let depth = -query::contact(&id, sa, &pose, sb, 0.0).expect("convex").expect("touching").dist;
                assert!(depth > DEEP - 1e-9, "EPA {depth} under {DEEP}: {pose:?}");
            }
            Meet::Overlap => measured += 1,
            Meet::Apart => assert!(!query::intersection_test(&id, sa, &pose, sb).expect("convex").intersecting),
        }
    }
    // Both ways are taken: proved deep, and left to EPA.
    assert!(proved > 500 && measured > 500, "{proved} proved, {measured} measured");
}

#[test]
fn a_tetrahedron_holds_the_origin_deep_inside_by_hand() {
    // The corner tetrahedron x, y, z >= -0.01, x + y + z <= 0.03: the origin is 1 cm
    // from the three axis faces and 0.03 / sqrt 3 = 17.3 mm from the slanted one.
    let corner = |x: f64, y: f64, z: f64| CsoPoint::single_point(PVec::new(x, y, z));
    let mut s = VoronoiSimplex::new();
    s.reset(corner(-0.01, -0.01, -0.01));
    for p in [corner(0.05, -0.01, -0.01), corner(-0.01, 0.05, -0.01), corner(-0.01, -0.01, 0.05)] {
        assert!(s.add_point(p));
    }
    assert!(origin_deep_in(&s, 0.0099));
    assert!(!origin_deep_in(&s, 0.0101));
    // Moved 2 cm along +x, the face x = 0.01 passes the origin: it is outside.
    let mut t = VoronoiSimplex::new();
    t.reset(corner(0.01, -0.01, -0.01));
    for p in [corner(0.07, -0.01, -0.01), corner(0.01, 0.05, -0.01), corner(0.01, -0.01, 0.05)] {
        assert!(t.add_point(p));
    }
    assert!(!origin_deep_in(&t, 0.0));
}

/// A ball against a turned box, the centre anywhere near it in half the draws and in the
/// others at the ball's radius from the box give or take 0 to 10 nm (where parry's own
/// arithmetic must decide): wherever `ball_meets_box` decides, parry's intersection test
/// agrees, and it decides every ball more than 10 nm from touching. (A sign slip, a full
/// extent taken for a half one or a margin of 0 fails it.)
#[test]
fn a_ball_against_a_box_decides_as_parry_does_or_leaves_it_to_parry() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let (mut decided, mut left) = (0, 0);
    for i in 0..20_000 {
        let half = PVec::new(rng.random(), rng.random(), rng.random()) * 0.2 + PVec::splat(0.001);
        let axis = PVec::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
        let shift = (PVec::new(rng.random(), rng.random(), rng.random()) - PVec::splat(0.5)) * 2.0;
        let pose = PPose::from_parts(shift, Rotation::from_scaled_axis(axis * 6.0));
        let local = (PVec::new(rng.random(), rng.random(), rng.random()) - PVec::splat(0.5)) * 0.8;
        let outside = (local.abs() - half).max(PVec::ZERO).length();
        let r = if i % 2 == 0 || outside == 0.0 {
            rng.random::<f64>() * 0.1 + 1e-4
        } else {
            outside + (rng.random::<f64>() - 0.5) * 2e-8
        };
        let centre = pose.translation + pose.rotation * local;
        let parry = query::intersection_test(
            &PPose::from_translation(centre),
            &parry3d_f64::shape::Ball::new(r),
            &pose,
            &Cuboid::new(half),
        )
        .expect("ball and box")
        .intersecting;
        match ball_meets_box(centre, r, &pose, half) {
            Some(hit) => {
                assert_eq!(hit, parry, "{local:?} {half:?} {r}");
                decided += 1;
            }
            None => {
                assert!((outside - r).abs() < 1e-8, "left to parry {} from touching", outside - r);
                left += 1;
            }
        }
    }
    assert!(decided > 10_000 && left > 100, "{decided} decided, {left} left to parry");
}
