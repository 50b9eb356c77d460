//! The checks of a segment's samples with the hand empty and carrying an object at once
//! (`World::check_samples_twin`: how the planner walks an edge that a path takes both
//! ways, out with the hand empty and back carrying) against the two checks they stand
//! for: the same answers, blockers named alike, on random segments of the shipped
//! examples, carrying every object by its reachable grasps, for the coarse samples and for
//! the certifying ones the coarse check leaves (`World::check_motion_rest_twin`); and
//! where the fingers hold the object open, as in the empty hand, each sample checked once
//! for both.

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::ObjectId;
use declutter::world::{self, Check, CheckCtx, ObjectSet, WorldOptions, OPEN_POSTURE};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What the comparison met, so that a test passing on nothing but free segments fails.
#[derive(Default, Debug)]
struct Seen {
    /// Both free, both touching something.
    touching: usize,
    /// Blocked carrying only (the carried object hits), blocked in both.
    carry_blocked: usize,
    both_blocked: usize,
    /// Segments checked with the fingers closed on the object.
    closed: usize,
}

fn compare(example: &str, segments_per_grasp: usize, seen: &mut Seen) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(example);
    let scn = declutter::resolve::resolve(&path, &FsLoader, &mut SourceMap::new()).unwrap_or_else(|e| panic!("{e:?}"));
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:?}"));
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for r in scn.robot_ids() {
        let limits = w.limits(r).to_vec();
        for o in (0..scn.objects.len()).map(|o| ObjectId(o as u32)) {
            let grasps = w.select_grasps(r, o);
            let ends: Vec<Vec<f64>> = grasps
                .iter()
                .flat_map(|g| [g.q_grasp.0.clone(), g.q_pregrasp.0.clone()])
                .chain([w.home(r).0.clone()])
                .collect();
            for g in grasps.iter().take(3) {
                let held = w.held(r, o, g.grasp, &g.q_grasp);
                for _ in 0..segments_per_grasp {
                    // Between the grasps' configurations and home, each moved a little.
                    let mut end = || -> Vec<f64> {
                        let e = &ends[rng.random_range(0..ends.len())];
                        e.iter()
                            .zip(&limits)
                            .map(|(v, (lo, hi))| (v + 0.3 * (rng.random::<f64>() - 0.5)).clamp(*lo, *hi))
                            .collect()
                    };
                    let (a, b) = (end(), end());
                    let n = rng.random_range(1..40usize);
                    let stride = rng.random_range(1..8usize);
                    let indices: Vec<usize> = (rng.random_range(0..stride)..=n).step_by(stride).collect();
                    // Some other objects already removed.
                    let absent: ObjectSet = (0..scn.objects.len() as u32)
                        .map(ObjectId)
                        .filter(|&x| x != o && rng.random::<f64>() < 0.2)
                        .collect();
                    let twin = CheckCtx::with_held(absent.clone(), held.clone());
                    let (e, c) = w.check_samples_twin(r, (&a, &b), n, &indices, &twin);
                    let (empty, carry) =
                        (CheckCtx::with_absent(absent.clone()), CheckCtx::with_held(absent.clone(), held.clone()));
                    let want_e = w.check_samples(r, (&a, &b), n, &mut indices.iter().copied(), &empty);
                    let want_c = w.check_samples(r, (&a, &b), n, &mut indices.iter().copied(), &carry);
                    let at = format!("{example}, robot {r:?}, object {o:?}, grasp {}: {a:?} -> {b:?}, n {n}", g.grasp);
                    assert_eq!(e, want_e, "empty hand, {at}");
                    assert_eq!(c, want_c, "carrying, {at}");
                    if held.posture == OPEN_POSTURE {
                        assert_eq!(twin.count(), empty.count(), "each sample once, {at}");
                    } else {
                        seen.closed += 1;
                        assert_eq!(twin.count(), empty.count() + carry.count(), "{at}");
                    }
                    // The certifying samples the coarse check does not take, alike.
                    let res = 0.02 + 0.1 * rng.random::<f64>();
                    let (twin, empty, carry) = (
                        CheckCtx::with_held(absent.clone(), held.clone()),
                        CheckCtx::with_absent(absent.clone()),
                        CheckCtx::with_held(absent.clone(), held.clone()),
                    );
                    let (re, rc) = w.check_motion_rest_twin(r, &a, &b, res, &twin);
                    assert_eq!(re, w.check_motion_rest(r, &a, &b, res, &empty), "rest, empty hand, {at}");
                    assert_eq!(rc, w.check_motion_rest(r, &a, &b, res, &carry), "rest, carrying, {at}");
                    let counted = empty.count() + if held.posture == OPEN_POSTURE { 0 } else { carry.count() };
                    assert_eq!(twin.count(), counted, "rest, {at}");
                    match (&e, &c) {
                        (Check::Touches(x), Check::Touches(y)) if !x.is_empty() && !y.is_empty() => seen.touching += 1,
                        (Check::Touches(_), Check::Blocked(_)) => seen.carry_blocked += 1,
                        (Check::Blocked(_), _) => seen.both_blocked += 1,
                        _ => {}
                    }
                }
            }
        }
    }
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn twin_checks_answer_as_the_empty_hand_and_the_carrying_checks() {
    let mut seen = Seen::default();
    for example in ["box_lid.dcl", "cans_5.dcl", "three_arm.dcl", "gripper.dcl"] {
        compare(example, 40, &mut seen);
    }
    eprintln!("{seen:?}");
    assert!(seen.touching > 50 && seen.carry_blocked > 20 && seen.both_blocked > 50 && seen.closed > 50, "{seen:?}");
}
