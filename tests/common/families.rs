//! Seeded benchmark families on real arms of `../shared/robots` (the TX-90 with a hand,
//! the Panda's sphere model): a configuration target with fixed obstacles built around
//! the hand (or the flange) at that target.
//!
//! Each problem is a pure function of (family, index): a ChaCha RNG draws the goal
//! configuration until the hand stands where the family wants it and the arm touches
//! nothing there, then the obstacles are placed around the hand and the goal is kept
//! only if it is still clear. The families:
//! - `table_top`: the hand low over the table;
//! - `cage`: four bars and a roof around the hand, entered between two bars;
//! - `shelf`: a board above and below the hand and a back wall behind it;
//! - `narrow_gap`: a wall across the hand's way with a window it reaches through, and
//!   removable boxes beside the window (never in it): the right answer removes nothing.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use declutter::diag::{FsLoader, SourceMap};
use declutter::resolve::RobotId;
use declutter::world::{self, CheckCtx, World, WorldOptions};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub const FAMILIES: [&str; 4] = ["table_top", "cage", "shelf", "narrow_gap"];

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

/// The arms the families run on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Arm {
    /// The TX-90 (`tx90/tx90.urdf`) with the `sah` hand of the examples.
    Tx90,
    /// The Panda's sphere model (`panda/vamp/panda_spherized.urdf`), its own hand.
    Panda,
}

fn cell(arm: Arm, robots: &Path) -> String {
    match arm {
        Arm::Tx90 => {
            let hands = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hands/sah.urdf");
            format!(
                "hand sah {{\n    urdf \"{}\"\n    tcp at (0, 0, 16cm)\n}}\n\
                 robot arm {{\n    urdf \"{}\"\n    hand sah\n    home [0, -20deg, 110deg, 0, 60deg, 0]\n}}\n\
                 fixed table box(1.6m, 1.6m, 4cm) at (0, 0, -2cm)\n",
                hands.display(),
                robots.join("tx90/tx90.urdf").display()
            )
        }
        Arm::Panda => format!(
            "robot arm {{\n    urdf \"{}\"\n    home [0, -45deg, 0, -135deg, 0, 90deg, 45deg]\n}}\n\
             fixed table box(1.6m, 1.6m, 4cm) at (0, 0, -2cm)\n",
            robots.join("panda/vamp/panda_spherized.urdf").display()
        ),
    }
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
    let home = match arm {
        Arm::Tx90 => "[0, -20deg, 110deg, 0, 60deg, 0]",
        Arm::Panda => "[0, -45deg, 0, -135deg, 0, 90deg, 45deg]",
    };
    let text = format!("scenario \"probe\"\n{}target arm at {home}\n", cell(arm, robots));
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
    let arm_key = match arm {
        Arm::Tx90 => 0,
        Arm::Panda => 100,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(mix(fam + 1 + arm_key, index));
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
        let z_band = if family == "table_top" { (0.08, 0.25) } else { (0.15, 0.55) };
        if !(0.45..=0.85).contains(&reach) || p.z < z_band.0 || p.z > z_band.1 {
            continue;
        }
        // The obstacles' frame: x from the base out to the hand, z up.
        let yaw = p.y.atan2(p.x);
        let obstacles = obstacles(family, &mut rng, p.z);
        let mut text = format!("scenario \"{family}-{index}\"\n{}", cell(arm, robots));
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
        let name = match arm {
            Arm::Tx90 => format!("{family}_{index}"),
            Arm::Panda => format!("panda_{family}_{index}"),
        };
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

/// A box in the hand's frame (x out from the base, z up from the table).
struct Obstacle {
    size: [f64; 3],
    at: [f64; 3],
    removable: bool,
}

fn obstacles(family: &str, rng: &mut ChaCha8Rng, z: f64) -> Vec<Obstacle> {
    let fixed = |size: [f64; 3], at: [f64; 3]| Obstacle { size, at, removable: false };
    let mut out = Vec::new();
    match family {
        "table_top" => {
            // A few fixed blocks around, not under, the hand.
            for _ in 0..3 {
                let (a, d) = (rng.random::<f64>() * std::f64::consts::TAU, 0.18 + 0.1 * rng.random::<f64>());
                out.push(fixed([0.06, 0.06, 0.12], [d * a.cos(), d * a.sin(), 0.06]));
            }
        }
        "cage" => {
            let h = 0.11 + 0.03 * rng.random::<f64>();
            let top = z + 0.12;
            for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                out.push(fixed([0.02, 0.02, top], [sx * h, sy * h, top / 2.0]));
            }
            out.push(fixed([2.0 * h + 0.04, 2.0 * h + 0.04, 0.02], [0.0, 0.0, top + 0.01]));
        }
        "shelf" => {
            let gap = 0.13 + 0.05 * rng.random::<f64>();
            let (below, above) = (z - gap / 2.0, z + gap / 2.0);
            out.push(fixed([0.4, 0.6, 0.02], [0.05, 0.0, below.max(0.03) - 0.01]));
            out.push(fixed([0.4, 0.6, 0.02], [0.05, 0.0, above + 0.01]));
            out.push(fixed([0.02, 0.6, above + 0.02], [0.26, 0.0, (above + 0.02) / 2.0]));
        }
        "narrow_gap" => {
            // A wall 10 cm in front of the hand (towards the base) with a window around
            // the line from the base to the hand, 16-20 cm wide.
            let w = 0.08 + 0.02 * rng.random::<f64>();
            let x = -0.1;
            let height = z + 0.4;
            out.push(fixed([0.02, 0.5, height], [x, w + 0.25, height / 2.0]));
            out.push(fixed([0.02, 0.5, height], [x, -w - 0.25, height / 2.0]));
            out.push(fixed([0.02, 2.0 * w, (z - w).max(0.0)], [x, 0.0, (z - w).max(0.0) / 2.0]));
            out.push(fixed([0.02, 2.0 * w, height - z - w], [x, 0.0, (height + z + w) / 2.0]));
            // Removable boxes beside the window on the near side, never in it.
            for k in 0..4 {
                let side = if k % 2 == 0 { 1.0 } else { -1.0 };
                let off = w + 0.06 + 0.08 * rng.random::<f64>();
                out.push(Obstacle { size: [0.05, 0.05, 0.1], at: [x - 0.08, side * off, 0.05], removable: true });
            }
        }
        _ => {}
    }
    out
}
