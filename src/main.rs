//! The `declutter` command line: parses arguments and calls the library's driver.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::{Parser, Subcommand};

use declutter::driver::{self, Format, GlobalOptions, Meshes};
use declutter::timing::Execution;

#[derive(Parser)]
#[command(
    name = "declutter",
    version,
    about = "Compile robot-cell scenarios into verified obstacle-removal schedules",
    after_help = "Exit codes: 0 success; 1 input or usage error, or a schedule that does not verify; 2 infeasible."
)]
struct Cli {
    /// Extra directories searched for `package://NAME/...` mesh URIs (also: DECLUTTER_PACKAGE_PATH).
    #[arg(long = "package-path", global = true, value_name = "DIR")]
    package_path: Vec<PathBuf>,
    /// How mesh collision geometry is modelled: convex hulls (fast, the default) or the
    /// exact triangle meshes (slower; a shape lying wholly inside a mesh is not a hit).
    #[arg(long, global = true, value_enum, default_value_t = Meshes::Convex)]
    meshes: Meshes,
    /// Never colour diagnostics.
    #[arg(long, global = true)]
    no_color: bool,
    /// Show every warning: past three of one kind, the rest are otherwise only counted.
    #[arg(long, global = true)]
    verbose: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check a scenario: parse, resolve names and units, load robots and meshes.
    ///
    /// Example: declutter check examples/box_lid.dcl
    Check {
        /// The scenario file (.dcl).
        file: PathBuf,
    },
    /// Print the resolved scenario as YAML (world-frame poses, SI units, grasps expanded).
    ///
    /// Example: declutter resolve examples/box_lid.dcl
    Resolve {
        /// The scenario file (.dcl).
        file: PathBuf,
    },
    /// Plan and print a verified action schedule.
    ///
    /// Example: declutter compile examples/box_lid.dcl --seed 7 --stats
    Compile {
        /// The scenario file (.dcl).
        file: PathBuf,
        /// Override the scenario's planner seed.
        #[arg(long)]
        seed: Option<u64>,
        /// Override the scenario's objective.
        #[arg(long, value_parser = ["fewest_removals", "fewest_vertices"])]
        objective: Option<String>,
        /// The schedule's format.
        #[arg(long, value_enum, default_value_t = Format::Yaml)]
        format: Format,
        /// Write the schedule here instead of stdout.
        #[arg(long, short)]
        out: Option<PathBuf>,
        /// Print per-query statistics (the paper's Table 1) and both makespans to stderr.
        #[arg(long)]
        stats: bool,
        /// Run the robots at the same time where safe, or one action after another.
        #[arg(long, value_parser = ["concurrent", "sequential"], default_value = "concurrent")]
        execution: String,
    },
    /// Independently re-check a schedule against its scenario.
    ///
    /// Example: declutter verify examples/box_lid.dcl box_lid.yaml
    Verify {
        /// The scenario file (.dcl) the schedule was compiled from.
        file: PathBuf,
        /// The schedule to check, as `declutter compile` wrote it (YAML or JSON).
        schedule: PathBuf,
        /// Demand this distance between every moving thing and what it must not touch
        /// (e.g. `5mm`); without it, only contact is a violation.
        #[arg(long, value_name = "LENGTH", value_parser = driver::parse_clearance, default_value = "0")]
        clearance: f64,
    },
    /// Write a scenario from another tool's scene description.
    #[command(subcommand)]
    Import(ImportCommand),
    /// Write the cell, and a schedule's replay, as one self-contained HTML page (3-D, three.js).
    ///
    /// A schedule that does not verify is still shown, each violation marked in red; one
    /// of another scenario is refused. The page fetches nothing: it opens from file://.
    ///
    /// Example: declutter show examples/box_lid.dcl box_lid.yaml -o box_lid.html
    Show {
        /// The scenario file (.dcl).
        file: PathBuf,
        /// The schedule to replay, as `declutter compile` wrote it (YAML or JSON); without it, the cell alone.
        schedule: Option<PathBuf>,
        /// The HTML file to write.
        #[arg(long, short)]
        out: PathBuf,
    },
    /// Print the AND/OR precedence graph in Graphviz DOT (exit 2, with the reason, if infeasible).
    ///
    /// Example: declutter graph examples/box_lid.dcl | dot -Tsvg > g.svg
    Graph {
        /// The scenario file (.dcl).
        file: PathBuf,
        /// Override the scenario's planner seed (as for `compile`).
        #[arg(long)]
        seed: Option<u64>,
        /// Override the scenario's objective (as for `compile`).
        #[arg(long, value_parser = ["fewest_removals", "fewest_vertices"])]
        objective: Option<String>,
    },
}

#[derive(Subcommand)]
enum ImportCommand {
    /// A MoveIt planning scene (YAML) and, optionally, a motion-plan request.
    ///
    /// Example: declutter import moveit scene.yaml --request req.yaml --cell cell.dcl --removable '^can' -o scene.dcl
    Moveit {
        /// The planning scene, as MoveIt writes it in YAML (`moveit_msgs/PlanningScene`).
        scene: PathBuf,
        /// A motion-plan request: its start state becomes the robots' `home`, its joint goal the `target`.
        #[arg(long)]
        request: Option<PathBuf>,
        /// A cell file whose robots, hands, fixed bodies and planner block are written with the scene.
        #[arg(long)]
        cell: Option<PathBuf>,
        /// Objects whose id matches this regular expression become removable `object`s (else `fixed`).
        #[arg(long, value_name = "REGEX")]
        removable: Option<String>,
        /// The scenario file to write (mesh files are written beside it).
        #[arg(long, short)]
        out: PathBuf,
    },
}

fn main() -> ExitCode {
    // Exit 2 means "infeasible", so usage errors must not use clap's default of 2.
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            let asked = matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion);
            return ExitCode::from(if asked { driver::EXIT_OK } else { driver::EXIT_INPUT });
        }
    };
    let mut global = GlobalOptions::from_env(cli.package_path, cli.no_color);
    global.meshes = cli.meshes;
    global.verbose = cli.verbose;
    let code = match cli.command {
        Command::Check { file } => driver::check(&file, &global),
        Command::Resolve { file } => driver::resolve(&file, &global),
        Command::Compile { file, seed, objective, format, out, stats, execution } => {
            let execution = if execution == "sequential" { Execution::Sequential } else { Execution::Concurrent };
            driver::compile(&file, &global, &driver::CompileOptions { seed, objective, format, out, stats, execution })
        }
        Command::Verify { file, schedule, clearance } => {
            driver::verify(&file, &schedule, &global, &driver::VerifyOptions { clearance })
        }
        Command::Import(ImportCommand::Moveit { scene, request, cell, removable, out }) => {
            driver::import_moveit(&driver::ImportOptions { scene, request, cell, removable, out }, &global)
        }
        Command::Show { file, schedule, out } => driver::show(&file, &global, &driver::ShowOptions { schedule, out }),
        Command::Graph { file, seed, objective } => {
            driver::graph(&file, &global, &driver::GraphOptions { seed, objective })
        }
    };
    ExitCode::from(code)
}
