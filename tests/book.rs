//! Every ```dcl block in the book passes `check` against the files in `examples/` (or,
//! with ```dcl,error=CODE, fails with that code); the language reference covers every
//! construct and lists every diagnostic code.

use std::path::{Path, PathBuf};

use declutter::diag::{MemLoader, SourceMap};
use declutter::resolve;

struct Block {
    page: String,
    line: usize,
    text: String,
    error: Option<String>,
}

fn add_dir(l: &mut MemLoader, dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            add_dir(l, &p);
        } else {
            l.insert(&p, std::fs::read(&p).unwrap());
        }
    }
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
                    current = Some(Block { page: page.display().to_string(), line: i + 1, text: String::new(), error });
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

#[test]
fn every_dcl_block_checks() {
    let blocks = blocks();
    assert!(blocks.len() >= 15, "only {} dcl blocks", blocks.len());
    let mut base = MemLoader::new();
    add_dir(&mut base, Path::new("examples"));
    for b in &blocks {
        let mut l = base.clone();
        let root = Path::new("examples/__book_block.dcl");
        l.insert(root, b.text.clone());
        let mut sources = SourceMap::new();
        let result = resolve::check(root, &l, &mut sources);
        match (&b.error, result) {
            (None, Ok(_)) => {}
            (None, Err(errs)) => panic!(
                "{}:{}: block should check, got:\n{}",
                b.page,
                b.line,
                declutter::diag::render_all(&sources, &errs, declutter::diag::RenderOptions::plain())
            ),
            (Some(code), Ok(_)) => panic!("{}:{}: block should fail with {code}", b.page, b.line),
            (Some(code), Err(errs)) => {
                let codes: Vec<String> = errs.iter().map(|e| e.code_str()).collect();
                assert!(codes.contains(code), "{}:{}: expected {code}, got {codes:?}", b.page, b.line);
            }
        }
    }
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
