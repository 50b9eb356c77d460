//! One synchronised point-to-point segment: a straight line in joint space travelled
//! with a trapezoidal (or, when short, triangular) profile of its path parameter.
//!
//! With `q(s) = a + s (b - a)`, `s` in [0, 1], joint `i` moves at `|b_i - a_i| ṡ` and
//! accelerates at `|b_i - a_i| s̈`; bounding `ṡ` by `min_i v_i / |b_i - a_i|` and `s̈` by
//! `min_i a_i / |b_i - a_i|` keeps every joint within its limits, makes all joints start
//! and stop together, and keeps the motion on the straight segment the planner checked.

/// Velocity and acceleration limits per joint, already scaled by `speed`.
#[derive(Clone, Debug, PartialEq)]
pub struct Limits {
    pub velocity: Vec<f64>,
    pub acceleration: Vec<f64>,
}

/// The time law of one segment: accelerate for `t_acc`, cruise at `peak` (in units of
/// `s` per second), decelerate for `t_acc`; `duration = 2 t_acc + cruise`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    pub t_acc: f64,
    pub duration: f64,
    /// Peak `ṡ`.
    pub peak: f64,
    /// `s̈` during the ramps.
    pub accel: f64,
}

impl Profile {
    /// The fastest profile from `a` to `b` within `lim`; `None` when `a == b`.
    pub fn between(a: &[f64], b: &[f64], lim: &Limits) -> Option<Profile> {
        let mut v_s = f64::INFINITY;
        let mut a_s = f64::INFINITY;
        for i in 0..a.len() {
            let d = (b[i] - a[i]).abs();
            if d > 0.0 {
                v_s = v_s.min(lim.velocity[i] / d);
                a_s = a_s.min(lim.acceleration[i] / d);
            }
        }
        if !v_s.is_finite() {
            return None;
        }
        // Reaching the cruise speed and braking from it covers v²/a of the unit path.
        if v_s * v_s / a_s >= 1.0 {
            let t_acc = (1.0 / a_s).sqrt();
            Some(Profile { t_acc, duration: 2.0 * t_acc, peak: a_s * t_acc, accel: a_s })
        } else {
            let t_acc = v_s / a_s;
            Some(Profile { t_acc, duration: 1.0 / v_s + t_acc, peak: v_s, accel: a_s })
        }
    }

    /// `(s, ṡ)` at time `t` in [0, duration].
    pub fn at(&self, t: f64) -> (f64, f64) {
        let t = t.clamp(0.0, self.duration);
        let ramp = 0.5 * self.accel * self.t_acc * self.t_acc;
        if t <= self.t_acc {
            (0.5 * self.accel * t * t, self.accel * t)
        } else if t >= self.duration - self.t_acc {
            let r = self.duration - t;
            (1.0 - 0.5 * self.accel * r * r, self.accel * r)
        } else {
            (ramp + self.peak * (t - self.t_acc), self.peak)
        }
    }

    /// The phase boundaries strictly inside the segment (one for a triangle, two for a
    /// trapezoid): with the end points they are the knots between which the motion is
    /// a polynomial of degree ≤ 2, so cubic Hermite interpolation on (q, qd) is exact.
    pub fn knots(&self) -> Vec<f64> {
        let cruise = self.duration - 2.0 * self.t_acc;
        if cruise > 1e-12 * self.duration {
            vec![self.t_acc, self.duration - self.t_acc]
        } else {
            vec![self.t_acc]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lim(v: f64, a: f64, n: usize) -> Limits {
        Limits { velocity: vec![v; n], acceleration: vec![a; n] }
    }

    #[test]
    fn short_move_is_a_triangle() {
        // 1 rad at vmax 4, amax 4: v²/a = 4 rad > 1 rad, so a triangle; each half covers
        // 0.5 rad = ½·4·t², t = 0.5 s; peak 2 rad/s.
        let p = Profile::between(&[0.0], &[1.0], &lim(4.0, 4.0, 1)).expect("moves");
        assert!((p.t_acc - 0.5).abs() < 1e-12);
        assert!((p.duration - 1.0).abs() < 1e-12);
        assert!((p.peak * 1.0 - 2.0).abs() < 1e-12);
        assert_eq!(p.knots().len(), 1);
    }

    #[test]
    fn long_move_is_a_trapezoid() {
        // 1 rad at vmax 2, amax 8: ramps of 2/8 = 0.25 s, each covering ½·8·0.25² =
        // 0.25 rad; the middle 0.5 rad at 2 rad/s takes 0.25 s; total 0.75 s.
        let p = Profile::between(&[0.0], &[1.0], &lim(2.0, 8.0, 1)).expect("moves");
        assert!((p.t_acc - 0.25).abs() < 1e-12);
        assert!((p.duration - 0.75).abs() < 1e-12);
        assert_eq!(p.knots(), vec![0.25, 0.5]);
        let (s, sd) = p.at(0.375);
        assert!((s - 0.5).abs() < 1e-12 && (sd - 2.0).abs() < 1e-12);
        assert_eq!(p.at(0.75), (1.0, 0.0));
    }

    #[test]
    fn the_slowest_joint_sets_the_pace_and_all_stop_together() {
        // Joint 0 moves 0.5 rad, joint 1 moves 2 rad, both at vmax 1, amax 10: joint 1
        // needs 2/1 + 1/10 = 2.1 s; joint 0 then peaks at 0.25 rad/s.
        let p = Profile::between(&[0.0, 0.0], &[0.5, -2.0], &lim(1.0, 10.0, 2)).expect("moves");
        assert!((p.duration - 2.1).abs() < 1e-12);
        assert!((p.peak * 0.5 - 0.25).abs() < 1e-12);
        assert!((p.peak * 2.0 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn no_motion_no_profile() {
        assert_eq!(Profile::between(&[0.3, 1.0], &[0.3, 1.0], &lim(1.0, 1.0, 2)), None);
    }
}
