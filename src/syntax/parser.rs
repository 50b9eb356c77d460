//! pest pairs -> [`ast`] nodes, and pest errors -> readable [`SyntaxError`]s.

use pest::iterators::{Pair, Pairs};
use pest::Parser as _;
use pest_derive::Parser;

use super::ast::*;
use super::SyntaxError;
use crate::diag::{FileId, Located, Span};

#[derive(Parser)]
#[grammar = "../grammar/declutter.pest"]
struct Grammar;

type R<T> = Result<T, SyntaxError>;

/// Parses one file. On failure returns the (single) first syntax error.
/// Most syntax errors reported for one file; after that the rest is likely noise.
const MAX_SYNTAX_ERRORS: usize = 20;

/// Parses one file. On failure returns its syntax errors: after each, parsing resumes
/// at the next line that starts (in column 0) with a top-level keyword, so independent
/// mistakes in different declarations are all reported.
pub fn parse(file: FileId, text: &str) -> Result<File, Vec<SyntaxError>> {
    // Makes pest record the literal tokens (`(`, `,`, `}`) it expected, for the message.
    pest::set_error_detail(true);
    let whole = Span::new(file, 0, text.len());
    let mut errors = Vec::new();
    let mut start = 0;
    loop {
        // Blank out what was already reported, keeping byte offsets (and line numbers) intact.
        let masked: String;
        let src = if start == 0 {
            text
        } else {
            masked = text
                .char_indices()
                .map(|(i, c)| if i >= start || c == '\n' { c.to_string() } else { " ".repeat(c.len_utf8()) })
                .collect();
            &masked
        };
        match parse_all(file, src) {
            Ok(items) if errors.is_empty() => return Ok(File { items, span: whole }),
            Ok(_) => return Err(errors),
            Err(e) => {
                let pos = e.primary_span().map_or(text.len(), |s| s.start as usize);
                errors.push(e);
                match next_declaration(text, pos) {
                    Some(next) if errors.len() < MAX_SYNTAX_ERRORS => start = next,
                    _ => return Err(errors),
                }
            }
        }
    }
}

fn parse_all(file: FileId, text: &str) -> Result<Vec<Item>, SyntaxError> {
    let cx = Cx { file, text };
    let mut pairs = Grammar::parse(Rule::file, text).map_err(|e| convert_error(file, text, &e))?;
    let whole = Span::new(file, 0, text.len());
    let top = pairs.next().ok_or(SyntaxError::Internal { span: whole })?;
    let mut items = Vec::new();
    for p in top.into_inner() {
        if p.as_rule() != Rule::EOI {
            items.push(cx.item(p)?);
        }
    }
    Ok(items)
}

/// The start of the first line after the one holding `pos` that begins, in column 0,
/// with a top-level keyword.
fn next_declaration(text: &str, pos: usize) -> Option<usize> {
    const KEYWORDS: [&str; 8] = ["scenario", "use", "hand", "robot", "fixed", "object", "planner", "target"];
    let mut at = text.get(pos..)?.find('\n').map(|i| pos + i + 1)?;
    while at < text.len() {
        let line = &text[at..];
        let starts = KEYWORDS.iter().any(|k| {
            line.strip_prefix(k).is_some_and(|rest| !rest.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_'))
        });
        if starts {
            return Some(at);
        }
        at = line.find('\n').map(|i| at + i + 1)?;
    }
    None
}

struct Cx<'t> {
    file: FileId,
    text: &'t str,
}

impl Cx<'_> {
    /// The pair's span without the whitespace and comments pest skips after its last token.
    fn span(&self, p: &Pair<Rule>) -> Span {
        let s = p.as_span();
        let end = trim_end(self.text.get(s.start()..s.end()).unwrap_or(""));
        Span::new(self.file, s.start(), s.start() + end)
    }

    fn bad(&self, p: &Pair<Rule>) -> SyntaxError {
        SyntaxError::Internal { span: self.span(p) }
    }

    /// The next child, which the grammar guarantees.
    fn next<'a>(&self, parent: &Pair<'a, Rule>, it: &mut Pairs<'a, Rule>) -> R<Pair<'a, Rule>> {
        it.next().ok_or_else(|| self.bad(parent))
    }

    /// Children after skipping keyword tokens.
    fn inner<'a>(&self, p: &Pair<'a, Rule>) -> Pairs<'a, Rule> {
        p.clone().into_inner()
    }

    fn item(&self, p: Pair<Rule>) -> R<Item> {
        let span = self.span(&p);
        let mut it = self.inner(&p).filter(|c| !is_keyword(c.as_rule())).collect::<Vec<_>>().into_iter();
        let mut take = || it.next().ok_or_else(|| self.bad(&p));
        Ok(match p.as_rule() {
            Rule::scenario_decl => Item::Scenario { name: self.string(take()?)?, span },
            Rule::use_decl => Item::Use { path: self.string(take()?)?, span },
            Rule::hand_decl => {
                let name = self.ident(take()?);
                let mut items = Vec::new();
                for c in it {
                    let cs = self.span(&c);
                    let inner = self.first_non_kw(&c)?;
                    items.push(match c.as_rule() {
                        Rule::urdf_stmt => HandItem::Urdf { path: self.string(inner)?, span: cs },
                        Rule::tcp_stmt => HandItem::Tcp { pose: self.pose(inner)?, span: cs },
                        _ => return Err(self.bad(&c)),
                    });
                }
                Item::Hand(Hand { name, items, span })
            }
            Rule::robot_decl => {
                let name = self.ident(take()?);
                let mut items = Vec::new();
                for c in it {
                    items.push(self.robot_item(c)?);
                }
                Item::Robot(Robot { name, items, span })
            }
            Rule::body_decl => self.body(&p)?,
            Rule::planner_decl => {
                let mut entries = Vec::new();
                for c in it {
                    let cs = self.span(&c);
                    let mut ci = c.clone().into_inner();
                    let key = self.ident(self.next(&c, &mut ci)?);
                    let v = self.next(&c, &mut ci)?;
                    let value = match v.as_rule() {
                        Rule::quantity => Value::Quantity(self.quantity(v)?),
                        Rule::string => Value::Str(self.string(v)?),
                        Rule::ident => Value::Ident(self.ident(v)),
                        _ => return Err(self.bad(&v)),
                    };
                    entries.push(PlannerEntry { key, value, span: cs });
                }
                Item::Planner { entries, span }
            }
            Rule::target_decl => {
                let name = self.ident(take()?);
                let q = match it.next() {
                    Some(l) => Some(self.list(l)?),
                    None => None,
                };
                Item::Target(Target { name, q, span })
            }
            _ => return Err(self.bad(&p)),
        })
    }

    fn first_non_kw<'a>(&self, p: &Pair<'a, Rule>) -> R<Pair<'a, Rule>> {
        self.inner(p).find(|c| !is_keyword(c.as_rule())).ok_or_else(|| self.bad(p))
    }

    fn robot_item(&self, c: Pair<Rule>) -> R<RobotItem> {
        let span = self.span(&c);
        let mut it = self.inner(&c).filter(|x| !is_keyword(x.as_rule()));
        let mut take = || it.next().ok_or_else(|| self.bad(&c));
        Ok(match c.as_rule() {
            Rule::urdf_stmt => RobotItem::Urdf { path: self.string(take()?)?, span },
            Rule::base_stmt => RobotItem::Base { pose: self.pose(take()?)?, span },
            Rule::hand_stmt => RobotItem::Hand { name: self.ident(take()?), span },
            Rule::flange_stmt => RobotItem::Flange { link: self.string(take()?)?, span },
            Rule::home_stmt => RobotItem::Home { q: self.list(take()?)?, span },
            Rule::drop_stmt => RobotItem::Drop { q: self.list(take()?)?, span },
            Rule::contact_stmt => {
                let a = self.string(take()?)?;
                let b = self.string(take()?)?;
                RobotItem::AllowContact { a, b, span }
            }
            _ => return Err(self.bad(&c)),
        })
    }

    fn body(&self, p: &Pair<Rule>) -> R<Item> {
        let span = self.span(p);
        let mut it = self.inner(p);
        let kind_pair = self.next(p, &mut it)?;
        let kind = if kind_pair.as_str().starts_with("fixed") { BodyKind::Fixed } else { BodyKind::Object };
        let kind_span = self.span(&kind_pair);
        let name = self.ident(self.next(p, &mut it)?);
        let mut shape = None;
        let mut pose = None;
        let mut items = Vec::new();
        for c in it {
            match c.as_rule() {
                Rule::shape => shape = Some(self.shape(c)?),
                Rule::pose => pose = Some(self.pose(c)?),
                Rule::body_block => {
                    for b in c.into_inner() {
                        items.push(match b.as_rule() {
                            Rule::part => {
                                let bs = self.span(&b);
                                let mut bi = b.clone().into_inner();
                                let shape = self.shape(self.next(&b, &mut bi)?)?;
                                let pose = match bi.next() {
                                    Some(x) => Some(self.pose(x)?),
                                    None => None,
                                };
                                BodyItem::Part(Part { shape, pose, span: bs })
                            }
                            Rule::grasp => BodyItem::Grasp(self.grasp(b)?),
                            _ => return Err(self.bad(&b)),
                        });
                    }
                }
                _ => return Err(self.bad(&c)),
            }
        }
        Ok(Item::Body(Box::new(Body { kind, kind_span, name, shape, pose, items, span })))
    }

    fn shape(&self, p: Pair<Rule>) -> R<Shape> {
        let span = self.span(&p);
        let mut it = self.inner(&p);
        let k = self.next(&p, &mut it)?;
        let kind_span = self.span(&k);
        let kind = match k.as_str() {
            "box" => ShapeKind::Box,
            "cylinder" => ShapeKind::Cylinder,
            "capsule" => ShapeKind::Capsule,
            "sphere" => ShapeKind::Sphere,
            "mesh" => ShapeKind::Mesh,
            _ => return Err(self.bad(&k)),
        };
        let mut args = Vec::new();
        let mut scale = None;
        let mut args_end = kind_span.end as usize;
        for c in it {
            match c.as_rule() {
                Rule::arg => {
                    let cs = self.span(&c);
                    let mut name = None;
                    let mut value = None;
                    for a in c.clone().into_inner() {
                        match a.as_rule() {
                            Rule::ident => name = Some(self.ident(a)),
                            Rule::quantity => value = Some(ArgValue::Quantity(self.quantity(a)?)),
                            Rule::string => value = Some(ArgValue::Str(self.string(a)?)),
                            _ => return Err(self.bad(&a)),
                        }
                    }
                    let value = value.ok_or_else(|| self.bad(&c))?;
                    args.push(Arg { name, value, span: cs });
                }
                Rule::scale => {
                    let ss = self.span(&c);
                    args_end = ss.start as usize;
                    let v = self.first_non_kw(&c)?;
                    let s = match v.as_rule() {
                        Rule::quantity => Scale::Uniform(self.quantity(v)?),
                        Rule::tuple => Scale::PerAxis(self.tuple(v)?),
                        _ => return Err(self.bad(&v)),
                    };
                    scale = Some((s, ss));
                }
                _ => return Err(self.bad(&c)),
            }
        }
        if scale.is_none() {
            args_end = span.end as usize;
        }
        // The parentheses: from the end of the keyword to the last `)` before any `scale`.
        let text = p.as_str();
        let rel_end = args_end.saturating_sub(span.start as usize).min(text.len());
        let close = text.get(..rel_end).and_then(|t| t.rfind(')')).map_or(rel_end, |i| i + 1);
        let args_span = Span::new(self.file, kind_span.end as usize, span.start as usize + close);
        Ok(Shape { kind, kind_span, args, args_span, scale, span })
    }

    fn grasp(&self, p: Pair<Rule>) -> R<Grasp> {
        let span = self.span(&p);
        let mut it = self.inner(&p).filter(|c| !is_keyword(c.as_rule()));
        let name = self.ident(it.next().ok_or_else(|| self.bad(&p))?);
        let pose = self.pose(it.next().ok_or_else(|| self.bad(&p))?)?;
        let mut options = Vec::new();
        for c in it {
            let cs = self.span(&c);
            let mut ci = self.inner(&c).filter(|x| !is_keyword(x.as_rule()));
            options.push(match c.as_rule() {
                Rule::approach => {
                    GraspOption::Approach { length: self.quantity(ci.next().ok_or_else(|| self.bad(&c))?)?, span: cs }
                }
                Rule::repeat => {
                    let count = self.quantity(ci.next().ok_or_else(|| self.bad(&c))?)?;
                    let a = ci.next().ok_or_else(|| self.bad(&c))?;
                    let axis = match a.as_str() {
                        "x" => Axis::X,
                        "y" => Axis::Y,
                        _ => Axis::Z,
                    };
                    GraspOption::Repeat { count, axis, span: cs }
                }
                Rule::for_hands => GraspOption::For { hands: ci.map(|h| self.ident(h)).collect(), span: cs },
                _ => return Err(self.bad(&c)),
            });
        }
        Ok(Grasp { name, pose, options, span })
    }

    fn pose(&self, p: Pair<Rule>) -> R<Pose> {
        let span = self.span(&p);
        let mut tuples = self.inner(&p).filter(|c| c.as_rule() == Rule::tuple);
        let at = self.tuple(tuples.next().ok_or_else(|| self.bad(&p))?)?;
        let rot = match tuples.next() {
            Some(t) => Some(self.tuple(t)?),
            None => None,
        };
        Ok(Pose { at, rot, span })
    }

    fn tuple(&self, p: Pair<Rule>) -> R<Tuple> {
        let span = self.span(&p);
        let items = p.into_inner().map(|q| self.quantity(q)).collect::<R<Vec<_>>>()?;
        Ok(Tuple { items, span })
    }

    fn list(&self, p: Pair<Rule>) -> R<List> {
        let span = self.span(&p);
        let items = p.into_inner().map(|q| self.quantity(q)).collect::<R<Vec<_>>>()?;
        Ok(List { items, span })
    }

    fn quantity(&self, p: Pair<Rule>) -> R<Quantity> {
        let span = self.span(&p);
        let mut it = self.inner(&p);
        let n = self.next(&p, &mut it)?;
        let number = n.as_str().to_string();
        // The grammar only admits decimal literals, which `f64::from_str` always accepts
        // (overflow gives infinity, which `resolve` reports).
        let value = number.parse::<f64>().map_err(|_| self.bad(&n))?;
        let unit = it.next().map(|u| self.ident(u));
        Ok(Quantity { number, value, unit, span })
    }

    fn ident(&self, p: Pair<Rule>) -> Ident {
        Ident { name: p.as_str().to_string(), span: self.span(&p) }
    }

    fn string(&self, p: Pair<Rule>) -> R<Str> {
        let span = self.span(&p);
        let raw = self.inner(&p).next().map_or("", |r| r.as_str());
        let mut value = String::with_capacity(raw.len());
        let mut chars = raw.chars();
        while let Some(c) = chars.next() {
            if c == '\\' {
                match chars.next() {
                    Some('n') => value.push('\n'),
                    Some('t') => value.push('\t'),
                    Some(o) => value.push(o),
                    None => {}
                }
            } else {
                value.push(c);
            }
        }
        Ok(Str { value, span })
    }
}

/// Length of `t` without trailing whitespace and `//` comments.
fn trim_end(t: &str) -> usize {
    let mut t = t.trim_end();
    loop {
        let line_start = t.rfind('\n').map_or(0, |i| i + 1);
        let line = &t[line_start..];
        match comment_start(line) {
            Some(c) => t = t[..line_start + c].trim_end(),
            None => return t.len(),
        }
    }
}

/// Where a `//` comment starts in one line, ignoring `//` inside strings.
fn comment_start(line: &str) -> Option<usize> {
    let mut in_string = false;
    let mut escaped = false;
    let bytes = line.as_bytes();
    for (i, b) in bytes.iter().enumerate() {
        match b {
            _ if escaped => escaped = false,
            b'\\' if in_string => escaped = true,
            b'"' => in_string = !in_string,
            b'/' if !in_string && bytes.get(i + 1) == Some(&b'/') => return Some(i),
            _ => {}
        }
    }
    None
}

fn is_keyword(r: Rule) -> bool {
    matches!(
        r,
        Rule::k_scenario
            | Rule::k_use
            | Rule::k_hand
            | Rule::k_robot
            | Rule::k_urdf
            | Rule::k_tcp
            | Rule::k_base
            | Rule::k_flange
            | Rule::k_home
            | Rule::k_drop
            | Rule::k_allow_contact
            | Rule::k_scale
            | Rule::k_grasp
            | Rule::k_approach
            | Rule::k_repeat
            | Rule::k_about
            | Rule::k_for
            | Rule::k_planner
            | Rule::k_target
            | Rule::k_at
            | Rule::k_rot
    )
}

/// What a user would call the thing a rule matches.
fn describe(r: Rule) -> &'static str {
    match r {
        Rule::EOI => "the end of the file",
        Rule::scenario_decl | Rule::k_scenario => "`scenario`",
        Rule::use_decl | Rule::k_use => "`use`",
        Rule::hand_decl | Rule::k_hand | Rule::hand_stmt => "`hand`",
        Rule::robot_decl | Rule::k_robot => "`robot`",
        Rule::body_decl | Rule::body_kind => "`fixed` or `object`",
        Rule::planner_decl | Rule::k_planner => "`planner`",
        Rule::target_decl | Rule::k_target => "`target`",
        Rule::urdf_stmt | Rule::k_urdf => "`urdf`",
        Rule::tcp_stmt | Rule::k_tcp => "`tcp`",
        Rule::base_stmt | Rule::k_base => "`base`",
        Rule::flange_stmt | Rule::k_flange => "`flange`",
        Rule::home_stmt | Rule::k_home => "`home`",
        Rule::drop_stmt | Rule::k_drop => "`drop`",
        Rule::contact_stmt | Rule::k_allow_contact => "`allow_contact`",
        Rule::body_block => "a `{` block of shapes and grasps",
        Rule::part | Rule::shape | Rule::shape_kind => "a shape (box, cylinder, capsule, sphere, mesh)",
        Rule::arg => "a shape argument (a quantity, `name: quantity` or a \"string\")",
        Rule::scale | Rule::k_scale => "`scale`",
        Rule::grasp | Rule::k_grasp => "`grasp`",
        Rule::approach | Rule::k_approach => "`approach`",
        Rule::repeat | Rule::k_repeat => "`repeat`",
        Rule::k_about => "`about`",
        Rule::axis => "an axis (x, y or z)",
        Rule::for_hands | Rule::k_for => "`for`",
        Rule::planner_entry => "a planner setting (`key value`)",
        Rule::pose | Rule::k_at => "`at`",
        Rule::k_rot => "`rot`",
        Rule::tuple => "a tuple like `(x, y, z)`",
        Rule::list => "a list of joint values like `[0, 90deg]`",
        Rule::quantity | Rule::number => "a number",
        Rule::unit => "a unit",
        Rule::string | Rule::string_raw => "a \"string\"",
        Rule::ident => "a name",
        Rule::file | Rule::item => "a declaration (scenario, use, hand, robot, fixed, object, planner, target)",
        // Silent rules never show up in errors; keep the match exhaustive anyway.
        _ => "something else",
    }
}

/// Top-level declarations are listed as one item, not seven.
fn collapse(words: &mut Vec<String>) {
    let top = ["`scenario`", "`use`", "`robot`", "`fixed` or `object`", "`planner`", "`target`"];
    if top.iter().all(|t| words.iter().any(|w| w == t)) {
        words.retain(|w| !top.contains(&w.as_str()) && w != "`hand`");
        words.insert(0, "a declaration (scenario, use, hand, robot, fixed, object, planner, target)".to_string());
    }
}

fn convert_error(file: FileId, text: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let mut pos = match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    };
    let mut words: Vec<String> = Vec::new();
    if let pest::error::ErrorVariant::ParsingError { positives, .. } = &e.variant {
        for r in positives {
            let w = describe(*r).to_string();
            if !words.contains(&w) {
                words.push(w);
            }
        }
    }
    // Rules do not list punctuation; the parse attempts do, sometimes further on (after
    // skipping whitespace), where the real mistake is.
    if let Some(attempts) = e.parse_attempts() {
        let punct: Vec<String> = attempts
            .expected_tokens()
            .iter()
            .map(|t| t.to_string())
            .filter(|t| !t.is_empty() && t != "//" && t.chars().all(|c| c.is_ascii_punctuation()))
            .map(|t| format!("`{t}`"))
            .collect();
        if attempts.max_position > pos && !punct.is_empty() {
            pos = attempts.max_position;
            words.clear();
        }
        if attempts.max_position == pos {
            for w in punct {
                if !words.contains(&w) {
                    words.push(w);
                }
            }
        }
    }
    // A unit can always follow a number; saying so only helps when nothing else fits.
    if words.len() > 1 {
        words.retain(|w| w != "a unit");
    }
    // `(` is how a tuple starts, and so on: say it once.
    for (rule_word, punct) in [("tuple", "`(`"), ("list of joint", "`[`"), ("block", "`{`")] {
        if words.iter().any(|w| w.contains(rule_word)) {
            words.retain(|w| w != punct);
        }
    }
    collapse(&mut words);
    // The most specific expectations first; "a declaration" and "the end of the file" last.
    words.sort_by_key(|w| w.starts_with("a declaration") || w.starts_with("the end"));
    let pos = pos.min(text.len());
    let (found, found_span) = token_at(text, pos);
    // At the end of the file, point at the last character so the report shows a line.
    let at_end = found.is_empty();
    let (pos, found_span) = if at_end {
        let last = text.trim_end().char_indices().next_back().map_or(0, |(i, _)| i);
        (last, text[last..].chars().next().map_or(0, char::len_utf8))
    } else {
        (pos, found_span)
    };
    let after = text.get(pos + found_span..).unwrap_or("");
    let mut expected = join_or(&words);
    if expected.is_empty() {
        expected = "something else".to_string();
    }
    let raw = text.get(..pos).unwrap_or("");
    let trimmed = raw.trim_end_matches([' ', '\t']);
    let spaced_number = trimmed.len() < raw.len() && trimmed.ends_with(|c: char| c.is_ascii_digit());
    let help = hint(&found, spaced_number, &words, after);
    let label = if at_end {
        "the file ends after this".to_string()
    } else if expected.len() <= 40 {
        format!("expected {expected}")
    } else {
        "unexpected here".to_string()
    };
    SyntaxError::Expected {
        expected,
        found: describe_found(&found),
        span: Span::new(file, pos, pos + found_span),
        label,
        help,
    }
}

fn hint(found: &str, spaced_number: bool, words: &[String], after: &str) -> Option<String> {
    if let Some(rest) = found.strip_prefix('"') {
        if !rest.contains('"') {
            return Some("a string must end with `\"` on the same line".to_string());
        }
    }
    if words.iter().any(|w| w == "`\"`") {
        return Some("a string must end with `\"` on the same line".to_string());
    }
    let is_word = found.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_');
    if is_word && after.starts_with('(') && words.iter().any(|w| w.starts_with("a shape")) {
        let shapes = ["box", "cylinder", "capsule", "sphere", "mesh"];
        let close = super::did_you_mean(found, shapes);
        return Some(match close {
            Some(s) => format!("did you mean `{s}`? The shapes are box, cylinder, capsule, sphere and mesh"),
            None => "the shapes are box, cylinder, capsule, sphere and mesh".to_string(),
        });
    }
    if spaced_number && matches!(found, "m" | "cm" | "mm" | "deg" | "rad" | "s" | "ms") {
        return Some("a unit goes right after its number, without a space: `16cm`".to_string());
    }
    None
}

fn join_or(words: &[String]) -> String {
    match words {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} or {}", init.join(", "), last),
    }
}

/// The token starting at `pos`, for "found ..." and the label width.
fn token_at(text: &str, pos: usize) -> (String, usize) {
    let rest = text.get(pos..).unwrap_or("");
    let mut chars = rest.char_indices();
    let Some((_, first)) = chars.next() else { return (String::new(), 0) };
    let len = if first.is_alphanumeric() || first == '_' || first == '.' {
        rest.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.')).unwrap_or(rest.len())
    } else if first == '"' {
        rest[1..].find(['"', '\n']).map_or(rest.len(), |i| i + 2).min(rest.len())
    } else {
        first.len_utf8()
    };
    let len = len.min(40);
    // Keep the cut on a char boundary.
    let mut cut = len;
    while cut > 0 && !rest.is_char_boundary(cut) {
        cut -= 1;
    }
    (rest[..cut].to_string(), cut)
}

fn describe_found(tok: &str) -> String {
    match tok.chars().next() {
        None => "the end of the file".to_string(),
        Some('\n') => "the end of the line".to_string(),
        Some(c) if c.is_ascii_digit() => format!("the number `{tok}`"),
        Some(c) if c.is_alphabetic() || c == '_' => format!("`{tok}`"),
        Some('"') => format!("the string {tok}"),
        Some(c) if c.is_control() => format!("the control character U+{:04X}", c as u32),
        Some(_) => format!("`{tok}`"),
    }
}
