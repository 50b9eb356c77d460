//! One labelled check of a TX-90 with an SAH hand against a table and 10 or 200
//! removable objects, cycling through 256 seeded random configurations (the 10-object
//! cell also without the check's shortcuts, `_plain`, and with the TX-90 of meshes of
//! `../shared`), and of the Panda of spheres of `../shared` in a narrow gap; and the
//! inverse kinematics of one grasp pose, all solutions, and of one pose of the shared
//! Panda (7 joints) in closed form and by the numeric solver.
//!
//! Measured twice: wall time (criterion's default), and the benchmark thread's own
//! CPU time (`CLOCK_THREAD_CPUTIME_ID`), which is what one core spends per
//! check even when the machine is shared and the thread waits for a core.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, Criterion};
use declutter::diag::{FileId, FsLoader, Span};
use declutter::resolve::*;
use declutter::world::{build, CheckCtx, World, WorldOptions};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "support/cpu_time.rs"]
mod cpu_time;
use cpu_time::CpuTime;

fn at(x: f64, y: f64, z: f64) -> Pose {
    Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::identity())
}

fn body(name: String, shape: Shape, pose: Pose) -> Body {
    Body {
        name,
        span: Span::default(),
        pose_world_body: pose,
        parts: vec![Part { shape, pose_world_part: pose, pose_body_part: Pose::identity(), span: Span::default() }],
    }
}

fn file(p: PathBuf) -> FileRef {
    FileRef { written: p.display().to_string(), path: p, span: Span::new(FileId(0), 0, 1) }
}

fn robot(name: &str, urdf: PathBuf, hand: Option<HandId>, home: Vec<f64>) -> Robot {
    Robot {
        name: name.into(),
        span: Span::default(),
        urdf: file(urdf),
        pose_world_base: Pose::identity(),
        hand,
        flange: None,
        srdf: None,
        home: JointValues { values: home, span: Span::default(), units: Vec::new() },
        drop: None,
        allow_contact: vec![],
        open: None,
        closed: None,
    }
}

fn world(objects: usize) -> World {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    world_of(root.join("examples/robots/tx90.urdf"), objects, &WorldOptions::default())
}

/// The same cell with another TX-90 model (the shared package's, whose links are meshes).
fn world_of(urdf: PathBuf, objects: usize, opts: &WorldOptions) -> World {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let hand = Hand {
        name: "sah".into(),
        span: Span::default(),
        urdf: file(root.join("examples/hands/sah.urdf")),
        pose_flange_tcp: at(0.0, 0.0, 0.16),
    };
    let robot = robot("tx90", urdf, Some(HandId(0)), vec![0.0, 0.0, 90f64.to_radians(), 0.0, 0.0, 0.0]);
    // Table top at z 0.40 in front of the robot; objects standing on it in a grid.
    let table = body("table".into(), Shape::Box { size: Vector3::new(1.2, 1.6, 0.1) }, at(0.95, 0.0, 0.35));
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let objs = (0..objects)
        .map(|i| {
            let (x, y) = (rng.random_range(0.45..1.5), rng.random_range(-0.75..0.75));
            let shape = if i % 2 == 0 {
                Shape::Cylinder { radius: 0.033, length: 0.12 }
            } else {
                Shape::Box { size: Vector3::new(0.06, 0.08, 0.1) }
            };
            Object { body: body(format!("o{i}"), shape, at(x, y, 0.46)), grasps: vec![] }
        })
        .collect();
    let scn = Scenario {
        name: None,
        root: root.join("bench.dcl"),
        hands: vec![hand],
        robots: vec![robot],
        fixed: vec![table],
        objects: objs,
        target: Target::Object { object: ObjectId(0), span: Span::default() },
        planner: PlannerSettings::default(),
    };
    build(&scn, opts, &FsLoader).unwrap_or_else(|e| panic!("{e:?}"))
}

/// A Panda of `../shared/robots/panda/` (`path` in it) at its home, no hand, among `fixed`
/// and `objects`, a configuration target; `None` when ../shared is absent.
fn panda_among(path: &str, fixed: Vec<Body>, objects: Vec<Object>, opts: &WorldOptions) -> Option<World> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let urdf = root.join("../shared/robots/panda").join(path);
    if !urdf.is_file() {
        eprintln!("skipped a Panda: {} is absent", urdf.display());
        return None;
    }
    let robot = robot("panda", urdf, None, vec![0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785]);
    let q = robot.home.clone();
    let scn = Scenario {
        name: None,
        root: root.join("bench.dcl"),
        hands: vec![],
        robots: vec![robot],
        fixed,
        objects,
        target: Target::Config { robot: RobotId(0), q, span: Span::default() },
        planner: PlannerSettings::default(),
    };
    Some(build(&scn, opts, &FsLoader).unwrap_or_else(|e| panic!("{e:?}")))
}

/// The shared Panda alone on the floor, no hand.
fn panda(opts: &WorldOptions) -> Option<World> {
    let floor = body("floor".into(), Shape::Box { size: Vector3::new(1.6, 1.6, 0.04) }, at(0.0, 0.0, -0.02));
    panda_among("example-robot-data/robots/panda_description/urdf/panda.urdf", vec![floor], vec![], opts)
}

/// The shared Panda of spheres (`vamp/panda_spherized.urdf`) between the walls of a narrow
/// gap (the benchmark family's problem 34: a table, two walls, a shelf board above and
/// below the gap, four boxes on the floor).
fn panda_spheres_gap() -> Option<World> {
    let turned = |x: f64, y: f64, z: f64| {
        Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(0.0, 0.0, -0.592_68))
    };
    let slab = |name: &str, (dx, dy, dz): (f64, f64, f64), (x, y, z): (f64, f64, f64)| {
        body(name.into(), Shape::Box { size: Vector3::new(dx, dy, dz) }, turned(x, y, z))
    };
    let fixed = vec![
        body("table".into(), Shape::Box { size: Vector3::new(1.6, 1.6, 0.04) }, at(0.0, 0.0, -0.02)),
        slab("o0", (0.02, 0.5, 0.871), (0.5922, 0.0218, 0.4354)),
        slab("o1", (0.02, 0.5, 0.871), (0.2024, -0.5570, 0.4354)),
        slab("o2", (0.02, 0.198, 0.372), (0.3973, -0.2676, 0.1860)),
        slab("o3", (0.02, 0.198, 0.301), (0.3973, -0.2676, 0.7203)),
    ];
    let objects = [(0.4297, -0.0762), (0.2362, -0.3636), (0.4667, -0.0212), (0.1956, -0.4239)]
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| Object {
            body: slab(&format!("o{}", i + 4), (0.05, 0.05, 0.1), (x, y, 0.05)),
            grasps: vec![],
        })
        .collect();
    panda_among("vamp/panda_spherized.urdf", fixed, objects, &WorldOptions::default())
}

fn configs(w: &World) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let lim = w.limits(RobotId(0)).to_vec();
    (0..256).map(|_| lim.iter().map(|(lo, hi)| rng.random_range(*lo..*hi)).collect()).collect()
}

fn bench_wall(c: &mut Criterion) {
    bench(c, "")
}

fn bench_cpu(c: &mut Criterion<CpuTime>) {
    bench(c, "cpu_")
}

fn bench<M: Measurement + 'static>(c: &mut Criterion<M>, tag: &str) {
    // Inverse kinematics of one grasp pose, every solution: the TCP above the table,
    // pointing down, as a top grasp of a can leaves it.
    let w = world(10);
    let q = [0.3, 0.7, 1.3, 0.2, 1.1, 0.5];
    let pose = w.fk_tcp(RobotId(0), &q);
    let n = w.ik(RobotId(0), &pose, 1, usize::MAX).len();
    eprintln!("ik: {n} in-limit solutions for the grasp pose");
    c.bench_function(&format!("{tag}ik_tx90_sah_all_solutions"), |b| {
        b.iter(|| black_box(w.ik(RobotId(0), black_box(&pose), 1, usize::MAX)))
    });
    // What `selectGrasps` asks for: six solutions.
    c.bench_function(&format!("{tag}ik_tx90_sah_six_solutions"), |b| {
        b.iter(|| black_box(w.ik(RobotId(0), black_box(&pose), 1, 6)))
    });
    // The Panda: a pose in front of it, pointing down; six solutions as `selectGrasps`
    // asks, in closed form (joint 7 sampled) and by damped least squares.
    let numeric = WorldOptions { closed_form_ik: false, ..WorldOptions::default() };
    if let (Some(wc), Some(wn)) = (panda(&WorldOptions::default()), panda(&numeric)) {
        let pose = wc.fk_tcp(RobotId(0), &[0.3, 0.4, -0.2, -1.9, 0.1, 2.2, 0.6]);
        for (name, w) in [("closed_form", &wc), ("numeric", &wn)] {
            let n = w.ik(RobotId(0), &pose, 1, 6).len();
            eprintln!("ik panda {name}: {n} solutions");
            c.bench_function(&format!("{tag}ik_panda_six_solutions_{name}"), |b| {
                b.iter(|| black_box(w.ik(RobotId(0), black_box(&pose), 1, 6)))
            });
        }
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let meshes = root.join("../shared/robots/tx90/tx90.urdf");
    let mut cells: Vec<(String, World)> = [10, 200].map(|n| (format!("tx90_sah_table_{n}_objects"), world(n))).into();
    // The same check without its shortcuts (self-collision grids, bodies placed on demand).
    let plain = WorldOptions { fast_check: false, ..WorldOptions::default() };
    cells
        .push(("tx90_sah_table_10_objects_plain".into(), world_of(root.join("examples/robots/tx90.urdf"), 10, &plain)));
    // The TX-90 of ../shared, its links convex hulls of its collision meshes.
    if meshes.is_file() {
        cells.push(("tx90_mesh_sah_table_10_objects".into(), world_of(meshes, 10, &WorldOptions::default())));
    } else {
        eprintln!("skipped the mesh TX-90: {} is absent", meshes.display());
    }
    // The Panda of spheres in a narrow gap: its bodies of balls (see `world/ball_pack.rs`).
    if let Some(w) = panda_spheres_gap() {
        cells.push(("panda_spheres_narrow_gap".into(), w));
    }
    for (name, w) in &cells {
        let qs = configs(w);
        let ctx = CheckCtx::new();
        let (mut blocked, mut touching) = (0, 0);
        for q in &qs {
            match w.check(RobotId(0), q, &ctx) {
                declutter::world::Check::Blocked(_) => blocked += 1,
                declutter::world::Check::Touches(s) if !s.is_empty() => touching += 1,
                _ => {}
            }
        }
        eprintln!("{name}: of {} configurations {blocked} blocked, {touching} touch objects", qs.len());
        let mut i = 0;
        c.bench_function(&format!("{tag}check_{name}"), |b| {
            b.iter(|| {
                i = (i + 1) % qs.len();
                black_box(w.check(RobotId(0), black_box(&qs[i]), &ctx))
            })
        });
        // Free configurations only: the full cost of a check that finds nothing fixed.
        let free: Vec<_> = qs.iter().filter(|q| !w.check(RobotId(0), q, &ctx).is_blocked()).cloned().collect();
        let mut j = 0;
        c.bench_function(&format!("{tag}check_{name}_unblocked"), |b| {
            b.iter(|| {
                j = (j + 1) % free.len();
                black_box(w.check(RobotId(0), black_box(&free[j]), &ctx))
            })
        });
    }
}

criterion_group!(wall, bench_wall);
criterion_group! {
    name = cpu;
    config = Criterion::default().with_measurement(CpuTime::thread());
    targets = bench_cpu
}
criterion_main!(wall, cpu);
