//! `check` and `resolve`: the front end and the world on the real file system,
//! reports to stderr.

use std::path::Path;

use miette::Diagnostic;

use super::pipeline::{fail, warn_grouped};
use super::{GlobalOptions, EXIT_OK};
use crate::diag::{render_all, FsLoader, Located, RenderOptions, SourceMap, Span};
use crate::resolve::{self, JointInfo};
use crate::world;

/// Renders resolve errors, sorted by position (long lines fall back to one-line reports).
pub fn render_report(sources: &SourceMap, errs: &[resolve::ResolveError], opts: RenderOptions) -> String {
    render_all(sources, errs, opts)
}

/// An object no robot can grasp: the scenario is valid, but planning will need another way.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("no robot can grasp `{name}`")]
#[diagnostic(code(declutter::world::ungraspable), severity(Warning))]
pub struct Ungraspable {
    pub name: String,
    #[label("declared here")]
    pub span: Span,
    /// Why, robot by robot, then what to do.
    #[help]
    pub help: String,
}

impl Located for Ungraspable {
    fn primary_span(&self) -> Option<Span> {
        Some(self.span)
    }
}

fn plural(n: usize, w: &str) -> String {
    format!("{n} {w}{}", if n == 1 { "" } else { "s" })
}

pub fn check(file: &Path, g: &GlobalOptions) -> u8 {
    let mut sources = SourceMap::new();
    let summary = match resolve::check(file, &FsLoader, &mut sources) {
        Ok(s) => s,
        Err(errs) => return fail(&sources, &errs, g),
    };
    let counts = format!(
        "{}, {}, {}, {}",
        plural(summary.robots, "robot"),
        plural(summary.objects, "object"),
        plural(summary.fixed, "fixed body").replace("bodys", "bodies"),
        plural(summary.grasps, "grasp")
    );
    let name = match (&summary.name, summary.library) {
        (_, true) => format!("{} (a library: no target)", file.display()),
        (Some(n), false) => n.clone(),
        (None, false) => file.display().to_string(),
    };
    // A library's robots, hands and meshes are loaded all the same: a broken URDF in a
    // cell file should not wait for the first scenario that uses it.
    let Some(scn) = summary.scenario else {
        eprintln!("ok: {name} — {counts}");
        return warn_all(&sources, &summary.warnings, g);
    };
    let opts = g.world_options();
    let w = match world::build(&scn, &opts, &FsLoader) {
        Ok(w) => w,
        Err(errs) => return fail(&sources, &errs, g),
    };
    let mut overlapping = world::overlaps(&w);
    overlapping.extend(world::target_collides(&w));
    if !overlapping.is_empty() {
        return fail(&sources, &overlapping, g);
    }
    let report = world::report(&w);
    eprintln!("ok: {name} — {counts}");
    // Where the hand is bolted is a choice (`flange`, else `tool0`, else the last link): show it.
    for (i, r) in scn.robots.iter().enumerate() {
        let id = resolve::RobotId(i as u32);
        let on = match r.hand {
            Some(h) => format!("hand `{}` on", scn.hands[h.index()].name),
            None => "no hand; tool frame".to_string(),
        };
        let fingers = w.finger_names(id);
        let gripper = if fingers.is_empty() {
            String::new()
        } else {
            let names: Vec<String> = fingers.iter().map(|f| format!("`{f}`")).collect();
            let posture = |p: usize| {
                let v: Vec<String> =
                    w.finger_values(id, p).iter().enumerate().map(|(k, x)| w.finger_value_text(id, k, *x)).collect();
                format!("[{}]", v.join(", "))
            };
            let closed = if r.closed.is_some() { format!(", closed {}", posture(1)) } else { String::new() };
            format!("; fingers {} open {}{closed}", names.join(", "), posture(0))
        };
        eprintln!("  {}: {on} `{}`{gripper}", r.name, w.flange_link(id));
    }
    for o in &report.objects {
        let total = scn.object(o.object).grasps.len();
        let per_robot: Vec<String> =
            o.robots.iter().map(|r| format!("{} {}/{total}", r.name, r.grasps.len())).collect();
        eprintln!("  {}: grasps reachable by {}", o.name, per_robot.join(", "));
    }
    let ungraspable: Vec<Ungraspable> = report
        .unreachable()
        .map(|o| {
            let why: Vec<String> = o
                .robots
                .iter()
                .map(|r| format!("{}: {}", r.name, world::why_ungraspable(&w, r.robot, o.object)))
                .collect();
            let help = format!("{}; move the object, add grasps, or add a robot", why.join("; "));
            Ungraspable { name: o.name.clone(), span: scn.object(o.object).body.span, help }
        })
        .collect();
    warn_grouped(&sources, &ungraspable, g);
    warn_all(&sources, &summary.warnings, g)
}

/// Prints the warnings, grouped by code; `check` still succeeds.
fn warn_all(sources: &SourceMap, warnings: &[resolve::ResolveWarning], g: &GlobalOptions) -> u8 {
    warn_grouped(sources, warnings, g);
    EXIT_OK
}

pub fn resolve(file: &Path, g: &GlobalOptions) -> u8 {
    let mut sources = SourceMap::new();
    let scn = match resolve::resolve_with_warnings(file, &FsLoader, &mut sources) {
        Ok((s, warnings)) => {
            warn_all(&sources, &warnings, g);
            s
        }
        Err(errs) => return fail(&sources, &errs, g),
    };
    let opts = g.world_options();
    let mut joints = Vec::new();
    let mut errs = Vec::new();
    for r in &scn.robots {
        match world::load_kinematics(&r.urdf, r.flange.as_ref(), &opts, &FsLoader) {
            Ok(k) => joints.push(
                k.joint_names()
                    .iter()
                    .zip(k.limits())
                    .map(|(n, &(lower, upper))| JointInfo { name: n.clone(), lower, upper })
                    .collect(),
            ),
            Err(e) => errs.extend(e),
        }
    }
    if !errs.is_empty() {
        return fail(&sources, &errs, g);
    }
    print!("{}", resolve::to_yaml_with_joints(&scn, &joints));
    EXIT_OK
}
