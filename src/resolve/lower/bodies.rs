//! Bodies (`fixed`, `object`) and their shapes.

use std::path::Path;

use nalgebra::Vector3;

use super::Lower;
use crate::resolve::units::{convert, positive_length, written, Kind};
use crate::resolve::{Body, Part, Pose, ResolveError, Shape};
use crate::syntax::ast;
use crate::syntax::did_you_mean;

/// Largest mesh scale factor.
pub const MAX_SCALE: f64 = 1000.0;

impl Lower<'_> {
    pub(super) fn body(&mut self, b: &ast::Body) -> Body {
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
            me.check_bare_length(q);
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
        // `cylinder(radius: 3cm, length: 1cm, radius: 4cm)`: the repeated name is the
        // mistake, reported below, not the count.
        let name = |a: &ast::Arg| a.name.as_ref().map(|n| n.name.clone());
        let repeats_a_name =
            s.args.iter().enumerate().any(|(i, a)| a.name.is_some() && s.args[..i].iter().any(|b| name(b) == name(a)));
        let too_many = s.args.len() > spec.len() && !repeats_a_name;
        if too_many || (s.args.iter().all(|a| a.name.is_none()) && s.args.len() < spec.len()) {
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
        let mut named_seen = false;
        for a in &s.args {
            if a.name.is_some() {
                named_seen = true;
            } else if named_seen {
                // `cylinder(length: 1cm, 2cm)` would make 2cm the radius: surely not meant.
                self.errors.push(ResolveError::ShapeArgument {
                    problem: format!("a positional argument of `{kw}` after a named one"),
                    span: a.span,
                    help: Some(format!("name it too, or give all arguments in order: {signature}")),
                });
                ok = false;
                continue;
            }
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
                None => {
                    self.errors.push(ResolveError::ShapeArgument {
                        problem: format!("`{kw}` takes {} arguments; this one is too many", spec.len()),
                        span: a.span,
                        help: Some(format!("the arguments are {signature}")),
                    });
                    ok = false;
                }
                Some(Some(_)) => {
                    self.errors.push(ResolveError::ShapeArgument {
                        problem: format!("argument `{}` of `{kw}` given twice", spec[slot]),
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
}
