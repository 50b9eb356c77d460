//! `check` and `resolve`: the front end on the real file system, reports to stderr.

use std::path::Path;

use super::{GlobalOptions, EXIT_INPUT, EXIT_OK};
use crate::diag::{render_all, FsLoader, RenderOptions, SourceMap};
use crate::resolve;

fn options(g: &GlobalOptions) -> RenderOptions {
    RenderOptions { color: g.color, ..RenderOptions::plain() }
}

fn report(sources: &SourceMap, errs: &[resolve::ResolveError], g: &GlobalOptions) -> u8 {
    eprint!("{}", render_all(sources, errs, options(g)));
    let n = errs.len();
    eprintln!("error: {n} problem{} found", if n == 1 { "" } else { "s" });
    EXIT_INPUT
}

pub fn check(file: &Path, g: &GlobalOptions) -> u8 {
    let mut sources = SourceMap::new();
    match resolve::check(file, &FsLoader, &mut sources) {
        Ok(s) => {
            let plural = |n: usize, w: &str| format!("{n} {w}{}", if n == 1 { "" } else { "s" });
            let what = match (&s.name, s.library) {
                (_, true) => format!("{} (a library: no target)", file.display()),
                (Some(n), _) => n.clone(),
                (None, _) => file.display().to_string(),
            };
            eprintln!(
                "ok: {what} — {}, {}, {}, {}",
                plural(s.robots, "robot"),
                plural(s.objects, "object"),
                plural(s.fixed, "fixed body").replace("bodys", "bodies"),
                plural(s.grasps, "grasp")
            );
            EXIT_OK
        }
        Err(errs) => report(&sources, &errs, g),
    }
}

pub fn resolve(file: &Path, g: &GlobalOptions) -> u8 {
    let mut sources = SourceMap::new();
    match resolve::resolve(file, &FsLoader, &mut sources) {
        Ok(s) => {
            print!("{}", resolve::to_yaml(&s));
            EXIT_OK
        }
        Err(errs) => report(&sources, &errs, g),
    }
}
