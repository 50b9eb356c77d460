//! The driver runs the pipeline for each CLI command and turns errors into reports.
//! Exit codes: 0 success, 1 input or usage error (or verification failure), 2 no schedule
//! (proved infeasible, or not found within the planning budget: the diagnostic codes differ).

use std::path::PathBuf;

mod commands;
mod compile;
mod import_cmd;
mod pipeline;
mod show_cmd;
mod verify_cmd;

pub use compile::{plan_verified, plan_verified_with, stats_table, Planned};
pub use verify_cmd::{parse_clearance, parse_schedule, VerifyOptions};
mod front;

pub use commands::{check, compile, graph, resolve, show, verify};
pub use front::render_report;
pub use import_cmd::{import_moveit, ImportOptions};

/// Output format of a schedule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    Yaml,
    Json,
}

/// How meshes are modelled for collision checking.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Meshes {
    /// Convex hull of each mesh (fast).
    #[default]
    Convex,
    /// The triangle mesh itself.
    Exact,
}

impl GlobalOptions {
    /// World options for these command-line choices.
    pub fn world_options(&self) -> crate::world::WorldOptions {
        let mesh_mode = match self.meshes {
            Meshes::Convex => crate::world::MeshMode::ConvexHull,
            Meshes::Exact => crate::world::MeshMode::TriMesh,
        };
        crate::world::WorldOptions { package_path: self.package_path.clone(), mesh_mode, ..Default::default() }
    }
}

/// Options every command shares.
#[derive(Clone, Debug, Default)]
pub struct GlobalOptions {
    /// Directories searched for `package://` URIs, after the URDF's own folder and its ancestors.
    pub package_path: Vec<PathBuf>,
    pub color: bool,
    pub meshes: Meshes,
    /// Print every warning (otherwise repeats of one kind are counted, not shown).
    pub verbose: bool,
}

impl GlobalOptions {
    /// Adds `DECLUTTER_PACKAGE_PATH` (colon-separated) after the command-line directories.
    pub fn from_env(mut package_path: Vec<PathBuf>, no_color: bool) -> GlobalOptions {
        if let Some(v) = std::env::var_os("DECLUTTER_PACKAGE_PATH") {
            package_path.extend(std::env::split_paths(&v).filter(|p| !p.as_os_str().is_empty()));
        }
        let color =
            !no_color && std::env::var_os("NO_COLOR").is_none() && std::io::IsTerminal::is_terminal(&std::io::stderr());
        GlobalOptions { package_path, color, meshes: Meshes::Convex, verbose: false }
    }
}

/// Options of `declutter compile`.
#[derive(Clone, Debug)]
pub struct CompileOptions {
    pub seed: Option<u64>,
    pub objective: Option<String>,
    pub format: Format,
    pub out: Option<PathBuf>,
    pub stats: bool,
    pub execution: crate::timing::Execution,
}

/// Options of `declutter graph`: the planning overrides of `compile`, so it draws the
/// graph a `compile` run with the same options planned.
#[derive(Clone, Debug, Default)]
pub struct GraphOptions {
    pub seed: Option<u64>,
    pub objective: Option<String>,
}

/// Options of `declutter show`.
#[derive(Clone, Debug)]
pub struct ShowOptions {
    /// The schedule to replay; `None` shows the cell alone.
    pub schedule: Option<PathBuf>,
    /// Where the page is written.
    pub out: PathBuf,
}

pub const EXIT_OK: u8 = 0;
pub const EXIT_INPUT: u8 = 1;
pub const EXIT_INFEASIBLE: u8 = 2;
