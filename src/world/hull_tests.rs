//! The climbing support function against parry's scan: on random point clouds, and on
//! every collision mesh of `../shared/robots`, where GJK's verdicts and distances against
//! boxes, cylinders, balls and the robot's other hulls must come out the same.

use std::path::{Path, PathBuf};

use parry3d_f64::math::{Pose as PPose, Vector as PVec};
use parry3d_f64::query;
use parry3d_f64::shape::{Shape, SharedShape, SupportMap};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{as_convex_mesh, cell, cell_centre, closed, hull_shape, mesh_hull, scan, Hull, Plateau, CELLS, SIDE};

fn random_dir(rng: &mut ChaCha8Rng) -> PVec {
    PVec::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
}

/// Directions where ties are likely and where the cube map's cells meet: the axes, the
/// cube's diagonals, every cell's centre and corners.
fn awkward_dirs() -> Vec<PVec> {
    let mut dirs = vec![PVec::X, PVec::Y, PVec::Z, -PVec::X, -PVec::Y, -PVec::Z];
    for i in 0..8 {
        let s = |bit: usize| if i & bit == 0 { 1.0 } else { -1.0 };
        dirs.push(PVec::new(s(1), s(2), s(4)));
    }
    let edge = 2.0 / SIDE as f64;
    for c in 0..CELLS {
        let d = cell_centre(c);
        dirs.push(d);
        // The corners: step half a cell both ways along the two minor axes.
        let major = d.abs().max_position();
        for (du, dv) in [(-0.5, -0.5), (-0.5, 0.5), (0.5, -0.5), (0.5, 0.5)] {
            let mut x = d;
            x[(major + 1) % 3] += du * edge;
            x[(major + 2) % 3] += dv * edge;
            dirs.push(x);
        }
    }
    dirs
}

#[test]
fn each_cell_centre_falls_in_its_own_cell() {
    for c in 0..CELLS {
        assert_eq!(cell(cell_centre(c)), c, "{:?}", cell_centre(c));
    }
    // By hand: +x is face 0; its centre row and column are SIDE / 2 (the upper half).
    assert_eq!(cell(PVec::X), SIDE / 2 * SIDE + SIDE / 2);
    // -z, with y at the face's lower edge and x at its upper: face 5, row SIDE - 1, column 0.
    assert_eq!(cell(PVec::new(1.0, -1.0, -1.0 - 1e-9)), 5 * SIDE * SIDE + (SIDE - 1) * SIDE);
    // Degenerate directions land in some cell.
    for d in [PVec::ZERO, PVec::splat(f64::NAN), PVec::new(f64::INFINITY, 1.0, 0.0)] {
        assert!(cell(d) < CELLS, "{d:?}");
    }
}

fn hull_of(shape: &SharedShape) -> &Hull {
    shape.as_shape::<Hull>().expect("hull_shape makes a Hull")
}

/// The climb returns the scan's vertex: the farthest, and of equally far ones the first
/// (ties are common along the axes and on flat faces).
fn assert_climb_matches_scan(h: &Hull, dirs: impl IntoIterator<Item = PVec>, what: &str) {
    for d in dirs {
        assert_eq!(h.support_index(d), scan(h.points(), d), "{what}, {d:?}");
    }
}

#[test]
fn the_climb_reaches_as_far_as_the_scan() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for trial in 0..20 {
        let pts: Vec<PVec> = (0..50 + 40 * trial)
            .map(|_| {
                let v = random_dir(&mut rng);
                // Even trials put many points on a box's faces: ties along the axes.
                if trial % 2 == 0 {
                    v.clamp(PVec::splat(-0.6), PVec::splat(0.6))
                } else {
                    v * PVec::new(0.1, 1.0, 0.5)
                }
            })
            .collect();
        let shape = hull_shape(&pts).expect("a solid hull");
        let h = hull_of(&shape);
        let mut dirs = awkward_dirs();
        dirs.extend((0..500).map(|_| random_dir(&mut rng)));
        assert_climb_matches_scan(h, dirs, &format!("trial {trial}"));
    }
}

fn collision_meshes(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            collision_meshes(&p, out);
        } else if p.components().any(|c| c.as_os_str() == "collision")
            && p.extension().is_some_and(|e| ["stl", "obj", "dae"].iter().any(|x| e.eq_ignore_ascii_case(x)))
        {
            out.push(p);
        }
    }
}

fn mesh_of(path: &Path) -> (Vec<PVec>, Vec<[u32; 3]>) {
    let scene = mesh_loader::Loader::default().merge_meshes(true).load(path).expect("a readable mesh");
    let mut points = Vec::new();
    let mut triangles = Vec::new();
    for m in &scene.meshes {
        let base = points.len() as u32;
        points.extend(m.vertices.iter().map(|v| PVec::new(v[0] as f64, v[1] as f64, v[2] as f64)));
        triangles.extend(m.faces.iter().map(|f| f.map(|i| i + base)));
    }
    (points, triangles)
}

/// GJK stops once its bounds are within a relative tolerance, and which of two equally
/// far vertices a support query returns changes its path: distances and depths may
/// differ at that level, far below the contact tolerance (1 mm).
const GJK_ACCURACY: f64 = 1e-7;

/// Same verdict, distance and depth from GJK whichever support function the hull uses.
fn assert_queries_agree(pose: &PPose, a: &Hull, b: &dyn Shape, what: &str) -> bool {
    let id = PPose::IDENTITY;
    let poly: &dyn Shape = a.poly();
    let hit = |s: &dyn Shape| query::intersection_test(&id, s, pose, b).expect("convex pair").intersecting;
    assert_eq!(hit(a), hit(poly), "{what}: intersection at {pose:?}");
    let dist = |s: &dyn Shape| super::super::proximity::shape_distance(&id, s, pose, b).expect("convex pair");
    let (d1, d2) = (dist(a), dist(poly));
    assert!((d1 - d2).abs() <= GJK_ACCURACY, "{what}: distance {d1} against {d2} at {pose:?}");
    let depth = |s: &dyn Shape| query::contact(&id, s, pose, b, 0.0).expect("convex pair").map(|c| c.dist);
    match (depth(a), depth(poly)) {
        (Some(x), Some(y)) => assert!((x - y).abs() <= GJK_ACCURACY, "{what}: depth {x} against {y} at {pose:?}"),
        (x, y) => assert_eq!(x.is_some(), y.is_some(), "{what}: contact at {pose:?}"),
    }
    hit(a)
}

/// Every collision mesh of the shared robot packages: the hull of its distinct points
/// has the vertices of the hull of all its points, the climb agrees with the scan on
/// 2 000 directions, and 100 000 GJK queries per robot, with the other shape placed
/// around the hull so that many pairs are near contact, agree.
#[test]
fn every_shared_collision_mesh_answers_as_parrys_hull() {
    let shared = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/robots");
    if !shared.is_dir() {
        eprintln!("skipped: {} is absent", shared.display());
        return;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let robots = ["tx90", "ur5", "panda", "iiwa"];
    let (mut checked, mut hits, mut fast) = (0, 0, 0);
    for robot in robots {
        let mut meshes = Vec::new();
        collision_meshes(&shared.join(robot), &mut meshes);
        assert!(!meshes.is_empty(), "{robot}: no collision meshes under {}", shared.display());
        let hulls: Vec<(String, SharedShape)> = meshes
            .iter()
            .map(|p| {
                let (raw, triangles) = mesh_of(p);
                fast += usize::from(as_convex_mesh(&raw, &triangles).is_some());
                let shape = mesh_hull(&raw, &triangles).expect("a solid hull");
                let parry = SharedShape::convex_hull(&raw).expect("a solid hull");
                let key = |pts: &[PVec]| {
                    let mut k: Vec<[u64; 3]> = pts.iter().map(|v| v.to_array().map(f64::to_bits)).collect();
                    k.sort_unstable();
                    k
                };
                let parry_pts = parry.as_convex_polyhedron().expect("parry's hull").points();
                assert_eq!(key(hull_of(&shape).points()), key(parry_pts), "{}: hull vertices", p.display());
                (p.display().to_string(), shape)
            })
            .collect();
        let per_mesh = 100_000 / hulls.len();
        for (i, (name, shape)) in hulls.iter().enumerate() {
            let h = hull_of(shape);
            assert_climb_matches_scan(h, (0..2000).map(|_| random_dir(&mut rng)), name);
            let aabb = h.poly().local_aabb();
            let others: [SharedShape; 4] = [
                SharedShape::cuboid(0.05, 0.2, 0.01),
                SharedShape::cylinder(0.1, 0.03),
                SharedShape::ball(0.04),
                hulls[(i + 1) % hulls.len()].1.clone(),
            ];
            for k in 0..per_mesh {
                let at = PVec::new(
                    rng.random_range(aabb.mins.x - 0.1..aabb.maxs.x + 0.1),
                    rng.random_range(aabb.mins.y - 0.1..aabb.maxs.y + 0.1),
                    rng.random_range(aabb.mins.z - 0.1..aabb.maxs.z + 0.1),
                );
                let axis = random_dir(&mut rng) * rng.random_range(0.0..std::f64::consts::PI);
                let pose = PPose::new(at, axis);
                hits += usize::from(assert_queries_agree(&pose, h, &*others[k % others.len()].0, name));
                checked += 1;
            }
        }
    }
    eprintln!("{fast} meshes are their own hull");
    // Both verdicts common: the poses are near the hulls, not all inside or far away.
    assert!(checked >= 390_000 && hits > checked / 5 && hits < checked * 4 / 5, "{hits} of {checked} intersect");
}

/// The six vertices of the unit octahedron and its eight outward triangles, each with
/// its own copies of its corners (as STL files store them).
fn octahedron() -> (Vec<PVec>, Vec<[u32; 3]>) {
    let mut points = Vec::new();
    for sx in [1.0, -1.0] {
        for sy in [1.0, -1.0] {
            for sz in [1.0, -1.0] {
                let (x, y, z) = (PVec::X * sx, PVec::Y * sy, PVec::Z * sz);
                // Counter-clockwise seen from outside.
                points.extend(if sx * sy * sz > 0.0 { [x, y, z] } else { [x, z, y] });
            }
        }
    }
    let triangles = (0..8).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    (points, triangles)
}

#[test]
fn only_closed_outward_convex_meshes_skip_the_hull() {
    let (points, triangles) = octahedron();
    let (vertices, tris) = as_convex_mesh(&points, &triangles).expect("the octahedron is convex");
    assert_eq!((vertices.len(), tris.len()), (6, 8));
    // A dent: the top vertex pushed below the equator.
    let dented: Vec<PVec> = points.iter().map(|p| if *p == PVec::Z { PVec::Z * -0.5 } else { *p }).collect();
    assert!(as_convex_mesh(&dented, &triangles).is_none(), "dented");
    // Flattening the top to the equator's plane keeps it convex (coplanar faces).
    let flat: Vec<PVec> = points.iter().map(|p| if *p == PVec::Z { PVec::ZERO } else { *p }).collect();
    assert!(as_convex_mesh(&flat, &triangles).is_some(), "flat top");
    // Open: a triangle missing.
    assert!(as_convex_mesh(&points, &triangles[1..]).is_none(), "open");
    // Inside out: every triangle wound the other way.
    let inward: Vec<[u32; 3]> = triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
    assert!(as_convex_mesh(&points, &inward).is_none(), "inside out");
    // Two octahedra: closed and convex piece by piece, but not one hull.
    let mut two = points.clone();
    two.extend(points.iter().map(|p| *p + PVec::X * 3.0));
    let mut both = triangles.clone();
    both.extend(triangles.iter().map(|t| t.map(|i| i + 24)));
    assert!(as_convex_mesh(&two, &both).is_none(), "two pieces");
    // A face index past the vertices.
    assert!(as_convex_mesh(&points, &[[0, 1, 99]]).is_none(), "bad index");
}

/// What a quickhull's triangles must be before a hull is built on them without parry's
/// polyhedron (built later, on first use, from the same triangles): closed.
#[test]
fn closed_means_every_edge_twice_once_each_way() {
    let (vertices, tris) = as_convex_mesh(&octahedron().0, &octahedron().1).expect("convex");
    assert!(closed(vertices.len(), &tris));
    assert!(!closed(vertices.len(), &tris[1..]), "a triangle missing");
    let mut doubled = tris.clone();
    doubled.push(tris[0]);
    assert!(!closed(vertices.len(), &doubled), "a triangle twice");
    let mut repeated = tris.clone();
    repeated[0] = [tris[0][0], tris[0][0], tris[0][1]];
    assert!(!closed(vertices.len(), &repeated), "a corner repeated");
    assert!(!closed(3, &tris), "an index past the vertices");
    // The hull of a cloud: closed, and parry's polyhedron of it, built on first use, has
    // the same vertices in the same order.
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let cloud: Vec<PVec> = (0..200).map(|_| random_dir(&mut rng)).collect();
    let shape = hull_shape(&cloud).expect("a solid hull");
    let h = hull_of(&shape);
    assert_eq!(h.poly().points(), h.points());
}

/// The flattened octahedron's centre is a vertex inside its top face: seen from below,
/// its neighbours (the face's corners) all tie with it, and the climb must go on from the
/// face's rim to the bottom vertex.
#[test]
fn a_climb_leaves_a_flat_face_it_stands_inside() {
    let (points, triangles) = octahedron();
    let flat: Vec<PVec> = points.iter().map(|p| if *p == PVec::Z { PVec::ZERO } else { *p }).collect();
    let shape = super::convex_mesh_shape(&flat, &triangles).expect("convex");
    let h = hull_of(&shape);
    let pts = h.points();
    let centre = pts.iter().position(|p| *p == PVec::ZERO).expect("the centre is a vertex");
    let bottom = pts.iter().position(|p| *p == -PVec::Z).expect("the bottom vertex");
    assert_eq!(h.off_plateau(centre, 0.0, -PVec::Z), Plateau::Beyond(bottom));
    // Upwards the face is the farthest: nothing beyond it, and the answer is the face's
    // first vertex, as parry's scan's.
    let first = pts.iter().position(|p| p.z == 0.0).expect("a vertex on the face");
    assert_eq!(h.off_plateau(centre, 0.0, PVec::Z), Plateau::Top(first));
    assert_eq!(h.support_index(PVec::Z), first);
    assert_eq!(h.support_index(PVec::Z), scan(pts, PVec::Z));
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut dirs = awkward_dirs();
    dirs.extend((0..200).map(|_| random_dir(&mut rng)));
    assert_climb_matches_scan(h, dirs, "flat octahedron");
    // A direction that is no direction still ends the climb, at some vertex.
    for d in [PVec::ZERO, PVec::splat(f64::NAN), PVec::new(f64::INFINITY, 1.0, 0.0)] {
        assert!(h.support_index(d) < pts.len(), "{d:?}");
    }
}

/// A cube whose corner `(1, 1, 1)` is raised by 0.1 (corner 6), its top cut along the
/// diagonal 5-7 that does not reach that corner: the top bends inwards there, as an
/// exporter's quad cut the wrong way does.
fn cube_cut_along_a_valley(corner6: PVec) -> (Vec<PVec>, Vec<[u32; 3]>) {
    let mut points: Vec<PVec> =
        [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
            .iter()
            .map(|&(x, y, z)| PVec::new(x as f64, y as f64, z as f64))
            .collect();
    points[6] = corner6;
    // Bottom, top (cut along 5-7), front, back, left, right; each wound outwards.
    let triangles = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 7],
        [5, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [2, 3, 7],
        [2, 7, 6],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ];
    (points, triangles)
}

#[test]
fn a_quad_cut_along_its_valley_is_flipped_to_its_ridge() {
    let (points, triangles) = cube_cut_along_a_valley(PVec::new(1.0, 1.0, 1.1));
    let (vertices, tris) = as_convex_mesh(&points, &triangles).expect("convex once flipped");
    assert_eq!((vertices.len(), tris.len()), (8, 12));
    let has = |a: u32, b: u32| tris.iter().any(|t| t.contains(&a) && t.contains(&b));
    assert!(has(4, 6) && !has(5, 7), "the top is cut along 4-6 now: {tris:?}");
    // The same solid as parry's hull of the points.
    let shape = mesh_hull(&points, &triangles).expect("a hull");
    let parry = SharedShape::convex_hull(&points).expect("parry's hull");
    for d in awkward_dirs() {
        let (ours, theirs) =
            (hull_of(&shape).local_support_point(d), parry.as_support_map().expect("convex").local_support_point(d));
        assert!(ours.dot(d) >= theirs.dot(d) - 1e-12 && theirs.dot(d) >= ours.dot(d) - 1e-12, "{d:?}");
    }
    // A corner pushed inside the others' hull (below the plane x + y + z = 1 of corners 2,
    // 5 and 7) cannot be flipped onto it: quickhull decides, and drops it.
    let (dented, triangles) = cube_cut_along_a_valley(PVec::new(0.2, 0.2, 0.2));
    assert!(as_convex_mesh(&dented, &triangles).is_none(), "dented");
    assert_eq!(hull_of(&mesh_hull(&dented, &triangles).expect("a hull")).points().len(), 7);
}
