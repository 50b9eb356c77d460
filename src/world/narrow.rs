//! The narrow phase of the labelled check: does one moving shape overlap another deeper
//! than [`CONTACT_TOLERANCE`]? A moving primitive (box, cylinder, capsule, sphere) is
//! eroded by the tolerance once at build time and tested with one `intersection_test` (a
//! box against a box by the fifteen-axis separating test, `boxes_intersect`); a mesh hull
//! is tested with GJK, started along the direction that last separated the pair, then
//! `contact` measures the depth of pairs that intersect, unless GJK's last simplex, a box
//! shrunk by twice the tolerance or a ball inside the hull already proves them that deep.

use std::cell::Cell;

use parry3d_f64::math::{Pose as PPose, Vector as PVec};
use parry3d_f64::query;
use parry3d_f64::query::gjk::VoronoiSimplex;
use parry3d_f64::shape::{Cuboid, Shape};

use super::hull::Ball;
use super::shapes::{ball_meets_box, boxes_intersect, Obb, Placed, CONTACT_TOLERANCE};

/// True when the shapes overlap deeper than the tolerance.
#[cfg(test)]
fn collide(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> bool {
    collide_from(p1, s1, p2, s2, &mut no_start())
}

/// No separating direction known (see [`collide_from`]): GJK starts where parry's would.
#[inline]
pub(super) fn no_start() -> PVec {
    PVec::ZERO
}

/// [`collide`], GJK started along `dir` (in `s1`'s frame) unless it is zero, and `dir`
/// left at the separating direction GJK ends with when the shapes are apart. A planner's
/// checks along a motion ask of each pair nearly the same question again, and the last
/// separating direction usually separates again at once. The verdict does not depend on
/// where GJK starts: apart means a separating plane was found; an overlap it finds is
/// proved deep by its simplex or measured by EPA, and one within GJK's tolerance of
/// touching, whichever GJK says of it, is not deeper than the contact tolerance.
#[inline]
fn collide_from(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, dir: &mut PVec) -> bool {
    let meet = match gjk_meet(p1, s1, p2, s2, dir) {
        Some(m) => m,
        None => match query::intersection_test(p1, s1, p2, s2) {
            Ok(i) if !i.intersecting => Meet::Apart,
            _ => Meet::Overlap,
        },
    };
    match meet {
        Meet::Apart => false,
        Meet::Deep => true,
        Meet::Overlap if surely_deeper(p1, s1, p2, s2) => true,
        Meet::Overlap => match query::contact(p1, s1, p2, s2, 0.0) {
            Ok(Some(c)) if c.dist < -CONTACT_TOLERANCE => true,
            // EPA says shallower than the tolerance: proved when moving the second shape
            // that far along EPA's normal parts them. EPA can fall short (a hull 2.4 mm
            // into a thin box, read as 0.7 mm): unproved is a contact.
            Ok(Some(c)) => !parted_by(p1, s1, p2, s2, c.normal1 * CONTACT_TOLERANCE),
            Ok(None) => false,
            // No depth query for this pair: trust the intersection test.
            Err(_) => true,
        },
    }
}

/// Whether the shapes are apart once the second is moved by `shift`: then no more than
/// `|shift|` separates them where they stand.
fn parted_by(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, shift: PVec) -> bool {
    let moved = PPose::from_parts(p2.translation + shift, p2.rotation);
    query::intersection_test(p1, s1, &moved, s2).is_ok_and(|i| !i.intersecting)
}

/// What an intersection test found.
enum Meet {
    Apart,
    /// Overlapping by more than the contact tolerance.
    Deep,
    /// Overlapping, by how much unknown.
    Overlap,
}

/// parry's own intersection test of two convex shapes it tests with GJK (neither a ball,
/// not two boxes, no triangle: the pairs its dispatcher sends there), keeping GJK's last
/// simplex: `None` for other pairs. Four points of the shapes' Minkowski difference
/// enclosing the origin span a tetrahedron inside it; when the origin lies [`DEEP`]
/// inside each of its faces, no move shorter than that separates the shapes, and the
/// overlap is deeper than the tolerance without EPA (most overlaps of a mesh arm's
/// self-collision samples are centimetres deep).
fn gjk_meet(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape, dir: &mut PVec) -> Option<Meet> {
    let other = |s: &dyn Shape| s.as_ball().is_some() || s.as_triangle().is_some();
    if other(s1) || other(s2) || (s1.as_cuboid().is_some() && s2.as_cuboid().is_some()) {
        return None;
    }
    let (g1, g2) = (s1.as_support_map()?, s2.as_support_map()?);
    let mut simplex = VoronoiSimplex::new();
    let pos12 = p1.inv_mul(p2);
    let start = (*dir != PVec::ZERO).then_some(*dir);
    let (hit, apart) =
        query::details::intersection_test_support_map_support_map_with_params(&pos12, g1, g2, &mut simplex, start);
    if !hit {
        *dir = apart;
    }
    Some(match hit {
        false => Meet::Apart,
        true if origin_deep_in(&simplex, DEEP) => Meet::Deep,
        true => Meet::Overlap,
    })
}

/// Whether `simplex` is a tetrahedron with the origin at least `depth` inside each face.
fn origin_deep_in(simplex: &VoronoiSimplex, depth: f64) -> bool {
    if simplex.dimension() != 3 {
        return false;
    }
    let p: [PVec; 4] = std::array::from_fn(|i| simplex.point(i).point);
    [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)].into_iter().all(|(i, j, k, l)| {
        let n = (p[j] - p[i]).cross(p[k] - p[i]);
        let len = n.length();
        // The face's normal turned away from the fourth point; the origin's depth
        // behind the face is the plane's offset along it.
        let side = n.dot(p[l] - p[i]);
        len > 0.0 && side != 0.0 && -side.signum() * n.dot(p[i]) / len >= depth
    })
}

/// Twice [`CONTACT_TOLERANCE`]: how far inside a box [`surely_deeper`] looks.
const DEEP: f64 = 2.0 * CONTACT_TOLERANCE;

/// Whether two shapes overlap deeper than the tolerance, where one intersection test can
/// prove it: one is a box, the other convex and meeting the box shrunk by [`DEEP`]. A
/// point that deep in the box stays in it however the two are moved apart by less than
/// that, so their penetration depth is at least [`DEEP`]. `false` when not proved (the
/// caller then measures the depth); most planner samples in a cage of bars are deep in one,
/// and this spares EPA.
fn surely_deeper(p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape) -> bool {
    let shrunk = |s: &dyn Shape| {
        let c = s.as_cuboid()?;
        (c.half_extents.min_element() > DEEP).then(|| Cuboid::new(c.half_extents - PVec::splat(DEEP)))
    };
    let meets = |p1: &PPose, s1: &dyn Shape, p2: &PPose, s2: &dyn Shape| {
        query::intersection_test(p1, s1, p2, s2).is_ok_and(|i| i.intersecting)
    };
    match (shrunk(s2), s1.as_support_map().is_some(), shrunk(s1), s2.as_support_map().is_some()) {
        (Some(b), true, _, _) => meets(p1, s1, p2, &b),
        (_, _, Some(a), true) => meets(p1, &a, p2, s2),
        _ => false,
    }
}

/// Collision of a moving shape (robot or carried) with another: by its eroded
/// primitive when it has one (one intersection test), else by contact depth. `balls`:
/// whether to try the balls inside the moving shape first against a box (`false` for
/// the plain check); `proved` counts the contacts they proved.
#[inline]
pub(super) fn collide_moving(
    (p1, moving, balls): (&PPose, &Placed, bool),
    (p2, s2, obb2): (&PPose, &dyn Shape, &Obb),
    dir: &mut PVec,
    proved: &Cell<u64>,
) -> bool {
    if !moving.eroded_obb.as_ref().unwrap_or(&moving.obb).may_touch(p1, obb2, p2) {
        return false;
    }
    if balls && obb2.exact && inner_ball_meets(p1, moving.inner(), &obb2.placed(p2), obb2.cuboid.half_extents) {
        proved.set(proved.get() + 1);
        return true;
    }
    match &moving.eroded {
        Some(e) => match (e.as_cuboid(), s2.as_cuboid()) {
            (Some(c1), Some(c2)) => boxes_intersect(c1.half_extents, c2.half_extents, &p1.inv_mul(p2)),
            _ => query::intersection_test(p1, &*e.0, p2, s2).map_or(true, |i| i.intersecting),
        },
        None => collide_from(p1, &*moving.shape.0, p2, s2, dir),
    }
}

/// Whether one of `inner` (balls inside a shape, in its frame at `p1`), eroded by the
/// contact tolerance, meets the box of half extents `he` at `p2`: a contact deeper than
/// the tolerance. Unsure (within parry's margin of touching) is not a proof, nor is a
/// ball no larger than the tolerance.
#[inline]
fn inner_ball_meets(p1: &PPose, inner: &[Ball], p2: &PPose, he: PVec) -> bool {
    inner.iter().any(|&(c, r)| ball_meets_box(*p1 * c, r - CONTACT_TOLERANCE, p2, he) == Some(true))
}

#[cfg(test)]
#[path = "narrow_tests.rs"]
mod tests;
