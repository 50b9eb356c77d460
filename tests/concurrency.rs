//! Two arms at once, as a user meets them: the split-lid crate, whose two first actions
//! are independent but sweep the same space above the crate, and the makespans of every
//! shipped scenario with two or more robots, pinned in the book.

mod time_support;

use std::path::{Path, PathBuf};
use std::process::Command;

use declutter::diag::{FsLoader, SourceMap};
use declutter::driver::parse_schedule;
use declutter::schedule::{self, Execution, Status};
use declutter::world::{self, WorldOptions};
use time_support::shift_earlier;

fn run(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_declutter")).arg("--no-color").args(args).output().expect("runs");
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("concurrency").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn split_lid_arms_share_the_crate_and_started_together_they_collide() {
    let dir = scratch("split_lid");
    let file = dir.join("s.yaml");
    let file = file.to_str().expect("utf-8 path");
    let (code, err) = run(&["compile", "examples/split_lid.dcl", "-o", file]);
    assert_eq!(code, 0, "{err}");
    let (code, err) = run(&["verify", "examples/split_lid.dcl", file]);
    assert_eq!(code, 0, "{err}");
    let mut s = parse_schedule(&std::fs::read_to_string(file).expect("written")).expect("parses");
    // Each arm lifts one half lid first, neither waiting for the other's object ...
    let first = |r: &str| s.actions.iter().find(|a| a.robot == r).expect("an action of each arm").clone();
    let (a1, a2) = (first("r1"), first("r2"));
    assert!(a1.after.is_empty() && a2.after.is_empty(), "{:?} {:?}", a1.after, a2.after);
    assert_eq!((a1.object.as_deref(), a2.object.as_deref()), (Some("lid_a"), Some("lid_b")));
    // ... but one waits for the other to be out of its way over the crate.
    let (late, wait) = if a2.start > a1.start { ("r2", a2.start) } else { ("r1", a1.start) };
    assert!(wait > 0.0, "one arm waits");
    // Started at once, the arms meet: verify names both, their bodies and the time.
    shift_earlier(&mut s, late, wait, wait);
    let shifted = dir.join("shifted.yaml");
    std::fs::write(&shifted, schedule::to_yaml(&s).expect("yaml")).expect("written");
    let (code, err) = run(&["verify", "examples/split_lid.dcl", shifted.to_str().expect("utf-8 path")]);
    assert_eq!(code, 1, "{err}");
    let contact =
        err.lines().find(|l| l.contains("robot `r1`") && l.contains("robot `r2`")).unwrap_or_else(|| panic!("{err}"));
    assert!(contact.starts_with("violation: t = "), "{contact}");
    insta::assert_snapshot!(err.replace(shifted.to_str().expect("utf-8 path"), "[shifted.yaml]"));
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn skipping_ahead_where_nothing_can_come_close_finds_what_every_step_finds() {
    // split_lid with its waiting arm started 0 %, 10 %, … 100 % of its wait earlier: from
    // safe to colliding. The replay that skips ahead where an instant proves the cell clear
    // must report the same contacts, first found at the same instants, as the one that
    // checks every 2 mm step (its instants are among the latter's).
    let (w, s) = time_support::compiled("examples/split_lid.dcl");
    let first = |r: &str| s.actions.iter().find(|a| a.robot == r).expect("an action of each arm").start;
    let (late, wait) = if first("r2") > first("r1") { ("r2", first("r2")) } else { ("r1", first("r1")) };
    let mut contacts = 0;
    for k in 0..=10 {
        let mut shifted = s.clone();
        shift_earlier(&mut shifted, late, wait, wait * k as f64 / 10.0);
        let run = |every_step| {
            let opts = declutter::verify::Options { every_step, ..Default::default() };
            let found = declutter::verify::verify_with(&w, &shifted, &opts).err().unwrap_or_default();
            found.iter().map(ToString::to_string).collect::<Vec<_>>()
        };
        let (skipping, every) = (run(false), run(true));
        assert_eq!(skipping, every, "shifted by {k}0 % of the wait");
        contacts += every.iter().filter(|v| v.contains("touches")).count();
    }
    assert!(contacts > 0, "some shifts collide");
}

/// The replay's free time taken from the pairs whose bounds can matter (queued by when
/// their bounds run out) against every pair's bound at every instant: the same instants
/// and the same findings, on split_lid shifted from safe to colliding (as above) and on
/// every shipped example that solves, at clearances 0 and 2 cm.
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn queued_pairs_skip_to_the_instants_every_pair_gives() {
    let outcome = |w: &world::World, s: &declutter::schedule::Schedule, clearance: f64, every_pair: bool| {
        let opts = declutter::verify::Options { every_pair, clearance, ..Default::default() };
        match declutter::verify::verify_with(w, s, &opts) {
            Ok(summary) => (summary.samples, Vec::new()),
            Err(found) => (0, found.iter().map(ToString::to_string).collect::<Vec<_>>()),
        }
    };
    let (w, s) = time_support::compiled("examples/split_lid.dcl");
    let first = |r: &str| s.actions.iter().find(|a| a.robot == r).expect("an action of each arm").start;
    let (late, wait) = if first("r2") > first("r1") { ("r2", first("r2")) } else { ("r1", first("r1")) };
    let mut cases = Vec::new();
    for k in 0..=10 {
        let mut shifted = s.clone();
        shift_earlier(&mut shifted, late, wait, wait * k as f64 / 10.0);
        cases.push((format!("split_lid shifted {k}0 %"), 0, shifted));
    }
    let mut worlds = vec![w];
    for (path, w) in example_worlds(1) {
        if let Ok(planned) = declutter::driver::plan_verified(&w, &|_| {}) {
            if planned.schedule.status == Status::Solved {
                cases.push((path.display().to_string(), worlds.len(), planned.schedule));
                worlds.push(w);
            }
        }
    }
    let (mut instants, mut findings) = (0, 0);
    for (name, wi, s) in &cases {
        let w = &worlds[*wi];
        for clearance in [0.0, 0.02] {
            let (queued, every) = (outcome(w, s, clearance, false), outcome(w, s, clearance, true));
            assert_eq!(queued, every, "{name} at clearance {clearance}");
            instants += queued.0;
            findings += queued.1.len();
        }
    }
    assert!(
        cases.len() > 15 && instants > 1000 && findings > 0,
        "{} cases, {instants} instants, {findings} findings",
        cases.len()
    );
}

/// Every shipped example that is a scenario (not a library) with at least `robots`
/// robots, and its world, in file-name order.
fn example_worlds(robots: usize) -> Vec<(PathBuf, world::World)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir("examples")
        .expect("examples/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "dcl"))
        .collect();
    files.sort();
    let mut out = Vec::new();
    for path in files {
        let mut sources = SourceMap::new();
        let summary = declutter::resolve::check(&path, &FsLoader, &mut sources).expect("example checks");
        if summary.library || summary.robots < robots {
            continue;
        }
        let scn = declutter::resolve::resolve(&path, &FsLoader, &mut sources).expect("example resolves");
        let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("example builds");
        out.push((path, w));
    }
    out
}

/// `(example, actions, sequential makespan, concurrent makespan)` of every shipped example
/// with two or more robots that solves, in file-name order.
fn makespans() -> Vec<(String, usize, f64, f64)> {
    let mut out = Vec::new();
    for (path, w) in example_worlds(2) {
        let planned = declutter::driver::plan_verified(&w, &|_| {}).unwrap_or_else(|v| panic!("{v:#?}"));
        if planned.schedule.status != Status::Solved {
            continue;
        }
        let seq = schedule::build(&w, &planned.solution, Execution::Sequential);
        let name = path.file_stem().expect("stem").to_string_lossy().into_owned();
        out.push((name, planned.schedule.actions.len(), seq.makespan, planned.schedule.makespan));
    }
    out
}

const PAGE: &str = "book/src/makespans.md";
const BEGIN: &str = "<!-- makespans: begin (tests/concurrency.rs writes this table) -->";
const END: &str = "<!-- makespans: end -->";

fn table(rows: &[(String, usize, f64, f64)]) -> String {
    let mut t = String::from(
        "| example | actions | sequential (s) | concurrent (s) | concurrent / sequential |\n|---|---:|---:|---:|---:|\n",
    );
    for (name, n, seq, conc) in rows {
        t.push_str(&format!("| `{name}` | {n} | {seq:.3} | {conc:.3} | {:.2} |\n", conc / seq));
    }
    t
}

#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn concurrent_makespans_beat_sequential_and_the_books_table_is_current() {
    let rows = makespans();
    let ratio = |name: &str| {
        let (_, _, seq, conc) = rows.iter().find(|r| r.0 == name).unwrap_or_else(|| panic!("{name} solves"));
        conc / seq
    };
    for (name, _, seq, conc) in &rows {
        assert!(conc <= seq, "{name}: concurrent {conc} s > sequential {seq} s");
    }
    assert!(ratio("cans_5") <= 0.8, "cans_5: {}", ratio("cans_5"));
    assert!(ratio("clutter") <= 0.8, "clutter: {}", ratio("clutter"));
    assert!(ratio("split_lid") <= 0.6, "split_lid: {}", ratio("split_lid"));
    let page = std::fs::read_to_string(PAGE).expect("the book's makespan page");
    let (Some(b), Some(e)) = (page.find(BEGIN), page.find(END)) else { panic!("{PAGE} lacks its table markers") };
    let want = format!("{BEGIN}\n{}{END}", table(&rows));
    let found = &page[b..e + END.len()];
    if found != want {
        if std::env::var_os("UPDATE_BOOK").is_some() {
            std::fs::write(PAGE, page.replace(found, &want)).expect("page written");
        } else {
            panic!("{PAGE} is stale; run `UPDATE_BOOK=1 cargo test --release --test concurrency`:\n{want}");
        }
    }
}
