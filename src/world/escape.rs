//! A straight move of the hand out of where a goal configuration puts it. A goal behind a
//! window or inside a shelf is usually left the way the hand went in: back towards the
//! robot. A search through joint space finds that way only by chance, one random step
//! after another, where the hand may move only along a few directions.

use nalgebra::Vector3;

use super::ik::{refine, rotational};
use super::{Config, World};
use crate::resolve::RobotId;

/// How far the line goes (metres), and in steps of how much.
const ESCAPE_LENGTH: f64 = 0.3;
const STEP: f64 = 0.02;
/// An IK step that turns any joint more than this (radians) ends the line: the arm left
/// the posture it was in.
const JUMP: f64 = 0.5;

impl World {
    /// Configurations from `q` on (`q` left out) moving the TCP in a straight line
    /// towards the robot's base, level (along the floor's plane), its orientation kept,
    /// `ESCAPE_LENGTH` (30 cm) in steps of 2 cm: each step solved by the IK started at the last.
    /// The line stops short where the IK does not converge or jumps (see `JUMP`), and is
    /// empty when the TCP stands over the base. Unchecked: the caller checks each move.
    ///
    /// Panics if `q.len()` is not [`World::dof`].
    pub fn escape_line(&self, r: RobotId, q: &[f64]) -> Vec<Config> {
        let m = self.robot_for(r, q);
        let tcp = self.fk_tcp(r, q);
        let out = tcp.translation.vector - m.pose_world_base.translation.vector;
        let inward = Vector3::new(-out.x, -out.y, 0.0);
        if inward.norm() < 1e-6 {
            return Vec::new();
        }
        let dir = inward.normalize();
        let rot = rotational(&m.chain);
        let base_world = m.pose_world_base.inverse();
        let mut line: Vec<Config> = Vec::new();
        let mut last = q.to_vec();
        for k in 1..=(ESCAPE_LENGTH / STEP).round() as usize {
            let mut target = tcp;
            target.translation.vector += dir * (STEP * k as f64);
            let mut next = last.clone();
            if !refine(m, &(base_world * target), &mut next, &rot)
                || next.iter().zip(&last).any(|(a, b)| (a - b).abs() > JUMP)
            {
                break;
            }
            line.push(Config(next.clone()));
            last = next;
        }
        line
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_arms::{example, shared_arms};
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// On the shipped TX-90 with its hand, the UR5 and both Pandas, from random
    /// configurations whose TCP stands away from the base: step `k` of the line puts the
    /// TCP `2k` cm from where it started, level and towards the base, turned as it was
    /// (forward kinematics, to the IK's tolerance), each step turning no joint more than
    /// the jump. Over the cases more than a third run the whole length (59 of 153: the others
    /// leave the arm's reach or limits first), so the test sees lines.
    #[test]
    fn the_line_moves_the_tcp_straight_to_the_base_its_orientation_kept() {
        let mut worlds = vec![("box_lid".to_string(), example("box_lid"))];
        worlds.extend(shared_arms());
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (mut cases, mut whole) = (0, 0);
        for (name, w) in &worlds {
            let r = RobotId(0);
            for _ in 0..40 {
                let q: Vec<f64> = w.limits(r).iter().map(|(lo, hi)| lo + rng.random::<f64>() * (hi - lo)).collect();
                let start = w.fk_tcp(r, &q);
                let base = w.robots[0].pose_world_base.translation.vector;
                let out = start.translation.vector - base;
                let level = Vector3::new(out.x, out.y, 0.0);
                if level.norm() < 0.1 {
                    continue;
                }
                let dir = -level.normalize();
                let line = w.escape_line(r, &q);
                let mut last = q.clone();
                for (k, c) in line.iter().enumerate() {
                    let at = w.fk_tcp(r, &c.0);
                    let want = start.translation.vector + dir * (STEP * (k + 1) as f64);
                    assert!((at.translation.vector - want).norm() < 1e-8, "{name}: step {k} at {at:?}, not {want:?}");
                    assert!(at.rotation.angle_to(&start.rotation) < 1e-8, "{name}: step {k} turned the TCP");
                    assert!(c.0.iter().zip(&last).all(|(a, b)| (a - b).abs() <= JUMP), "{name}: step {k} jumped");
                    last.clone_from(&c.0);
                }
                cases += 1;
                whole += usize::from(line.len() == (ESCAPE_LENGTH / STEP).round() as usize);
            }
        }
        // The TX-90 alone (without ../shared) gives 37 cases, 21 of them whole lines.
        assert!(cases >= 30, "{cases} cases");
        assert!(3 * whole > cases, "{whole} of {cases} lines ran the whole length");
    }
}
