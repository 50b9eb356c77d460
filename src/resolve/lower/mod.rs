//! Declarations -> typed scenario parts: names to ids, units to SI, poses to the world frame.
//!
//! One file per concern: bodies and shapes, grasps, the planner block; names, poses,
//! hands, robots and the target are here.

use std::collections::HashMap;
use std::path::Path;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

mod bodies;
mod grasps;
mod planner;

use super::load::{dir_name, normalize, Sourced};
use super::units::{convert, Kind};
use super::*;
use crate::diag::{FileId, Loader, SourceMap, Span};
use crate::syntax::ast;
use crate::syntax::did_you_mean;

/// Most joints a robot may have.
pub const MAX_JOINTS: usize = 64;

/// What `resolve` produced before the target requirement is applied.
pub struct Partial {
    pub name: Option<String>,
    pub hands: Vec<Hand>,
    pub robots: Vec<Robot>,
    pub fixed: Vec<Body>,
    pub objects: Vec<Object>,
    pub target: Option<Target>,
    pub planner: PlannerSettings,
    /// Where a missing target or robot is reported: the `scenario` line, or the root file's start.
    pub anchor: Span,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum DeclKind {
    Hand(usize),
    Robot(usize),
    Fixed(usize),
    Object(usize),
}

impl DeclKind {
    fn noun(self) -> &'static str {
        match self {
            DeclKind::Hand(_) => "a hand",
            DeclKind::Robot(_) => "a robot",
            DeclKind::Fixed(_) => "a fixed body",
            DeclKind::Object(_) => "an object",
        }
    }
}

struct Lower<'a> {
    sources: &'a SourceMap,
    loader: &'a dyn Loader,
    errors: &'a mut Vec<ResolveError>,
    names: HashMap<String, (DeclKind, Span)>,
    order: Vec<String>,
}

pub fn lower(
    items: &[Sourced],
    root: Option<FileId>,
    loader: &dyn Loader,
    sources: &SourceMap,
    errors: &mut Vec<ResolveError>,
) -> Partial {
    let mut lw = Lower { sources, loader, errors, names: HashMap::new(), order: Vec::new() };
    let mut hands_ast = Vec::new();
    let mut robots_ast = Vec::new();
    let mut fixed_ast = Vec::new();
    let mut objects_ast = Vec::new();
    let mut planner_entries = Vec::new();
    let mut targets = Vec::new();
    let mut name: Option<(String, Span)> = None;
    let anchor_file = root.unwrap_or_default();
    let mut anchor = Span::new(anchor_file, 0, 0);

    // Pass 1: declare every name, so declarations may refer to later ones.
    for s in items {
        match &s.item {
            ast::Item::Hand(h) => {
                if lw.declare(&h.name, DeclKind::Hand(hands_ast.len())) {
                    hands_ast.push(h);
                }
            }
            ast::Item::Robot(r) => {
                if lw.declare(&r.name, DeclKind::Robot(robots_ast.len())) {
                    robots_ast.push(r);
                }
            }
            ast::Item::Body(b) => match b.kind {
                ast::BodyKind::Fixed => {
                    if lw.declare(&b.name, DeclKind::Fixed(fixed_ast.len())) {
                        fixed_ast.push(b);
                    }
                }
                ast::BodyKind::Object => {
                    if lw.declare(&b.name, DeclKind::Object(objects_ast.len())) {
                        objects_ast.push(b);
                    }
                }
            },
            ast::Item::Planner { entries, .. } => planner_entries.extend(entries.iter()),
            ast::Item::Target(t) => targets.push(t),
            ast::Item::Scenario { name: n, span } => {
                if let Some((_, first)) = &name {
                    lw.errors.push(ResolveError::DuplicateStatement {
                        what: "scenario".to_string(),
                        span: *span,
                        first: *first,
                    });
                } else {
                    name = Some((n.value.clone(), *span));
                    anchor = *span;
                }
            }
            // `use` is inlined by the loader.
            ast::Item::Use { .. } => {}
        }
    }

    let hands: Vec<Hand> = hands_ast.iter().map(|h| lw.hand(h)).collect();
    let robots: Vec<Robot> = robots_ast.iter().map(|r| lw.robot(r)).collect();
    let fixed: Vec<Body> = fixed_ast.iter().map(|b| lw.body(b)).collect();
    let objects: Vec<Object> = objects_ast
        .iter()
        .map(|b| {
            let body = lw.body(b);
            let grasps = lw.grasps(b, &body);
            Object { body, grasps }
        })
        .collect();
    let planner = lw.planner(&planner_entries);

    let mut target = None;
    let mut first_target: Option<Span> = None;
    for t in &targets {
        if let Some(first) = first_target {
            lw.errors.push(ResolveError::DuplicateTarget { span: t.span, first: lw.same_file(t.span, first) });
            continue;
        }
        first_target = Some(t.span);
        target = lw.target(t, &robots);
    }

    Partial { name: name.map(|(n, _)| n), hands, robots, fixed, objects, target, planner, anchor }
}
impl Lower<'_> {
    /// Records a name; false (and an error) if it is taken.
    fn declare(&mut self, name: &ast::Ident, kind: DeclKind) -> bool {
        if let Some((_, first)) = self.names.get(&name.name) {
            let first = *first;
            let same = self.same_file(name.span, first);
            let help = if same.is_none() { Some(format!("first declared at {}", self.place(first))) } else { None };
            self.errors.push(ResolveError::DuplicateName {
                name: name.name.clone(),
                span: name.span,
                first: same,
                help,
            });
            return false;
        }
        self.names.insert(name.name.clone(), (kind, name.span));
        self.order.push(name.name.clone());
        true
    }

    /// `other` if it is in the same file as `span` (so it can be labelled), else `None`.
    fn same_file(&self, span: Span, other: Span) -> Option<Span> {
        (span.file == other.file).then_some(other)
    }

    /// `file:line:col` of a span, for help text pointing into another file.
    fn place(&self, span: Span) -> String {
        let name = self.sources.get(span.file).map_or("?", |f| f.name.as_str()).to_string();
        match self.sources.line_col(span) {
            Some((l, c)) => format!("{name}:{l}:{c}"),
            None => name,
        }
    }

    /// Looks a name up, expecting one kind of declaration.
    fn lookup(&mut self, id: &ast::Ident, want: fn(DeclKind) -> Option<usize>, noun: &'static str) -> Option<usize> {
        match self.names.get(&id.name) {
            Some((k, decl)) => match want(*k) {
                Some(i) => Some(i),
                None => {
                    let (k, decl_span) = (*k, *decl);
                    let decl = self.same_file(id.span, decl_span);
                    let help =
                        decl.is_none().then(|| format!("`{}` is declared at {}", id.name, self.place(decl_span)));
                    self.errors.push(ResolveError::WrongKind {
                        name: id.name.clone(),
                        expected: noun,
                        found: k.noun(),
                        span: id.span,
                        decl,
                        help,
                    });
                    None
                }
            },
            None => {
                let candidates: Vec<&str> = self
                    .order
                    .iter()
                    .filter(|n| self.names.get(*n).is_some_and(|(k, _)| want(*k).is_some()))
                    .map(String::as_str)
                    .collect();
                let help = did_you_mean(&id.name, candidates.iter().copied()).map(|s| format!("did you mean `{s}`?"));
                let help = help.or_else(|| {
                    (!candidates.is_empty()).then(|| {
                        format!(
                            "declared: {}",
                            candidates.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", ")
                        )
                    })
                });
                self.errors.push(ResolveError::UnknownName {
                    kind: noun.trim_start_matches("a ").trim_start_matches("an "),
                    name: id.name.clone(),
                    span: id.span,
                    help,
                });
                None
            }
        }
    }

    fn ok<T>(&mut self, r: Result<T, ResolveError>) -> Option<T> {
        match r {
            Ok(v) => Some(v),
            Err(e) => {
                self.errors.push(e);
                None
            }
        }
    }

    /// A file named by `s`, relative to the directory of the file `s` is in; reports a missing one.
    fn file_ref(&mut self, s: &ast::Str, what: &'static str) -> FileRef {
        let dir = self.sources.get(s.span.file).and_then(|f| f.path.parent()).unwrap_or(Path::new("")).to_path_buf();
        let path = normalize(&dir.join(&s.value));
        if s.value.is_empty() || !self.loader.exists(&path) {
            self.errors.push(ResolveError::MissingFile {
                what,
                path: s.value.clone(),
                dir: dir_name(&dir),
                span: s.span,
            });
        }
        FileRef { path, written: s.value.clone(), span: s.span }
    }

    fn vec3(&mut self, t: &ast::Tuple, kind: Kind, what: &str) -> Option<Vector3<f64>> {
        if t.items.len() != 3 {
            let names = if kind == Kind::Angle { "(roll, pitch, yaw)" } else { "(x, y, z)" };
            self.errors.push(ResolveError::WrongCount {
                what: what.to_string(),
                expected: format!("3 values {names}"),
                found: t.items.len(),
                span: t.span,
            });
            return None;
        }
        let mut v = Vector3::zeros();
        let mut ok = true;
        for (i, q) in t.items.iter().enumerate() {
            match self.ok(convert(q, kind)) {
                Some(x) => v[i] = x,
                None => ok = false,
            }
        }
        ok.then_some(v)
    }

    fn pose(&mut self, p: &ast::Pose) -> Option<Pose> {
        let xyz = self.vec3(&p.at, Kind::Length, "a position");
        let rpy = match &p.rot {
            Some(r) => self.vec3(r, Kind::Angle, "a rotation"),
            None => Some(Vector3::zeros()),
        };
        let (xyz, rpy) = (xyz?, rpy?);
        Some(Isometry3::from_parts(Translation3::from(xyz), UnitQuaternion::from_euler_angles(rpy.x, rpy.y, rpy.z)))
    }

    fn opt_pose(&mut self, p: Option<&ast::Pose>) -> Pose {
        p.and_then(|p| self.pose(p)).unwrap_or_else(Pose::identity)
    }

    fn once<T>(&mut self, slot: &mut Option<(T, Span)>, what: &str, v: T, span: Span) {
        if let Some((_, first)) = slot {
            self.errors.push(ResolveError::DuplicateStatement { what: what.to_string(), span, first: *first });
        } else {
            *slot = Some((v, span));
        }
    }

    fn hand(&mut self, h: &ast::Hand) -> Hand {
        let mut urdf = None;
        let mut tcp = None;
        for it in &h.items {
            match it {
                ast::HandItem::Urdf { path, span } => {
                    let f = self.file_ref(path, "URDF");
                    self.once(&mut urdf, "urdf", f, *span);
                }
                ast::HandItem::Tcp { pose, span } => {
                    let p = self.opt_pose(Some(pose));
                    self.once(&mut tcp, "tcp", p, *span);
                }
            }
        }
        let urdf = self.required(urdf, "hand", &h.name, "urdf", "`urdf \"hands/NAME.urdf\"`");
        Hand {
            name: h.name.name.clone(),
            span: h.name.span,
            urdf,
            pose_flange_tcp: tcp.map_or_else(Pose::identity, |(p, _)| p),
        }
    }

    fn required(
        &mut self,
        slot: Option<(FileRef, Span)>,
        decl: &'static str,
        name: &ast::Ident,
        what: &'static str,
        example: &str,
    ) -> FileRef {
        match slot {
            Some((f, _)) => f,
            None => {
                self.errors.push(ResolveError::MissingStatement {
                    decl,
                    name: name.name.clone(),
                    what,
                    span: name.span,
                    help: Some(format!("add {example} to its block")),
                });
                FileRef { path: Default::default(), written: String::new(), span: name.span }
            }
        }
    }

    fn joints(&mut self, l: &ast::List, what: &str) -> JointValues {
        let mut values = Vec::with_capacity(l.items.len());
        if l.items.is_empty() || l.items.len() > MAX_JOINTS {
            self.errors.push(ResolveError::WrongCount {
                what: what.to_string(),
                expected: format!("one value per joint (1 to {MAX_JOINTS})"),
                found: l.items.len(),
                span: l.span,
            });
        }
        for q in &l.items {
            // Prismatic joints take lengths; everything else is an angle.
            let is_length = q.unit.as_ref().is_some_and(|u| matches!(u.name.as_str(), "m" | "cm" | "mm"));
            let v = self.ok(convert(q, if is_length { Kind::Length } else { Kind::Angle }));
            values.push(v.unwrap_or(0.0));
        }
        JointValues { values, span: l.span }
    }

    fn robot(&mut self, r: &ast::Robot) -> Robot {
        let mut urdf = None;
        let mut base = None;
        let mut hand = None;
        let mut flange = None;
        let mut home = None;
        let mut drop = None;
        let mut allow_contact = Vec::new();
        for it in &r.items {
            match it {
                ast::RobotItem::Urdf { path, span } => {
                    let f = self.file_ref(path, "URDF");
                    self.once(&mut urdf, "urdf", f, *span);
                }
                ast::RobotItem::Base { pose, span } => {
                    let p = self.opt_pose(Some(pose));
                    self.once(&mut base, "base", p, *span);
                }
                ast::RobotItem::Hand { name, span } => {
                    let h = self.lookup(name, |k| if let DeclKind::Hand(i) = k { Some(i) } else { None }, "a hand");
                    self.once(&mut hand, "hand", h.map(|i| HandId(i as u32)), *span);
                }
                ast::RobotItem::Flange { link, span } => {
                    self.once(&mut flange, "flange", (link.value.clone(), link.span), *span);
                }
                ast::RobotItem::Home { q, span } => {
                    let j = self.joints(q, "`home`");
                    self.once(&mut home, "home", j, *span);
                }
                ast::RobotItem::Drop { q, span } => {
                    let j = self.joints(q, "`drop`");
                    self.once(&mut drop, "drop", j, *span);
                }
                ast::RobotItem::AllowContact { a, b, span } => {
                    allow_contact.push(LinkPair { a: a.value.clone(), b: b.value.clone(), span: *span })
                }
            }
        }
        let urdf = self.required(urdf, "robot", &r.name, "urdf", "`urdf \"robots/NAME.urdf\"`");
        let home = match home {
            Some((h, _)) => h,
            None => {
                self.errors.push(ResolveError::MissingStatement {
                    decl: "robot",
                    name: r.name.name.clone(),
                    what: "home",
                    span: r.name.span,
                    help: Some("add its home configuration, e.g. `home [0, -20deg, 110deg, 0, 60deg, 0]`".to_string()),
                });
                JointValues { values: Vec::new(), span: r.name.span }
            }
        };
        let drop = drop.map(|(d, _)| d);
        if let Some(d) = &drop {
            self.check_joint_count(&r.name.name, &home, d);
        }
        Robot {
            name: r.name.name.clone(),
            span: r.name.span,
            urdf,
            pose_world_base: base.map_or_else(Pose::identity, |(p, _)| p),
            hand: hand.and_then(|(h, _)| h),
            flange: flange.map(|(f, _)| f),
            home,
            drop,
            allow_contact,
        }
    }

    fn check_joint_count(&mut self, robot: &str, home: &JointValues, q: &JointValues) {
        if !home.values.is_empty() && !q.values.is_empty() && home.values.len() != q.values.len() {
            self.errors.push(ResolveError::JointCount {
                robot: robot.to_string(),
                expected: home.values.len(),
                found: q.values.len(),
                span: q.span,
                home: self.same_file(q.span, home.span),
            });
        }
    }

    fn target(&mut self, t: &ast::Target, robots: &[Robot]) -> Option<Target> {
        let Some((kind, _)) = self.names.get(&t.name.name).copied() else {
            self.lookup(
                &t.name,
                |k| if let DeclKind::Object(i) | DeclKind::Robot(i) = k { Some(i) } else { None },
                "an object or robot",
            );
            return None;
        };
        match (kind, &t.q) {
            (DeclKind::Object(i), None) => Some(Target::Object { object: ObjectId(i as u32), span: t.span }),
            (DeclKind::Object(_), Some(q)) => {
                self.errors.push(ResolveError::BadTarget {
                    problem: format!("`{}` is an object; an object target takes no joint values", t.name.name),
                    span: q.span,
                    help: Some(format!("write `target {}` to grasp it", t.name.name)),
                });
                None
            }
            (DeclKind::Robot(i), Some(l)) => {
                let q = self.joints(l, "a robot target");
                if let Some(r) = robots.get(i) {
                    let home = r.home.clone();
                    self.check_joint_count(&t.name.name, &home, &q);
                }
                Some(Target::Config { robot: RobotId(i as u32), q, span: t.span })
            }
            (DeclKind::Robot(_), None) => {
                self.errors.push(ResolveError::BadTarget {
                    problem: format!("`{}` is a robot; a robot target needs a configuration", t.name.name),
                    span: t.name.span,
                    help: Some(format!("write `target {} at [joint values]`", t.name.name)),
                });
                None
            }
            (k, _) => {
                let decl_span = self.names.get(&t.name.name).map(|(_, s)| *s);
                let decl = decl_span.and_then(|s| self.same_file(t.name.span, s));
                let help = match (decl, decl_span) {
                    (None, Some(s)) => Some(format!("`{}` is declared at {}", t.name.name, self.place(s))),
                    _ => None,
                };
                self.errors.push(ResolveError::WrongKind {
                    name: t.name.name.clone(),
                    expected: "an object or a robot",
                    found: k.noun(),
                    span: t.name.span,
                    decl,
                    help,
                });
                None
            }
        }
    }
}
