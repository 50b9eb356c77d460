//! `compile` and `graph`: plan a scenario, then write its schedule or its AND/OR graph.

use std::io::Write as _;
use std::path::Path;

use super::pipeline::{fail, load, render_options, Loaded};
use super::{CompileOptions, Format, GlobalOptions, EXIT_INFEASIBLE, EXIT_INPUT, EXIT_OK};
use crate::diag::render_one;
use crate::plan::andor::{self, Solution};
use crate::plan::Planner;
use crate::resolve::Objective;
use crate::schedule::{self, QueryStat, Schedule, Status};
use crate::verify;

/// Resolves, builds the world with the command-line overrides, and solves.
fn plan(
    file: &Path,
    g: &GlobalOptions,
    seed: Option<u64>,
    objective: Option<Objective>,
) -> Result<(Loaded, Solution), u8> {
    let loaded = load(file, g, |scn| {
        if let Some(s) = seed {
            scn.planner.seed = s;
        }
        if let Some(o) = objective {
            scn.planner.objective = o;
        }
    })?;
    let scn = loaded.world.scenario();
    let planner = Planner::new(&loaded.world, &scn.planner);
    let solution = andor::solve(scn, &planner);
    Ok((loaded, solution))
}

fn parse_objective(s: Option<&str>) -> Option<Objective> {
    match s? {
        "fewest_vertices" => Some(Objective::FewestVertices),
        _ => Some(Objective::FewestRemovals),
    }
}

/// The paper's Table 1 for this run: one row per `findPath` query P(robot, object).
pub fn stats_table(stats: &[QueryStat]) -> String {
    let mut out = String::from("query                      time (ms)   samples  connected  paths     checks\n");
    for s in stats {
        let name = format!("P({}, {})", s.robot, s.object);
        out.push_str(&format!(
            "{name:<26} {:>9.2} {:>9} {:>10} {:>6} {:>10}\n",
            s.time_ms, s.samples, s.connected, s.paths, s.checks
        ));
    }
    let total: f64 = stats.iter().map(|s| s.time_ms).sum();
    out.push_str(&format!("{:<26} {total:>9.2}\n", "total"));
    out
}

/// Writes `text` to `out` (via a temporary file renamed into place, so a failure never
/// leaves half a schedule) or to stdout.
fn write_output(text: &str, out: Option<&Path>) -> std::io::Result<()> {
    match out {
        None => std::io::stdout().lock().write_all(text.as_bytes()),
        Some(path) => {
            let tmp = path.with_extension("declutter-tmp");
            std::fs::write(&tmp, text)?;
            std::fs::rename(&tmp, path).inspect_err(|_| {
                let _ = std::fs::remove_file(&tmp);
            })
        }
    }
}

pub fn compile(file: &Path, g: &GlobalOptions, o: &CompileOptions) -> u8 {
    let (loaded, solution) = match plan(file, g, o.seed, parse_objective(o.objective.as_deref())) {
        Ok(x) => x,
        Err(code) => return code,
    };
    let scn = loaded.world.scenario();
    let schedule: Schedule = schedule::build(scn, &solution);
    if o.stats {
        eprint!("{}", stats_table(&schedule.stats));
    }
    // The promise is a verified schedule: a solved one is re-checked before it is written.
    if schedule.status == Status::Solved {
        if let Err(violations) = verify::verify(&loaded.world, &schedule) {
            for v in &violations {
                eprintln!("violation: {v}");
            }
            eprintln!(
                "error: internal: the planned schedule failed independent verification ({} violations); nothing written. Please report this scenario.",
                violations.len()
            );
            return EXIT_INPUT;
        }
    }
    let text = match o.format {
        Format::Yaml => schedule::to_yaml(&schedule),
        Format::Json => schedule::to_json(&schedule),
    };
    let text = match text {
        Ok(t) => t,
        Err(e) => return fail(&loaded.sources, &[e], g),
    };
    if let Err(e) = write_output(&text, o.out.as_deref()) {
        let target = o.out.as_ref().map_or_else(|| "standard output".to_string(), |p| p.display().to_string());
        eprintln!("error: cannot write the schedule to {target}: {e}");
        return EXIT_INPUT;
    }
    match &solution.outcome {
        Ok(_) => EXIT_OK,
        Err(why) => {
            eprint!("{}", render_one(&loaded.sources, why, render_options(g)));
            EXIT_INFEASIBLE
        }
    }
}

pub fn graph(file: &Path, g: &GlobalOptions, seed: Option<u64>) -> u8 {
    let (loaded, solution) = match plan(file, g, seed, None) {
        Ok(x) => x,
        Err(code) => return code,
    };
    print!("{}", schedule::to_dot(loaded.world.scenario(), &solution));
    EXIT_OK
}
