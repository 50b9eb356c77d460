//! Arms for the world's unit tests: the shipped examples' and those of `../shared/robots`.

use crate::diag::{FsLoader, SourceMap};
use crate::world::{build, World, WorldOptions};

pub(super) fn world_of(path: &std::path::Path) -> World {
    let scn = crate::resolve::resolve(path, &FsLoader, &mut SourceMap::new()).expect("resolves");
    build(&scn, &WorldOptions::default(), &FsLoader).expect("builds")
}

pub(crate) fn example(name: &str) -> World {
    world_of(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(format!("{name}.dcl")))
}

/// Three arms of `../shared/robots`, each alone: the UR5 (meshes), the Panda of meshes and
/// the Panda of spheres; none when it is absent. (Their self-collision grids reach across
/// to the other side of a pair and span three joints.)
pub(super) fn shared_arms() -> Vec<(String, World)> {
    let robots = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots");
    if !robots.join("ur5").is_dir() {
        eprintln!("shared arms skipped: {} is absent (../shared is not there)", robots.display());
        return Vec::new();
    }
    let panda_home = "0, -45deg, 0, -135deg, 0, 90deg, 45deg";
    let arms = [
        ("ur5", "ur5/example-robot-data/robots/ur_description/urdf/ur5_joint_limited_robot.urdf", "0, 0, 0, 0, 0, 0"),
        ("panda", "panda/example-robot-data/robots/panda_description/urdf/panda.urdf", panda_home),
        ("panda of spheres", "panda/vamp/panda_spherized.urdf", panda_home),
    ];
    arms.iter()
        .map(|(name, urdf, home)| {
            // Tests run on several threads, each calling this: a file of its own each time.
            static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
            let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let file = std::env::temp_dir().join(format!("declutter-grid-{}-{k}.dcl", std::process::id()));
            let text = format!(
                "scenario \"grid\"\nrobot arm {{\n    urdf \"{}\"\n    home [{home}]\n}}\ntarget arm at [{home}]\n",
                robots.join(urdf).display()
            );
            std::fs::write(&file, text).expect("a temporary file");
            let w = world_of(&file);
            let _ = std::fs::remove_file(&file);
            (name.to_string(), w)
        })
        .collect()
}
