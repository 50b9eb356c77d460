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

/// Every example scenario, read once: the seeds for mutation.
fn examples() -> &'static [(String, Vec<u8>)] {
    static EXAMPLES: std::sync::OnceLock<Vec<(String, Vec<u8>)>> = std::sync::OnceLock::new();
    EXAMPLES.get_or_init(|| {
        let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir("examples")
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|x| x == "dcl"))
            .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
            .collect();
        v.sort();
        assert!(v.len() >= 10, "the examples are the fuzz seeds");
        v
    })
}

fn loader(root: &[u8]) -> MemLoader {
    let mut l = MemLoader::new();
    for (name, bytes) in examples() {
        l.insert(Path::new("examples").join(name), bytes.clone());
    }
    for f in ["robots/tx90.urdf", "robots/planar3.urdf", "hands/sah.urdf", "hands/sdh2.urdf", "meshes/bracket.stl"] {
        let p = Path::new("examples").join(f);
        l.insert(&p, std::fs::read(&p).unwrap());
    }
    l.insert("examples/fuzz.dcl", root.to_vec());
    l
}

/// Runs parse + resolve + check + rendering and checks every span lies in its file.
fn exercise(bytes: &[u8]) {
    exercise_once(bytes);
    // Random bytes are rarely UTF-8, and the loader stops at the first bad byte; the
    // lossy text gets the same bytes through to the parser and resolver.
    if std::str::from_utf8(bytes).is_err() {
        exercise_once(String::from_utf8_lossy(bytes).as_bytes());
    }
}

fn exercise_once(bytes: &[u8]) {
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
    /// A run of one character: very long names, numbers, strings, nesting.
    Run(usize, u8, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 0usize..40).prop_map(|(a, n)| Edit::Delete(a, n)),
        (any::<usize>(), proptest::collection::vec(any::<u8>(), 0..8)).prop_map(|(a, b)| Edit::Insert(a, b)),
        (any::<usize>(), 0usize..60).prop_map(|(a, n)| Edit::Duplicate(a, n)),
        (any::<usize>(), any::<usize>(), 0usize..30).prop_map(|(a, b, n)| Edit::Swap(a, b, n)),
        (any::<usize>(), 0..TOKENS.len()).prop_map(|(a, t)| Edit::Token(a, t)),
        (any::<usize>(), prop::sample::select(&b"a9(\"{[.e_-"[..]), 1usize..3000)
            .prop_map(|(a, c, n)| Edit::Run(a, c, n)),
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
            Edit::Run(a, c, n) => {
                let a = (a % len).min(v.len());
                v.splice(a..a, std::iter::repeat_n(*c, *n));
            }
        }
    }
    v
}

proptest! {
    // Sized to run in a few seconds in release on two cores.
    #![proptest_config(ProptestConfig { cases: 1000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..4000)) {
        exercise(&bytes);
    }

    #[test]
    fn mutated_examples_never_panic(which in any::<prop::sample::Index>(), edits in proptest::collection::vec(edit(), 1..6)) {
        let (_, base) = which.get(examples());
        exercise(&apply(base.clone(), &edits));
    }

    #[test]
    fn token_soup_never_panics(toks in proptest::collection::vec(0..TOKENS.len(), 0..600)) {
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

/// A very long name and a misspelling of it: the did-you-mean search once built a
/// len x len table here (80 GB for 100k characters) and aborted.
#[test]
fn long_names_are_cheap() {
    let started = std::time::Instant::now();
    for n in [300, 15_000, 100_000] {
        let name = "a".repeat(n);
        let typo = format!("{}b", &name[1..]);
        let text = format!("use \"cell.dcl\"\nobject {name} sphere(radius: 1cm)\ntarget {typo}\n");
        exercise(text.as_bytes());
        let mut sources = SourceMap::new();
        let errs =
            resolve::resolve(Path::new("examples/fuzz.dcl"), &loader(text.as_bytes()), &mut sources).unwrap_err();
        let codes: Vec<String> = errs.iter().map(|e| e.code_str()).collect();
        assert!(codes.contains(&"declutter::resolve::out_of_range".to_string()), "{codes:?}");
        assert!(codes.contains(&"declutter::resolve::unknown_name".to_string()), "{codes:?}");
    }
    assert!(started.elapsed().as_secs_f64() < 5.0, "took {:?}", started.elapsed());
}
