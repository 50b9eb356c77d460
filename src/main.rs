//! The `declutter` command line: parses arguments and calls the library's driver.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use declutter::driver::{self, Format, GlobalOptions, Meshes};

#[derive(Parser)]
#[command(name = "declutter", version, about = "Compile robot-cell scenarios into verified obstacle-removal schedules")]
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
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check a scenario: parse, resolve names and units, load robots and meshes.
    ///
    /// Example: declutter check examples/box_lid.dcl
    Check { file: PathBuf },
    /// Print the resolved scenario as YAML (world-frame poses, SI units, grasps expanded).
    ///
    /// Example: declutter resolve examples/box_lid.dcl
    Resolve { file: PathBuf },
    /// Plan and print a verified action schedule.
    ///
    /// Example: declutter compile examples/box_lid.dcl --seed 7 --stats
    Compile {
        file: PathBuf,
        /// Override the scenario's planner seed.
        #[arg(long)]
        seed: Option<u64>,
        /// Override the scenario's objective.
        #[arg(long, value_parser = ["fewest_removals", "fewest_vertices"])]
        objective: Option<String>,
        #[arg(long, value_enum, default_value_t = Format::Yaml)]
        format: Format,
        /// Write the schedule here instead of stdout.
        #[arg(long, short)]
        out: Option<PathBuf>,
        /// Print per-query statistics (the paper's Table 1) to stderr.
        #[arg(long)]
        stats: bool,
    },
    /// Independently re-check a schedule against its scenario.
    ///
    /// Example: declutter verify examples/box_lid.dcl box_lid.yaml
    Verify { file: PathBuf, schedule: PathBuf },
    /// Print the AND/OR precedence graph in Graphviz DOT.
    ///
    /// Example: declutter graph examples/box_lid.dcl | dot -Tsvg > g.svg
    Graph {
        file: PathBuf,
        #[arg(long)]
        seed: Option<u64>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut global = GlobalOptions::from_env(cli.package_path, cli.no_color);
    global.meshes = cli.meshes;
    let code = match cli.command {
        Command::Check { file } => driver::check(&file, &global),
        Command::Resolve { file } => driver::resolve(&file, &global),
        Command::Compile { file, seed, objective, format, out, stats } => {
            driver::compile(&file, &global, &driver::CompileOptions { seed, objective, format, out, stats })
        }
        Command::Verify { file, schedule } => driver::verify(&file, &schedule, &global),
        Command::Graph { file, seed } => driver::graph(&file, &global, seed),
    };
    ExitCode::from(code)
}
