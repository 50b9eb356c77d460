//! Quantities -> SI numbers. A bare number is metres, radians or seconds by context.

use super::ResolveError;
use crate::syntax::ast::Quantity;
use crate::syntax::did_you_mean;

/// Largest length anywhere in a scenario (metres). A robot cell is a few metres across.
pub const MAX_LENGTH: f64 = 100.0;
/// Smallest size or radius (metres): 0.01 mm. Below it a value is surely a unit slip,
/// and collision checking at that scale is meaningless.
pub const MIN_SIZE: f64 = 1e-5;
/// Largest angle written anywhere (radians): a few turns either way.
pub const MAX_ANGLE: f64 = 100.0;
/// Largest angle that may be written without a unit: a bare `90` is surely meant as degrees.
pub const MAX_BARE_ANGLE: f64 = std::f64::consts::TAU;
/// A bare length beyond this (metres) is warned of: a size in mm or cm without its unit.
pub const BARE_LENGTH_WARN: f64 = 10.0;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Length,
    Angle,
    Time,
    /// Joint acceleration: rad/s² (taken as m/s² on a prismatic joint).
    Acceleration,
    Count,
}

impl Kind {
    fn article(self) -> &'static str {
        match self {
            Kind::Length => "a length",
            Kind::Angle => "an angle",
            Kind::Time => "a duration",
            Kind::Acceleration => "an acceleration",
            Kind::Count => "a plain number",
        }
    }
    fn units(self) -> &'static str {
        match self {
            Kind::Length => "m, cm or mm",
            Kind::Angle => "deg or rad",
            Kind::Time => "s or ms",
            Kind::Acceleration => "rad/s2 or deg/s2",
            Kind::Count => "no unit",
        }
    }
}

const UNITS: [(&str, Kind, f64); 9] = [
    ("m", Kind::Length, 1.0),
    ("cm", Kind::Length, 0.01),
    ("mm", Kind::Length, 0.001),
    ("deg", Kind::Angle, std::f64::consts::PI / 180.0),
    ("rad", Kind::Angle, 1.0),
    ("s", Kind::Time, 1.0),
    ("ms", Kind::Time, 0.001),
    ("rad/s2", Kind::Acceleration, 1.0),
    ("deg/s2", Kind::Acceleration, std::f64::consts::PI / 180.0),
];

/// The value of `q` in SI units, checking that its unit is of kind `want` and that it is finite.
pub fn convert(q: &Quantity, want: Kind) -> Result<f64, ResolveError> {
    if !q.value.is_finite() {
        return Err(ResolveError::NotFinite { span: q.span });
    }
    let factor = match &q.unit {
        None => 1.0,
        Some(u) => {
            let Some((_, kind, factor)) = UNITS.iter().find(|(n, _, _)| *n == u.name) else {
                let names: Vec<&str> = UNITS.iter().map(|(n, _, _)| *n).collect();
                let help = match did_you_mean(&u.name, names.iter().copied()) {
                    Some(s) => format!("did you mean `{s}`? Units are m, cm, mm, deg, rad (and s, ms for times)"),
                    None => "units are m, cm, mm for lengths and deg, rad for angles (s, ms for times)".to_string(),
                };
                return Err(ResolveError::UnknownUnit { unit: u.name.clone(), span: u.span, help });
            };
            if *kind != want {
                return Err(ResolveError::UnitMismatch {
                    expected: want.article(),
                    found: format!("{} ({})", kind.article(), u.name),
                    span: q.span,
                    help: Some(format!("{} is written in {}", want.article(), want.units())),
                });
            }
            *factor
        }
    };
    let v = q.value * factor;
    if want == Kind::Angle && q.unit.is_none() && v.abs() > MAX_BARE_ANGLE {
        return Err(ResolveError::BareAngle {
            value: written(q),
            span: q.span,
            help: format!(
                "did you mean `{}deg`? A bare angle is in radians; write `deg` or `rad` to say which",
                written(q)
            ),
        });
    }
    let limit = match want {
        Kind::Length => MAX_LENGTH,
        Kind::Angle => MAX_ANGLE,
        _ => f64::INFINITY,
    };
    if v.abs() > limit {
        return Err(ResolveError::OutOfRange {
            what: want.article().to_string(),
            limit: format!("at most {limit} {} in size", if want == Kind::Length { "m" } else { "rad" }),
            value: written(q),
            span: q.span,
            help: Some("declutter rejects absurd quantities; check the unit".to_string()),
        });
    }
    Ok(v)
}

/// A length that must be strictly positive (sizes, radii).
pub fn positive_length(q: &Quantity, what: &str) -> Result<f64, ResolveError> {
    let v = convert(q, Kind::Length)?;
    if v <= 0.0 {
        return Err(ResolveError::OutOfRange {
            what: what.to_string(),
            limit: "greater than zero".to_string(),
            value: written(q),
            span: q.span,
            help: Some("sizes are full extents and radii are radii: both must be positive".to_string()),
        });
    }
    if v < MIN_SIZE {
        return Err(ResolveError::OutOfRange {
            what: what.to_string(),
            limit: "at least 0.01mm".to_string(),
            value: written(q),
            span: q.span,
            help: Some("declutter rejects sizes below 0.01mm (1e-5 m) as absurd; check the unit".to_string()),
        });
    }
    Ok(v)
}

/// A finite number without unit (a quaternion component).
pub fn plain(q: &Quantity, what: &str) -> Result<f64, ResolveError> {
    if let Some(u) = &q.unit {
        return Err(ResolveError::UnitMismatch {
            expected: "a plain number",
            found: format!("the unit `{}`", u.name),
            span: q.span,
            help: Some(format!("{what} takes no unit")),
        });
    }
    if !q.value.is_finite() {
        return Err(ResolveError::NotFinite { span: q.span });
    }
    Ok(q.value)
}

/// The warning for a length written without a unit and larger than [`BARE_LENGTH_WARN`].
pub fn bare_length_warning(q: &Quantity) -> Option<super::ResolveWarning> {
    (q.unit.is_none() && q.value.is_finite() && q.value.abs() > BARE_LENGTH_WARN).then(|| {
        let w = written(q);
        super::ResolveWarning::LargeBareLength {
            help: format!("did you mean `{w}mm` or `{w}cm`? A bare length is in metres"),
            value: w,
            span: q.span,
        }
    })
}

/// A whole number without unit in `lo..=hi`.
pub fn integer(q: &Quantity, what: &str, lo: u64, hi: u64) -> Result<u64, ResolveError> {
    if let Some(u) = &q.unit {
        return Err(ResolveError::UnitMismatch {
            expected: "a plain number",
            found: format!("the unit `{}`", u.name),
            span: q.span,
            help: Some(format!("{what} is a count and takes no unit")),
        });
    }
    let text = q.number.strip_prefix('+').unwrap_or(&q.number);
    // `1e2` is the whole number 100; only the spelling differs.
    let whole = (q.value.fract() == 0.0 && q.value >= 0.0 && q.value <= u64::MAX as f64).then_some(q.value as u64);
    let n = match text.parse::<u64>().ok().or(whole) {
        Some(n) => n,
        None => {
            if !q.value.is_finite() {
                return Err(ResolveError::NotFinite { span: q.span });
            }
            if q.value < 0.0 || (q.value.fract() == 0.0 && q.value > hi as f64) {
                return Err(ResolveError::OutOfRange {
                    what: what.to_string(),
                    limit: format!("between {lo} and {hi}"),
                    value: written(q),
                    span: q.span,
                    help: None,
                });
            }
            return Err(ResolveError::NotInteger { what: what.to_string(), value: written(q), span: q.span });
        }
    };
    if n < lo || n > hi {
        return Err(ResolveError::OutOfRange {
            what: what.to_string(),
            limit: format!("between {lo} and {hi}"),
            value: written(q),
            span: q.span,
            help: None,
        });
    }
    Ok(n)
}

/// The quantity as the user wrote it.
pub fn written(q: &Quantity) -> String {
    // A 300-digit literal is shown by its value: the span already points at the text.
    let number = if q.number.len() > 24 && q.value.is_finite() { format!("{:e}", q.value) } else { q.number.clone() };
    match &q.unit {
        Some(u) => format!("{number}{}", u.name),
        None => number,
    }
}
