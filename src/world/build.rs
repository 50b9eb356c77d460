//! `Scenario` -> [`World`]: load URDFs and meshes, attach hands, place bodies, check
//! the joint vectors, find self-collision pairs worth checking, and check that
//! `home` and `drop` are free.

use std::path::PathBuf;

use nalgebra::Isometry3;

use super::analytic::Analytic;
use super::analytic7::Redundant;
use super::chain::Chain;
use super::check::{self, CheckCtx};
use super::error::WorldError;
use super::fingers::posture;
use super::load::{push_body, Arm, HandModel, LoadCtx};
use super::pair_grid::PairGrid;
use super::robot::{Posture, RobotModel};
use super::scene::{Entry, Owner, Scene};
use super::self_pairs;
use super::shapes::{MeshCache, MeshMode, Placed};
use super::{Blocker, Check, Config, World};
use crate::diag::{Loader, Span};
use crate::resolve::{FileRef, FixedId, ObjectId, Pose, RobotId, Scenario, Target};
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
    /// The labelled check's shortcuts: self-collision pairs that turn on one to three joints
    /// decided by a grid of their distances first, and a body's shapes placed only when its
    /// box is near something. The same verdicts; off only to compare against the plain check.
    pub fast_check: bool,
    /// Inverse kinematics in closed form where the arm allows it (the 6R families, 7R
    /// arms with joint 7 sampled); off, the numeric solver for every arm (to compare).
    pub closed_form_ik: bool,
}

impl Default for WorldOptions {
    fn default() -> Self {
        WorldOptions {
            package_path: Vec::new(),
            mesh_mode: MeshMode::ConvexHull,
            self_collision_samples: 2000,
            fast_check: true,
            closed_form_ik: true,
        }
    }
}

/// Builds the world, or returns every error found (sorted by position).
pub fn build(scn: &Scenario, opts: &WorldOptions, loader: &dyn Loader) -> Result<World, Vec<WorldError>> {
    let mut errs = Vec::new();
    let mut meshes = MeshCache::new(loader, opts.mesh_mode);
    let mut ctx = LoadCtx::new(loader, opts, &mut errs);

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
        let unturned = |p: &parry3d_f64::math::Pose| p.rotation == parry3d_f64::math::Rotation::IDENTITY;
        for (si, sh) in shapes.iter_mut().enumerate() {
            sh.unturned = unturned(&sh.placed.pose) && postures.iter().all(|p| p.poses.get(si).is_none_or(unturned));
        }
        let pose_flange_tcp = hand.map_or(Pose::identity(), |(h, _)| scn.hands[h.index()].pose_flange_tcp);
        let analytic = if opts.closed_form_ik { Analytic::detect(&chain) } else { None };
        let redundant = if opts.closed_form_ik && analytic.is_none() { Redundant::detect(&chain) } else { None };
        let body_frames = RobotModel::frame_boxes(&bodies, &shapes, &postures);
        let ball_packs = RobotModel::ball_packs(&bodies, &shapes, &postures);
        robots.push(RobotModel {
            analytic,
            redundant,
            name: r.name.clone(),
            chain,
            pose_world_base: r.pose_world_base,
            pose_flange_tcp,
            shapes,
            bodies,
            self_pairs: Vec::new(),
            self_grids: Vec::new(),
            body_frames,
            ball_packs,
            fast_check: true,
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
        m.self_pairs = self_pairs::self_pairs(m, &allowed, opts.self_collision_samples, ri as u64);
        m.fast_check = opts.fast_check;
        m.self_grids = match opts.fast_check {
            true => m.self_pairs.iter().map(|&(a, b)| PairGrid::new(m, a, b)).collect(),
            false => m.self_pairs.iter().map(|_| None).collect(),
        };
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
    let mut ctx = LoadCtx::new(loader, opts, &mut errs);
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
