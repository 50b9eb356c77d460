//! Balls inside a hull, for proving contacts without GJK.
//!
//! A shape overlaps another at least as deep as any part of it does: a move that parts
//! the hull from a box parts every ball inside the hull too. So a ball inside the hull
//! that meets a box deeper than the contact tolerance proves the hull's contact, for the
//! cost of a point's distance to a box, where the exact test runs GJK and often EPA. In
//! a narrow passage most of a planner's checks are contacts (the UR5's trees through a
//! window: three in five of its hull tests). Only contacts are decided this way; a pair
//! the balls do not prove goes on to the exact test, so no verdict changes.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as PVec;

/// Most balls kept per hull (each costs a point-to-box distance per tested pair).
pub(crate) const MOST: usize = 6;
/// Balls smaller than this (metres) are not kept: they would prove only deep contacts.
const SMALLEST: f64 = 0.01;
/// Candidate centres along the longest axis of the hull's box, and across it per axis
/// (a link is long and narrow: its balls lie along it).
const ALONG: usize = 9;
const ACROSS: usize = 3;
/// The rough bound on a centre's ball takes every this many face planes.
const ROUGH: usize = 16;

/// A ball: centre in the hull's frame, radius.
pub(crate) type Ball = (PVec, f64);

/// Up to [`MOST`] balls inside the hull of `points` bounded by `triangles` (outward or
/// not: each plane is turned to face away from the vertices' mean, inside a convex hull),
/// the largest first: centres drawn from a grid over `bounds`, each ball as large as its
/// centre's distance to the nearest face plane, each new centre outside the balls before.
pub(crate) fn inner_balls(points: &[PVec], triangles: &[[u32; 3]], bounds: &Aabb) -> Vec<Ball> {
    if points.is_empty() {
        return Vec::new();
    }
    let mean = points.iter().fold(PVec::ZERO, |a, p| a + *p) / points.len() as f64;
    let planes: Vec<(PVec, f64)> = triangles
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.map(|i| points.get(i as usize).copied());
            let (a, b, c) = (a?, b?, c?);
            let n = (b - a).cross(c - a);
            let len = n.length();
            (len > 1e-12).then(|| {
                let n = n / len;
                match n.dot(a) >= n.dot(mean) {
                    true => (n, n.dot(a)),
                    false => (-n, -n.dot(a)),
                }
            })
        })
        .collect();
    // A centre's ball: its distance inside every face plane, less a hair for rounding.
    // Every `ROUGH`-th plane alone bounds it from above (fewer planes, a larger polytope).
    let radius = |p: PVec, step: usize| {
        planes.iter().step_by(step).map(|(n, d)| d - n.dot(p)).fold(f64::INFINITY, f64::min) - 1e-9
    };
    let (lo, size) = (bounds.mins, bounds.maxs - bounds.mins);
    let long = (0..3).fold(0, |l, a| if size[a] > size[l] { a } else { l });
    let counts: [usize; 3] = std::array::from_fn(|a| if a == long { ALONG } else { ACROSS });
    let mut centres: Vec<PVec> = Vec::with_capacity(ALONG * ACROSS * ACROSS);
    for i in 0..counts[0] {
        for j in 0..counts[1] {
            for k in 0..counts[2] {
                let f = |n: usize, a: usize| (n as f64 + 0.5) / counts[a] as f64;
                centres.push(lo + size * PVec::new(f(i, 0), f(j, 1), f(k, 2)));
            }
        }
    }
    // Largest ball first, ties in grid order, each kept when its centre is outside the
    // balls kept before: best first on the rough bounds, a centre's exact radius taken
    // only when its bound comes to the top (an exact one on top is the largest left). A
    // hull of two thousand faces measures a dozen centres exactly, not eighty.
    // Keys: radius bits (positive radii order as their bits), then the lower index first.
    let mut queue: BinaryHeap<(u64, Reverse<usize>, bool)> = centres
        .iter()
        .enumerate()
        .map(|(i, &p)| (radius(p, ROUGH), i))
        .filter(|&(r, _)| r >= SMALLEST)
        .map(|(r, i)| (r.to_bits(), Reverse(i), false))
        .collect();
    let mut balls: Vec<Ball> = Vec::new();
    while let Some((bits, Reverse(i), exact)) = queue.pop() {
        if balls.len() == MOST {
            break;
        }
        let p = centres[i];
        // A centre inside a ball kept stays inside (balls are only added): it would be
        // passed over at its turn, so it is now, unmeasured.
        if balls.iter().any(|(c, rc)| (p - *c).length() <= *rc) {
            continue;
        }
        if !exact {
            let r = radius(p, 1);
            if r >= SMALLEST {
                queue.push((r.to_bits(), Reverse(i), true));
            }
        } else {
            balls.push((p, f64::from_bits(bits)));
        }
    }
    balls
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In a 40 x 10 x 10 cm bar, balls of radius 5 cm at most (the half width), none
    /// reaching out of the bar, and the first centred across the bar.
    #[test]
    fn a_bars_balls_lie_inside_it() {
        let h = PVec::new(0.2, 0.05, 0.05);
        let (points, triangles) = super::super::box_mesh(h);
        let bounds = Aabb::new(-h, h);
        let balls = inner_balls(&points, &triangles, &bounds);
        assert!(balls.len() >= 3, "{balls:?}");
        for (c, r) in &balls {
            assert!(*r <= 0.05 + 1e-12, "{c:?} {r}");
            assert!((c.abs() + PVec::splat(*r) - h).max_element() <= 1e-9, "{c:?} {r} leaves the bar");
        }
        // The grid's middle row across the bar: y and z at the centre, the ball touching
        // both long sides.
        let (c, r) = balls[0];
        assert!(c.y.abs() < 1e-12 && c.z.abs() < 1e-12 && (r - 0.05).abs() < 1e-8, "{c:?} {r}");
    }

    /// Inward triangles give the same balls: each plane is turned away from the middle.
    #[test]
    fn the_triangles_winding_does_not_matter() {
        let h = PVec::new(0.1, 0.07, 0.03);
        let (points, triangles) = super::super::box_mesh(h);
        let flipped: Vec<[u32; 3]> = triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
        let bounds = Aabb::new(-h, h);
        assert_eq!(inner_balls(&points, &triangles, &bounds), inner_balls(&points, &flipped, &bounds));
        assert!(!inner_balls(&points, &triangles, &bounds).is_empty());
    }

    /// The best-first choice is the plain one: every centre's exact ball, largest first
    /// (ties in grid order), each kept outside those before. On hulls of random points,
    /// from a few faces (each plane in the rough bound) to hundreds.
    #[test]
    fn best_first_keeps_the_balls_the_plain_greedy_keeps() {
        let mut seed = 99u64;
        let mut rnd = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [8, 20, 60, 200, 600] {
            let pts: Vec<PVec> =
                (0..n).map(|_| PVec::new(0.4 * rnd() - 0.1, 0.12 * rnd(), 0.1 * rnd() + 0.3 * rnd() * rnd())).collect();
            let (points, triangles) = parry3d_f64::transformation::try_convex_hull(&pts).expect("a hull");
            let bounds = Aabb::from_points(points.iter().copied());
            let got = inner_balls(&points, &triangles, &bounds);
            // The plain greedy, every centre measured against every face.
            let mean = points.iter().fold(PVec::ZERO, |a, p| a + *p) / points.len() as f64;
            let planes: Vec<(PVec, f64)> = triangles
                .iter()
                .map(|t| t.map(|i| points[i as usize]))
                .filter(|[a, b, c]| (*b - *a).cross(*c - *a).length() > 1e-12)
                .map(|[a, b, c]| {
                    let n = (b - a).cross(c - a);
                    let n = n / n.length();
                    if n.dot(a) >= n.dot(mean) {
                        (n, n.dot(a))
                    } else {
                        (-n, -n.dot(a))
                    }
                })
                .collect();
            let size = bounds.maxs - bounds.mins;
            let long = (0..3).fold(0, |l, a| if size[a] > size[l] { a } else { l });
            let counts: [usize; 3] = std::array::from_fn(|a| if a == long { ALONG } else { ACROSS });
            let mut all: Vec<Ball> = Vec::new();
            for i in 0..counts[0] {
                for j in 0..counts[1] {
                    for k in 0..counts[2] {
                        let f = |n: usize, a: usize| (n as f64 + 0.5) / counts[a] as f64;
                        let p = bounds.mins + size * PVec::new(f(i, 0), f(j, 1), f(k, 2));
                        let r = planes.iter().map(|(n, d)| d - n.dot(p)).fold(f64::INFINITY, f64::min) - 1e-9;
                        if r >= SMALLEST {
                            all.push((p, r));
                        }
                    }
                }
            }
            all.sort_by(|a, b| b.1.total_cmp(&a.1));
            let mut want: Vec<Ball> = Vec::new();
            for (p, r) in all {
                if want.len() < MOST && want.iter().all(|(c, rc)| (p - *c).length() > *rc) {
                    want.push((p, r));
                }
            }
            assert!(!want.is_empty(), "{n} points");
            assert_eq!(got, want, "{n} points, {} faces", triangles.len());
        }
    }

    /// A hull thinner than the smallest ball keeps none.
    #[test]
    fn a_thin_plate_keeps_no_ball() {
        let h = PVec::new(0.2, 0.2, 0.004);
        let (points, triangles) = super::super::box_mesh(h);
        assert!(inner_balls(&points, &triangles, &Aabb::new(-h, h)).is_empty());
    }
}
