//! Closed-form inverse kinematics for the two common 6R families, found from the
//! chain itself (joint axes and offsets at zero), not from a table of robot names:
//!
//! - **spherical wrist** (TX-90, most industrial arms): axes 2 and 3 parallel, axes 4,
//!   5 and 6 meeting in one point, the wrist centre. Up to 8 solutions.
//! - **three parallel axes** (UR5 and the other UR arms): axes 2, 3 and 4 parallel,
//!   axes 5 and 6 meeting. Up to 8 solutions.
//!
//! The chain is written in product-of-exponentials form (each joint an axis `w`
//! through a point `p`, both in the base frame at q = 0), and each family is split
//! into Paden–Kahan subproblems. A detected solver is checked on a few seeded
//! configurations before it is trusted; a chain that fits neither family keeps the
//! numeric solver.

use nalgebra::{Isometry3, Point3, Rotation3, Unit, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::chain::{Chain, Source};
use super::urdf::Motion;

/// Axes closer than this to parallel / intersecting count as such (metres, sines).
pub(super) const GEOMETRY_EPS: f64 = 1e-9;
/// Margins (from ±1 for an `acos`, from 0 for a square root) below which a solution
/// is confirmed by forward kinematics.
pub(super) const CONDITION: f64 = 1e-6;
/// A closed-form solution is accepted when its forward kinematics is this close.
pub(crate) const ACCEPT: f64 = 1e-7;

#[derive(Debug, Clone, Copy)]
pub(super) struct Axis {
    pub(super) w: Vector3<f64>,
    pub(super) p: Vector3<f64>,
}

impl Axis {
    pub(super) fn rot(&self, t: f64) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Unit::new_unchecked(self.w), t)
    }
    /// The point `x` turned by `t` about this axis.
    pub(super) fn turn(&self, t: f64, x: &Vector3<f64>) -> Vector3<f64> {
        self.p + self.rot(t) * (x - self.p)
    }
    /// The turn by `t` as a rigid motion.
    pub(super) fn motion(&self, t: f64) -> Isometry3<f64> {
        let r = self.rot(t);
        Isometry3::from_parts((self.p - r * self.p).into(), r.into())
    }
}

/// The joint axes of a chain of plain revolute joints (no slide, mimic or frozen joint
/// on the path) in the base frame at q = 0, or `None`.
pub(super) fn plain_axes(chain: &Chain) -> Option<Vec<Axis>> {
    let mut axes = Vec::with_capacity(chain.dof());
    let mut t = Isometry3::identity();
    for &l in &chain.path[1..] {
        let link = &chain.links[l];
        t *= link.pose_parent_joint;
        match (link.motion, link.source) {
            (Motion::Fixed, _) | (_, Source::Fixed) => {}
            (Motion::Rotate(a), Source::Active { index, mult, offset })
                if index == axes.len() && mult == 1.0 && offset == 0.0 =>
            {
                axes.push(Axis { w: t.rotation * a.into_inner(), p: t.translation.vector });
            }
            _ => return None,
        }
    }
    Some(axes)
}

#[derive(Debug, Clone, Copy)]
enum Family {
    /// Axes 4, 5, 6 meet at `centre` (base frame, q = 0).
    SphericalWrist { centre: Vector3<f64> },
    /// Axes 5 and 6 meet at `p56`; axes 2, 3, 4 are parallel.
    ThreeParallel { p56: Vector3<f64> },
}

/// A closed-form solver for one chain.
#[derive(Debug, Clone)]
pub(crate) struct Analytic {
    axes: [Axis; 6],
    /// Flange pose at q = 0 (base frame).
    flange0: Isometry3<f64>,
    family: Family,
}

impl Analytic {
    /// The solver for `chain`, when it is a 6R arm of a known family.
    pub fn detect(chain: &Chain) -> Option<Analytic> {
        if chain.dof() != 6 {
            return None;
        }
        // A slide, a mimic, a frozen joint on the path: not a plain 6R arm.
        let axes: [Axis; 6] = plain_axes(chain)?.try_into().ok()?;
        let flange0 = chain.fk_flange(&[0.0; 6]);
        let parallel = |i: usize, j: usize| axes[i].w.cross(&axes[j].w).norm() < GEOMETRY_EPS;
        if !parallel(1, 2) || parallel(0, 1) {
            return None;
        }
        let wrist = meet(&axes[3], &axes[4]).filter(|c| on_axis(&axes[5], c));
        let family = match wrist {
            Some(centre) => Family::SphericalWrist { centre },
            None if parallel(1, 3) && !parallel(4, 1) && !parallel(4, 5) => {
                Family::ThreeParallel { p56: meet(&axes[4], &axes[5])? }
            }
            None => return None,
        };
        let a = Analytic { axes, flange0, family };
        recovers(chain, 0xa11a, |target, _| a.solve(target)).then_some(a)
    }

    /// Every solution for the flange pose `target` (base frame), angles in (-π, π].
    /// Not filtered by limits or checked against forward kinematics.
    pub fn solve(&self, target: &Isometry3<f64>) -> Vec<[f64; 6]> {
        self.solve_conditioned(target).into_iter().map(|(q, _)| q).collect()
    }

    /// [`Analytic::solve`], each solution with whether it is well conditioned: no
    /// `acos` of nearly ±1 and no near-singular wrist on its way, so rounding cannot
    /// have cost more than a few digits and forward kinematics need not confirm it.
    pub fn solve_conditioned(&self, target: &Isometry3<f64>) -> Vec<([f64; 6], bool)> {
        let mut out = Vec::with_capacity(8);
        let [a1, a2, a3, a4, a5, a6] = &self.axes;
        // Rotation and motion of the whole arm, relative to q = 0.
        let r_all: Rotation3<f64> = (target.rotation * self.flange0.rotation.inverse()).to_rotation_matrix();
        let to_target = |x: &Vector3<f64>| -> Vector3<f64> {
            let local = self.flange0.inverse_transform_point(&Point3::from(*x));
            target.transform_point(&local).coords
        };
        match self.family {
            Family::SphericalWrist { centre } => {
                let wc = to_target(&centre);
                let (q1s, ok1) = plane_angle(a1, &(wc - a1.p), &a2.w, a2.w.dot(&(centre - a1.p)));
                for q1 in q1s.into_iter().flatten() {
                    let wp = a1.turn(-q1, &wc);
                    let (q23, ok23) = planar_2r(a2, a3, &centre, &wp);
                    for (q2, q3) in q23 {
                        let r123 = a1.rot(q1) * a2.rot(q2) * a3.rot(q3);
                        let m = r123.inverse() * r_all;
                        let (q456, ok456) = wrist(a4, a5, a6, &m);
                        for (q4, q5, q6) in q456 {
                            out.push(([q1, q2, q3, q4, q5, q6].map(wrap_pi), ok1 && ok23 && ok456));
                        }
                    }
                }
            }
            Family::ThreeParallel { p56 } => {
                let pt = to_target(&p56);
                let d = a2.w;
                let a6_world = r_all * a6.w;
                let (q1s, ok1) = plane_angle(a1, &(pt - a1.p), &d, d.dot(&(p56 - a1.p)));
                for q1 in q1s.into_iter().flatten() {
                    let r1 = a1.rot(q1);
                    let k = d.dot(&(r1.inverse() * a6_world));
                    // d · Rot5(q5) w6 = k: `plane_angle` turns the other way.
                    let (turned, ok5) = plane_angle(&Axis { w: a5.w, p: Vector3::zeros() }, &a6.w, &d, k);
                    for q5 in turned.into_iter().flatten().map(|t| -t) {
                        // N = R1ᵀ R_all = Rot(d, φ) Rot5 Rot6, φ = q2 + q3 + q4.
                        let n = r1.inverse() * r_all;
                        let u = a5.rot(-q5) * d;
                        let q6 = angle_to(&a6.w, &(n.inverse() * d), &u);
                        let r_phi = n * a6.rot(-q6) * a5.rot(-q5);
                        let v = any_normal(&d);
                        let phi = angle_to(&d, &v, &(r_phi * v));
                        let x = a1.turn(-q1, &pt);
                        let y = x - a2.rot(phi) * (p56 - a4.p);
                        // Axis 6 near axis 2's direction: the wrist is near its singularity.
                        let ok6 = u.cross(&a6.w).norm() > CONDITION;
                        let (q23, ok23) = planar_2r(a2, a3, &a4.p, &y);
                        for (q2, q3) in q23 {
                            let q = [q1, q2, q3, phi - q2 - q3, q5, q6].map(wrap_pi);
                            out.push((q, ok1 && ok5 && ok6 && ok23));
                        }
                    }
                }
            }
        }
        out
    }
}

/// Whether `solve` (given a flange pose and the configuration it came from, for a
/// solver that takes part of it as given) recovers a few seeded configurations of
/// `chain`: a family detected wrongly (a geometry these files do not handle) fails here,
/// and the numeric solver stays.
pub(super) fn recovers<const N: usize>(
    chain: &Chain,
    seed: u64,
    solve: impl Fn(&Isometry3<f64>, &[f64]) -> Vec<[f64; N]>,
) -> bool {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..8).all(|_| {
        let q: Vec<f64> =
            chain.limits.iter().map(|(lo, hi)| super::chain::sample_in(&mut rng, lo.max(-3.0), hi.min(3.0))).collect();
        let target = chain.fk_flange(&q);
        solve(&target, &q)
            .iter()
            .any(|s| s.iter().zip(&q).all(|(a, b)| wrap_pi(a - b).abs() < 1e-6) && close(&chain.fk_flange(s), &target))
    })
}

/// The point where two axes meet, if they do.
pub(super) fn meet(a: &Axis, b: &Axis) -> Option<Vector3<f64>> {
    let n = a.w.cross(&b.w);
    let nn = n.norm_squared();
    if nn < GEOMETRY_EPS * GEOMETRY_EPS {
        return None;
    }
    let r = b.p - a.p;
    if r.dot(&n).abs() / nn.sqrt() > GEOMETRY_EPS {
        return None;
    }
    let t = r.cross(&b.w).dot(&n) / nn;
    Some(a.p + a.w * t)
}

pub(super) fn on_axis(a: &Axis, x: &Vector3<f64>) -> bool {
    (x - a.p).cross(&a.w).norm() < GEOMETRY_EPS
}

fn close(a: &Isometry3<f64>, b: &Isometry3<f64>) -> bool {
    (a.translation.vector - b.translation.vector).norm() < ACCEPT && a.rotation.angle_to(&b.rotation) < ACCEPT
}

pub(crate) fn wrap_pi(x: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let y = x.rem_euclid(TAU);
    if y > PI {
        y - TAU
    } else {
        y
    }
}

pub(super) fn any_normal(d: &Vector3<f64>) -> Vector3<f64> {
    let t = if d.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    d.cross(&t).normalize()
}

/// Subproblem 1: the angle about `w` (through the origin) turning `u` onto `v`
/// (their components across `w`).
pub(super) fn angle_to(w: &Vector3<f64>, u: &Vector3<f64>, v: &Vector3<f64>) -> f64 {
    let up = u - w * w.dot(u);
    let vp = v - w * w.dot(v);
    w.dot(&up.cross(&vp)).atan2(up.dot(&vp))
}

/// The angles `t` with `d · Rot(axis, -t) x = k` when `axis.p` is the origin of `x`
/// (`x` relative to the axis point, `k` likewise): `a cos t + b sin t = c`.
fn plane_angle(axis: &Axis, x: &Vector3<f64>, d: &Vector3<f64>, k: f64) -> ([Option<f64>; 2], bool) {
    let w = axis.w;
    let along = w * w.dot(x);
    let a = d.dot(&(x - along));
    let b = -d.dot(&w.cross(x));
    let c = k - d.dot(&along);
    two_angles(a, b, c)
}

/// Solutions of `a cos t + b sin t = c`.
fn two_angles(a: f64, b: f64, c: f64) -> ([Option<f64>; 2], bool) {
    let r = a.hypot(b);
    if r < GEOMETRY_EPS {
        return ([None, None], false);
    }
    let ratio = c / r;
    if ratio.abs() > 1.0 + 1e-9 {
        return ([None, None], false);
    }
    let base = b.atan2(a);
    let delta = ratio.clamp(-1.0, 1.0).acos();
    ([Some(base + delta), Some(base - delta)], 1.0 - ratio.abs() > CONDITION && r > CONDITION)
}

/// Two parallel axes moving `x0` (on a plane across them) onto `target`: (q2, q3) pairs.
fn planar_2r(a2: &Axis, a3: &Axis, x0: &Vector3<f64>, target: &Vector3<f64>) -> (Vec<(f64, f64)>, bool) {
    let w = a2.w;
    // Subproblem 3 about axis 3: |Rot3(q3) x0 - p2| = |target - p2|, across w.
    let across = |v: Vector3<f64>| v - w * w.dot(&v);
    let u = across(x0 - a3.p);
    let v = across(a2.p - a3.p);
    let delta = across(target - a2.p).norm();
    let (nu, nv) = (u.norm(), v.norm());
    let mut out = Vec::with_capacity(2);
    if nu < GEOMETRY_EPS || nv < GEOMETRY_EPS {
        return (out, false);
    }
    let c = (nu * nu + nv * nv - delta * delta) / (2.0 * nu * nv);
    if c.abs() > 1.0 + 1e-9 {
        return (out, false);
    }
    let theta0 = w.dot(&u.cross(&v)).atan2(u.dot(&v));
    let dt = c.clamp(-1.0, 1.0).acos();
    for q3 in [theta0 - dt, theta0 + dt] {
        let x = a3.turn(q3, x0);
        let q2 = angle_to(&w, &(x - a2.p), &(target - a2.p));
        out.push((q2, q3));
        if dt < 1e-12 {
            break;
        }
    }
    (out, 1.0 - c.abs() > CONDITION && delta > CONDITION)
}

/// Subproblem 2 and 1 on a spherical wrist: `Rot4 Rot5 Rot6 = m`.
pub(super) fn wrist(a4: &Axis, a5: &Axis, a6: &Axis, m: &Rotation3<f64>) -> (Vec<(f64, f64, f64)>, bool) {
    let w6 = a6.w;
    let (q45, ok) = two_axes(&a4.w, &a5.w, &w6, &(m * w6));
    let q456 = q45
        .into_iter()
        .map(|(q4, q5)| {
            let rest = a5.rot(-q5) * a4.rot(-q4) * m;
            let v = any_normal(&w6);
            (q4, q5, angle_to(&w6, &v, &(rest * v)))
        })
        .collect();
    (q456, ok)
}

/// Subproblem 2: the angles (a, b) with `Rot(wa, a) Rot(wb, b) x = y`, `x` and `y` unit.
pub(super) fn two_axes(
    wa: &Vector3<f64>,
    wb: &Vector3<f64>,
    x: &Vector3<f64>,
    y: &Vector3<f64>,
) -> (Vec<(f64, f64)>, bool) {
    // z = Rot(wb) x = Rot(wa)⁻¹ y: wb·z = wb·x, wa·z = wa·y, |z| = 1.
    let c = wa.dot(wb);
    let den = 1.0 - c * c;
    let alpha = (wa.dot(y) - c * wb.dot(x)) / den;
    let beta = (wb.dot(x) - c * wa.dot(y)) / den;
    let n = wa.cross(wb);
    let g2 = (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * c) / n.norm_squared();
    let mut out = Vec::with_capacity(2);
    if g2 < -1e-9 {
        return (out, false);
    }
    let g = g2.max(0.0).sqrt();
    for gamma in [g, -g] {
        let z = wa * alpha + wb * beta + n * gamma;
        out.push((angle_to(wa, &z, y), angle_to(wb, x, &z)));
        if g == 0.0 {
            break;
        }
    }
    (out, g2 > CONDITION)
}

#[cfg(test)]
#[path = "analytic_tests.rs"]
mod tests;
