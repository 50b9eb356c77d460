//! pest pairs -> [`ast`] nodes, and pest errors -> readable [`SyntaxError`]s.

use pest::iterators::{Pair, Pairs};
use pest::Parser as _;
use pest_derive::Parser;

use super::ast::*;
use super::expected::convert_error;
use super::SyntaxError;
use crate::diag::{FileId, Span};

#[derive(Parser)]
#[grammar = "../grammar/declutter.pest"]
pub(super) struct Grammar;

type R<T> = Result<T, SyntaxError>;

/// Parses the whole text, stopping at the first error.
pub(super) fn parse_all(file: FileId, text: &str) -> Result<Vec<Item>, SyntaxError> {
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
            Rule::srdf_stmt => RobotItem::Srdf { path: self.string(take()?)?, span },
            Rule::home_stmt => RobotItem::Home { q: self.list(take()?)?, span },
            Rule::drop_stmt => RobotItem::Drop { q: self.list(take()?)?, span },
            Rule::open_stmt => RobotItem::Open { q: self.list(take()?)?, span },
            Rule::closed_stmt => RobotItem::Closed { q: self.list(take()?)?, span },
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
                Rule::width => {
                    GraspOption::Width { length: self.quantity(ci.next().ok_or_else(|| self.bad(&c))?)?, span: cs }
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
        let mut parts = self.inner(&p).filter(|c| matches!(c.as_rule(), Rule::tuple | Rule::quat));
        let at = self.tuple(parts.next().ok_or_else(|| self.bad(&p))?)?;
        let rot = match parts.next() {
            Some(q) if q.as_rule() == Rule::quat => {
                let qspan = self.span(&q);
                let t = self.inner(&q).find(|c| c.as_rule() == Rule::tuple).ok_or_else(|| self.bad(&q))?;
                Some(Rotation::Quat { xyzw: self.tuple(t)?, span: qspan })
            }
            Some(t) => Some(Rotation::Rpy(self.tuple(t)?)),
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
            | Rule::k_srdf
            | Rule::k_home
            | Rule::k_drop
            | Rule::k_open
            | Rule::k_closed
            | Rule::k_width
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
