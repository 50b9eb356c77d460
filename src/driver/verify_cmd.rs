//! `declutter verify FILE SCHEDULE`: read a schedule back and re-check it.

use std::path::Path;

use miette::Diagnostic;

use super::pipeline::{fail, load};
use super::{GlobalOptions, EXIT_INPUT, EXIT_OK};
use crate::diag::{Located, SourceMap, Span};
use crate::schedule::{Schedule, SCHEDULE_VERSION};
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
    #[error("`{path}` is a schedule of format version {found}; this declutter reads version {expected}")]
    #[diagnostic(
        code(declutter::verify::version),
        help("compile the scenario with this declutter to get a version {expected} schedule, or verify it with the declutter that wrote it")
    )]
    Version { path: String, found: String, expected: u32 },
}

impl Located for ScheduleReadError {
    fn primary_span(&self) -> Option<Span> {
        match self {
            ScheduleReadError::Read { .. } | ScheduleReadError::Version { .. } => None,
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
    if let Some(found) = foreign_version(&text) {
        return Err(ScheduleReadError::Version { path, found, expected: SCHEDULE_VERSION });
    }
    parse_schedule(&text).map_err(|(message, at)| {
        let file_id = sources.add(path.clone(), schedule_path, text.clone());
        let span = at.and_then(|(l, c)| sources.offset_of(file_id, l, c)).map(|o| Span::new(file_id, o, o + 1));
        ScheduleReadError::Parse { path, message, span }
    })
}

/// The `schedule_version` a text declares, read leniently (any other keys ignored), so
/// a schedule of another version is named as such rather than failing on its keys.
/// `None` when the text declares the supported version, or is not a mapping at all
/// (then the full parse reports what is wrong).
pub fn foreign_version(text: &str) -> Option<String> {
    #[derive(serde::Deserialize)]
    struct Probe {
        schedule_version: Option<serde_json::Value>,
    }
    let probe: Probe = if text.trim_start().starts_with('{') {
        serde_json::from_str(text).ok()?
    } else {
        serde_saphyr::from_str(text).ok()?
    };
    match probe.schedule_version {
        Some(serde_json::Value::Number(n)) if n.as_u64() == Some(u64::from(SCHEDULE_VERSION)) => None,
        Some(v) => Some(v.to_string()),
        None => Some("1 (no `schedule_version` key)".to_string()),
    }
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

/// Options of `declutter verify`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VerifyOptions {
    /// Distance (metres) every moving thing must keep (`--clearance`); 0: no contact.
    pub clearance: f64,
}

/// A `--clearance` value: a non-negative length, in `m`, `cm` or `mm` (bare numbers are metres).
pub fn parse_clearance(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let (number, scale) = [("mm", 1e-3), ("cm", 1e-2), ("m", 1.0)]
        .iter()
        .find_map(|(unit, scale)| t.strip_suffix(unit).map(|n| (n.trim(), *scale)))
        .unwrap_or((t, 1.0));
    match number.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v * scale),
        _ => Err(format!("`{text}` is not a length ≥ 0 (examples: 5mm, 0.5cm, 0.005m)")),
    }
}

pub fn verify(file: &Path, schedule_path: &Path, g: &GlobalOptions, o: &VerifyOptions) -> u8 {
    let mut loaded = match load(file, g, |_| {}) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let path = schedule_path.display().to_string();
    let schedule = match read_schedule(schedule_path, &mut loaded.sources) {
        Ok(s) => s,
        Err(e) => return fail(&loaded.sources, &[e], g),
    };
    let opts = verify::Options { clearance: o.clearance, ..verify::Options::default() };
    match verify::verify_with(&loaded.world, &schedule, &opts) {
        Ok(summary) => {
            eprintln!(
                "ok: {} verified — {} action{}, {:.3} s replayed at {} instants (between two of them no point moves more than {} mm, or nothing can come too close)",
                path,
                summary.actions,
                if summary.actions == 1 { "" } else { "s" },
                summary.makespan,
                summary.samples,
                verify::time::SAMPLE_BOUND * 1e3
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

#[cfg(test)]
mod tests {
    use super::parse_clearance;

    #[test]
    fn clearances_in_metres() {
        assert_eq!(parse_clearance("5mm"), Ok(0.005));
        assert_eq!(parse_clearance("0.5cm"), Ok(0.005));
        assert_eq!(parse_clearance("0.005"), Ok(0.005));
        assert_eq!(parse_clearance("2 m"), Ok(2.0));
        assert!(parse_clearance("-1mm").is_err());
        assert!(parse_clearance("5in").is_err());
        assert!(parse_clearance("NaNmm").is_err());
    }
}
