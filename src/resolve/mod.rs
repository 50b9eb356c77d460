//! Resolve: spanned AST -> typed [`Scenario`].
//!
//! In: the root file's path and a [`Loader`]. Out: a [`Scenario`] in which names are
//! ids, quantities are SI (metres, radians, seconds), `use` files are inlined, poses
//! are in the world frame and grasp `repeat`s are expanded — or every independent
//! error found, sorted by position. Files read are added to the [`SourceMap`].
//!
//! `scenario` and `target` belong to the root file; a used file that has them is an
//! error. A file without `scenario` and `target` is a *library* (like a cell file):
//! [`check`] accepts it, [`resolve`] reports the missing target.

mod error;
mod load;
mod lower;
mod scenario;
mod units;
mod yaml;

pub use error::{ResolveError, ResolveWarning};
pub use scenario::*;
pub use yaml::{to_yaml, to_yaml_with_joints, JointInfo};

use std::path::Path;

use crate::diag::{Loader, SourceMap};

/// Parses and resolves the scenario at `root` and every file it uses.
pub fn resolve(root: &Path, loader: &dyn Loader, sources: &mut SourceMap) -> Result<Scenario, Vec<ResolveError>> {
    resolve_with_warnings(root, loader, sources).map(|(s, _)| s)
}

/// Like [`resolve`], with the warnings of a valid scenario (for the CLI to print).
pub fn resolve_with_warnings(
    root: &Path,
    loader: &dyn Loader,
    sources: &mut SourceMap,
) -> Result<(Scenario, Vec<ResolveWarning>), Vec<ResolveError>> {
    let (partial, errors) = run(root, loader, sources);
    let Some(mut p) = partial else { return Err(errors) };
    let warnings = std::mem::take(&mut p.warnings);
    finish(root, p, errors).map(|s| (s, warnings))
}

/// What `check` found in a valid file.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The `scenario` name, if any.
    pub name: Option<String>,
    /// True for a file with neither `scenario` nor `target` (a cell or other shared file).
    pub library: bool,
    pub robots: usize,
    pub objects: usize,
    pub fixed: usize,
    pub grasps: usize,
    /// Valid but suspicious: for `check` to print (it still succeeds).
    pub warnings: Vec<ResolveWarning>,
    /// What `check` builds a world from: the resolved scenario, or for a library with a
    /// robot a stand-in whose target is its first robot's home, so that URDFs, meshes and
    /// joint vectors are checked before a scenario uses the file. `None` for a library
    /// without robots.
    pub scenario: Option<Box<Scenario>>,
}

/// Like [`resolve`], but a file with neither `scenario` nor `target` is accepted as a library.
pub fn check(root: &Path, loader: &dyn Loader, sources: &mut SourceMap) -> Result<Summary, Vec<ResolveError>> {
    let (partial, errors) = run(root, loader, sources);
    let Some(mut p) = partial else { return Err(errors) };
    let mut warnings = std::mem::take(&mut p.warnings);
    let root_file = Some(p.anchor.file);
    let errors = drop_follow_ons(errors);
    if p.name.is_none() && p.target.is_none() {
        if !errors.is_empty() {
            return Err(sorted(errors));
        }
        // A library the user ran directly that declares objects of its own was most
        // likely meant as a scenario whose `target` was forgotten.
        let own_object = p.objects.iter().map(|o| o.body.span).find(|s| Some(s.file) == root_file);
        warnings.extend(own_object.map(|span| ResolveWarning::ObjectsWithoutTarget { span }));
        let target =
            p.robots.first().map(|r| Target::Config { robot: RobotId(0), q: r.home.clone(), span: r.home.span });
        let stand_in = Scenario {
            name: None,
            root: root.to_path_buf(),
            hands: p.hands,
            robots: p.robots,
            fixed: p.fixed,
            objects: p.objects,
            // Replaced below when there is a robot; without one nothing is built.
            target: Target::Object { object: ObjectId(0), span: p.anchor },
            planner: p.planner,
        };
        let mut summary = summarize(&stand_in, true, warnings);
        summary.scenario = target.map(|target| Box::new(Scenario { target, ..stand_in }));
        return Ok(summary);
    }
    let s = finish(root, p, errors)?;
    let mut summary = summarize(&s, false, warnings);
    summary.scenario = Some(Box::new(s));
    Ok(summary)
}

/// The counts `check` prints, without the scenario.
fn summarize(s: &Scenario, library: bool, warnings: Vec<ResolveWarning>) -> Summary {
    Summary {
        name: s.name.clone(),
        library,
        warnings,
        robots: s.robots.len(),
        objects: s.objects.len(),
        fixed: s.fixed.len(),
        grasps: s.objects.iter().map(|o| o.grasps.len()).sum(),
        scenario: None,
    }
}

/// True if some file could not be read or parsed in full: it would likely have declared
/// names, the robot or the target that now look missing.
fn incomplete(errors: &[ResolveError]) -> bool {
    errors.iter().any(|e| {
        matches!(
            e,
            ResolveError::Syntax(_)
                | ResolveError::Unreadable { .. }
                | ResolveError::NotUtf8 { .. }
                | ResolveError::UseCycle { .. }
                | ResolveError::MissingFile { what: "used", .. }
        )
    })
}

/// Without some file's declarations, "unknown name" and "wrong kind" errors are
/// mostly echoes of the real cause (a syntax error in cell.dcl makes every hand
/// unknown), and they would sort before it; drop them.
fn drop_follow_ons(mut errors: Vec<ResolveError>) -> Vec<ResolveError> {
    if incomplete(&errors) {
        errors.retain(|e| !matches!(e, ResolveError::UnknownName { .. } | ResolveError::WrongKind { .. }));
    }
    errors
}

fn finish(root: &Path, p: lower::Partial, errors: Vec<ResolveError>) -> Result<Scenario, Vec<ResolveError>> {
    let mut errors = drop_follow_ons(errors);
    let incomplete = incomplete(&errors);
    if p.robots.is_empty() && !incomplete {
        errors.push(ResolveError::NoRobot { span: p.anchor });
    }
    let quiet = incomplete
        || errors.iter().any(|e| {
            matches!(
                e,
                ResolveError::DuplicateTarget { .. }
                    | ResolveError::BadTarget { .. }
                    | ResolveError::UnknownName { .. }
                    | ResolveError::WrongKind { .. }
                    | ResolveError::JointCount { .. }
            )
        });
    match p.target {
        Some(target) if errors.is_empty() => Ok(Scenario {
            name: p.name,
            root: root.to_path_buf(),
            hands: p.hands,
            robots: p.robots,
            fixed: p.fixed,
            objects: p.objects,
            target,
            planner: p.planner,
        }),
        target => {
            if target.is_none() && !quiet {
                errors.push(ResolveError::MissingTarget { span: p.anchor });
            }
            Err(sorted(errors))
        }
    }
}

/// Loads and lowers; `None` when the root file itself could not be read.
fn run(root: &Path, loader: &dyn Loader, sources: &mut SourceMap) -> (Option<lower::Partial>, Vec<ResolveError>) {
    let mut errors = Vec::new();
    let loaded = load::load(root, loader, sources, &mut errors);
    if loaded.root.is_none() {
        return (None, errors);
    }
    let partial = lower::lower(&loaded.items, loaded.root, loader, sources, &mut errors);
    (Some(partial), errors)
}

fn sorted(mut errors: Vec<ResolveError>) -> Vec<ResolveError> {
    use crate::diag::Located;
    errors.sort_by_key(|e| e.primary_span());
    errors.dedup();
    errors
}
