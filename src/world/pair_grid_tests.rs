//! The reach that makes a grid sound: moving a pair's joints never changes its distance
//! by more than Σ ρ_i |δ_i|, and that bound is not vacuous; a box gap never overstates.

use parry3d_f64::math::{Pose as PPose, Rotation, Vector as PVec};
use parry3d_f64::shape::SharedShape;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{body_distance, Measure};
use crate::diag::{FsLoader, SourceMap};
use crate::world::lower_bound::LOWER_BOUND_TOLERANCE;
use crate::world::proximity::shape_distance;
use crate::world::shapes::Obb;
use crate::world::{build, World, WorldOptions};

fn example(name: &str) -> World {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(format!("{name}.dcl"));
    let scn = crate::resolve::resolve(&path, &FsLoader, &mut SourceMap::new()).expect("resolves");
    build(&scn, &WorldOptions::default(), &FsLoader).expect("builds")
}

#[test]
fn a_pairs_distance_moves_no_faster_than_its_reach_allows() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut grids, mut measured) = (0, 0);
    for name in ["box_lid", "gripper"] {
        let w = example(name);
        for m in &w.robots {
            for (&(a, b), g) in m.self_pairs.iter().zip(&m.self_grids) {
                let Some(g) = g else { continue };
                grids += 1;
                let mut s = Measure::default();
                let mut tightest = 0.0f64;
                for _ in 0..2000 {
                    let q: Vec<f64> = m.chain.limits.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect();
                    let mut moved = q.clone();
                    let mut bound = 0.0;
                    for (i, reach) in g.reaches() {
                        let (lo, hi) = m.chain.limits[i];
                        moved[i] = (q[i] + rng.random_range(-0.3..0.3)).clamp(lo, hi);
                        bound += reach * (moved[i] - q[i]).abs();
                    }
                    s.q = q;
                    let d0 = body_distance(m, a, b, f64::INFINITY, &mut s).expect("convex shapes");
                    // A lower bound within GJK's dual bound's tolerance of the distance.
                    let exact = s.posed[0]
                        .iter()
                        .flat_map(|(i, pi, _, _)| s.posed[1].iter().map(move |(j, pj, _, _)| (*i, *pi, *j, *pj)))
                        .map(|(i, pi, j, pj)| {
                            let (si, sj) = (&*m.shapes[i].placed.shape.0, &*m.shapes[j].placed.shape.0);
                            shape_distance(&pi, si, &pj, sj).expect("convex")
                        })
                        .fold(f64::INFINITY, f64::min);
                    assert!(d0 <= exact + 1e-9 && d0 >= exact - LOWER_BOUND_TOLERANCE - 1e-9, "{d0} against {exact}");
                    measured += usize::from(exact > 0.0);
                    s.q = moved;
                    let d1 = body_distance(m, a, b, f64::INFINITY, &mut s).expect("convex shapes");
                    let change = (d1 - d0).abs();
                    // Each measure within the tolerance below the distance.
                    assert!(
                        change <= bound + LOWER_BOUND_TOLERANCE + 1e-7,
                        "{name} {}-{}: {change} > {bound}",
                        m.bodies[a].name,
                        m.bodies[b].name
                    );
                    if bound > 1e-3 {
                        tightest = tightest.max(change / bound);
                    }
                }
                // Not a bound so loose that any grid would be useless.
                assert!(
                    tightest > 0.2,
                    "{name} {}-{}: at most {tightest} of the bound",
                    m.bodies[a].name,
                    m.bodies[b].name
                );
            }
        }
    }
    assert!(grids >= 8 && measured > 1000, "only {grids} pairs have grids, {measured} measured apart");
}

#[test]
fn a_box_gap_never_overstates_the_distance() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let shapes = [SharedShape::cuboid(0.1, 0.02, 0.05), SharedShape::cylinder(0.08, 0.03), SharedShape::ball(0.04)];
    let mut apart = 0;
    for k in 0..20_000 {
        let (s1, s2) = (&shapes[k % 3], &shapes[(k / 3) % 3]);
        let mut pose = |spread: f64| {
            let axis = PVec::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
            let at = PVec::new(rng.random::<f64>(), rng.random::<f64>(), rng.random::<f64>()) * spread;
            PPose::from_parts(at, Rotation::from_scaled_axis(axis * 6.0))
        };
        let (p1, p2) = (pose(0.3), pose(0.3));
        let (o1, o2) = (Obb::of(&*s1.0), Obb::of(&*s2.0));
        let gap = o1.gap(&p1, &o2, &p2);
        let d = shape_distance(&p1, &*s1.0, &p2, &*s2.0).expect("convex");
        assert!(gap <= d + 1e-9, "gap {gap} > distance {d}");
        if gap > 0.5 * d && d > 0.01 {
            apart += 1;
        }
    }
    // Not vacuous: the gap is often a good part of the distance.
    assert!(apart > 2000, "{apart}");
}
