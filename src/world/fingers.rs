//! A gripper's postures: its finger joints (the arm URDF's past the flange, then the
//! hand's), the values each posture gives them (open, `closed`, each grasp `width`), and
//! every collision shape's pose with the fingers there.

use nalgebra::Isometry3;

use super::chain::{Chain, FingerJoint};
use super::check;
use super::error::WorldError;
use super::load::{HandModel, LoadCtx};
use super::robot::{Posture, RBody, RShape};
use crate::resolve::{JointValues, Scenario};

impl LoadCtx<'_> {
    /// The robot's finger joints (the arm's, then its hand's), the values of each posture
    /// they take (open first, then `closed`, then each grasp `width` that differs), and
    /// per object and grasp the posture holding it.
    pub(super) fn finger_stances(
        &mut self,
        scn: &Scenario,
        r: &crate::resolve::Robot,
        chain: &Chain,
        hand: Option<&HandModel>,
    ) -> (Vec<FingerJoint>, Vec<Vec<f64>>, Vec<Vec<usize>>) {
        let mut fingers = chain.fingers.clone();
        fingers.extend(hand.iter().flat_map(|hm| hm.chain.fingers.iter().cloned()));
        let upper: Vec<f64> = fingers.iter().map(|f| f.upper).collect();
        let open = r.open.as_ref().and_then(|v| self.finger_values(&r.name, "open", v, &fingers)).unwrap_or(upper);
        let mut stances = vec![open];
        let closed = match r.closed.as_ref().and_then(|v| self.finger_values(&r.name, "closed", v, &fingers)) {
            Some(c) => {
                stances.push(c);
                1
            }
            None => super::OPEN_POSTURE,
        };
        let mut per_object = Vec::with_capacity(scn.objects.len());
        for o in &scn.objects {
            let mut per_grasp = Vec::with_capacity(o.grasps.len());
            for g in &o.grasps {
                let for_this_hand = match (&g.hands, r.hand) {
                    (Some(hs), Some(h)) => hs.contains(&h),
                    (Some(_), None) => false,
                    (None, _) => true,
                };
                let stance = match g.width {
                    Some((w, span)) if for_this_hand && !fingers.is_empty() => {
                        match width_stance(&fingers, w) {
                            Ok(v) => Some(match stances.iter().position(|s| *s == v) {
                                Some(k) => k,
                                None => {
                                    stances.push(v);
                                    stances.len() - 1
                                }
                            }),
                            Err(reason) => {
                                // One error per written width, not per copy of a repeated grasp.
                                let seen = self.errs.iter().any(|e| {
                                    matches!(e, WorldError::GraspWidth { robot, span: s, .. } if robot == &r.name && *s == span)
                                });
                                if !seen {
                                    self.errs.push(WorldError::GraspWidth {
                                        robot: r.name.clone(),
                                        object: o.body.name.clone(),
                                        grasp: g.name.split('#').next().unwrap_or(&g.name).to_string(),
                                        width_mm: (w * 1e4).round() / 10.0,
                                        reason,
                                        span,
                                    });
                                }
                                None
                            }
                        }
                    }
                    _ => None,
                };
                per_grasp.push(stance.unwrap_or(closed));
            }
            per_object.push(per_grasp);
        }
        (fingers, stances, per_object)
    }

    /// A finger posture's values: one per finger joint, with units and limits checked.
    fn finger_values(&mut self, robot: &str, what: &str, v: &JointValues, fingers: &[FingerJoint]) -> Option<Vec<f64>> {
        if fingers.is_empty() {
            self.errs.push(WorldError::NoFingers { robot: robot.into(), what: what.into(), span: v.span });
            return None;
        }
        let names: Vec<String> = fingers.iter().map(|f| f.name.clone()).collect();
        if v.values.len() != fingers.len() {
            self.errs.push(WorldError::FingerCount {
                robot: robot.into(),
                what: what.into(),
                expected: fingers.len(),
                got: v.values.len(),
                joints: names.join(", "),
                span: v.span,
            });
            return None;
        }
        let limits: Vec<(f64, f64)> = fingers.iter().map(|f| (f.lower, f.upper)).collect();
        let turns: Vec<bool> = fingers.iter().map(|f| f.turns).collect();
        self.units_and_limits(robot, what, v, &names, &limits, &turns).then(|| v.values.clone())
    }
}

/// Every shape's pose in its body's link frame with the fingers (the arm's, then the
/// hand's) at `values`; the shapes were placed with them at their upper limits. A finger
/// link is rigid with the flange whatever the arm does, so its offset from where it
/// stood is the same in every configuration: it is measured at zero.
pub(super) fn posture(
    chain: &Chain,
    hand: Option<&HandModel>,
    shapes: &[RShape],
    bodies: &[RBody],
    hand_start: usize,
    values: &[f64],
) -> Posture {
    let arm_fingers = chain.fingers.len().min(values.len());
    let frames = |c: &Chain, moved: &Chain, q: &[f64]| {
        let n = c.links.len();
        let (mut was, mut now) = (vec![Isometry3::identity(); n], vec![Isometry3::identity(); n]);
        c.fk_into(q, &mut was);
        moved.fk_into(q, &mut now);
        (was, now)
    };
    let arm = frames(chain, &chain.with_fingers(&values[..arm_fingers]), &vec![0.0; chain.dof()]);
    let hand = hand.map(|hm| (hm, frames(&hm.chain, &hm.chain.with_fingers(&values[arm_fingers..]), &[])));
    let poses = shapes
        .iter()
        .enumerate()
        .map(|(si, sh)| {
            let in_hand = hand.as_ref().and_then(|(hm, f)| {
                let l = *hm.shape_links.get(si.checked_sub(hand_start)?)?;
                // Hand shapes are placed in the hand's root frame (the flange's).
                Some(f.1[l] * f.0[l].inverse())
            });
            let delta = in_hand.unwrap_or_else(|| {
                let l = bodies[sh.body].link;
                arm.0[l].inverse() * arm.1[l]
            });
            super::shapes::to_ppose(&delta) * sh.placed.pose
        })
        .collect();
    Posture { values: values.to_vec(), poses }
}

/// The stances the fingers pass through between open (`stances[0]`) and each other
/// stance, appended to `stances`: spaced so that a sliding finger moves at most
/// [`FINGER_STEP`] and a turning one [`FINGER_TURN_STEP`] between two. Returns, per
/// original stance, the indices of its intermediate ones, from open on.
pub(super) fn closing_stances(fingers: &[FingerJoint], stances: &mut Vec<Vec<f64>>) -> Vec<Vec<usize>> {
    let Some(open) = stances.first().cloned() else { return Vec::new() };
    let n = stances.len();
    let mut out = vec![Vec::new(); n];
    for (p, closing) in out.iter_mut().enumerate().skip(1) {
        let to = stances[p].clone();
        let parts = fingers
            .iter()
            .zip(open.iter().zip(&to))
            .map(|(f, (a, b))| {
                let step = if f.turns { FINGER_TURN_STEP } else { FINGER_STEP / f.spread.max(1.0) };
                ((b - a).abs() / step).ceil()
            })
            .fold(1.0, f64::max)
            .min(1000.0) as usize;
        for k in 1..parts {
            let s = k as f64 / parts as f64;
            stances.push(open.iter().zip(&to).map(|(a, b)| a + (b - a) * s).collect());
            closing.push(stances.len() - 1);
        }
    }
    out
}

/// How far a sliding finger moves between two checked stances while closing (metres).
pub const FINGER_STEP: f64 = 0.002;
/// How far a turning finger turns between two checked stances while closing (radians).
pub const FINGER_TURN_STEP: f64 = 0.02;

/// The finger values that close sliding fingers to `width`: every finger joint at the
/// same value, their openings (each joint's value times the links it slides) adding up
/// to it.
fn width_stance(fingers: &[FingerJoint], width: f64) -> Result<Vec<f64>, String> {
    if let Some(f) = fingers.iter().find(|f| !f.slides || f.turns) {
        return Err(format!("finger joint `{}` turns, and a width sets only sliding fingers", f.name));
    }
    let spread: f64 = fingers.iter().map(|f| f.spread).sum();
    let v = width / spread;
    if let Some(f) = fingers.iter().find(|f| v < f.lower - check::LIMIT_SLACK || v > f.upper + check::LIMIT_SLACK) {
        return Err(format!(
            "it needs finger joint `{}` at {:.1} mm, outside its limits [{:.1} mm, {:.1} mm]",
            f.name,
            v * 1e3,
            f.lower * 1e3,
            f.upper * 1e3
        ));
    }
    Ok(vec![v; fingers.len()])
}
