//! Declarations -> typed scenario parts: names to ids, units to SI, poses to the world frame.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::load::{dir_name, normalize, Sourced};
use super::units::{convert, integer, positive_length, written, Kind};
use super::*;
use crate::diag::{FileId, Loader, SourceMap, Span};
use crate::syntax::ast;
use crate::syntax::did_you_mean;

/// Most grasp copies one `repeat` may make.
pub const MAX_REPEAT: u64 = 10_000;
/// Most joints a robot may have.
pub const MAX_JOINTS: usize = 64;
/// Largest mesh scale factor.
pub const MAX_SCALE: f64 = 1000.0;

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
                    let decl = self.same_file(id.span, *decl);
                    self.errors.push(ResolveError::WrongKind {
                        name: id.name.clone(),
                        expected: noun,
                        found: k.noun(),
                        span: id.span,
                        decl,
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

    fn body(&mut self, b: &ast::Body) -> Body {
        let pose_world_body = self.opt_pose(b.pose.as_ref());
        let mut parts = Vec::new();
        if let Some(s) = &b.shape {
            if let Some(shape) = self.shape(s) {
                parts.push(Part {
                    shape,
                    pose_world_part: pose_world_body,
                    pose_body_part: Pose::identity(),
                    span: s.span,
                });
            }
        }
        let mut any_shape = b.shape.is_some();
        for it in &b.items {
            if let ast::BodyItem::Part(p) = it {
                any_shape = true;
                let pose_body_part = self.opt_pose(p.pose.as_ref());
                if let Some(shape) = self.shape(&p.shape) {
                    parts.push(Part {
                        shape,
                        pose_world_part: pose_world_body * pose_body_part,
                        pose_body_part,
                        span: p.span,
                    });
                }
            }
        }
        let kind = match b.kind {
            ast::BodyKind::Fixed => "fixed",
            ast::BodyKind::Object => "object",
        };
        if !any_shape {
            self.errors.push(ResolveError::NoShape { kind, name: b.name.name.clone(), span: b.name.span });
        }
        if b.kind == ast::BodyKind::Fixed {
            for it in &b.items {
                if let ast::BodyItem::Grasp(g) = it {
                    self.errors.push(ResolveError::GraspOnFixed {
                        grasp: g.name.name.clone(),
                        body: b.name.name.clone(),
                        span: g.span,
                        kind: b.kind_span,
                    });
                }
            }
        }
        Body { name: b.name.name.clone(), span: b.name.span, pose_world_body, parts }
    }

    fn shape(&mut self, s: &ast::Shape) -> Option<Shape> {
        let kw = s.kind.keyword();
        let spec: &[&str] = match s.kind {
            ast::ShapeKind::Box => &["x", "y", "z"],
            ast::ShapeKind::Cylinder | ast::ShapeKind::Capsule => &["radius", "length"],
            ast::ShapeKind::Sphere => &["radius"],
            ast::ShapeKind::Mesh => &["file"],
        };
        let args = self.match_args(s, spec)?;
        if s.kind != ast::ShapeKind::Mesh {
            if let Some((_, span)) = &s.scale {
                self.errors.push(ResolveError::ShapeArgument {
                    problem: format!("`scale` only applies to meshes, not to a {kw}"),
                    span: *span,
                    help: Some("write the sizes of a primitive directly".to_string()),
                });
            }
        }
        let len = |me: &mut Self, a: &ast::Arg, what: &str, zero_ok: bool| -> Option<f64> {
            let ast::ArgValue::Quantity(q) = &a.value else {
                me.errors.push(ResolveError::UnitMismatch {
                    expected: "a length",
                    found: "a string".to_string(),
                    span: a.value.span(),
                    help: None,
                });
                return None;
            };
            if zero_ok {
                let v = me.ok(convert(q, Kind::Length))?;
                if v < 0.0 {
                    me.errors.push(ResolveError::OutOfRange {
                        what: what.to_string(),
                        limit: "zero or more".to_string(),
                        value: written(q),
                        span: q.span,
                        help: None,
                    });
                    return None;
                }
                Some(v)
            } else {
                me.ok(positive_length(q, what))
            }
        };
        let shape = match s.kind {
            ast::ShapeKind::Box => {
                let x = len(self, args[0], "the size of a box", false);
                let y = len(self, args[1], "the size of a box", false);
                let z = len(self, args[2], "the size of a box", false);
                Shape::Box { size: Vector3::new(x?, y?, z?) }
            }
            ast::ShapeKind::Cylinder => {
                let radius = len(self, args[0], "the radius of a cylinder", false);
                let length = len(self, args[1], "the length of a cylinder", false);
                Shape::Cylinder { radius: radius?, length: length? }
            }
            ast::ShapeKind::Capsule => {
                let radius = len(self, args[0], "the radius of a capsule", false);
                let length = len(self, args[1], "the length of a capsule", true);
                Shape::Capsule { radius: radius?, length: length? }
            }
            ast::ShapeKind::Sphere => Shape::Sphere { radius: len(self, args[0], "the radius of a sphere", false)? },
            ast::ShapeKind::Mesh => {
                let ast::ArgValue::Str(path) = &args[0].value else {
                    self.errors.push(ResolveError::ShapeArgument {
                        problem: "a mesh takes a file name".to_string(),
                        span: args[0].value.span(),
                        help: Some("write `mesh(\"meshes/part.stl\")`".to_string()),
                    });
                    return None;
                };
                let ext = Path::new(&path.value).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
                if !matches!(ext.as_deref(), Some("stl" | "obj" | "dae")) {
                    self.errors.push(ResolveError::ShapeArgument {
                        problem: format!("unsupported mesh format `{}`", path.value),
                        span: path.span,
                        help: Some("meshes are STL (.stl), Wavefront OBJ (.obj) or COLLADA (.dae) files".to_string()),
                    });
                    return None;
                }
                let file = self.file_ref(path, "mesh");
                let scale = match &s.scale {
                    None => Vector3::repeat(1.0),
                    Some((ast::Scale::Uniform(q), _)) => Vector3::repeat(self.scale(q)?),
                    Some((ast::Scale::PerAxis(t), _)) => {
                        if t.items.len() != 3 {
                            self.errors.push(ResolveError::WrongCount {
                                what: "a per-axis scale".to_string(),
                                expected: "3 factors (x, y, z)".to_string(),
                                found: t.items.len(),
                                span: t.span,
                            });
                            return None;
                        }
                        let f: Vec<Option<f64>> = t.items.iter().map(|q| self.scale(q)).collect();
                        Vector3::new(f[0]?, f[1]?, f[2]?)
                    }
                };
                Shape::Mesh { file, scale }
            }
        };
        Some(shape)
    }

    fn scale(&mut self, q: &ast::Quantity) -> Option<f64> {
        let v = self.ok(convert(q, Kind::Count))?;
        if v <= 0.0 || v > MAX_SCALE {
            self.errors.push(ResolveError::OutOfRange {
                what: "a mesh scale".to_string(),
                limit: format!("greater than 0 and at most {MAX_SCALE}"),
                value: written(q),
                span: q.span,
                help: Some("a mesh in millimetres needs `scale 0.001`".to_string()),
            });
            return None;
        }
        Some(v)
    }

    /// Matches positional and named arguments to `spec`; one argument per name, in spec order.
    fn match_args<'s>(&mut self, s: &'s ast::Shape, spec: &[&str]) -> Option<Vec<&'s ast::Arg>> {
        let kw = s.kind.keyword();
        let mut slots: Vec<Option<&ast::Arg>> = vec![None; spec.len()];
        let mut ok = true;
        let mut next = 0;
        let signature = format!("{kw}({})", spec.join(", "));
        if s.args.len() > spec.len() || (s.args.iter().all(|a| a.name.is_none()) && s.args.len() < spec.len()) {
            self.errors.push(ResolveError::WrongCount {
                what: format!("`{kw}`"),
                expected: format!(
                    "{} value{} ({})",
                    spec.len(),
                    if spec.len() == 1 { "" } else { "s" },
                    spec.join(", ")
                ),
                found: s.args.len(),
                span: s.args_span,
            });
            return None;
        }
        for a in &s.args {
            let slot = match &a.name {
                None => {
                    let i = next;
                    next += 1;
                    i
                }
                Some(n) => match spec.iter().position(|p| *p == n.name) {
                    Some(i) => i,
                    None => {
                        let help = match did_you_mean(&n.name, spec.iter().copied()) {
                            Some(s) => format!("did you mean `{s}`? The arguments are {signature}"),
                            None => format!("the arguments are {signature}"),
                        };
                        self.errors.push(ResolveError::ShapeArgument {
                            problem: format!("`{kw}` has no argument `{}`", n.name),
                            span: n.span,
                            help: Some(help),
                        });
                        ok = false;
                        continue;
                    }
                },
            };
            match slots.get_mut(slot) {
                Some(x @ None) => *x = Some(a),
                _ => {
                    self.errors.push(ResolveError::ShapeArgument {
                        problem: format!("argument `{}` of `{kw}` given twice", spec.get(slot).unwrap_or(&"?")),
                        span: a.span,
                        help: Some(format!("the arguments are {signature}")),
                    });
                    ok = false;
                }
            }
        }
        let mut out = Vec::with_capacity(spec.len());
        for (i, sl) in slots.into_iter().enumerate() {
            match sl {
                Some(a) => out.push(a),
                None => {
                    if ok {
                        self.errors.push(ResolveError::ShapeArgument {
                            problem: format!("`{kw}` is missing its `{}`", spec[i]),
                            span: s.args_span,
                            help: Some(format!("the arguments are {signature}")),
                        });
                    }
                    ok = false;
                }
            }
        }
        ok.then_some(out)
    }

    fn grasps(&mut self, b: &ast::Body, body: &Body) -> Vec<Grasp> {
        let mut out = Vec::new();
        let mut seen: HashMap<&str, Span> = HashMap::new();
        for it in &b.items {
            let ast::BodyItem::Grasp(g) = it else { continue };
            if let Some(first) = seen.get(g.name.name.as_str()) {
                self.errors.push(ResolveError::DuplicateName {
                    name: g.name.name.clone(),
                    span: g.name.span,
                    first: Some(*first),
                    help: Some(format!("grasp names are unique within `{}`", b.name.name)),
                });
                continue;
            }
            seen.insert(&g.name.name, g.name.span);
            let pose = self.pose(&g.pose);
            let mut approach: Option<(f64, Span)> = None;
            let mut repeat: Option<((u64, ast::Axis), Span)> = None;
            let mut hands: Option<(Vec<HandId>, Span)> = None;
            for o in &g.options {
                match o {
                    ast::GraspOption::Approach { length, span } => {
                        let v = self.ok(convert(length, Kind::Length)).and_then(|v| {
                            if v < 0.0 {
                                self.errors.push(ResolveError::OutOfRange {
                                    what: "an approach".to_string(),
                                    limit: "zero or more".to_string(),
                                    value: written(length),
                                    span: length.span,
                                    help: Some("the approach is a distance back along the TCP's -z".to_string()),
                                });
                                None
                            } else {
                                Some(v)
                            }
                        });
                        self.once(&mut approach, "approach", v.unwrap_or(0.0), *span);
                    }
                    ast::GraspOption::Repeat { count, axis, span } => {
                        let n = if count.unit.is_none()
                            && count.number.trim_start_matches(['+', '-']).chars().all(|c| c == '0' || c == '.')
                            && count.value == 0.0
                        {
                            self.errors.push(ResolveError::RepeatZero { span: count.span });
                            None
                        } else {
                            self.ok(integer(count, "`repeat`", 1, MAX_REPEAT))
                        };
                        self.once(&mut repeat, "repeat", (n.unwrap_or(1), *axis), *span);
                    }
                    ast::GraspOption::For { hands: hs, span } => {
                        let mut ids = Vec::new();
                        for h in hs {
                            if let Some(i) =
                                self.lookup(h, |k| if let DeclKind::Hand(i) = k { Some(i) } else { None }, "a hand")
                            {
                                let id = HandId(i as u32);
                                if !ids.contains(&id) {
                                    ids.push(id);
                                }
                            }
                        }
                        self.once(&mut hands, "for", ids, *span);
                    }
                }
            }
            let Some(pose) = pose else { continue };
            let approach = approach.map_or(0.0, |(a, _)| a);
            let hands = hands.map(|(h, _)| h);
            match repeat {
                None => out.push(Grasp {
                    name: g.name.name.clone(),
                    span: g.span,
                    pose_object_tcp: pose,
                    pose_world_tcp: body.pose_world_body * pose,
                    approach,
                    hands,
                }),
                Some(((n, axis), _)) => {
                    let axis = match axis {
                        ast::Axis::X => Vector3::x(),
                        ast::Axis::Y => Vector3::y(),
                        ast::Axis::Z => Vector3::z(),
                    };
                    for k in 0..n {
                        let angle = 2.0 * PI * k as f64 / n as f64;
                        let pose_object_tcp = Isometry3::rotation(axis * angle) * pose;
                        out.push(Grasp {
                            name: format!("{}#{k}", g.name.name),
                            span: g.span,
                            pose_object_tcp,
                            pose_world_tcp: body.pose_world_body * pose_object_tcp,
                            approach,
                            hands: hands.clone(),
                        });
                    }
                }
            }
        }
        out
    }

    fn planner(&mut self, entries: &[&ast::PlannerEntry]) -> PlannerSettings {
        const KEYS: [&str; 7] =
            ["seed", "max_samples", "resolution", "objective", "time_budget", "neighbours", "first_path"];
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
                    if let Some(v) = self.ok(convert(q, Kind::Angle)) {
                        if v <= 0.0 || v > PI / 2.0 {
                            self.errors.push(ResolveError::OutOfRange {
                                what: "`resolution`".to_string(),
                                limit: "greater than 0 and at most 90deg".to_string(),
                                value: written(q),
                                span: q.span,
                                help: Some("a typical resolution is 1deg to 5deg".to_string()),
                            });
                        } else {
                            p.resolution = v;
                        }
                    }
                }
                ("time_budget", ast::Value::Quantity(q)) => {
                    if let Some(v) = self.ok(convert(q, Kind::Time)) {
                        if v <= 0.0 || v > 86_400.0 {
                            self.errors.push(ResolveError::OutOfRange {
                                what: "`time_budget`".to_string(),
                                limit: "greater than 0 and at most one day (86400s)".to_string(),
                                value: written(q),
                                span: q.span,
                                help: None,
                            });
                        } else {
                            p.time_budget = Some(v);
                        }
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
                _ => self.errors.push(bad("a whole number", None)),
            }
        }
        p
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
                let decl = self.names.get(&t.name.name).map(|(_, s)| *s).and_then(|s| self.same_file(t.name.span, s));
                self.errors.push(ResolveError::WrongKind {
                    name: t.name.name.clone(),
                    expected: "an object or a robot",
                    found: k.noun(),
                    span: t.name.span,
                    decl,
                });
                None
            }
        }
    }
}
