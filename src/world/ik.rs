//! Inverse kinematics of the TCP pose: the closed form of [`super::analytic`] when
//! the arm has one (every in-limit solution, nearest home first), that of
//! [`super::analytic7`] for a 7R arm of its family (joint 7 sampled), else damped least
//! squares (Levenberg–Marquardt) from several seeded starts, joint values kept inside
//! their limits (revolute joints wrapped by 2π when that brings them inside).
//! Deterministic per seed.

use nalgebra::{Isometry3, Matrix6, Matrix6xX, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::analytic::{self, Analytic};
use super::analytic7::Redundant;
use super::chain::Chain;
use super::robot::RobotModel;
use super::urdf::Motion;
use super::Config;
use crate::resolve::Pose;

/// Position (m) and rotation (rad) error under which a solution is accepted.
pub(crate) const IK_TOLERANCE: f64 = 1e-9;
/// A converging start needs about 15 iterations on average (shipped examples); one
/// still far off after 40 is stuck (at a limit or a singularity) and another start is cheaper.
const MAX_ITERATIONS: usize = 40;
/// Two solutions closer than this in every joint are the same.
const DISTINCT: f64 = 1e-4;

/// Pose error (linear; angular), target vs current, both in the base frame.
fn pose_error(target: &Isometry3<f64>, cur: &Isometry3<f64>) -> Vector6<f64> {
    let dp = target.translation.vector - cur.translation.vector;
    let dr = (target.rotation * cur.rotation.inverse()).scaled_axis();
    Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z)
}

fn clamp_into(chain: &Chain, q: &mut [f64], rotational: &[bool]) {
    clamp_limits(&chain.limits, q, rotational)
}

/// Brings each value inside its limits, by whole turns for revolute joints when that
/// suffices, else by clamping.
fn clamp_limits(limits: &[(f64, f64)], q: &mut [f64], rotational: &[bool]) {
    use std::f64::consts::TAU;
    for ((v, (lo, hi)), rot) in q.iter_mut().zip(limits).zip(rotational) {
        if *rot && v.is_finite() {
            // Far outside, jump by whole turns at once: a huge DLS step would loop for
            // ages, and forever past 1e17 where `v - TAU == v`. Nearer, the loops below
            // keep results bit-identical to the pinned schedules.
            const FAR: f64 = 64.0 * TAU;
            if *v - *hi > FAR {
                let k = ((*v - *hi) / TAU).ceil();
                // When no whole turn lands inside, the loop would end clamped at `hi`.
                *v = if *v - k * TAU >= *lo { *v - k * TAU } else { *hi };
            } else if *lo - *v > FAR {
                let k = ((*lo - *v) / TAU).ceil();
                *v = if *v + k * TAU <= *hi { *v + k * TAU } else { *lo };
            }
            while *v > *hi && *v - TAU >= *lo {
                *v -= TAU;
            }
            while *v < *lo && *v + TAU <= *hi {
                *v += TAU;
            }
        }
        // (Limits are finite and ordered, checked at load, so `clamp` cannot panic.)
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
    refine_chain(&m.chain, &m.pose_flange_tcp, target, q, rot)
}

/// [`refine`] on a bare chain and TCP offset.
pub(crate) fn refine_chain(
    chain: &Chain,
    pose_flange_tcp: &Isometry3<f64>,
    target: &Isometry3<f64>,
    q: &mut [f64],
    rot: &[bool],
) -> bool {
    let n = chain.dof();
    let mut jac = Matrix6xX::zeros(n);
    let mut jac_trial = Matrix6xX::zeros(n);
    let mut trial = q.to_vec();
    let mut lambda = 1e-2;
    let cur = chain.jacobian(q, pose_flange_tcp, &mut jac);
    let mut err = pose_error(target, &cur);
    let mut norm = err.norm();
    for _ in 0..MAX_ITERATIONS {
        if err.fixed_rows::<3>(0).norm() < IK_TOLERANCE && err.fixed_rows::<3>(3).norm() < IK_TOLERANCE {
            return true;
        }
        // J Jᵀ + λ²I and Jᵀ y column by column: fixed-size, no allocation per iteration.
        let mut jjt = Matrix6::identity() * (lambda * lambda);
        for col in jac.column_iter() {
            let c: Vector6<f64> = col.fixed_rows::<6>(0).into_owned();
            jjt += c * c.transpose();
        }
        let Some(chol) = jjt.cholesky() else { return false };
        let y = chol.solve(&err);
        for (k, t) in trial.iter_mut().enumerate() {
            *t = q[k] + jac.column(k).dot(&y);
        }
        clamp_into(chain, &mut trial, rot);
        // The Jacobian pass computes the pose on the way, with the same arithmetic as
        // `fk_flange`: most steps are accepted, and then it is needed anyway.
        let next = chain.jacobian(&trial, pose_flange_tcp, &mut jac_trial);
        let next_err = pose_error(target, &next);
        let next_norm = next_err.norm();
        if next_norm < norm {
            q.copy_from_slice(&trial);
            lambda = (lambda * 0.3).max(1e-9);
            std::mem::swap(&mut jac, &mut jac_trial);
            err = next_err;
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
    if let Some(a) = &m.analytic {
        let mut all = closed_form(m, a, &target);
        all.truncate(max_solutions);
        return all;
    }
    if let Some(r) = &m.redundant {
        return closed_form7(m, r, &target, max_solutions);
    }
    let rot = rotational(&m.chain);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Each start that converges buys more starts, up to the cap: a pose out of reach
    // costs `FIRST_STARTS` attempts, one with many solutions up to the full budget.
    const FIRST_STARTS: usize = 24;
    const STARTS_PER_SOLUTION: usize = 12;
    let cap = STARTS_PER_SOLUTION.saturating_mul(max_solutions).saturating_add(FIRST_STARTS);
    let mut converged = 0;
    let mut q = vec![0.0; m.chain.dof()];
    let dof = q.len();
    for attempt in 0..cap {
        if attempt >= FIRST_STARTS + STARTS_PER_SOLUTION * converged {
            break;
        }
        for (k, v) in q.iter_mut().enumerate() {
            let (lo, hi) = m.chain.limits[k];
            // First start: the home configuration, a natural posture.
            *v =
                if attempt == 0 && m.home.len() == dof { m.home[k] } else { super::chain::sample_in(&mut rng, lo, hi) };
        }
        if !refine(m, &target, &mut q, &rot) {
            continue;
        }
        converged += 1;
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
    if let Some(a) = &m.analytic {
        let dist = |c: &Config| c.iter().zip(start).map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
        return closed_form(m, a, &target).into_iter().min_by(|x, y| dist(x).total_cmp(&dist(y)));
    }
    // A 7R arm keeps joint 7 where it starts: the nearest posture with it, if any.
    if let (Some(r), Some(&q7)) = (&m.redundant, start.get(6)) {
        let flange = target * m.pose_flange_tcp.inverse();
        let mut found: Vec<(f64, bool, [f64; 7])> = Vec::with_capacity(8);
        let from: [f64; 7] = std::array::from_fn(|k| start[k]);
        gather(m, &target, &flange, r.solve_at(&flange, q7), &from, &mut found);
        if let Some(best) = found.iter().min_by(|x, y| x.0.total_cmp(&y.0)) {
            return Some(Config(best.2.to_vec()));
        }
    }
    let rot = rotational(&m.chain);
    let mut q = start.to_vec();
    refine(m, &target, &mut q, &rot).then_some(Config(q))
}

/// Every in-limit configuration reaching `target` (TCP, base frame) by the closed
/// form: first each posture at its turn nearest home, nearest home first, then the
/// same postures turned by whole turns of a joint where the limits allow.
fn closed_form(m: &RobotModel, a: &Analytic, target: &Isometry3<f64>) -> Vec<Config> {
    let flange = target * m.pose_flange_tcp.inverse();
    let home: [f64; 6] = std::array::from_fn(|k| m.home.get(k).copied().unwrap_or(0.0));
    let mut found = Vec::with_capacity(16);
    gather(m, target, &flange, a.solve_conditioned(&flange), &home, &mut found);
    pick(found, &[DISTINCT], usize::MAX)
}

/// Values of joint 7 the 7R closed form is solved at: home's, then this many spread
/// evenly over the joint's range.
const REDUNDANT_SAMPLES: usize = 12;
/// Solutions of a 7R arm closer than this in every joint (radians) are one posture:
/// the first `max_solutions` answers are taken from distinct postures while there are.
const POSTURE: f64 = 0.5;

/// Up to `max` in-limit configurations of a 7R arm reaching `target` (TCP, base
/// frame) by the closed form at sampled values of joint 7: nearest home first, one per
/// posture (see [`POSTURE`]) before a second of the same one.
fn closed_form7(m: &RobotModel, r: &Redundant, target: &Isometry3<f64>, max: usize) -> Vec<Config> {
    let flange = target * m.pose_flange_tcp.inverse();
    let home: [f64; 7] = std::array::from_fn(|k| m.home.get(k).copied().unwrap_or(0.0));
    let (lo, hi) = m.chain.limits[6];
    let spread = (0..REDUNDANT_SAMPLES).map(|i| lo + (hi - lo) * (i as f64 + 0.5) / REDUNDANT_SAMPLES as f64);
    let mut found = Vec::with_capacity(8 * (REDUNDANT_SAMPLES + 1));
    for q7 in std::iter::once(home[6].clamp(lo, hi)).chain(spread) {
        gather(m, target, &flange, r.solve_at(&flange, q7), &home, &mut found);
    }
    pick(found, &[POSTURE, DISTINCT], max)
}

/// Up to `max` of `found` (see [`gather`]), untouched turns first, then nearest home; in
/// one pass per entry of `apart`, each taking those farther than it (in some joint)
/// from every one taken so far.
fn pick<const N: usize>(mut found: Vec<(f64, bool, [f64; N])>, apart: &[f64], max: usize) -> Vec<Config> {
    found.sort_by(|x, y| x.1.cmp(&y.1).then(x.0.total_cmp(&y.0)));
    let near =
        |out: &[Config], q: &[f64; N], d: f64| out.iter().any(|s| s.iter().zip(q).all(|(a, b)| (a - b).abs() <= d));
    let mut out: Vec<Config> = Vec::with_capacity(max.min(found.len()));
    for &d in apart {
        for (_, _, q) in &found {
            if out.len() < max && !near(&out, q, d) {
                out.push(Config(q.to_vec()));
            }
        }
    }
    out
}

/// Confirms closed-form candidates (polishing ill-conditioned ones with the numeric
/// step) and adds each in-limit one, with its whole-turn variants, to `found` as
/// (distance from home, turned by a whole turn?, configuration).
fn gather<const N: usize>(
    m: &RobotModel,
    target: &Isometry3<f64>,
    flange: &Isometry3<f64>,
    candidates: Vec<([f64; N], bool)>,
    home: &[f64; N],
    found: &mut Vec<(f64, bool, [f64; N])>,
) {
    let dist = |q: &[f64; N]| q.iter().zip(home).map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
    let mut rot = None;
    for (mut q, sure) in candidates {
        if !q.iter().all(|v| v.is_finite()) {
            continue;
        }
        // Rounding near a singularity (acos of ±1) can cost digits: confirm, and polish
        // with the numeric step, which converges in one or two iterations from there.
        let err = if sure { Vector6::zeros() } else { pose_error(flange, &m.chain.fk_flange(&q)) };
        if err.fixed_rows::<3>(0).norm() >= IK_TOLERANCE || err.fixed_rows::<3>(3).norm() >= IK_TOLERANCE {
            let rot = rot.get_or_insert_with(|| rotational(&m.chain));
            if err.norm() > analytic::ACCEPT || !refine(m, target, &mut q, rot) {
                continue;
            }
        }
        let Some((turns, counts)) = in_limits(&m.chain.limits, &q, home) else { continue };
        // Every combination of the joints' in-limit turns, the nearest-home one first.
        let mut digit = [0usize; N];
        loop {
            let v: [f64; N] = std::array::from_fn(|k| turns[k][digit[k]]);
            found.push((dist(&v), digit != [0; N], v));
            let Some(k) = (0..N).find(|&k| digit[k] + 1 < counts[k]) else { break };
            digit[k] += 1;
            digit[..k].fill(0);
        }
    }
}

/// At most this many whole-turn variants of one joint are kept (limits wider than
/// ±8π are not seen in practice).
const MAX_TURNS: usize = 8;

/// Per joint, the values `q + 2πk` inside the limits, the one nearest home first, and
/// how many there are; `None` when some joint has none.
fn in_limits<const N: usize>(
    limits: &[(f64, f64)],
    q: &[f64; N],
    home: &[f64; N],
) -> Option<([[f64; MAX_TURNS]; N], [usize; N])> {
    use std::f64::consts::TAU;
    let slack = super::check::LIMIT_SLACK;
    let mut turns = [[0.0; MAX_TURNS]; N];
    let mut counts = [0usize; N];
    for k in 0..N {
        let (v, (lo, hi), h) = (q[k], limits[k], home[k]);
        let mut x = v - ((v - lo) / TAU).floor() * TAU;
        let options = &mut turns[k];
        let n = &mut counts[k];
        while x <= hi + slack && *n < MAX_TURNS {
            if x >= lo - slack {
                options[*n] = x.clamp(lo, hi);
                *n += 1;
            }
            x += TAU;
        }
        if *n == 0 {
            return None;
        }
        options[..*n].sort_by(|a, b| (a - h).abs().total_cmp(&(b - h).abs()));
    }
    Some((turns, counts))
}

#[cfg(test)]
mod tests {
    #[test]
    fn wrapping_by_whole_turns_matches_the_loop_and_ends_on_huge_values() {
        use std::f64::consts::TAU;
        let looped = |mut v: f64, lo: f64, hi: f64| {
            while v > hi && v - TAU >= lo {
                v -= TAU;
            }
            while v < lo && v + TAU <= hi {
                v += TAU;
            }
            v.clamp(lo, hi)
        };
        let computed = |v: f64, lo: f64, hi: f64| {
            let mut q = [v];
            super::clamp_limits(&[(lo, hi)], &mut q, &[true]);
            q[0]
        };
        for (v, lo, hi) in [
            (7.0, -3.0, 3.0),
            (-20.0, -3.0, 3.0),
            (3.5, -1.0, 1.0),
            (0.5, -1.0, 1.0),
            (40.0, -6.5, 6.5),
            (1000.0, -6.5, 6.5),
            (-1000.0, -3.0, 3.0),
            (999.0, -0.1, 0.1),
        ] {
            // (Equal up to the rounding the loop accumulates over many turns.)
            assert!((looped(v, lo, hi) - computed(v, lo, hi)).abs() < 1e-9, "{v} [{lo}, {hi}]");
        }
        assert!(computed(1e300, -TAU, TAU).is_finite());
    }
}
