//! `Scenario` -> [`World`]: load URDFs and meshes, attach hands, place bodies, check
//! the joint vectors, find self-collision pairs worth checking, and check that
//! `home` and `drop` are free.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::Isometry3;

use super::analytic::Analytic;
use super::chain::{Chain, ChainError};
use super::check::{self, CheckCtx};
use super::error::WorldError;
use super::fingers::posture;
use super::robot::{Posture, RBody, RShape, RobotModel};
use super::scene::{Entry, Owner, Scene};
use super::shapes::{describe_tried, resolve_uri, Geometry, MeshCache, MeshMode, Placed};
use super::urdf::{self, GeomKind, Model, UrdfProblem};
use super::{Blocker, Check, Config, World};
use crate::diag::{Loader, Span};
use crate::resolve::{FileRef, FixedId, JointUnit, JointValues, ObjectId, Pose, RobotId, Scenario, Shape, Target};
use parry3d_f64::bounding_volume::BoundingVolume as _;

/// How to build a world.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldOptions {
    /// Directories searched for `package://NAME/...`, after the URDF's folder and its ancestors.
    pub package_path: Vec<PathBuf>,
    pub mesh_mode: MeshMode,
    /// Random configurations sampled per robot to find link pairs that always or
    /// never collide (MoveIt setup assistant style); 0 checks every non-adjacent pair.
    pub self_collision_samples: usize,
}

impl Default for WorldOptions {
    fn default() -> Self {
        WorldOptions { package_path: Vec::new(), mesh_mode: MeshMode::ConvexHull, self_collision_samples: 2000 }
    }
}

/// A hand: its shapes in the flange frame, by link, its fingers open.
pub(super) struct HandModel {
    pub(super) bodies: Vec<(String, Vec<Placed>)>,
    pub(super) chain: Chain,
    /// Each shape's link in `chain`, in the order of `bodies` flattened.
    pub(super) shape_links: Vec<usize>,
}

/// Builds the world, or returns every error found (sorted by position).
pub fn build(scn: &Scenario, opts: &WorldOptions, loader: &dyn Loader) -> Result<World, Vec<WorldError>> {
    let mut errs = Vec::new();
    let mut meshes = MeshCache::new(loader, opts.mesh_mode);
    let mut ctx = LoadCtx { loader, opts, errs: &mut errs, urdfs: HashMap::new() };

    let hands: Vec<Option<HandModel>> = scn.hands.iter().map(|h| ctx.load_hand(&h.urdf, &mut meshes)).collect();
    let mut robots = Vec::new();
    // Per robot: the link pairs its package (Drake filter groups, SRDF) never checks.
    let mut package_allowed: Vec<Vec<(String, String)>> = Vec::new();
    for (i, r) in scn.robots.iter().enumerate() {
        let Some(Arm { chain, mut shapes, mut bodies, mut filter_pairs, links }) =
            ctx.load_arm(&r.name, &r.urdf, r.flange.as_ref(), &mut meshes)
        else {
            continue;
        };
        if let Some(f) = &r.srdf {
            filter_pairs.extend(ctx.load_srdf(&r.name, f, &links));
        }
        package_allowed.push(filter_pairs);
        let root_group = chain.links[0].group;
        let flange_group = chain.links[chain.flange].group;
        let hand = r.hand.and_then(|h| hands[h.index()].as_ref().map(|m| (h, m)));
        let hand_start = shapes.len();
        if let Some((h, hm)) = hand {
            let moving = flange_group != root_group;
            // The hand is rigid: one body, named after the hand, for all its links.
            let placed: Vec<Placed> = hm.bodies.iter().flat_map(|(_, p)| p.iter().cloned()).collect();
            push_body(&mut shapes, &mut bodies, &scn.hands[h.index()].name, chain.flange, placed, moving, true);
        }
        let what = |n: &str| n.to_string();
        let home = ctx.joint_values(r.name.as_str(), &what("home"), &r.home, &chain);
        let drop = match &r.drop {
            Some(d) => ctx.joint_values(&r.name, &what("drop"), d, &chain),
            None => home.clone(),
        };
        if let Target::Config { robot, q, .. } = &scn.target {
            // A target that is the home itself (a library's stand-in) was just checked.
            if robot.index() == i && q != &r.home {
                ctx.joint_values(&r.name, "target", q, &chain);
            }
        }
        let hand_model = hand.map(|(_, hm)| hm);
        let (fingers, mut stances, grasp_posture) = ctx.finger_stances(scn, r, &chain, hand_model);
        let closing = super::fingers::closing_stances(&fingers, &mut stances);
        let postures: Vec<Posture> =
            stances.iter().map(|v| posture(&chain, hand_model, &shapes, &bodies, hand_start, v)).collect();
        // The shapes themselves stand open: what reads them directly (the other robots'
        // view of this one at home, the drawing, the pair sampling) sees the empty hand.
        for (sh, p) in shapes.iter_mut().zip(postures.first().map_or(&[][..], |p| &p.poses)) {
            sh.placed.pose = *p;
        }
        let pose_flange_tcp = hand.map_or(Pose::identity(), |(h, _)| scn.hands[h.index()].pose_flange_tcp);
        let analytic = Analytic::detect(&chain);
        robots.push(RobotModel {
            analytic,
            name: r.name.clone(),
            chain,
            pose_world_base: r.pose_world_base,
            pose_flange_tcp,
            shapes,
            bodies,
            self_pairs: Vec::new(),
            allowed_pairs: Vec::new(),
            scene: Scene::new(Vec::new()),
            home: Config(home.unwrap_or_default()),
            drop: Config(drop.unwrap_or_default()),
            fingers,
            postures,
            grasp_posture,
            closing,
        });
    }

    // Bodies of the scene.
    let mut statics = Vec::new();
    for (i, f) in scn.fixed.iter().enumerate() {
        for part in &f.parts {
            if let Some(p) = ctx.part(&part.shape, &part.pose_world_part, &f.name, &mut meshes) {
                statics.push(Entry::new(Owner::Fixed(FixedId(i as u32)), p));
            }
        }
    }
    let mut object_parts = Vec::new();
    for (i, o) in scn.objects.iter().enumerate() {
        let mut parts = Vec::new();
        for part in &o.body.parts {
            if let Some(p) = ctx.part(&part.shape, &part.pose_body_part, &o.body.name, &mut meshes) {
                let world = Placed::new(p.shape.clone(), super::shapes::to_ppose(&o.body.pose_world_body) * p.pose);
                statics.push(Entry::new(Owner::Object(ObjectId(i as u32)), world));
                parts.push(p);
            }
        }
        object_parts.push(parts);
    }
    if !errs.is_empty() {
        errs.sort_by_key(diag_key);
        return Err(errs);
    }

    // Each robot sees the others standing at home.
    let mut at_home: Vec<Vec<Entry>> = Vec::new();
    for (ri, m) in robots.iter().enumerate() {
        let mut links = vec![Isometry3::identity(); m.chain.links.len()];
        m.chain.fk_into(&m.home, &mut links);
        let entries = m
            .shapes
            .iter()
            .map(|s| {
                let pose = super::shapes::to_ppose(&(m.pose_world_base * links[m.bodies[s.body].link])) * s.placed.pose;
                Entry::new(Owner::Robot(RobotId(ri as u32), s.body), Placed::new(s.placed.shape.clone(), pose))
            })
            .collect();
        at_home.push(entries);
    }
    // An `allow_contact` naming no link of the robot is surely a typo: say so.
    let mut errs = Vec::new();
    for (ri, m) in robots.iter().enumerate() {
        for pair in &scn.robots[ri].allow_contact {
            for name in [&pair.a, &pair.b] {
                let known = m.bodies.iter().any(|b| &b.name == name) || m.chain.links.iter().any(|l| &l.name == name);
                if !known {
                    let mut links: Vec<&str> = m.bodies.iter().map(|b| b.name.as_str()).collect();
                    links.dedup();
                    errs.push(WorldError::UnknownLink {
                        robot: m.name.clone(),
                        link: name.clone(),
                        links: links.join(", "),
                        span: pair.span,
                    });
                }
            }
        }
    }
    if !errs.is_empty() {
        return Err(errs);
    }
    for (ri, m) in robots.iter_mut().enumerate() {
        let mut entries: Vec<Entry> = statics.clone();
        for (other, e) in at_home.iter().enumerate() {
            if other != ri {
                entries.extend(e.iter().cloned());
            }
        }
        m.scene = Scene::new(entries);
        let mut allowed: Vec<(String, String)> =
            scn.robots[ri].allow_contact.iter().map(|p| (p.a.clone(), p.b.clone())).collect();
        allowed.extend(package_allowed[ri].iter().cloned());
        m.self_pairs = check::self_pairs(m, &allowed, opts.self_collision_samples, ri as u64);
        m.allowed_pairs = allowed;
    }

    let world = World { scenario: scn.clone(), robots, object_parts };
    // `home` and `drop` must be free of fixed things (touching objects is fine).
    let mut errs = Vec::new();
    for (ri, r) in scn.robots.iter().enumerate() {
        let id = RobotId(ri as u32);
        let mut cases = vec![("home", world.home(id).clone(), r.home.span)];
        if let Some(d) = &r.drop {
            cases.push(("drop", world.drop_config(id).clone(), d.span));
        }
        for (what, q, span) in cases {
            if let Check::Blocked(b) = world.check(id, &q, &CheckCtx::new()) {
                errs.push(WorldError::ConfigCollides {
                    robot: r.name.clone(),
                    what: what.into(),
                    reason: check::describe(&world, id, &b),
                    span,
                    help: collides_help(&b),
                });
            }
        }
    }
    if errs.is_empty() {
        Ok(world)
    } else {
        Err(errs)
    }
}

/// A robot's kinematics and collision model loaded on its own, without a scenario:
/// for listing joints (`declutter resolve`) and for testing URDF files.
pub struct RobotKinematics {
    chain: Chain,
    bodies: Vec<String>,
    shapes: usize,
}

impl RobotKinematics {
    /// Actuated joints, in configuration order.
    pub fn joint_names(&self) -> &[String] {
        &self.chain.joint_names
    }
    /// (lower, upper) per actuated joint.
    pub fn limits(&self) -> &[(f64, f64)] {
        &self.chain.limits
    }
    /// Every link, root first.
    pub fn link_names(&self) -> Vec<&str> {
        self.chain.links.iter().map(|l| l.name.as_str()).collect()
    }
    pub fn flange(&self) -> &str {
        &self.chain.links[self.chain.flange].name
    }
    /// Links with collision geometry.
    pub fn collision_links(&self) -> &[String] {
        &self.bodies
    }
    /// Number of collision shapes over all links.
    pub fn shape_count(&self) -> usize {
        self.shapes
    }
    /// Pose of every link in the robot's base frame.
    ///
    /// # Panics
    /// If `q.len()` is not the number of [`joint_names`](Self::joint_names): a bug
    /// in the caller, not something a URDF can cause.
    pub fn fk_links(&self, q: &[f64]) -> Vec<(String, Pose)> {
        assert!(
            q.len() == self.chain.dof(),
            "configuration has {} values, but the robot has {} joints",
            q.len(),
            self.chain.dof()
        );
        let mut out = vec![Pose::identity(); self.chain.links.len()];
        self.chain.fk_into(q, &mut out);
        self.chain.links.iter().zip(out).map(|(l, p)| (l.name.clone(), p)).collect()
    }
}

/// Loads one robot URDF (and its collision meshes) by itself.
pub fn load_kinematics(
    urdf: &FileRef,
    flange: Option<&(String, Span)>,
    opts: &WorldOptions,
    loader: &dyn Loader,
) -> Result<RobotKinematics, Vec<WorldError>> {
    let mut errs = Vec::new();
    let mut meshes = MeshCache::new(loader, opts.mesh_mode);
    let mut ctx = LoadCtx { loader, opts, errs: &mut errs, urdfs: HashMap::new() };
    let arm = ctx.load_arm("robot", urdf, flange, &mut meshes);
    match arm {
        Some(Arm { chain, shapes, bodies, .. }) if errs.is_empty() => {
            Ok(RobotKinematics { chain, bodies: bodies.into_iter().map(|b| b.name).collect(), shapes: shapes.len() })
        }
        _ => Err(errs),
    }
}

/// A configuration target that hits something fixed, for `check` to report before
/// planning (`compile` reports it as a proof of infeasibility). A library's stand-in
/// target is its home, checked when the world was built.
pub fn target_collides(world: &World) -> Option<WorldError> {
    let scn = &world.scenario;
    let Target::Config { robot, q, .. } = &scn.target else { return None };
    let r = scn.robot(*robot);
    if q.values == r.home.values {
        return None;
    }
    match world.check(*robot, &q.values, &CheckCtx::new()) {
        Check::Blocked(b) => Some(WorldError::ConfigCollides {
            robot: r.name.clone(),
            what: "target".into(),
            reason: check::describe(world, *robot, &b),
            span: q.span,
            help: collides_help(&b),
        }),
        Check::Touches(_) => None,
    }
}

/// What to do about a colliding `home` or `drop`: a self-collision may be a pair the
/// robot's package allows, which declutter learns from its SRDF or an `allow_contact`.
fn collides_help(b: &Blocker) -> String {
    match b {
        Blocker::SelfCollision { link_a, link_b } => format!(
            "choose another configuration; or, if the robot's package allows these links to touch, add its SRDF (`srdf \"ROBOT.srdf\"`, whose `disable_collisions` pairs are not checked) or `allow_contact \"{link_a}\" \"{link_b}\"` to the robot"
        ),
        _ => "a robot's `home`, `drop` and target configuration must be free of fixed bodies, other robots and itself"
            .to_string(),
    }
}

/// An arm's URDF loaded: its chain, collision bodies, the file's own filter pairs and
/// every link name (for checking an SRDF against it).
struct Arm {
    chain: Chain,
    shapes: Vec<RShape>,
    bodies: Vec<RBody>,
    filter_pairs: Vec<(String, String)>,
    links: Vec<String>,
}

/// Objects sunk into a fixed body or into each other deeper than the contact tolerance
/// (resting contact is fine): a scene that cannot be, whose blocking relations would be
/// nonsense. Fixed bodies may overlap each other (a shelf's boards do). One error per
/// pair. `check` reports these; planning does not need them refused.
pub fn overlaps(world: &World) -> Vec<WorldError> {
    let scn = &world.scenario;
    let Some(m) = world.robots.first() else { return Vec::new() };
    // Every robot's scene holds all fixed bodies and objects (and the other robots).
    let statics = &m.scene.entries;
    let name_span = |o: Owner| match o {
        Owner::Fixed(f) => Some((format!("fixed body `{}`", scn.fixed[f.index()].name), scn.fixed[f.index()].span)),
        Owner::Object(o) => {
            Some((format!("object `{}`", scn.objects[o.index()].body.name), scn.objects[o.index()].body.span))
        }
        Owner::Robot(..) => None,
    };
    let mut seen: Vec<(Owner, Owner)> = Vec::new();
    let mut out = Vec::new();
    for a in statics {
        let Owner::Object(_) = a.owner else { continue };
        for b in statics {
            let pair_seen = seen.contains(&(a.owner, b.owner)) || seen.contains(&(b.owner, a.owner));
            if a.owner == b.owner || pair_seen || !a.aabb.intersects(&b.aabb) {
                continue;
            }
            let depth = match parry3d_f64::query::contact(&a.pose, &*a.shape.0, &b.pose, &*b.shape.0, 0.0) {
                Ok(Some(c)) if c.dist < -super::shapes::CONTACT_TOLERANCE => -c.dist,
                _ => continue,
            };
            let (Some((what_a, span)), Some((what_b, other))) = (name_span(a.owner), name_span(b.owner)) else {
                continue;
            };
            seen.push((a.owner, b.owner));
            let (other, elsewhere) = if other.file == span.file { (Some(other), None) } else { (None, Some(other)) };
            out.push(WorldError::BodiesOverlap {
                a: what_a,
                b: what_b,
                depth_mm: depth * 1000.0,
                span,
                other,
                elsewhere,
            });
        }
    }
    out
}

fn diag_key(e: &WorldError) -> Option<Span> {
    crate::diag::Located::primary_span(e)
}

fn push_body(
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
    shapes.extend(placed.into_iter().map(|placed| RShape { body, placed }));
    bodies.push(RBody { name: name.to_string(), link, shapes: start..shapes.len(), moving, holds });
}

pub(super) struct LoadCtx<'a> {
    loader: &'a dyn Loader,
    opts: &'a WorldOptions,
    pub(super) errs: &'a mut Vec<WorldError>,
    /// URDFs parsed so far, by path: two robots of one model (or one hand on two arms)
    /// read and parse it once. Only successes are kept, so a broken file is reported at
    /// every use, as before.
    urdfs: HashMap<PathBuf, Model>,
}

impl LoadCtx<'_> {
    /// The arm's chain and its own collision bodies (no hand).
    fn load_arm(
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
    fn load_srdf(&mut self, robot: &str, file: &FileRef, links: &[String]) -> Vec<(String, String)> {
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

    fn load_urdf(&mut self, file: &FileRef) -> Option<Model> {
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

    fn load_hand(&mut self, file: &FileRef, meshes: &mut MeshCache) -> Option<HandModel> {
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

    fn geoms(&mut self, file: &FileRef, link: &str, geoms: &[urdf::Geom], meshes: &mut MeshCache) -> Vec<Placed> {
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

    fn part(&mut self, shape: &Shape, pose: &Pose, body: &str, meshes: &mut MeshCache) -> Option<Placed> {
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
    fn joint_values(&mut self, robot: &str, what: &str, v: &JointValues, chain: &Chain) -> Option<Vec<f64>> {
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
