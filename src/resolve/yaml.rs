//! The resolved scenario as YAML, for `declutter resolve`: world-frame poses, SI units,
//! numbers rounded to 6 decimals so the output is stable across platforms.
//!
//! Written by hand rather than through a serializer so that poses and vectors stay on
//! one line (`{xyz: [..], rpy: [..]}`) while the rest is block style.

use std::fmt::Write as _;

use super::*;

/// One actuated joint of a loaded robot, for the listing.
#[derive(Debug, Clone, PartialEq)]
pub struct JointInfo {
    pub name: String,
    pub lower: f64,
    pub upper: f64,
}

/// Renders a scenario as YAML (deterministic: declaration order, fixed rounding).
pub fn to_yaml(s: &Scenario) -> String {
    to_yaml_with_joints(s, &[])
}

/// Like [`to_yaml`], listing under each robot the joints its URDF declares
/// (`joints[i]` for robot `i`; the world stage loads them, this stage only prints).
pub fn to_yaml_with_joints(s: &Scenario, joints: &[Vec<JointInfo>]) -> String {
    let mut w = String::new();
    let hand_name = |h: HandId| s.hands.get(h.index()).map_or_else(String::new, |h| h.name.clone());
    match &s.name {
        Some(n) => line(&mut w, 0, "scenario", &q(n)),
        None => line(&mut w, 0, "scenario", "null"),
    }

    header(&mut w, 0, "hands", s.hands.is_empty());
    for h in &s.hands {
        item(&mut w, 2, "name", &q(&h.name));
        line(&mut w, 4, "urdf", &q(&path(&h.urdf)));
        line(&mut w, 4, "tcp_in_flange", &pose(&h.pose_flange_tcp));
    }

    header(&mut w, 0, "robots", s.robots.is_empty());
    for (i, r) in s.robots.iter().enumerate() {
        item(&mut w, 2, "name", &q(&r.name));
        line(&mut w, 4, "urdf", &q(&path(&r.urdf)));
        line(&mut w, 4, "base", &pose(&r.pose_world_base));
        line(&mut w, 4, "hand", &r.hand.map_or_else(|| "null".to_string(), |h| q(&hand_name(h))));
        line(&mut w, 4, "flange", &r.flange.as_ref().map_or_else(|| "null".to_string(), |(f, _)| q(f)));
        line(&mut w, 4, "home", &nums(&r.home.values));
        line(&mut w, 4, "drop", &r.drop.as_ref().map_or_else(|| "null".to_string(), |d| nums(&d.values)));
        // The finger postures only where given, so that a cell without them reads as before.
        for (key, v) in [("open", &r.open), ("closed", &r.closed)] {
            if let Some(v) = v {
                line(&mut w, 4, key, &nums(&v.values));
            }
        }
        let pairs: Vec<String> = r.allow_contact.iter().map(|p| format!("[{}, {}]", q(&p.a), q(&p.b))).collect();
        line(&mut w, 4, "allow_contact", &format!("[{}]", pairs.join(", ")));
        if let Some(js) = joints.get(i) {
            header(&mut w, 4, "joints", js.is_empty());
            for j in js {
                item(&mut w, 6, "name", &q(&j.name));
                line(&mut w, 8, "limits", &nums(&[j.lower, j.upper]));
            }
        }
    }

    header(&mut w, 0, "fixed", s.fixed.is_empty());
    for b in &s.fixed {
        body(&mut w, b);
    }

    header(&mut w, 0, "objects", s.objects.is_empty());
    for o in &s.objects {
        body(&mut w, &o.body);
        header(&mut w, 4, "grasps", o.grasps.is_empty());
        for g in &o.grasps {
            item(&mut w, 6, "name", &q(&g.name));
            line(&mut w, 8, "tcp", &pose(&g.pose_world_tcp));
            line(&mut w, 8, "approach", &num(g.approach));
            if let Some((width, _)) = g.width {
                line(&mut w, 8, "width", &num(width));
            }
            let hands = match &g.hands {
                None => "all".to_string(),
                Some(hs) => format!("[{}]", hs.iter().map(|h| q(&hand_name(*h))).collect::<Vec<_>>().join(", ")),
            };
            line(&mut w, 8, "hands", &hands);
        }
    }

    header(&mut w, 0, "target", false);
    match &s.target {
        Target::Object { object, .. } => {
            let name = s.objects.get(object.index()).map_or_else(String::new, |o| o.body.name.clone());
            line(&mut w, 2, "object", &q(&name));
        }
        Target::Config { robot, q: values, .. } => {
            let name = s.robots.get(robot.index()).map_or_else(String::new, |r| r.name.clone());
            line(&mut w, 2, "robot", &q(&name));
            line(&mut w, 2, "at", &nums(&values.values));
        }
    }

    let p = &s.planner;
    header(&mut w, 0, "planner", false);
    line(&mut w, 2, "seed", &p.seed.to_string());
    line(&mut w, 2, "max_samples", &p.max_samples.to_string());
    line(&mut w, 2, "resolution", &num(p.resolution));
    let objective = match p.objective {
        Objective::FewestRemovals => "fewest_removals",
        Objective::FewestVertices => "fewest_vertices",
    };
    line(&mut w, 2, "objective", objective);
    line(&mut w, 2, "time_budget", &p.time_budget.map_or_else(|| "null".to_string(), num));
    line(&mut w, 2, "neighbours", &p.neighbours.to_string());
    line(&mut w, 2, "first_path", if p.first_path { "true" } else { "false" });
    line(&mut w, 2, "acceleration", &num(p.acceleration));
    line(&mut w, 2, "speed", &num(p.speed));
    w
}

fn body(w: &mut String, b: &Body) {
    item(w, 2, "name", &q(&b.name));
    line(w, 4, "pose", &pose(&b.pose_world_body));
    header(w, 4, "parts", b.parts.is_empty());
    for p in &b.parts {
        let shape = match &p.shape {
            Shape::Box { size } => ("box", format!("{{size: {}}}", nums(size.as_slice()))),
            Shape::Cylinder { radius, length } => {
                ("cylinder", format!("{{radius: {}, length: {}}}", num(*radius), num(*length)))
            }
            Shape::Capsule { radius, length } => {
                ("capsule", format!("{{radius: {}, length: {}}}", num(*radius), num(*length)))
            }
            Shape::Sphere { radius } => ("sphere", format!("{{radius: {}}}", num(*radius))),
            Shape::Mesh { file, scale } => {
                ("mesh", format!("{{file: {}, scale: {}}}", q(&path(file)), nums(scale.as_slice())))
            }
        };
        item(w, 6, shape.0, &shape.1);
        line(w, 8, "pose", &pose(&p.pose_world_part));
    }
}

fn line(w: &mut String, indent: usize, key: &str, value: &str) {
    let _ = writeln!(w, "{:indent$}{key}: {value}", "");
}

/// The first line of a list item: `- key: value`, at `indent` (later keys go at `indent + 2`).
fn item(w: &mut String, indent: usize, key: &str, value: &str) {
    let _ = writeln!(w, "{:indent$}- {key}: {value}", "");
}

fn header(w: &mut String, indent: usize, key: &str, empty: bool) {
    if empty {
        let _ = writeln!(w, "{:indent$}{key}: []", "");
    } else {
        let _ = writeln!(w, "{:indent$}{key}:", "");
    }
}

/// A double-quoted YAML string (JSON escaping is valid YAML).
fn q(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".to_string())
}

fn path(f: &FileRef) -> String {
    f.path.display().to_string().replace('\\', "/")
}

/// Rounds to 6 decimals and turns `-0` into `0`.
fn round(x: f64) -> f64 {
    let r = (x * 1e6).round() / 1e6;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{}", round(x))
    } else {
        ".nan".to_string()
    }
}

fn nums(xs: &[f64]) -> String {
    format!("[{}]", xs.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", "))
}

/// An angle rounded like [`num`], with -pi printed as pi so half turns print one way.
fn angle(a: f64) -> String {
    let r = round(a);
    if r <= -round(std::f64::consts::PI) {
        num(-r)
    } else {
        num(r)
    }
}

fn pose(p: &Pose) -> String {
    let t = p.translation.vector;
    let (r, pi, y) = p.rotation.euler_angles();
    format!("{{xyz: [{}, {}, {}], rpy: [{}, {}, {}]}}", num(t.x), num(t.y), num(t.z), angle(r), angle(pi), angle(y))
}
