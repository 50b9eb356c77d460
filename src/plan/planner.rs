//! The planner over a [`World`]: one lazily grown PRMwO roadmap per robot, answering
//! `findPath` queries for every object and target configuration of that robot.

use super::prm::{PrmOptions, RobotPlanner};
use super::space::{Mode, Space};
use super::{Answer, Goal, Oracle};
use crate::resolve::{ObjectId, Objective, PlannerSettings, RobotId};
use crate::world::{Blocker, Check, CheckCtx, GraspConfig, Held, ObjectSet, World};

/// One robot of a world as a [`Space`]; the other robots stand at home.
pub struct RobotSpace<'w> {
    world: &'w World,
    robot: RobotId,
}

impl<'w> RobotSpace<'w> {
    pub fn new(world: &'w World, robot: RobotId) -> Self {
        RobotSpace { world, robot }
    }
}

fn ctx(mode: &Mode) -> CheckCtx {
    CheckCtx { absent: mode.absent.clone(), held: mode.held.clone(), ..CheckCtx::default() }
}

/// `f` in `mode`'s context, its configurations added to `checks`.
fn counted<T>(mode: &Mode, checks: &mut u64, f: impl FnOnce(&CheckCtx) -> T) -> T {
    let c = ctx(mode);
    let out = f(&c);
    *checks += c.count();
    out
}

impl Space for RobotSpace<'_> {
    fn dof(&self) -> usize {
        self.world.dof(self.robot)
    }
    fn has_objects(&self) -> bool {
        !self.world.scenario().objects.is_empty()
    }
    fn limits(&self) -> &[(f64, f64)] {
        self.world.limits(self.robot)
    }
    fn check(&self, q: &[f64], mode: &Mode, checks: &mut u64) -> Check {
        counted(mode, checks, |c| self.world.check(self.robot, q, c))
    }
    fn touches_nothing(&self, q: &[f64], mode: &Mode, checks: &mut u64) -> bool {
        counted(mode, checks, |c| self.world.touches_nothing(self.robot, q, c))
    }
    fn check_segment(&self, a: &[f64], b: &[f64], step: f64, mode: &Mode, checks: &mut u64) -> Check {
        counted(mode, checks, |c| self.world.check_segment(self.robot, a, b, step, c))
    }
    fn segment_steps(&self, a: &[f64], b: &[f64], step: f64) -> Option<usize> {
        Some(crate::world::segment_steps(a, b, step, 1))
    }
    fn check_samples(
        &self,
        ends: (&[f64], &[f64]),
        n: usize,
        indices: &mut dyn Iterator<Item = usize>,
        mode: &Mode,
        checks: &mut u64,
    ) -> Check {
        counted(mode, checks, |c| self.world.check_samples(self.robot, ends, n, indices, c))
    }
    fn check_samples_twin(
        &self,
        ends: (&[f64], &[f64]),
        n: usize,
        indices: &[usize],
        mode: &Mode,
        checks: &mut u64,
    ) -> (Check, Check) {
        counted(mode, checks, |c| self.world.check_samples_twin(self.robot, ends, n, indices, c))
    }
    fn check_segment_known(
        &self,
        ends: (&[f64], &[f64]),
        step: f64,
        known: (bool, bool),
        mode: &Mode,
        checks: &mut u64,
    ) -> Check {
        counted(mode, checks, |c| self.world.check_segment_known(self.robot, ends, step, known, c))
    }
    fn check_segment_held(&self, a: &[f64], b: &[f64], step: f64, mode: &Mode, checks: &mut u64) -> Check {
        counted(mode, checks, |c| self.world.check_segment_held(self.robot, a, b, step, c))
    }
    fn check_motion(&self, a: &[f64], b: &[f64], resolution: f64, mode: &Mode, checks: &mut u64) -> Check {
        counted(mode, checks, |c| self.world.check_motion(self.robot, a, b, resolution, c))
    }
    fn check_motion_rest(&self, a: &[f64], b: &[f64], resolution: f64, mode: &Mode, checks: &mut u64) -> Check {
        counted(mode, checks, |c| self.world.check_motion_rest(self.robot, a, b, resolution, c))
    }
    fn check_motion_rest_twin(
        &self,
        a: &[f64],
        b: &[f64],
        resolution: f64,
        mode: &Mode,
        checks: &mut u64,
    ) -> (Check, Check) {
        counted(mode, checks, |c| self.world.check_motion_rest_twin(self.robot, a, b, resolution, c))
    }
    fn home(&self) -> &[f64] {
        self.world.home(self.robot)
    }
    fn drop_config(&self) -> &[f64] {
        self.world.drop_config(self.robot)
    }
    fn grasps(&self, o: ObjectId) -> Vec<GraspConfig> {
        self.world.select_grasps(self.robot, o)
    }
    fn held(&self, o: ObjectId, grasp: usize, q_grasp: &[f64]) -> Held {
        self.world.held(self.robot, o, grasp, q_grasp)
    }
    fn fingers_clear(&self, held: &Held, q_grasp: &[f64], checks: &mut u64) -> Result<ObjectSet, Blocker> {
        let absent = ObjectSet::single(held.object);
        let mut touched = ObjectSet::new();
        for q in [q_grasp, self.world.drop_config(self.robot)] {
            for &posture in self.world.closing(self.robot, held.posture) {
                let c = CheckCtx::with_held(absent.clone(), Held { posture, ..held.clone() });
                let found = self.world.check(self.robot, q, &c);
                *checks += c.count();
                match found {
                    Check::Blocked(b) => return Err(b),
                    Check::Touches(objects) => touched.union_with(&objects),
                }
            }
        }
        Ok(touched)
    }
    fn escape_line(&self, q: &[f64]) -> Vec<Vec<f64>> {
        self.world.escape_line(self.robot, q).into_iter().map(|c| c.0).collect()
    }
    fn why_no_grasp(&self, o: ObjectId) -> Option<String> {
        Some(crate::world::why_ungraspable(self.world, self.robot, o))
    }
}

/// PRMwO roadmaps for every robot of a world. Queries for one robot share its
/// roadmap; queries may come from several threads.
pub struct Planner<'w> {
    world: &'w World,
    settings: PlannerSettings,
    robots: Vec<RobotPlanner<RobotSpace<'w>>>,
}

impl<'w> Planner<'w> {
    pub fn new(world: &'w World, settings: &PlannerSettings) -> Self {
        Planner::with_options(world, settings, &PrmOptions::default())
    }

    pub fn with_options(world: &'w World, settings: &PlannerSettings, opts: &PrmOptions) -> Self {
        let robots = world
            .scenario()
            .robot_ids()
            .map(|r| RobotPlanner::new(RobotSpace::new(world, r), settings, opts, r.0 as u64))
            .collect();
        Planner { world, settings: settings.clone(), robots }
    }

    /// The roadmap planner of one robot.
    pub fn robot(&self, r: RobotId) -> &RobotPlanner<RobotSpace<'w>> {
        &self.robots[r.index()]
    }

    /// `findPath` with an explicit objective, on the same roadmap as every other query.
    pub fn find_path_with(&self, robot: RobotId, goal: &Goal, objective: Objective) -> Answer {
        let mut a = self.robots[robot.index()].query_with(goal, objective);
        let scn = self.world.scenario();
        a.stats.robot = scn.robot(robot).name.clone();
        a.stats.object = match goal {
            Goal::Grasp(o) => scn.object(*o).body.name.clone(),
            Goal::Reach(q) => format!("{:?}", q.0),
        };
        a
    }
}

impl Oracle for Planner<'_> {
    fn find_path(&self, robot: RobotId, goal: &Goal) -> Answer {
        self.find_path_with(robot, goal, self.settings.objective)
    }

    /// Robots in parallel, each robot's queries in the given order: robots share no
    /// roadmap, so the answers are those of the sequential order whatever the threads.
    fn find_paths(&self, queries: &[(RobotId, Goal)]) -> Vec<Answer> {
        use rayon::prelude::*;
        let mut robots: Vec<RobotId> = queries.iter().map(|q| q.0).collect();
        robots.sort_unstable_by_key(|r| r.0);
        robots.dedup();
        let per_robot: Vec<Vec<(usize, Answer)>> = robots
            .par_iter()
            .map(|&r| {
                queries
                    .iter()
                    .enumerate()
                    .filter(|(_, q)| q.0 == r)
                    .map(|(i, (robot, goal))| (i, self.find_path(*robot, goal)))
                    .collect()
            })
            .collect();
        let mut answers: Vec<(usize, Answer)> = per_robot.into_iter().flatten().collect();
        answers.sort_unstable_by_key(|a| a.0);
        answers.into_iter().map(|a| a.1).collect()
    }
}
