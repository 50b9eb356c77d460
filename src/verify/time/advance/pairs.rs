//! The pairs the replay bounds: every pair the contact check looks at, each with whose
//! joints can move its two sides apart.

use parry3d_f64::bounding_volume::Aabb;

use super::{Memory, Movers, Pair, Thing, Unit};
use crate::verify::time::scene::{Cell, RobotAt, Scratch};
use crate::world::{GjkStart, ObjectSet, StaticOwner};

impl Cell<'_> {
    /// Every pair the checks look at, in an order fixed by who holds what and which
    /// objects are in place; nothing measured yet.
    pub(super) fn list_pairs(&self, at: &[RobotAt], present: &ObjectSet, s: &Scratch, memory: &mut Memory) {
        let c = self.clearance;
        let whole_bodies = !memory.every_pair;
        memory.units = s
            .posed
            .iter()
            .zip(&self.robots)
            .map(|(posed, g)| {
                let mut balls = vec![whole_bodies; g.bodies.len()];
                for ps in posed.iter().filter(|ps| ps.shape.0.as_ball().is_none()) {
                    balls[ps.body] = false;
                }
                let mut units: Vec<Unit> = Vec::new();
                let mut unit_of: Vec<Option<usize>> = vec![None; g.bodies.len()];
                for (i, ps) in posed.iter().enumerate() {
                    match unit_of[ps.body] {
                        Some(u) if balls[ps.body] => units[u].shapes.push(i),
                        _ => {
                            unit_of[ps.body] = Some(units.len());
                            units.push(Unit { body: ps.body, shapes: vec![i] });
                        }
                    }
                }
                units
            })
            .collect();
        memory.unit_box = memory.units.iter().map(|us| vec![(0, Aabb::new_invalid()); us.len()]).collect();
        let (pairs, movers) = (&mut memory.pairs, &mut memory.movers);
        let units = &memory.units;
        pairs.clear();
        movers.clear();
        let mut group = |m: Movers| {
            movers.push(m);
            movers.len() - 1
        };
        for (ri, ra) in at.iter().enumerate() {
            let g = &self.robots[ri];
            let held = &s.held[ri];
            // Each unit, with its body.
            let bodies = |ri: usize| units[ri].iter().enumerate().map(|(u, unit)| (u, unit.body));
            let checked = |owner: StaticOwner, carried: bool| match owner {
                StaticOwner::Fixed(_) => true,
                StaticOwner::Object(o) => {
                    present.contains(o) && ra.held.is_none_or(|h| h.object != o) && (carried || Some(o) != ra.exempt)
                }
            };
            let whole = group(Movers::Robot(ri));
            // The weights are the body's reach over the rates', set at each part of a
            // stretch (`Memory::start_stretch`, which follows every new list of pairs).
            let weigh = |body: usize| Movers::Weighted {
                robot: ri,
                moved: vec![Some(body); g.body_joints[body].len()],
                weights: vec![0.0; g.body_joints[body].len()],
            };
            // Against the scene a body closes in no faster than its own points move: the
            // joints below it, each by the body's own reach. A link near the base moves
            // slowly, whatever the wrist does.
            let mut own: Vec<Option<usize>> = vec![None; g.bodies.len()];
            for (e, _) in self.statics.iter().enumerate().filter(|(_, st)| checked(st.owner, false)) {
                for (u, b) in bodies(ri).filter(|&(_, b)| g.bodies[b].moving) {
                    let m = *own[b].get_or_insert_with(|| group(weigh(b)));
                    pairs.push(Pair { a: Thing::Unit(ri, u), b: Thing::Static(e), must: c, movers: m });
                }
            }
            for (e, _) in self.statics.iter().enumerate().filter(|(_, st)| checked(st.owner, true)) {
                for i in 0..held.len() {
                    pairs.push(Pair { a: Thing::Held(ri, i), b: Thing::Static(e), must: 0.0, movers: whole });
                }
            }
            let apart = |x: &[bool], y: &[bool]| x.iter().zip(y).map(|(x, y)| x != y).collect::<Vec<bool>>();
            for &(a, b) in &g.self_pairs {
                let moved: Vec<Option<usize>> = (0..g.body_joints[a].len())
                    .map(|j| match (g.body_joints[a][j], g.body_joints[b][j]) {
                        (true, false) => Some(a),
                        (false, true) => Some(b),
                        _ => None,
                    })
                    .collect();
                let weights = vec![0.0; moved.len()];
                let m = group(Movers::Weighted { robot: ri, moved, weights });
                for (x, _) in bodies(ri).filter(|&(_, x)| x == a) {
                    for (y, _) in bodies(ri).filter(|&(_, y)| y == b) {
                        pairs.push(Pair { a: Thing::Unit(ri, x), b: Thing::Unit(ri, y), must: 0.0, movers: m });
                    }
                }
            }
            for i in 0..held.len() {
                for (u, b) in bodies(ri).filter(|&(_, b)| !g.bodies[b].holds) {
                    let m = group(Movers::Apart(ri, apart(&g.flange_joints, &g.body_joints[b])));
                    pairs.push(Pair { a: Thing::Held(ri, i), b: Thing::Unit(ri, u), must: 0.0, movers: m });
                }
            }
            for rj in ri + 1..at.len() {
                let gj = &self.robots[rj];
                let both = group(Movers::Robots(ri, rj));
                let mine = bodies(ri).map(|(u, b)| (Thing::Unit(ri, u), g.bodies[b].moving));
                for (x, xm) in mine.chain((0..held.len()).map(|i| (Thing::Held(ri, i), true))) {
                    let theirs = bodies(rj).map(|(u, b)| (Thing::Unit(rj, u), gj.bodies[b].moving));
                    for (y, ym) in theirs.chain((0..s.held[rj].len()).map(|k| (Thing::Held(rj, k), true))) {
                        if xm || ym {
                            pairs.push(Pair { a: x, b: y, must: c, movers: both });
                        }
                    }
                }
            }
        }
        memory.populated.clear();
        memory.populated.resize(memory.movers.len(), false);
        for p in &memory.pairs {
            memory.populated[p.movers] = true;
        }
        memory.odometer.clear();
        memory.odometer.resize(memory.movers.len(), 0.0);
        memory.odo_at.clear();
        memory.odo_at.resize(memory.movers.len(), 0);
        memory.measured.clear();
        memory.measured.resize(memory.pairs.len(), None);
        memory.hints.clear();
        memory.hints.resize(memory.pairs.len(), GjkStart::default());
        memory.fresh = true;
    }
}
