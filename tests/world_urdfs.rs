//! The real robot files in `../shared/robots` load, with finite forward kinematics.
//! Skipped (with the reason printed) when that directory is absent.

mod world_support;

use std::path::Path;

use declutter::diag::FsLoader;
use declutter::resolve::RobotId;
use declutter::world::{build, load_kinematics, MeshMode, RobotKinematics, WorldOptions};
use world_support::*;

fn load(path: &Path, mode: MeshMode) -> RobotKinematics {
    let opts = WorldOptions { mesh_mode: mode, ..WorldOptions::default() };
    load_kinematics(&file(path, sp(10, 20)), None, &opts, &FsLoader)
        .unwrap_or_else(|e| panic!("{}: {e:#?}", path.display()))
}

fn mid(k: &RobotKinematics) -> Vec<f64> {
    k.limits().iter().map(|(lo, hi)| (lo + hi) / 2.0).collect()
}

fn assert_finite(k: &RobotKinematics, name: &str) {
    for q in [mid(k), k.limits().iter().map(|l| l.0).collect(), k.limits().iter().map(|l| l.1).collect()] {
        for (link, p) in k.fk_links(&q) {
            let ok =
                p.translation.vector.iter().all(|v| v.is_finite()) && p.rotation.coords.iter().all(|v| v.is_finite());
            assert!(ok, "{name}: link {link} not finite at {q:?}");
        }
    }
}

#[test]
fn shared_robots_load_with_finite_fk() {
    let Some(root) = shared_robots() else { return };
    // (file, actuated joints, collision links at least, collision shapes at least). The
    // Panda's default flange is `panda_hand_tcp` (the deepest link, first in file order),
    // so its fingers are off the chain: frozen at 0, the mimic finger following.
    let cases: [(&str, usize, usize, usize); 8] = [
        ("tx90/tx90.urdf", 6, 7, 7),
        ("panda/example-robot-data/robots/panda_description/urdf/panda.urdf", 7, 10, 10),
        ("panda/vamp/panda_spherized.urdf", 7, 8, 50),
        ("ur5/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf", 6, 6, 6),
        ("ur5/example-robot-data/robots/ur_description/urdf/ur5_joint_limited_robot.urdf", 6, 6, 6),
        ("iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf", 7, 7, 7),
        ("iiwa/drake_models/iiwa_description/urdf/iiwa14_polytope_collision.urdf", 7, 1, 1),
        ("iiwa/drake_models/iiwa_description/urdf/iiwa14_spheres_dense_collision.urdf", 7, 7, 20),
    ];
    for (f, dof, links, shapes) in cases {
        let path = root.join(f);
        if !path.is_file() {
            eprintln!("skipped {f}: not present");
            continue;
        }
        let k = load(&path, MeshMode::ConvexHull);
        println!(
            "{f}: {} joints {:?}, flange {}, {} collision links, {} shapes",
            k.joint_names().len(),
            k.joint_names(),
            k.flange(),
            k.collision_links().len(),
            k.shape_count()
        );
        assert_eq!(k.joint_names().len(), dof, "{f}");
        assert!(k.collision_links().len() >= links, "{f}: {:?}", k.collision_links());
        assert!(k.shape_count() >= shapes, "{f}: {} shapes", k.shape_count());
        assert_finite(&k, f);
    }
}

/// Every `*.urdf` under `dir`, sorted.
fn urdfs_under(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let entries = std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
        for e in entries {
            let p = e.expect("dir entry").path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "urdf") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn every_shared_urdf_loads_with_finite_fk_at_random_configurations() {
    use rand::{RngExt, SeedableRng};
    let Some(root) = shared_robots() else { return };
    let files = urdfs_under(&root);
    // The list above is hand-checked; this one cannot miss a file added later.
    assert!(files.len() >= 10, "{files:?}");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    for path in &files {
        let name = path.strip_prefix(&root).unwrap_or(path).display().to_string();
        let k = load(path, MeshMode::ConvexHull);
        assert!(!k.joint_names().is_empty(), "{name}");
        assert!(k.limits().iter().all(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo <= hi), "{name}");
        assert_finite(&k, &name);
        let zero: Vec<f64> = k.limits().iter().map(|(lo, hi)| 0f64.clamp(*lo, *hi)).collect();
        let mut configs = vec![zero];
        for _ in 0..5 {
            configs.push(
                k.limits().iter().map(|(lo, hi)| if hi > lo { rng.random_range(*lo..*hi) } else { *lo }).collect(),
            );
        }
        for q in configs {
            for (link, p) in k.fk_links(&q) {
                let ok = p.translation.vector.iter().all(|v| v.is_finite())
                    && p.rotation.coords.iter().all(|v| v.is_finite());
                assert!(ok, "{name}: link {link} not finite at {q:?}");
            }
        }
        println!("{name}: {} joints, {} shapes", k.joint_names().len(), k.shape_count());
    }
}

#[test]
fn shared_meshes_load_as_triangle_meshes_too() {
    let Some(root) = shared_robots() else { return };
    for f in [
        "tx90/tx90.urdf",
        "panda/example-robot-data/robots/panda_description/urdf/panda.urdf",
        "iiwa/drake_models/iiwa_description/urdf/iiwa14_polytope_collision.urdf",
    ] {
        let k = load(&root.join(f), MeshMode::TriMesh);
        assert_finite(&k, f);
    }
}

#[test]
fn real_tx90_matches_the_shipped_model() {
    let Some(root) = shared_robots() else { return };
    let real = load(&root.join("tx90/tx90.urdf"), MeshMode::ConvexHull);
    let ours = load(&tx90(), MeshMode::ConvexHull);
    assert_eq!(real.limits(), ours.limits());
    for q in [[0.0; 6], [0.3, -0.4, 1.1, 0.5, -0.7, 2.0]] {
        let a = real.fk_links(&q);
        let b = ours.fk_links(&q);
        let pa = &a.iter().find(|(n, _)| n == "link_6").unwrap().1;
        let pb = &b.iter().find(|(n, _)| n == "link_6").unwrap().1;
        assert!((pa.translation.vector - pb.translation.vector).norm() < 1e-12);
        assert!(pa.rotation.angle_to(&pb.rotation) < 1e-12);
    }
}

#[test]
fn real_tx90_builds_into_a_world_with_self_collision_sampling() {
    let Some(root) = shared_robots() else { return };
    let scn = scenario(vec![robot("tx90", root.join("tx90/tx90.urdf"), vec![0.0; 6], None)], vec![], vec![], vec![]);
    let w = build(&scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"));
    let r = RobotId(0);
    assert!(!w.check(r, &[0.0; 6], &declutter::world::CheckCtx::new()).is_blocked());
}

#[test]
fn real_tx90_meshes_collide_with_a_table_in_both_mesh_modes() {
    let Some(root) = shared_robots() else { return };
    for mode in [MeshMode::ConvexHull, MeshMode::TriMesh] {
        let table = cuboid("table", [1.0, 1.0, 0.1], at(0.9, 0.0, 0.40));
        let scn =
            scenario(vec![robot("tx90", root.join("tx90/tx90.urdf"), vec![0.0; 6], None)], vec![], vec![table], vec![]);
        let opts = WorldOptions { mesh_mode: mode, self_collision_samples: 300, ..WorldOptions::default() };
        let w = build(&scn, &opts, &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"));
        let ctx = declutter::world::CheckCtx::new();
        assert!(!w.check(RobotId(0), &[0.0; 6], &ctx).is_blocked(), "{mode:?}");
        let c = w.check(RobotId(0), &[0.0, std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0], &ctx);
        assert!(
            matches!(&c, declutter::world::Check::Blocked(declutter::world::Blocker::Fixed { body, .. }) if body.0 == 0),
            "{mode:?}: {c:?}"
        );
    }
}

#[test]
fn shipped_tx90_encloses_the_real_collision_meshes() {
    use declutter::resolve::{ObjectId, Shape};
    use declutter::world::{Check, CheckCtx};
    let Some(root) = shared_robots() else { return };
    let real = load(&root.join("tx90/tx90.urdf"), MeshMode::ConvexHull);
    let configs = [
        [0.0; 6],
        [0.5, -0.6, 1.2, 0.8, -0.9, 1.5],
        [-1.0, 0.9, -1.3, -2.0, 1.2, 0.3],
        [2.0, 0.2, 0.4, 1.0, 0.5, -2.0],
    ];
    for q in configs {
        let poses = real.fk_links(&q);
        let mut probes = Vec::new();
        // The base never moves and is not checked against the scene: probe the moving links.
        for link in ["link_1", "link_2", "link_3", "link_4", "link_5", "link_6"] {
            let pose = poses.iter().find(|(n, _)| n == link).unwrap().1;
            let p = root.join(format!("tx90/tx90/meshes/collision/{link}.stl"));
            let bytes = std::fs::read(&p).unwrap();
            let scene = mesh_loader::Loader::default().merge_meshes(true).load_from_slice(&bytes, &p).unwrap();
            let v = &scene.meshes[0].vertices;
            for x in v.iter().step_by(v.len() / 60 + 1) {
                let pt = pose * nalgebra::Point3::new(x[0] as f64, x[1] as f64, x[2] as f64);
                let b = body(link, Shape::Sphere { radius: 0.002 }, at(pt.x, pt.y, pt.z));
                probes.push(declutter::resolve::Object { body: b, grasps: vec![] });
            }
        }
        let n = probes.len();
        let names: Vec<String> = probes.iter().map(|o| o.body.name.clone()).collect();
        let scn = scenario(vec![robot("t", tx90(), vec![0.0; 6], None)], vec![], vec![], probes);
        let opts = WorldOptions { self_collision_samples: 0, ..WorldOptions::default() };
        let w = build(&scn, &opts, &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"));
        let Check::Touches(s) = w.check(RobotId(0), &q, &CheckCtx::new()) else { panic!("{q:?} blocked") };
        let missed: Vec<&String> = (0..n).filter(|&i| !s.contains(ObjectId(i as u32))).map(|i| &names[i]).collect();
        assert!(
            missed.is_empty(),
            "q {q:?}: {} of {n} mesh vertices outside the shipped model: {missed:?}",
            missed.len()
        );
    }
}

/// What the book's "Using your own robot" says of this file: the ROS-Industrial
/// `flange` and `tool0` frames are commented out, so the chain ends at `link_6`.
#[test]
fn real_tx90_ends_at_link_6_and_a_flange_named_flange_is_refused_with_the_links() {
    let Some(root) = shared_robots() else { return };
    let urdf = root.join("tx90/tx90.urdf");
    let scn = scenario(vec![robot("tx90", &urdf, vec![0.0; 6], None)], vec![], vec![], vec![]);
    let w = build(&scn, &WorldOptions::default(), &FsLoader).unwrap_or_else(|e| panic!("{e:#?}"));
    assert_eq!(w.flange_link(RobotId(0)), "link_6");
    let mut scn = scn;
    scn.robots[0].flange = Some(("flange".into(), sp(30, 38)));
    let errs = build(&scn, &WorldOptions::default(), &FsLoader).expect_err("there is no link `flange`");
    assert_eq!(errs.len(), 1, "{errs:?}");
    let help = miette::Diagnostic::help(&errs[0]).map(|h| h.to_string()).unwrap_or_default();
    assert_eq!(help, "the URDF's links: `base_link`, `link_1`, `link_2`, `link_3`, `link_4`, `link_5`, `link_6`");
}
