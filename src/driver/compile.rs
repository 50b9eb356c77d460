//! `compile` and `graph`: plan a scenario, then write its schedule or its AND/OR graph.

use std::io::Write as _;
use std::path::Path;

use super::pipeline::{fail, load, render_options, Loaded};
use super::{CompileOptions, Format, GlobalOptions, GraphOptions, EXIT_INFEASIBLE, EXIT_INPUT, EXIT_OK};
use crate::diag::render_one;
use crate::plan::andor::{self, Solution};
use crate::plan::Planner;
use crate::resolve::Objective;
use crate::schedule::{self, QueryStat, Schedule, Status};
use crate::timing::Execution;
use crate::verify;
use crate::world::World;

/// Resolves, builds the world with the command-line overrides, plans and verifies.
fn plan(
    file: &Path,
    g: &GlobalOptions,
    seed: Option<u64>,
    objective: Option<Objective>,
    execution: Execution,
) -> Result<(Loaded, Planned), u8> {
    let loaded = load(file, g, |scn| {
        if let Some(s) = seed {
            scn.planner.seed = s;
        }
        if let Some(o) = objective {
            scn.planner.objective = o;
        }
    })?;
    // A spinner with the phase and the elapsed time, only when a person is watching.
    let spinner = std::io::IsTerminal::is_terminal(&std::io::stderr()).then(|| {
        let bar = indicatif::ProgressBar::new_spinner();
        if let Ok(style) = indicatif::ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
            bar.set_style(style);
        }
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
        bar
    });
    let result = plan_verified_with(&loaded.world, execution, &|phase| {
        if let Some(bar) = &spinner {
            bar.set_message(phase.to_string());
        }
    });
    if let Some(bar) = spinner {
        bar.finish_and_clear();
    }
    match result {
        Ok(planned) => {
            if planned.refinements > 0 {
                let scn = loaded.world.scenario();
                let final_step = scn.planner.resolution / f64::from(1u32 << planned.refinements);
                eprintln!(
                    "note: at resolution {:.3}° a planned motion touched objects between its checks; planned again at {:.3}°",
                    scn.planner.resolution.to_degrees(),
                    final_step.to_degrees()
                );
            }
            Ok((loaded, planned))
        }
        Err(violations) => {
            for v in &violations {
                eprintln!("violation: {v}");
            }
            eprintln!(
                "error: internal: the planned schedule failed independent verification ({} violations); nothing written. Please report this scenario.",
                violations.len()
            );
            Err(EXIT_INPUT)
        }
    }
}

/// A plan that passed verification, or an infeasible one.
pub struct Planned {
    pub solution: Solution,
    pub schedule: Schedule,
    /// How many times the resolution was halved before the schedule verified.
    pub refinements: u32,
}

/// The planner checks straight motions every `resolution` of joint travel; the verifier
/// replays them so that no point moves more than 2 mm between its samples, so a thin
/// gap the planner stepped over can fail verification. Planning again at half the step,
/// up to a sixteenth (2° → 0.125°, about 2 mm at a TX-90's hand), closes that gap.
const MAX_REFINEMENTS: u32 = 4;

/// Plans a built world (one PRMwO planner over every robot, then the AND/OR graph) and
/// verifies the schedule, refining the resolution when verification fails. This is all
/// of `compile` between loading and writing.
/// `progress` is told each phase as it starts.
pub fn plan_verified(world: &World, progress: &dyn Fn(&str)) -> Result<Planned, Vec<verify::Violation>> {
    plan_verified_with(world, Execution::default(), progress)
}

/// [`plan_verified`] with the actions placed in time by `execution`.
pub fn plan_verified_with(
    world: &World,
    execution: Execution,
    progress: &dyn Fn(&str),
) -> Result<Planned, Vec<verify::Violation>> {
    let scn = world.scenario();
    let mut refinements = 0;
    loop {
        let mut settings = scn.planner.clone();
        settings.resolution /= f64::from(1u32 << refinements);
        progress(&format!("planning at resolution {:.3}°", settings.resolution.to_degrees()));
        let planner = Planner::new(world, &settings);
        let solution = andor::solve(scn, &planner);
        let schedule = schedule::build(world, &solution, execution);
        if schedule.status != Status::Solved {
            return Ok(Planned { solution, schedule, refinements });
        }
        progress("verifying the schedule");
        match verify::verify(world, &schedule) {
            Ok(_) => return Ok(Planned { solution, schedule, refinements }),
            Err(v) if refinements >= MAX_REFINEMENTS => return Err(v),
            Err(_) => refinements += 1,
        }
    }
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

/// Writes `text` to `out` or to stdout. A regular file is written to a temporary file
/// renamed into place, so a failure never leaves half a schedule; a symbolic link is
/// followed, so the file it names is replaced, not the link.
fn write_output(text: &str, out: Option<&Path>) -> std::io::Result<()> {
    let Some(path) = out else {
        return std::io::stdout().lock().write_all(text.as_bytes());
    };
    let target = match std::fs::metadata(path) {
        // `/dev/null`, a FIFO, a terminal: a rename would put a regular file in the
        // device's place (as root, that breaks the whole machine), so write in place.
        Ok(meta) if !meta.is_file() && !meta.is_dir() => return std::fs::write(path, text),
        Ok(_) => std::fs::canonicalize(path)?,
        Err(_) => path.to_path_buf(),
    };
    let tmp = temp_path(&target);
    let written = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, &target));
    // Also after a partial write: no temporary file is left behind.
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

/// A temporary name next to `path` (a rename stays on one file system), hidden, and
/// unique per target file and process: `a.yaml` and `a.json`, or two runs, never share it.
pub(super) fn temp_path(path: &Path) -> std::path::PathBuf {
    let name = path.file_name().map_or_else(|| "schedule".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.declutter-tmp-{}", std::process::id()))
}

pub fn compile(file: &Path, g: &GlobalOptions, o: &CompileOptions) -> u8 {
    // The promise is a verified schedule: `plan` re-checks a solved one before it is written.
    let (loaded, Planned { solution, schedule, .. }) =
        match plan(file, g, o.seed, parse_objective(o.objective.as_deref()), o.execution) {
            Ok(x) => x,
            Err(code) => return code,
        };
    if o.stats {
        eprint!("{}", stats_table(&schedule.stats));
        if schedule.status == Status::Solved {
            // The other execution's makespan, timed from the same plan.
            let other = match o.execution {
                Execution::Sequential => Execution::Concurrent,
                Execution::Concurrent => Execution::Sequential,
            };
            let other = schedule::build(&loaded.world, &solution, other);
            let (seq, conc) = match o.execution {
                Execution::Sequential => (schedule.makespan, other.makespan),
                Execution::Concurrent => (other.makespan, schedule.makespan),
            };
            eprintln!("makespan: sequential {seq:.3} s, concurrent {conc:.3} s");
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

/// `declutter graph`: G in DOT on stdout, also for an infeasible scenario (it shows
/// why), which then reports the reason and exits 2 like `compile`.
pub fn graph(file: &Path, g: &GlobalOptions, o: &GraphOptions) -> u8 {
    let (loaded, planned) = match plan(file, g, o.seed, parse_objective(o.objective.as_deref()), Execution::default()) {
        Ok(x) => x,
        Err(code) => return code,
    };
    print!("{}", schedule::to_dot(loaded.world.scenario(), &planned.solution));
    match &planned.solution.outcome {
        Ok(_) => EXIT_OK,
        Err(why) => {
            eprint!("{}", render_one(&loaded.sources, why, render_options(g)));
            EXIT_INFEASIBLE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::temp_path;
    use std::path::Path;

    #[test]
    fn temporary_names_differ_per_target_file() {
        let pid = std::process::id();
        let yaml = temp_path(Path::new("out/a.yaml"));
        assert_eq!(yaml, Path::new(&format!("out/.a.yaml.declutter-tmp-{pid}")));
        assert_ne!(yaml, temp_path(Path::new("out/a.json")));
        assert_eq!(temp_path(Path::new("a")), Path::new(&format!(".a.declutter-tmp-{pid}")));
    }
}
