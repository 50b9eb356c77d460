//! (World, Timeline, violations) -> the one JSON blob the page draws: every body's
//! shapes in its own frame, and per keyframe the world pose of every body that moves.

use serde::Serialize;

use super::timeline::{EventKind, Timeline};
use crate::resolve::{FixedId, ObjectId, Pose, RobotId, Target};
use crate::schedule::Schedule;
use crate::verify::{Location, Violation};
use crate::world::{Drawable, DrawnShape, World, OPEN_POSTURE};

/// Time between keyframes (s). A joint turning at 2 rad/s turns 0.08 rad between two:
/// the page's straight interpolation of a link 1 m out cuts the arc by under 1 mm.
pub const KEYFRAME_STEP: f64 = 0.04;
/// Most keyframes a page holds: a longer schedule gets a longer step, so the file stays
/// small (about 1.2 kB per keyframe for two arms and a few objects).
pub const MAX_KEYFRAMES: usize = 2500;

const ROBOT_COLOURS: [&str; 6] = ["#4f83c2", "#c25b4f", "#5aa05a", "#8f6fb8", "#d99a3b", "#8c6d5a"];
const HAND_COLOURS: [&str; 6] = ["#2c5a91", "#8f3328", "#33702f", "#5e4487", "#a86b17", "#5e4537"];

/// Everything the page shows.
#[derive(Serialize)]
pub struct SceneData {
    pub scenario: String,
    /// `cell` (no schedule), `verified`, or `violations`.
    pub status: &'static str,
    pub bodies: Vec<BodyData>,
    pub robots: Vec<String>,
    /// Keyframe times are `k * step`, for `k` in `0..frames`.
    pub step: f64,
    pub frames: usize,
    /// Per keyframe, per track: x, y, z, qx, qy, qz, qw (world frame).
    pub poses: Vec<Vec<f64>>,
    pub duration: f64,
    pub actions: Vec<ActionData>,
    pub violations: Vec<ViolationData>,
}

#[derive(Serialize)]
pub struct BodyData {
    pub name: String,
    /// `link`, `hand`, `tcp`, `fixed` or `object`.
    pub kind: &'static str,
    /// For objects: `target`, `removed` or `untouched`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub role: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub robot: Option<usize>,
    pub colour: &'static str,
    /// Index into each keyframe's poses; `None` for a body that never moves.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub track: Option<usize>,
    /// The pose of a body without a track.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pose: Option<[f64; 7]>,
    /// When an object is picked up and let go of (it is hidden from then on).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grasped_at: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub released_at: Option<f64>,
    pub shapes: Vec<ShapeData>,
}

/// One shape in its body's frame. Round shapes have their axis along y (three.js's).
#[derive(Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ShapeData {
    Box {
        size: [f64; 3],
        pose: [f64; 7],
    },
    Cylinder {
        radius: f64,
        length: f64,
        pose: [f64; 7],
    },
    Sphere {
        radius: f64,
        pose: [f64; 7],
    },
    /// Vertices flat (x, y, z, …) to 0.1 mm, triangles flat.
    Mesh {
        vertices: Vec<f64>,
        triangles: Vec<u32>,
        pose: [f64; 7],
    },
}

#[derive(Serialize)]
pub struct ActionData {
    pub id: u32,
    pub robot: String,
    pub object: Option<String>,
    pub after: Vec<u32>,
    pub start: f64,
    pub end: f64,
}

#[derive(Serialize)]
pub struct ViolationData {
    pub text: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub action: Option<u32>,
    /// When, and where (the acting robot's TCP then), if the violation has a place.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at: Option<[f64; 3]>,
}

/// Rounds to 0.1 mm (or 1e-4 of a unit quaternion): enough to draw, a third of the bytes.
fn r4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

fn pose7(p: &Pose) -> [f64; 7] {
    let t = p.translation.vector;
    let q = p.rotation.quaternion().coords;
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(r4)
}

fn shape(s: &DrawnShape) -> ShapeData {
    let pose = pose7(&s.pose);
    match &s.shape {
        Drawable::Box { size } => ShapeData::Box { size: size.map(r4), pose },
        Drawable::Cylinder { radius, length } => ShapeData::Cylinder { radius: r4(*radius), length: r4(*length), pose },
        Drawable::Sphere { radius } => ShapeData::Sphere { radius: r4(*radius), pose },
        Drawable::Mesh { vertices, triangles } => ShapeData::Mesh {
            vertices: vertices.iter().flat_map(|v| v.map(r4)).collect(),
            triangles: triangles.iter().flatten().copied().collect(),
            pose,
        },
    }
}

/// Builds the blob. `schedule` is `None` to show the cell alone.
pub fn build(world: &World, schedule: Option<&Schedule>, timeline: &Timeline, violations: &[Violation]) -> SceneData {
    let scn = world.scenario();
    let mut bodies = Vec::new();
    let mut tracks = 0;
    let mut next_track = || {
        tracks += 1;
        Some(tracks - 1)
    };
    for (i, f) in scn.fixed.iter().enumerate() {
        let shapes = world.drawn_fixed(FixedId(i as u32)).iter().map(shape).collect();
        bodies.push(BodyData {
            name: f.name.clone(),
            kind: "fixed",
            role: None,
            robot: None,
            colour: if f.name == "table" { "#cdbf9f" } else { "#a7a9ac" },
            track: None,
            pose: Some(pose7(&Pose::identity())),
            grasped_at: None,
            released_at: None,
            shapes,
        });
    }
    // (body index, robot, link, index among the robot's drawn bodies) of every robot
    // body, and the TCP body per robot.
    let mut links: Vec<(usize, RobotId, usize, usize)> = Vec::new();
    let mut tcps: Vec<(usize, RobotId)> = Vec::new();
    for r in scn.robot_ids() {
        let c = r.index() % ROBOT_COLOURS.len();
        for (k, b) in world.drawn_robot(r).into_iter().enumerate() {
            let hand = scn.robot(r).hand.is_some_and(|h| scn.hands[h.index()].name == b.name);
            links.push((bodies.len(), r, b.link, k));
            bodies.push(BodyData {
                name: format!("{} {}", scn.robot(r).name, b.name),
                kind: if hand { "hand" } else { "link" },
                role: None,
                robot: Some(r.index()),
                colour: if hand { HAND_COLOURS[c] } else { ROBOT_COLOURS[c] },
                track: next_track(),
                pose: None,
                grasped_at: None,
                released_at: None,
                shapes: b.shapes.iter().map(shape).collect(),
            });
        }
        tcps.push((bodies.len(), r));
        bodies.push(BodyData {
            name: format!("{} TCP", scn.robot(r).name),
            kind: "tcp",
            role: None,
            robot: Some(r.index()),
            colour: HAND_COLOURS[c],
            track: next_track(),
            pose: None,
            grasped_at: None,
            released_at: None,
            shapes: Vec::new(),
        });
    }
    let removed: Vec<&str> = schedule.map(|s| s.removed.iter().map(String::as_str).collect()).unwrap_or_default();
    let mut objects: Vec<(usize, ObjectId)> = Vec::new();
    for o in scn.object_ids() {
        let name = &scn.object(o).body.name;
        let target = matches!(scn.target, Target::Object { object, .. } if object == o);
        let role = if target {
            "target"
        } else if removed.contains(&name.as_str()) {
            "removed"
        } else {
            "untouched"
        };
        let at = |kind| timeline.events.iter().find(|e| e.object == o && e.kind == kind).map(|e| r4(e.t));
        objects.push((bodies.len(), o));
        bodies.push(BodyData {
            name: name.clone(),
            kind: "object",
            role: Some(role),
            robot: None,
            colour: match role {
                "target" => "#f2c12e",
                "removed" => "#e8743b",
                _ => "#8fa3b8",
            },
            track: next_track(),
            pose: None,
            grasped_at: at(EventKind::Grasp),
            released_at: at(EventKind::Release),
            shapes: world.drawn_object(o).iter().map(shape).collect(),
        });
    }

    let holding = fingers_closed(world, schedule, timeline);
    // Per robot, per posture met: where each drawn body stands off its link.
    let mut offsets: Vec<Vec<(usize, Vec<Pose>)>> = vec![Vec::new(); scn.robots.len()];
    let step = KEYFRAME_STEP.max(timeline.duration / (MAX_KEYFRAMES - 1) as f64);
    let frames = ((timeline.duration / step).ceil() as usize + 1).min(MAX_KEYFRAMES);
    let mut poses = Vec::with_capacity(frames);
    for k in 0..frames {
        let t = (k as f64 * step).min(timeline.duration);
        let qs: Vec<Vec<f64>> = timeline.tracks.iter().map(|tr| tr.sample(t)).collect();
        let fk: Vec<Vec<(String, Pose)>> = scn.robot_ids().map(|r| world.fk_links(r, &qs[r.index()])).collect();
        let mut row = vec![0.0; tracks * 7];
        let mut put = |body: usize, p: &Pose| {
            if let Some(tr) = bodies[body].track {
                row[tr * 7..tr * 7 + 7].copy_from_slice(&pose7(p));
            }
        };
        let postures: Vec<usize> = scn
            .robot_ids()
            .map(|r| holding.iter().find(|h| h.0 == r && t >= h.1 && t < h.2).map_or(OPEN_POSTURE, |h| h.3))
            .collect();
        for (r, &posture) in scn.robot_ids().zip(&postures) {
            if !offsets[r.index()].iter().any(|(p, _)| *p == posture) {
                offsets[r.index()].push((posture, world.drawn_offsets(r, posture)));
            }
        }
        for &(b, r, link, k) in &links {
            let posture = postures[r.index()];
            let offset = offsets[r.index()].iter().find(|(p, _)| *p == posture).and_then(|(_, o)| o.get(k));
            put(b, &(fk[r.index()][link].1 * offset.copied().unwrap_or_else(Pose::identity)));
        }
        for &(b, r) in &tcps {
            put(b, &world.fk_tcp(r, &qs[r.index()]));
        }
        for &(b, o) in &objects {
            put(b, &object_pose(world, timeline, o, t, &qs));
        }
        poses.push(row);
    }

    let actions = schedule
        .map(|s| {
            let mut list: Vec<ActionData> = s
                .actions
                .iter()
                .map(|a| {
                    let span = timeline.actions.iter().find(|x| x.id == a.id);
                    ActionData {
                        id: a.id,
                        robot: a.robot.clone(),
                        object: a.object.clone(),
                        after: a.after.clone(),
                        start: span.map_or(0.0, |x| r4(x.start)),
                        end: span.map_or(0.0, |x| r4(x.end)),
                    }
                })
                .collect();
            list.sort_by_key(|a| a.id);
            list
        })
        .unwrap_or_default();
    let violations: Vec<ViolationData> = violations.iter().map(|v| violation(world, timeline, v)).collect();
    SceneData {
        scenario: crate::schedule::scenario_name(scn),
        status: match (schedule, violations.is_empty()) {
            (None, _) => "cell",
            (Some(_), true) => "verified",
            (Some(_), false) => "violations",
        },
        bodies,
        robots: scn.robots.iter().map(|r| r.name.clone()).collect(),
        step,
        frames,
        poses,
        duration: r4(timeline.duration),
        actions,
        violations,
    }
}

/// Each carry: (robot, grasp time, release time, the fingers' posture while holding).
fn fingers_closed(world: &World, schedule: Option<&Schedule>, timeline: &Timeline) -> Vec<(RobotId, f64, f64, usize)> {
    let scn = world.scenario();
    let Some(s) = schedule else { return Vec::new() };
    timeline
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Grasp)
        .map(|g| {
            let release = timeline.events.iter().find(|e| e.object == g.object && e.kind == EventKind::Release);
            let name = &scn.object(g.object).body.name;
            let grasp = s.actions.iter().find(|a| a.object.as_ref() == Some(name)).and_then(|a| a.grasp.as_deref());
            let index = grasp.and_then(|x| scn.object(g.object).grasp_index(x));
            let posture = index.map_or(OPEN_POSTURE, |i| world.posture_of(g.robot, g.object, i));
            (g.robot, g.t, release.map_or(f64::INFINITY, |e| e.t), posture)
        })
        .collect()
}

/// Where an object is at `t`: in place, or carried rigidly by the hand since its grasp.
fn object_pose(world: &World, timeline: &Timeline, o: ObjectId, t: f64, qs: &[Vec<f64>]) -> Pose {
    let scn = world.scenario();
    let placed = scn.object(o).body.pose_world_body;
    let grasp = timeline.events.iter().find(|e| e.object == o && e.kind == EventKind::Grasp && e.t <= t);
    let Some(g) = grasp else { return placed };
    let release = timeline.events.iter().find(|e| e.object == o && e.kind == EventKind::Release);
    let until = release.map_or(f64::INFINITY, |e| e.t);
    let track = &timeline.tracks[g.robot.index()];
    // The object rides with the flange; how the fingers close (which grasp, here the
    // first) does not move it.
    let held = world.held(g.robot, o, 0, &track.sample(g.t));
    let q = if t <= until { qs[g.robot.index()].clone() } else { track.sample(until) };
    world.fk_flange(g.robot, &q) * held.pose_flange_object
}

/// A violation with the time and place of what it is about, where it has them.
fn violation(world: &World, timeline: &Timeline, v: &Violation) -> ViolationData {
    let (action, t) = match &v.location {
        Location::Schedule => (None, None),
        // An instant of a timed replay: the action running then.
        Location::At { t } => (timeline.actions.iter().find(|a| a.start <= *t && *t <= a.end).map(|a| a.id), Some(*t)),
        Location::Action(id) => (Some(*id), timeline.actions.iter().find(|a| a.id == *id).map(|a| a.start)),
        Location::Waypoint { action, phase, index } => {
            let span = timeline.actions.iter().find(|a| a.id == *action);
            (Some(*action), span.and_then(|s| s.waypoint_t(*phase, *index)))
        }
        Location::Segment { action, phase, index } => {
            let span = timeline.actions.iter().find(|a| a.id == *action);
            let mid =
                span.and_then(|s| Some((s.waypoint_t(*phase, *index)? + s.waypoint_t(*phase, *index + 1)?) / 2.0));
            (Some(*action), mid)
        }
    };
    let robot = action.and_then(|id| timeline.actions.iter().find(|a| a.id == id)).and_then(|a| a.robot);
    let at = match (robot, t) {
        (Some(r), Some(t)) => {
            let q = timeline.tracks[r.index()].sample(t);
            let p = world.fk_tcp(r, &q).translation.vector;
            Some([p.x, p.y, p.z].map(r4))
        }
        _ => None,
    };
    ViolationData { text: v.to_string(), action, t: t.map(r4), at }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn a_pose_is_position_then_quaternion_xyzw() {
        let p = Pose::from_parts(
            Translation3::new(1.0, 2.0, 3.0),
            UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), std::f64::consts::FRAC_PI_2),
        );
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert_eq!(pose7(&p), [1.0, 2.0, 3.0, 0.0, 0.0, r4(h), r4(h)]);
        assert_eq!(r4(0.123456), 0.1235);
    }
}
