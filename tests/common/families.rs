//! Seeded benchmark families on real arms of `../shared/robots` (see [`Arm`]: the TX-90
//! with a hand, the Panda's sphere and mesh models, the UR5): a configuration target with
//! fixed obstacles built around the hand (or the flange) at that target.
//!
//! Each problem is a pure function of (arm, family, index): a ChaCha RNG draws the goal
//! configuration until the hand stands where the family wants it and the arm touches
//! nothing there, then the obstacles are placed around the hand and the goal is kept
//! only if it is still clear. The families:
//! - `table_top`: the hand low over the table;
//! - `cage`: four bars and a roof around the hand, entered between two bars;
//! - `shelf`: a board above and below the hand and a back wall behind it;
//! - `narrow_gap`: a wall across the hand's way with a window it reaches through, and
//!   removable boxes beside the window (never in it): the right answer removes nothing;
//! - `bookshelf`: 3-4 boards between two sides and a back, the hand in one shelf,
//!   pointing in from the front;
//! - `deep_box`: an open box on the table, walls above the wrist, the hand pointing down
//!   near its floor;
//! - `under_table`: a second table on four legs over the hand, reached under from the
//!   base's side.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::RobotId;
use declutter::world::{self, CheckCtx, World, WorldOptions};
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "families/arms.rs"]
mod arms;
#[path = "families/known.rs"]
pub mod known;
#[path = "families/obstacles.rs"]
mod obstacles;

pub use arms::{Arm, ARMS};
use obstacles::obstacles;

/// New families go at the end: a family's index is part of its problems' seeds.
pub const FAMILIES: [&str; 7] = ["table_top", "cage", "shelf", "narrow_gap", "bookshelf", "deep_box", "under_table"];

/// The shared robot directory, or `None` (with the reason printed) when absent.
pub fn shared_robots() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots");
    if p.join("tx90/tx90.urdf").is_file() {
        Some(p)
    } else {
        eprintln!("skipped: {} is absent (the shared robot files are not in this checkout)", p.display());
        None
    }
}

/// Whether the comma-separated list in the environment variable `var` names `name`
/// (everything is chosen when it is unset).
pub fn chosen(var: &str, name: &str) -> bool {
    std::env::var(var).map_or(true, |v| v.split(',').any(|x| x == name))
}

/// The scenario at `path` from the file to a verified schedule, as `declutter compile`
/// does but print; what went wrong otherwise.
pub fn compile(path: &Path) -> Result<declutter::driver::Planned, String> {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(path, &FsLoader, &mut sources).map_err(|e| format!("resolve: {e:?}"))?;
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).map_err(|e| format!("world: {e:?}"))?;
    declutter::driver::plan_verified(&w, &|_| {}).map_err(|v| format!("the schedule failed verification: {v:?}"))
}

fn load(text: &str, dir: &Path, name: &str) -> Option<World> {
    let path = dir.join(format!("{name}.dcl"));
    std::fs::write(&path, text).ok()?;
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(&path, &FsLoader, &mut sources).ok()?;
    world::build(&scn, &WorldOptions::default(), &FsLoader).ok()
}

/// A generated problem: the scenario text and where it was written.
pub struct Problem {
    pub family: &'static str,
    pub index: u64,
    pub path: PathBuf,
    pub text: String,
}

/// The arm alone on the table (for drawing goals); `None` if it does not build.
pub fn probe(arm: Arm, robots: &Path, dir: &Path) -> Option<World> {
    let text = format!("scenario \"probe\"\n{}target arm at {}\n", arm.cell(robots), arm.home());
    load(&text, dir, &format!("probe_{arm:?}"))
}

fn mix(a: u64, b: u64) -> u64 {
    let mut z = a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b.wrapping_add(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 31)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 29)
}

/// Problem `index` of `family`, written into `dir`; `None` if no goal was found in the
/// draws allowed (never for the shipped families in practice).
pub fn problem(
    arm: Arm,
    probe: &World,
    robots: &Path,
    dir: &Path,
    family: &'static str,
    index: u64,
) -> Option<Problem> {
    let fam = FAMILIES.iter().position(|f| *f == family)? as u64;
    let mut rng = ChaCha8Rng::seed_from_u64(mix(fam + 1 + arm.key(), index));
    let r = RobotId(0);
    let lim = probe.limits(r).to_vec();
    for _ in 0..20_000 {
        let q: Vec<f64> = lim.iter().map(|(lo, hi)| lo + rng.random::<f64>() * (hi - lo)).collect();
        if probe.check(r, &q, &CheckCtx::new()).is_blocked() {
            continue;
        }
        let tcp = probe.fk_tcp(r, &q);
        let p = tcp.translation.vector;
        let reach = (p.x * p.x + p.y * p.y).sqrt();
        let (reach_band, z_band) = bands(family);
        if !reach_band.contains(&reach) || p.z < z_band.0 || p.z > z_band.1 {
            continue;
        }
        // The obstacles' frame: x from the base out to the hand, z up.
        let yaw = p.y.atan2(p.x);
        if !facing(family, &(tcp.rotation * Vector3::z()), yaw) {
            continue;
        }
        let obstacles = obstacles(family, arm, &mut rng, p.z);
        let mut text = format!("scenario \"{family}-{index}\"\n{}", arm.cell(robots));
        for (k, o) in obstacles.iter().enumerate() {
            let (c, s) = (yaw.cos(), yaw.sin());
            let (x, y) = (p.x + c * o.at[0] - s * o.at[1], p.y + s * o.at[0] + c * o.at[1]);
            let kind = if o.removable { "object" } else { "fixed" };
            let grasp = if o.removable {
                " {\n    grasp top at (0, 0, 0) rot (180deg, 0, 0) approach 5cm repeat 2 about z\n}"
            } else {
                ""
            };
            text.push_str(&format!(
                "{kind} o{k} box({:.3}, {:.3}, {:.3}) at ({x:.4}, {y:.4}, {:.4}) rot (0, 0, {:.4}deg){grasp}\n",
                o.size[0],
                o.size[1],
                o.size[2],
                o.at[2],
                yaw.to_degrees()
            ));
        }
        let values: Vec<String> = q.iter().map(|v| format!("{v:.6}")).collect();
        text.push_str(&format!("target arm at [{}]\n", values.join(", ")));
        let name = format!("{}{family}_{index}", arm.prefix());
        let Some(w) = load(&text, dir, &name) else { continue };
        // The goal must be clear of every obstacle, removable ones included.
        if w.check(r, &q, &CheckCtx::new()) != world::Check::free() {
            continue;
        }
        if w.check(r, w.home(r), &CheckCtx::new()) != world::Check::free() {
            continue;
        }
        return Some(Problem { family, index, path: dir.join(format!("{name}.dcl")), text });
    }
    None
}

/// The hand's distance from the base's axis and its height above the table (metres)
/// that `family` draws goals in.
fn bands(family: &str) -> (std::ops::RangeInclusive<f64>, (f64, f64)) {
    match family {
        "table_top" => (0.45..=0.85, (0.08, 0.25)),
        "bookshelf" => (0.5..=0.85, (0.25, 0.75)),
        "deep_box" => (0.4..=0.75, (0.04, 0.12)),
        "under_table" => (0.5..=0.85, (0.1, 0.3)),
        _ => (0.45..=0.85, (0.15, 0.55)),
    }
}

/// Whether the tool's approach axis `z_tool` suits `family` at azimuth `yaw`: into a
/// bookshelf or under a table from the front (away from the base, near level), down
/// into a deep box. The first four families take any.
fn facing(family: &str, z_tool: &Vector3<f64>, yaw: f64) -> bool {
    let out = Vector3::new(yaw.cos(), yaw.sin(), 0.0);
    match family {
        "bookshelf" => z_tool.dot(&out) > 0.8,
        "under_table" => z_tool.dot(&out) > 0.7 && z_tool.z < 0.3,
        "deep_box" => z_tool.z < -0.85,
        _ => true,
    }
}
