//! The stages shared by `compile`, `graph` and `verify`: resolve the scenario and
//! build its world, rendering any error to stderr.

use std::path::Path;

use super::{GlobalOptions, EXIT_INPUT};
use miette::Diagnostic;

use crate::diag::{render_all, FsLoader, Located, RenderOptions, SourceMap};
use crate::resolve::{self, Scenario};
use crate::world::{self, World};

pub(super) fn render_options(g: &GlobalOptions) -> RenderOptions {
    RenderOptions { color: g.color, ..RenderOptions::plain() }
}

/// Prints diagnostics and a count to stderr; returns the input-error exit code.
pub(super) fn fail<E: Diagnostic + Located>(sources: &SourceMap, errs: &[E], g: &GlobalOptions) -> u8 {
    eprint!("{}", render_all(sources, errs, render_options(g)));
    let n = errs.len();
    eprintln!("error: {n} problem{} found", if n == 1 { "" } else { "s" });
    EXIT_INPUT
}

/// How many warnings of one code are printed before the rest are counted in one line.
pub(super) const WARNINGS_SHOWN_PER_CODE: usize = 3;

/// Prints warnings in order, but past [`WARNINGS_SHOWN_PER_CODE`] of one code (forty
/// ungraspable cans, thirty unread scene fields) only a count, unless `--verbose`.
pub(super) fn warn_grouped<W: Diagnostic + Located>(sources: &SourceMap, warnings: &[W], g: &GlobalOptions) {
    let code = |w: &W| w.code().map(|c| c.to_string()).unwrap_or_default();
    let mut shown: Vec<(String, usize)> = Vec::new();
    for w in warnings {
        let c = code(w);
        let n = match shown.iter_mut().find(|(k, _)| *k == c) {
            Some((_, n)) => {
                *n += 1;
                *n
            }
            None => {
                shown.push((c, 1));
                1
            }
        };
        if g.verbose || n <= WARNINGS_SHOWN_PER_CODE {
            eprint!("{}", crate::diag::render_one(sources, w, render_options(g)));
        }
    }
    for (c, n) in shown {
        if !g.verbose && n > WARNINGS_SHOWN_PER_CODE {
            let more = n - WARNINGS_SHOWN_PER_CODE;
            eprintln!(
                "note: {more} more `{c}` warning{} not shown (--verbose shows them)",
                if more == 1 { "" } else { "s" }
            );
        }
    }
}

/// A scenario resolved and its world built, with the sources for later reports.
pub(super) struct Loaded {
    pub sources: SourceMap,
    pub world: World,
}

/// Resolves `file` and builds its world; on failure the errors are already printed.
pub(super) fn load(file: &Path, g: &GlobalOptions, edit: impl FnOnce(&mut Scenario)) -> Result<Loaded, u8> {
    let mut sources = SourceMap::new();
    let (mut scn, warnings) =
        resolve::resolve_with_warnings(file, &FsLoader, &mut sources).map_err(|errs| fail(&sources, &errs, g))?;
    for w in &warnings {
        eprint!("{}", crate::diag::render_one(&sources, w, render_options(g)));
    }
    edit(&mut scn);
    let opts = g.world_options();
    let world = world::build(&scn, &opts, &FsLoader).map_err(|errs| fail(&sources, &errs, g))?;
    Ok(Loaded { sources, world })
}
