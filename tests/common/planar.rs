//! An exact 2-D planar arm among rectangles, implementing the planner's `Space`.
//!
//! The arm matches examples/robots/planar3.urdf: base at the origin, three revolute
//! joints about z, links 0.4, 0.3 and 0.2 m long and 0.04 m thick, limits ±170°.
//! Collisions are exact rectangle/rectangle separating-axis tests, not tables.
#![allow(dead_code)]

use declutter::plan::{Mode, Space};
use declutter::resolve::{FixedId, ObjectId, Pose};
use declutter::world::{Blocker, Check, Config, GraspConfig, Held, ObjectSet};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub const LINKS: [f64; 3] = [0.4, 0.3, 0.2];
pub const THICK: f64 = 0.04;
pub const LIMIT: f64 = 170.0 * std::f64::consts::PI / 180.0;

/// An oriented rectangle: centre, half extents, angle.
#[derive(Clone, Copy, Debug)]
pub struct Rect {
    pub c: [f64; 2],
    pub h: [f64; 2],
    pub a: f64,
}

impl Rect {
    pub fn aabb(cx: f64, cy: f64, hx: f64, hy: f64) -> Rect {
        Rect { c: [cx, cy], h: [hx, hy], a: 0.0 }
    }
    fn axes(&self) -> [[f64; 2]; 2] {
        let (s, c) = self.a.sin_cos();
        [[c, s], [-s, c]]
    }
    /// Exact overlap test (separating axis theorem; touching counts as overlap).
    pub fn overlaps(&self, o: &Rect) -> bool {
        let (aa, ab) = (self.axes(), o.axes());
        let d = [o.c[0] - self.c[0], o.c[1] - self.c[1]];
        for ax in aa.iter().chain(ab.iter()) {
            let proj = |r: &Rect, axes: &[[f64; 2]; 2]| {
                r.h[0] * (axes[0][0] * ax[0] + axes[0][1] * ax[1]).abs()
                    + r.h[1] * (axes[1][0] * ax[0] + axes[1][1] * ax[1]).abs()
            };
            let dist = (d[0] * ax[0] + d[1] * ax[1]).abs();
            if dist > proj(self, &aa) + proj(o, &ab) {
                return false;
            }
        }
        true
    }
    /// This rectangle expressed in the frame (x, y, angle) `f`.
    fn relative_to(&self, f: (f64, f64, f64)) -> Rect {
        let (s, c) = f.2.sin_cos();
        let (dx, dy) = (self.c[0] - f.0, self.c[1] - f.1);
        Rect { c: [c * dx + s * dy, -s * dx + c * dy], h: self.h, a: self.a - f.2 }
    }
    fn placed_in(&self, f: (f64, f64, f64)) -> Rect {
        let (s, c) = f.2.sin_cos();
        Rect {
            c: [f.0 + c * self.c[0] - s * self.c[1], f.1 + s * self.c[0] + c * self.c[1]],
            h: self.h,
            a: self.a + f.2,
        }
    }
}

/// Link rectangles and the tip frame (x, y, angle) at `q`.
pub fn fk(q: &[f64]) -> ([Rect; 3], (f64, f64, f64)) {
    let (mut x, mut y, mut a) = (0.0, 0.0, 0.0);
    let mut rects = [Rect::aabb(0.0, 0.0, 0.0, 0.0); 3];
    for i in 0..3 {
        a += q[i];
        let (s, c) = a.sin_cos();
        let l = LINKS[i];
        rects[i] = Rect { c: [x + c * l / 2.0, y + s * l / 2.0], h: [l / 2.0, THICK / 2.0], a };
        x += c * l;
        y += s * l;
    }
    (rects, (x, y, a))
}

/// Analytic IK: tip at (x, y) with angle `phi`, elbow up or down.
pub fn ik(x: f64, y: f64, phi: f64, up: bool) -> Option<Vec<f64>> {
    let (wx, wy) = (x - LINKS[2] * phi.cos(), y - LINKS[2] * phi.sin());
    let (l1, l2) = (LINKS[0], LINKS[1]);
    let c2 = (wx * wx + wy * wy - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if c2.abs() > 1.0 {
        return None;
    }
    let q2 = if up { c2.acos() } else { -c2.acos() };
    let q1 = wy.atan2(wx) - (l2 * q2.sin()).atan2(l1 + l2 * q2.cos());
    let wrap = |a: f64| (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI;
    let q = vec![wrap(q1), wrap(q2), wrap(phi - q1 - q2)];
    q.iter().all(|v| v.abs() <= LIMIT).then_some(q)
}

fn pose2(f: (f64, f64, f64)) -> Pose {
    Isometry3::from_parts(Translation3::new(f.0, f.1, 0.0), UnitQuaternion::from_axis_angle(&Vector3::z_axis(), f.2))
}
fn frame2(p: &Pose) -> (f64, f64, f64) {
    (p.translation.x, p.translation.y, p.rotation.euler_angles().2)
}

/// The scene: removable rectangles, fixed rectangles, the arm's home and grasps.
#[derive(Clone, Debug)]
pub struct Planar {
    pub objects: Vec<Rect>,
    pub fixed: Vec<Rect>,
    pub home: Vec<f64>,
    pub drop: Vec<f64>,
    pub grasps: Vec<Vec<GraspConfig>>,
    limits: Vec<(f64, f64)>,
}

impl Planar {
    pub fn new(objects: Vec<Rect>, fixed: Vec<Rect>, home: Vec<f64>) -> Planar {
        Planar {
            grasps: vec![Vec::new(); objects.len()],
            objects,
            fixed,
            drop: home.clone(),
            home,
            limits: vec![(-LIMIT, LIMIT); 3],
        }
    }

    /// Adds a grasp of object `o`: the tip at the object's centre pointing along `phi`,
    /// approached from `approach` metres back along the tip axis.
    pub fn add_grasp(&mut self, o: usize, phi: f64, approach: f64, up: bool) -> bool {
        let c = self.objects[o].c;
        let solve = |up| {
            Some((ik(c[0], c[1], phi, up)?, ik(c[0] - approach * phi.cos(), c[1] - approach * phi.sin(), phi, up)?))
        };
        let Some((qg, qp)) = solve(up).or_else(|| solve(!up)) else {
            return false;
        };
        let grasp = self.grasps[o].len();
        self.grasps[o].push(GraspConfig { grasp, q_grasp: Config(qg), q_pregrasp: Config(qp) });
        true
    }

    /// Labels of a configuration as a bitmask, `None` if blocked (for brute force).
    pub fn mask(&self, q: &[f64]) -> Option<u32> {
        let mut c = 0;
        match self.check(q, &Mode::default(), &mut c) {
            Check::Blocked(_) => None,
            Check::Touches(s) => Some(s.iter().fold(0, |m, o| m | 1 << o.0)),
        }
    }
}

impl Space for Planar {
    fn dof(&self) -> usize {
        3
    }
    fn limits(&self) -> &[(f64, f64)] {
        &self.limits
    }
    fn check(&self, q: &[f64], mode: &Mode, checks: &mut u64) -> Check {
        *checks += 1;
        for (i, (&v, &(lo, hi))) in q.iter().zip(&self.limits).enumerate() {
            if v < lo || v > hi {
                return Check::Blocked(Blocker::JointLimit { joint: format!("j{i}"), value: v });
            }
        }
        let (links, tip) = fk(q);
        let held_rect = mode.held.as_ref().map(|h| {
            let local = Rect { c: [0.0, 0.0], h: self.objects[h.object.index()].h, a: 0.0 };
            local.placed_in(frame2(&h.pose_flange_object)).placed_in(tip)
        });
        for (fi, f) in self.fixed.iter().enumerate() {
            for (li, l) in links.iter().enumerate() {
                if l.overlaps(f) {
                    return Check::Blocked(Blocker::Fixed { body: FixedId(fi as u32), link: format!("link{li}") });
                }
            }
            if let (Some(hr), Some(h)) = (&held_rect, &mode.held) {
                if hr.overlaps(f) {
                    return Check::Blocked(Blocker::HeldFixed { object: h.object, body: FixedId(fi as u32) });
                }
            }
        }
        let mut s = ObjectSet::new();
        for (oi, o) in self.objects.iter().enumerate() {
            let id = ObjectId(oi as u32);
            if mode.absent.contains(id) || mode.held.as_ref().is_some_and(|h| h.object == id) {
                continue;
            }
            if links.iter().any(|l| l.overlaps(o)) || held_rect.is_some_and(|hr| hr.overlaps(o)) {
                s.insert(id);
            }
        }
        Check::Touches(s)
    }
    fn check_segment(&self, a: &[f64], b: &[f64], step: f64, mode: &Mode, checks: &mut u64) -> Check {
        let d = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        let n = (d / step).ceil().max(1.0) as usize;
        let mut out = Check::free();
        let mut q = vec![0.0; a.len()];
        for i in 0..=n {
            let t = i as f64 / n as f64;
            for j in 0..a.len() {
                q[j] = a[j] + t * (b[j] - a[j]);
            }
            out = out.and(self.check(&q, mode, checks));
            if out.is_blocked() {
                return out;
            }
        }
        out
    }
    fn home(&self) -> &[f64] {
        &self.home
    }
    fn drop_config(&self) -> &[f64] {
        &self.drop
    }
    fn grasps(&self, o: ObjectId) -> Vec<GraspConfig> {
        self.grasps[o.index()].clone()
    }
    fn held(&self, o: ObjectId, _grasp: usize, q_grasp: &[f64]) -> Held {
        let (_, tip) = fk(q_grasp);
        let r = self.objects[o.index()];
        // Object frame = its rectangle's centre and angle; expressed in the tip frame.
        let rel = Rect { c: r.c, h: r.h, a: r.a }.relative_to(tip);
        Held { object: o, pose_flange_object: pose2((rel.c[0], rel.c[1], rel.a)), posture: 0 }
    }
}

/// A random world: 4–10 removable boxes, one fixed wall, home and goal at grid-cell
/// centres (`n` cells per joint) that hit nothing fixed.
pub fn random_world(seed: u64, n: usize) -> (Planar, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut u = move |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
    let wall_angle = u(-3.1, 3.1);
    let wall_r = u(0.45, 0.75);
    let wall = Rect {
        c: [wall_r * wall_angle.cos(), wall_r * wall_angle.sin()],
        h: [u(0.05, 0.08), u(0.15, 0.3)],
        a: wall_angle,
    };
    let k = 4 + (u(0.0, 7.0) as usize).min(6);
    let mut objects = Vec::new();
    while objects.len() < k {
        let (ang, r) = (u(-3.1, 3.1), u(0.3, 0.85));
        let b = Rect { c: [r * ang.cos(), r * ang.sin()], h: [u(0.04, 0.1), u(0.04, 0.1)], a: u(0.0, 1.5) };
        if !b.overlaps(&wall) {
            objects.push(b);
        }
    }
    let mut world = Planar::new(objects, vec![wall], vec![0.0; 3]);
    let cell = |i: usize| -LIMIT + (i as f64 + 0.5) * 2.0 * LIMIT / n as f64;
    let mut pick = |w: &Planar| loop {
        let q: Vec<f64> = (0..3).map(|_| cell((u(0.0, n as f64) as usize).min(n - 1))).collect();
        if w.mask(&q).is_some() {
            return q;
        }
    };
    let home = loop {
        let q = pick(&world);
        if world.mask(&q) == Some(0) {
            break q;
        }
    };
    world.home = home.clone();
    world.drop = home;
    let goal = pick(&world);
    (world, goal)
}

/// Labels every cell centre of an `n`^3 grid: bitmask, or `u32::MAX` if blocked.
pub fn label_grid(w: &Planar, n: usize) -> Vec<u32> {
    let cell = |i: usize| -LIMIT + (i as f64 + 0.5) * 2.0 * LIMIT / n as f64;
    let mut out = Vec::with_capacity(n * n * n);
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                out.push(w.mask(&[cell(i), cell(j), cell(k)]).unwrap_or(u32::MAX));
            }
        }
    }
    out
}

/// The grid cell index of a cell-centre configuration.
pub fn cell_of(q: &[f64], n: usize) -> usize {
    let idx = |v: f64| (((v + LIMIT) / (2.0 * LIMIT) * n as f64).floor() as usize).min(n - 1);
    (idx(q[0]) * n + idx(q[1])) * n + idx(q[2])
}

/// The smallest number of objects whose removal connects `a` to `b` on the grid
/// (6-connected), trying subsets in increasing size; `None` if none does.
pub fn grid_min_removals(labels: &[u32], n: usize, k: usize, a: usize, b: usize) -> Option<usize> {
    let mut masks: Vec<u32> = (0..1u32 << k).collect();
    masks.sort_by_key(|m| m.count_ones());
    let mut seen = vec![u32::MAX; labels.len()];
    for (round, &m) in masks.iter().enumerate() {
        let ok = |c: usize| labels[c] != u32::MAX && labels[c] & !m == 0;
        if !ok(a) || !ok(b) {
            continue;
        }
        let mut stack = vec![a];
        seen[a] = round as u32;
        while let Some(c) = stack.pop() {
            if c == b {
                return Some(m.count_ones() as usize);
            }
            let (i, j, l) = (c / (n * n), (c / n) % n, c % n);
            let mut push = |c2: usize| {
                if seen[c2] != round as u32 && ok(c2) {
                    seen[c2] = round as u32;
                    stack.push(c2);
                }
            };
            if i > 0 {
                push(c - n * n);
            }
            if i + 1 < n {
                push(c + n * n);
            }
            if j > 0 {
                push(c - n);
            }
            if j + 1 < n {
                push(c + n);
            }
            if l > 0 {
                push(c - 1);
            }
            if l + 1 < n {
                push(c + 1);
            }
        }
    }
    None
}
