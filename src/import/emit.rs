//! Scenario text: numbers, poses and declarations written so that `resolve` reads back
//! exactly the values given (shortest round-trip decimals, metres and radians).

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use nalgebra::{Isometry3, UnitQuaternion};

use crate::resolve::{Body, Hand, JointUnit, JointValues, PlannerSettings, Robot, Scenario, Shape};

/// A number as the language reads it back bit for bit (Rust prints the shortest
/// round-trip decimal and never an exponent).
pub fn num(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else {
        format!("{v}")
    }
}

pub fn length(v: f64) -> String {
    format!("{}m", num(v))
}

/// `at (x, y, z) rot quat(x, y, z, w)`, the rotation left out when there is none.
pub fn pose(p: &Isometry3<f64>) -> String {
    let t = p.translation.vector;
    let mut s = format!("at ({}, {}, {})", length(t.x), length(t.y), length(t.z));
    if p.rotation != UnitQuaternion::identity() {
        let q = p.rotation.quaternion();
        let _ = write!(s, " rot quat({}, {}, {}, {})", num(q.i), num(q.j), num(q.k), num(q.w));
    }
    s
}

/// A shape's constructor, with paths relative to `dir` (the written file's folder).
pub fn shape(s: &Shape, dir: &Path) -> String {
    match s {
        Shape::Box { size } => format!("box({}, {}, {})", length(size.x), length(size.y), length(size.z)),
        Shape::Cylinder { radius, length: l } => {
            format!("cylinder(radius: {}, length: {})", length(*radius), length(*l))
        }
        Shape::Capsule { radius, length: l } => format!("capsule(radius: {}, length: {})", length(*radius), length(*l)),
        Shape::Sphere { radius } => format!("sphere(radius: {})", length(*radius)),
        Shape::Mesh { file, scale } => {
            let mut m = format!("mesh({})", string(&relative(&file.path, dir)));
            if scale.iter().any(|v| *v != 1.0) {
                let _ = write!(m, " scale ({}, {}, {})", num(scale.x), num(scale.y), num(scale.z));
            }
            m
        }
    }
}

/// A quoted string with the language's escapes.
pub fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Joint values: bare where a bare number means the same for either kind of joint (up to
/// a full turn), else with the unit the cell wrote for that joint.
pub fn joints(values: &[f64], like: Option<&JointValues>) -> String {
    let items: Vec<String> = values
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let unit = like.and_then(|l| l.units.get(k)).map(|(u, _)| *u);
            if v.abs() <= std::f64::consts::PI {
                num(*v)
            } else if unit == Some(JointUnit::Length) {
                length(*v)
            } else {
                format!("{}rad", num(*v))
            }
        })
        .collect();
    format!("[{}]", items.join(", "))
}

/// A body as `KIND NAME at (...) { parts }`: the body's world pose, each part relative to it.
pub fn body(
    out: &mut String,
    kind: &str,
    name: &str,
    pose_world_body: &Isometry3<f64>,
    parts: &[(String, Isometry3<f64>)],
) {
    let _ = writeln!(out, "{kind} {name} {} {{", pose(pose_world_body));
    for (shape, p) in parts {
        let _ = writeln!(out, "    {shape} {}", pose(p));
    }
    out.push_str("}\n");
}

pub fn hand(out: &mut String, h: &Hand, dir: &Path) {
    let _ = writeln!(out, "hand {} {{", h.name);
    let _ = writeln!(out, "    urdf {}", string(&relative(&h.urdf.path, dir)));
    let _ = writeln!(out, "    tcp {}", pose(&h.pose_flange_tcp));
    out.push_str("}\n");
}

/// A robot block with `home` and extra `allow_contact` pairs given by the import.
pub fn robot(out: &mut String, scn: &Scenario, r: &Robot, home: &[f64], extra_pairs: &[(String, String)], dir: &Path) {
    let _ = writeln!(out, "robot {} {{", r.name);
    let _ = writeln!(out, "    urdf {}", string(&relative(&r.urdf.path, dir)));
    let _ = writeln!(out, "    base {}", pose(&r.pose_world_base));
    if let Some(h) = r.hand {
        let _ = writeln!(out, "    hand {}", scn.hands[h.index()].name);
    }
    if let Some((f, _)) = &r.flange {
        let _ = writeln!(out, "    flange {}", string(f));
    }
    let _ = writeln!(out, "    home {}", joints(home, Some(&r.home)));
    if let Some(d) = &r.drop {
        let _ = writeln!(out, "    drop {}", joints(&d.values, Some(&r.home)));
    }
    let pairs = r.allow_contact.iter().map(|p| (p.a.clone(), p.b.clone())).chain(extra_pairs.iter().cloned());
    for (a, b) in pairs {
        let _ = writeln!(out, "    allow_contact {} {}", string(&a), string(&b));
    }
    out.push_str("}\n");
}

pub fn fixed(out: &mut String, b: &Body, dir: &Path) {
    let parts: Vec<(String, Isometry3<f64>)> =
        b.parts.iter().map(|p| (shape(&p.shape, dir), p.pose_body_part)).collect();
    body(out, "fixed", &b.name, &b.pose_world_body, &parts);
}

pub fn planner(out: &mut String, p: &PlannerSettings) {
    out.push_str("planner {\n");
    let _ = writeln!(out, "    seed {}", p.seed);
    let _ = writeln!(out, "    max_samples {}", p.max_samples);
    let _ = writeln!(out, "    resolution {}rad", num(p.resolution));
    let objective = match p.objective {
        crate::resolve::Objective::FewestRemovals => "fewest_removals",
        crate::resolve::Objective::FewestVertices => "fewest_vertices",
    };
    let _ = writeln!(out, "    objective {objective}");
    let _ = writeln!(out, "    neighbours {}", p.neighbours);
    let _ = writeln!(out, "    first_path {}", p.first_path);
    if let Some(t) = p.time_budget {
        let _ = writeln!(out, "    time_budget {}s", num(t));
    }
    let _ = writeln!(out, "    acceleration {}rad/s2", num(p.acceleration));
    let _ = writeln!(out, "    speed {}", num(p.speed));
    out.push_str("}\n");
}

/// `path` relative to the folder `dir`, with `/` separators (both made absolute first).
pub fn relative(path: &Path, dir: &Path) -> String {
    let abs = |p: &Path| std::path::absolute(p).map(|p| normalize(&p)).unwrap_or_else(|_| p.to_path_buf());
    let (path, dir) = (abs(path), abs(dir));
    let p: Vec<Component> = path.components().collect();
    let d: Vec<Component> = dir.components().collect();
    let common = p.iter().zip(&d).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return path.to_string_lossy().replace('\\', "/");
    }
    let mut parts: Vec<String> = d[common..].iter().map(|_| "..".to_string()).collect();
    parts.extend(p[common..].iter().map(|c| c.as_os_str().to_string_lossy().into_owned()));
    parts.join("/")
}

/// `a/./b/../c` -> `a/c`, without touching the file system.
fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_exactly() {
        for v in [0.1, -0.3826834323650898, 1e-9, 123456.789, f64::MIN_POSITIVE, 7.0] {
            assert_eq!(num(v).parse::<f64>().unwrap(), v);
            assert!(!num(v).contains('e'), "{}", num(v));
        }
        assert_eq!(num(-0.0), "0");
    }

    #[test]
    fn relative_paths() {
        assert_eq!(relative(Path::new("/a/b/robots/x.urdf"), Path::new("/a/c")), "../b/robots/x.urdf");
        assert_eq!(relative(Path::new("/a/b/x.urdf"), Path::new("/a/b")), "x.urdf");
        assert_eq!(relative(Path::new("/a/b/./c/../x.urdf"), Path::new("/a")), "b/x.urdf");
    }
}
