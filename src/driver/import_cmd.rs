//! `declutter import moveit SCENE [--request R] [--cell C] [--removable RE] -o OUT`.
//!
//! Reads the files, builds the import's options from the cell (resolved as a library,
//! each robot's URDF loaded for its joint and link names), and writes the scenario and
//! its meshes only once the scenario is known to resolve: nothing is half-written.

use std::path::{Path, PathBuf};

use super::pipeline::{fail, render_options, warn_grouped};
use super::{GlobalOptions, EXIT_INPUT, EXIT_OK};
use crate::diag::{FsLoader, SourceMap};
use crate::import::{self, CellRobot, ImportError, ImportWarning};
use crate::{resolve, world};

/// Options of `declutter import moveit`.
#[derive(Clone, Debug)]
pub struct ImportOptions {
    pub scene: PathBuf,
    pub request: Option<PathBuf>,
    pub cell: Option<PathBuf>,
    pub removable: Option<String>,
    pub out: PathBuf,
}

pub fn import_moveit(o: &ImportOptions, g: &GlobalOptions) -> u8 {
    let mut sources = SourceMap::new();
    let read = |sources: &mut SourceMap, p: &Path| match std::fs::read_to_string(p) {
        Ok(t) => Ok(sources.add(p.display().to_string(), p, t)),
        Err(e) => Err(ImportError::Unreadable { path: p.display().to_string(), reason: e.to_string() }),
    };
    let scene = match read(&mut sources, &o.scene) {
        Ok(f) => f,
        Err(e) => return fail(&sources, &[e], g),
    };
    let request = match o.request.as_deref().map(|p| read(&mut sources, p)).transpose() {
        Ok(f) => f,
        Err(e) => return fail(&sources, &[e], g),
    };
    let removable = match o.removable.as_deref().map(regex::Regex::new).transpose() {
        Ok(r) => r,
        Err(e) => {
            let pattern = o.removable.clone().unwrap_or_default();
            return fail(&sources, &[ImportError::BadRegex { pattern, message: e.to_string() }], g);
        }
    };
    let mut warnings = Vec::new();
    let cell = match &o.cell {
        None => None,
        Some(path) => match load_cell(path, &mut sources, g, &mut warnings) {
            Ok(c) => Some(c),
            Err(code) => return code,
        },
    };
    let out_dir = match o.out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let stem = o.out.file_stem().map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned());
    let opts = import::Options {
        cell: cell.as_ref().map(|(s, r)| (s.as_ref(), r.as_slice())),
        removable: removable.as_ref(),
        out_dir: &out_dir,
        mesh_stem: &stem,
    };
    let imported = match import::moveit(&sources, scene, request, &opts) {
        Ok(i) => i,
        Err(errs) => return fail(&sources, &errs, g),
    };
    warnings.extend(imported.warnings);
    warn_grouped(&sources, &warnings, g);
    match write_all(&o.out, &out_dir, &imported.dcl, &imported.meshes, g) {
        Ok(()) => {
            eprintln!(
                "ok: wrote {} ({} mesh file{}, {} warning{})",
                o.out.display(),
                imported.meshes.len(),
                if imported.meshes.len() == 1 { "" } else { "s" },
                warnings.len(),
                if warnings.len() == 1 { "" } else { "s" }
            );
            EXIT_OK
        }
        Err(code) => code,
    }
}

type Cell = (Box<resolve::Scenario>, Vec<CellRobot>);

/// The cell resolved as a library, and each robot's joint and link names.
fn load_cell(
    path: &Path,
    sources: &mut SourceMap,
    g: &GlobalOptions,
    warnings: &mut Vec<ImportWarning>,
) -> Result<Cell, u8> {
    let summary = resolve::check(path, &FsLoader, sources).map_err(|errs| fail(sources, &errs, g))?;
    let Some(scn) = summary.scenario else {
        return Err(fail(sources, &[ImportError::CellWithoutRobot { path: path.display().to_string() }], g));
    };
    if !scn.objects.is_empty() {
        warnings.push(ImportWarning::CellObjects { count: scn.objects.len() });
    }
    let opts = g.world_options();
    let mut robots = Vec::new();
    let mut errs = Vec::new();
    for r in &scn.robots {
        match world::load_kinematics(&r.urdf, r.flange.as_ref(), &opts, &FsLoader) {
            Ok(k) => robots.push(CellRobot {
                joints: k.joint_names().to_vec(),
                links: k.link_names().into_iter().map(str::to_string).collect(),
            }),
            Err(e) => errs.extend(e),
        }
    }
    if !errs.is_empty() {
        return Err(fail(sources, &errs, g));
    }
    Ok((scn, robots))
}

/// Writes the meshes and the scenario under temporary names, checks that the scenario
/// resolves, then renames them into place; on any failure nothing is left behind.
fn write_all(out: &Path, dir: &Path, dcl: &str, meshes: &[import::MeshFile], g: &GlobalOptions) -> Result<(), u8> {
    let tmp = |p: &Path| {
        let mut name = p.file_name().map(|n| n.to_os_string()).unwrap_or_default();
        name.push(format!(".declutter-tmp-{}", std::process::id()));
        p.with_file_name(name)
    };
    let mut written: Vec<(PathBuf, PathBuf)> = Vec::new();
    let cleanup = |written: &[(PathBuf, PathBuf)]| {
        for (t, _) in written {
            let _ = std::fs::remove_file(t);
        }
    };
    let write_err = |p: &Path, e: std::io::Error| {
        fail(&SourceMap::new(), &[ImportError::Write { path: p.display().to_string(), reason: e.to_string() }], g)
    };
    for m in meshes {
        let dest = dir.join(&m.name);
        let t = tmp(&dest);
        if let Err(e) = std::fs::write(&t, &m.stl) {
            cleanup(&written);
            return Err(write_err(&dest, e));
        }
        written.push((t, dest));
    }
    // The scenario names its meshes by their final names: they are moved into place,
    // then the scenario, still under its temporary name in the same folder, is resolved.
    let t = tmp(out);
    if let Err(e) = std::fs::write(&t, dcl) {
        cleanup(&written);
        return Err(write_err(out, e));
    }
    written.push((t.clone(), out.to_path_buf()));
    for (t, dest) in &written[..written.len() - 1] {
        if let Err(e) = std::fs::rename(t, dest) {
            cleanup(&written);
            return Err(write_err(dest, e));
        }
    }
    let mut sources = SourceMap::new();
    if let Err(errs) = resolve::check(&t, &FsLoader, &mut sources) {
        let _ = std::fs::remove_file(&t);
        for (_, dest) in &written[..written.len() - 1] {
            let _ = std::fs::remove_file(dest);
        }
        eprint!("{}", crate::diag::render_all(&sources, &errs, render_options(g)));
        eprintln!(
            "error: internal: the imported scenario does not resolve; nothing written. Please report this scene."
        );
        return Err(EXIT_INPUT);
    }
    std::fs::rename(&t, out).map_err(|e| {
        let _ = std::fs::remove_file(&t);
        write_err(out, e)
    })
}
