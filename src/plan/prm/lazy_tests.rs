//! The walk of an edge's samples level by level.

use std::sync::Mutex;

use super::*;
use crate::plan::layers::ModeKey;
use crate::world::{Config, GraspConfig, Held};

/// One joint from 0 to `n` in steps of 1: sample `i` is the configuration `[i]`; the
/// checks are recorded, and the one at `blocked` (if any) is blocked.
struct Line {
    seen: Mutex<Vec<usize>>,
    blocked: Option<usize>,
}

impl Space for Line {
    fn dof(&self) -> usize {
        1
    }
    fn limits(&self) -> &[(f64, f64)] {
        &[(0.0, 1e6)]
    }
    fn check(&self, q: &[f64], _: &Mode, checks: &mut u64) -> Check {
        *checks += 1;
        let i = q[0].round() as usize;
        self.seen.lock().unwrap_or_else(|p| p.into_inner()).push(i);
        match self.blocked == Some(i) {
            true => Check::Blocked(crate::world::Blocker::JointLimit { joint: "j".into(), value: q[0] }),
            false => Check::free(),
        }
    }
    fn check_segment(&self, _: &[f64], _: &[f64], _: f64, _: &Mode, _: &mut u64) -> Check {
        Check::free()
    }
    fn home(&self) -> &[f64] {
        &[0.0]
    }
    fn drop_config(&self) -> &[f64] {
        &[0.0]
    }
    fn grasps(&self, _: ObjectId) -> Vec<GraspConfig> {
        vec![GraspConfig { grasp: 0, q_grasp: Config(vec![0.0]), q_pregrasp: Config(vec![0.0]) }]
    }
    fn held(&self, o: ObjectId, _: usize, _: &[f64]) -> Held {
        Held { object: o, pose_flange_object: nalgebra::Isometry3::identity(), posture: 0 }
    }
}

/// A walk checks every sample of its segment once, the inside ones coarse to fine (the
/// first at the middle power of two, as `check_segment` goes), the ends last.
#[test]
fn a_walk_checks_every_sample_once_coarse_to_fine_and_the_ends_last() {
    for n in 1..=300usize {
        let space = Line { seen: Mutex::new(Vec::new()), blocked: None };
        let mut w = Walk::new(&[0.0], &[n as f64], n);
        let (mut checks, mut levels) = (0, 0);
        while !w.done() {
            assert!(!w.step(&space, &Mode::default(), &mut checks));
            levels += 1;
        }
        let seen = space.seen.into_inner().unwrap_or_else(|p| p.into_inner());
        let mut sorted = seen.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..=n).collect::<Vec<_>>(), "n = {n}");
        assert_eq!(checks as usize, n + 1);
        assert_eq!(&seen[n - 1..], &[0, n], "n = {n}: the ends last");
        if n >= 2 {
            assert_eq!(seen[0], n.next_power_of_two() / 2, "n = {n}: the middle first");
        }
        // One level per halving of the stride, and one for the ends.
        assert_eq!(levels, n.next_power_of_two().trailing_zeros() as usize + 1, "n = {n}");
    }
}

/// A blocked sample ends its level's checks there: the walk says blocked, and no sample
/// after it is checked.
#[test]
fn a_walk_stops_at_a_blocked_sample() {
    let n = 100;
    let space = Line { seen: Mutex::new(Vec::new()), blocked: Some(48) };
    let mut w = Walk::new(&[0.0], &[n as f64], n);
    let mut checks = 0;
    let mut steps = 0;
    while !w.step(&space, &Mode::default(), &mut checks) {
        steps += 1;
        assert!(!w.done());
    }
    // Strides 64 (64) and 32 (32, 96) pass; stride 16 checks 16, then 48: blocked.
    assert_eq!(steps, 2);
    let seen = space.seen.into_inner().unwrap_or_else(|p| p.into_inner());
    assert_eq!(seen, vec![64, 32, 96, 16, 48]);
    assert_eq!(checks, 5);
}

/// Carrying `o` with the fingers open.
fn carrying(o: ObjectId) -> Mode {
    Mode {
        absent: crate::world::ObjectSet::single(o),
        held: Some(Held { object: o, pose_flange_object: nalgebra::Isometry3::identity(), posture: 0 }),
    }
}

/// A carrying edge's walk is stepped with the same edge's empty-hand walk when that is in
/// the same batch at the same level and in the carrying mode's empty hand; every other
/// walk goes alone, and each walk keeps its own job.
#[test]
fn twins_pair_a_carrying_walk_with_its_edges_empty_hand_walk_at_the_same_level() {
    let o = ObjectId(0);
    let held = carrying(o);
    let (m1, m2, m3, m4) = (Node::Map(1), Node::Map(2), Node::Map(3), Node::Map(4));
    let job = |item, mode: &Mode| Job {
        item,
        a: vec![0.0],
        b: Some(vec![8.0]),
        mode: mode.clone(),
        grasp: None,
        empty: None,
    };
    let empty = Mode::default();
    let mut elsewhere = empty.clone();
    elsewhere.absent.insert(ObjectId(1));
    let jobs = vec![
        job(LabelKey::Edge(ModeKey::Empty, m1, m2), &empty),
        job(LabelKey::Edge(ModeKey::Carry(o, 0), m1, m2), &held),
        // A second grasp of the same edge: its empty-hand walk is taken.
        job(LabelKey::Edge(ModeKey::Carry(o, 1), m1, m2), &held),
        // The same edge's empty-hand walk a level further on.
        job(LabelKey::Edge(ModeKey::Empty, m2, m3), &empty),
        job(LabelKey::Edge(ModeKey::Carry(o, 0), m2, m3), &held),
        // No empty-hand walk of this edge.
        job(LabelKey::Edge(ModeKey::Carry(o, 0), m3, m4), &held),
    ];
    let space = Line { seen: Mutex::new(Vec::new()), blocked: None };
    let mut walks: Vec<(usize, Walk)> = (0..jobs.len()).map(|i| (i, Walk::new(&[0.0], &[8.0], 8))).collect();
    assert!(!walks[3].1.step(&space, &empty, &mut 0));
    let walkers = twins(&jobs, walks);
    let pairs: Vec<(usize, Option<usize>)> = walkers.iter().map(|w| (w.i, w.twin.as_ref().map(|t| t.0))).collect();
    assert_eq!(pairs, vec![(1, Some(0)), (2, None), (3, None), (4, None), (5, None)]);
    // The empty hand's mode must be the carrying one's with the object back in place.
    let mut jobs = jobs;
    jobs[0].mode = elsewhere;
    walks = (0..jobs.len()).map(|i| (i, Walk::new(&[0.0], &[8.0], 8))).collect();
    let pairs: Vec<(usize, Option<usize>)> =
        twins(&jobs, walks).iter().map(|w| (w.i, w.twin.as_ref().map(|t| t.0))).collect();
    assert_eq!(pairs, vec![(0, None), (1, None), (2, None), (4, Some(3)), (5, None)]);
}

/// A twin step steps both walks over the same level: each its own label and block.
#[test]
fn a_twin_step_walks_both_levels_and_blocks_each_on_its_own() {
    let held = carrying(ObjectId(0));
    let space = Line { seen: Mutex::new(Vec::new()), blocked: Some(6) };
    let (mut carry, mut empty) = (Walk::new(&[0.0], &[8.0], 8), Walk::new(&[0.0], &[8.0], 8));
    let mut checks = 0;
    // Strides 4 (4), then 2 (2, 6): 6 is blocked in both modes of `Line`.
    assert_eq!(carry.step_twin(&mut empty, &space, &held, &mut checks), (false, false));
    assert_eq!((carry.stride, empty.stride), (2, 2));
    assert_eq!(carry.step_twin(&mut empty, &space, &held, &mut checks), (true, true));
    let seen = space.seen.into_inner().unwrap_or_else(|p| p.into_inner());
    // `Line` takes the default: the empty hand's samples, then the carrying ones.
    assert_eq!(seen, vec![4, 4, 2, 6, 2, 6]);
    assert_eq!(checks, 6);
}
