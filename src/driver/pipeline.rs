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
