//! A whole query's path touching nothing, leg by leg, from the free-space searches of
//! `connect`: for a configuration goal one leg, home to the goal; for a grasp, home to a
//! pre-grasp whose straight approach touches nothing (the empty hand), then that
//! pre-grasp to the drop carrying the object, then the drop to home (the object gone)
//! when the drop is elsewhere. Each leg starts once the one before it has a path.

use std::time::Instant;

use super::super::layers::{mode_of, GraspGoal, ModeKey};
use super::super::space::{Mode, Space};
use super::connect::FreeConnect;
use super::RobotPlanner;
use crate::plan::FoundPath;
use crate::resolve::ObjectId;
use crate::world::{Config, JointPath, ObjectSet};

/// Where a query's free-space search stands.
pub(super) struct FreeSearch {
    object: Option<ObjectId>,
    /// The query goals the first leg may end at (indices among the query's goals).
    ends: Vec<usize>,
    /// The query goal the first leg reached.
    goal: Option<usize>,
    /// The legs found so far, each shortened in the mode it was searched in.
    done: Vec<Vec<Vec<f64>>>,
    /// The leg being searched; `None` once the next leg cannot be (its start or end
    /// touches something in its mode).
    current: Option<FreeConnect>,
    /// Extension attempts over every leg.
    pub(super) attempted: u64,
}

impl FreeSearch {
    /// The first leg: home to the goal configuration, or to the pre-grasps of the grasps
    /// whose pre-grasp and approach touch nothing. `None` when there is no such leg.
    pub(super) fn new<S: Space>(
        p: &RobotPlanner<S>,
        object: Option<ObjectId>,
        goals: &[GraspGoal],
        checks: &mut u64,
    ) -> Option<FreeSearch> {
        let ends: Vec<usize> =
            (0..goals.len()).filter(|&i| goals[i].pre_set.is_empty() && goals[i].approach.is_empty()).collect();
        let qs: Vec<&[f64]> = ends.iter().map(|&i| goals[i].cfg.q_pregrasp.0.as_slice()).collect();
        let first = FreeConnect::new(p, p.space.home(), &qs, Mode::default(), checks)?;
        Some(FreeSearch { object, ends, goal: None, done: Vec::new(), current: Some(first), attempted: 0 })
    }

    /// Up to `attempts` more extensions over the legs in turn; the query's answer once
    /// the last leg has its path.
    pub(super) fn grow<S: Space>(
        &mut self,
        p: &RobotPlanner<S>,
        goals: &[GraspGoal],
        mut attempts: u64,
        t0: Instant,
        checks: &mut u64,
    ) -> Option<FoundPath> {
        while attempts > 0 {
            let leg = self.current.as_mut()?;
            let before = leg.attempted;
            let found = leg.grow(p, attempts, t0, checks);
            self.attempted += leg.attempted - before;
            attempts -= (leg.attempted - before).min(attempts);
            let (path, end) = found?;
            if self.goal.is_none() {
                self.goal = Some(self.ends[end]);
            }
            self.done.push(path);
            let (Some(o), Some(g)) = (self.object, self.goal) else { return Some(p.free_answer(self, goals)) };
            let (home, drop) = (p.space.home().to_vec(), p.space.drop_config().to_vec());
            self.current = match self.done.len() {
                // Carrying the object from its pre-grasp to the drop.
                1 => {
                    let carry = p.lock(|s| mode_of(s, ModeKey::Carry(o, goals[g].key)), checks);
                    FreeConnect::new(p, &goals[g].cfg.q_pregrasp.0, &[&drop], carry, checks)
                }
                // Back home without it, when the drop is elsewhere.
                2 if drop != home => {
                    let gone = Mode { absent: ObjectSet::single(o), held: None };
                    FreeConnect::new(p, &drop, &[&home], gone, checks)
                }
                _ => return Some(p.free_answer(self, goals)),
            };
        }
        None
    }
}

impl<S: Space> RobotPlanner<S> {
    /// The answer from a free search's legs: it removes nothing.
    fn free_answer(&self, f: &FreeSearch, goals: &[GraspGoal]) -> FoundPath {
        let legs = &f.done;
        let (approach, retreat) = match (f.object, f.goal) {
            (Some(_), Some(g)) => {
                let q_grasp = goals[g].cfg.q_grasp.clone();
                let mut approach: Vec<Config> = legs[0].iter().cloned().map(Config).collect();
                approach.push(q_grasp.clone());
                let mut retreat = vec![q_grasp];
                for q in legs[1..].iter().flatten() {
                    if retreat.last().is_none_or(|l| l.0 != *q) {
                        retreat.push(Config(q.clone()));
                    }
                }
                (approach, retreat)
            }
            _ => (legs[0].iter().cloned().map(Config).collect(), Vec::new()),
        };
        FoundPath {
            grasp: f.object.and(f.goal).map(|g| goals[g].cfg.grasp),
            approach: JointPath(approach),
            retreat: JointPath(retreat),
            removals: ObjectSet::new(),
            forced: super::forced(goals),
        }
    }
}
