//! `declutter verify FILE SCHEDULE`: read a schedule back and re-check it.

use std::path::Path;

use miette::Diagnostic;

use super::pipeline::{fail, load};
use super::{GlobalOptions, EXIT_INPUT, EXIT_OK};
use crate::diag::{Located, SourceMap, Span};
use crate::schedule::Schedule;
use crate::verify;

/// A schedule file that cannot be read as a schedule.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub enum ScheduleReadError {
    #[error("cannot read schedule `{path}`: {reason}")]
    #[diagnostic(code(declutter::verify::read))]
    Read { path: String, reason: String },
    #[error("`{path}` is not a valid schedule: {message}")]
    #[diagnostic(
        code(declutter::verify::parse),
        help("a schedule is what `declutter compile` writes, as YAML or JSON")
    )]
    Parse {
        path: String,
        message: String,
        #[label("here")]
        span: Option<Span>,
    },
}

impl Located for ScheduleReadError {
    fn primary_span(&self) -> Option<Span> {
        match self {
            ScheduleReadError::Read { .. } => None,
            ScheduleReadError::Parse { span, .. } => *span,
        }
    }
}

/// Reads and parses a schedule file; a parse error points into the text, which is added
/// to `sources` for the report.
pub(super) fn read_schedule(schedule_path: &Path, sources: &mut SourceMap) -> Result<Schedule, ScheduleReadError> {
    let path = schedule_path.display().to_string();
    let text = std::fs::read_to_string(schedule_path)
        .map_err(|e| ScheduleReadError::Read { path: path.clone(), reason: e.to_string() })?;
    parse_schedule(&text).map_err(|(message, at)| {
        let file_id = sources.add(path.clone(), schedule_path, text.clone());
        let span = at.and_then(|(l, c)| sources.offset_of(file_id, l, c)).map(|o| Span::new(file_id, o, o + 1));
        ScheduleReadError::Parse { path, message, span }
    })
}

/// Parses a schedule as JSON when it looks like JSON, else as YAML.
pub fn parse_schedule(text: &str) -> Result<Schedule, (String, Option<(u64, u64)>)> {
    if text.trim_start().starts_with('{') {
        serde_json::from_str(text).map_err(|e| (e.to_string(), Some((e.line() as u64, e.column() as u64))))
    } else {
        serde_saphyr::from_str(text).map_err(|e| {
            let at = e.location().map(|l| (l.line(), l.column()));
            (e.to_string().lines().next().unwrap_or("").to_string(), at)
        })
    }
}

pub fn verify(file: &Path, schedule_path: &Path, g: &GlobalOptions) -> u8 {
    let mut loaded = match load(file, g, |_| {}) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let path = schedule_path.display().to_string();
    let schedule = match read_schedule(schedule_path, &mut loaded.sources) {
        Ok(s) => s,
        Err(e) => return fail(&loaded.sources, &[e], g),
    };
    match verify::verify(&loaded.world, &schedule) {
        Ok(summary) => {
            eprintln!(
                "ok: {} verified — {} action{}, {} segments, {} configurations checked",
                path,
                summary.actions,
                if summary.actions == 1 { "" } else { "s" },
                summary.segments,
                summary.checks
            );
            EXIT_OK
        }
        Err(violations) => {
            for v in &violations {
                eprintln!("violation: {v}");
            }
            let n = violations.len();
            eprintln!("error: {path} is not valid: {n} violation{}", if n == 1 { "" } else { "s" });
            EXIT_INPUT
        }
    }
}
