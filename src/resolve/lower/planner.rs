//! The `planner` block: known keys, typed values, defaults from [`PlannerSettings`].

use std::collections::HashMap;
use std::f64::consts::PI;

use super::Lower;
use crate::diag::{FileId, Span};
use crate::resolve::units::{convert, integer, written, Kind};
use crate::resolve::{Objective, PlannerSettings, ResolveError};
use crate::syntax::ast;
use crate::syntax::did_you_mean;

impl Lower<'_> {
    pub(super) fn planner(&mut self, entries: &[&ast::PlannerEntry]) -> PlannerSettings {
        const KEYS: [&str; 9] = [
            "seed",
            "max_samples",
            "resolution",
            "objective",
            "time_budget",
            "neighbours",
            "first_path",
            "acceleration",
            "speed",
        ];
        let mut p = PlannerSettings::default();
        // Within one file a key may appear once; a later file (the root, after its `use`)
        // may override a used file's setting.
        let mut seen: HashMap<(FileId, &str), Span> = HashMap::new();
        for e in entries {
            let key = e.key.name.as_str();
            if !KEYS.contains(&key) {
                let help = match did_you_mean(key, KEYS) {
                    Some(s) => format!("did you mean `{s}`?"),
                    None => format!("planner settings are {}", KEYS.join(", ")),
                };
                self.errors.push(ResolveError::UnknownPlannerKey { key: key.to_string(), span: e.key.span, help });
                continue;
            }
            if let Some(first) = seen.get(&(e.span.file, key)) {
                self.errors.push(ResolveError::DuplicateStatement {
                    what: key.to_string(),
                    span: e.span,
                    first: *first,
                });
                continue;
            }
            seen.insert((e.span.file, key), e.span);
            let bad = |expected: &str, help: Option<String>| ResolveError::BadPlannerValue {
                key: key.to_string(),
                expected: expected.to_string(),
                span: e.value.span(),
                help,
            };
            match (key, &e.value) {
                ("seed", ast::Value::Quantity(q)) => {
                    if let Some(v) = self.ok(integer(q, "`seed`", 0, u64::MAX)) {
                        p.seed = v;
                    }
                }
                ("max_samples", ast::Value::Quantity(q)) => {
                    if let Some(v) = self.ok(integer(q, "`max_samples`", 1, 100_000_000)) {
                        p.max_samples = v as usize;
                    }
                }
                ("neighbours", ast::Value::Quantity(q)) => {
                    if let Some(v) = self.ok(integer(q, "`neighbours`", 1, 1000)) {
                        p.neighbours = v as usize;
                    }
                }
                ("resolution", ast::Value::Quantity(q)) => {
                    let help = "a typical resolution is 1deg to 5deg";
                    if let Some(v) = self.up_to(q, Kind::Angle, PI / 2.0, key, "90deg", Some(help)) {
                        p.resolution = v;
                    }
                }
                ("time_budget", ast::Value::Quantity(q)) => {
                    if let Some(v) = self.up_to(q, Kind::Time, 86_400.0, key, "one day (86400s)", None) {
                        p.time_budget = Some(v);
                    }
                }
                ("acceleration", ast::Value::Quantity(q)) => {
                    let help = "a typical arm accelerates its joints at 1rad/s2 to 10rad/s2";
                    if let Some(v) = self.up_to(q, Kind::Acceleration, 1000.0, key, "1000rad/s2", Some(help)) {
                        p.acceleration = v;
                    }
                }
                ("speed", ast::Value::Quantity(q)) => {
                    let help = "`speed` scales the URDF's velocity limits and `acceleration`: 0.5 is half speed";
                    if let Some(v) = self.up_to(q, Kind::Count, 1.0, key, "1", Some(help)) {
                        p.speed = v;
                    }
                }
                ("objective", ast::Value::Ident(i)) => match i.name.as_str() {
                    "fewest_removals" => p.objective = Objective::FewestRemovals,
                    "fewest_vertices" => p.objective = Objective::FewestVertices,
                    other => {
                        let help = did_you_mean(other, ["fewest_removals", "fewest_vertices"])
                            .map(|s| format!("did you mean `{s}`?"));
                        self.errors.push(bad("`fewest_removals` or `fewest_vertices`", help));
                    }
                },
                ("first_path", ast::Value::Ident(i)) => match i.name.as_str() {
                    "true" => p.first_path = true,
                    "false" => p.first_path = false,
                    other => {
                        let help = did_you_mean(other, ["true", "false"]).map(|s| format!("did you mean `{s}`?"));
                        self.errors.push(bad("`true` or `false`", help));
                    }
                },
                ("objective", _) => self.errors.push(bad("`fewest_removals` or `fewest_vertices`", None)),
                ("first_path", _) => self.errors.push(bad("`true` or `false`", None)),
                ("resolution", _) => self.errors.push(bad("an angle like `2deg`", None)),
                ("time_budget", _) => self.errors.push(bad("a duration like `30s` or `500ms`", None)),
                ("acceleration", _) => self.errors.push(bad("an acceleration like `3rad/s2`", None)),
                ("speed", _) => self.errors.push(bad("a number in (0, 1] like `0.5`", None)),
                _ => self.errors.push(bad("a whole number", None)),
            }
        }
        p
    }

    /// `q` as a `kind` in (0, `max`]; outside, an error saying the range (`max_text`).
    fn up_to(
        &mut self,
        q: &ast::Quantity,
        kind: Kind,
        max: f64,
        key: &str,
        max_text: &str,
        help: Option<&str>,
    ) -> Option<f64> {
        let v = self.ok(convert(q, kind))?;
        if v <= 0.0 || v > max {
            self.errors.push(ResolveError::OutOfRange {
                what: format!("`{key}`"),
                limit: format!("greater than 0 and at most {max_text}"),
                value: written(q),
                span: q.span,
                help: help.map(str::to_string),
            });
            return None;
        }
        Some(v)
    }
}
