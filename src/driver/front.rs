//! `check` and `resolve`: the front end on the real file system, reports to stderr.

use std::path::Path;

use super::{GlobalOptions, EXIT_INPUT, EXIT_OK};
use crate::diag::{render_all, FsLoader, RenderOptions, SourceMap};
use crate::resolve;

fn options(g: &GlobalOptions) -> RenderOptions {
    RenderOptions { color: g.color, ..RenderOptions::plain() }
}

fn report(sources: &SourceMap, errs: &[resolve::ResolveError], g: &GlobalOptions) -> u8 {
    eprint!("{}", render_report(sources, errs, options(g)));
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

/// Longest source line a graphical report is drawn for; miette cannot pad beyond
/// 65535 columns, so errors on longer lines are printed as `file:line:col: message`.
const MAX_DRAWN_LINE: usize = 10_000;

/// Renders errors like [`render_all`], falling back to one-line reports for labels on
/// absurdly long lines (which the graphical renderer cannot draw).
pub fn render_report(sources: &SourceMap, errs: &[resolve::ResolveError], opts: RenderOptions) -> String {
    use crate::diag::Located;
    use miette::Diagnostic;
    let drawable = |e: &resolve::ResolveError| {
        let Some(file) = e.primary_span().and_then(|s| sources.get(s.file)) else { return true };
        e.labels().into_iter().flatten().all(|l| {
            let at = l.offset().min(file.text.len());
            let start = file.text[..at].rfind('\n').map_or(0, |i| i + 1);
            let end = file.text[at..].find('\n').map_or(file.text.len(), |i| at + i);
            end - start <= MAX_DRAWN_LINE
        })
    };
    if errs.iter().all(drawable) {
        return render_all(sources, errs, opts);
    }
    let mut order: Vec<&resolve::ResolveError> = errs.iter().collect();
    order.sort_by_key(|e| e.primary_span());
    let mut out = String::new();
    for e in order {
        if drawable(e) {
            out.push_str(&crate::diag::render_one(sources, e, opts));
        } else {
            let place = e
                .primary_span()
                .and_then(|s| Some((sources.get(s.file)?.name.clone(), sources.line_col(s)?)))
                .map_or_else(String::new, |(n, (l, c))| format!("{n}:{l}:{c}: "));
            let code = e.code().map(|c| format!(" [{c}]")).unwrap_or_default();
            out.push_str(&format!("error{code}: {place}{e}\n"));
            if let Some(h) = e.help() {
                out.push_str(&format!("  help: {h}\n"));
            }
        }
        out.push('\n');
    }
    out
}
