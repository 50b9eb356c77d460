//! Import: a MoveIt planning scene (and motion-plan request) -> scenario text.
//!
//! In: the scene's YAML (boxes, spheres, cylinders with MoveIt's `[height, radius]`,
//! meshes; each object's `pose` composed with its shapes' poses; quaternions), an
//! optional request (start state, joint goal), and optionally a cell (a resolved library
//! with hands, robots, fixed bodies and a planner block) whose robots the request's
//! joints are matched to by name. Out: the text of a scenario, the STL files of the
//! scene's meshes, and warnings for everything not imported. A leaf beside the pipeline:
//! it reads `resolve`'s types and writes text that `resolve` reads; nothing imports it
//! but `driver`.
//!
//! With a cell, its hands, robots, fixed bodies and planner block are written into the
//! scenario (not `use`d): the start state becomes each robot's `home`, and the allowed
//! collision matrix's pairs of one robot's links become its `allow_contact` lines, and
//! neither can be added to a robot declared in another file.

mod emit;
mod error;
mod scene;

pub use error::{ImportError, ImportWarning};

use std::collections::{BTreeSet, HashSet};
use std::fmt::Write as _;
use std::path::Path;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};

use crate::diag::{FileId, SourceMap, Span};
use crate::resolve::Scenario;
use scene::{CollisionObject, MotionPlanRequest, PlanningScene, PoseMsg};

/// A cell's robots as the import needs them beyond the resolved scenario.
pub struct CellRobot {
    /// Joint names of the robot's chain, in `home` order.
    pub joints: Vec<String>,
    /// Every link name of its URDF (for the allowed collision matrix).
    pub links: Vec<String>,
}

pub struct Options<'a> {
    /// The resolved cell (a library's stand-in scenario) and, per robot, its joints and links.
    pub cell: Option<(&'a Scenario, &'a [CellRobot])>,
    /// Objects whose id matches become removable `object`s; the rest are `fixed`.
    pub removable: Option<&'a regex::Regex>,
    /// The folder the scenario is written to: paths in it are relative to this.
    pub out_dir: &'a Path,
    /// The stem of mesh files written beside the scenario (`STEM_ID.stl`).
    pub mesh_stem: &'a str,
}

/// A mesh file to write beside the scenario.
pub struct MeshFile {
    pub name: String,
    pub stl: Vec<u8>,
}

pub struct Imported {
    pub dcl: String,
    pub meshes: Vec<MeshFile>,
    pub warnings: Vec<ImportWarning>,
}

/// Reads the scene (and request) in `sources` and writes the scenario.
pub fn moveit(
    sources: &SourceMap,
    scene: FileId,
    request: Option<FileId>,
    opts: &Options,
) -> Result<Imported, Vec<ImportError>> {
    let mut im = Importer { sources, warnings: Vec::new(), errors: Vec::new() };
    let doc: PlanningScene = im.parse(scene, "planning scene").map_err(|e| vec![e])?;
    let req: Option<MotionPlanRequest> = match request {
        Some(f) => Some(im.parse(f, "motion-plan request").map_err(|e| vec![e])?),
        None => None,
    };
    if req.is_some() && opts.cell.is_none() {
        return Err(vec![ImportError::RequestWithoutCell]);
    }
    let req = req.as_ref().zip(request);
    let out = im.write(scene, &doc, req, opts);
    if im.errors.is_empty() {
        out.map(|(dcl, meshes)| Imported { dcl, meshes, warnings: im.warnings }).ok_or_else(Vec::new)
    } else {
        Err(im.errors)
    }
}

struct Importer<'a> {
    sources: &'a SourceMap,
    warnings: Vec<ImportWarning>,
    errors: Vec<ImportError>,
}

impl Importer<'_> {
    fn text(&self, f: FileId) -> &str {
        self.sources.get(f).map_or("", |s| s.text.as_str())
    }

    fn name(&self, f: FileId) -> String {
        self.sources.get(f).map_or_else(String::new, |s| s.name.clone())
    }

    /// The rest of the line from a YAML location, as a span.
    fn span(&self, f: FileId, loc: &serde_saphyr::Location) -> Option<Span> {
        let start = self.sources.offset_of(f, loc.line(), loc.column())?;
        let rest = self.text(f).get(start..)?;
        // A scalar ends at the line's end, or in a flow collection at `,`, `}` or `]`.
        let len = rest.find(['\n', ',', '}', ']']).unwrap_or(rest.len());
        let len = rest[..len].trim_end().len().max(1);
        Some(Span::new(f, start, start + len))
    }

    /// Typed, then as a tree to name every field that carries data but is not imported.
    fn parse<T: serde::de::DeserializeOwned>(&mut self, f: FileId, what: &'static str) -> Result<T, ImportError> {
        let text = self.text(f);
        let yaml_err = |e: serde_saphyr::Error| {
            let span = e.location().and_then(|l| self.span(f, &l));
            let message = e.to_string().lines().next().unwrap_or("").to_string();
            ImportError::Yaml { path: self.name(f), what, message, span }
        };
        let typed: T = serde_saphyr::from_str(text).map_err(yaml_err)?;
        let tree: serde_json::Value = serde_saphyr::from_str(text).map_err(yaml_err)?;
        let request = what != "planning scene";
        self.warnings.extend(
            scene::unsupported(&tree, request).into_iter().map(|field| ImportWarning::UnsupportedField { field }),
        );
        Ok(typed)
    }

    fn write(
        &mut self,
        f: FileId,
        doc: &PlanningScene,
        req: Option<(&MotionPlanRequest, FileId)>,
        opts: &Options,
    ) -> Option<(String, Vec<MeshFile>)> {
        let mut out = String::new();
        let _ = writeln!(out, "// Imported from {} by `declutter import moveit`.", self.name(f));
        let mut taken: HashSet<String> = HashSet::new();
        let goal = match (req, &opts.cell) {
            (Some((r, rf)), Some((cell, robots))) => Some(self.goal(r, rf, cell, robots)?),
            _ => None,
        };
        // Without a goal there is no target: the file is a library, which has no `scenario` line.
        if let Some(n) = doc.name.as_deref().filter(|n| !n.is_empty()) {
            match goal {
                Some(_) => {
                    let _ = writeln!(out, "scenario {}", emit::string(n));
                }
                None => {
                    let _ =
                        writeln!(out, "// The scene `{}`; with `--request`, a scenario of it.", n.replace('\n', " "));
                }
            }
        }
        if let Some((cell, robots)) = &opts.cell {
            self.cell(&mut out, doc, req.map(|(r, _)| r), cell, robots, opts.out_dir, &mut taken);
        } else if let Some(acm) = &doc.allowed_collision_matrix {
            for (a, b) in allowed_pairs(acm) {
                self.warnings.push(ImportWarning::AcmPair { a, b, why: "no `--cell` names the robots".to_string() });
            }
        }
        let mut meshes = Vec::new();
        let mut frames = BTreeSet::new();
        let mut removable = 0;
        let objects = doc.world.as_ref().map_or(&[][..], |w| &w.collision_objects[..]);
        for o in objects {
            let span = self.span(f, &o.id.referenced);
            if o.operation != 0 {
                self.warnings.push(ImportWarning::Operation { id: o.id.value.clone(), operation: o.operation, span });
                continue;
            }
            if !matches!(o.header.frame_id.trim_start_matches('/'), "" | "world" | "map") {
                frames.insert(o.header.frame_id.clone());
            }
            let name = self.unique_name(&o.id.value, span, &mut taken);
            let Some(parts) = self.parts(f, o, &name, opts.mesh_stem, &mut meshes) else { continue };
            if parts.is_empty() {
                continue;
            }
            let kind = if opts.removable.is_some_and(|re| re.is_match(&o.id.value)) {
                removable += 1;
                "object"
            } else {
                "fixed"
            };
            let pose = o.pose.map_or_else(Isometry3::identity, |p| self.pose(&p, &o.id.value, span));
            emit::body(&mut out, kind, &name, &pose, &parts);
        }
        self.warnings.extend(frames.into_iter().map(|frame| ImportWarning::Frame { frame }));
        if removable > 0 {
            self.warnings.push(ImportWarning::NoGrasps { count: removable });
        }
        if let Some((robot, q)) = goal {
            let like = opts.cell.as_ref().and_then(|(c, _)| c.robots.iter().find(|r| r.name == robot)).map(|r| &r.home);
            let _ = writeln!(out, "target {robot} at {}", emit::joints(&q, like));
        }
        Some((out, meshes))
    }

    /// The cell's hands, robots (home from the start state, allowed pairs added), fixed
    /// bodies and planner block.
    #[allow(clippy::too_many_arguments)]
    fn cell(
        &mut self,
        out: &mut String,
        doc: &PlanningScene,
        req: Option<&MotionPlanRequest>,
        cell: &Scenario,
        robots: &[CellRobot],
        dir: &Path,
        taken: &mut HashSet<String>,
    ) {
        taken.extend(cell.hands.iter().map(|h| h.name.clone()));
        taken.extend(cell.robots.iter().map(|r| r.name.clone()));
        taken.extend(cell.fixed.iter().map(|b| b.name.clone()));
        // The request's start state wins over the scene's robot state.
        let state = req.and_then(|r| r.start_state.as_ref()).or(doc.robot_state.as_ref()).map(|s| &s.joint_state);
        if let Some(s) = state {
            if s.name.len() != s.position.len() {
                self.errors.push(ImportError::JointState { names: s.name.len(), positions: s.position.len() });
            }
        }
        let mut extra: Vec<Vec<(String, String)>> = vec![Vec::new(); cell.robots.len()];
        if let Some(acm) = &doc.allowed_collision_matrix {
            for (a, b) in allowed_pairs(acm) {
                let has = |r: &CellRobot, l: &str| r.links.iter().any(|x| x == l);
                let both: Vec<usize> =
                    (0..robots.len()).filter(|&i| has(&robots[i], &a) && has(&robots[i], &b)).collect();
                if both.is_empty() {
                    let stranger = [&a, &b].into_iter().find(|l| !robots.iter().any(|r| has(r, l)));
                    let why = match stranger {
                        Some(l) => format!("`{l}` is not a link of a robot of the cell"),
                        None => "they are links of two robots".to_string(),
                    };
                    self.warnings.push(ImportWarning::AcmPair { a, b, why });
                    continue;
                }
                for i in both {
                    let known =
                        cell.robots[i].allow_contact.iter().any(|p| (p.a == a && p.b == b) || (p.a == b && p.b == a));
                    if !known {
                        extra[i].push((a.clone(), b.clone()));
                    }
                }
            }
        }
        let mut unused: Vec<String> = Vec::new();
        if let Some(s) = state {
            for n in &s.name {
                match owners(robots, n).len() {
                    0 => unused.push(n.clone()),
                    1 => {}
                    _ => self.errors.push(ambiguous(cell, robots, n)),
                }
            }
        }
        if !unused.is_empty() {
            self.warnings.push(ImportWarning::UnsupportedField {
                field: format!("start state of joints no cell robot has: {}", unused.join(", ")),
            });
        }
        for h in &cell.hands {
            emit::hand(out, h, dir);
        }
        for (k, r) in cell.robots.iter().enumerate() {
            let mut home = r.home.values.clone();
            if let (Some(s), Some(cr)) = (state, robots.get(k)) {
                for (n, v) in s.name.iter().zip(&s.position) {
                    if let Some(i) = cr.joints.iter().position(|j| j == n) {
                        if let Some(slot) = home.get_mut(i) {
                            *slot = *v;
                        }
                    }
                }
            }
            emit::robot(out, cell, r, &home, &extra[k], dir);
        }
        for b in &cell.fixed {
            emit::fixed(out, b, dir);
        }
        let mut planner = cell.planner.clone();
        if let Some(speed) = req.and_then(|r| self.speed(r)) {
            planner.speed = speed;
        }
        emit::planner(out, &planner);
    }

    /// `speed` from the request's scaling factors: the smaller of those set (MoveIt's 0
    /// is unset), so neither scaled limit is exceeded; `None` when neither is set.
    fn speed(&mut self, r: &MotionPlanRequest) -> Option<f64> {
        let mut factor = |field: &str, value: f64| {
            if value == 0.0 {
                None
            } else if value > 0.0 && value <= 1.0 {
                Some(value)
            } else {
                self.warnings.push(ImportWarning::ScalingRange { field: field.to_string(), value });
                None
            }
        };
        let v = factor("max_velocity_scaling_factor", r.max_velocity_scaling_factor);
        let a = factor("max_acceleration_scaling_factor", r.max_acceleration_scaling_factor);
        match (v, a) {
            (Some(v), Some(a)) if v != a => {
                let speed = v.min(a);
                self.warnings.push(ImportWarning::Scaling { velocity: v, acceleration: a, speed });
                Some(speed)
            }
            (v, a) => v.or(a),
        }
    }

    /// The robot and configuration of the request's first joint goal.
    fn goal(
        &mut self,
        req: &MotionPlanRequest,
        f: FileId,
        cell: &Scenario,
        robots: &[CellRobot],
    ) -> Option<(String, Vec<f64>)> {
        let Some(c) = req.goal_constraints.first().filter(|c| !c.joint_constraints.is_empty()) else {
            self.errors.push(ImportError::NoGoal);
            return None;
        };
        let mut owner: BTreeSet<usize> = BTreeSet::new();
        for jc in &c.joint_constraints {
            match owners(robots, &jc.joint_name.value)[..] {
                [i] => {
                    owner.insert(i);
                }
                [_, _, ..] => {
                    self.errors.push(ambiguous(cell, robots, &jc.joint_name.value));
                    return None;
                }
                [] => {
                    let all: Vec<&str> = robots.iter().flat_map(|r| r.joints.iter().map(String::as_str)).collect();
                    let help = match crate::syntax::did_you_mean(&jc.joint_name.value, all.iter().copied()) {
                        Some(s) => format!("did you mean `{s}`?"),
                        None => format!("the cell's robots have {}", all.join(", ")),
                    };
                    let span = self.span(f, &jc.joint_name.referenced);
                    self.errors.push(ImportError::UnknownJoint { joint: jc.joint_name.value.clone(), span, help });
                }
            }
        }
        if owner.len() > 1 {
            let names: Vec<&str> = owner.iter().map(|&i| cell.robots[i].name.as_str()).collect();
            self.errors.push(ImportError::SeveralRobots { robots: names.join(", ") });
            return None;
        }
        let i = *owner.iter().next()?;
        let mut q = Vec::with_capacity(robots[i].joints.len());
        for j in &robots[i].joints {
            match c.joint_constraints.iter().find(|jc| &jc.joint_name.value == j) {
                Some(jc) => q.push(jc.position),
                None => {
                    self.errors
                        .push(ImportError::IncompleteGoal { robot: cell.robots[i].name.clone(), joint: j.clone() });
                    return None;
                }
            }
        }
        Some((cell.robots[i].name.clone(), q))
    }

    /// Each primitive and mesh as (constructor, pose in the object); `None` after an error.
    fn parts(
        &mut self,
        f: FileId,
        o: &CollisionObject,
        name: &str,
        stem: &str,
        meshes: &mut Vec<MeshFile>,
    ) -> Option<Vec<(String, Isometry3<f64>)>> {
        let id = o.id.value.as_str();
        let span = self.span(f, &o.id.referenced);
        if o.primitives.len() != o.primitive_poses.len() || o.meshes.len() != o.mesh_poses.len() {
            self.errors.push(ImportError::PoseCount {
                id: id.to_string(),
                shapes: o.primitives.len() + o.meshes.len(),
                poses: o.primitive_poses.len() + o.mesh_poses.len(),
                span,
            });
            return None;
        }
        let mut parts = Vec::new();
        for (p, pose) in o.primitives.iter().zip(&o.primitive_poses) {
            let pspan = self.span(f, &p.kind.referenced);
            let d = &p.dimensions;
            let (shape, want, n) = match p.kind.value {
                1 => ("box", "3 values [x, y, z]", 3),
                2 => ("sphere", "1 value [radius]", 1),
                3 => ("cylinder", "2 values [height, radius]", 2),
                4 => {
                    self.warnings.push(ImportWarning::Cone { id: id.to_string(), span: pspan });
                    continue;
                }
                kind => {
                    self.errors.push(ImportError::UnknownPrimitive { id: id.to_string(), kind, span: pspan });
                    return None;
                }
            };
            if d.len() != n {
                self.errors.push(ImportError::Dimensions {
                    id: id.to_string(),
                    shape,
                    expected: want,
                    found: d.len(),
                    span: pspan,
                });
                return None;
            }
            if let Some(bad) = d.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
                self.errors.push(ImportError::BadValue { id: id.to_string(), value: bad.to_string(), span: pspan });
                return None;
            }
            let ctor = match p.kind.value {
                1 => format!("box({}, {}, {})", emit::length(d[0]), emit::length(d[1]), emit::length(d[2])),
                2 => format!("sphere(radius: {})", emit::length(d[0])),
                // MoveIt's cylinder is [height, radius], about z like declutter's.
                _ => format!("cylinder(radius: {}, length: {})", emit::length(d[1]), emit::length(d[0])),
            };
            parts.push((ctor, self.pose(pose, id, span)));
        }
        for (k, (m, pose)) in o.meshes.iter().zip(&o.mesh_poses).enumerate() {
            let file = format!("{stem}_{name}{}.stl", if o.meshes.len() > 1 { format!("_{k}") } else { String::new() });
            let stl = self.stl(f, m, id)?;
            meshes.push(MeshFile { name: file.clone(), stl });
            parts.push((format!("mesh({})", emit::string(&file)), self.pose(pose, id, span)));
        }
        Some(parts)
    }

    /// A binary STL of a `shape_msgs/Mesh` (single precision, as STL is).
    fn stl(&mut self, f: FileId, m: &scene::MeshMsg, id: &str) -> Option<Vec<u8>> {
        let mut out = vec![0u8; 80];
        out[..25].copy_from_slice(b"declutter import (MoveIt)");
        out.extend_from_slice(&(m.triangles.len() as u32).to_le_bytes());
        for t in &m.triangles {
            let idx = &t.vertex_indices.value;
            let mut v = [Vector3::zeros(); 3];
            if idx.len() != 3 {
                let span = self.span(f, &t.vertex_indices.referenced);
                self.errors.push(ImportError::Dimensions {
                    id: id.to_string(),
                    shape: "mesh triangle",
                    expected: "3 vertex indices",
                    found: idx.len(),
                    span,
                });
                return None;
            }
            for (slot, &i) in v.iter_mut().zip(idx) {
                let Some(p) = m.vertices.get(i as usize) else {
                    let span = self.span(f, &t.vertex_indices.referenced);
                    self.errors.push(ImportError::MeshIndex {
                        id: id.to_string(),
                        index: i,
                        count: m.vertices.len(),
                        span,
                    });
                    return None;
                };
                *slot = Vector3::new(p.x, p.y, p.z);
            }
            let n = (v[1] - v[0]).cross(&(v[2] - v[0])).try_normalize(0.0).unwrap_or_else(Vector3::zeros);
            for c in std::iter::once(n).chain(v) {
                for x in c.iter() {
                    out.extend_from_slice(&(*x as f32).to_le_bytes());
                }
            }
            out.extend_from_slice(&[0, 0]);
        }
        Some(out)
    }

    fn pose(&mut self, p: &PoseMsg, id: &str, span: Option<Span>) -> Isometry3<f64> {
        let o = p.orientation;
        let q = Quaternion::new(o.w, o.x, o.y, o.z);
        let rotation = if q.norm() == 0.0 {
            self.warnings.push(ImportWarning::ZeroQuaternion { id: id.to_string(), span });
            UnitQuaternion::identity()
        } else {
            UnitQuaternion::from_quaternion(q)
        };
        let t = p.position;
        Isometry3::from_parts(Translation3::new(t.x, t.y, t.z), rotation)
    }

    /// A declutter name for a MoveIt id: invalid characters become `_`, a leading digit
    /// gets `_` before it, and a taken name a number after it; renaming is warned of.
    fn unique_name(&mut self, id: &str, span: Option<Span>, taken: &mut HashSet<String>) -> String {
        let mut base: String =
            id.chars().map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' }).take(200).collect();
        if base.is_empty() || base.starts_with(|c: char| c.is_ascii_digit()) {
            base.insert(0, '_');
        }
        let mut name = base.clone();
        let mut k = 2;
        while taken.contains(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        if name != id {
            self.warnings.push(ImportWarning::Renamed { id: id.to_string(), name: name.clone(), span });
        }
        taken.insert(name.clone());
        name
    }
}

/// The cell robots that have a joint of this name.
fn owners(robots: &[CellRobot], joint: &str) -> Vec<usize> {
    (0..robots.len()).filter(|&i| robots[i].joints.iter().any(|j| j == joint)).collect()
}

fn ambiguous(cell: &Scenario, robots: &[CellRobot], joint: &str) -> ImportError {
    let names: Vec<&str> = owners(robots, joint).into_iter().map(|i| cell.robots[i].name.as_str()).collect();
    ImportError::AmbiguousJoint { joint: joint.to_string(), robots: names.join(", ") }
}

/// Pairs (i < j) the matrix allows to touch, in either direction, by name.
fn allowed_pairs(acm: &scene::Acm) -> Vec<(String, String)> {
    let n = acm.entry_names.len();
    let at = |i: usize, j: usize| acm.entry_values.get(i).and_then(|r| r.enabled.get(j)).copied().unwrap_or(false);
    let mut out = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            if at(i, j) || at(j, i) {
                out.push((acm.entry_names[i].clone(), acm.entry_names[j].clone()));
            }
        }
    }
    out
}
