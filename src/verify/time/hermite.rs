//! One joint between two trajectory points: the cubic Hermite curve through
//! `(t0, q0, qd0)` and `(t1, q1, qd1)`, as a ROS joint-trajectory controller
//! interpolates points given with positions and velocities.
//!
//! In the local parameter `s = (t − t0)/h`, `q = a + b s + c s² + d s³`; velocity is a
//! quadratic and acceleration a line in `s`, so their extremes over a segment are exact:
//! the ends, and for the velocity the vertex of the parabola.

/// The cubic of one joint over one segment of duration `h > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cubic {
    h: f64,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
}

impl Cubic {
    /// Through `q0` with velocity `v0` at the start and `q1`, `v1` after `h` seconds.
    pub fn new(h: f64, q0: f64, v0: f64, q1: f64, v1: f64) -> Cubic {
        let dq = q1 - q0;
        Cubic { h, a: q0, b: h * v0, c: 3.0 * dq - 2.0 * h * v0 - h * v1, d: -2.0 * dq + h * v0 + h * v1 }
    }

    /// Position at `s ∈ [0, 1]`.
    pub fn position(&self, s: f64) -> f64 {
        self.a + s * (self.b + s * (self.c + s * self.d))
    }

    /// Velocity (per second) at `s`.
    pub fn velocity(&self, s: f64) -> f64 {
        (self.b + s * (2.0 * self.c + 3.0 * s * self.d)) / self.h
    }

    /// Acceleration (per second²) at `s`.
    pub fn acceleration(&self, s: f64) -> f64 {
        (2.0 * self.c + 6.0 * self.d * s) / (self.h * self.h)
    }

    /// Where on `[0, 1]` the velocity has its extreme inside the segment, if anywhere.
    fn velocity_vertex(&self) -> Option<f64> {
        (self.d != 0.0).then(|| -self.c / (3.0 * self.d)).filter(|s| *s > 0.0 && *s < 1.0)
    }

    /// The largest |velocity| over the segment, and where (`s`).
    pub fn max_speed(&self) -> (f64, f64) {
        let mut best = (self.velocity(0.0).abs(), 0.0);
        for s in std::iter::once(1.0).chain(self.velocity_vertex()) {
            let v = self.velocity(s).abs();
            if v > best.0 {
                best = (v, s);
            }
        }
        best
    }

    /// The largest |velocity| over `[s0, s1]`, a part of the segment: its ends, and the
    /// parabola's vertex when it lies between them.
    pub fn max_speed_on(&self, s0: f64, s1: f64) -> f64 {
        let ends = self.velocity(s0).abs().max(self.velocity(s1).abs());
        match self.velocity_vertex().filter(|s| *s > s0 && *s < s1) {
            Some(s) => ends.max(self.velocity(s).abs()),
            None => ends,
        }
    }

    /// The largest |acceleration| over the segment (at an end: it is linear), and where.
    pub fn max_acceleration(&self) -> (f64, f64) {
        let (a0, a1) = (self.acceleration(0.0).abs(), self.acceleration(1.0).abs());
        if a1 > a0 {
            (a1, 1.0)
        } else {
            (a0, 0.0)
        }
    }

    /// The lowest and highest position over the segment, each with its `s`: the ends and
    /// the points where the velocity is zero.
    pub fn position_range(&self) -> ((f64, f64), (f64, f64)) {
        // Roots of b + 2c s + 3d s².
        let mut cands = vec![0.0, 1.0];
        let (qa, qb, qc) = (3.0 * self.d, 2.0 * self.c, self.b);
        if qa.abs() > 1e-15 {
            let disc = qb * qb - 4.0 * qa * qc;
            if disc >= 0.0 {
                let r = disc.sqrt();
                cands.push((-qb + r) / (2.0 * qa));
                cands.push((-qb - r) / (2.0 * qa));
            }
        } else if qb.abs() > 1e-15 {
            cands.push(-qc / qb);
        }
        let mut lo = (f64::INFINITY, 0.0);
        let mut hi = (f64::NEG_INFINITY, 0.0);
        for s in cands.into_iter().filter(|s| (0.0..=1.0).contains(s)) {
            let q = self.position(s);
            if q < lo.0 {
                lo = (q, s);
            }
            if q > hi.0 {
                hi = (q, s);
            }
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_its_ends() {
        let c = Cubic::new(2.0, 1.0, 0.5, 3.0, -0.25);
        assert!((c.position(0.0) - 1.0).abs() < 1e-12);
        assert!((c.position(1.0) - 3.0).abs() < 1e-12);
        assert!((c.velocity(0.0) - 0.5).abs() < 1e-12);
        assert!((c.velocity(1.0) + 0.25).abs() < 1e-12);
    }

    #[test]
    fn rest_to_rest_peaks_at_one_and_a_half_times_the_mean_speed() {
        // q = 3s² − 2s³ over h: peak velocity 1.5·Δq/h at s = ½, acceleration ±6Δq/h² at the ends.
        let c = Cubic::new(2.0, 0.0, 0.0, 1.0, 0.0);
        let (v, s) = c.max_speed();
        assert!((v - 0.75).abs() < 1e-12 && (s - 0.5).abs() < 1e-12);
        let (a, _) = c.max_acceleration();
        assert!((a - 1.5).abs() < 1e-12);
    }

    #[test]
    fn the_peak_speed_on_a_part_is_at_its_ends_or_the_vertex_inside_it() {
        // Rest to rest over 2 s: q = 3s² − 2s³, v(s) = 3s(1 − s): 0.75 at s = ½, 0 at the ends.
        let c = Cubic::new(2.0, 0.0, 0.0, 1.0, 0.0);
        assert!((c.max_speed_on(0.0, 1.0) - 0.75).abs() < 1e-12);
        assert!((c.max_speed_on(0.4, 0.6) - 0.75).abs() < 1e-12);
        // Off the vertex the larger end: v(0.25) = v(0.75) = 0.5625.
        assert!((c.max_speed_on(0.0, 0.25) - 0.5625).abs() < 1e-12);
        assert!((c.max_speed_on(0.75, 1.0) - 0.5625).abs() < 1e-12);
        // Finely sampled, never above.
        for k in 0..100 {
            let (a, b) = (k as f64 / 100.0, (k + 1) as f64 / 100.0);
            let peak = c.max_speed_on(a, b);
            for i in 0..=20 {
                assert!(c.velocity(a + (b - a) * i as f64 / 20.0).abs() <= peak + 1e-15);
            }
        }
    }

    #[test]
    fn finds_an_overshoot_between_points() {
        // Leaving 0 fast and arriving at 0 at rest overshoots: q = s − 2s² + s³ peaks at s = ⅓.
        let c = Cubic::new(1.0, 0.0, 1.0, 0.0, 0.0);
        let ((lo, _), (hi, s)) = c.position_range();
        assert!(lo.abs() < 1e-12);
        assert!((s - 1.0 / 3.0).abs() < 1e-9 && (hi - 4.0 / 27.0).abs() < 1e-12);
    }

    #[test]
    fn a_straight_constant_speed_segment_is_linear() {
        let c = Cubic::new(0.5, 1.0, 2.0, 2.0, 2.0);
        for k in 0..=10 {
            let s = k as f64 / 10.0;
            assert!((c.position(s) - (1.0 + s)).abs() < 1e-12);
            assert!(c.acceleration(s).abs() < 1e-12);
        }
    }
}
