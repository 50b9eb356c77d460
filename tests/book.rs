//! Every ```dcl block in the book passes the same full check as `declutter check`
//! (parse, resolve, load every URDF and mesh, build the world, and no object that no
//! robot can grasp), against the files in `examples/`; or, with ```dcl,error=CODE, fails
//! with that code; ```dcl,warn=declutter::world::ungraspable marks a block on which
//! `check` succeeds but warns that no robot can grasp some object. A library block (no target) is checked through a probe scenario that
//! `use`s it, so its URDFs and meshes are loaded too. ```dcl,link=NAME:DIR checks the
//! block with `NAME` pointing at DIR (relative to the repository) instead of
//! `examples/NAME`, and is skipped, with the reason printed, when DIR is absent.
//! The language reference covers every construct and lists every diagnostic code.

use std::path::{Path, PathBuf};

use declutter::diag::{render_all, FsLoader, RenderOptions, SourceMap};
use declutter::resolve;

struct Block {
    page: String,
    line: usize,
    text: String,
    error: Option<String>,
    warn: Option<String>,
    link: Option<(String, String)>,
}

/// Expands mdbook's `{{#include PATH}}` (relative to the page) in a block.
fn expand(page_dir: &Path, text: &str) -> String {
    text.lines()
        .map(|line| match line.trim().strip_prefix("{{#include ").and_then(|r| r.strip_suffix("}}")) {
            Some(path) => std::fs::read_to_string(page_dir.join(path.trim())).unwrap(),
            None => format!("{line}\n"),
        })
        .collect()
}

fn blocks() -> Vec<Block> {
    let mut out = Vec::new();
    let mut pages: Vec<PathBuf> = std::fs::read_dir("book/src")
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    pages.sort();
    for page in pages {
        let md = std::fs::read_to_string(&page).unwrap();
        let mut current: Option<Block> = None;
        for (i, line) in md.lines().enumerate() {
            match (&mut current, line.strip_prefix("```")) {
                (None, Some(info)) if info.split(',').next() == Some("dcl") => {
                    let error = info.split(',').find_map(|p| p.strip_prefix("error=")).map(str::to_string);
                    let warn = info.split(',').find_map(|p| p.strip_prefix("warn=")).map(str::to_string);
                    let link = info.split(',').find_map(|p| p.strip_prefix("link=")).map(|l| {
                        let (name, dir) = l.split_once(':').expect("link=NAME:DIR");
                        (name.to_string(), dir.to_string())
                    });
                    current = Some(Block {
                        page: page.display().to_string(),
                        line: i + 1,
                        text: String::new(),
                        error,
                        warn,
                        link,
                    });
                }
                (Some(_), Some("")) => {
                    let mut b = current.take().unwrap();
                    b.text = expand(page.parent().unwrap(), &b.text);
                    out.push(b);
                }
                (Some(b), _) => {
                    b.text.push_str(line);
                    b.text.push('\n');
                }
                (None, _) => {}
            }
        }
        assert!(current.is_none(), "unclosed dcl block in {}", page.display());
    }
    out
}

/// A scratch folder that looks like `examples/`: a symbolic link to every entry of
/// `examples/` (or to the block's `link=` target), so that relative paths in a block
/// resolve as they would next to the shipped scenarios. Removed on drop.
struct Scratch(PathBuf);

impl Scratch {
    fn new(n: usize, link: Option<&(String, String)>) -> Scratch {
        let root = std::env::current_dir().unwrap();
        let dir = root.join("target").join(format!("book-blocks-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for e in std::fs::read_dir(root.join("examples")).unwrap().flatten() {
            if link.is_some_and(|(name, _)| e.file_name() == name.as_str()) {
                continue;
            }
            std::os::unix::fs::symlink(e.path(), dir.join(e.file_name())).unwrap();
        }
        if let Some((name, target)) = link {
            std::os::unix::fs::symlink(root.join(target), dir.join(name)).unwrap();
        }
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs `declutter check`'s pipeline on `file`: Ok with the warnings `check` would print
/// (objects no robot can grasp), or the rendered report and the codes.
fn full_check(file: &Path, dir: &Path) -> Result<Vec<String>, (String, Vec<String>)> {
    let mut sources = SourceMap::new();
    let summary = match resolve::check(file, &FsLoader, &mut sources) {
        Ok(s) => s,
        Err(errs) => {
            let codes = errs.iter().map(|e| e.code_str()).collect();
            return Err((render_all(&sources, &errs, RenderOptions::plain()), codes));
        }
    };
    // A library is checked through a probe scenario that uses it and adds a target (and
    // an arm, when it has none, so that its hands are attached to something).
    let root = if summary.library {
        let probe = dir.join("__probe.dcl");
        let mut text = format!("use \"{}\"\n", file.file_name().unwrap().to_str().unwrap());
        if summary.robots == 0 {
            text.push_str("robot __probe_arm { urdf \"robots/planar3.urdf\" base at (20m, 20m, 0) home [0, 0, 0] }\n");
        }
        text.push_str("object __probe sphere(radius: 1cm) at (30m, 30m, 30m)\ntarget __probe\n");
        std::fs::write(&probe, text).unwrap();
        probe
    } else {
        file.to_path_buf()
    };
    let mut sources = SourceMap::new();
    let scn = match resolve::resolve(&root, &FsLoader, &mut sources) {
        Ok(s) => s,
        Err(errs) => {
            let codes = errs.iter().map(|e| e.code_str()).collect();
            return Err((render_all(&sources, &errs, RenderOptions::plain()), codes));
        }
    };
    let w = match declutter::world::build(&scn, &declutter::world::WorldOptions::default(), &FsLoader) {
        Ok(w) => w,
        Err(errs) => {
            let codes =
                errs.iter().map(|e| miette::Diagnostic::code(e).map(|c| c.to_string()).unwrap_or_default()).collect();
            return Err((render_all(&sources, &errs, RenderOptions::plain()), codes));
        }
    };
    let report = declutter::world::report(&w);
    let unreachable: Vec<String> =
        report.unreachable().filter(|o| o.name != "__probe").map(|o| o.name.clone()).collect();
    Ok(unreachable)
}

#[test]
fn every_dcl_block_checks() {
    let blocks = blocks();
    assert!(blocks.len() >= 15, "only {} dcl blocks", blocks.len());
    let mut failures = Vec::new();
    for (n, b) in blocks.iter().enumerate() {
        if let Some((_, target)) = &b.link {
            if !Path::new(target).is_dir() {
                eprintln!("{}:{}: skipped: {target} is absent (the block needs it)", b.page, b.line);
                continue;
            }
        }
        let scratch = Scratch::new(n, b.link.as_ref());
        let file = scratch.0.join("__book_block.dcl");
        std::fs::write(&file, &b.text).unwrap();
        match (&b.error, full_check(&file, &scratch.0)) {
            (None, Ok(unreachable)) => {
                let expected = b.warn.as_deref() == Some("declutter::world::ungraspable");
                if unreachable.is_empty() == expected {
                    failures.push(format!(
                        "{}:{}: no robot can grasp {unreachable:?} (`check` warns declutter::world::ungraspable); \
                         the block must say warn=declutter::world::ungraspable exactly when it does",
                        b.page, b.line
                    ));
                }
            }
            (None, Err((report, _))) => {
                failures.push(format!("{}:{}: block should check, got:\n{report}", b.page, b.line))
            }
            (Some(code), Ok(_)) => failures.push(format!("{}:{}: block should fail with {code}", b.page, b.line)),
            (Some(code), Err((report, codes))) => {
                if !codes.contains(code) {
                    failures.push(format!("{}:{}: expected {code}, got {codes:?}:\n{report}", b.page, b.line));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn reference_covers_every_construct() {
    let checked: String = blocks().into_iter().filter(|b| b.error.is_none()).map(|b| b.text).collect();
    let constructs = [
        "//",
        "scenario ",
        "use ",
        "hand ",
        "robot ",
        "urdf ",
        "tcp at",
        "base at",
        "flange ",
        "home [",
        "drop [",
        "open [",
        "closed [",
        " width ",
        "allow_contact ",
        "fixed ",
        "object ",
        "box(",
        "cylinder(",
        "capsule(",
        "sphere(",
        "mesh(",
        "scale (",
        "scale 0",
        "grasp ",
        "approach ",
        "repeat ",
        "about z",
        " for ",
        "target ",
        " at [",
        "rot (",
        "planner {",
        "seed ",
        "max_samples ",
        "resolution ",
        "objective fewest_vertices",
        "time_budget ",
        "neighbours ",
        "first_path ",
        "acceleration ",
        "speed ",
        "radius:",
        "length:",
        "x:",
        "m,",
        "cm",
        "mm",
        "deg",
        "rad",
        "ms",
    ];
    for c in constructs {
        assert!(checked.contains(c), "no checked book block shows `{c}`");
    }
}

#[test]
fn reference_lists_every_diagnostic_code() {
    let reference = std::fs::read_to_string("book/src/language-reference.md").unwrap();
    let mut n = 0;
    for src in ["src/syntax/error.rs", "src/resolve/error.rs"] {
        let text = std::fs::read_to_string(src).unwrap();
        for part in text.split("code(").skip(1) {
            let code: String = part.chars().take_while(|c| *c != ')' && *c != ',').collect();
            if !code.starts_with("declutter::") {
                continue;
            }
            assert!(reference.contains(&format!("`{code}`")), "{code} is not in the language reference");
            n += 1;
        }
    }
    assert!(n >= 25);
}

/// Tutorial 3 shows the graph of `examples/box_lid.dcl` from a committed DOT file, as
/// text, inside an `<object>` that shows the SVG `book/tools/render_graph.sh` draws into
/// the untracked `figures/generated/` when Graphviz is present. The DOT must be what
/// `declutter graph` prints today, and the script must write no tracked file unless it
/// changed.
#[test]
fn tutorial_3_graph_is_current() {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(Path::new("examples/box_lid.dcl"), &FsLoader, &mut sources)
        .expect("box_lid resolves");
    let w = declutter::world::build(&scn, &declutter::world::WorldOptions::default(), &FsLoader)
        .expect("box_lid world builds");
    let planned = declutter::driver::plan_verified(&w, &|_| {}).expect("box_lid verifies");
    let dot = declutter::schedule::to_dot(w.scenario(), &planned.solution);
    let committed = std::fs::read_to_string("book/src/figures/box_lid_graph.dot").expect("figure exists");
    assert_eq!(committed, dot, "book/src/figures/box_lid_graph.dot is stale: run book/tools/render_graph.sh");
    let fragment = std::fs::read_to_string("book/src/figures/box_lid_graph.md").expect("fragment exists");
    assert_eq!(fragment, format!("```dot\n{dot}```\n"), "book/src/figures/box_lid_graph.md is stale");
    let page = std::fs::read_to_string("book/src/reading-the-graph.md").unwrap();
    let object = page.find("<object data=\"figures/generated/box_lid_graph.svg\"").expect("the page shows the SVG");
    let include = page.find("{{#include figures/box_lid_graph.md}}").expect("the page falls back to the DOT text");
    let close = page.find("</object>").expect("the fallback is inside the <object>");
    assert!(object < include && include < close);
    let script = std::fs::read_to_string("book/tools/render_graph.sh").unwrap();
    assert!(script.contains("dot -Tsvg \"$gen/box_lid_graph.dot\" > \"$gen/box_lid_graph.svg\""), "{script}");
    assert!(script.contains("cmp -s"), "tracked figures are rewritten only when they changed");
    let ignore = std::fs::read_to_string(".gitignore").unwrap();
    assert!(ignore.lines().any(|l| l == "/book/src/figures/generated/"), "the generated SVG is not tracked");
}

/// The schedule format page has a row for every key `compile` writes: top level, an
/// action, a trajectory, one of its points and an event.
#[test]
#[cfg_attr(debug_assertions, ignore = "slow in debug; run with --release")]
fn the_schedule_format_page_names_every_key_compile_writes() {
    // cans_3 for two arms at once; gripper for the finger keys a rigid hand leaves out.
    for example in ["examples/cans_3.dcl", "examples/gripper.dcl"] {
        let mut sources = SourceMap::new();
        let scn = resolve::resolve(Path::new(example), &FsLoader, &mut sources).expect("resolves");
        let w = declutter::world::build(&scn, &declutter::world::WorldOptions::default(), &FsLoader).expect("builds");
        let planned = declutter::driver::plan_verified(&w, &|_| {}).expect("verifies");
        let json: serde_json::Value =
            serde_json::from_str(&declutter::schedule::to_json(&planned.schedule).expect("json")).expect("parses");
        let page = std::fs::read_to_string("book/src/schedule-format.md").expect("the page");
        let parts = [
            ("top level", &json),
            ("an action", &json["actions"][0]),
            ("a trajectory", &json["trajectories"][0]),
            ("a trajectory point", &json["trajectories"][0]["points"][0]),
            ("an event", &json["events"][0]),
        ];
        for (what, v) in parts {
            let keys = v.as_object().unwrap_or_else(|| panic!("{what} is a map"));
            for key in keys.keys() {
                let named = page.contains(&format!("| `{key}` |"))
                    || (what == "a trajectory point" && page.contains("`{t, q, qd}`"));
                assert!(named, "book/src/schedule-format.md has no row for `{key}` of {what} ({example})");
            }
        }
    }
}
