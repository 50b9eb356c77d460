//! A body of balls only (a spherized link) tested all at once: against a box, its centres
//! taken straight into the box's frame by one matrix, instead of each ball placed in the
//! world, bounded, and tested on its own (most of a spherized arm's check went there);
//! against another body of balls (self-collision, and a self-collision grid's measure),
//! pair by pair on squared distances, skipping the balls far from the other body.

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
    /// Per ball its radius and eroded radius; `-inf` for the padding, whose gaps are then
    /// infinite.
    radius: Vec<f64>,
    eroded: Vec<f64>,
    /// Per set, a ball holding all of them (centre in the link's frame, radius): a ball of
    /// the other body farther from it than the least gap so far is skipped whole.
    bounds: Vec<(PVec, f64)>,
    /// The set of the shapes' own poses (the last).
    own: usize,
}

/// A pack's balls placed in the world: centres as columns (`x`, `y`, `z`, `n` each).
#[derive(Default)]
pub(crate) struct PlacedBalls {
    centres: Vec<f64>,
    /// The pack's bounding ball, placed.
    bound: (PVec, f64),
}

impl BallPack {
    /// The pack of `shapes` (a body's) when every one is a ball with an eroded radius,
    /// whatever the posture; `None` otherwise.
    pub fn of(shapes: &[RShape], first: usize, postures: &[Posture]) -> Option<BallPack> {
        let balls: Vec<(f64, f64)> = shapes
            .iter()
            .map(|s| match s.placed.boxed {
                Boxed::Ball(r) => s.placed.eroded_ball.map(|e| (r, e)),
                _ => None,
            })
            .collect::<Option<_>>()?;
        if balls.is_empty() {
            return None;
        }
        let n = balls.len().div_ceil(LANES) * LANES;
        let mut centres = Vec::with_capacity((postures.len() + 1) * 3 * n);
        for set in 0..=postures.len() {
            let pose = |i: usize| {
                let si = first + i;
                postures.get(set).and_then(|p| p.poses.get(si)).unwrap_or(&shapes[i].placed.pose).translation
            };
            for axis in 0..3 {
                centres.extend((0..n).map(|i| if i < balls.len() { pose(i)[axis] } else { 0.0 }));
            }
        }
        let (mut outside, mut inside) = (vec![-1.0; n], vec![-1.0; n]);
        for (i, (_, r)) in balls.iter().enumerate() {
            outside[i] = (r + BALL_MARGIN) * (r + BALL_MARGIN);
            if *r > BALL_MARGIN {
                inside[i] = (r - BALL_MARGIN) * (r - BALL_MARGIN);
            }
        }
        let pad = |v: Vec<f64>| v.into_iter().chain(std::iter::repeat(f64::NEG_INFINITY)).take(n).collect();
        let radius = pad(balls.iter().map(|b| b.0).collect());
        let eroded = pad(balls.iter().map(|b| b.1).collect());
        let bounds = (0..=postures.len())
            .map(|set| {
                let at = |i: usize| {
                    let c = &centres[set * 3 * n..];
                    PVec::new(c[i], c[n + i], c[2 * n + i])
                };
                let k = balls.len();
                let centre = (0..k).map(at).fold(PVec::ZERO, |a, c| a + c) / k as f64;
                (centre, (0..k).map(|i| at(i).distance(centre) + balls[i].0).fold(0.0, f64::max))
            })
            .collect();
        Some(BallPack { n, centres, outside, inside, radius, eroded, bounds, own: postures.len() })
    }

    /// Whether a ball of the body, its link at `link` and the fingers in `posture`, meets
    /// the box of half extents `he` at `bx` deeper than the contact tolerance: what
    /// [`super::shapes::ball_meets_box`] says of each ball, `None` when it is unsure of one
    /// and sure of none meeting (the caller then asks ball by ball).
    #[inline]
    pub fn meets_box(&self, posture: usize, link: &PPose, bx: &PPose, he: PVec) -> Option<bool> {
        let (xs, ys, zs) = self.set(posture);
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

    /// The posture set for `posture`: its own, or the shapes' own poses.
    fn set_of(&self, posture: usize) -> usize {
        posture.min(self.own)
    }

    /// The set of centres for `posture`.
    fn set(&self, posture: usize) -> (&[f64], &[f64], &[f64]) {
        let (set, n) = (self.set_of(posture), self.n);
        let c = &self.centres[set * 3 * n..(set + 1) * 3 * n];
        let (xs, rest) = c.split_at(n);
        let (ys, zs) = rest.split_at(n);
        (xs, ys, zs)
    }

    /// Its balls' centres in the world, the link at `link` and the fingers in `posture`.
    pub fn place(&self, posture: usize, link: &PPose, out: &mut PlacedBalls) {
        let (xs, ys, zs) = self.set(posture);
        let m = Matrix::from_quat(link.rotation);
        let (n, t) = (self.n, link.translation);
        let (c, r) = self.bounds[self.set_of(posture)];
        out.bound = (link.translation + link.rotation * c, r);
        out.centres.resize(3 * n, 0.0);
        let (ox, rest) = out.centres.split_at_mut(n);
        let (oy, oz) = rest.split_at_mut(n);
        for i in 0..n {
            let (x, y, z) = (xs[i], ys[i], zs[i]);
            ox[i] = m.x_axis.x * x + m.y_axis.x * y + m.z_axis.x * z + t.x;
            oy[i] = m.x_axis.y * x + m.y_axis.y * y + m.z_axis.y * z + t.y;
            oz[i] = m.x_axis.z * x + m.y_axis.z * y + m.z_axis.z * z + t.z;
        }
    }

    /// The least gap between a ball of `self` (placed at `pa`) and one of `other` (at
    /// `pb`), a pair's gap being its centres' distance less both radii (two balls'
    /// distance); `limit` when none is below it. A pair is measured (a square root) only
    /// when its squared centre distance says it may be below the least so far.
    pub fn least_gap(&self, pa: &PlacedBalls, other: &BallPack, pb: &PlacedBalls, limit: f64) -> f64 {
        let (n, m) = (self.n, other.n);
        let (ax, ay, az) = columns(&pa.centres, n);
        let (bx, by, bz) = columns(&pb.centres, m);
        let mut best = limit;
        let (bc, br) = pb.bound;
        for i in 0..n {
            let (x, y, z, r) = (ax[i], ay[i], az[i], self.radius[i]);
            if !near_bound(PVec::new(x, y, z), best + r + br, bc) {
                continue;
            }
            for k in (0..m).step_by(LANES) {
                let d2 = squared_distances((x, y, z), (bx, by, bz), k);
                let mut near = false;
                for (d2, rb) in d2.iter().zip(&other.radius[k..k + LANES]) {
                    let reach = best + r + rb;
                    near |= reach > 0.0 && *d2 < reach * reach;
                }
                if near {
                    for (d2, rb) in d2.iter().zip(&other.radius[k..k + LANES]) {
                        best = best.min(d2.sqrt() - r - rb);
                    }
                }
            }
        }
        best
    }

    /// Whether a ball of `self` (at `pa`) overlaps one of `other` (at `pb`) deeper than the
    /// contact tolerance: `self`'s eroded ball meets `other`'s, as the exact test decides a
    /// pair of balls; `None` when unsure of one pair (within [`BALL_MARGIN`] of touching)
    /// and sure of none meeting.
    pub fn meets(&self, pa: &PlacedBalls, other: &BallPack, pb: &PlacedBalls) -> Option<bool> {
        let (n, m) = (self.n, other.n);
        let (ax, ay, az) = columns(&pa.centres, n);
        let (bx, by, bz) = columns(&pb.centres, m);
        let mut unsure = false;
        let (bc, br) = pb.bound;
        for i in 0..n {
            let (x, y, z, e) = (ax[i], ay[i], az[i], self.eroded[i]);
            if !near_bound(PVec::new(x, y, z), e + br + BALL_MARGIN, bc) {
                continue;
            }
            let mut hit = false;
            for k in (0..m).step_by(LANES) {
                let d2 = squared_distances((x, y, z), (bx, by, bz), k);
                for (d2, rb) in d2.iter().zip(&other.radius[k..k + LANES]) {
                    let reach = e + rb;
                    // Padding reaches -inf: never near.
                    let (inner, outer) = (reach - BALL_MARGIN, reach + BALL_MARGIN);
                    hit |= inner > 0.0 && *d2 < inner * inner;
                    unsure |= outer >= 0.0 && *d2 <= outer * outer || d2.is_nan();
                }
            }
            if hit {
                return Some(true);
            }
        }
        (!unsure).then_some(false)
    }
}

/// Whether `c` may be nearer than `reach` to `centre`: never when `reach` is not positive
/// (the padding's is `-inf`), always when `c` is not a number (the pairs then say unsure).
/// Rounding aside, nothing farther can matter, so the test is widened by a micrometre.
#[inline]
fn near_bound(c: PVec, reach: f64, centre: PVec) -> bool {
    let reach = reach + 1e-6;
    let d2 = c.distance_squared(centre);
    reach > 0.0 && (d2 < reach * reach || d2.is_nan())
}

/// The squared distances from `(x, y, z)` to the centres `k..k + LANES` of `columns`.
#[inline(always)]
fn squared_distances((x, y, z): (f64, f64, f64), (bx, by, bz): (&[f64], &[f64], &[f64]), k: usize) -> [f64; LANES] {
    std::array::from_fn(|l| {
        let (dx, dy, dz) = (bx[k + l] - x, by[k + l] - y, bz[k + l] - z);
        dx * dx + dy * dy + dz * dz
    })
}

/// The three columns of `n` centres.
fn columns(c: &[f64], n: usize) -> (&[f64], &[f64], &[f64]) {
    let (xs, rest) = c[..3 * n].split_at(n);
    let (ys, zs) = rest.split_at(n);
    (xs, ys, zs)
}

#[cfg(test)]
mod tests {
    use parry3d_f64::math::{Pose as PPose, Rotation, Vector as PVec};
    use parry3d_f64::query;
    use parry3d_f64::shape::{Ball, SharedShape};
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

    /// A random body of balls, a posture moving some of them or none, and the shapes.
    fn random_body(rng: &mut ChaCha8Rng) -> (Vec<RShape>, Vec<Posture>) {
        let n = rng.random_range(1..12);
        let shapes: Vec<RShape> = (0..n)
            .map(|_| {
                let pose = PPose::from_parts(near(rng, 0.15), Rotation::IDENTITY);
                let ball = SharedShape::ball(rng.random_range(0.003..0.06));
                RShape { body: 0, placed: Placed::new(ball, pose), unturned: true }
            })
            .collect();
        let postures = match rng.random_bool(0.5) {
            true => vec![Posture {
                values: vec![],
                poses: shapes
                    .iter()
                    .enumerate()
                    .map(|(i, s)| {
                        let shift = if i % 3 == 0 { near(rng, 0.05) } else { PVec::ZERO };
                        PPose::from_parts(s.placed.pose.translation + shift, Rotation::IDENTITY)
                    })
                    .collect(),
            }],
            false => vec![],
        };
        (shapes, postures)
    }

    /// Two random bodies of balls at random link poses: the least gap is the least of every
    /// pair's distance (parry's), or the limit when that is less (negative for balls that
    /// overlap); the overlap test says
    /// what parry's intersection test of each eroded ball with each ball says.
    #[test]
    fn two_packs_measure_and_meet_as_their_balls_do() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut met, mut apart, mut limited) = (0, 0, 0);
        for _ in 0..4000 {
            let (sa, posa) = random_body(&mut rng);
            let (sb, posb) = random_body(&mut rng);
            let (pa, pb) = (BallPack::of(&sa, 0, &posa).expect("balls"), BallPack::of(&sb, 0, &posb).expect("balls"));
            let (la, lb) = (
                PPose::from_parts(near(&mut rng, 0.2), turn(&mut rng)),
                PPose::from_parts(near(&mut rng, 0.2), turn(&mut rng)),
            );
            let posture = rng.random_range(0..2);
            let (mut wa, mut wb) = (super::PlacedBalls::default(), super::PlacedBalls::default());
            pa.place(posture, &la, &mut wa);
            pb.place(posture, &lb, &mut wb);
            let balls = |shapes: &[RShape], postures: &[Posture], link: &PPose| -> Vec<(PPose, f64, f64)> {
                shapes
                    .iter()
                    .enumerate()
                    .map(|(i, s)| {
                        let pose = postures.get(posture).map_or(&s.placed.pose, |p| &p.poses[i]);
                        let r = s.placed.shape.as_ball().expect("a ball").radius;
                        (place(link, pose, true), r, s.placed.eroded_ball.expect("a ball"))
                    })
                    .collect()
            };
            let (ba, bb) = (balls(&sa, &posa, &la), balls(&sb, &posb, &lb));
            let mut least = f64::INFINITY;
            let mut meets = false;
            for (pi, ri, ei) in &ba {
                for (pj, rj, _) in &bb {
                    let (i, j) = (Ball::new(*ri), Ball::new(*rj));
                    least = least.min(query::distance(pi, &i, pj, &j).expect("balls").distance);
                    meets |= query::intersection_test(pi, &Ball::new(*ei), pj, &j).expect("balls").intersecting;
                }
            }
            let limit = rng.random_range(0.0..0.05);
            let gap = pa.least_gap(&wa, &pb, &wb, limit);
            // parry's distance of overlapping balls is 0; the gap is then negative.
            match least > 0.0 {
                true => assert!((gap - least.min(limit)).abs() < 1e-12, "{gap} against {least} (limit {limit})"),
                false => assert!(gap <= 0.0, "{gap} for overlapping balls"),
            }
            limited += usize::from(least > limit);
            assert_eq!(pa.meets(&wa, &pb, &wb), Some(meets));
            (met, apart) = (met + usize::from(meets), apart + usize::from(!meets && least < limit));
        }
        // Overlaps, near misses measured, and pairs past the limit all common.
        assert!(met > 500 && apart > 100 && limited > 500, "{met} {apart} {limited}");
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

    /// A link pose that is not a number is never found apart (a meeting or unsure; the
    /// check's limits test blocks such a configuration before any of this).
    #[test]
    fn a_pose_not_a_number_is_never_apart() {
        let shapes =
            vec![RShape { body: 0, placed: Placed::new(SharedShape::ball(0.05), PPose::IDENTITY), unturned: true }];
        let pack = BallPack::of(&shapes, 0, &[]).expect("balls only");
        let nan = PPose::from_parts(PVec::new(f64::NAN, 0.0, 0.0), Rotation::IDENTITY);
        assert_ne!(pack.meets_box(0, &nan, &PPose::IDENTITY, PVec::splat(0.1)), Some(false));
        let (mut wa, mut wb) = (super::PlacedBalls::default(), super::PlacedBalls::default());
        pack.place(0, &nan, &mut wa);
        pack.place(0, &PPose::IDENTITY, &mut wb);
        assert_ne!(pack.meets(&wa, &pack, &wb), Some(false));
        assert_ne!(pack.meets(&wb, &pack, &wa), Some(false));
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
