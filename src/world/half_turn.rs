//! Sine and cosine of half a joint angle, for forward kinematics: a joint's turn is the
//! unit quaternion `(cos v/2, axis sin v/2)`, and every check turns each joint once.
//!
//! libm's `sincos` is accurate everywhere and pays for it (about 105 instructions a call,
//! 6 % of the cans examples' compile); joint angles are small, so a table of 64 steps
//! around the circle and short Taylor series on the remainder (at most pi/64) do it in
//! about a third, within 2 ulp of libm's values (see the tests). Plain multiplications and
//! additions only (no fused ones): the same bits on every machine, which libm does not
//! promise.

/// `(sin(a), cos(a))` for `a = j * pi / 32`, correctly rounded (computed at 200 bits).
#[rustfmt::skip]
const STEPS: [(f64, f64); 64] = [
    (f64::from_bits(0x0000000000000000), f64::from_bits(0x3ff0000000000000)),
    (f64::from_bits(0x3fb917a6bc29b42c), f64::from_bits(0x3fefd88da3d12526)),
    (f64::from_bits(0x3fc8f8b83c69a60b), f64::from_bits(0x3fef6297cff75cb0)),
    (f64::from_bits(0x3fd294062ed59f06), f64::from_bits(0x3fee9f4156c62dda)),
    (f64::from_bits(0x3fd87de2a6aea963), f64::from_bits(0x3fed906bcf328d46)),
    (f64::from_bits(0x3fde2b5d3806f63b), f64::from_bits(0x3fec38b2f180bdb1)),
    (f64::from_bits(0x3fe1c73b39ae68c8), f64::from_bits(0x3fea9b66290ea1a3)),
    (f64::from_bits(0x3fe44cf325091dd6), f64::from_bits(0x3fe8bc806b151741)),
    (f64::from_bits(0x3fe6a09e667f3bcd), f64::from_bits(0x3fe6a09e667f3bcd)),
    (f64::from_bits(0x3fe8bc806b151741), f64::from_bits(0x3fe44cf325091dd6)),
    (f64::from_bits(0x3fea9b66290ea1a3), f64::from_bits(0x3fe1c73b39ae68c8)),
    (f64::from_bits(0x3fec38b2f180bdb1), f64::from_bits(0x3fde2b5d3806f63b)),
    (f64::from_bits(0x3fed906bcf328d46), f64::from_bits(0x3fd87de2a6aea963)),
    (f64::from_bits(0x3fee9f4156c62dda), f64::from_bits(0x3fd294062ed59f06)),
    (f64::from_bits(0x3fef6297cff75cb0), f64::from_bits(0x3fc8f8b83c69a60b)),
    (f64::from_bits(0x3fefd88da3d12526), f64::from_bits(0x3fb917a6bc29b42c)),
    (f64::from_bits(0x3ff0000000000000), f64::from_bits(0x0000000000000000)),
    (f64::from_bits(0x3fefd88da3d12526), f64::from_bits(0xbfb917a6bc29b42c)),
    (f64::from_bits(0x3fef6297cff75cb0), f64::from_bits(0xbfc8f8b83c69a60b)),
    (f64::from_bits(0x3fee9f4156c62dda), f64::from_bits(0xbfd294062ed59f06)),
    (f64::from_bits(0x3fed906bcf328d46), f64::from_bits(0xbfd87de2a6aea963)),
    (f64::from_bits(0x3fec38b2f180bdb1), f64::from_bits(0xbfde2b5d3806f63b)),
    (f64::from_bits(0x3fea9b66290ea1a3), f64::from_bits(0xbfe1c73b39ae68c8)),
    (f64::from_bits(0x3fe8bc806b151741), f64::from_bits(0xbfe44cf325091dd6)),
    (f64::from_bits(0x3fe6a09e667f3bcd), f64::from_bits(0xbfe6a09e667f3bcd)),
    (f64::from_bits(0x3fe44cf325091dd6), f64::from_bits(0xbfe8bc806b151741)),
    (f64::from_bits(0x3fe1c73b39ae68c8), f64::from_bits(0xbfea9b66290ea1a3)),
    (f64::from_bits(0x3fde2b5d3806f63b), f64::from_bits(0xbfec38b2f180bdb1)),
    (f64::from_bits(0x3fd87de2a6aea963), f64::from_bits(0xbfed906bcf328d46)),
    (f64::from_bits(0x3fd294062ed59f06), f64::from_bits(0xbfee9f4156c62dda)),
    (f64::from_bits(0x3fc8f8b83c69a60b), f64::from_bits(0xbfef6297cff75cb0)),
    (f64::from_bits(0x3fb917a6bc29b42c), f64::from_bits(0xbfefd88da3d12526)),
    (f64::from_bits(0x0000000000000000), f64::from_bits(0xbff0000000000000)),
    (f64::from_bits(0xbfb917a6bc29b42c), f64::from_bits(0xbfefd88da3d12526)),
    (f64::from_bits(0xbfc8f8b83c69a60b), f64::from_bits(0xbfef6297cff75cb0)),
    (f64::from_bits(0xbfd294062ed59f06), f64::from_bits(0xbfee9f4156c62dda)),
    (f64::from_bits(0xbfd87de2a6aea963), f64::from_bits(0xbfed906bcf328d46)),
    (f64::from_bits(0xbfde2b5d3806f63b), f64::from_bits(0xbfec38b2f180bdb1)),
    (f64::from_bits(0xbfe1c73b39ae68c8), f64::from_bits(0xbfea9b66290ea1a3)),
    (f64::from_bits(0xbfe44cf325091dd6), f64::from_bits(0xbfe8bc806b151741)),
    (f64::from_bits(0xbfe6a09e667f3bcd), f64::from_bits(0xbfe6a09e667f3bcd)),
    (f64::from_bits(0xbfe8bc806b151741), f64::from_bits(0xbfe44cf325091dd6)),
    (f64::from_bits(0xbfea9b66290ea1a3), f64::from_bits(0xbfe1c73b39ae68c8)),
    (f64::from_bits(0xbfec38b2f180bdb1), f64::from_bits(0xbfde2b5d3806f63b)),
    (f64::from_bits(0xbfed906bcf328d46), f64::from_bits(0xbfd87de2a6aea963)),
    (f64::from_bits(0xbfee9f4156c62dda), f64::from_bits(0xbfd294062ed59f06)),
    (f64::from_bits(0xbfef6297cff75cb0), f64::from_bits(0xbfc8f8b83c69a60b)),
    (f64::from_bits(0xbfefd88da3d12526), f64::from_bits(0xbfb917a6bc29b42c)),
    (f64::from_bits(0xbff0000000000000), f64::from_bits(0x0000000000000000)),
    (f64::from_bits(0xbfefd88da3d12526), f64::from_bits(0x3fb917a6bc29b42c)),
    (f64::from_bits(0xbfef6297cff75cb0), f64::from_bits(0x3fc8f8b83c69a60b)),
    (f64::from_bits(0xbfee9f4156c62dda), f64::from_bits(0x3fd294062ed59f06)),
    (f64::from_bits(0xbfed906bcf328d46), f64::from_bits(0x3fd87de2a6aea963)),
    (f64::from_bits(0xbfec38b2f180bdb1), f64::from_bits(0x3fde2b5d3806f63b)),
    (f64::from_bits(0xbfea9b66290ea1a3), f64::from_bits(0x3fe1c73b39ae68c8)),
    (f64::from_bits(0xbfe8bc806b151741), f64::from_bits(0x3fe44cf325091dd6)),
    (f64::from_bits(0xbfe6a09e667f3bcd), f64::from_bits(0x3fe6a09e667f3bcd)),
    (f64::from_bits(0xbfe44cf325091dd6), f64::from_bits(0x3fe8bc806b151741)),
    (f64::from_bits(0xbfe1c73b39ae68c8), f64::from_bits(0x3fea9b66290ea1a3)),
    (f64::from_bits(0xbfde2b5d3806f63b), f64::from_bits(0x3fec38b2f180bdb1)),
    (f64::from_bits(0xbfd87de2a6aea963), f64::from_bits(0x3fed906bcf328d46)),
    (f64::from_bits(0xbfd294062ed59f06), f64::from_bits(0x3fee9f4156c62dda)),
    (f64::from_bits(0xbfc8f8b83c69a60b), f64::from_bits(0x3fef6297cff75cb0)),
    (f64::from_bits(0xbfb917a6bc29b42c), f64::from_bits(0x3fefd88da3d12526)),
];

/// pi/32 in two parts: the first with 33 significant bits, so that `k * STEP_HI` is exact
/// for `|k| < 2^20`; the second the rest, rounded.
const STEP_HI: f64 = f64::from_bits(0x3fb9_21fb_5440_0000);
const STEP_LO: f64 = f64::from_bits(0x3d90_b461_1a62_6331);
const INV_STEP: f64 = 10.185_916_357_881_302;
/// Adding this rounds a number below 2^51 in magnitude to an integer, which then lies in
/// the sum's low bits (two's complement, offset by 2^51: the last six are it modulo 64).
const ROUND: f64 = 6_755_399_441_055_744.0;
/// Beyond this many steps the reduction loses its exactness: libm takes over.
const MAX_STEPS: f64 = 1_000_000.0;

/// `(sin(v / 2), cos(v / 2))`.
#[inline]
pub(crate) fn half_turn(v: f64) -> (f64, f64) {
    let x = v * 0.5;
    let t = x * INV_STEP;
    // (NaN and infinities too.)
    if t.abs().partial_cmp(&MAX_STEPS) != Some(std::cmp::Ordering::Less) {
        return x.sin_cos();
    }
    let shifted = t + ROUND;
    let k = shifted - ROUND;
    let (sa, ca) = STEPS[(shifted.to_bits() & 63) as usize];
    let r = (x - k * STEP_HI) - k * STEP_LO;
    let r2 = r * r;
    // Taylor series to r^9 and r^8: at |r| <= pi/64 the next terms are below 1e-19.
    let sr = r + r * r2 * (-1.0 / 6.0 + r2 * (1.0 / 120.0 + r2 * (-1.0 / 5040.0 + r2 * (1.0 / 362_880.0))));
    let cr = 1.0 + r2 * (-0.5 + r2 * (1.0 / 24.0 + r2 * (-1.0 / 720.0 + r2 * (1.0 / 40_320.0))));
    (sa * cr + ca * sr, ca * cr - sa * sr)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Within `ulps` units in the last place of libm's value, or (near a zero of the
    /// function, where an ulp of the result is tiny) within 2^-53 absolute.
    fn close(a: f64, b: f64, ulps: f64) -> bool {
        let ulp = (b.abs() * f64::EPSILON).max(f64::EPSILON / 2.0);
        (a - b).abs() <= ulps * ulp
    }

    #[test]
    fn half_turns_are_within_two_ulps_of_libm_over_joint_ranges_and_beyond() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut worst_s, mut worst_c) = (0.0f64, 0.0f64);
        for i in 0..200_000 {
            // Joint ranges, several turns, and the steps' own boundaries.
            let v = match i % 4 {
                0 => rng.random_range(-7.0..7.0),
                1 => rng.random_range(-200.0..200.0),
                2 => (rng.random_range(-400i32..400) as f64) * std::f64::consts::PI / 16.0,
                _ => rng.random_range(-1e-6..1e-6),
            };
            let (s, c) = half_turn(v);
            let (ls, lc) = (v * 0.5).sin_cos();
            assert!(close(s, ls, 2.0) && close(c, lc, 2.0), "v = {v:e}: ({s:e}, {c:e}) vs libm ({ls:e}, {lc:e})");
            worst_s = worst_s.max((s - ls).abs());
            worst_c = worst_c.max((c - lc).abs());
        }
        assert!(worst_s < 5e-16 && worst_c < 5e-16, "{worst_s:e} {worst_c:e}");
    }

    #[test]
    fn right_at_the_steps_and_libm_past_the_range() {
        use std::f64::consts::{FRAC_1_SQRT_2, PI};
        assert_eq!(half_turn(0.0), (0.0, 1.0));
        // A quarter turn: 45 degrees each side.
        let (s, c) = half_turn(PI / 2.0);
        assert!((s - FRAC_1_SQRT_2).abs() <= 1.2e-16 && (c - FRAC_1_SQRT_2).abs() <= 1.2e-16, "{s:e} {c:e}");
        // A half turn: cos(pi/2) is the rounding of pi, 6.1e-17, to within what the
        // reduction leaves out of pi/32 (3e-26 here).
        let (s, c) = half_turn(PI);
        assert_eq!(s, 1.0);
        assert!((c - (PI / 2.0).cos()).abs() < 1e-25, "{c:e}");
        assert_eq!(half_turn(1e9), (5e8f64).sin_cos());
        let (s, c) = half_turn(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
    }
}
