//! Grasps: options checked, `repeat` expanded, poses composed into the world frame.

use std::collections::HashMap;
use std::f64::consts::PI;

use nalgebra::{Isometry3, Vector3};

use super::{DeclKind, Lower};
use crate::diag::Span;
use crate::resolve::units::{convert, integer, written, Kind};
use crate::resolve::{Body, Grasp, HandId, ResolveError};
use crate::syntax::ast;

/// Most grasp copies one `repeat` may make.
pub const MAX_REPEAT: u64 = 10_000;
/// Most grasps one object may have after `repeat`s are expanded: every grasp is tried
/// by every robot's inverse kinematics, so thousands make `check` crawl.
pub const MAX_GRASPS_PER_OBJECT: usize = 1_000;
/// Most grasps in the whole scenario after expansion, for the same reason.
pub const MAX_GRASPS_TOTAL: usize = 10_000;

impl Lower<'_> {
    pub(super) fn grasps(&mut self, b: &ast::Body, body: &Body) -> Vec<Grasp> {
        let mut out = Vec::new();
        let mut seen: HashMap<&str, Span> = HashMap::new();
        for it in &b.items {
            let ast::BodyItem::Grasp(g) = it else { continue };
            if let Some(first) = seen.get(g.name.name.as_str()) {
                self.errors.push(ResolveError::DuplicateName {
                    name: g.name.name.clone(),
                    span: g.name.span,
                    first: Some(*first),
                    elsewhere: None,
                    help: Some(format!("grasp names are unique within `{}`", b.name.name)),
                });
                continue;
            }
            seen.insert(&g.name.name, g.name.span);
            let pose = self.pose(&g.pose);
            let mut approach: Option<(f64, Span)> = None;
            let mut width: Option<((f64, Span), Span)> = None;
            let mut repeat: Option<((u64, ast::Axis), Span)> = None;
            let mut hands: Option<(Vec<HandId>, Span)> = None;
            for o in &g.options {
                match o {
                    ast::GraspOption::Approach { length, span } => {
                        self.check_bare_length(length);
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
                    ast::GraspOption::Width { length, span } => {
                        self.check_bare_length(length);
                        let v = self.ok(convert(length, Kind::Length)).and_then(|v| {
                            if v > 0.0 {
                                Some(v)
                            } else {
                                self.errors.push(ResolveError::OutOfRange {
                                    what: "a grip width".to_string(),
                                    limit: "more than zero".to_string(),
                                    value: written(length),
                                    span: length.span,
                                    help: Some(
                                        "the width is how far apart the fingers close on the object".to_string(),
                                    ),
                                });
                                None
                            }
                        });
                        if let Some(v) = v {
                            self.once(&mut width, "width", (v, length.span), *span);
                        }
                    }
                    ast::GraspOption::Repeat { count, axis, span } => {
                        // Any spelling of zero (`0`, `0.0`, `0e5`, `-0`) is the same slip.
                        let n = if count.unit.is_none() && count.value == 0.0 {
                            self.errors.push(ResolveError::RepeatZero { span: count.span });
                            None
                        } else {
                            self.ok(integer(count, "`repeat`", 1, MAX_REPEAT))
                        };
                        self.once(&mut repeat, "repeat", (n.unwrap_or(1), *axis), *span);
                    }
                    ast::GraspOption::For { hands: hs, span } => {
                        let mut ids = Vec::new();
                        for (k, h) in hs.iter().enumerate() {
                            if let Some(first) = hs[..k].iter().find(|f| f.name == h.name) {
                                self.errors.push(ResolveError::DuplicateInList {
                                    name: h.name.clone(),
                                    span: h.span,
                                    first: first.span,
                                });
                                continue;
                            }
                            if let Some(i) =
                                self.lookup(h, |k| if let DeclKind::Hand(i) = k { Some(i) } else { None }, "a hand")
                            {
                                ids.push(HandId(i as u32));
                            }
                        }
                        self.once(&mut hands, "for", ids, *span);
                    }
                }
            }
            let Some(pose) = pose else { continue };
            let copies = repeat.map_or(1, |((n, _), _)| n as usize);
            let blame = g.options.iter().find_map(|o| match o {
                ast::GraspOption::Repeat { count, .. } => Some(count.span),
                _ => None,
            });
            if !self.room_for_grasps(&b.name.name, out.len(), copies, blame.unwrap_or(g.name.span)) {
                break;
            }
            let approach = approach.map_or(0.0, |(a, _)| a);
            let hands = hands.map(|(h, _)| h);
            let width = width.map(|(w, _)| w);
            match repeat {
                None => out.push(Grasp {
                    name: g.name.name.clone(),
                    span: g.span,
                    pose_object_tcp: pose,
                    pose_world_tcp: body.pose_world_body * pose,
                    approach,
                    hands,
                    width,
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
                            width,
                        });
                    }
                }
            }
        }
        out
    }

    /// False (and an error) if `copies` more grasps would pass the per-object or total limit.
    fn room_for_grasps(&mut self, object: &str, have: usize, copies: usize, span: Span) -> bool {
        // After one limit error the scenario is rejected anyway; more objects would each
        // repeat it, so their grasps are dropped quietly.
        let Some(total) = self.grasp_total else { return false };
        let (what, limit, value) = if have + copies > MAX_GRASPS_PER_OBJECT {
            (format!("the number of grasps of `{object}`"), MAX_GRASPS_PER_OBJECT, have + copies)
        } else if total + copies > MAX_GRASPS_TOTAL {
            ("the number of grasps in the scenario".to_string(), MAX_GRASPS_TOTAL, total + copies)
        } else {
            self.grasp_total = Some(total + copies);
            return true;
        };
        self.errors.push(ResolveError::OutOfRange {
            what,
            limit: format!("at most {limit} after `repeat`"),
            value: format!("{value} with this one"),
            span,
            help: Some(format!(
                "every grasp is tried by every robot; a few dozen per object are plenty (limits: {MAX_GRASPS_PER_OBJECT} per object, {MAX_GRASPS_TOTAL} in all)"
            )),
        });
        self.grasp_total = None;
        false
    }
}
