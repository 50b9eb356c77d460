//! The labelled check's fast paths (the joint-space grids of self-collision distances,
//! and a body's shapes placed only when its box is near something) against the plain
//! check: the same verdict, to the blocker named, on 100 000 random configurations of
//! every robot the examples ship and of the arms of `../shared/robots` (skipped, saying
//! so, when that is absent).

#[path = "common/families.rs"]
mod families;

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::{ObjectId, RobotId};
use declutter::world::{self, Blocker, Check, CheckCtx, World, WorldOptions};
use families::{shared_robots, Arm, ARMS};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SAMPLES: usize = 100_000;

fn worlds(path: &Path) -> (World, World) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(path, &FsLoader, &mut sources).unwrap_or_else(|e| panic!("{e:?}"));
    let build = |fast: bool| {
        let opts = WorldOptions { fast_check: fast, ..WorldOptions::default() };
        world::build(&scn, &opts, &FsLoader).unwrap_or_else(|e| panic!("{}: {e:?}", path.display()))
    };
    (build(true), build(false))
}

/// What the comparison saw, for the assertions that it was not vacuous.
#[derive(Default, Debug)]
struct Seen {
    grid_apart: u64,
    /// Bodies placed by the fast check and by the plain one.
    placed: (u64, u64),
    self_blocked: usize,
    held: usize,
    /// Carried objects that hit the arm carrying them.
    held_self: usize,
    /// Contacts with a box that a ball inside a hull proved.
    inner_proved: u64,
}

/// Compares both worlds on robot `r` at random configurations: uniform in the limits, or
/// near home (where the wrist folds over the forearm less often), sometimes carrying the
/// first object by its first grasp (the fingers closed on it).
fn compare(name: &str, fast: &World, exact: &World, r: RobotId, seed: u64, held_every: usize) -> Seen {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let limits = fast.limits(r).to_vec();
    let home = fast.home(r).to_vec();
    let has_object = !fast.scenario().objects.is_empty() && !fast.scenario().objects[0].grasps.is_empty();
    let mut seen = Seen::default();
    for i in 0..SAMPLES {
        let spread = if i % 2 == 0 { 1.0 } else { 0.3 };
        let q: Vec<f64> = limits
            .iter()
            .zip(&home)
            .map(|((lo, hi), h)| (h + spread * (lo + rng.random::<f64>() * (hi - lo) - h)).clamp(*lo, *hi))
            .collect();
        let (a, b) = if has_object && i % held_every == held_every - 1 {
            seen.held += 1;
            let h = fast.held(r, ObjectId(0), 0, &q);
            (CheckCtx::with_held(Default::default(), h.clone()), CheckCtx::with_held(Default::default(), h))
        } else {
            (CheckCtx::new(), CheckCtx::new())
        };
        let (got, want) = (fast.check(r, &q, &a), exact.check(r, &q, &b));
        assert_eq!(got, want, "{name}, robot {r:?}, sample {i}, q = {q:?}");
        assert_eq!(b.grid_apart.get(), 0, "the plain check used a grid");
        assert_eq!(b.inner_proved.get(), 0, "the plain check used a hull's balls");
        seen.inner_proved += a.inner_proved.get();
        seen.grid_apart += a.grid_apart.get();
        seen.placed.0 += a.bodies_placed.get();
        seen.placed.1 += b.bodies_placed.get();
        match want {
            Check::Blocked(Blocker::SelfCollision { .. }) => seen.self_blocked += 1,
            Check::Blocked(Blocker::HeldSelf { .. }) => seen.held_self += 1,
            _ => {}
        }
    }
    seen
}

fn example(name: &str) -> Vec<Seen> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(format!("{name}.dcl"));
    let (fast, exact) = worlds(&path);
    (0..fast.scenario().robots.len())
        .map(|r| compare(name, &fast, &exact, RobotId(r as u32), 11 + r as u64, 5))
        .inspect(|s| eprintln!("{name}: {s:?}"))
        .collect()
}

/// Every shipped robot and hand: the TX-90 with the SAH and SDH2 hands (`box_lid`), with
/// the parallel gripper whose fingers close on the object (`gripper`); the planar arm.
#[test]
fn the_fast_check_changes_no_verdict_on_the_shipped_robots() {
    for seen in example("box_lid").into_iter().chain(example("gripper")) {
        // Not vacuous: the grids answered often, and self-collisions were still found.
        assert!(seen.grid_apart > SAMPLES as u64 / 2, "{seen:?}");
        assert!(seen.self_blocked > 1000, "{seen:?}");
        assert!(seen.held > 0, "{seen:?}");
        assert!(seen.placed.0 < seen.placed.1 * 3 / 4, "{seen:?}");
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fast_check");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let planar = dir.join("planar.dcl");
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/robots/planar3.urdf");
    let text = format!(
        "scenario \"planar\"\nrobot p {{\n    urdf \"{}\"\n    home [0, 0, 0]\n}}\n\
         fixed post box(10cm, 10cm, 10cm) at (60cm, 30cm, 0)\ntarget p at [0, 90deg, 0]\n",
        urdf.display()
    );
    std::fs::write(&planar, text).expect("written");
    let (fast, exact) = worlds(&planar);
    let seen = compare("planar", &fast, &exact, RobotId(0), 5, 5);
    eprintln!("planar: {seen:?}");
    assert!(seen.grid_apart > 0 && seen.self_blocked > 0, "{seen:?}");
}

/// A bar 80 cm long in the SAH hand, carried half the time: it sweeps past the arm that
/// holds it, so the carried object's tests against the arm's bodies are exercised.
#[test]
fn the_fast_check_changes_no_verdict_for_a_long_carried_bar() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fast_check");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join("long_bar.dcl");
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    // No table: nothing fixed can stop a check before the bar is tested against the arm.
    let text = format!(
        "scenario \"long-bar\"\n\
         hand sah {{\n    urdf \"{0}/hands/sah.urdf\"\n    tcp at (0, 0, 16cm)\n}}\n\
         robot r1 {{\n    urdf \"{0}/robots/tx90.urdf\"\n    hand sah\n    home [0, -20deg, 110deg, 0, 60deg, 0]\n}}\n\
         object bar box(80cm, 4cm, 4cm) at (1m, 0, 50cm) {{\n\
             grasp top at (0, 0, 2cm) rot (180deg, 0, 0) approach 10cm\n}}\ntarget bar\n",
        examples.display()
    );
    std::fs::write(&path, text).expect("written");
    let (fast, exact) = worlds(&path);
    let seen = compare("long_bar", &fast, &exact, RobotId(0), 21, 2);
    eprintln!("long_bar: {seen:?}");
    assert!(seen.held_self > 50 && seen.placed.0 < seen.placed.1 * 3 / 4, "{seen:?}");
}

/// The arms of `../shared/robots` as the benchmark families load them: the TX-90 of
/// meshes with the SAH hand, the Panda's spheres, the UR5, the Panda of meshes with its
/// hand and SRDF.
#[test]
fn the_fast_check_changes_no_verdict_on_the_shared_arms() {
    let Some(robots) = shared_robots() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fast_check");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    for (k, arm) in ARMS.into_iter().enumerate() {
        let path = dir.join(format!("{arm:?}.dcl"));
        let text = format!("scenario \"fast-check\"\n{}target arm at {}\n", arm.cell(&robots), arm.home());
        std::fs::write(&path, text).expect("written");
        let (fast, exact) = worlds(&path);
        let seen = compare(&format!("{arm:?}"), &fast, &exact, RobotId(0), 100 + k as u64, 5);
        eprintln!("{arm:?}: {seen:?}");
        assert!(seen.grid_apart > 0 && seen.placed.0 < seen.placed.1, "{arm:?}: {seen:?}");
        // Every arm of meshes had contacts proved by its hulls' balls (the Panda's spheres
        // have no hulls).
        assert_eq!(seen.inner_proved > 0, arm != Arm::Panda, "{arm:?}: {seen:?}");
    }
}
