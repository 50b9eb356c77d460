//! No input can panic the parser or the resolver: random bytes and random mutations of
//! the example files all end in `Ok` or in diagnostics whose spans lie inside their file.

use std::path::Path;

use proptest::prelude::*;

use declutter::diag::{FileId, Located, MemLoader, RenderOptions, SourceMap};
use declutter::resolve;
use declutter::syntax;

const TOKENS: &[&str] = &[
    "use",
    "\"cell.dcl\"",
    "\"box_lid.dcl\"",
    "scenario",
    "hand",
    "robot",
    "fixed",
    "object",
    "planner",
    "target",
    "grasp",
    "repeat",
    "about",
    "approach",
    "for",
    "at",
    "rot",
    "box",
    "cylinder",
    "capsule",
    "sphere",
    "mesh",
    "scale",
    "urdf",
    "tcp",
    "base",
    "home",
    "drop",
    "flange",
    "allow_contact",
    "(",
    ")",
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    "//",
    "\"",
    "\n",
    " ",
    "0",
    "-1",
    "1e999",
    "1e-400",
    "0.5cm",
    "90deg",
    "2rad",
    "3mm",
    "7s",
    "x",
    "z",
    "can",
    "lid",
    "r1",
    "sah",
    "sdh2",
    "table",
    "seed",
    "max_samples",
    "objective",
    "fewest_vertices",
    "#",
    "é",
    "\u{0}",
    "\\",
    "radius:",
    "length:",
    "100000",
    "0",
    "-0",
    "+",
    ".",
    "\"robots/tx90.urdf\"",
    "\"a.stl\"",
];

fn loader(root: &[u8]) -> MemLoader {
    let mut l = MemLoader::new();
    for f in ["cell.dcl", "box_lid.dcl", "robots/tx90.urdf", "hands/sah.urdf", "hands/sdh2.urdf"] {
        let p = Path::new("examples").join(f);
        l.insert(&p, std::fs::read(&p).unwrap());
    }
    l.insert("examples/fuzz.dcl", root.to_vec());
    l
}

/// Runs parse + resolve + check + rendering and checks every span lies in its file.
fn exercise(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    match syntax::parse(FileId(0), &text) {
        Err(errs) => {
            for e in &errs {
                let s = e.primary_span().unwrap();
                assert!(s.start <= s.end && s.end as usize <= text.len());
            }
        }
        Ok(file) => {
            // Declarations lie inside the file, in order, without overlapping.
            let mut last = 0;
            for item in &file.items {
                let s = item_span(item);
                assert!(last <= s.start && s.start <= s.end && s.end as usize <= text.len());
                last = s.end;
            }
        }
    }
    let l = loader(bytes);
    let mut sources = SourceMap::new();
    match resolve::resolve(Path::new("examples/fuzz.dcl"), &l, &mut sources) {
        Ok(s) => {
            let _ = resolve::to_yaml(&s);
        }
        Err(errs) => {
            assert!(!errs.is_empty());
            for e in &errs {
                if let Some(s) = e.primary_span() {
                    let f = sources.get(s.file).expect("span in a known file");
                    assert!(s.start <= s.end && s.end as usize <= f.text.len(), "{e}");
                }
            }
            let _ = declutter::driver::render_report(&sources, &errs, RenderOptions::plain());
        }
    }
    let mut sources = SourceMap::new();
    let _ = resolve::check(Path::new("examples/fuzz.dcl"), &l, &mut sources);
}

fn item_span(item: &syntax::ast::Item) -> declutter::diag::Span {
    use syntax::ast::Item;
    match item {
        Item::Scenario { span, .. } | Item::Use { span, .. } | Item::Planner { span, .. } => *span,
        Item::Hand(h) => h.span,
        Item::Robot(r) => r.span,
        Item::Body(b) => b.span,
        Item::Target(t) => t.span,
    }
}

#[derive(Debug, Clone)]
enum Edit {
    Delete(usize, usize),
    Insert(usize, Vec<u8>),
    Duplicate(usize, usize),
    Swap(usize, usize, usize),
    Token(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 0usize..40).prop_map(|(a, n)| Edit::Delete(a, n)),
        (any::<usize>(), proptest::collection::vec(any::<u8>(), 0..8)).prop_map(|(a, b)| Edit::Insert(a, b)),
        (any::<usize>(), 0usize..60).prop_map(|(a, n)| Edit::Duplicate(a, n)),
        (any::<usize>(), any::<usize>(), 0usize..30).prop_map(|(a, b, n)| Edit::Swap(a, b, n)),
        (any::<usize>(), 0..TOKENS.len()).prop_map(|(a, t)| Edit::Token(a, t)),
    ]
}

fn apply(mut v: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
    for e in edits {
        let len = v.len().max(1);
        match e {
            Edit::Delete(a, n) => {
                let a = a % len;
                let b = (a + n).min(v.len());
                if a < b {
                    v.drain(a..b);
                }
            }
            Edit::Insert(a, bytes) => {
                let a = (a % len).min(v.len());
                v.splice(a..a, bytes.iter().copied());
            }
            Edit::Duplicate(a, n) => {
                let a = (a % len).min(v.len());
                let b = (a + n).min(v.len());
                let chunk = v[a..b].to_vec();
                v.splice(b..b, chunk);
            }
            Edit::Swap(a, b, n) => {
                let (mut a, mut b) = ((a % len).min(v.len()), (b % len).min(v.len()));
                if a > b {
                    std::mem::swap(&mut a, &mut b);
                }
                let n = (*n).min(b - a).min(v.len() - b);
                for i in 0..n {
                    v.swap(a + i, b + i);
                }
            }
            Edit::Token(a, t) => {
                let a = (a % len).min(v.len());
                v.splice(a..a, TOKENS[*t].bytes());
            }
        }
    }
    v
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        exercise(&bytes);
    }

    #[test]
    fn mutated_examples_never_panic(which in 0usize..2, edits in proptest::collection::vec(edit(), 1..6)) {
        let base = std::fs::read(["examples/box_lid.dcl", "examples/cell.dcl"][which]).unwrap();
        exercise(&apply(base, &edits));
    }

    #[test]
    fn token_soup_never_panics(toks in proptest::collection::vec(0..TOKENS.len(), 0..60)) {
        let text: String = toks.iter().map(|t| TOKENS[*t]).collect::<Vec<_>>().join(" ");
        exercise(text.as_bytes());
    }
}

#[test]
fn deep_nesting_and_long_files_do_not_overflow() {
    for text in [
        format!("fixed a box{}", "(".repeat(100_000)),
        format!("planner {{ {} }}", "seed 1 ".repeat(20_000)),
        "{".repeat(100_000),
        format!("object o box(1,1,1) {{ {} }}", "grasp g at (0,0,0) ".repeat(5_000)),
        format!("// {}", "x".repeat(1_000_000)),
    ] {
        exercise(text.as_bytes());
    }
}
