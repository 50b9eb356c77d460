//! The `declutter` binary end to end: exit codes (0 ok, 1 input or usage error or an
//! invalid schedule, 2 infeasible), `--out`, `verify` and `graph` on shipped examples.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use declutter::driver::parse_schedule;
use declutter::schedule;

/// Runs the binary from the crate root, without colour.
fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_declutter"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("NO_COLOR", "1")
        .stdin(std::process::Stdio::null())
        .output()
        .expect("the declutter binary runs")
}

fn code(o: &Output) -> i32 {
    o.status.code().expect("exited with a code")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// An empty directory of this test's own, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("declutter-cli-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir is created");
        TempDir(dir)
    }
    fn path(&self, name: &str) -> String {
        self.0.join(name).display().to_string()
    }
    /// File names in the directory, sorted (hidden temporary files included).
    fn files(&self) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(&self.0)
            .expect("temp dir is readable")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
    /// Output with the directory's path replaced by `[dir]`, for snapshots.
    fn mask(&self, text: &str) -> String {
        text.replace(&self.0.display().to_string(), "[dir]")
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn compile_writes_out_and_verify_accepts_it_in_both_formats() {
    let dir = TempDir::new("compile-ok");
    let (yaml, json) = (dir.path("a.yaml"), dir.path("a.json"));
    let o = run(&["compile", "examples/box_lid.dcl", "--out", &yaml]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(stdout(&o), "", "with --out, nothing goes to stdout");
    let o = run(&["compile", "examples/box_lid.dcl", "--format", "json", "--out", &json]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    // Both written, no temporary file left behind.
    assert_eq!(dir.files(), ["a.json", "a.yaml"]);
    for file in [&yaml, &json] {
        let o = run(&["verify", "examples/box_lid.dcl", file]);
        assert_eq!(code(&o), 0, "{}", stderr(&o));
        assert!(stderr(&o).starts_with(&format!("ok: {file} verified — 2 actions, ")), "{}", stderr(&o));
    }
}

#[test]
fn verify_exits_1_with_the_violation_on_a_tampered_schedule() {
    let dir = TempDir::new("tampered");
    let file = dir.path("a.yaml");
    let o = run(&["compile", "examples/box_lid.dcl", "--out", &file]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let text = std::fs::read_to_string(&file).expect("schedule written");
    let mut s = parse_schedule(&text).expect("the schedule reads back");
    // Shoulder far forward, elbow stretched: the arm lies on the table, on the way.
    let robot = s.actions[0].robot.clone();
    let tr = s.trajectories.iter_mut().find(|t| t.robot == robot).expect("its trajectory");
    let moving = tr.points.iter().position(|p| p.qd.iter().any(|v| *v != 0.0)).expect("a moving point");
    tr.points[moving].q = vec![0.0, 2.2, 0.3, 0.0, 0.0, 0.0];
    std::fs::write(&file, schedule::to_yaml(&s).expect("YAML")).expect("tampered schedule written");
    let o = run(&["verify", "examples/box_lid.dcl", &file]);
    assert_eq!(code(&o), 1);
    assert_eq!(stdout(&o), "");
    insta::assert_snapshot!("verify_table_waypoint", dir.mask(&stderr(&o)));
}

#[test]
fn verify_refuses_a_schedule_of_another_format_version_by_name() {
    let dir = TempDir::new("version");
    let file = dir.path("s.yaml");
    let o = run(&["compile", "examples/box_lid.dcl", "-o", &file]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let text = std::fs::read_to_string(&file).expect("schedule written");
    // A version 1 schedule had no `schedule_version` key; a later one names its number.
    let v1 = text.strip_prefix("schedule_version: 2\n").expect("version 2 first").to_string();
    for (name, body) in [("v1.yaml", v1), ("v3.yaml", text.replacen("schedule_version: 2", "schedule_version: 3", 1))] {
        let path = dir.path(name);
        std::fs::write(&path, body).expect("written");
        let o = run(&["verify", "examples/box_lid.dcl", &path]);
        assert_eq!(code(&o), 1, "{}", stderr(&o));
        insta::assert_snapshot!(format!("verify_version_{name}"), dir.mask(&stderr(&o)));
    }
}

#[test]
fn compile_of_an_infeasible_scenario_exits_2_with_the_reason() {
    let dir = TempDir::new("infeasible");
    let file = dir.path("w.yaml");
    let o = run(&["compile", "examples/walled.dcl", "--out", &file]);
    assert_eq!(code(&o), 2);
    insta::assert_snapshot!("compile_walled_stderr", stderr(&o));
    // The infeasible schedule is still written; it carries the reason.
    let s = parse_schedule(&std::fs::read_to_string(&file).expect("written")).expect("reads back");
    assert_eq!(s.status, schedule::Status::Infeasible);
    assert!(s.reason.is_some());
    // And `verify` rejects it.
    let o = run(&["verify", "examples/walled.dcl", &file]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("violation: schedule: the schedule is not solved"), "{}", stderr(&o));
}

/// The time a query took, which varies from run to run, as `[time]`; help text joined
/// onto one line, so the width of the time cannot move its line breaks.
fn mask_time(text: &str) -> String {
    let joined = text.replace("\n        ", " ");
    let mut out = String::new();
    let mut rest = joined.as_str();
    while let Some(i) = rest.find(" samples in ") {
        let (head, tail) = rest.split_at(i + " samples in ".len());
        out.push_str(head);
        out.push_str("[time]");
        rest = &tail[tail.find(';').unwrap_or(tail.len())..];
    }
    out.push_str(rest);
    out
}

#[test]
fn a_proof_and_a_budget_give_up_exit_2_with_distinct_codes() {
    let dir = TempDir::new("proof-or-budget");
    let status = |file: &str| parse_schedule(&std::fs::read_to_string(file).expect("written")).expect("reads").status;
    // Proved: the target configuration puts a link in the table, and the message says which.
    let proved = dir.path("proved.yaml");
    let o = run(&["compile", "tests/fixtures/plan/config_in_table.dcl", "--out", &proved]);
    assert_eq!(code(&o), 2);
    assert_eq!(status(&proved), schedule::Status::Infeasible, "the schedule says it is a proof too");
    let proof = stderr(&o);
    assert!(proof.starts_with("declutter::plan::infeasible\n"), "{proof}");
    assert!(!proof.contains("grasp"), "a configuration target's message speaks of the configuration: {proof}");
    insta::assert_snapshot!("compile_config_in_table_stderr", proof);
    // Not found within two samples: its own code, the figures, and the setting to raise.
    let budget = dir.path("budget.yaml");
    let o = run(&["compile", "tests/fixtures/plan/gave_up.dcl", "--out", &budget]);
    assert_eq!(code(&o), 2);
    assert_eq!(status(&budget), schedule::Status::GaveUp, "the schedule does not claim a proof");
    let gave_up = stderr(&o);
    assert!(gave_up.starts_with("declutter::plan::gave_up\n"), "{gave_up}");
    assert!(gave_up.contains("declutter::plan::budget_exhausted"), "{gave_up}");
    assert!(gave_up.contains("raise `max_samples`"), "{gave_up}");
    assert!(!gave_up.contains("grasp"), "{gave_up}");
    insta::assert_snapshot!("compile_gave_up_stderr", mask_time(&gave_up));
    // And it was the budget: with the default one the same cell is solved.
    let cell = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cell.dcl");
    let text = std::fs::read_to_string("tests/fixtures/plan/gave_up.dcl").expect("the fixture");
    let raised = text
        .replace("max_samples 2", "max_samples 5000")
        .replace("\"../../../examples/cell.dcl\"", &format!("{:?}", cell.display().to_string()));
    assert_ne!(raised, text);
    let scenario = dir.path("raised.dcl");
    std::fs::write(&scenario, raised).expect("written");
    let solved = dir.path("solved.yaml");
    let o = run(&["compile", &scenario, "--out", &solved]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(status(&solved), schedule::Status::Solved);
}

#[test]
fn an_ungraspable_target_says_why_per_robot_out_of_reach_or_hitting_a_named_body() {
    for (name, says) in [("out_of_reach", "out of reach"), ("under_a_shelf", "fixed body `board`")] {
        let o = run(&["compile", &format!("tests/fixtures/plan/{name}.dcl"), "--out", "/dev/null"]);
        assert_eq!(code(&o), 2, "{}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains("declutter::plan::ungraspable") && err.contains(says), "{err}");
        insta::assert_snapshot!(format!("compile_{name}_stderr"), err);
    }
}

#[test]
fn compile_input_errors_exit_1_and_write_nothing() {
    let dir = TempDir::new("input-error");
    let missing = dir.path("missing.dcl");
    let o = run(&["compile", &missing, "--out", &dir.path("a.yaml")]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("error: 1 problem found"), "{}", stderr(&o));
    assert!(dir.files().is_empty(), "{:?}", dir.files());
    // A directory that does not exist: the write fails, and nothing is left.
    let o = run(&["compile", "examples/box_lid.dcl", "--out", &dir.path("no/such/dir/a.yaml")]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("error: cannot write the schedule to "), "{}", stderr(&o));
    assert!(dir.files().is_empty(), "{:?}", dir.files());
    // `--out` names a directory: the rename fails after the write; the temporary file goes.
    std::fs::create_dir(dir.0.join("taken")).expect("dir created");
    let o = run(&["compile", "examples/box_lid.dcl", "--out", &dir.path("taken")]);
    assert_eq!(code(&o), 1);
    assert_eq!(dir.files(), ["taken"]);
}

#[test]
fn out_to_a_fifo_writes_through_it_and_leaves_it_a_fifo() {
    use std::os::unix::fs::FileTypeExt;
    // `-o /dev/null` is in the book: a special file must be written in place, never
    // replaced by a renamed regular file. A FIFO stands in for the device here.
    let dir = TempDir::new("fifo");
    let fifo = dir.path("pipe");
    let c_path = std::ffi::CString::new(fifo.clone()).expect("no NUL in the path");
    // SAFETY: a valid NUL-terminated path; mkfifo only creates a directory entry.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0, "mkfifo");
    // A second name for the FIFO: if `pipe` were replaced, the reader could still be
    // released through it, so a regression fails instead of hanging.
    let spare = dir.path("spare");
    std::fs::hard_link(&fifo, &spare).expect("hard link");
    let reader = {
        let spare = spare.clone();
        std::thread::spawn(move || std::fs::read_to_string(spare).expect("the FIFO is readable"))
    };
    let o = run(&["compile", "examples/box_lid.dcl", "-o", &fifo]);
    let kind = std::fs::symlink_metadata(&fifo).expect("still there").file_type();
    if !kind.is_fifo() {
        drop(std::fs::OpenOptions::new().write(true).open(&spare));
    }
    let text = reader.join().expect("reader thread");
    assert!(kind.is_fifo(), "the FIFO was replaced: {kind:?}");
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(text.starts_with("schedule_version: 2\nscenario: box-lid\n"), "{text}");
    assert_eq!(dir.files(), ["pipe", "spare"], "no temporary file left");
}

#[test]
fn out_through_a_symlink_replaces_the_file_it_names_not_the_link() {
    let dir = TempDir::new("symlink");
    std::fs::create_dir(dir.0.join("real")).expect("dir created");
    std::fs::write(dir.0.join("real/a.yaml"), "old").expect("old file");
    std::os::unix::fs::symlink(dir.0.join("real/a.yaml"), dir.0.join("link.yaml")).expect("symlink");
    let o = run(&["compile", "examples/box_lid.dcl", "-o", &dir.path("link.yaml")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let link = std::fs::symlink_metadata(dir.0.join("link.yaml")).expect("link still there");
    assert!(link.file_type().is_symlink(), "the link was replaced by a file");
    let text = std::fs::read_to_string(dir.0.join("real/a.yaml")).expect("target readable");
    assert!(text.starts_with("schedule_version: 2\nscenario: box-lid\n"), "{text}");
    assert_eq!(dir.files(), ["link.yaml", "real"]);
}

#[test]
fn graph_of_a_solved_example_exits_0() {
    let o = run(&["graph", "examples/box_lid.dcl"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).starts_with("digraph"), "{}", stdout(&o));
    assert_eq!(stderr(&o), "");
    // The planning overrides of `compile` are accepted.
    let o = run(&["graph", "examples/reach_pose.dcl", "--seed", "3", "--objective", "fewest_vertices"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert!(stdout(&o).starts_with("digraph"), "{}", stdout(&o));
}

#[test]
fn graph_of_an_infeasible_example_prints_it_and_the_reason_and_exits_2() {
    let o = run(&["graph", "examples/walled.dcl"]);
    assert_eq!(code(&o), 2);
    assert!(stdout(&o).starts_with("digraph"), "{}", stdout(&o));
    // The same reason as `compile` gives.
    let c = run(&["compile", "examples/walled.dcl"]);
    assert_eq!(stderr(&o), stderr(&c));
}

#[test]
fn usage_errors_exit_1_and_help_and_version_exit_0() {
    for args in [
        &[][..],
        &["compile"][..],
        &["compile", "examples/box_lid.dcl", "--bogus"][..],
        &["verify", "examples/box_lid.dcl"][..],
        &["frobnicate"][..],
    ] {
        let o = run(args);
        assert_eq!(code(&o), 1, "{args:?}: {}", stderr(&o));
        assert_eq!(stdout(&o), "", "{args:?}");
        assert!(stderr(&o).contains("Usage: declutter"), "{args:?}: {}", stderr(&o));
    }
    for args in [&["--help"][..], &["compile", "--help"][..], &["--version"][..]] {
        let o = run(args);
        assert_eq!(code(&o), 0, "{args:?}: {}", stderr(&o));
        assert!(!stdout(&o).is_empty(), "{args:?}");
    }
    // A bad value is a usage error too.
    let o = run(&["compile", "examples/box_lid.dcl", "--objective", "fastest"]);
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).starts_with("error: invalid value 'fastest' for '--objective"), "{}", stderr(&o));
}

#[test]
fn help_describes_every_argument() {
    let o = run(&["verify", "--help"]);
    assert_eq!(code(&o), 0);
    insta::assert_snapshot!("verify_help", stdout(&o));
    let o = run(&["graph", "--help"]);
    assert_eq!(code(&o), 0);
    insta::assert_snapshot!("graph_help", stdout(&o));
}

#[test]
fn use_of_the_current_directory_from_a_file_in_it_says_it_is_a_directory() {
    let dir = TempDir::new("use_dot");
    std::fs::write(dir.0.join("s.dcl"), "use \".\"\n").expect("scenario written");
    let o = Command::new(env!("CARGO_BIN_EXE_declutter"))
        .args(["check", "s.dcl"])
        .current_dir(&dir.0)
        .env("NO_COLOR", "1")
        .output()
        .expect("the declutter binary runs");
    assert_eq!(code(&o), 1);
    assert!(stderr(&o).contains("× used file `.` is a directory"), "{}", stderr(&o));
}

#[test]
fn check_of_a_library_loads_its_robots() {
    // A cell file has no target, but a broken robot in it must not wait for a scenario.
    let dir = TempDir::new("library");
    let tx90 = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/robots/tx90.urdf");
    let cell = format!("robot r1 {{\n    urdf \"{}\"\n    home [0, 0, 0]\n}}\n", tx90.display());
    std::fs::write(dir.0.join("cell.dcl"), cell).expect("library written");
    let o = run(&["check", &dir.path("cell.dcl")]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("declutter::world::joint_count"), "{}", stderr(&o));
    let o = run(&["check", "examples/cell.dcl"]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        "ok: examples/cell.dcl (a library: no target) — 2 robots, 0 objects, 1 fixed body, 0 grasps\n  \
         r1: hand `sah` on `flange`\n  r2: hand `sdh2` on `flange`\n"
    );
}

#[test]
fn compile_stats_prints_one_row_per_query_with_the_schedules_figures() {
    let dir = TempDir::new("stats");
    let out = dir.path("s.yaml");
    let o = run(&["compile", "examples/box_lid.dcl", "--stats", "-o", &out]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let err = stderr(&o);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(
        lines.first().map(|l| l.split_whitespace().collect::<Vec<_>>()),
        Some(vec!["query", "time", "(ms)", "samples", "connected", "paths", "checks"]),
        "{err}"
    );
    // Every row but the time column is what the schedule's `stats` list holds.
    let s = parse_schedule(&std::fs::read_to_string(&out).expect("schedule written")).expect("parses");
    assert_eq!(lines.len(), s.stats.len() + 3, "header, one row per query, total, makespans: {err}");
    for (line, q) in lines[1..].iter().zip(&s.stats) {
        let cols: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(cols[0..2].join(" "), format!("P({}, {})", q.robot, q.object), "{line}");
        let figures: Vec<u64> = cols[3..].iter().map(|c| c.parse().expect("a count")).collect();
        assert_eq!(figures, [q.samples, q.connected, q.paths, q.checks], "{line}");
    }
    assert!(lines[lines.len() - 2].starts_with("total"), "{err}");
    // Both makespans, the written (concurrent) one as the schedule states it.
    let makespans: Vec<f64> = lines[lines.len() - 1]
        .strip_prefix("makespan: sequential ")
        .and_then(|l| l.strip_suffix(" s"))
        .map(|l| l.split(" s, concurrent ").map(|v| v.parse().expect("seconds")).collect())
        .unwrap_or_default();
    assert_eq!(makespans.len(), 2, "{err}");
    assert_eq!(format!("{:.3}", makespans[1]), format!("{:.3}", s.makespan), "{err}");
    assert!(makespans[1] < makespans[0], "box_lid's two actions overlap: {err}");
}

#[test]
fn check_of_a_library_with_objects_reports_their_grasps_then_warns() {
    let dir = TempDir::new("library_objects");
    let cell = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/cell.dcl");
    let text = format!(
        "use \"{}\"\nobject can cylinder(radius: 3cm, length: 12cm) at (60cm, 0, 6cm) {{\n    \
         grasp top at (0, 0, 6cm) rot (180deg, 0, 0) approach 5cm repeat 4 about z\n}}\n",
        cell.display()
    );
    std::fs::write(dir.0.join("lib.dcl"), text).expect("library written");
    let o = run(&["check", &dir.path("lib.dcl")]);
    assert_eq!(code(&o), 0, "{}", stderr(&o));
    let err = stderr(&o);
    let lines: Vec<&str> = err.lines().collect();
    assert!(lines[0].ends_with("lib.dcl (a library: no target) — 2 robots, 1 object, 1 fixed body, 4 grasps"), "{err}");
    assert_eq!(lines[1..3], ["  r1: hand `sah` on `flange`", "  r2: hand `sdh2` on `flange`"], "{err}");
    assert_eq!(lines[3], "  can: grasps reachable by r1 4/4, r2 4/4", "{err}");
    assert!(lines[4].contains("declutter::resolve::no_target"), "{err}");
}
