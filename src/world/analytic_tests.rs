//! The closed forms against forward kinematics and against the numeric solver, on
//! every 6R arm the project ships or keeps in `../shared/robots`, and on its 7R arms
//! (the Panda, the iiwa) at a given joint 7.

use std::path::{Path, PathBuf};

use nalgebra::Isometry3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{wrap_pi, Analytic, ACCEPT};
use crate::world::analytic7::Redundant;
use crate::world::chain::{sample_in, Chain};
use crate::world::urdf;

fn chain_of(path: &Path) -> Option<Chain> {
    let Ok(text) = std::fs::read_to_string(path) else {
        eprintln!("skipped: {} is absent (../shared is not there)", path.display());
        return None;
    };
    let model = urdf::parse(&text).unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
    Some(Chain::new(&model, None).unwrap_or_else(|e| panic!("{}: {e:?}", path.display())))
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn arms() -> Vec<(&'static str, PathBuf)> {
    let shared = root().join("../shared/robots");
    vec![
        ("tx90 (examples)", root().join("examples/robots/tx90.urdf")),
        ("tx90 (shared)", shared.join("tx90/tx90.urdf")),
        ("ur5 (shared)", shared.join("ur5/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf")),
    ]
}

fn random_q(rng: &mut ChaCha8Rng, chain: &Chain) -> Vec<f64> {
    chain.limits.iter().map(|(lo, hi)| sample_in(rng, *lo, *hi)).collect()
}

fn same_mod_turns(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| wrap_pi(x - y).abs() < tol)
}

fn pose_gap(a: &Isometry3<f64>, b: &Isometry3<f64>) -> f64 {
    (a.translation.vector - b.translation.vector).norm().max(a.rotation.angle_to(&b.rotation))
}

#[test]
fn planar_and_seven_joint_arms_are_not_taken_for_six_joint_families() {
    let planar = chain_of(&root().join("examples/robots/planar3.urdf")).expect("shipped");
    assert!(Analytic::detect(&planar).is_none());
    if let Some(panda) =
        chain_of(&root().join("../shared/robots/panda/example-robot-data/robots/panda_description/urdf/panda.urdf"))
    {
        assert!(Analytic::detect(&panda).is_none());
    }
}

#[test]
fn every_closed_form_solution_reaches_the_pose_and_the_sampled_one_is_among_them() {
    for (name, path) in arms() {
        let Some(chain) = chain_of(&path) else { continue };
        let a = Analytic::detect(&chain).unwrap_or_else(|| panic!("{name}: no closed form detected"));
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let (mut worst, mut total) = (0.0f64, 0usize);
        for i in 0..10_000 {
            let q = random_q(&mut rng, &chain);
            let target = chain.fk_flange(&q);
            let conditioned = a.solve_conditioned(&target);
            assert!(conditioned.len() <= 8, "{name} #{i}: {} solutions", conditioned.len());
            for (s, sure) in &conditioned {
                let gap = pose_gap(&chain.fk_flange(s), &target);
                worst = worst.max(gap);
                // A solution called well conditioned is trusted without this check.
                let bound = if *sure { crate::world::ik::IK_TOLERANCE } else { ACCEPT };
                assert!(gap < bound, "{name} #{i}: solution {s:?} misses the pose of {q:?} by {gap}");
            }
            let sols: Vec<[f64; 6]> = conditioned.into_iter().map(|(s, _)| s).collect();
            assert!(sols.iter().any(|s| same_mod_turns(s, &q, 1e-6)), "{name} #{i}: {q:?} not among {sols:?}");
            total += sols.len();
        }
        eprintln!("{name}: {total} solutions for 10000 poses, worst pose error {worst:e}");
    }
}

#[test]
fn the_numeric_solver_finds_nothing_the_closed_form_misses() {
    let tcp = Isometry3::identity();
    for (name, path) in arms() {
        let Some(chain) = chain_of(&path) else { continue };
        let a = Analytic::detect(&chain).unwrap_or_else(|| panic!("{name}: no closed form detected"));
        let rot = vec![true; 6];
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        let mut found = 0;
        for i in 0..100 {
            let target = chain.fk_flange(&random_q(&mut rng, &chain));
            let sols = a.solve(&target);
            for _ in 0..40 {
                let mut q = random_q(&mut rng, &chain);
                if !crate::world::ik::refine_chain(&chain, &tcp, &target, &mut q, &rot) {
                    continue;
                }
                found += 1;
                assert!(
                    sols.iter().any(|s| same_mod_turns(s, &q, 1e-6)),
                    "{name} #{i}: numeric {q:?} not among {sols:?}"
                );
            }
        }
        assert!(found > 100, "{name}: the numeric solver converged only {found} times");
        eprintln!("{name}: {found} numeric solutions, all among the closed form's");
    }
}

fn arms7() -> Vec<(&'static str, PathBuf)> {
    let shared = root().join("../shared/robots");
    vec![
        ("panda", shared.join("panda/example-robot-data/robots/panda_description/urdf/panda.urdf")),
        ("panda (spheres)", shared.join("panda/vamp/panda_spherized.urdf")),
        ("iiwa14", shared.join("iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf")),
    ]
}

#[test]
fn six_joint_and_planar_arms_are_not_taken_for_the_seven_joint_family() {
    let planar = chain_of(&root().join("examples/robots/planar3.urdf")).expect("shipped");
    assert!(Redundant::detect(&planar).is_none());
    let tx90 = chain_of(&root().join("examples/robots/tx90.urdf")).expect("shipped");
    assert!(Redundant::detect(&tx90).is_none());
}

#[test]
fn every_solution_reaches_the_pose_and_the_sampled_one_is_among_them() {
    for (name, path) in arms7() {
        let Some(chain) = chain_of(&path) else { continue };
        let r = Redundant::detect(&chain).unwrap_or_else(|| panic!("{name}: no closed form detected"));
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let (mut worst, mut total, mut near_singular) = (0.0f64, 0usize, 0usize);
        for i in 0..10_000 {
            let q = random_q(&mut rng, &chain);
            let target = chain.fk_flange(&q);
            let conditioned = r.solve_at(&target, q[6]);
            assert!(conditioned.len() <= 8, "{name} #{i}: {} solutions", conditioned.len());
            for (s, sure) in &conditioned {
                assert_eq!(s[6], q[6], "{name} #{i}: joint 7 is the one given");
                let gap = pose_gap(&chain.fk_flange(s), &target);
                worst = worst.max(gap);
                // A solution called well conditioned is trusted without this check.
                let bound = if *sure { crate::world::ik::IK_TOLERANCE } else { ACCEPT };
                assert!(gap < bound, "{name} #{i}: solution {s:?} misses the pose of {q:?} by {gap}");
            }
            // Near a singularity (an `acos` of nearly ±1) the pose hardly moves with some
            // joints, and rounding moves them further: such solutions say so.
            if !conditioned.iter().any(|(s, _)| same_mod_turns(s, &q, 1e-6)) {
                assert!(
                    conditioned.iter().any(|(s, sure)| !sure && same_mod_turns(s, &q, 1e-4)),
                    "{name} #{i}: {q:?} not among {conditioned:?}"
                );
                near_singular += 1;
            }
            total += conditioned.len();
        }
        assert!(near_singular < 50, "{name}: {near_singular} of 10000 found only near a singularity");
        eprintln!(
            "{name}: {total} solutions for 10000 poses, worst pose error {worst:e}, {near_singular} near a singularity"
        );
    }
}

#[test]
fn the_numeric_solver_finds_nothing_the_closed_form_misses_at_its_joint_7() {
    let tcp = Isometry3::identity();
    for (name, path) in arms7() {
        let Some(chain) = chain_of(&path) else { continue };
        let r = Redundant::detect(&chain).unwrap_or_else(|| panic!("{name}: no closed form detected"));
        let rot = vec![true; 7];
        let mut rng = ChaCha8Rng::seed_from_u64(37);
        let (mut found, mut loose) = (0, 0);
        for i in 0..100 {
            let target = chain.fk_flange(&random_q(&mut rng, &chain));
            for _ in 0..40 {
                let mut q = random_q(&mut rng, &chain);
                if !crate::world::ik::refine_chain(&chain, &tcp, &target, &mut q, &rot) {
                    continue;
                }
                found += 1;
                // The numeric answer is only as exact as its pose tolerance (1e-9) lets it
                // be: near a singularity (joint 2 near 0, the two elbow answers of joint 4
                // nearly one) some joints drift by up to 1e-5. The nearest distinct
                // solutions seen are 3e-3 apart.
                let sols = r.solve_at(&target, q[6]);
                if !sols.iter().any(|(s, _)| same_mod_turns(s, &q, 1e-6)) {
                    assert!(
                        sols.iter().any(|(s, _)| same_mod_turns(s, &q, 1e-4)),
                        "{name} #{i}: numeric {q:?} not among {sols:?}"
                    );
                    loose += 1;
                }
            }
        }
        assert!(found > 100, "{name}: the numeric solver converged only {found} times");
        assert!(loose * 20 < found, "{name}: {loose} of {found} numeric solutions matched only loosely");
        eprintln!("{name}: {found} numeric solutions, all among the closed form's at their joint 7 ({loose} to 1e-4)");
    }
}
