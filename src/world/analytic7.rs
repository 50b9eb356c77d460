//! Closed-form inverse kinematics of 7R arms with a spherical shoulder (axes 1, 2 and 3
//! meeting in one point) and axes 5 and 6 meeting (the Panda, the iiwa), for a given
//! value of joint 7, the redundant one the caller samples. Found from the chain, as in
//! [`super::analytic`], not from a table of robot names.
//!
//! In product-of-exponentials form, with joint 7 fixed the rest must give
//! `G = E1 … E6 = T M⁻¹ E7⁻¹`. Axes 5 and 6 leave their meeting point `W` where it is
//! and axes 1–3 leave the shoulder `S`, so:
//! 1. `|E4 W − S| = |G W − S|`: joint 4 alone sets the shoulder–wrist distance
//!    (Paden–Kahan subproblem 3, up to 2 solutions);
//! 2. `R123 (E4 W − S) = G W − S` with `R123 = R_G (R4 R5 R6)ᵀ`, that is
//!    `R5 R6 R_Gᵀ (G W − S) = R4ᵀ (E4 W − S)`: joints 5 and 6 turn one known direction
//!    onto another (subproblem 2, up to 2);
//! 3. `R1 R2 R3 = R_G (R4 R5 R6)ᵀ`: the shoulder as a spherical triple (up to 2).
//!
//! So up to 8 solutions per value of joint 7.

use nalgebra::{Isometry3, Point3, Rotation3, Vector3};

use super::analytic::{meet, on_axis, plain_axes, recovers, two_axes, wrap_pi, wrist, Axis, CONDITION, GEOMETRY_EPS};
use super::chain::Chain;

/// A closed-form solver for one 7R chain, given joint 7.
#[derive(Debug, Clone)]
pub(crate) struct Redundant {
    axes: [Axis; 7],
    /// Flange pose at q = 0 (base frame).
    flange0: Isometry3<f64>,
    /// Where axes 1, 2 and 3 meet.
    shoulder: Vector3<f64>,
    /// Where axes 5 and 6 meet.
    wrist: Vector3<f64>,
}

impl Redundant {
    /// The solver for `chain`, when it is a 7R arm of this family.
    pub fn detect(chain: &Chain) -> Option<Redundant> {
        if chain.dof() != 7 {
            return None;
        }
        let axes: [Axis; 7] = plain_axes(chain)?.try_into().ok()?;
        let parallel = |i: usize, j: usize| axes[i].w.cross(&axes[j].w).norm() < GEOMETRY_EPS;
        // The shoulder triple is solved like a spherical wrist: its first two axes and
        // its last two must cross.
        if parallel(0, 1) || parallel(1, 2) {
            return None;
        }
        let shoulder = meet(&axes[0], &axes[1]).filter(|s| on_axis(&axes[2], s))?;
        let wrist = meet(&axes[4], &axes[5])?;
        // On axis 4, the wrist point would not move with joint 4 (step 1 has no answer).
        if on_axis(&axes[3], &wrist) {
            return None;
        }
        let flange0 = chain.fk_flange(&[0.0; 7]);
        let r = Redundant { axes, flange0, shoulder, wrist };
        let solve = |target: &Isometry3<f64>, q: &[f64]| r.solve_at(target, q[6]).into_iter().map(|(s, _)| s).collect();
        recovers(chain, 0xa117, solve).then_some(r)
    }

    /// Every solution for the flange pose `target` (base frame) with joint 7 at `q7`,
    /// angles in (-π, π] (joint 7 as given), each with whether it is well conditioned
    /// (see [`super::analytic::Analytic::solve_conditioned`]). Not filtered by limits.
    pub fn solve_at(&self, target: &Isometry3<f64>, q7: f64) -> Vec<([f64; 7], bool)> {
        let mut out = Vec::with_capacity(8);
        let [a1, a2, a3, a4, a5, a6, a7] = &self.axes;
        let g = target * self.flange0.inverse() * a7.motion(q7).inverse();
        let r_g: Rotation3<f64> = g.rotation.to_rotation_matrix();
        let p = g.transform_point(&Point3::from(self.wrist)).coords;
        let u = p - self.shoulder;
        let (q4s, ok4) = distance_angles(a4, &self.wrist, &self.shoulder, u.norm());
        for q4 in q4s.into_iter().flatten() {
            let v = a4.turn(q4, &self.wrist) - self.shoulder;
            let (x, y) = (a4.rot(-q4) * v, r_g.inverse() * u);
            let (nx, ny) = (x.norm(), y.norm());
            if nx < GEOMETRY_EPS || ny < GEOMETRY_EPS {
                continue;
            }
            let (q56, ok56) = two_axes(&a5.w, &a6.w, &(y / ny), &(x / nx));
            for (q5, q6) in q56 {
                let r123 = r_g * (a4.rot(q4) * a5.rot(q5) * a6.rot(q6)).inverse();
                let (q123, ok123) = wrist(a1, a2, a3, &r123);
                for (q1, q2, q3) in q123 {
                    let q = [q1, q2, q3, q4, q5, q6].map(wrap_pi);
                    out.push(([q[0], q[1], q[2], q[3], q[4], q[5], q7], ok4 && ok56 && ok123));
                }
            }
        }
        out
    }
}

/// Subproblem 3: the angles turning `x` about `axis` to the distance `delta` from `c`.
fn distance_angles(axis: &Axis, x: &Vector3<f64>, c: &Vector3<f64>, delta: f64) -> ([Option<f64>; 2], bool) {
    let w = axis.w;
    let across = |v: Vector3<f64>| v - w * w.dot(&v);
    let (u, v) = (across(x - axis.p), across(c - axis.p));
    // The offset along the axis does not turn.
    let h = w.dot(&(x - c));
    let d2 = delta * delta - h * h;
    let (nu, nv) = (u.norm(), v.norm());
    if nu < GEOMETRY_EPS || nv < GEOMETRY_EPS || d2 < -1e-12 {
        return ([None, None], false);
    }
    let cos = (nu * nu + nv * nv - d2.max(0.0)) / (2.0 * nu * nv);
    if cos.abs() > 1.0 + 1e-9 {
        return ([None, None], false);
    }
    let theta0 = w.dot(&u.cross(&v)).atan2(u.dot(&v));
    let dt = cos.clamp(-1.0, 1.0).acos();
    let second = (dt > 1e-12).then_some(theta0 + dt);
    ([Some(theta0 - dt), second], 1.0 - cos.abs() > CONDITION)
}
