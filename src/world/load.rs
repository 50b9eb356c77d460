//! Loading a scenario's files for [`super::build`]: URDFs (each parsed once per build),
//! their collision geometry and meshes, SRDFs, hands, and the joint values written in
//! the scenario, with every problem collected as a [`WorldError`].

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::Isometry3;

use super::build::WorldOptions;
use super::chain::{Chain, ChainError};
use super::check;
use super::error::WorldError;
use super::robot::{RBody, RShape};
use super::shapes::{describe_tried, resolve_uri, Geometry, MeshCache, Placed};
use super::urdf::{self, GeomKind, Model, UrdfProblem};
use crate::diag::{Loader, Span};
use crate::resolve::{FileRef, JointUnit, JointValues, Pose, Shape};

/// A hand: its shapes in the flange frame, by link, its fingers open.
pub(super) struct HandModel {
    pub(super) bodies: Vec<(String, Vec<Placed>)>,
    pub(super) chain: Chain,
    /// Each shape's link in `chain`, in the order of `bodies` flattened.
    pub(super) shape_links: Vec<usize>,
}

/// An arm's URDF loaded: its chain, collision bodies, the file's own filter pairs and
/// every link name (for checking an SRDF against it).
pub(super) struct Arm {
    pub(super) chain: Chain,
    pub(super) shapes: Vec<RShape>,
    pub(super) bodies: Vec<RBody>,
    pub(super) filter_pairs: Vec<(String, String)>,
    pub(super) links: Vec<String>,
}

/// Appends a body of `placed` shapes on `link` (nothing when it has none).
pub(super) fn push_body(
    shapes: &mut Vec<RShape>,
    bodies: &mut Vec<RBody>,
    name: &str,
    link: usize,
    placed: Vec<Placed>,
    moving: bool,
    holds: bool,
) {
    if placed.is_empty() {
        return;
    }
    let start = shapes.len();
    let body = bodies.len();
    shapes.extend(placed.into_iter().map(|placed| RShape { body, placed, unturned: false }));
    bodies.push(RBody { name: name.to_string(), link, shapes: start..shapes.len(), moving, holds });
}

/// What loading needs across files: the loader, the options, the errors found so far.
pub(super) struct LoadCtx<'a> {
    loader: &'a dyn Loader,
    opts: &'a WorldOptions,
    pub(super) errs: &'a mut Vec<WorldError>,
    /// URDFs parsed so far, by path: two robots of one model (or two hands of one file)
    /// read and parse it once. Only successes are kept, so a broken file is reported at
    /// every use, as before.
    urdfs: HashMap<PathBuf, Model>,
}

impl<'a> LoadCtx<'a> {
    pub(super) fn new(loader: &'a dyn Loader, opts: &'a WorldOptions, errs: &'a mut Vec<WorldError>) -> LoadCtx<'a> {
        LoadCtx { loader, opts, errs, urdfs: HashMap::new() }
    }

    /// The arm's chain and its own collision bodies (no hand).
    pub(super) fn load_arm(
        &mut self,
        robot: &str,
        urdf: &FileRef,
        flange: Option<&(String, Span)>,
        meshes: &mut MeshCache,
    ) -> Option<Arm> {
        let model = self.load_urdf(urdf)?;
        let chain = match Chain::new(&model, flange.map(|f| f.0.as_str())) {
            Ok(c) => c,
            Err(ChainError::UnknownFlange) => {
                let (link, span) = flange.cloned().unwrap_or_default();
                let links = model.links.iter().map(|l| format!("`{}`", l.name)).collect::<Vec<_>>().join(", ");
                self.errs.push(WorldError::UnknownFlange { robot: robot.to_string(), link, links, span });
                return None;
            }
            Err(ChainError::Structure(reason)) => {
                self.errs.push(WorldError::UrdfStructure { path: urdf.written.clone(), reason, span: urdf.span });
                return None;
            }
        };
        // Without this, `home` would be reported as having too many values for 0 joints.
        if chain.dof() == 0 {
            self.errs.push(WorldError::NoJoints {
                robot: robot.to_string(),
                root: chain.links[0].name.clone(),
                flange: chain.links[chain.flange].name.clone(),
                span: urdf.span,
            });
            return None;
        }
        let mut shapes = Vec::new();
        let mut bodies = Vec::new();
        let root_group = chain.links[0].group;
        let flange_group = chain.links[chain.flange].group;
        for (li, link) in chain.links.iter().enumerate() {
            let ml = &model.links[chain.model_index[li]];
            let placed = self.geoms(urdf, &ml.name, &ml.collisions, meshes);
            let (moving, holds) = (link.group != root_group, link.group == flange_group);
            push_body(&mut shapes, &mut bodies, &link.name, li, placed, moving, holds);
        }
        let links = model.links.iter().map(|l| l.name.clone()).collect();
        Some(Arm { chain, shapes, bodies, filter_pairs: model.filter_pairs, links })
    }

    /// The SRDF's `disable_collisions` pairs, each link checked against the URDF's.
    pub(super) fn load_srdf(&mut self, robot: &str, file: &FileRef, links: &[String]) -> Vec<(String, String)> {
        let path = file.written.clone();
        let text = match self.loader.read_to_string(&file.path) {
            Ok(t) => t,
            Err(e) => {
                self.errs.push(WorldError::SrdfRead { path, reason: e.to_string(), span: file.span });
                return Vec::new();
            }
        };
        match super::srdf::disabled_pairs(&text) {
            Ok(pairs) => {
                let mut out = Vec::new();
                for p in pairs {
                    let unknown = [&p.a, &p.b].into_iter().find(|l| !links.contains(l));
                    match unknown {
                        Some(link) => self.errs.push(WorldError::SrdfLink {
                            path: path.clone(),
                            line: p.line,
                            robot: robot.to_string(),
                            link: link.clone(),
                            links: links.join(", "),
                            span: file.span,
                        }),
                        None => out.push((p.a, p.b)),
                    }
                }
                out
            }
            Err((reason, line)) => {
                self.errs.push(WorldError::SrdfParse { path, line, reason, span: file.span });
                Vec::new()
            }
        }
    }

    pub(super) fn load_urdf(&mut self, file: &FileRef) -> Option<Model> {
        if let Some(m) = self.urdfs.get(&file.path) {
            return Some(m.clone());
        }
        let path = file.written.clone();
        let text = match self.loader.read_to_string(&file.path) {
            Ok(t) => t,
            Err(e) => {
                self.errs.push(WorldError::UrdfRead { path, reason: e.to_string(), span: file.span });
                return None;
            }
        };
        match urdf::parse(&text) {
            Ok(m) => {
                self.urdfs.insert(file.path.clone(), m.clone());
                Some(m)
            }
            Err(p) => {
                self.errs.push(match p {
                    UrdfProblem::Parse(reason) => WorldError::UrdfParse { path, reason, span: file.span },
                    UrdfProblem::Empty => WorldError::UrdfEmpty { path, span: file.span },
                    UrdfProblem::Xacro => WorldError::UrdfXacro { path, span: file.span },
                    UrdfProblem::Structure(reason) => WorldError::UrdfStructure { path, reason, span: file.span },
                    UrdfProblem::Limit { joint, reason } => {
                        WorldError::UrdfLimit { path, joint, reason, span: file.span }
                    }
                });
                None
            }
        }
    }

    pub(super) fn load_hand(&mut self, file: &FileRef, meshes: &mut MeshCache) -> Option<HandModel> {
        let model = self.load_urdf(file)?;
        let chain = match Chain::hand(&model) {
            Ok(c) => c,
            Err(ChainError::Structure(reason)) => {
                self.errs.push(WorldError::UrdfStructure { path: file.written.clone(), reason, span: file.span });
                return None;
            }
            Err(ChainError::UnknownFlange) => return None,
        };
        // A hand is rigid: its fingers stand open (at their upper limits), the chain has
        // nothing to actuate.
        let q: Vec<f64> = Vec::new();
        let mut poses = vec![Isometry3::identity(); chain.links.len()];
        chain.fk_into(&q, &mut poses);
        let mut bodies = Vec::new();
        let mut shape_links = Vec::new();
        for (li, link) in chain.links.iter().enumerate() {
            let ml = &model.links[chain.model_index[li]];
            let geoms: Vec<urdf::Geom> = ml
                .collisions
                .iter()
                .map(|g| urdf::Geom { pose_link_geom: poses[li] * g.pose_link_geom, kind: g.kind.clone() })
                .collect();
            let placed = self.geoms(file, &link.name, &geoms, meshes);
            if !placed.is_empty() {
                shape_links.extend(std::iter::repeat_n(li, placed.len()));
                bodies.push((link.name.clone(), placed));
            }
        }
        Some(HandModel { bodies, chain, shape_links })
    }

    pub(super) fn geoms(
        &mut self,
        file: &FileRef,
        link: &str,
        geoms: &[urdf::Geom],
        meshes: &mut MeshCache,
    ) -> Vec<Placed> {
        let dir = file.path.parent().unwrap_or(Path::new(""));
        let mut out = Vec::new();
        for g in geoms {
            let made = match &g.kind {
                GeomKind::Box(s) => meshes.make(&Geometry::Box(*s), &g.pose_link_geom),
                GeomKind::Cylinder { radius, length } => {
                    meshes.make(&Geometry::Cylinder { radius: *radius, length: *length }, &g.pose_link_geom)
                }
                GeomKind::Capsule { radius, length } => {
                    meshes.make(&Geometry::Capsule { radius: *radius, length: *length }, &g.pose_link_geom)
                }
                GeomKind::Sphere(r) => meshes.make(&Geometry::Sphere(*r), &g.pose_link_geom),
                GeomKind::Mesh { uri, scale } => match resolve_uri(uri, dir, &self.opts.package_path, self.loader) {
                    Ok(path) => meshes.make(&Geometry::Mesh { path: &path, scale: *scale }, &g.pose_link_geom),
                    Err(tried) => {
                        self.errs.push(WorldError::MeshMissing {
                            owner: format!("link `{link}`"),
                            uri: uri.clone(),
                            tried: describe_tried(&tried),
                            span: file.span,
                            help: super::error::mesh_missing_help(uri),
                        });
                        continue;
                    }
                },
            };
            match made {
                Ok(p) => out.push(p),
                Err(reason) => self.errs.push(WorldError::MeshLoad {
                    owner: format!("link `{link}`"),
                    uri: match &g.kind {
                        GeomKind::Mesh { uri, .. } => uri.clone(),
                        _ => String::new(),
                    },
                    reason,
                    span: file.span,
                }),
            }
        }
        out
    }

    pub(super) fn part(&mut self, shape: &Shape, pose: &Pose, body: &str, meshes: &mut MeshCache) -> Option<Placed> {
        let made = match shape {
            Shape::Box { size } => meshes.make(&Geometry::Box(*size), pose),
            Shape::Cylinder { radius, length } => {
                meshes.make(&Geometry::Cylinder { radius: *radius, length: *length }, pose)
            }
            Shape::Capsule { radius, length } => {
                meshes.make(&Geometry::Capsule { radius: *radius, length: *length }, pose)
            }
            Shape::Sphere { radius } => meshes.make(&Geometry::Sphere(*radius), pose),
            Shape::Mesh { file, scale } => {
                if !self.loader.exists(&file.path) {
                    self.errs.push(WorldError::MeshMissing {
                        owner: format!("body `{body}`"),
                        uri: file.written.clone(),
                        tried: describe_tried(std::slice::from_ref(&file.path)),
                        span: file.span,
                        help: super::error::mesh_missing_help(&file.written),
                    });
                    return None;
                }
                match meshes.make(&Geometry::Mesh { path: &file.path, scale: *scale }, pose) {
                    Ok(p) => Ok(p),
                    Err(reason) => {
                        self.errs.push(WorldError::MeshLoad {
                            owner: format!("body `{body}`"),
                            uri: file.written.clone(),
                            reason,
                            span: file.span,
                        });
                        return None;
                    }
                }
            }
        };
        made.ok()
    }

    /// Checks length and limits; returns the values when they fit.
    pub(super) fn joint_values(&mut self, robot: &str, what: &str, v: &JointValues, chain: &Chain) -> Option<Vec<f64>> {
        if v.values.len() != chain.dof() {
            self.errs.push(WorldError::JointCount {
                robot: robot.into(),
                what: what.into(),
                expected: chain.dof(),
                got: v.values.len(),
                joints: chain.joint_names.join(", "),
                span: v.span,
            });
            return None;
        }
        let turns = super::ik::rotational(chain);
        self.units_and_limits(robot, what, v, &chain.joint_names, &chain.limits, &turns).then(|| v.values.clone())
    }

    /// Each value written with the unit its joint moves by (an angle for one that turns, a
    /// length for one that slides) and inside its limits.
    pub(super) fn units_and_limits(
        &mut self,
        robot: &str,
        what: &str,
        v: &JointValues,
        names: &[String],
        limits: &[(f64, f64)],
        turns: &[bool],
    ) -> bool {
        let mut ok = true;
        for ((unit, span), (turns, name)) in v.units.iter().zip(turns.iter().zip(names)) {
            let (moves, written) = match (unit, turns) {
                (JointUnit::Length, true) => ("turns", "a length"),
                (JointUnit::Angle, false) => ("slides", "an angle"),
                _ => continue,
            };
            ok = false;
            self.errs.push(WorldError::JointUnit {
                robot: robot.into(),
                what: what.into(),
                joint: name.clone(),
                moves,
                written,
                span: *span,
            });
        }
        if !ok {
            return false;
        }
        for (index, ((x, (lo, hi)), name)) in v.values.iter().zip(limits).zip(names).enumerate() {
            if !(x.is_finite() && *x >= lo - check::LIMIT_SLACK && *x <= hi + check::LIMIT_SLACK) {
                ok = false;
                self.errs.push(WorldError::JointLimit {
                    robot: robot.into(),
                    what: what.into(),
                    joint: name.clone(),
                    value: *x,
                    lower: *lo,
                    upper: *hi,
                    turns: turns.get(index).copied().unwrap_or(true),
                    span: v.span,
                    index,
                });
            }
        }
        ok
    }
}
