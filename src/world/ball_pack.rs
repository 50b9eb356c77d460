//! A body of balls only (a spherized link) tested against a box all at once: its centres
//! taken straight into the box's frame by one matrix, instead of each ball placed in the
//! world, bounded, and tested on its own (most of a spherized arm's check went there).

use parry3d_f64::math::{Matrix, Pose as PPose, Vector as PVec};

use super::robot::{Posture, RShape};
use super::shapes::{Boxed, BALL_MARGIN};

/// Balls are tested this many at a time (lanes the compiler can vectorise).
const LANES: usize = 4;

/// One body's balls: per posture set (each finger posture, then the shapes' own poses),
/// the centres in the link's frame as columns, and per ball the squared radii that decide.
pub(crate) struct BallPack {
    /// Balls rounded up to whole lanes; the padding balls are never near anything.
    n: usize,
    /// Set `k`'s centres: `x` at `k * 3n`, then `y`, then `z`, `n` each.
    centres: Vec<f64>,
    /// Per ball, `(r + margin)²` of its eroded radius `r`: farther from the box, apart.
    outside: Vec<f64>,
    /// Per ball, `(r - margin)²`: nearer, a contact deeper than the tolerance; `-1` for a
    /// ball no larger than the margin (never a proof).
    inside: Vec<f64>,
    /// The set of the shapes' own poses (the last).
    own: usize,
}

impl BallPack {
    /// The pack of `shapes` (a body's) when every one is a ball with an eroded radius,
    /// whatever the posture; `None` otherwise.
    pub fn of(shapes: &[RShape], first: usize, postures: &[Posture]) -> Option<BallPack> {
        let radii: Vec<f64> = shapes
            .iter()
            .map(|s| match s.placed.boxed {
                Boxed::Ball(_) => s.placed.eroded_ball,
                _ => None,
            })
            .collect::<Option<_>>()?;
        if radii.is_empty() {
            return None;
        }
        let n = radii.len().div_ceil(LANES) * LANES;
        let mut centres = Vec::with_capacity((postures.len() + 1) * 3 * n);
        for set in 0..=postures.len() {
            let pose = |i: usize| {
                let si = first + i;
                postures.get(set).and_then(|p| p.poses.get(si)).unwrap_or(&shapes[i].placed.pose).translation
            };
            for axis in 0..3 {
                centres.extend((0..n).map(|i| if i < radii.len() { pose(i)[axis] } else { 0.0 }));
            }
        }
        let (mut outside, mut inside) = (vec![-1.0; n], vec![-1.0; n]);
        for (i, r) in radii.iter().enumerate() {
            outside[i] = (r + BALL_MARGIN) * (r + BALL_MARGIN);
            if *r > BALL_MARGIN {
                inside[i] = (r - BALL_MARGIN) * (r - BALL_MARGIN);
            }
        }
        Some(BallPack { n, centres, outside, inside, own: postures.len() })
    }

    /// Whether a ball of the body, its link at `link` and the fingers in `posture`, meets
    /// the box of half extents `he` at `bx` deeper than the contact tolerance: what
    /// [`super::shapes::ball_meets_box`] says of each ball, `None` when it is unsure of one
    /// and sure of none meeting (the caller then asks ball by ball).
    #[inline]
    pub fn meets_box(&self, posture: usize, link: &PPose, bx: &PPose, he: PVec) -> Option<bool> {
        let set = if posture < self.own { posture } else { self.own };
        let n = self.n;
        let c = &self.centres[set * 3 * n..(set + 1) * 3 * n];
        let (xs, rest) = c.split_at(n);
        let (ys, zs) = rest.split_at(n);
        let inv = bx.rotation.inverse();
        let m = Matrix::from_quat(inv * link.rotation);
        let v = inv * (link.translation - bx.translation);
        let (a, b, c3) = (m.x_axis, m.y_axis, m.z_axis);
        let mut unsure = false;
        let chunks = xs.chunks_exact(LANES).zip(ys.chunks_exact(LANES)).zip(zs.chunks_exact(LANES));
        let radii = self.inside.chunks_exact(LANES).zip(self.outside.chunks_exact(LANES));
        for (((x, y), z), (inside, outside)) in chunks.zip(radii) {
            // Lane by lane, as columns: the compiler keeps the lanes in vector registers.
            let mut d2 = [0.0; LANES];
            for l in 0..LANES {
                let ex = ((a.x * x[l] + b.x * y[l] + c3.x * z[l] + v.x).abs() - he.x).max(0.0);
                let ey = ((a.y * x[l] + b.y * y[l] + c3.y * z[l] + v.y).abs() - he.y).max(0.0);
                let ez = ((a.z * x[l] + b.z * y[l] + c3.z * z[l] + v.z).abs() - he.z).max(0.0);
                d2[l] = ex * ex + ey * ey + ez * ez;
            }
            let mut hit = false;
            for l in 0..LANES {
                hit |= d2[l] < inside[l];
                unsure |= d2[l] <= outside[l] || d2[l].is_nan();
            }
            if hit {
                return Some(true);
            }
        }
        (!unsure).then_some(false)
    }
}

#[cfg(test)]
mod tests {
    use parry3d_f64::math::{Pose as PPose, Rotation, Vector as PVec};
    use parry3d_f64::shape::SharedShape;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::BallPack;
    use crate::world::robot::{Posture, RShape};
    use crate::world::shapes::{ball_meets_box, place, Placed};

    fn turn(rng: &mut ChaCha8Rng) -> Rotation {
        let axis = PVec::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        Rotation::from_scaled_axis(axis.normalize_or(PVec::Z) * rng.random_range(-3.2..3.2))
    }

    fn near(rng: &mut ChaCha8Rng, size: f64) -> PVec {
        PVec::new(rng.random_range(-size..size), rng.random_range(-size..size), rng.random_range(-size..size))
    }

    /// On random bodies of balls (some moved by a finger posture), links and boxes, the pack
    /// says what the balls one by one say: a meeting ball when one meets the box, apart when
    /// every one is, unsure only when one is unsure and none meets.
    #[test]
    fn a_pack_says_what_its_balls_say_one_by_one() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut seen = [0usize; 3];
        for _ in 0..20_000 {
            let n = rng.random_range(1..10);
            let shapes: Vec<RShape> = (0..n)
                .map(|_| {
                    let pose = PPose::from_parts(near(&mut rng, 0.2), Rotation::IDENTITY);
                    let ball = SharedShape::ball(rng.random_range(0.003..0.08));
                    RShape { body: 0, placed: Placed::new(ball, pose), unturned: true }
                })
                .collect();
            // One posture moving every other ball, or none.
            let postures: Vec<Posture> = match rng.random_bool(0.5) {
                true => vec![Posture {
                    values: vec![],
                    poses: shapes
                        .iter()
                        .enumerate()
                        .map(|(i, s)| {
                            let shift = if i % 2 == 0 { near(&mut rng, 0.05) } else { PVec::ZERO };
                            PPose::from_parts(s.placed.pose.translation + shift, Rotation::IDENTITY)
                        })
                        .collect(),
                }],
                false => vec![],
            };
            let pack = BallPack::of(&shapes, 0, &postures).expect("balls only");
            let link = PPose::from_parts(near(&mut rng, 0.3), turn(&mut rng));
            let bx = PPose::from_parts(near(&mut rng, 0.3), turn(&mut rng));
            let he = PVec::new(rng.random_range(0.01..0.3), rng.random_range(0.01..0.3), rng.random_range(0.01..0.3));
            for posture in 0..=postures.len() {
                let one_by_one: Vec<Option<bool>> = shapes
                    .iter()
                    .enumerate()
                    .map(|(i, s)| {
                        let own = &s.placed.pose;
                        let pose = postures.get(posture).map_or(own, |p| &p.poses[i]);
                        let c = place(&link, pose, true).translation;
                        ball_meets_box(c, s.placed.eroded_ball.expect("a ball"), &bx, he)
                    })
                    .collect();
                let expected = if one_by_one.contains(&Some(true)) {
                    Some(true)
                } else if one_by_one.iter().all(|v| *v == Some(false)) {
                    Some(false)
                } else {
                    None
                };
                let got = pack.meets_box(posture, &link, &bx, he);
                assert_eq!(got, expected, "{one_by_one:?}");
                seen[match got {
                    Some(true) => 0,
                    Some(false) => 1,
                    None => 2,
                }] += 1;
            }
        }
        // Both verdicts are common; unsure needs a ball within a nanometre of touching.
        assert!(seen[0] > 3000 && seen[1] > 3000, "{seen:?}");
    }

    /// A ball whose eroded radius exactly reaches the box's face is left to the caller, and
    /// one a micrometre nearer or farther is decided.
    #[test]
    fn a_ball_touching_the_box_is_unsure() {
        let he = PVec::new(0.1, 0.2, 0.3);
        let ball = Placed::new(SharedShape::ball(0.05), PPose::IDENTITY);
        let r = ball.eroded_ball.expect("a ball");
        let shapes = vec![RShape { body: 0, placed: ball, unturned: true }];
        let pack = BallPack::of(&shapes, 0, &[]).expect("balls only");
        let at = |x: f64| PPose::from_parts(PVec::new(x, 0.0, 0.0), Rotation::IDENTITY);
        assert_eq!(pack.meets_box(0, &at(0.1 + r), &PPose::IDENTITY, he), None);
        assert_eq!(pack.meets_box(0, &at(0.1 + r - 1e-6), &PPose::IDENTITY, he), Some(true));
        assert_eq!(pack.meets_box(0, &at(0.1 + r + 1e-6), &PPose::IDENTITY, he), Some(false));
    }

    /// Not a pack: a body with a shape other than a ball.
    #[test]
    fn a_body_with_a_box_is_no_pack() {
        let ball = Placed::new(SharedShape::ball(0.05), PPose::IDENTITY);
        let cube = Placed::new(SharedShape::cuboid(0.1, 0.1, 0.1), PPose::IDENTITY);
        let shapes: Vec<RShape> =
            [ball, cube].into_iter().map(|placed| RShape { body: 0, placed, unturned: true }).collect();
        assert!(BallPack::of(&shapes, 0, &[]).is_none());
        assert!(BallPack::of(&shapes[..1], 0, &[]).is_some());
    }
}
