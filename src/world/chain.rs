//! Kinematic chains: a [`Model`] flattened into links in topological order, with
//! each joint's value drawn from the configuration, a mimic leader, or frozen.
//!
//! The configuration is the actuated (non-fixed, non-mimic) joints on the path
//! from the root to the flange, in that order. Movable joints off that path stay at
//! 0 clamped into their limits, except a gripper's fingers: the joints hanging from
//! the links rigidly fixed to the flange, which stand open, at their upper limit, so
//! that an object fits between them. Mimic joints follow their leader wherever they
//! are.

use nalgebra::{Isometry3, Matrix6xX, Quaternion, Translation3, Unit, UnitQuaternion, Vector3};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::half_turn::half_turn;
use super::urdf::{Model, Motion};

/// Where a link's joint value comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Source {
    Fixed,
    /// `q[i] * mult + offset`.
    Active {
        index: usize,
        mult: f64,
        offset: f64,
    },
    Frozen(f64),
}

#[derive(Debug, Clone)]
pub(crate) struct ChainLink {
    pub name: String,
    /// Index of the parent link in [`Chain::links`] (always smaller).
    pub parent: Option<usize>,
    pub pose_parent_joint: Isometry3<f64>,
    pub motion: Motion,
    pub source: Source,
    /// Links joined by joints that never move share a group.
    pub group: usize,
    /// Which components of `pose_parent_joint`'s rotation and of the motion's turn are
    /// zero (see [`Turn`]).
    turns: (Turn, Turn),
}

/// A unit quaternion's shape, read once so that forward kinematics multiplies by it
/// without the terms its zero components make zero: most URDF joints turn about a
/// principal axis and most origins are turned by none or about one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Turn {
    None,
    /// Only `w` and the vector component on this axis are non-zero.
    About(usize),
    Any,
}

impl Turn {
    fn of(q: &UnitQuaternion<f64>) -> Turn {
        let v = q.as_ref().vector();
        match (v[0] == 0.0, v[1] == 0.0, v[2] == 0.0) {
            (true, true, true) if q.as_ref().w == 1.0 => Turn::None,
            (false, true, true) => Turn::About(0),
            (true, false, true) => Turn::About(1),
            (true, true, false) => Turn::About(2),
            _ => Turn::Any,
        }
    }

    fn of_motion(m: Motion) -> Turn {
        match m {
            Motion::Rotate(axis) => match Turn::of(&UnitQuaternion::from_axis_angle(&axis, 1.0)) {
                Turn::None => Turn::Any,
                t => t,
            },
            _ => Turn::Any,
        }
    }

    /// `a * b`, `b` of this shape: nalgebra's product with the terms of `b`'s zero
    /// components left out (each is a product with ±0, which adds nothing), so the same
    /// value but for the sign of a zero.
    #[inline]
    fn mul(self, a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
        let (s, r) = (a.as_ref(), b.as_ref());
        let (sw, si, sj, sk) = (s.w, s.i, s.j, s.k);
        let q = match self {
            Turn::None => return *a,
            Turn::About(0) => {
                let (rw, ri) = (r.w, r.i);
                Quaternion::new(sw * rw - si * ri, sw * ri + si * rw, sj * rw + sk * ri, sk * rw - sj * ri)
            }
            Turn::About(1) => {
                let (rw, rj) = (r.w, r.j);
                Quaternion::new(sw * rw - sj * rj, si * rw - sk * rj, sw * rj + sj * rw, si * rj + sk * rw)
            }
            Turn::About(_) => {
                let (rw, rk) = (r.w, r.k);
                Quaternion::new(sw * rw - sk * rk, si * rw + sj * rk, sj * rw - si * rk, sw * rk + sk * rw)
            }
            Turn::Any => return a * b,
        };
        UnitQuaternion::new_unchecked(q)
    }
}

#[derive(Debug, Clone)]
pub(crate) struct Chain {
    pub links: Vec<ChainLink>,
    pub joint_names: Vec<String>,
    pub limits: Vec<(f64, f64)>,
    /// Velocity limit per actuated joint (rad/s or m/s).
    pub velocities: Vec<f64>,
    /// The URDF's acceleration limit per actuated joint, where it states one (Drake's extension).
    pub accelerations: Vec<Option<f64>>,
    pub flange: usize,
    /// Links from the root to the flange, root first.
    pub path: Vec<usize>,
    /// For each link, the index in `Model::links` it came from.
    pub model_index: Vec<usize>,
    /// The gripper's finger joints (movable, not mimic), in file order.
    pub fingers: Vec<FingerJoint>,
    /// Where the fingers stand in this chain (their upper limits unless set).
    pub finger_values: Vec<f64>,
    /// Links whose frozen value a finger sets: (link, finger, mult, offset).
    finger_links: Vec<(usize, usize, f64, f64)>,
}

/// Which finger a frozen joint follows: (finger, mult, offset).
type FingerLink = (usize, f64, f64);

/// A joint of the gripper: not part of the configuration, set by a posture.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FingerJoint {
    pub name: String,
    pub lower: f64,
    pub upper: f64,
    /// Over the links it moves that slide: the sum of their |mult| (how much the opening
    /// grows per unit of this joint); 0 when every one turns.
    pub spread: f64,
    /// Some link it moves slides (a `width` can set it).
    pub slides: bool,
    /// The joint itself turns (its values are angles).
    pub turns: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum ChainError {
    UnknownFlange,
    Structure(String),
}

/// The link ROS-Industrial robots name their tool flange.
pub const TOOL0: &str = "tool0";

impl Chain {
    /// Builds the chain ending at `flange`: by default the link named `tool0` when there is
    /// one (ROS-Industrial's tool flange, +z out of the flange), else the deepest link,
    /// first in file order on ties.
    pub fn new(model: &Model, flange: Option<&str>) -> Result<Chain, ChainError> {
        Chain::build(model, flange, false)
    }

    /// A hand's chain: rooted and ending at the hand's root link (it has no joints of its
    /// own to actuate), every movable joint a finger, standing open.
    pub fn hand(model: &Model) -> Result<Chain, ChainError> {
        let root = model.links[model.root].name.clone();
        Chain::build(model, Some(&root), true)
    }

    fn build(model: &Model, flange: Option<&str>, all_fingers: bool) -> Result<Chain, ChainError> {
        // Topological order, children in file order.
        let mut order = Vec::with_capacity(model.links.len());
        let mut stack = vec![model.root];
        while let Some(l) = stack.pop() {
            order.push(l);
            for &j in model.links[l].child_joints.iter().rev() {
                stack.push(model.joints[j].child);
            }
        }
        let mut pos = vec![usize::MAX; model.links.len()];
        for (i, &l) in order.iter().enumerate() {
            pos[l] = i;
        }
        let parent_of = |l: usize| model.links[l].parent_joint.map(|j| model.joints[j].parent);
        let depth = |mut l: usize| {
            let mut d = 0;
            while let Some(p) = parent_of(l) {
                d += 1;
                l = p;
            }
            d
        };
        let flange_model = match flange.map(|n| model.link_index(n)) {
            Some(found) => found.ok_or(ChainError::UnknownFlange)?,
            None if model.link_index(TOOL0).is_some() => model.link_index(TOOL0).unwrap_or(model.root),
            None => {
                let mut best = model.root;
                for &l in &order {
                    if depth(l) > depth(best) {
                        best = l;
                    }
                }
                best
            }
        };
        let mut path_model = vec![flange_model];
        while let Some(p) = parent_of(*path_model.last().unwrap_or(&model.root)) {
            path_model.push(p);
        }
        path_model.reverse();

        // Actuated joints: on the path, movable, not mimic.
        let mut joint_names = Vec::new();
        let mut limits = Vec::new();
        let mut velocities = Vec::new();
        let mut accelerations = Vec::new();
        let mut active_of_joint = vec![None; model.joints.len()];
        for &l in &path_model {
            if let Some(j) = model.links[l].parent_joint {
                let mj = &model.joints[j];
                if mj.motion != Motion::Fixed && mj.mimic.is_none() {
                    active_of_joint[j] = Some(joint_names.len());
                    joint_names.push(mj.name.clone());
                    limits.push((mj.lower, mj.upper));
                    velocities.push(mj.velocity);
                    accelerations.push(mj.acceleration);
                }
            }
        }
        // The links rigid with the flange (joined to it by fixed joints, up or down): a
        // movable joint hanging from one, off the path, is a finger.
        let mut rigid = vec![false; model.links.len()];
        let mut todo = vec![flange_model];
        while let Some(l) = todo.pop() {
            if std::mem::replace(&mut rigid[l], true) {
                continue;
            }
            if let Some(j) = model.links[l].parent_joint.filter(|&j| model.joints[j].motion == Motion::Fixed) {
                todo.push(model.joints[j].parent);
            }
            for &j in &model.links[l].child_joints {
                if model.joints[j].motion == Motion::Fixed {
                    todo.push(model.joints[j].child);
                }
            }
        }
        let finger =
            |j: usize| (all_fingers || rigid[model.joints[j].parent]) && model.joints[j].motion != Motion::Fixed;
        let finger_joints: Vec<usize> = (0..model.joints.len())
            .filter(|&j| finger(j) && model.joints[j].mimic.is_none() && active_of_joint[j].is_none())
            .collect();
        // Resolve every joint's value source, following mimic chains.
        // The value source, and the finger (index, mult, offset) it follows, if any.
        let resolve = |j: usize| -> Result<(Source, Option<FingerLink>), ChainError> {
            let (mut mult, mut offset, mut cur) = (1.0, 0.0, j);
            for _ in 0..=model.joints.len() {
                let mj = &model.joints[cur];
                if mj.motion == Motion::Fixed {
                    return Ok((Source::Frozen(offset), None));
                }
                if let Some(index) = active_of_joint[cur] {
                    return Ok((Source::Active { index, mult, offset }, None));
                }
                match &mj.mimic {
                    Some((leader, m, o)) => {
                        offset += mult * o;
                        mult *= m;
                        cur = model.joint_index(leader).ok_or_else(|| {
                            ChainError::Structure(format!("joint `{}` mimics an undefined joint", mj.name))
                        })?;
                    }
                    None => {
                        let of = finger_joints.iter().position(|&f| f == cur);
                        let v = if of.is_some() { mj.upper } else { 0f64.clamp(mj.lower, mj.upper) };
                        return Ok((Source::Frozen(mult * v + offset), of.map(|k| (k, mult, offset))));
                    }
                }
            }
            Err(ChainError::Structure(format!("the mimic joints around `{}` form a cycle", model.joints[j].name)))
        };

        let mut links = Vec::with_capacity(order.len());
        let mut groups: Vec<usize> = Vec::with_capacity(order.len());
        let mut finger_links = Vec::new();
        let mut fingers: Vec<FingerJoint> = finger_joints
            .iter()
            .map(|&j| {
                let mj = &model.joints[j];
                FingerJoint {
                    name: mj.name.clone(),
                    lower: mj.lower,
                    upper: mj.upper,
                    spread: 0.0,
                    slides: false,
                    turns: matches!(mj.motion, Motion::Rotate(_)),
                }
            })
            .collect();
        for (i, &l) in order.iter().enumerate() {
            let ml = &model.links[l];
            let (parent, pose, motion, source) = match ml.parent_joint {
                None => (None, Isometry3::identity(), Motion::Fixed, Source::Fixed),
                Some(j) => {
                    let mj = &model.joints[j];
                    let src = if mj.motion == Motion::Fixed {
                        Source::Fixed
                    } else {
                        let (src, of) = resolve(j)?;
                        if let Some((k, mult, offset)) = of {
                            finger_links.push((i, k, mult, offset));
                            if let Motion::Slide(_) = mj.motion {
                                fingers[k].spread += mult.abs();
                                fingers[k].slides = true;
                            }
                        }
                        src
                    };
                    (Some(pos[mj.parent]), mj.pose_parent_joint, mj.motion, src)
                }
            };
            let group = match (parent, source) {
                (Some(p), Source::Fixed | Source::Frozen(_)) => groups[p],
                _ => i,
            };
            groups.push(group);
            let turns = (Turn::of(&pose.rotation), Turn::of_motion(motion));
            links.push(ChainLink {
                name: ml.name.clone(),
                parent,
                pose_parent_joint: pose,
                motion,
                source,
                group,
                turns,
            });
        }
        Ok(Chain {
            path: path_model.iter().map(|&l| pos[l]).collect(),
            flange: pos[flange_model],
            links,
            joint_names,
            limits,
            velocities,
            accelerations,
            model_index: order,
            finger_values: fingers.iter().map(|f| f.upper).collect(),
            fingers,
            finger_links,
        })
    }

    /// The same chain with its fingers at `values` (one per [`Chain::fingers`]).
    pub fn with_fingers(&self, values: &[f64]) -> Chain {
        let mut c = self.clone();
        for &(l, k, mult, offset) in &self.finger_links {
            if let Some(v) = values.get(k) {
                c.links[l].source = Source::Frozen(mult * v + offset);
            }
        }
        c.finger_values = values.to_vec();
        c
    }

    pub fn dof(&self) -> usize {
        self.joint_names.len()
    }

    fn joint_value(src: Source, q: &[f64]) -> f64 {
        match src {
            Source::Fixed => 0.0,
            Source::Active { index, mult, offset } => q[index] * mult + offset,
            Source::Frozen(v) => v,
        }
    }

    fn motion_pose(motion: Motion, v: f64) -> Isometry3<f64> {
        match motion {
            Motion::Fixed => Isometry3::identity(),
            Motion::Rotate(axis) => Isometry3::from_parts(Translation3::identity(), turn_about(&axis, v)),
            Motion::Slide(axis) => {
                Isometry3::from_parts(Translation3::from(axis.into_inner() * v), UnitQuaternion::identity())
            }
        }
    }

    /// `t * motion_pose(motion, v)`, with a revolute joint's zero translation skipped:
    /// the hot loop of FK and IK.
    #[inline]
    fn apply_motion(t: &mut Isometry3<f64>, motion: Motion, v: f64) {
        match motion {
            Motion::Fixed => {}
            Motion::Rotate(axis) => t.rotation *= turn_about(&axis, v),
            m => *t *= Self::motion_pose(m, v),
        }
    }

    /// Poses of every link in the base frame, written into `out` (length = number of links).
    pub fn fk_into(&self, q: &[f64], out: &mut [Isometry3<f64>]) {
        self.fk_from(&Isometry3::identity(), q, out)
    }

    /// [`Chain::fk_into`] with the root link at `root` (the robot's base in the world):
    /// every link's world pose without a second product per link.
    pub fn fk_from(&self, root: &Isometry3<f64>, q: &[f64], out: &mut [Isometry3<f64>]) {
        self.fk_prefix(root, q, self.links.len(), out);
    }

    /// The first `n` links' poses (a link's parent comes before it), the root at `root`.
    #[inline]
    pub(crate) fn fk_prefix(&self, root: &Isometry3<f64>, q: &[f64], n: usize, out: &mut [Isometry3<f64>]) {
        for (i, l) in self.links.iter().enumerate().take(n) {
            out[i] = match l.parent {
                None => *root,
                Some(p) => Self::link_pose(&out[p], l, Self::joint_value(l.source, q)),
            };
        }
    }

    /// [`Chain::fk_into`] for links `0..=last` only (a link's parent comes before it):
    /// what a question about two bodies needs, not the links beyond them.
    pub fn fk_upto(&self, q: &[f64], last: usize, out: &mut [Isometry3<f64>]) {
        self.fk_prefix(&Isometry3::identity(), q, last + 1, out);
    }

    /// The flange pose in the base frame, walking only the path.
    pub fn fk_flange(&self, q: &[f64]) -> Isometry3<f64> {
        let mut t = Isometry3::identity();
        for &l in &self.path[1..] {
            let link = &self.links[l];
            t = Self::link_pose(&t, link, Self::joint_value(link.source, q));
        }
        t
    }

    /// Link `l`'s pose from its parent's, its joint at `v`: `parent * pose_parent_joint`,
    /// then the joint's motion, as [`Chain::apply_motion`] does, with the quaternion
    /// products' zero terms left out (see [`Turn`]).
    #[inline]
    fn link_pose(parent: &Isometry3<f64>, l: &ChainLink, v: f64) -> Isometry3<f64> {
        let shift = parent.rotation * l.pose_parent_joint.translation.vector;
        let translation = Translation3::from(parent.translation.vector + shift);
        let mut rotation = l.turns.0.mul(&parent.rotation, &l.pose_parent_joint.rotation);
        match l.motion {
            Motion::Fixed => {}
            Motion::Rotate(axis) => rotation = l.turns.1.mul(&rotation, &turn_about(&axis, v)),
            m => return Isometry3::from_parts(translation, rotation) * Self::motion_pose(m, v),
        }
        Isometry3::from_parts(translation, rotation)
    }

    /// TCP pose (base frame) and its geometric Jacobian, one column per actuated joint,
    /// rows (linear; angular).
    pub fn jacobian(&self, q: &[f64], pose_flange_tcp: &Isometry3<f64>, jac: &mut Matrix6xX<f64>) -> Isometry3<f64> {
        // One pass: a revolute column is w × (p_tcp − o) = w × p_tcp − w × o. The angular
        // rows collect Σ w (mimic joints share a column), the linear rows Σ −w × o and the
        // slides; the w × p_tcp term is added once the TCP is known.
        jac.fill(0.0);
        let mut t = Isometry3::identity();
        for &l in &self.path[1..] {
            let link = &self.links[l];
            t *= link.pose_parent_joint;
            if let Source::Active { index, mult, .. } = link.source {
                match link.motion {
                    Motion::Rotate(axis) => {
                        let w: Vector3<f64> = t.rotation * axis.into_inner() * mult;
                        let v = -w.cross(&t.translation.vector);
                        for k in 0..3 {
                            jac[(k, index)] += v[k];
                            jac[(k + 3, index)] += w[k];
                        }
                    }
                    Motion::Slide(axis) => {
                        let v: Vector3<f64> = t.rotation * axis.into_inner() * mult;
                        for k in 0..3 {
                            jac[(k, index)] += v[k];
                        }
                    }
                    Motion::Fixed => {}
                }
            }
            Self::apply_motion(&mut t, link.motion, Self::joint_value(link.source, q));
        }
        let tcp = t * pose_flange_tcp;
        let p_tcp = tcp.translation.vector;
        for mut col in jac.column_iter_mut() {
            let w = Vector3::new(col[3], col[4], col[5]);
            let v = w.cross(&p_tcp);
            for k in 0..3 {
                col[k] += v[k];
            }
        }
        tcp
    }
}

/// `UnitQuaternion::from_axis_angle(axis, v)`, its half angle's sine and cosine by
/// [`half_turn`] (within 2 ulp of libm's; see there).
#[inline]
fn turn_about(axis: &Unit<Vector3<f64>>, v: f64) -> UnitQuaternion<f64> {
    let (s, c) = half_turn(v);
    UnitQuaternion::new_unchecked(Quaternion::from_parts(c, axis.as_ref() * s))
}

/// A uniform sample of `[lo, hi)` that cannot panic, unlike a bare `random_range` on
/// a non-finite or empty range: such a range yields its finite end, or 0.
pub(crate) fn sample_in(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    let width = hi - lo;
    if width > 0.0 && width.is_finite() {
        // `random_range` cannot fail on a finite, non-empty range; kept (rather than
        // an affine map) so the random stream, and the pinned schedules, are unchanged.
        rng.random_range(lo..hi)
    } else if lo.is_finite() {
        lo
    } else if hi.is_finite() {
        hi
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;

    use super::*;

    #[test]
    fn sampling_never_panics_and_stays_in_range() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for (lo, hi) in [(-1e308, 1e308), (f64::NEG_INFINITY, 1.0), (f64::NAN, f64::NAN), (2.0, 1.0), (0.5, 0.5)] {
            let v = sample_in(&mut rng, lo, hi);
            assert!(v.is_finite(), "[{lo}, {hi}] gave {v}");
        }
        for _ in 0..1000 {
            let v = sample_in(&mut rng, -0.3, 0.7);
            assert!((-0.3..=0.7).contains(&v));
        }
    }

    /// A chain whose joints turn about +x, -y, +z and a slanted axis and slide, behind
    /// origins turned by nothing, about one axis (each of the three) and about several,
    /// then the shared robots' arms: every link's pose from `fk_from` and `fk_flange`
    /// equals (`==`, so up to a zero's sign) the plain product `parent * origin *
    /// motion` at 2 000 random configurations each. A wrong sign or a swapped term in
    /// one of `Turn::mul`'s products fails it.
    #[test]
    fn forward_kinematics_equals_the_plain_products() {
        let joint = |i: usize, kind: &str, rpy: &str, axis: &str| {
            format!(
                r#"<link name="l{}"/><joint name="j{i}" type="{kind}"><parent link="l{i}"/><child link="l{}"/>
                <origin xyz="0.1 -0.2 0.3" rpy="{rpy}"/><axis xyz="{axis}"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>"#,
                i + 1,
                i + 1
            )
        };
        let mut text = String::from(r#"<robot name="r"><link name="l0"/>"#);
        let joints = [
            ("revolute", "0 0 0", "1 0 0"),
            ("revolute", "0.4 0 0", "0 -1 0"),
            ("revolute", "0 -0.7 0", "0 0 1"),
            ("fixed", "0 0 1.2", "1 0 0"),
            ("revolute", "0.3 0.2 -0.1", "0.6 0 0.8"),
            ("prismatic", "1.5707963267948966 0 0", "0 0 1"),
            ("revolute", "-1.5707963267948966 0 0", "0 0 1"),
            ("fixed", "0 0 0", "1 0 0"),
        ];
        for (i, (kind, rpy, axis)) in joints.iter().enumerate() {
            text += &joint(i, kind, rpy, axis);
        }
        text += "</robot>";
        let mut chains = vec![Chain::new(&super::super::urdf::parse(&text).expect("parses"), None).expect("a chain")];
        let shared = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots");
        for f in [
            "panda/vamp/panda_spherized.urdf",
            "tx90/tx90.urdf",
            "ur5/vamp/ur5_spherized.urdf",
            "iiwa/drake_models/iiwa_description/urdf/iiwa14_primitive_collision.urdf",
        ] {
            match std::fs::read_to_string(shared.join(f)) {
                Ok(t) => {
                    chains.push(Chain::new(&super::super::urdf::parse(&t).expect("parses"), None).expect("a chain"))
                }
                Err(_) => eprintln!("skipped {f}: ../shared/robots is absent"),
            }
        }
        let turned = chains[0].links.iter().map(|l| l.turns).collect::<Vec<_>>();
        assert!(turned.contains(&(Turn::None, Turn::About(0))) && turned.contains(&(Turn::About(0), Turn::About(2))));
        assert!(turned.contains(&(Turn::About(1), Turn::About(2))) && turned.contains(&(Turn::Any, Turn::Any)));
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for chain in &chains {
            let mut out = vec![Isometry3::identity(); chain.links.len()];
            let root = Isometry3::from_parts(
                Translation3::new(0.3, 0.1, -0.2),
                UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
            );
            for _ in 0..2000 {
                let q: Vec<f64> = chain.limits.iter().map(|&(lo, hi)| sample_in(&mut rng, lo, hi)).collect();
                chain.fk_from(&root, &q, &mut out);
                let mut plain: Vec<Isometry3<f64>> = Vec::new();
                for l in &chain.links {
                    let t = match l.parent {
                        None => root,
                        Some(p) => {
                            plain[p]
                                * l.pose_parent_joint
                                * Chain::motion_pose(l.motion, Chain::joint_value(l.source, &q))
                        }
                    };
                    plain.push(t);
                }
                for (a, b) in out.iter().zip(&plain) {
                    assert!(
                        a.translation == b.translation && a.rotation.coords == b.rotation.coords,
                        "{a} against {b}"
                    );
                }
                let flange = chain.fk_flange(&q);
                let mut plain = Isometry3::identity();
                for &l in &chain.path[1..] {
                    let l = &chain.links[l];
                    plain =
                        plain * l.pose_parent_joint * Chain::motion_pose(l.motion, Chain::joint_value(l.source, &q));
                }
                assert!(flange.translation == plain.translation && flange.rotation.coords == plain.rotation.coords);
            }
        }
    }
}
