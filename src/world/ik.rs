//! Inverse kinematics of the TCP pose: damped least squares (Levenberg–Marquardt)
//! from several seeded starts, joint values kept inside their limits (revolute
//! joints wrapped by 2π when that brings them inside). Deterministic per seed.

use nalgebra::{Isometry3, Matrix6, Matrix6xX, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::build::RobotModel;
use super::chain::Chain;
use super::urdf::Motion;
use super::Config;
use crate::resolve::Pose;

/// Position (m) and rotation (rad) error under which a solution is accepted.
pub(crate) const IK_TOLERANCE: f64 = 1e-9;
const MAX_ITERATIONS: usize = 150;
/// Two solutions closer than this in every joint are the same.
const DISTINCT: f64 = 1e-4;

/// Pose error (linear; angular), target vs current, both in the base frame.
fn pose_error(target: &Isometry3<f64>, cur: &Isometry3<f64>) -> Vector6<f64> {
    let dp = target.translation.vector - cur.translation.vector;
    let dr = (target.rotation * cur.rotation.inverse()).scaled_axis();
    Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z)
}

fn clamp_into(chain: &Chain, q: &mut [f64], rotational: &[bool]) {
    use std::f64::consts::TAU;
    for ((v, (lo, hi)), rot) in q.iter_mut().zip(&chain.limits).zip(rotational) {
        if *rot {
            while *v > *hi && *v - TAU >= *lo {
                *v -= TAU;
            }
            while *v < *lo && *v + TAU <= *hi {
                *v += TAU;
            }
        }
        *v = v.clamp(*lo, *hi);
    }
}

pub(crate) fn rotational(chain: &Chain) -> Vec<bool> {
    let mut rot = vec![false; chain.dof()];
    for l in &chain.links {
        if let (super::chain::Source::Active { index, .. }, Motion::Rotate(_)) = (l.source, l.motion) {
            rot[index] = true;
        }
    }
    rot
}

/// Refines `q` towards `target` (TCP in the base frame); true when it converged.
pub(crate) fn refine(m: &RobotModel, target: &Isometry3<f64>, q: &mut [f64], rot: &[bool]) -> bool {
    let n = m.chain.dof();
    let mut jac = Matrix6xX::zeros(n);
    let mut trial = q.to_vec();
    let mut lambda = 1e-2;
    let mut cur = m.chain.jacobian(q, &m.pose_flange_tcp, &mut jac);
    let mut err = pose_error(target, &cur);
    let mut norm = err.norm();
    for _ in 0..MAX_ITERATIONS {
        if err.fixed_rows::<3>(0).norm() < IK_TOLERANCE && err.fixed_rows::<3>(3).norm() < IK_TOLERANCE {
            return true;
        }
        let jjt: Matrix6<f64> = &jac * jac.transpose() + Matrix6::identity() * (lambda * lambda);
        let Some(chol) = jjt.cholesky() else { return false };
        let y = chol.solve(&err);
        let dq = jac.transpose() * y;
        for (k, t) in trial.iter_mut().enumerate() {
            *t = q[k] + dq[k];
        }
        clamp_into(&m.chain, &mut trial, rot);
        let next = m.chain.fk_flange(&trial) * m.pose_flange_tcp;
        let next_err = pose_error(target, &next);
        let next_norm = next_err.norm();
        if next_norm < norm {
            q.copy_from_slice(&trial);
            lambda = (lambda * 0.3).max(1e-9);
            cur = m.chain.jacobian(q, &m.pose_flange_tcp, &mut jac);
            err = pose_error(target, &cur);
            norm = next_norm;
        } else {
            lambda *= 5.0;
            if lambda > 1e3 {
                return false;
            }
        }
    }
    err.fixed_rows::<3>(0).norm() < IK_TOLERANCE && err.fixed_rows::<3>(3).norm() < IK_TOLERANCE
}

/// Up to `max_solutions` distinct configurations reaching `pose_world_tcp`.
pub(crate) fn solve(m: &RobotModel, pose_world_tcp: &Pose, seed: u64, max_solutions: usize) -> Vec<Config> {
    let mut out: Vec<Config> = Vec::new();
    if max_solutions == 0 {
        return out;
    }
    let target = m.pose_world_base.inverse() * pose_world_tcp;
    let rot = rotational(&m.chain);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let attempts = 24 + 12 * max_solutions;
    let mut q = vec![0.0; m.chain.dof()];
    let dof = q.len();
    for attempt in 0..attempts {
        for (k, v) in q.iter_mut().enumerate() {
            let (lo, hi) = m.chain.limits[k];
            // First start: the home configuration, a natural posture.
            *v = if attempt == 0 && m.home.len() == dof {
                m.home[k]
            } else if hi > lo {
                rng.random_range(lo..hi)
            } else {
                lo
            };
        }
        if !refine(m, &target, &mut q, &rot) {
            continue;
        }
        if out.iter().all(|s| s.iter().zip(&q).any(|(a, b)| (a - b).abs() > DISTINCT)) {
            out.push(Config(q.clone()));
            if out.len() >= max_solutions {
                break;
            }
        }
    }
    out
}

/// A configuration reaching `pose_world_tcp` starting from `start` (the nearest one, usually).
pub(crate) fn solve_near(m: &RobotModel, pose_world_tcp: &Pose, start: &[f64]) -> Option<Config> {
    let target = m.pose_world_base.inverse() * pose_world_tcp;
    let rot = rotational(&m.chain);
    let mut q = start.to_vec();
    refine(m, &target, &mut q, &rot).then_some(Config(q))
}
