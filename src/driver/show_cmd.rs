//! `declutter show FILE [SCHEDULE] -o OUT.html`: the cell, and the schedule's replay, as
//! one self-contained HTML page.

use std::path::Path;

use miette::Diagnostic;

use super::pipeline::{fail, load};
use super::verify_cmd::read_schedule;
use super::{GlobalOptions, ShowOptions, EXIT_INPUT, EXIT_OK};
use crate::diag::{Located, Span};
use crate::verify::{self, ViolationKind};

/// The page cannot be written.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("cannot write `{path}`: {reason}")]
#[diagnostic(code(declutter::show::write), help("check that the folder exists and is writable"))]
pub struct WriteError {
    pub path: String,
    pub reason: String,
}

impl Located for WriteError {
    fn primary_span(&self) -> Option<Span> {
        None
    }
}

pub fn show(file: &Path, g: &GlobalOptions, o: &ShowOptions) -> u8 {
    let mut loaded = match load(file, g, |_| {}) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let mut schedule = None;
    let mut violations = Vec::new();
    if let Some(schedule_path) = &o.schedule {
        let path = schedule_path.display().to_string();
        let parsed = match read_schedule(schedule_path, &mut loaded.sources) {
            Ok(s) => s,
            Err(e) => return fail(&loaded.sources, &[e], g),
        };
        if let Err(found) = verify::verify(&loaded.world, &parsed) {
            // A schedule of another scenario or target would be drawn in the wrong cell.
            let foreign = |k: &ViolationKind| {
                matches!(k, ViolationKind::ScenarioMismatch { .. } | ViolationKind::TargetMismatch { .. })
            };
            if found.iter().any(|v| foreign(&v.kind)) {
                for v in found.iter().filter(|v| foreign(&v.kind)) {
                    eprintln!("violation: {v}");
                }
                eprintln!("error: {path} is not a schedule of this scenario; nothing written");
                return EXIT_INPUT;
            }
            for v in &found {
                eprintln!("violation: {v}");
            }
            let n = found.len();
            eprintln!(
                "warning: {path} does not verify ({n} violation{}); the page marks {} in red",
                if n == 1 { "" } else { "s" },
                if n == 1 { "it" } else { "them" }
            );
            violations = found;
        }
        schedule = Some(parsed);
    }
    let page = crate::show::show(&loaded.world, schedule.as_ref(), &violations);
    let out = o.out.display().to_string();
    if let Err(e) = std::fs::write(&o.out, page.as_bytes()) {
        return fail(&loaded.sources, &[WriteError { path: out, reason: e.to_string() }], g);
    }
    eprintln!("wrote {out} ({} kB); open it in a browser", page.len().div_ceil(1000));
    EXIT_OK
}
